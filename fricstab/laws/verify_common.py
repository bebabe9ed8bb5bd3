"""What the kernel proofs share: bounds and steps, the case sampler, the error models.

:mod:`fricstab.laws.verify` (the (kn, kt, mu, t) family) and
:mod:`fricstab.laws.verify_lee_hurley` build on these.  The error models say
how close each reference can come to an exact block: the rounding of a block
(``ROUNDING_ULPS`` eps of the terms a row sums, times the cancellation factor
of the row), and the floor of float64 central differences (truncation,
round-off, first-order terms where a step crosses a kink, lost digits of the
centre distance).
"""

import math
from dataclasses import dataclass

import numpy as np

from fricstab._numerics import overlap_correction

__all__ = [
    "CENTRAL_BOUND", "CENTRAL_STEPS", "COMPLEX_STEP", "EPS", "EXACT_BOUND", "EXTREMES",
    "HARD_CAP", "MP_DPS", "MP_STEP", "ON_CAP", "ROUNDING_ULPS", "TAYLOR_RESOLUTION",
    "TAYLOR_STEPS", "Case",
    "cancellation_factor", "cap_gap", "case_inputs", "central_error_model", "hard_cap_length",
    "on_cap", "exact_reference_bound",
    "pick_extreme", "row_relative_error", "sample_cases", "taylor_consistent",
    "uncancelled_scale"]

EPS = float(np.finfo(float).eps)
MP_DPS = 50
COMPLEX_STEP = 1e-20  # times the column length scale
MP_STEP = 1e-20
#: float64 central-difference steps, times the column length scale.
CENTRAL_STEPS = tuple(10.0 ** (-k / 2) for k in range(2, 29))
#: Smallest Taylor remainder (relative to the row scale) used in the fit.
TAYLOR_RESOLUTION = 1e-30
#: Steps of the Taylor test, times the column length scale.
TAYLOR_STEPS = tuple(10.0 ** (-k) for k in range(3, 9))

#: Acceptance bound of float64 central differences at the best step.
CENTRAL_BOUND = 1e-6
#: Acceptance bound against complex step and 50-digit differences.
EXACT_BOUND = 1e-12
#: Rounding of a generated block in eps of the terms a row sums (~100 flops;
#: measured at most ~10 over 10,000 well-conditioned cases).
ROUNDING_ULPS = 64

#: Laws with a hard Coulomb cap (symbolic/linear.py): F_t = -k_t t, whose block
#: jumps on the circle |t| = t* (sticking and sliding one-sided derivatives).
HARD_CAP = ("linear", "linear_wall", "linear_fi", "linear_fi_wall")
#: Hard cap: a history with ||t|/t* - 1| below this is on the cap; the
#: difference checks skip it (a step would cross the jump), complex step
#: (branch on real parts) checks its sliding block.
ON_CAP = 1e-6

#: Ranges of the configuration space; the ends are sampled exactly.
EXTREMES = {
    "delta_over_R": (1e-12, 1e-1),
    "t_ratio": (0.0, 1.0),
    "kt_over_kn": (1e-10, 10.0),
    "mu": (0.1, 100.0),
    "radius_ratio": (1.0, 1.4),
}


@dataclass(frozen=True)
class Case:
    """One contact configuration, dimensionless.

    ``delta_over_R`` is the overlap over the radius of particle i (the smaller
    one); ``t_ratio`` is ``|t| / t*`` with ``t* = mu (kn/kt) delta`` (for the
    Ishima law, which has no Coulomb limit, ``t*`` only sets the scale of
    ``|t|``); ``phi`` is the angle of the normal n, ``psi`` the angle of the
    history vector (or, for the wall, its sign: ``cos psi``).
    """

    delta_over_R: float
    t_ratio: float
    phi: float
    psi: float
    kt_over_kn: float
    mu: float
    radius_ratio: float


def _log_uniform(rng, lo, hi):
    return float(math.exp(rng.uniform(math.log(lo), math.log(hi))))


def pick_extreme(rng, lo, hi, p, log=True):
    """``lo`` or ``hi`` exactly, each with probability ``p/2``; else log-uniform
    (uniform if ``log`` is false or ``lo <= 0``) in ``[lo, hi]``."""
    u = rng.uniform()
    if u < p / 2:
        return lo
    if u < p:
        return hi
    return _log_uniform(rng, lo, hi) if log and lo > 0 else float(rng.uniform(lo, hi))


def sample_cases(n, seed, p_extreme=0.15, ranges=None):
    """``n`` cases from ``numpy.random.default_rng(seed)``.

    ``ranges`` overrides entries of :data:`EXTREMES`.

    Each parameter takes one of its end points exactly with probability
    ``p_extreme`` (``|t|/t*`` with probability ``2 p_extreme``), otherwise a
    log-uniform value (uniform for ``|t|/t*``, the angles and the radius ratio).
    """
    rng = np.random.default_rng(seed)
    ranges = {**EXTREMES, **(ranges or {})}
    cases = []
    for _ in range(n):
        def pick(key, log=True, p=p_extreme):
            return pick_extreme(rng, *ranges[key], p, log)
        phi = float(rng.uniform(0.0, 2 * math.pi))
        # Half of the histories are tangent to the contact (as the increment
        # rule produces from t = 0), half point anywhere.
        psi = phi + math.pi / 2 if rng.uniform() < 0.5 else float(rng.uniform(0, 2 * math.pi))
        cases.append(Case(
            delta_over_R=pick("delta_over_R"), t_ratio=pick("t_ratio", False, 2 * p_extreme),
            phi=phi, psi=psi, kt_over_kn=pick("kt_over_kn"), mu=pick("mu"),
            radius_ratio=pick("radius_ratio", False)))
    return cases


def case_inputs(law, case, radius=0.5, kn=1.0):
    """Kernel arguments (a tuple of floats, in ``law.inputs`` order) for a case."""
    kt = kn * case.kt_over_kn
    v = {"kn": kn, "kt": kt, "mu": case.mu}
    if law.kind == "pair":
        ri, rj = radius, radius * case.radius_ratio
        r = ri + rj - case.delta_over_R * ri
        dx, dy = r * math.cos(case.phi), r * math.sin(case.phi)
        naive = ri + rj - math.sqrt(dx * dx + dy * dy)
        delta = naive + overlap_correction(dx, dy, ri, rj, naive)  # as the kernel sees it
        v.update(dx=dx, dy=dy, Ri=ri, Rj=rj)
        if law.history:
            tmag = case.t_ratio * case.mu * kn / kt * delta
            v.update(tx=tmag * math.cos(case.psi), ty=tmag * math.sin(case.psi))
            v.update(t=math.copysign(tmag, math.cos(case.psi)))  # a _fi law's scalar
    else:
        y = radius - case.delta_over_R * radius
        delta = radius - y
        v.update(y=y, R=radius)
        if law.history:
            sign = 1.0 if math.cos(case.psi) >= 0 else -1.0
            v.update(t=sign * case.t_ratio * case.mu * kn / kt * delta)
    return tuple(float(v[name]) for name in law.inputs)


def cap_gap(law, a):
    """Hard cap: ``(|t| - t*, t*)``; ``(inf, inf)`` for any other law."""
    if law.name not in HARD_CAP:
        return math.inf, math.inf
    tstar = a["mu"] * a["kn"] / a["kt"] * _overlap(law, a)
    return math.sqrt(sum(a[h] ** 2 for h in law.history)) - tstar, tstar


def hard_cap_length(law, a, length):
    """Column length such that no difference step (<= 0.1 length) reaches the cap.

    Per unit of a column (translation: unit length; rotation: length/R),
    ``|t| - t*`` moves by at most ``|A_k| + (t*/delta) |d delta/dq_k| <= 1 + t*/delta``,
    so with ``length <= |gap| / (1 + t*/delta)`` a step of 0.1 length moves it by
    at most 0.1 |gap|.  Other laws, and a history on the cap (:func:`on_cap`, no
    difference step is taken there): ``length`` unchanged.
    """
    gap, tstar = cap_gap(law, a)
    if not math.isfinite(gap) or abs(gap) < ON_CAP * tstar:  # on the cap: complex step only
        return length
    return min(length, abs(gap) / (1.0 + tstar / _overlap(law, a)))


def on_cap(law, a):
    """True for a hard-cap history within :data:`ON_CAP` of its circle."""
    gap, tstar = cap_gap(law, a)
    return abs(gap) < ON_CAP * tstar


def _overlap(law, a):
    """The overlap as the kernels compute it (accurate, see fricstab._numerics)."""
    if law.kind == "wall":
        return a["R"] - a["y"]
    naive = a["Ri"] + a["Rj"] - math.hypot(a["dx"], a["dy"])
    return naive + overlap_correction(a["dx"], a["dy"], a["Ri"], a["Rj"], naive)


def _row_scale(jref):
    absj = np.abs(jref)
    rowmax = absj.max(axis=1)
    block = absj.max() if absj.size else 0.0
    return np.where(rowmax > 0, rowmax, block if block > 0 else 1.0)


def row_relative_error(jac, jref):
    """Largest over rows of max|jac - jref| / max|jref| of that row (see module doc)."""
    return float((np.abs(jac - jref).max(axis=1) / _row_scale(jref)).max())


def uncancelled_scale(law, args):
    """Per row, the size of the terms that a row of the block sums.

    A pair's force row sums normal and tangential terms,
    ``(|F_n| + |F_t|)/delta + k_t delta^{1/2}``; a torque row (and the wall's
    tangential row) only tangential ones, ``|F_t|/delta + k_t delta^{1/2}``,
    times the arm for a torque; the wall's normal row ``|F_n|/delta``.
    """
    a = dict(zip(law.inputs, args))
    delta = _overlap(law, a)
    sd = math.sqrt(delta)
    fn = a["kn"] * delta * sd
    ft = 0.0
    if law.name in HARD_CAP:  # F_n = kn delta, F_t = -kt t (|t| <= t*), dF_t/dt = kt
        fn, sd = a["kn"] * delta, 1.0
        tn = math.sqrt(sum(a[h] ** 2 for h in law.history))
        ft = a["kt"] * min(tn, a["mu"] * a["kn"] / a["kt"] * delta)
    elif law.history:
        tn = math.sqrt(sum(a[h] ** 2 for h in law.history))
        ft = a["kt"] * sd * tn
        if law.coulomb:
            s = min(tn / (a["mu"] * a["kn"] / a["kt"] * delta), 1.0)
            ft *= 1 + s - s * s
    tangential = ft / delta + a.get("kt", 0.0) * sd if law.history else 0.0
    rows = []
    for i, name in enumerate(law.outputs):
        if name.startswith(("T", "Fl")):
            arm = 1.0
            if name.startswith("T"):
                arm = a[("Ri", "Rj")[i // 3]] if law.kind == "pair" else a["R"]
            rows.append(tangential * arm)
        elif law.kind == "wall":
            rows.append(fn / delta if name == "Fy" else tangential)
        else:
            rows.append(fn / delta + tangential)
    return np.array(rows)


def cancellation_factor(law, args, jac):
    """Largest over rows of :func:`uncancelled_scale` / (row's largest entry).

    Where the terms of a row nearly cancel (normal against tangential
    stiffness, or a history along the normal, whose torque terms ~|F_t|/delta
    cancel exactly), any absolute error, rounding included, is large relative
    to the row.  A row that is zero in ``jac`` is measured against the
    block's largest entry, as in :func:`row_relative_error`.
    """
    return max(1.0, float(np.max(uncancelled_scale(law, args) / _row_scale(jac))))


def exact_reference_bound(kappa):
    """Bound on the error of the float64 block against an exact reference.

    The generated block and a complex-step (or 50-digit) reference differ by
    the float64 rounding of the block: ~:data:`ROUNDING_ULPS` eps of the terms a
    row sums, i.e. of kappa times the row scale; never below 1e-12.
    """
    return max(EXACT_BOUND, ROUNDING_ULPS * EPS * kappa)


def taylor_consistent(slope, errs, kappa):
    """Whether a Taylor test shows K to be the derivative of F.

    Either the remainder falls at least as fast as h^2 (slope >= 1.9; along a
    special direction the h^2 and h^3 terms can cancel and it falls faster,
    while an error in K leaves a term linear in h, slope 1), or e(h)/h^2 stays
    bounded down to the smallest resolved step (a kink crossed by the steps
    changes its coefficient, not its order), or it is no
    larger than the rounding of the float64 block would make it,
    ``ROUNDING_ULPS eps kappa h`` (plus the 50-digit resolution): the case of a
    direction along which F is linear, or of a base point within rounding of
    the slip kink |t| = t*, where 50-digit arithmetic may put it on the other
    side of the kink than float64 does.
    """
    if slope is not None and slope >= 1.9:
        return True
    steps = np.array(TAYLOR_STEPS)
    resolved = np.flatnonzero(errs > TAYLOR_RESOLUTION)
    if resolved.size >= 3:
        # Bounded second-order remainder: e(h)/h^2 at the smallest resolved
        # step at most 10x its largest value over the larger half of the
        # steps.  A kink (t = 0, |t| = t*) within the step range changes the
        # coefficient of h^2 by O(1); an error eps in K makes e/h^2 grow
        # tenfold per decade of h, i.e. 100x or more across the range.
        ratio = errs[resolved] / steps[resolved] ** 2
        if ratio[-1] <= 10.0 * ratio[: len(ratio) // 2 + 1].max():
            return True
    return bool(np.all(errs <= ROUNDING_ULPS * EPS * kappa * steps + TAYLOR_RESOLUTION))


def central_error_model(law, args, jac):
    """Predicted floor of float64 central differences at the best step.

    Terms relative to a row's largest derivative, for a step h along a column
    of length scale L = min(delta, t*):

    * truncation, ``c h^2 / delta^2`` with ``c = 1/24`` for Hertz (third over
      first derivative of ``delta^{3/2}`` is ``-1/(4 delta^2)``) and ``c = 2``
      for the smoothed Coulomb law (its ``t^3 / (t*^2 delta^{3/2})`` term has
      third over first derivative up to ``(105/8) / (3/2)``, over 6), plus
      ``h^2 / t*^2`` from the curvature in t;
    * rounding of the two force evaluations, ``4 eps delta / h``;
    * where a step can reach a point at which the law is C1 but not C2, a
      first-order error: ``h / t*`` at ``t = 0`` (the term ``|t| t``),
      ``h / t* + h / delta`` at ``|t| = t*`` (sliding starts and the overlap
      moves ``t*`` across ``|t|``);
    * the step cannot be smaller than the last bit of the centre distance
      ``|d|`` (or of ``y`` at a wall): ``h >= ulp(|d|)``;
    * all terms are multiplied by the cancellation factor
      :func:`cancellation_factor`.

    Returns the minimum over the step sweep.
    """
    a = dict(zip(law.inputs, args))
    size = math.hypot(a["dx"], a["dy"]) if law.kind == "pair" else a["y"]
    delta = _overlap(law, a)
    tn = math.sqrt(sum(a[h] ** 2 for h in law.history))
    curve = 1.0 / (24 * delta * delta)
    tstar = None
    if law.coulomb:
        tstar = a["mu"] * a["kn"] / a["kt"] * delta
        curve = 2.0 / (delta * delta) + 1.0 / (tstar * tstar)
    kappa = cancellation_factor(law, args, jac)
    # Hard cap: the columns are shortened so that no step reaches the cap
    # (hard_cap_length), hence no kink term; the Coulomb curvature above
    # bounds the linear law's (n and t_hat turn on the scales r and t*).
    length = hard_cap_length(law, a, delta)
    if law.name in HARD_CAP:
        tstar = None
        if CENTRAL_STEPS[0] * length < 2 * math.ulp(size):
            return math.inf  # no float64 step stays on one side of the cap
    best = math.inf
    for step in CENTRAL_STEPS:
        h = max(step * length, math.ulp(size))
        kink = 0.0
        if tstar is not None:
            # The history moves by ~h and t* by ~(t*/delta) h: a step that
            # can reach t = 0 or the circle sees the kink there.
            if tn <= 2 * h:
                kink += 1.0 / tstar
            if abs(tstar - tn) <= 2 * h * (1 + tstar / delta):
                kink += 1.0 / tstar + 1.0 / delta
        best = min(best, curve * h * h + 4 * EPS * delta / h + kink * h)
    return kappa * best
