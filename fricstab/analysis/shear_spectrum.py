"""The Jacobian of a sheared packing (walls clamped) from the engine, and its spectrum.

For one state of the plane-shear cell (Lee & Hurley Sec. 2, any contact law)
this module builds the engine :class:`~fricstab.engine.System` with the wall
rows clamped (families 1 and 2 carry no dof) and a :class:`~fricstab.engine.State`
with the recorded contact histories, takes ``K = dF/dq`` from
:func:`fricstab.engine.jacobian` (the verified generated blocks, histories
advanced by the law's increment rule, a contact on its cap on the slide
branch) and the dynamical matrix ``D = -M^{-1} K`` with the generalized
masses ``system.gmass`` (``m, m, I/s^2``).  Units: those of the inputs (SI
for frames, reduced for a run's own state).

Shapes and conventions
----------------------
* ``pos`` (N, 2), ``theta`` (N,), ``radius``, ``mass``, ``inertia`` (N,);
  x periodic with box length ``lx``, y open; ``kind`` (N,): 0 bulk, 1 bottom
  row, 2 top row.
* ``contacts`` (M, 2) pairs ``(i, j)``, ``i < j``, with their histories
  ``hist`` (M, H) in the law's slots (``lee_hurley``: ft, mr; ``charan``,
  ``ishima``: tx, ty; ``hertz``: none) and, optionally, the cap ``flags``
  (M,) of the run that recorded them (bit 1 tangential, bit 2 rolling).
* Degrees of freedom: the engine's, ``dof`` per bulk particle in the order
  of ``np.flatnonzero(kind == 0)``.  ``D = -M^{-1} K``: a stable real mode has
  a positive eigenvalue ``omega^2``.

Recorded branches (:data:`CAP_REL`)
-----------------------------------
A history exactly on its cap is on the slide branch of the generated kernels
(``>=``).  A frame stores its histories in SI, converted from the reduced
units of the run, and the cap recomputed from the SI positions differs from
the converted history by a few ulp: the branch could flip.  So when the
run's flags are given, a history recorded on its cap is moved outside it by
the relative :data:`CAP_REL` and projected back onto the recomputed cap (the
slide branch), and one recorded inside that the recomputation puts on its cap
is moved inside by the same ``CAP_REL``.  The forces change by ``CAP_REL`` of
the cap at most, far below anything derived from them.  Histories in the
run's own units (a checkpoint, the regression state) need no flags.

Spectrum routes
---------------
Small-amplitude motion ``M q'' = K q`` has modes ``exp(s t)`` with
``s^2 = -lambda``; the growth rate of a mode is ``|Re sqrt(-lambda)|`` (0 for
a positive real lambda, > 0 for a negative one or a complex pair: flutter).
A degree of freedom whose column or row of K is zero (a disk without a
touching contact: a rattler) gives an exact zero eigenvalue (D is block
triangular), and the rest of the spectrum is that of D without it; their
number is ``n_null``.

* ``dense`` (:func:`spectrum`): every eigenvalue, ``scipy.linalg.eigvals``
  of D (up to :data:`MAX_DENSE_DOF` degrees of freedom): the statistics are
  over the whole spectrum.
* ``soft`` (:func:`soft_spectrum`): only the soft end, the ``k`` eigenvalues
  of smallest modulus ``|lambda| = |omega|^2`` beside the null dof, by
  shift-invert ARPACK (``scipy.sparse.linalg.eigs``, ``sigma = -SHIFT_REL *
  radius``) on the sparse ``S = -M^{-1/2} K M^{-1/2}`` without the null dof.
  S is similar to D and as close to normal as K is to symmetric; D itself is
  far from normal (``m`` and ``I/s^2`` differ by ~1e13 in SI), which would
  cost ARPACK six digits.

What the soft route reports, over its window (:func:`softest`) only:
complex pairs *among the k softest* (the dense route counts them over the
whole spectrum, most of them stiffer); the largest growth rate *among the k
softest* (a lower bound of the dense one, whose maximum may sit in a stiffer
pair); the lowest real eigenvalue of the window, or 0 when ``n_null > 0``
(the dense value whenever the dense minimum is 0 or a negative eigenvalue
softer than the window's edge).  The spectral radius (the scale of the pair
threshold :data:`IMAG_TOL`) comes from an ARPACK estimate of the largest
modulus to :data:`RADIUS_TOL`.  Where ARPACK does not converge or the
shifted matrix is exactly singular, the route takes the dense eigenvalues in
the same window and says why in ``fallback``.

Error of the soft route: ARPACK stops when the residual of a Ritz pair of
``(S - sigma)^-1`` is below ``tol`` times its Ritz value, so an eigenvalue
moves by ``~ cond * max(tol, eps) * |lambda|`` (``cond`` its condition
number in S), plus ``~ cond * n eps |S|`` from the sparse LU: the size of the
dense route's own round-off.  ``bench_slip_spectra.py`` measures it.
"""

import math
from dataclasses import dataclass

import numpy as np
import scipy.linalg
import scipy.sparse.linalg

from fricstab.engine import Material, System, jacobian
from fricstab.errors import ParameterError, check_finite

__all__ = ["CAP_REL", "CAP_SLOTS", "IMAG_TOL", "MAX_DENSE_DOF", "RADIUS_TOL", "ROUTES",
           "SHIFT_REL", "SOFT_K", "SOFT_TOL", "ShearSpectrum", "check_window", "clamped_system",
           "recorded_state", "soft_spectrum", "softest", "spectrum"]

#: Largest problem for the dense eigenvalue route (3,000 dof: ~1 min, 0.2 GB).
MAX_DENSE_DOF = 3000
#: A pair is complex when |Im lambda| > IMAG_TOL * spectral radius; the
#: round-off of a dense nonsymmetric eigensolver is ~eps * radius * condition,
#: so 1e-8 leaves a margin of ~1e8 / condition over it.
IMAG_TOL = 1e-8
#: Relative move of a recorded history off (or onto) its cap (module docstring).
CAP_REL = 1e-9
#: History slots of each flag bit: bit 1 the tangential cap, bit 2 the rolling cap.
CAP_SLOTS = {"lee_hurley": {1: (0,), 2: (1,)}, "charan": {1: (0, 1)}, "linear": {1: (0, 1)},
             "charan_fi": {1: (0,)}, "linear_fi": {1: (0,)}}
#: Spectrum routes (module docstring).
ROUTES = ("soft", "dense")
#: Default window of the soft route: the k eigenvalues of smallest modulus.
SOFT_K = 50
#: ARPACK tolerance of the soft route (0: machine precision).
SOFT_TOL = 0.0
#: Relative tolerance of the ARPACK estimate of the spectral radius (it only
#: scales the pair threshold IMAG_TOL, where a factor 1 + 1e-3 is immaterial).
RADIUS_TOL = 1e-3
#: Shift of the soft route, ``sigma = -SHIFT_REL * radius``: off an exact
#: singularity of K (a mechanism, not only rattlers), far below the soft end.
SHIFT_REL = 1e-9


@dataclass(frozen=True)
class ShearSpectrum:
    """Spectrum of ``D = -M^{-1} K`` (module docstring), whole or its soft end.

    Attributes
    ----------
    eigenvalues : ndarray of complex
        ``dense``: all eigenvalues of D, sorted by real part; ``soft``: those
        of the window, the same as ``softest``.
    n_complex_pairs : int
        Conjugate pairs with ``|Im lambda| > IMAG_TOL * spectral_radius``
        (``soft``: among the window).
    max_growth_rate : float
        ``max |Re sqrt(-lambda)|`` (1/time) (``soft``: over the window).
    lowest_real_eigenvalue : float
        Smallest real part among the eigenvalues counted as real, 0 included
        when ``n_null > 0`` (NaN if none).
    symmetric : bool
        Whether K is symmetric to 1e3 eps of its largest entry.
    n_sliding, n_rolling : int
        Touching contacts with the tangential (rolling) history on its cap.
    route : str
        ``"dense"`` or ``"soft"`` (:data:`ROUTES`).
    softest : ndarray of complex
        The k eigenvalues of smallest modulus beside the exact zeros of the
        null dof, sorted by modulus (:func:`softest`).
    n_null : int
        Degrees of freedom with a zero column or row of K (each an exact zero eigenvalue).
    spectral_radius : float
        ``max |lambda|`` (``soft``: the ARPACK estimate, to :data:`RADIUS_TOL`).
    fallback : str
        ``soft`` only: why ARPACK gave way to the dense eigenvalues ("" if it did not).
    """

    eigenvalues: np.ndarray
    n_complex_pairs: int
    max_growth_rate: float
    lowest_real_eigenvalue: float
    symmetric: bool
    n_sliding: int = 0
    n_rolling: int = 0
    route: str = "dense"
    softest: np.ndarray = None
    n_null: int = 0
    spectral_radius: float = float("nan")
    fallback: str = ""


def clamped_system(law, law_params, radius, mass, inertia, kind, lx, skin=None):
    """The engine System of a cell state: walls clamped, no dashpots, contacts by neighbour list.

    ``skin`` (length, default a tenth of the smallest radius) only decides
    which pairs are listed; pairs that do not touch carry no force.
    """
    radius = np.asarray(radius, float)
    skin = 0.1 * float(radius.min()) if skin is None else skin
    return System(Material(law, dict(law_params)), radius, mass, inertia,
                  family=np.asarray(kind, np.int8), lx=float(lx), skin=skin)


def _check(system, pos, theta, contacts, hist, flags):
    n = system.n
    if np.shape(pos) != (n, 2):
        raise ParameterError(f"pos must have shape ({n}, 2), got {np.shape(pos)}")
    if np.shape(theta) != (n,):
        raise ParameterError(f"theta must have shape ({n},), got {np.shape(theta)}")
    m = len(contacts)
    h = system.material.info.n_hist
    if np.shape(contacts) != (m, 2) or np.shape(hist) != (m, h):
        raise ParameterError(f"contacts must be (M, 2) with hist (M, {h}) "
                             f"({system.material.law}), got {np.shape(contacts)}, "
                             f"{np.shape(hist)}")
    if flags is not None and np.shape(flags) != (m,):
        raise ParameterError(f"flags must have shape ({m},), got {np.shape(flags)}")
    if m and (np.min(contacts) < 0 or np.max(contacts) >= n):
        raise ParameterError(f"contacts must index particles 0..{n - 1}")
    if m and np.any(contacts[:, 0] >= contacts[:, 1]):
        raise ParameterError("contacts must be pairs (i, j) with i < j")


def recorded_state(system, pos, theta, contacts, hist, flags=None):
    """A State at ``pos``, ``theta`` with the recorded histories of ``contacts``.

    Pairs the neighbour list finds that are not in ``contacts`` start with
    zero history; with ``flags``, every history is put on the branch the run
    recorded (module docstring, :data:`CAP_REL`).  Raises ParameterError for
    a recorded contact the neighbour list does not find (it does not touch).
    """
    contacts = np.asarray(contacts, np.int64).reshape(-1, 2)
    hist = np.asarray(hist, float).reshape(len(contacts), -1)
    _check(system, pos, theta, contacts, hist, flags)
    state = system.state(np.asarray(pos, float), np.asarray(theta, float))
    c = state.contacts
    n = system.n
    pair = c.j >= 0
    have = c.i[pair] * n + c.j[pair]
    rows = np.flatnonzero(pair)
    if len(np.unique(have)) != len(have):
        raise ParameterError("a pair touches in two periodic images: the box is too narrow")
    order = np.argsort(have)
    want = contacts[:, 0] * n + contacts[:, 1]
    at = np.searchsorted(have[order], want)
    found = (at < len(have)) & (have[order][np.minimum(at, len(have) - 1)] == want)
    if not found.all():
        i, j = contacts[np.flatnonzero(~found)[0]]
        raise ParameterError(f"recorded contact ({i}, {j}) is not within reach at pos")
    target = rows[order[at]]
    c.hist[:] = 0.0
    c.hist[target, :hist.shape[1]] = hist
    if flags is not None:
        _recorded_branch(system, state, target, np.asarray(flags, np.int64))
    system.project(state)
    return state


def _recorded_branch(system, state, target, flags):
    """Move histories onto the cap branch of ``flags`` (module docstring)."""
    slots = CAP_SLOTS.get(system.material.law, {})
    h = state.contacts.hist
    for bit, idx in slots.items():
        on = target[(flags & bit) != 0]
        h[np.ix_(on, idx)] *= 1.0 + CAP_REL
    system.project(state)
    now = state.contacts.flag
    for bit, idx in slots.items():
        spurious = target[((now[target] & bit) != 0) & ((flags & bit) == 0)]
        h[np.ix_(spurious, idx)] *= 1.0 - CAP_REL


def softest(eigenvalues, k):
    """The ``k`` eigenvalues of smallest modulus, sorted by modulus.

    A conjugate pair split by the edge is kept whole: ``k + 1`` values.
    """
    w = np.asarray(eigenvalues, complex)
    w = w[np.argsort(np.abs(w), kind="stable")]
    if k < len(w) and w[k - 1].imag != 0 and w[k] == np.conj(w[k - 1]):
        k += 1
    return w[:k]


def check_window(k, name="k"):
    """``k`` as an int >= 1 (the soft window), or ParameterError naming ``name``."""
    if isinstance(k, bool) or not isinstance(k, (int, np.integer)) or k < 1:
        raise ParameterError(f"{name} must be an integer >= 1, got {k!r}")
    return int(k)


def _stiffness(system, state):
    """``K`` (CSC), whether it is symmetric, the mask of null dof, the generalized masses."""
    if system.dof * int(system.free.sum()) == 0:
        raise ParameterError("the state has no bulk particle (family 0)")
    system.project(state)
    _, k = jacobian(system, state)
    k = k.tocsc()
    if not np.isfinite(k.data).all():          # LAPACK, ARPACK would refuse it unnamed
        check_finite("stiffness entry", k.toarray(), item="row")
    big = abs(k).max() if k.nnz else 0.0
    symmetric = bool(abs(k - k.T).max() <= 1e3 * np.finfo(float).eps * big) if big else True
    a = abs(k)
    null = (np.asarray(a.sum(axis=0)).ravel() == 0) | (np.asarray(a.sum(axis=1)).ravel() == 0)
    return k, symmetric, null, system.gmass[system.free, :system.dof].ravel()


def _result(state, lam, window, radius, symmetric, n_null, route, fallback=""):
    """The statistics over ``lam`` (dense: all; soft: the window), ``window`` the k softest."""
    is_complex = np.abs(lam.imag) > IMAG_TOL * radius
    growth = np.abs(np.sqrt(-lam.astype(complex)).real)
    real = lam.real[~is_complex]
    if n_null:
        real = np.append(real, 0.0)
    flag = state.contacts.flag     # 0 for a listed pair that does not touch
    return ShearSpectrum(
        eigenvalues=lam, n_complex_pairs=int(is_complex.sum() // 2),
        max_growth_rate=float(growth.max()) if growth.size else 0.0,
        lowest_real_eigenvalue=float(real.min()) if real.size else float("nan"),
        symmetric=symmetric, n_sliding=int(((flag & 1) != 0).sum()),
        n_rolling=int(((flag & 2) != 0).sum()), route=route, softest=window, n_null=n_null,
        spectral_radius=float(radius), fallback=fallback)


def _eigvals_dense(k, mass):
    """Every eigenvalue of ``-diag(mass)^-1 k``, sorted by real part."""
    n_dof = k.shape[0]
    if n_dof > MAX_DENSE_DOF:
        raise ParameterError(f"{n_dof} degrees of freedom exceed the dense route "
                             f"(MAX_DENSE_DOF = {MAX_DENSE_DOF}); use the soft route")
    lam = scipy.linalg.eigvals(-k.toarray() / mass[:, None])
    return lam[np.argsort(lam.real, kind="stable")]


def spectrum(system, state, k=SOFT_K):
    """Whole spectrum of ``D = -M^{-1} K`` of one state (walls clamped): a :class:`ShearSpectrum`.

    Its ``softest`` holds the window of the ``k`` softest, as the soft route reports it.
    """
    k = check_window(k)
    kk, symmetric, null, mass = _stiffness(system, state)
    lam = _eigvals_dense(kk, mass)
    n_null = int(null.sum())
    radius = np.abs(lam).max() if lam.size else 0.0
    window = softest(lam[np.argsort(np.abs(lam), kind="stable")][n_null:], k)
    return _result(state, lam, window, radius, symmetric, n_null, "dense")


def soft_spectrum(system, state, k=SOFT_K, tol=SOFT_TOL):
    """The ``k`` softest eigenvalues of ``D`` by shift-invert ARPACK: a :class:`ShearSpectrum`.

    Module docstring: what the window can and cannot report, its error, and
    the dense fallback when ARPACK fails (recorded in ``fallback``).
    """
    k = check_window(k)
    if not (math.isfinite(tol) and tol >= 0):
        raise ParameterError(f"tol must be a finite number >= 0, got {tol!r}")
    kk, symmetric, null, mass = _stiffness(system, state)
    keep = np.flatnonzero(~null)
    kk, mass = kk[keep][:, keep], mass[keep]
    n, fallback = len(keep), ""
    if n == 0:
        lam, radius = np.zeros(0, complex), 0.0
    elif k + 2 >= n - 1:            # ARPACK needs k < n - 1: small enough for dense
        lam = _eigvals_dense(kk, mass)
        radius = np.abs(lam).max()
    else:
        w = scipy.sparse.diags(1.0 / np.sqrt(mass))
        s = (-(w @ kk @ w)).tocsc()     # similar to D, but as normal as K is symmetric
        v0 = np.random.default_rng(0).standard_normal(n)      # reproducible Krylov start
        try:
            radius = float(np.abs(scipy.sparse.linalg.eigs(
                s, k=1, which="LM", tol=RADIUS_TOL, v0=v0,
                return_eigenvectors=False)).max())
            lam = scipy.sparse.linalg.eigs(s, k=k + 2, sigma=-SHIFT_REL * radius, which="LM",
                                           tol=tol, v0=v0, return_eigenvectors=False)
        except RuntimeError as exc:   # ArpackError (no convergence), splu: exactly singular
            fallback = f"{type(exc).__name__}: {exc}".strip()
            lam = _eigvals_dense(kk, mass)
            radius = np.abs(lam).max()
    window = softest(lam, k)
    return _result(state, window, window, radius, symmetric, len(null) - n, "soft", fallback)
