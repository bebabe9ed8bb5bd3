"""Athermal quasistatic shear (AQS) of a periodic packing with tangential history (issue 17).

Each strain step ``dgamma`` is the step of :mod:`fricstab.protocols.stepstrain`:
an affine move ``x_i -> x_i + dgamma y_i`` with the Lees-Edwards offset
``shift -> shift + dgamma L`` at frozen history, then Newton relaxation
(:func:`fricstab.engine.newton`, bordered solver, the verified Jacobian) with
the histories carried by the increment rule along the iterates and projected
(Coulomb cap of charan) at each; contacts are created (zero history) and lost
as the iterates move.  Each iteration's largest coordinate change is capped at
:data:`MAX_STEP` so that an iterate cannot jump past contacts.  Where Newton
does not converge, or converges to an equilibrium with a real positive
eigenvalue (a saddle: the branch ended in a plastic event), the step is
relaxed by FIRE from the affine state (damped dynamics, history by the
increment rule) to ``FIRE_TOL`` and polished by Newton; the step is then
flagged ``fire``.  A singular bordered solve (a disk that lost its contacts)
is retried by the regularized sparse solve (a sparse LU of K + s I, the
minimum-norm step up to O(s); :func:`fricstab.engine.newton.regularized_solve`),
for at most ``singular_iter`` iterations (:func:`relax_step`) before FIRE; the
polish after FIRE may take the full 60, and is also restarted that way when the
bordered solve stalls
unconverged without raising (a nearly singular Jacobian).  A step that still
has no equilibrium raises
:class:`~fricstab.errors.ConvergenceError` naming the step and its strain.

Spectrum.  At each relaxed state, the eigenvalues of ``M^-1 K`` (``K = dF/dq``,
Charan's sign: stable modes have lambda < 0) on the complement of the two
uniform translations (:func:`spectrum`: ``K`` annihilates them on both sides
in a periodic box, so the complement ``C^T M x = 0`` is invariant and the
exact zero pair is deflated rather than thresholded).  A complex pair is
counted (:func:`pairs`) when ``|lambda| > ZERO_CLUSTER max |lambda|``: a zero
eigenvalue of multiplicity m (a disk that lost its contacts) is smeared by
round-off over ``(eps |A|^m)^(1/m) <= sqrt(eps) |A| = 1.5e-8 |A|``, well below.
Pairs are matched between steps as in the chain ramp
(:func:`fricstab.protocols.ramp._match`); each birth and death is located by
bisection in strain on the sign of the pair indicator
(:func:`fricstab.analysis.spectrum.pair_indicator`), every trial relaxed from
the equilibrium of the step before the event, to ``tol`` (default 1e-6):
``gamma_hi - gamma_lo <= tol``.  The growth rate is ``growth_rate`` (largest
``Im sqrt(-lambda)`` = largest ``Re sqrt(lambda)``).
"""

import time
from dataclasses import dataclass, field

import numpy as np
import scipy.linalg

from fricstab import signals
from fricstab.analysis.spectrum import complex_pairs, growth_rate, pair_indicator, tracking_radius
from fricstab.engine import fire, jacobian, newton
from fricstab.engine.newton import touching, translation_modes
from fricstab.engine.system import check_system_state
from fricstab.errors import ConvergenceError, ParameterError, check_real
from fricstab.protocols.ramp import _match
from fricstab.protocols.stepstrain import affine_step, shear_stress
from fricstab.scenes.packing_relax import singular_guard

__all__ = ["AQSResult", "Event", "MAX_STEP", "TOL_ULPS", "ZERO_CLUSTER", "check_strain",
           "check_tol", "pairs",
           "reduced_matrix", "relax_step", "run_aqs", "spectrum"]

MAX_STEP = 2e-3        # largest coordinate change of one Newton iteration, in d
ZERO_CLUSTER = 1e-6    # pairs with |lambda| below this times max |lambda| are zero modes
FIRE_TOL = 1e-9        # FIRE fallback, before the Newton polish
FIRE_MAX_ITER = 2_000_000
EVENT_COLUMNS = ("kind", "step", "gamma_lo", "gamma_hi", "center", "radius", "bisections",
                 "located", "growth_hi")


def check_strain(strain, dgamma):
    """``dgamma > 0`` finite and ``strain >= dgamma`` (ParameterError naming the option)."""
    real = (int, float, np.integer, np.floating)
    if not (isinstance(dgamma, real) and np.isfinite(dgamma) and dgamma > 0):
        raise ParameterError(f"--dgamma must be a finite number > 0, got {dgamma!r}")
    if not (isinstance(strain, real) and np.isfinite(strain) and strain >= dgamma):
        raise ParameterError(f"--strain must be a finite number >= --dgamma = {dgamma:g}, "
                             f"got {strain!r}")
    if strain / dgamma > 10_000_000:
        raise ParameterError(f"--strain / --dgamma = {strain / dgamma:.3g} steps; at most 1e7")


#: The finest bracket the bisection resolves, in units of the spacing of doubles at the
#: final strain (its midpoints stop being new strains a few ulps apart).
TOL_ULPS = 4


def check_tol(tol, strain):
    """``tol`` finite, > 0 and at least :data:`TOL_ULPS` ulps of ``strain`` (ParameterError)."""
    if not (isinstance(tol, (int, float)) and np.isfinite(tol) and tol > 0):
        raise ParameterError(f"--tol must be a finite number > 0, got {tol!r}")
    floor = TOL_ULPS * float(np.spacing(abs(float(strain))))
    if tol < floor:
        raise ParameterError(f"--tol {tol:g} is below what the bisection can resolve at "
                             f"strain {strain:g}: {TOL_ULPS} ulps of the strain = {floor:.3g}; "
                             f"give --tol >= {floor:.3g}")


def reduced_matrix(k, gmass, n_free, dof):
    """``B^T M^-1 K B`` with ``B`` an orthonormal basis of ``{x: C^T M x = 0}`` (dense), and B."""
    c = translation_modes(n_free, dof)
    basis = scipy.linalg.qr(c * gmass[:, None], mode="full")[0][:, 2:]
    a = (k.toarray() if hasattr(k, "toarray") else np.asarray(k)) / gmass[:, None]
    return basis.T @ (a @ basis), basis


def spectrum(system, state):
    """Eigenvalues of M^-1 K without the translations (module doc), sorted by real part; K."""
    _, k = jacobian(system, state)
    gm = system.gmass[system.free, :system.dof].ravel()
    a, _ = reduced_matrix(k, gm, int(system.free.sum()), system.dof)
    w = scipy.linalg.eigvals(a)
    return w[np.argsort(w.real, kind="stable")], k


def pairs(eigenvalues):
    """The counted conjugate pairs (Im > 0 member), zero-mode clusters left out (module doc)."""
    w = complex_pairs(eigenvalues)
    scale = float(np.abs(eigenvalues).max()) if eigenvalues.size else 0.0
    return w[np.abs(w) > ZERO_CLUSTER * scale]


def _unstable(eigenvalues):
    """A real eigenvalue above the zero cluster: the equilibrium is a saddle."""
    scale = float(np.abs(eigenvalues).max()) if eigenvalues.size else 0.0
    real = eigenvalues[eigenvalues.imag == 0].real
    return bool(real.size and real.max() > ZERO_CLUSTER * scale)


def _newton(system, state, f_tol, max_iter=60, singular_iter=None, retry_stalled=False):
    """Newton, bordered solver; a singular one (a disk lost its contacts) by the regularized
    sparse solve (:func:`fricstab.engine.newton.regularized_solve`), for at most
    ``singular_iter`` iterations (default ``max_iter``).  That fallback was dense least
    squares up to 3,000 dof and LSMR above: at N = 512 (charan, strain steps 340-352) 85 % of
    the path's time, 2.0 s a solve (LSMR 5.7 s); the regularized solve 0.02 s, with the same
    iterations and stresses.

    ``retry_stalled``: also restart by the fallback from the same state when the bordered
    Newton ends unconverged without raising.  A nearly (not exactly) singular Jacobian does
    that: measured at N = 512 (hertz, strain step 34, after FIRE), the bordered Newton stalls
    at max|F| = 8.7e-10 through 60 iterations while the fallback (then dense least squares)
    converges in 2 to 1.6e-15.
    """
    # imported here: a module-level import would change the frame every stamped run holds
    from fricstab._stderr import drop_c_lines
    backup = state.copy()
    try:
        # SuperLU on a singular matrix prints BLAS's "illegal value" lines (the singularity
        # is handled below); they are dropped
        with singular_guard("Newton relaxation"), drop_c_lines():
            res = newton(system, state, f_tol, max_iter=max_iter, solver="bordered",
                         max_step=MAX_STEP, raise_on_failure=False)
        if res.converged or not retry_stalled:
            return res
    except ConvergenceError:
        pass
    state.__dict__.update(backup.copy().__dict__)
    return newton(system, state, f_tol, solver="regularized", max_step=MAX_STEP,
                  max_iter=max_iter if singular_iter is None else singular_iter,
                  raise_on_failure=False)


def relax_step(system, prev, dgamma, f_tol, where="", use_fire=False, singular_iter=8):
    """The equilibrium after an affine step ``dgamma`` from ``prev`` (a copy); (state, fire used).

    Newton first (unless ``use_fire``); FIRE and a Newton polish if it fails.
    Raises :class:`ConvergenceError` naming ``where`` when neither converges.

    ``singular_iter``: Newton iterations of the singular fallback (:func:`_newton`) tried on
    a singular Jacobian before FIRE (the polish after FIRE may take the full 60).  Measured
    at N = 512 (charan, strain 0.036, a disk without contacts and one with a single
    contact; the fallback then dense least squares): its iterates wander along the near-zero modes (residual 8e-5 -> 1e-6 in 30 iterations, never
    converging) at 2 s an iteration, while FIRE and the polish take seconds; a Newton that
    converges from the affine state does so in a few iterations.
    """
    affine = affine_step(system, prev, dgamma)
    if not use_fire:
        s = affine.copy()
        try:
            if _newton(system, s, f_tol, singular_iter=singular_iter).converged:
                return s, False
        except ConvergenceError:
            pass
    s = affine.copy()
    s.v[:] = 0.0
    it, res = fire(system, s, FIRE_TOL, FIRE_MAX_ITER)
    # the polish also when FIRE ran out: ishima at N = 64 (seed 3, strain step 125) leaves
    # FIRE at 5.6e-8 after its 2e6 iterations
    res_newton = _newton(system, s, f_tol, retry_stalled=True)
    if not res_newton.converged:
        raise ConvergenceError(f"relaxation {where} did not reach max|F| < {f_tol:g} "
                               f"(FIRE residual {res:.3g} after {it} iterations, then Newton)")
    return s, True


@dataclass(frozen=True)
class Event:
    """A birth or death of a complex pair, located in strain (``gamma_hi - gamma_lo <= tol``)."""

    kind: str
    step: int            # the strain step in which it happened (between step - 1 and step)
    gamma_lo: float
    gamma_hi: float
    center: float        # real part of the pair (t0^-2)
    radius: float
    bisections: int
    located: bool
    growth_hi: float     # growth rate of the pair's side of the bracket (birth: hi)

    @property
    def gamma(self):
        return 0.5 * (self.gamma_lo + self.gamma_hi)

    def row(self):
        return [0.0 if self.kind == "birth" else 1.0, self.step, self.gamma_lo, self.gamma_hi,
                self.center, self.radius, self.bisections, float(self.located), self.growth_hi]

    @classmethod
    def from_row(cls, r):
        return cls("birth" if r[0] == 0 else "death", int(r[1]), float(r[2]), float(r[3]),
                   float(r[4]), float(r[5]), int(r[6]), bool(r[7]), float(r[8]))


@dataclass
class AQSResult:
    """The path: per state (step 0 = the start) strain, stress, spectrum summaries; the events."""

    strain: np.ndarray
    stress: np.ndarray
    n_pairs: np.ndarray
    growth: np.ndarray
    pair_min_imag: np.ndarray  # smallest |Im lambda| of the counted pairs (NaN: no pair)
    min_real: np.ndarray      # the largest real part of the spectrum (closest to instability)
    contacts: np.ndarray      # touching contacts
    fire: np.ndarray          # bool: the step needed FIRE
    events: list = field(default_factory=list)
    seconds: float = 0.0
    failure: str = None       # on_failure="stop": why the path ended early


def _indicator(system, prev, dgamma, f_tol, center, radius, where):
    s, _ = relax_step(system, prev, dgamma, f_tol, where)
    w, _ = spectrum(system, s)
    d, c = pair_indicator(w, center, radius)
    return d, c, s, w


def locate(system, prev, gamma_prev, gamma_lo, gamma_hi, center, radius, tol, f_tol,
           max_iter=80):
    """Bisect the sign change of D in strain; ``prev`` is the equilibrium at ``gamma_prev``.

    Returns ``(lo, hi, center, iterations, located, state_lo, state_hi, w_lo, w_hi)``.
    """
    where = f"in the bisection after strain {gamma_prev:.9g}"
    d_lo, _, s_lo, w_lo = _indicator(system, prev, gamma_lo - gamma_prev, f_tol, center,
                                     radius, where)
    d_hi, c_hi, s_hi, w_hi = _indicator(system, prev, gamma_hi - gamma_prev, f_tol, center,
                                        radius, where)
    if np.sign(d_lo) == np.sign(d_hi):
        return gamma_lo, gamma_hi, center, 0, False, s_lo, s_hi, w_lo, w_hi
    it = 0
    while gamma_hi - gamma_lo > tol and it < max_iter:
        mid = 0.5 * (gamma_lo + gamma_hi)
        d_mid, c_mid, s_mid, w_mid = _indicator(system, prev, mid - gamma_prev, f_tol, center,
                                                radius, where)
        if d_mid < 0:
            center = c_mid
        if np.sign(d_mid) == np.sign(d_lo):
            gamma_lo, d_lo, s_lo, w_lo = mid, d_mid, s_mid, w_mid
        else:
            gamma_hi, s_hi, w_hi = mid, s_mid, w_mid
        it += 1
    return gamma_lo, gamma_hi, center, it, True, s_lo, s_hi, w_lo, w_hi


def run_aqs(system, state, strain, dgamma, *, f_tol=1e-13, tol=1e-6, locate_events=True,
            progress=None, resume=None, checkpoint=None, checkpoint_every=0, on_birth=None,
            on_failure="raise"):
    """Athermal quasistatic shear with history: shear ``state`` to ``strain`` in steps ``dgamma``.

    Each step applies the affine simple shear (the Lees-Edwards offset grows by
    ``dgamma L``) at frozen history, then relaxes by Newton with the verified
    Jacobian, the history carried by the law's increment rule (through the
    Coulomb cap for charan; FIRE first when Newton alone does not converge).
    At every relaxed state the spectrum of ``M^-1 K`` is taken (dense);
    complex pairs are tracked between steps as the chain ramp does, and each
    birth and death is bisected in strain on the pair indicator.

    Parameters
    ----------
    system : fricstab.System
        A periodic packing system (:func:`packing_system`); reduced units
        (lengths in d, stiffness k_N, time t0).
    state : fricstab.State
        The start, an equilibrium (it is relaxed here first).
    strain : float
        Final shear strain (dimensionless), ``>= dgamma``.
    dgamma : float
        Strain step, ``> 0``.
    f_tol : float, optional
        Force tolerance of every relaxation, ``max |F|`` in ``k_N d^(3/2)``.
    tol : float, optional
        Bracket of a located pair event in strain (default 1e-6).
    locate_events : bool, optional
        Bisect births and deaths (``False``: step resolution only).
    progress : tqdm-like, optional
        ``progress.update(1)`` after every step (a ``tqdm`` bar, for instance).
    resume : dict, optional
        The arrays of a checkpoint (:class:`AQSResult` fields, ``state_*`` and
        ``step``); the path continues after its step, bit-identically.
    checkpoint : callable, optional
        ``checkpoint(step, arrays)``, called every ``checkpoint_every`` steps.
    checkpoint_every : int, optional
        Steps between checkpoints (0: none).
    on_birth : callable, optional
        ``on_birth(k, event, state_lo, state_hi)`` for every located birth
        (``k`` counts births from 0), with the states at both bracket ends.
    on_failure : {"raise", "stop"}, optional
        A step without equilibrium raises :class:`ConvergenceError` naming the
        step, or (``"stop"``) ends the path there (``failure`` says why).

    Returns
    -------
    AQSResult
        Per state: strain, shear stress (``k_N d^(-1/2)``), pair count,
        growth rate (``t0^-1``, largest Re sqrt(-lambda)), the smallest
        ``|Im lambda|`` of the counted pairs (``t0^-2``, NaN without one), the
        largest real part, contacts; the events
        with their brackets; the wall time.

    Raises
    ------
    ParameterError
        ``dgamma <= 0``, ``strain < dgamma``, a bad ``tol``.
    ConvergenceError
        A relaxation that does not converge (``on_failure="raise"``).
    """
    check_system_state(system, state)
    check_strain(strain, dgamma)
    check_tol(tol, strain)
    check_real("f_tol", f_tol, 0.0, low_open=True)
    t0 = time.perf_counter()
    n_steps = int(np.floor(strain / dgamma + 1e-9))
    grid = dgamma * np.arange(n_steps + 1)
    cols = {name: [] for name in ("stress", "n_pairs", "growth", "pair_min_imag", "min_real",
                                  "contacts", "fire")}
    events = []
    if resume is None:
        s = state.copy()
        with singular_guard("relaxation of the initial state"):
            res = newton(system, s, f_tol, solver="bordered", raise_on_failure=False)
        if not res.converged:
            raise ConvergenceError(f"relaxation of the initial state (step 0) did not reach "
                                   f"max|F| < {f_tol:g} (residual {res.residual:.3g})")
        first, w, used_fire = 0, spectrum(system, s)[0], False
    else:
        from fricstab.engine import State
        s = State.from_arrays({k[6:]: v for k, v in resume.items() if k.startswith("state_")})
        for name in cols:   # a checkpoint from before pair_min_imag: NaN for its steps
            cols[name] = list(resume[name] if name in resume
                              else np.full(len(resume["stress"]), np.nan))
        events = [Event.from_row(r) for r in np.asarray(resume["events"]).reshape(-1, 9)]
        first = int(resume["step"]) + 1
        w = spectrum(system, s)[0]
    births = sum(e.kind == "birth" for e in events)
    failure = None

    def record(state_k, w_k, fire_k):
        cols["stress"].append(shear_stress(system, state_k)[0])
        p_k = pairs(w_k)
        cols["n_pairs"].append(len(p_k))
        cols["growth"].append(growth_rate(w_k))
        cols["pair_min_imag"].append(float(p_k.imag.min()) if p_k.size else np.nan)
        cols["min_real"].append(float(w_k.real.max()))
        cols["contacts"].append(len(touching(system, state_k)))
        cols["fire"].append(fire_k)

    if resume is None:
        record(s, w, used_fire)
        first = 1
    for k in range(first, n_steps + 1):
        signals.check(f" at strain step {k}")
        where = f"at strain step {k} (strain {grid[k]:.9g})"
        try:
            new, used_fire = relax_step(system, s, dgamma, f_tol, where)
            w_new = spectrum(system, new)[0]
            if not used_fire and _unstable(w_new):
                new, used_fire = relax_step(system, s, dgamma, f_tol, where, use_fire=True)
                w_new = spectrum(system, new)[0]
        except ConvergenceError as exc:
            if on_failure != "stop":
                raise
            failure = str(exc)
            break
        prev_pairs, cur_pairs = pairs(w), pairs(w_new)
        scale = 0.1 * (np.abs(w_new.real).max() + 1e-300)
        born, died = _match(prev_pairs, cur_pairs, scale)
        for kind, group, where_w in (("birth", born, w_new), ("death", died, w)):
            for p in group:
                radius = tracking_radius(where_w, p.real)
                if locate_events and not used_fire:
                    lo, hi, c, n_it, ok, s_lo, s_hi, w_lo, w_hi = locate(
                        system, s, grid[k - 1], grid[k - 1], grid[k], p.real, radius, tol,
                        f_tol)
                else:   # a plastic event in the step: the branch is not continuous
                    lo, hi, c, n_it, ok, s_lo, s_hi, w_lo, w_hi = (
                        grid[k - 1], grid[k], p.real, 0, False, s, new, w, w_new)
                ev = Event(kind, k, lo, hi, c, radius, n_it, ok,
                           growth_rate(w_hi if kind == "birth" else w_lo))
                events.append(ev)
                if kind == "birth" and ok and on_birth is not None:
                    on_birth(births, ev, s_lo, s_hi)
                births += kind == "birth"
        s, w = new, w_new
        record(s, w, used_fire)
        if progress is not None:
            progress.update(1)
        if checkpoint is not None and checkpoint_every and k % checkpoint_every == 0:
            checkpoint(k, {**{f"state_{key}": v for key, v in s.arrays().items()},
                           **{name: np.asarray(v) for name, v in cols.items()},
                           "events": np.array([e.row() for e in events], float).reshape(-1, 9)})
    return AQSResult(grid[:len(cols["stress"])],
                     *(np.asarray(cols[n]) for n in ("stress", "n_pairs", "growth",
                                                     "pair_min_imag", "min_real", "contacts",
                                                     "fire")),
                     events=events, seconds=time.perf_counter() - t0, failure=failure)
