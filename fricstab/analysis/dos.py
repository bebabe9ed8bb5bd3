"""Density of states and mode character of a packing's Jacobian (Ishima Sec. IV B).

Eigenvalues ``lambda_n = omega_n^2`` of ``J`` (Eq. 21; ``J`` in Ishima's
convention, :func:`fricstab.analysis.rigidity.linear_response`: ``-dF/dq`` in
``(x, y, l = R theta)`` whatever the law, units ``k_N d^(1/2)``, so
``omega t0 = sqrt(lambda)``), the DOS ``D(omega) = (1/3N) sum'_n delta(omega -
omega_n)`` (Eq. 23; N counts all particles, rattlers included, and the sum
excludes rattlers and the two translations), translational and rotational
participation fractions ``psi^T_n``, ``psi^R_n`` (Eqs. 49-50), their
frequency averages (Eqs. 51-52), and the participation ratio ``p_n`` (Eq. E1).

Routes to the spectrum (measured against each other in ``validation/``):

``"dense"``
    ``scipy.linalg.eig`` with left and right vectors: the general route for a
    non-symmetric Jacobian, and the baseline.
``"symmetric"``
    ``scipy.linalg.eigh`` of ``(J + J^T)/2``.  Exact when ``J = J^T``, which
    holds in the unstrained packing: friction is switched on at the
    frictionless force-balanced state, every tangential history is zero, and
    ``J`` is then the Hessian of the effective potential (App. H).  For a
    small antisymmetric part ``A`` the eigenvalue error is second order in
    ``|A|`` (``r^T A r = 0``).
``"auto"``
    ``"symmetric"`` when ``max|J - J^T| <= 1e-12 max|J|``, else ``"dense"``.
"""

import time
from dataclasses import dataclass

import numpy as np
import scipy.linalg

__all__ = ["Spectrum", "binned_mean", "dos", "log_bins", "participation",
           "rotational_peak", "spectrum"]


@dataclass(frozen=True)
class Spectrum:
    """Eigenvalues (ascending real parts), unit right eigenvectors (columns) and
    left eigenvectors scaled so that ``left[:, n].conj() @ right[:, n] = 1``
    (the same array as ``right`` on the symmetric route)."""

    eigenvalues: np.ndarray
    right: np.ndarray
    left: np.ndarray
    route: str
    seconds: float
    asymmetry: float
    max_imag: float

    @property
    def omega(self):
        """``omega t0 = sqrt(lambda)`` (negative round-off clipped to 0)."""
        return np.sqrt(np.clip(self.eigenvalues.real, 0.0, None))


def asymmetry(dense):
    """``max|J - J^T| / max|J|``."""
    return float(np.abs(dense - dense.T).max() / np.abs(dense).max())


def spectrum(jac, route="auto", vectors=True):
    """Eigen-decomposition of a packing's Jacobian for the density of states (Ishima Sec. IV B).

    ``lambda_n = (omega_n t0)^2`` of ``J`` (Eq. 21; Ishima's convention
    ``-dF/dq``, units ``k_N d^(1/2)``, so ``omega t0 = sqrt(lambda)``).

    Parameters
    ----------
    jac : ndarray or scipy.sparse matrix
        ``J`` (:func:`linear_response`).
    route : {"auto", "dense", "symmetric"}
        ``"dense"``: ``scipy.linalg.eig`` with left and right vectors (the
        general route); ``"symmetric"``: ``eigh`` of ``(J + J^T)/2``, exact for
        the unstrained packing (zero histories: J is the Hessian of the
        effective potential, App. H); ``"auto"``: symmetric when
        ``max|J - J^T| <= 1e-12 max|J|``, else dense.
    vectors : bool
        Also compute the eigenvectors.

    Returns
    -------
    Spectrum
        ``eigenvalues`` (ascending real parts, ``(omega t0)^2``), unit right
        eigenvectors (columns) and left ones, the ``route`` taken, ``seconds``,
        the asymmetry ``max|J - J^T| / max|J|`` and ``max_imag``.

    Raises
    ------
    NumericalError
        A non-finite Jacobian entry, naming its row.
    """
    from fricstab.errors import ParameterError, check_bool, check_finite
    if route not in ("auto", "dense", "symmetric"):
        raise ParameterError(f"unknown spectrum route {route!r}; use dense, symmetric or auto")
    check_bool("vectors", vectors)
    dense = jac.toarray() if hasattr(jac, "toarray") else np.asarray(jac)
    if dense.ndim != 2 or dense.shape[0] != dense.shape[1] or dense.dtype.kind not in "iuf":
        raise ParameterError(f"jac must be a square real matrix, got shape {dense.shape} "
                             f"of dtype {dense.dtype}")
    check_finite("Jacobian entry", dense, item="row")   # LAPACK would refuse it unnamed
    asym = asymmetry(dense)
    if route == "auto":
        route = "symmetric" if asym <= 1e-12 else "dense"
    t0 = time.perf_counter()
    if route == "symmetric":
        sym = (dense + dense.T) / 2
        w, right = scipy.linalg.eigh(sym) if vectors else (scipy.linalg.eigvalsh(sym), None)
        left = right
    elif route == "dense":
        if vectors:
            w, left, right = scipy.linalg.eig(dense, left=True, right=True)
        else:
            w, left, right = scipy.linalg.eigvals(dense), None, None
        order = np.argsort(w.real, kind="stable")
        w = w[order]
        if vectors:
            right = right[:, order] / np.linalg.norm(right[:, order], axis=0)
            left = left[:, order]
            left = left / np.einsum("ij,ij->j", left.conj(), right).conj()
    else:
        raise ValueError(f"unknown spectrum route {route!r}; use dense, symmetric or auto")
    max_imag = float(np.abs(np.imag(w)).max())
    w = w.real if max_imag == 0.0 else w
    return Spectrum(w, right, left, route, time.perf_counter() - t0, asym, max_imag)


def participation(right, k):
    """``psi^T_n``, ``psi^R_n`` (Eqs. 49-50) and ``p_n`` (Eq. E1) of unit columns."""
    a = np.abs(right) ** 2
    n = right.shape[0] // k
    per = a.reshape(n, k, -1)
    psi_t = per[:, :2, :].sum(axis=(0, 1))
    psi_r = per[:, 2:, :].sum(axis=(0, 1)) if k == 3 else np.zeros_like(psi_t)
    mag2 = per.sum(axis=1)                      # |R_n,i|^2
    p = mag2.sum(axis=0) ** 2 / (n * (mag2 ** 2).sum(axis=0))
    return psi_t, psi_r, p


def log_bins(lo, hi, n=50):
    """``n`` logarithmic bins from ``lo`` to ``hi`` (the paper's 50, Sec. IV B)."""
    return np.geomspace(lo, hi, n + 1)


def dos(omega, n_particles, edges):
    """``D(omega)`` (Eq. 23) on ``edges``: counts / (3 N width)."""
    counts, _ = np.histogram(omega, bins=edges)
    return counts / (3 * n_particles * np.diff(edges))


def binned_mean(omega, values, edges):
    """Average of ``values`` over modes in each bin (Eqs. 51-52, E2); 0 where empty."""
    idx = np.digitize(omega, edges) - 1
    ok = (idx >= 0) & (idx < len(edges) - 1)
    tot = np.bincount(idx[ok], weights=values[ok], minlength=len(edges) - 1)
    cnt = np.bincount(idx[ok], minlength=len(edges) - 1)
    out = np.zeros(len(edges) - 1)
    np.divide(tot, cnt, out=out, where=cnt > 0)
    return out


def rotational_peak(omega, psi_r, bins_per_decade=10):
    """Frequency of the DOS peak of rotation-dominated modes (``psi^R > 1/2``).

    The peak of a log-binned histogram (bin centre, geometric), and the median
    frequency of the same modes as a bin-free companion.  ``nan`` if none.
    """
    rot = omega[(psi_r > 0.5) & (omega > 0)]
    if rot.size == 0:
        return float("nan"), float("nan")
    lo, hi = np.log10(rot.min()), np.log10(rot.max())
    nb = max(1, int(np.ceil((hi - lo) * bins_per_decade)))
    edges = np.logspace(lo, hi + 1e-12, nb + 1)
    counts, _ = np.histogram(rot, bins=edges)
    dens = counts / np.diff(edges)
    k = int(np.argmax(dens))
    return float(np.sqrt(edges[k] * edges[k + 1])), float(np.median(rot))
