import numpy as np
import fricstab as fs

# a FIRE packing (Ishima App. A.1), rattlers removed, friction switched on with
# Charan's smoothed-Coulomb law at zero history (kn = kt = 1, mu = 0.5; App. A.2)
packed = fs.backbone(fs.make_packing(128, 0.86, seed=0))
fr = fs.frictional(packed, fs.packing_material("charan"))
# a step strain of 1e-3: affine, Lees-Edwards offset, Newton with the histories carried
state, res = fs.strain(fr.system, fr.state, 1e-3)
f, K = fs.jacobian(fr.system, state)            # K = dF/dq with the increment rule
lam = np.linalg.eigvals(K.toarray() / fr.system.gmass.ravel()[:, None])   # M^-1 K
pairs = np.count_nonzero(lam.imag > 1e-10 * np.abs(lam).max())
print(f"{res.iterations} Newton iterations, max |F| = {res.residual:.1e}; "
      f"{lam.size} eigenvalues, {pairs} complex-conjugate pairs")
