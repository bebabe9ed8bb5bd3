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
hertz_wall, charan, charan_wall, ishima, ishima_wall, linear, linear_wall, and
the frame-indifferent ishima_fi, charan_fi, linear_fi (a scalar history along
the tangent, advanced by ``t_hat^T dt``) with their walls.
The block of ``linear`` (and ``linear_fi``) jumps on its circle (a hard cap): a history there is
checked by complex step only (``hard_cap_on_circle_cases``), and elsewhere the
columns are shortened so that no difference step reaches it
(:func:`fricstab.laws.verify_common.hard_cap_length`).

Relative error of a block: for each row (one force or torque component) the
largest ``|K - K_ref|`` divided by the largest ``|K_ref|`` of that row; a row
that is identically zero in the reference is divided by the block's largest
entry.  The maximum over rows is the error of the block.
"""

import math
import types
from dataclasses import asdict

import mpmath
import numpy as np

from fricstab import signals
from fricstab.laws import get_law
from fricstab.laws.verify_common import (  # the shared part; re-exported (see __all__)
    CENTRAL_BOUND, CENTRAL_STEPS, COMPLEX_STEP, EXACT_BOUND, EXTREMES, MP_DPS, MP_STEP,
    TAYLOR_RESOLUTION, TAYLOR_STEPS, Case, _overlap, _row_scale, cancellation_factor,
    case_inputs, central_error_model, exact_reference_bound, hard_cap_length, on_cap,
    row_relative_error, sample_cases, taylor_consistent, uncancelled_scale)

__all__ = [
    "CENTRAL_BOUND", "EXACT_BOUND", "EXTREMES", "Case", "cancellation_factor", "case_inputs",
    "central_error_model", "central_jacobian", "complex_step_jacobian", "exact_reference_bound",
    "generated_jacobian", "mp_central_jacobian", "perturbation_columns", "reference_increment",
    "row_relative_error", "sample_cases", "taylor_consistent", "taylor_slope",
    "uncancelled_scale", "verify_case", "verify_law"]


def reference_increment(law, args, sqrt=math.sqrt):
    """``dt/dq`` written from the papers, independently of the SymPy source.

    Pair (Charan Eq. 2; Ishima Eq. D4 with arms 1 in the l coordinates):
    ``dt = (I - n n^T)(dr_i - dr_j) + (a_i dq3_i + a_j dq3_j)(n_y, -n_x)``.
    Wall (Charan Eq. 2): ``dt = dx + R dtheta``; in Ishima's coordinates
    ``dt = dx + dl`` (``l = R theta``).  A frame-indifferent pair law (one
    history entry, the scalar xi along ``t_hat = (n_y, -n_x)``): the tangent
    component ``t_hat^T dt = t_hat . (dr_i - dr_j) + a_i dq3_i + a_j dq3_j``.
    With ``sqrt=mpmath.sqrt`` and mpmath inputs it is evaluated in that
    precision (an object array).
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
    if len(law.history) == 1:  # xi along t_hat = (n_y, -n_x)
        return np.array([[ny, -nx, arm_i, -ny, nx, arm_j]])
    p = [[one - nx * nx, -nx * ny], [-nx * ny, one - ny * ny]]
    return np.array([
        [p[0][0], p[0][1], arm_i * ny, -p[0][0], -p[0][1], arm_j * ny],
        [p[1][0], p[1][1], -arm_i * nx, -p[1][0], -p[1][1], -arm_j * nx],
    ])


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
    length = max(hard_cap_length(law, a, length), 1e-300)
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


def _last_bit(law, args):
    """ulp of the centre distance (pair) or of the height (wall)."""
    a = dict(zip(law.inputs, args))
    return math.ulp(math.hypot(a["dx"], a["dy"]) if law.kind == "pair" else a["y"])


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
        if col_best is None:  # every step below the last bit (a hard cap's short column)
            col_best = _central_column(law, args, inc, k, geo, 4 * _last_bit(law, args))
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


def verify_case(law, args, direction):
    """All comparisons for one configuration: a dict of errors."""
    f, jac = generated_jacobian(law, args)
    inc = reference_increment(law, args)
    finite = bool(np.all(np.isfinite(f)) and np.all(np.isfinite(jac)))
    jcs = complex_step_jacobian(law, args, inc)
    if on_cap(law, dict(zip(law.inputs, args))):
        # Hard cap, history on the circle: the block is the sliding one-sided
        # derivative, which complex step checks; a difference step would cross
        # the jump (tests/test_linear_law.py checks both one-sided limits).
        kappa = cancellation_factor(law, args, jcs)
        return {"finite": finite, "on_cap": True,
                "kappa": {"complex_step": kappa, "central_mp": kappa},
                "complex_step": row_relative_error(jac, jcs)}
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

    Returns the JSON-ready summary (see docs/reference/verification.md).
    """
    law = get_law(name)
    rng = np.random.default_rng([seed, 1])
    worst = {}
    agg = {"complex_step": 0.0, "central": 0.0, "central_mp": 0.0}
    slopes, nonfinite, above, unexplained, allowed, linear = [], 0, 0, 0, 0.0, 0
    taylor_failed = cap_cases = 0
    exact_above = {"complex_step": 0, "central_mp": 0}
    exact_unexplained = dict(exact_above)
    exact_conditioned = {"complex_step": 0.0, "central_mp": 0.0}
    for case in cases:
        args = case_inputs(law, case, radius=radius, kn=kn)
        direction = rng.uniform(-1.0, 1.0, len(law.coords))
        res = verify_case(law, args, direction)
        nonfinite += not res["finite"]
        if res.get("on_cap"):  # hard cap on its circle: complex step only
            cap_cases += 1
            res = {**res, "central": 0.0, "central_mp": res["complex_step"],
                   "central_model": 0.0, "taylor_slope": 2.0, "taylor_ok": True}
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
        signals.check()
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
        "hard_cap_on_circle_cases": cap_cases,
        "worst": worst,
    }
