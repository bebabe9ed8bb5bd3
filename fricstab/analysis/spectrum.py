"""Non-symmetric eigenproblem of M^-1 J: spectra, pairs and their indicator.

``M q'' = J q`` with ``J = dF/dq`` (Charan's sign): an eigenvalue lambda of
``M^-1 J`` gives ``q ~ exp(i omega t)`` with ``omega^2 = -lambda``.  Real
negative lambda are stable oscillations; a complex-conjugate pair makes one
root of ``omega`` grow: the oscillatory instability, with growth rate
``Im sqrt(-lambda)`` (largest over the pair).

Pair indicator.  For the two eigenvalues lambda_1, lambda_2 that coalesce at
an exceptional point, ``D = (lambda_1 - lambda_2)^2`` is real for a real pair
(D > 0) and for a conjugate pair (D = -4 Im^2 < 0).  D is a symmetric
function of the cluster, smooth through the exceptional point where the
eigenvalues themselves have a square-root singularity, and a backward-stable
eigensolver computes it to O(eps |A|^2) absolute: its sign is the
well-conditioned indicator that bisection uses.  Whether an eigenvalue is
real needs no threshold: LAPACK returns exactly zero imaginary parts for the
1 x 1 blocks of the real Schur form.
"""

from dataclasses import dataclass

import numpy as np
import scipy.linalg

from fricstab.errors import ParameterError, check_finite_array, check_real

__all__ = ["Spectrum", "complex_pairs", "decompose", "growth_rate", "pair_indicator",
           "tracking_radius"]


@dataclass(frozen=True)
class Spectrum:
    """Eigenvalues of M^-1 J with biorthonormal left/right eigenvectors.

    ``right[:, k]`` has unit norm, ``left[:, k]`` satisfies
    ``left[:, k].conj() @ right[:, k] = 1``; ``condition[k]`` is the
    eigenvalue condition number ``|l| |r| / |l^H r|`` (1 for a normal matrix,
    infinite at an exceptional point).
    """

    eigenvalues: np.ndarray
    right: np.ndarray
    left: np.ndarray
    condition: np.ndarray


def decompose(jac, mass, vectors=True):
    """Spectrum of ``M^-1 J`` with biorthonormal left and right eigenvectors.

    Dense ``scipy.linalg.eig`` of ``diag(mass)^-1 jac``.  ``J = dF/dq`` is not
    symmetric when histories are present (Charan Sec. II), so left and right
    eigenvectors differ; their overlap gives each eigenvalue's condition number,
    which diverges at an exceptional point (where a pair is born).

    Parameters
    ----------
    jac : ndarray, shape (n, n)
        The Jacobian ``dF/dq`` (force/length; Charan's sign: a stable mode has
        a negative eigenvalue).
    mass : ndarray, shape (n,)
        The diagonal of the mass matrix in the same dof order (mass, or
        moment of inertia for a rotation; Charan's scaled ``I/R^2`` where the
        coordinates are scaled).
    vectors : bool
        Also compute the eigenvectors and condition numbers.

    Returns
    -------
    Spectrum
        ``eigenvalues`` (n,) sorted by real part (1/time^2; ``lambda = -omega^2``
        for a stable mode); ``right`` (unit columns), ``left``
        (``left[:, k].conj() @ right[:, k] = 1``) and ``condition``
        ``|l| |r| / |l^H r|``; None without ``vectors``.
    """
    check_finite_array("jac", jac, ndim=2)
    n = np.shape(jac)[0]
    check_finite_array("mass", mass, shape=(n,))
    if np.shape(jac) != (n, n) or not np.all(np.asarray(mass) > 0):
        raise ParameterError(f"decompose: jac must be square (n, n) and mass (n,) > 0, got "
                             f"jac {np.shape(jac)}, mass min {np.min(mass, initial=np.inf):g}")
    a = jac / np.asarray(mass)[:, None]
    if not vectors:
        w = scipy.linalg.eigvals(a)
        return Spectrum(w[np.argsort(w.real, kind="stable")], None, None, None)
    w, vl, vr = scipy.linalg.eig(a, left=True, right=True)
    order = np.argsort(w.real, kind="stable")
    w, vl, vr = w[order], vl[:, order], vr[:, order]
    vr = vr / np.linalg.norm(vr, axis=0)
    vl = vl / np.linalg.norm(vl, axis=0)
    overlap = np.einsum("ij,ij->j", vl.conj(), vr)
    with np.errstate(divide="ignore"):
        cond = 1.0 / np.abs(overlap)
    left = vl / overlap.conj()
    return Spectrum(w, vr, left, cond)


def complex_pairs(eigenvalues):
    """The complex-conjugate pairs of a spectrum, one eigenvalue per pair.

    Parameters
    ----------
    eigenvalues : ndarray of complex
        A spectrum (e.g. of ``M^-1 J``).

    Returns
    -------
    ndarray of complex
        The eigenvalues with ``Im > 0``, sorted by real part.
    """
    eigenvalues = np.asarray(check_finite_array("eigenvalues", eigenvalues, ndim=1,
                                                complex_ok=True))
    w = eigenvalues[eigenvalues.imag > 0]
    return w[np.argsort(w.real)]


def pair_indicator(eigenvalues, center, radius):
    """The pair indicator ``D = (lambda_1 - lambda_2)^2`` of a tracked pair, for bisection.

    A symmetric function of the two eigenvalues, hence smooth through the
    exceptional point where they meet: ``D = -4 (Im lambda)^2 < 0`` for a
    conjugate pair, the squared gap ``> 0`` for two real eigenvalues.  The ramp
    locates a birth or death by its sign change rather than by a threshold on
    a small, ill-conditioned imaginary part.

    Parameters
    ----------
    eigenvalues : ndarray of complex
        A spectrum of ``M^-1 J`` (1/time^2).
    center : float
        Real part where the pair is tracked (1/time^2).
    radius : float
        A conjugate pair with its real part within ``radius`` of ``center`` is
        the tracked pair; ``radius`` should be less than half the distance to
        any other conjugate pair (:func:`tracking_radius`).

    Returns
    -------
    D : float
        ``-4 Im^2`` of the tracked pair if there is one, else the squared gap of
        the two real eigenvalues nearest ``center`` (1/time^4); inf with fewer
        than two real eigenvalues.
    center : float
        The updated centre (the pair's real part when found).
    """
    eigenvalues = np.asarray(check_finite_array("eigenvalues", eigenvalues, ndim=1,
                                                complex_ok=True))
    check_real("center", center)
    check_real("radius", radius, 0.0)
    upper = eigenvalues[eigenvalues.imag > 0]
    if upper.size:
        k = int(np.argmin(np.abs(upper.real - center)))
        if abs(upper[k].real - center) <= radius:
            return float(-4.0 * upper[k].imag ** 2), float(upper[k].real)
    reals = np.sort(eigenvalues[eigenvalues.imag == 0].real)
    if reals.size < 2:
        return np.inf, center
    idx = np.sort(np.argsort(np.abs(reals - center))[:2])
    return float((reals[idx[1]] - reals[idx[0]]) ** 2), center


def tracking_radius(eigenvalues, center):
    """Half the distance from ``center`` to the nearest other conjugate pair.

    Capped at a tenth of the spectral width; used as the ``radius`` of
    :func:`pair_indicator`.
    """
    width = float(np.abs(eigenvalues).max())
    others = eigenvalues[(eigenvalues.imag > 0)].real
    others = others[np.abs(others - center) > 1e-12 * width]
    gap = np.abs(others - center).min() if others.size else np.inf
    return min(0.5 * gap, 0.1 * width)


def growth_rate(eigenvalues):
    """The e-folding rate of the fastest-growing mode: the largest ``Im sqrt(-lambda)``.

    For ``M^-1 J`` with ``J = dF/dq`` a mode ``exp(s t)`` has ``s^2 = lambda``;
    a stable mode (``lambda < 0`` real) oscillates, a positive eigenvalue or a
    complex pair grows (Charan Sec. II).

    Parameters
    ----------
    eigenvalues : ndarray
        A spectrum of ``M^-1 J`` (1/time^2).

    Returns
    -------
    float
        The largest growth rate (1/time; 0 for a stable spectrum).
    """
    eigenvalues = np.asarray(check_finite_array("eigenvalues", eigenvalues, ndim=1,
                                                complex_ok=True))
    if eigenvalues.size == 0:
        raise ParameterError("growth_rate: no eigenvalues")
    return float(np.max(np.abs(np.sqrt(-eigenvalues.astype(complex)).imag)))
