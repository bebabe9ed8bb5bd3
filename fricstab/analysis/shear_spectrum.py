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

Spectrum route: dense ``scipy.linalg.eigvals`` of D (up to
:data:`MAX_DENSE_DOF` degrees of freedom).  Small-amplitude motion
``M q'' = K q`` has modes ``exp(s t)`` with ``s^2 = -lambda``; the growth rate
of the state is ``max_lambda |Re sqrt(-lambda)|`` (0 for a positive real
lambda, > 0 for a negative one or a complex pair: flutter).
"""

from dataclasses import dataclass

import numpy as np
import scipy.linalg

from fricstab.engine import Material, System, jacobian
from fricstab.errors import ParameterError, check_finite

__all__ = ["CAP_REL", "CAP_SLOTS", "IMAG_TOL", "MAX_DENSE_DOF", "ShearSpectrum",
           "clamped_system", "recorded_state", "spectrum"]

#: Largest problem for the dense eigenvalue route (3,000 dof: ~1 min, 0.2 GB).
MAX_DENSE_DOF = 3000
#: A pair is complex when |Im lambda| > IMAG_TOL * spectral radius; the
#: round-off of a dense nonsymmetric eigensolver is ~eps * radius * condition,
#: so 1e-8 leaves a margin of ~1e8 / condition over it.
IMAG_TOL = 1e-8
#: Relative move of a recorded history off (or onto) its cap (module docstring).
CAP_REL = 1e-9
#: History slots of each flag bit: bit 1 the tangential cap, bit 2 the rolling cap.
CAP_SLOTS = {"lee_hurley": {1: (0,), 2: (1,)}, "charan": {1: (0, 1)}}


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
    n_sliding, n_rolling : int
        Touching contacts with the tangential (rolling) history on its cap.
    """

    eigenvalues: np.ndarray
    n_complex_pairs: int
    max_growth_rate: float
    lowest_real_eigenvalue: float
    symmetric: bool
    n_sliding: int = 0
    n_rolling: int = 0


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


def spectrum(system, state):
    """Spectrum of ``D = -M^{-1} K`` of one state (walls clamped): a :class:`ShearSpectrum`."""
    n_dof = system.dof * int(system.free.sum())
    if n_dof == 0:
        raise ParameterError("the state has no bulk particle (family 0)")
    if n_dof > MAX_DENSE_DOF:
        raise ParameterError(f"{n_dof} degrees of freedom exceed the dense route "
                             f"(MAX_DENSE_DOF = {MAX_DENSE_DOF})")
    system.project(state)
    _, k = jacobian(system, state)
    kd = k.toarray()
    check_finite("stiffness entry", kd, item="row")     # LAPACK would refuse it unnamed
    big = np.abs(kd).max() if kd.size else 0.0
    symmetric = bool(np.abs(kd - kd.T).max() <= 1e3 * np.finfo(float).eps * big) if big else True
    minv = 1.0 / system.gmass[system.free, :system.dof].ravel()
    lam = scipy.linalg.eigvals(-minv[:, None] * kd)
    lam = lam[np.argsort(lam.real, kind="stable")]
    radius_d = np.abs(lam).max() if lam.size else 0.0
    is_complex = np.abs(lam.imag) > IMAG_TOL * radius_d
    growth = np.abs(np.sqrt(-lam.astype(complex)).real)
    real = lam.real[~is_complex]
    flag = state.contacts.flag     # 0 for a listed pair that does not touch
    return ShearSpectrum(
        eigenvalues=lam, n_complex_pairs=int(is_complex.sum() // 2),
        max_growth_rate=float(growth.max()) if growth.size else 0.0,
        lowest_real_eigenvalue=float(real.min()) if real.size else float("nan"),
        symmetric=symmetric, n_sliding=int(((flag & 1) != 0).sum()),
        n_rolling=int(((flag & 2) != 0).sum()))
