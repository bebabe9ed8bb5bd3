"""Is a packing a stable equilibrium?  The rule by which an ensemble excludes a packing.

A packing enters an average of Ishima et al.'s quantities (G, the DOS) only when it is a
stable equilibrium of its law.  Two failures are possible, and the rule excludes either:

1. **A saddle.**  ``K = dF/dq`` (stable modes have ``lambda < 0`` of ``M^-1 K``; Ishima's
   ``J = -K`` then has positive eigenvalues) has a *real* eigenvalue above the zero cluster,
   ``lambda > ZERO_CLUSTER |A|_inf`` (``|A|_inf`` the largest row sum of ``|M^-1 K|``, a bound on
   the spectral radius; ``ZERO_CLUSTER`` = 1e-6, the zero-mode rule of the AQS protocol and of
   :mod:`fricstab.analysis.sparse_spectrum`).  The two translations of the periodic box are
   deflated exactly; other eigenvalues inside the cluster (a disk without contacts) are zero
   modes, counted and not held against the packing.  Complex-conjugate pairs (a
   non-symmetric frictional Jacobian) are counted but do not exclude: they are the physics
   under study, not a failed preparation.
2. **Unstable to shear.**  ``G = G_A + G_NA < -G_TOL |G_A|``: the solve route agrees with the
   mode sum to ~1e-13 relative (``tests/test_rigidity.py``), so ``G_TOL`` = 1e-9 leaves four
   orders of magnitude for the condition of the solve.

The spectrum: dense (all eigenvalues) up to :data:`DENSE_MAX` free dof, else the ``k``
eigenvalues nearest zero by shift-invert Arnoldi (:func:`fricstab.analysis.sparse_spectrum.
soft_end`), which find the soft unstable direction a failed preparation leaves; an unstable
eigenvalue far from zero (beyond the returned ``radius``) is then not seen, and the report
says so (``searched_radius``).
"""

from dataclasses import dataclass

import numpy as np
import scipy.linalg

from fricstab.analysis.sparse_spectrum import ZERO_CLUSTER, _scale, soft_end
from fricstab.errors import ParameterError

__all__ = ["DENSE_MAX", "G_TOL", "Stability", "classify", "packing_stability"]

G_TOL = 1e-9
DENSE_MAX = 3000


@dataclass(frozen=True)
class Stability:
    """The verdict of the rule (module docstring) on one packing under one law.

    ``stable``: neither failure; ``reason``: why not (empty when stable); ``max_real``: the
    largest real eigenvalue of ``M^-1 K`` outside the zero cluster (1/time^2); ``n_unstable``:
    real eigenvalues above the cluster; ``n_pairs``: conjugate pairs seen; ``n_zero``: extra
    zero modes; ``scale``: ``|A|_inf``; ``g``, ``g_a``: the shear modulus and its affine part
    (NaN when not computed); ``route``: "dense" or "soft end"; ``searched_radius``: every
    eigenvalue of modulus below it was examined (inf for dense).
    """

    stable: bool
    reason: str
    max_real: float
    n_unstable: int
    n_pairs: int
    n_zero: int
    scale: float
    g: float
    g_a: float
    route: str
    searched_radius: float

    def to_json(self):
        return {k: (v.item() if hasattr(v, "item") else v) for k, v in self.__dict__.items()}


def classify(eigenvalues, scale, g=float("nan"), g_a=float("nan"), route="dense",
             searched_radius=float("inf")):
    """:class:`Stability` from eigenvalues of ``M^-1 K`` (translations already removed), the
    bound ``scale`` = ``|A|_inf`` and optionally ``G``, ``G_A`` (module docstring's rule)."""
    w = np.asarray(eigenvalues, complex)
    if not np.all(np.isfinite(w)):
        raise ParameterError("the eigenvalues must be finite (a NaN spectrum says nothing "
                             "about stability)")
    if not (np.isfinite(scale) and scale > 0):
        raise ParameterError(f"scale = {scale!r}: |A|_inf must be a finite positive number")
    zero = np.abs(w) <= ZERO_CLUSTER * scale
    live = w[~zero]
    real = live[live.imag == 0].real
    unstable = real[real > ZERO_CLUSTER * scale]
    reasons = []
    if unstable.size:
        reasons.append(f"{unstable.size} real eigenvalue(s) of M^-1 K above the zero cluster "
                       f"(largest {unstable.max():.3g}, {unstable.max() / scale:.2g} of |A|): a "
                       "saddle")
    if np.isfinite(g) and np.isfinite(g_a) and g < -G_TOL * abs(g_a):
        reasons.append(f"G = {g:.4g} < 0 (G_A = {g_a:.4g}): unstable to shear")
    return Stability(not reasons, "; ".join(reasons),
                     float(real.max()) if real.size else float("nan"), int(unstable.size),
                     int((live.imag > 0).sum()), int(zero.sum()), float(scale), float(g),
                     float(g_a), route, float(searched_radius))


def packing_stability(system, state, with_g=True, k=24):
    """The rule's verdict on a force-balanced periodic backbone (module docstring).

    ``with_g``: also compute ``G`` (:func:`fricstab.analysis.rigidity.rigidity`, solve route);
    ``k``: eigenvalues nearest zero on the sparse route (above :data:`DENSE_MAX` free dof).
    """
    from fricstab.engine.jacobian import jacobian
    from fricstab.protocols.aqs import reduced_matrix
    _, kmat = jacobian(system, state)
    gm = system.gmass[system.free, :system.dof].ravel()
    scale = _scale(kmat, gm)
    n_free = int(system.free.sum())
    if gm.size <= DENSE_MAX:
        a, _ = reduced_matrix(kmat, gm, n_free, system.dof)
        w, route, radius = scipy.linalg.eigvals(a), "dense", float("inf")
    else:
        soft = soft_end(kmat, gm, k=k, dof=system.dof)
        w, route, radius = soft.eigenvalues, "soft end", soft.radius
    g = g_a = float("nan")
    if with_g:
        from fricstab.analysis.rigidity import rigidity
        r = rigidity(system, state)
        g, g_a = r.g, r.g_a
    return classify(w, scale, g, g_a, route, radius)
