"""Proof of the generated Jacobian blocks against independent references.

For one contact configuration (a :class:`Case`) and one law, the generated
block ``K = dF/dq`` (with history) is compared with

* complex-step differentiation of the generated force kernel compiled for
  complex128 (error O(h^2) with h = 1e-20 L: machine precision);
* float64 central differences at the best step of a sweep (the minimum of the
  V-shaped error-versus-step curve, per column);
* central differences of the same generated force source evaluated in 50-digit
  arithmetic (``mpmath``), which removes the round-off floor of float64
  differences at the extremes (tiny overlap, non-C2 points);
* a Taylor test in 50-digit arithmetic: ``|F(q + h dq) - F(q) - h K dq|``
  must fall with slope 2 in h.

Every perturbation moves q *and* advances the tangential history by the law's
increment rule, written here by hand from the papers (Charan Eq. 2, Ishima
Eq. D4), independently of the SymPy source.  The laws are the
``(kn, kt, [mu], t)`` family :data:`fricstab.laws.LAW_NAMES`: hertz,
hertz_wall, charan, charan_wall, ishima, ishima_wall.

Relative error of a block: for each row (one force or torque component) the
largest ``|K - K_ref|`` divided by the largest ``|K_ref|`` of that row; a row
that is identically zero in the reference is divided by the block's largest
entry.  The maximum over rows is the error of the block.
"""

import math
import types
from dataclasses import asdict, dataclass

import mpmath
import numpy as np

from fricstab._numerics import overlap_correction
from fricstab.laws import get_law

__all__ = [
    "CENTRAL_BOUND", "EXACT_BOUND", "Case", "EXTREMES", "cancellation_factor", "case_inputs", "taylor_consistent", "uncancelled_scale", "exact_reference_bound", "central_error_model", "perturbation_columns", "central_jacobian", "complex_step_jacobian",
    "generated_jacobian", "mp_central_jacobian", "reference_increment",
    "row_relative_error", "sample_cases", "taylor_slope", "verify_case",
    "verify_law",
]

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
    else:
        y = radius - case.delta_over_R * radius
        delta = radius - y
        v.update(y=y, R=radius)
        if law.history:
            sign = 1.0 if math.cos(case.psi) >= 0 else -1.0
            v.update(t=sign * case.t_ratio * case.mu * kn / kt * delta)
    return tuple(float(v[name]) for name in law.inputs)


def reference_increment(law, args, sqrt=math.sqrt):
    """``dt/dq`` written from the papers, independently of the SymPy source.

    Pair (Charan Eq. 2; Ishima Eq. D4 with arms 1 in the l coordinates):
    ``dt = (I - n n^T)(dr_i - dr_j) + (a_i dq3_i + a_j dq3_j)(n_y, -n_x)``.
    Wall (Charan Eq. 2): ``dt = dx + R dtheta``; in Ishima's coordinates
    ``dt = dx + dl`` (``l = R theta``).  With ``sqrt=mpmath.sqrt`` and mpmath
    inputs it is evaluated in that precision (an object array).
    """
    a = dict(zip(law.inputs, args))
    if not law.history:
        return np.zeros((0, len(law.coords)))
    one, zero = a["kn"] / a["kn"], a["kn"] * 0
    if law.kind == "wall":
        return np.array([[one, zero, a["R"] if law.coords[2].startswith("theta") else one]])
    r = sqrt(a["dx"] * a["dx"] + a["dy"] * a["dy"])
    nx, ny = a["dx"] / r, a["dy"] / r
    arm_i, arm_j = (a["Ri"], a["Rj"]) if law.coords[2].startswith("theta") else (one, one)
    p = [[one - nx * nx, -nx * ny], [-nx * ny, one - ny * ny]]
    return np.array([
        [p[0][0], p[0][1], arm_i * ny, -p[0][0], -p[0][1], arm_j * ny],
        [p[1][0], p[1][1], -arm_i * nx, -p[1][0], -p[1][1], -arm_j * nx],
    ])


def _overlap(law, a):
    """The overlap as the kernels compute it (accurate, see fricstab._numerics)."""
    if law.kind == "wall":
        return a["R"] - a["y"]
    naive = a["Ri"] + a["Rj"] - math.hypot(a["dx"], a["dy"])
    return naive + overlap_correction(a["dx"], a["dy"], a["Ri"], a["Rj"], naive)


def perturbation_columns(law, args):
    """Per column: ({input index: coefficient}, length scale of the column).

    The length scale is the overlap delta, or the Coulomb distance t* where
    that is shorter (the smoothed law curves on the scale t*); rotation
    columns divide it by the radius.
    """
    a = dict(zip(law.inputs, args))
    delta = _overlap(law, a)
    length = delta
    if law.coulomb:
        length = min(delta, a["mu"] * a["kn"] / a["kt"] * delta)
    length = max(length, 1e-300)
    cols = []
    for k, name in enumerate(law.coords):
        if law.kind == "pair":
            p, c = divmod(k, law.n_dof)
            geo = {c: 1.0 if p == 0 else -1.0} if c < 2 else {}
            radius = a["Ri" if p == 0 else "Rj"]
        else:
            geo = {0: 1.0} if name == "y" else {}
            radius = a["R"]
        cols.append((geo, length / radius if name.startswith("theta") else length))
    return cols


def _hist_index(law):
    return [law.inputs.index(h) for h in law.history]


def generated_jacobian(law, args):
    """Forces and Jacobian block from the generated float64 kernel."""
    f = np.empty(len(law.outputs))
    jac = np.empty((len(law.outputs), len(law.coords)))
    law.force_jacobian(*args, f, jac)
    return f, jac


def _force(law, args, dtype=float):
    out = np.empty(len(law.outputs), dtype=dtype)
    law.force(*args, out)
    return out


def complex_step_jacobian(law, args, inc):
    """``Im F(q + i h e_k, t + i h A e_k) / h`` column by column."""
    hidx = _hist_index(law)
    jac = np.empty((len(law.outputs), len(law.coords)))
    for k, (geo, scale) in enumerate(perturbation_columns(law, args)):
        h = COMPLEX_STEP * scale
        z = [complex(x) for x in args]
        for idx, coef in geo.items():
            z[idx] += 1j * h * coef
        for row, idx in enumerate(hidx):
            z[idx] += 1j * h * inc[row, k]
        jac[:, k] = _force(law, tuple(z), complex).imag / h
    return jac


def _central_column(law, args, inc, k, geo, h):
    hidx = _hist_index(law)
    plus, minus = list(args), list(args)
    hp = hm = h
    for idx, coef in geo.items():
        # Use the step actually representable in floating point.
        plus[idx] = args[idx] + coef * h
        minus[idx] = args[idx] - coef * h
        hp = (plus[idx] - args[idx]) / coef
        hm = (args[idx] - minus[idx]) / coef
    if hp + hm == 0.0:  # below the last bit of the input: no difference
        return None
    for row, idx in enumerate(hidx):
        plus[idx] = args[idx] + inc[row, k] * hp
        minus[idx] = args[idx] - inc[row, k] * hm
    return (_force(law, tuple(plus)) - _force(law, tuple(minus))) / (hp + hm)


def _row_scale(jref):
    absj = np.abs(jref)
    rowmax = absj.max(axis=1)
    block = absj.max() if absj.size else 0.0
    return np.where(rowmax > 0, rowmax, block if block > 0 else 1.0)


def row_relative_error(jac, jref):
    """Largest over rows of max|jac - jref| / max|jref| of that row (see module doc)."""
    return float((np.abs(jac - jref).max(axis=1) / _row_scale(jref)).max())


def central_jacobian(law, args, inc, jac_generated, steps=CENTRAL_STEPS):
    """float64 central differences at the best step of ``steps`` per column.

    Returns the difference Jacobian and the chosen step of each column (times
    the column's length scale).  The best step minimizes that column's
    row-relative error against ``jac_generated``: the bottom of the V curve.
    """
    scale = _row_scale(jac_generated)
    jac = np.empty_like(jac_generated)
    best = []
    for k, (geo, length) in enumerate(perturbation_columns(law, args)):
        err_best, col_best, s_best = math.inf, None, None
        for s in steps:
            col = _central_column(law, args, inc, k, geo, s * length)
            if col is None:
                continue
            err = float(np.max(np.abs(col - jac_generated[:, k]) / scale))
            if col_best is None or err < err_best:
                err_best, col_best, s_best = err, col, s
        jac[:, k] = col_best
        best.append(s_best)
    return jac, best


def _mp_function(law, which):
    """A generated kernel's Python source, run with mpmath numbers.

    ``which`` is "force" or "force_jacobian"; outputs go into lists or
    object arrays.  50 digits need no cancellation repair of the overlap.
    """
    py = getattr(law, which).py_func
    shim = types.SimpleNamespace(sqrt=mpmath.sqrt)
    names = {**py.__globals__, "np": shim, "overlap_correction": lambda *a: 0}
    return types.FunctionType(py.__code__, names, py.__name__)


def _mp_eval(fn, values, n_out):
    out = [mpmath.mpf(0)] * n_out
    fn(*values, out)
    return out


def mp_central_jacobian(law, args, inc):
    """Central differences of the generated force source in 50-digit arithmetic."""
    fn = _mp_function(law, "force")
    hidx = _hist_index(law)
    nf = len(law.outputs)
    jac = np.empty((nf, len(law.coords)))
    with mpmath.workdps(MP_DPS):
        base = [mpmath.mpf(x) for x in args]
        for k, (geo, length) in enumerate(perturbation_columns(law, args)):
            h = mpmath.mpf(MP_STEP) * mpmath.mpf(length)
            plus, minus = list(base), list(base)
            for idx, coef in geo.items():
                plus[idx] += coef * h
                minus[idx] -= coef * h
            for row, idx in enumerate(hidx):
                plus[idx] += mpmath.mpf(inc[row, k]) * h
                minus[idx] -= mpmath.mpf(inc[row, k]) * h
            fp, fm = _mp_eval(fn, plus, nf), _mp_eval(fn, minus, nf)
            jac[:, k] = [float((p - m) / (2 * h)) for p, m in zip(fp, fm)]
    return jac


def taylor_slope(law, args, inc, direction):
    """Slope of log|F(q+h dq) - F(q) - h K dq| against log h, all in 50 digits.

    F and K are the generated force and Jacobian sources evaluated with
    mpmath, so the remainder has no float64 floor and shows the order of the
    expansion (2 if K is the derivative of F); the float64 rounding of the
    compiled block is what the complex-step check bounds.  ``direction`` is
    dq in units of each column's length scale.

    Returns the slope fitted over the (up to four) smallest steps of
    :data:`TAYLOR_STEPS` whose remainder exceeds :data:`TAYLOR_RESOLUTION`
    (None when fewer than three do: F is linear along dq to that resolution) and the remainders, each
    scaled by its row's largest Jacobian entry times the direction's length.
    """
    fn = _mp_function(law, "force")
    jfn = _mp_function(law, "force_jacobian")
    hidx = _hist_index(law)
    nf, nq = len(law.outputs), len(law.coords)
    cols = perturbation_columns(law, args)
    dq = np.array([d * length for d, (_, length) in zip(direction, cols)])
    if not np.any(dq):
        raise ValueError("Taylor direction must not be zero")
    errs = []
    with mpmath.workdps(MP_DPS):
        base = [mpmath.mpf(x) for x in args]
        f0 = [mpmath.mpf(0)] * nf
        jac = np.empty((nf, nq), dtype=object)
        jfn(*base, f0, jac)
        mdq = [mpmath.mpf(x) for x in dq]
        lin = [mpmath.fsum(jac[a, b] * mdq[b] for b in range(nq)) for a in range(nf)]
        rowscale = [max(abs(jac[a, b]) for b in range(nq)) for a in range(nf)]
        block = max(rowscale)
        rowscale = [(r if r > 0 else block) * float(np.max(np.abs(dq))) for r in rowscale]
        # The history moves by the increment rule evaluated in 50 digits too.
        inc_mp = reference_increment(law, base, sqrt=mpmath.sqrt)
        dt = [mpmath.fsum(inc_mp[row, k] * mdq[k] for k in range(nq))
              for row in range(len(hidx))]
        for h in TAYLOR_STEPS:
            hh = mpmath.mpf(h)
            moved = list(base)
            for k, (geo, _) in enumerate(cols):
                for idx, coef in geo.items():
                    moved[idx] += coef * hh * mdq[k]
            for row, idx in enumerate(hidx):
                moved[idx] += hh * dt[row]
            f1 = _mp_eval(fn, moved, nf)
            rem = [abs(f1[a] - f0[a] - hh * lin[a]) / rowscale[a] for a in range(nf)]
            errs.append(float(max(rem)))
    errs = np.array(errs)
    # Below 1e-30 of the row scale a remainder reflects the 50-digit
    # arithmetic, or a kink (|t| = t*) within 1e-16 of the base point, since
    # the base point is a float64 input; fit only above that.
    ok = errs > TAYLOR_RESOLUTION
    if ok.sum() < 3:
        # F is linear along dq to that resolution (a rigid translation, or a
        # direction whose active components are tiny): no slope to fit.
        return None, errs
    # Taylor's theorem holds as h -> 0: fit the four smallest resolved steps
    # (larger ones may cross a kink, |t| = t*, close to the base point).
    steps = np.array(TAYLOR_STEPS)
    use = np.flatnonzero(ok)[-4:]
    slope = np.polyfit(np.log(steps[use]), np.log(errs[use]), 1)[0]
    return float(slope), errs


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
    if law.history:
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
    best = math.inf
    for step in CENTRAL_STEPS:
        h = max(step * delta, math.ulp(size))
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


def verify_case(law, args, direction):
    """All comparisons for one configuration: a dict of errors."""
    f, jac = generated_jacobian(law, args)
    inc = reference_increment(law, args)
    finite = bool(np.all(np.isfinite(f)) and np.all(np.isfinite(jac)))
    jcs = complex_step_jacobian(law, args, inc)
    jfd, steps = central_jacobian(law, args, inc, jac)
    jmp = mp_central_jacobian(law, args, inc)
    slope, terrs = taylor_slope(law, args, inc, direction)
    taylor_ok = taylor_consistent(slope, terrs, cancellation_factor(law, args, jmp))
    return {
        "finite": finite,
        # kappa against each reference's rows, as row_relative_error divides
        "kappa": {"complex_step": cancellation_factor(law, args, jcs),
                  "central_mp": cancellation_factor(law, args, jmp)},
        "complex_step": row_relative_error(jac, jcs),
        "central": row_relative_error(jac, jfd),
        "central_steps": steps,
        "central_model": central_error_model(law, args, jfd),
        "central_mp": row_relative_error(jac, jmp),
        "taylor_slope": slope,
        "taylor_ok": taylor_ok,
    }


def verify_law(name, cases, seed, progress=None, radius=0.5, kn=1.0):
    """Run the proof for one law over ``cases`` configurations.

    Returns the JSON-ready summary (see README, "Verification report").
    """
    law = get_law(name)
    rng = np.random.default_rng([seed, 1])
    worst = {}
    agg = {"complex_step": 0.0, "central": 0.0, "central_mp": 0.0}
    slopes, nonfinite, above, unexplained, allowed, linear = [], 0, 0, 0, 0.0, 0
    taylor_failed = 0
    exact_above = {"complex_step": 0, "central_mp": 0}
    exact_unexplained = dict(exact_above)
    exact_conditioned = {"complex_step": 0.0, "central_mp": 0.0}
    for case in cases:
        args = case_inputs(law, case, radius=radius, kn=kn)
        direction = rng.uniform(-1.0, 1.0, len(law.coords))
        res = verify_case(law, args, direction)
        nonfinite += not res["finite"]
        for key in agg:
            val = res[key]
            if not math.isfinite(val):
                nonfinite += 1
                val = math.inf
            if val >= agg[key]:
                agg[key] = val
                worst[key] = {**asdict(case), "err": val,
                              "central_model": res["central_model"]}
        taylor_failed += not res["taylor_ok"]
        if res["taylor_slope"] is None or res["taylor_slope"] < 1.9:
            linear += res["taylor_ok"]
        if res["taylor_slope"] is not None:
            slopes.append(res["taylor_slope"])
        # float64 differences cannot beat their own floor: a case above the
        # bound is explained when it is within 10x of the predicted floor.
        err, model = res["central"], res["central_model"]
        above += err > CENTRAL_BOUND
        unexplained += err > max(CENTRAL_BOUND, 10.0 * model)
        if model <= CENTRAL_BOUND / 10:
            allowed = max(allowed, err)
        # Against exact references the block can only be as good as its own
        # rounding of the terms each row sums (cancellation factor kappa).
        for key in ("complex_step", "central_mp"):
            exact = exact_reference_bound(res["kappa"][key])
            exact_above[key] += res[key] > EXACT_BOUND
            exact_unexplained[key] += res[key] > exact
            if exact == EXACT_BOUND:
                exact_conditioned[key] = max(exact_conditioned[key], res[key])
        if progress is not None:
            progress.update(1)
    slopes = np.array(slopes)
    finite_slopes = slopes[np.isfinite(slopes)]
    return {
        "law": name,
        "cases": len(cases),
        "seed": seed,
        "analytic": True,
        "max_rel_err_complex_step": agg["complex_step"],
        "exact_bound": EXACT_BOUND,
        "complex_step_cases_above_bound": exact_above["complex_step"],
        "complex_step_unexplained_cases": exact_unexplained["complex_step"],
        "max_rel_err_complex_step_well_conditioned": exact_conditioned["complex_step"],
        "max_rel_err_central": agg["central"],
        "central_bound": CENTRAL_BOUND,
        "central_cases_above_bound": int(above),
        "central_unexplained_cases": int(unexplained),
        "max_rel_err_central_where_float64_can_resolve": allowed,
        "max_rel_err_central_mp50": agg["central_mp"],
        "central_mp50_cases_above_bound": exact_above["central_mp"],
        "central_mp50_unexplained_cases": exact_unexplained["central_mp"],
        "max_rel_err_central_mp50_well_conditioned": exact_conditioned["central_mp"],
        "taylor_slope_min": float(finite_slopes.min()) if finite_slopes.size else None,
        "taylor_slope_max": float(finite_slopes.max()) if finite_slopes.size else None,
        "taylor_unresolved_cases": int(slopes.size - finite_slopes.size),
        "taylor_rounding_level_cases": linear,
        "taylor_failed_cases": taylor_failed,
        "nonfinite": nonfinite,
        "worst": worst,
    }
