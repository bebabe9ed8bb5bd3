"""The worked example of the README (packings): Charan's law in a packing, step strain, spectrum.

Run as written: ``python validation/packing_example.py`` (about 5 s).  A
periodic packing made frictionless by FIRE (Ishima App. A.1), friction
switched on with Charan's smoothed-Coulomb law (Charan Eq. 5) at zero
history, a step strain of 1e-3 relaxed by Newton with the histories carried,
and the spectrum of ``M^-1 K``; the histories make ``K`` non-symmetric, and
complex-conjugate pairs appear (an oscillatory instability where Re > 0).
``validation/test_packing_figures.py`` runs it and checks its output.
"""
import numpy as np

from fricstab.engine import jacobian
from fricstab.protocols.stepstrain import strain
from fricstab.scenes.packing import make_packing
from fricstab.scenes.packing_friction import backbone, frictional, material

bb = backbone(make_packing(128, 0.86, seed=0))  # FIRE packing (App. A.1), rattlers removed
fr = frictional(bb, material("charan"))         # kn = kt = 1, mu = 0.5; zero histories (A.2)
state, res = strain(fr.system, fr.state, 1e-3)  # affine step, Lees-Edwards offset, Newton
print(f"step strain 1e-3: {res.iterations} Newton iterations, max |F| = {res.residual:.1e}, "
      f"contacts on the Coulomb cap: {np.count_nonzero(state.contacts.flag)}")

f, K = jacobian(fr.system, state)               # K = dF/dq, histories by the increment rule
m = fr.system.gmass.ravel()                     # diag(m, m, I): coordinates (x, y, theta)
lam = np.linalg.eigvals(K.toarray() / m[:, None])   # M^-1 K; M q'' = K q, stable: lambda < 0
pairs = np.count_nonzero(lam.imag > 1e-10 * np.abs(lam).max())
print(f"{lam.size} eigenvalues of M^-1 K: {pairs} complex-conjugate pairs, "
      f"largest |Im| / max|lambda| = {np.abs(lam.imag).max() / np.abs(lam).max():.1e}")
