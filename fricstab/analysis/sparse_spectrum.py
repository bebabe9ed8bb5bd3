"""The ends of the spectrum of ``M^-1 K`` by sparse (ARPACK) routes, and their error against dense.

The dense spectrum (:func:`fricstab.analysis.spectrum.decompose`) costs
``O(n^3)``; the AQS precursors need only the soft end (the eigenvalues nearest
zero, the complex pairs there) and the largest growth rate.

Soft end (:func:`soft_end`).  Shift-invert Arnoldi: the eigenvalues ``nu`` of
``OP = (K - sigma M)^-1 M`` of largest modulus are ``nu = 1/(lambda - sigma)``
for the ``lambda`` of ``A = M^-1 K`` nearest ``sigma``; ``K - sigma M`` is
factored once (:func:`scipy.sparse.linalg.splu`).  The shift is real and a
little *above* zero, ``sigma = SHIFT * |A|_inf`` (``|A|_inf`` the largest row
sum of ``|M^-1 K|``, a bound on the spectral radius): a stable state has no
eigenvalue there, and for a symmetric ``K <= 0`` (frictionless)
``K - sigma M`` is negative definite, hence never singular, whatever zero
modes (rattlers) it has.  Translations (``dof`` given): ``K C = 0`` and
``C^T K = 0`` for the uniform translations ``C`` of a periodic box, so the
complement ``{x : C^T M x = 0}`` is invariant and ``P = I - C (C^T M C)^-1
C^T M`` is the spectral projector that removes the exact zero pair; Arnoldi
runs on ``P OP`` from a start vector in the complement (no threshold).  Other
zero modes (a disk without contacts) are found as ``|lambda| <= ZERO_CLUSTER
|A|_inf`` (the rule of :mod:`fricstab.protocols.aqs`), counted and left out.

Error model.  Each returned eigenpair has the backward error ``eta = |A x -
lambda x| / (|A|_inf |x|)``; the eigenvalue error is at most about ``cond *
eta * |A|`` with ``cond = |l| |r| / |l^H r|`` its condition number (infinite
at an exceptional point).  ARPACK at ``tol = 0`` converges to ``eta`` of a
few ``eps``.  :func:`compare_with_dense` checks this against dense.
"""

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sps
import scipy.sparse.linalg as spla

from fricstab.errors import NumericalError, ParameterError, check_finite_array

__all__ = ["SHIFT", "ZERO_CLUSTER", "Growth", "SoftEnd", "compare_with_dense",
           "fastest_growth", "growth_of", "soft_end"]

SHIFT = 1e-8          # sigma = SHIFT |A|_inf: far below the softest eigenvalue of a packing
ZERO_CLUSTER = 1e-6   # |lambda| below this times |A|_inf is a zero mode (as in AQS)


@dataclass(frozen=True)
class SoftEnd:
    """The eigenvalues of ``M^-1 K`` nearest zero, zero modes left out.

    ``eigenvalues`` sorted by modulus (conjugates adjacent, Im > 0 first);
    ``backward_error`` of each (module doc); ``zero_modes`` the eigenvalues
    found in the zero cluster (beyond the deflated translations); ``radius``
    the largest returned modulus (every eigenvalue nearer zero is among them);
    ``sigma`` the shift, ``scale`` ``|A|_inf``, ``matvecs`` the solves.
    """

    eigenvalues: np.ndarray
    backward_error: np.ndarray
    zero_modes: int
    radius: float
    sigma: float
    scale: float
    matvecs: int

    @property
    def pairs(self):
        """Complex-conjugate pairs among them (Im > 0 member)."""
        return self.eigenvalues[self.eigenvalues.imag > 0]


@dataclass(frozen=True)
class Growth:
    """The largest growth rate found, and the Bendixson bound on what was not searched.

    ``rate`` (1/time) and its ``eigenvalue``; ``bound``: no eigenvalue outside
    the searched disc ``|lambda| < radius`` (nor beyond the 'LR' end) can grow
    faster (:func:`fastest_growth`); ``certified`` when ``rate >= bound``.
    """

    rate: float
    eigenvalue: complex
    radius: float
    bound: float
    certified: bool
    soft: SoftEnd


def _inputs(k_mat, mass, dof, where):
    """CSC ``K``, float ``mass`` and the translation basis (or None), checked."""
    if not sps.issparse(k_mat):
        check_finite_array("K", k_mat, ndim=2)
    k_mat = sps.csc_matrix(k_mat, dtype=float)
    n = k_mat.shape[0]
    if k_mat.shape != (n, n) or not np.all(np.isfinite(k_mat.data)):
        raise ParameterError(f"{where}: K must be a finite square matrix, got shape "
                             f"{k_mat.shape}")
    mass = np.asarray(check_finite_array("mass", mass, shape=(n,)), float)
    if not np.all(mass > 0):
        raise ParameterError(f"{where}: mass must be > 0, got min {mass.min(initial=0):g}")
    if dof is None:
        return k_mat, mass, None
    if not (isinstance(dof, (int, np.integer)) and dof >= 2 and n % dof == 0):
        raise ParameterError(f"{where}: dof must be an int >= 2 dividing n = {n}, got {dof!r}")
    c = np.zeros((n, 2))
    c[0::dof, 0] = c[1::dof, 1] = 1.0
    size = abs(k_mat).sum(axis=1).max() * np.sqrt(n)
    if max(np.abs(k_mat @ c).max(), np.abs(k_mat.T @ c).max()) > 1e-10 * size:
        raise ParameterError(f"{where}: the translations of dof = {dof} are not zero modes of "
                             "K on both sides (not a periodic box?); give dof=None")
    return k_mat, mass, c


def _scale(k_mat, mass):
    """``|M^-1 K|_inf``, a bound on the spectral radius (1/time^2)."""
    return float(np.asarray(abs(k_mat).sum(axis=1)).ravel().__truediv__(mass).max())


def _projector(c, mass):
    """``x -> P x`` removing the translations (module doc), identity without ``c``."""
    if c is None:
        return lambda x: x
    mc = c * mass[:, None]
    gram_inv = np.linalg.inv(c.T @ mc)
    return lambda x: x - c @ (gram_inv @ (mc.T @ x))


def _order(w):
    """Indices by modulus, conjugates adjacent (upper first)."""
    key = np.abs(w.real + 1j * np.abs(w.imag))
    return np.lexsort((-w.imag, key))


def soft_end(K, mass, k=12, sigma=None, dof=None, tol=0.0, seed=0):
    """The ``k`` eigenvalues of ``M^-1 K`` nearest zero by shift-invert Arnoldi (module doc).

    Parameters
    ----------
    K : scipy sparse or ndarray, shape (n, n)
        ``dF/dq`` (Charan's sign: stable modes have lambda < 0).
    mass : ndarray, shape (n,)
        Diagonal mass matrix, > 0.
    k : int
        Eigenvalues wanted (a conjugate pair cut at the k-th is kept whole).
    sigma : float, optional
        Real shift; default ``SHIFT * |A|_inf`` (just above zero).
    dof : int, optional
        Dof per particle of a periodic packing: its two translations are
        deflated exactly.  None: nothing deflated (a chain on a wall).
    tol : float
        ARPACK's relative tolerance on the Ritz values of ``OP`` (0: machine).
    seed : int
        Seed of the start vector.

    Returns
    -------
    SoftEnd

    Raises
    ------
    ParameterError
        Non-finite or mis-shaped input, ``k`` too large for Arnoldi.
    NumericalError
        ``K - sigma M`` exactly singular (``sigma`` is an eigenvalue), or no
        convergence.
    """
    k_mat, mass, c = _inputs(K, mass, dof, "soft_end")
    n = k_mat.shape[0]
    room = n - (2 if c is not None else 0)
    if not (isinstance(k, (int, np.integer)) and 1 <= k <= room - 3):
        raise ParameterError(f"soft_end: k must be an int in [1, {room - 3}] for n = {n}, "
                             f"got {k!r}; use the dense spectrum for small n")
    scale = _scale(k_mat, mass)
    sigma = SHIFT * scale if sigma is None else sigma
    if not (isinstance(sigma, (int, float, np.floating)) and np.isfinite(sigma)):
        raise ParameterError(f"soft_end: sigma must be a finite real number, got {sigma!r}")
    try:
        lu = spla.splu((k_mat - sigma * sps.diags(mass)).tocsc())
    except RuntimeError as exc:
        raise NumericalError(f"soft_end: K - sigma M is singular at sigma = {sigma:g} "
                             f"({exc}); give another sigma") from None
    project = _projector(c, mass)
    calls = [0]

    def op(x):
        calls[0] += 1
        return project(lu.solve(mass * np.ravel(x)))

    v0 = project(np.random.default_rng(seed).standard_normal(n))
    want = min(k + 1, room - 2)
    while True:   # widen past the zero cluster (a packing at jamming holds hundreds)
        w, x = _arnoldi(spla.LinearOperator((n, n), op, dtype=float), want, v0, tol)
        lam = sigma + 1.0 / w
        zero = np.abs(lam) <= ZERO_CLUSTER * scale
        if want - zero.sum() > k or want >= room - 2:
            break
        want = min(want + int(zero.sum()) + 1, room - 2)
    if zero.all():
        raise NumericalError(f"soft_end: all {want} eigenvalues found lie in the zero cluster "
                             f"(|lambda| <= {ZERO_CLUSTER:g} |A|_inf = "
                             f"{ZERO_CLUSTER * scale:.3g}) and Arnoldi can widen no further; "
                             "use the dense spectrum")
    lam, x = lam[~zero], x[:, ~zero]
    idx = _order(lam)[:k]
    if lam[idx[-1]].imag != 0 and len(idx) < len(lam):
        idx = _order(lam)[:k + 1]
    lam, x = lam[idx], x[:, idx]
    resid = np.linalg.norm(k_mat @ x / mass[:, None] - x * lam, axis=0)
    eta = resid / (scale * np.linalg.norm(x, axis=0))
    return SoftEnd(lam, eta, int(zero.sum()), float(np.abs(lam).max()), float(sigma), scale,
                   calls[0])


def _arnoldi(op, k, v0, tol):
    """``eigs`` of largest modulus; NumericalError naming what converged when it fails."""
    try:
        return spla.eigs(op, k=k, which="LM", v0=v0, tol=tol, maxiter=max(1000, 20 * k))
    except spla.ArpackNoConvergence as exc:
        raise NumericalError(f"ARPACK did not converge: {len(exc.eigenvalues)} of {k} "
                             "eigenvalues") from None


def growth_of(eigenvalues):
    """``Im sqrt(-lambda)`` of each eigenvalue (>= 0 on the principal branch; 1/time)."""
    return np.abs(np.sqrt(-np.asarray(eigenvalues, complex)).imag)


def _bendixson(k_mat, mass):
    """``mu``: largest eigenvalue of sym(B); ``beta``: |skew(B)|_2, ``B = M^-1/2 K M^-1/2``."""
    s = sps.diags(mass ** -0.5)
    b = (s @ k_mat @ s).tocsr()
    sym, skew = 0.5 * (b + b.T), 0.5 * (b - b.T)
    n = b.shape[0]
    if n < 40:
        mu = float(np.linalg.eigvalsh(sym.toarray()).max())
        beta = float(np.linalg.norm(skew.toarray(), 2))
        return mu, beta
    mu = float(spla.eigsh(sym, k=1, which="LA", tol=1e-8)[0][0])
    beta2 = float(spla.eigsh((skew.T @ skew).tocsr(), k=1, which="LA", tol=1e-8)[0][0])
    return mu, float(np.sqrt(max(beta2, 0.0)))


def fastest_growth(K, mass, k=24, dof=None, sigma=None, tol=0.0):
    """The largest growth rate ``Im sqrt(-lambda)`` among the soft end, with a bound on the rest.

    Why the soft end.  ``g(lambda) = Re sqrt(lambda) = sqrt((|lambda| + Re
    lambda)/2)``: a positive eigenvalue grows at ``sqrt(lambda)``, a pair
    ``a + ib`` with ``a < 0`` at ``~ |b| / (2 sqrt|a|)``: for a given ``|b|`` the
    pair nearest zero grows fastest, and shift-invert at ``sigma ~ 0``
    (:func:`soft_end`) finds every eigenvalue in the disc ``|lambda| < r``
    (``r`` the largest modulus returned).  A positive real eigenvalue below
    ``r`` is in it; a larger one is not searched here.

    What it can miss, and the bound.  By Bendixson's theorem on
    ``B = M^-1/2 K M^-1/2`` (similar to ``M^-1 K``), every eigenvalue has
    ``|Im| <= beta = |skew(B)|_2`` and ``Re <= mu = max eig sym(B)``.  Outside
    the disc a pair with ``a <= 0`` has ``g^2 = b^2 / (2 (|lambda| + |a|)) <=
    beta^2 / (2 r)`` and ``g^2 <= beta / 2``; with ``a > 0`` (only when
    ``mu > 0``) ``g^2 <= mu + beta / 2``.  ``bound`` is the largest of these;
    the answer is ``certified`` when the rate found reaches it.  Pairs in the
    bulk of the spectrum (|lambda| ~ |A|/5, the AQS packings' pairs, with
    ``|Im| << beta``) lie outside any affordable disc and are missed: there
    the bound is far above the rate and the answer is not certified; only the
    dense spectrum, or a slicing of the whole real axis, finds them.

    Parameters
    ----------
    K, mass, dof, sigma, tol
        As :func:`soft_end`.
    k : int
        Size of the soft end searched.

    Returns
    -------
    Growth
    """
    soft = soft_end(K, mass, k=k, sigma=sigma, dof=dof, tol=tol)
    k_mat, mass, _ = _inputs(K, mass, None, "fastest_growth")
    g = growth_of(soft.eigenvalues)
    i = int(np.argmax(g))
    mu, beta = _bendixson(k_mat, mass)
    bound = min(beta / np.sqrt(2.0 * soft.radius), np.sqrt(0.5 * beta))
    if mu > 0:
        bound = max(bound, float(np.sqrt(mu + 0.5 * beta)))
    return Growth(float(g[i]), complex(soft.eigenvalues[i]), soft.radius, float(bound),
                  bool(g[i] >= bound), soft)


def compare_with_dense(K, mass, k=12, dof=None, sigma=None, tol=0.0):
    """The sparse soft end and growth against the dense spectrum of the same state.

    Dense: :func:`fricstab.analysis.spectrum.decompose` (with condition
    numbers), zero cluster left out by the same rule; each sparse eigenvalue is
    matched to a dense one among the ``k + 4`` nearest zero (least total distance).

    Returns
    -------
    dict
        ``max_abs`` and ``max_rel`` (relative to ``|lambda|``) differences of
        the soft end; ``bound_ratio``: the largest ``|difference| / (10 cond
        (eta + n eps) |A|_inf)`` (the error model of the module doc, both
        solvers' backward errors; <= 1 expected); ``pairs_sparse`` and
        ``pairs_dense`` (conjugate pairs in the disc ``|lambda| <= radius``); ``growth_sparse``
        (:func:`fastest_growth` over the same soft end), ``growth_dense_soft``
        (the same over the dense soft end), ``growth_dense`` (whole spectrum),
        ``certified`` and ``bound``.
    """
    from scipy.optimize import linear_sum_assignment

    from fricstab.analysis.spectrum import decompose
    fast = fastest_growth(K, mass, k=k, dof=dof, sigma=sigma, tol=tol)
    soft = fast.soft
    k_mat, mass, _ = _inputs(K, mass, None, "compare_with_dense")
    spec = decompose(k_mat.toarray(), mass)
    w, cond = spec.eigenvalues, spec.condition
    keep = np.abs(w) > ZERO_CLUSTER * soft.scale
    w, cond = w[keep], cond[keep]
    cand = _order(w)[:len(soft.eigenvalues) + 4]
    cost = np.abs(w[cand][:, None] - soft.eigenvalues[None, :])
    rows, cols = linear_sum_assignment(cost)
    idx = cand[rows[np.argsort(cols)]]
    wd, cd = w[idx], cond[idx]
    diff = np.abs(wd - soft.eigenvalues)
    n = len(mass)
    model = 10.0 * cd * (soft.backward_error + n * np.finfo(float).eps) * soft.scale
    return {"max_abs": float(diff.max()),
            "max_rel": float((diff / np.abs(wd)).max()),
            "bound_ratio": float((diff / model).max()),
            "pairs_sparse": int(np.sum(soft.eigenvalues.imag > 0)),
            "pairs_dense": int(np.sum((w.imag > 0) & (np.abs(w) <= soft.radius * (1 + 1e-9)))),
            "growth_sparse": fast.rate, "growth_dense_soft": float(growth_of(wd).max()),
            "growth_dense": float(growth_of(w).max()) if w.size else 0.0,
            "certified": fast.certified, "bound": fast.bound, "radius": soft.radius}
