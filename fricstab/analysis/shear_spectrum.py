"""The Jacobian of a sheared packing before slip, and its spectrum.

For one state of the plane-shear cell (Lee & Hurley Sec. 2, contact law
``lee_hurley``) this module assembles the stiffness ``K = dF/dq`` from the
verified generated blocks and the dynamical matrix ``D = -M^{-1} K``.

Shapes and conventions
----------------------
* ``pos`` (N, 2), ``theta`` (N,), ``radius``, ``mass``, ``inertia`` (N,);
  x is periodic with box length ``lx`` (minimum image), y is not.
* ``mobile`` (N,) bool: bulk particles carry degrees of freedom; the others
  (wall disks) are clamped: their rows and columns are dropped.
* ``contacts`` (M, 2) int, pairs (i, j); ``ft``, ``mr`` (M,) the trial
  histories of ``lee_hurley`` (a history beyond its cap is a sliding contact).
* Degrees of freedom: ``(x, y, theta)`` per mobile particle, in the order of
  ``np.flatnonzero(mobile)``; unscaled rotation (theta in radians), mass
  matrix ``diag(m, m, I)``.
* ``K = dF/dq`` with the histories advanced by the increment rule and the
  caps (a sliding contact follows its cap): the Jacobian *before* slip in the
  sense of the incremental response of the current state.  ``D = -M^{-1} K``,
  so a stable real mode has a positive eigenvalue ``omega^2``.

Spectrum route: dense ``scipy.linalg.eigvals`` of D (up to
:data:`MAX_DENSE_DOF` degrees of freedom).  Small-amplitude motion
``M q'' = K q`` has modes ``exp(s t)`` with ``s^2 = -lambda`` for each
eigenvalue ``lambda`` of D; the growth rate of the state is
``max_lambda |Re sqrt(-lambda)|`` (0 for a positive real lambda, sqrt(-lambda)
for a negative one, > 0 for a complex pair: flutter).
"""

from dataclasses import dataclass

import numpy as np
import scipy.linalg
import scipy.sparse

from fricstab.generated.lee_hurley import lee_hurley_assemble
from fricstab.errors import check_finite
from fricstab.laws import ParameterError

__all__ = ["MAX_DENSE_DOF", "ShearSpectrum", "assemble_stiffness", "shear_spectrum"]

#: Largest problem for the dense eigenvalue route (3,000 dof: ~1 min, 0.2 GB).
MAX_DENSE_DOF = 3000
#: A pair is complex when |Im lambda| > IMAG_TOL * spectral radius; the
#: round-off of a dense nonsymmetric eigensolver is ~eps * radius * condition,
#: so 1e-8 leaves a margin of ~1e8 / condition over it.
IMAG_TOL = 1e-8


@dataclass(frozen=True)
class ShearSpectrum:
    """Spectrum of ``D = -M^{-1} K`` (module docstring).

    Attributes
    ----------
    eigenvalues : ndarray of complex
        All eigenvalues of D, sorted by real part.
    n_complex_pairs : int
        Conjugate pairs with ``|Im lambda| > IMAG_TOL * max |lambda|``.
    max_growth_rate : float
        ``max |Re sqrt(-lambda)|`` over all eigenvalues (1/time).
    lowest_real_eigenvalue : float
        Smallest real part among the eigenvalues counted as real (NaN if none).
    symmetric : bool
        Whether K is symmetric to 1e3 eps of its largest entry.
    """

    eigenvalues: np.ndarray
    n_complex_pairs: int
    max_growth_rate: float
    lowest_real_eigenvalue: float
    symmetric: bool


def _check(pos, theta, radius, mass, inertia, mobile, contacts, ft, mr):
    n = len(pos)
    if np.shape(pos) != (n, 2):
        raise ParameterError(f"pos must have shape (N, 2), got {np.shape(pos)}")
    for name, arr in (("theta", theta), ("radius", radius), ("mass", mass),
                      ("inertia", inertia), ("mobile", mobile)):
        if np.shape(arr) != (n,):
            raise ParameterError(f"{name} must have shape ({n},), got {np.shape(arr)}")
    m = len(contacts)
    if np.shape(contacts) != (m, 2) or np.shape(ft) != (m,) or np.shape(mr) != (m,):
        raise ParameterError("contacts must be (M, 2) with ft, mr of shape (M,)")
    if m and (np.min(contacts) < 0 or np.max(contacts) >= n):
        raise ParameterError(f"contacts must index particles 0..{n - 1}")
    if np.any(np.asarray(mass)[mobile] <= 0) or np.any(np.asarray(inertia)[mobile] <= 0):
        raise ParameterError("mass and inertia of mobile particles must be > 0")


def assemble_stiffness(pos, radius, mobile, contacts, ft, mr, lx, E, nu, mus, mur):
    """``K = dF/dq`` (scipy.sparse CSR, 3 dof per mobile particle) and the forces (N, 3).

    Blocks come from ``lee_hurley_assemble``; rows and columns of clamped
    particles are dropped.  ``lx`` is the periodic box length in x.
    """
    pos = np.asarray(pos, dtype=float)
    contacts = np.asarray(contacts, dtype=np.int64).reshape(-1, 2)
    sep = pos[contacts[:, 0]] - pos[contacts[:, 1]]
    sep[:, 0] -= lx * np.round(sep[:, 0] / lx)
    hist = np.column_stack([np.asarray(ft, float), np.asarray(mr, float)])
    forces = np.zeros((len(pos), 3))
    blocks = np.empty((len(contacts), 6, 6))
    lee_hurley_assemble(sep, np.asarray(radius, float), contacts, float(E), float(nu),
                        float(mus), float(mur), hist, forces, blocks)
    index = np.full(len(pos), -1)
    movers = np.flatnonzero(mobile)
    index[movers] = np.arange(len(movers))
    dof = np.where(index[contacts][:, :, None] >= 0,
                   3 * index[contacts][:, :, None] + np.arange(3), -1).reshape(-1, 6)
    rows = np.repeat(dof, 6, axis=1)
    cols = np.tile(dof, (1, 6))
    keep = (rows >= 0) & (cols >= 0)
    n = 3 * len(movers)
    k = scipy.sparse.coo_matrix((blocks.reshape(-1, 36)[keep], (rows[keep], cols[keep])),
                                shape=(n, n)).tocsr()
    return k, forces


def shear_spectrum(pos, theta, radius, mass, inertia, mobile, contacts, ft, mr, lx,
                   E, nu, mus, mur):
    """Spectrum of ``D = -M^{-1} K`` of one state: a :class:`ShearSpectrum`.

    ``theta`` is accepted for completeness of the state (the law depends on
    rotation increments only, not on the angles).
    """
    mobile = np.asarray(mobile, dtype=bool)
    _check(pos, theta, radius, mass, inertia, mobile, contacts, ft, mr)
    n_dof = 3 * int(mobile.sum())
    if n_dof == 0:
        raise ParameterError("mobile must select at least one particle")
    if n_dof > MAX_DENSE_DOF:
        raise ParameterError(f"{n_dof} degrees of freedom exceed the dense route "
                             f"(MAX_DENSE_DOF = {MAX_DENSE_DOF})")
    k, _ = assemble_stiffness(pos, radius, mobile, contacts, ft, mr, lx, E, nu, mus, mur)
    kd = k.toarray()
    check_finite("stiffness entry", kd, item="row")     # LAPACK would refuse it unnamed
    big = np.abs(kd).max() if kd.size else 0.0
    symmetric = bool(np.abs(kd - kd.T).max() <= 1e3 * np.finfo(float).eps * big) if big else True
    minv = 1.0 / np.column_stack([mass, mass, inertia])[mobile].ravel()
    d = -minv[:, None] * kd
    lam = scipy.linalg.eigvals(d)
    lam = lam[np.argsort(lam.real, kind="stable")]
    radius_d = np.abs(lam).max() if lam.size else 0.0
    is_complex = np.abs(lam.imag) > IMAG_TOL * radius_d
    growth = np.abs(np.sqrt(-lam.astype(complex)).real)
    real = lam.real[~is_complex]
    return ShearSpectrum(
        eigenvalues=lam, n_complex_pairs=int(is_complex.sum() // 2),
        max_growth_rate=float(growth.max()) if growth.size else 0.0,
        lowest_real_eigenvalue=float(real.min()) if real.size else float("nan"),
        symmetric=symmetric)
