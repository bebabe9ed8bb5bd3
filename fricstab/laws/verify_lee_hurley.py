"""Proof of the generated ``lee_hurley`` and ``lee_hurley_wall`` blocks.

The same four references as :mod:`fricstab.laws.verify` (which serves the
``(kn, kt, [mu], t)`` family), for the Lee & Hurley law with capped scalar
histories and the implicit contact width, in both forms: a pair of disks
(``lee_hurley``, args ``dx, dy, Ri, Rj, E, nu, mus, mur, ft, mr``) and a disk
on the flat wall y = 0 (``lee_hurley_wall``, args
``y, R, E, nu, mus, mur, Rw, ft, mr``; ``Rw`` the wall's radius of curvature):

* complex step through the generated force kernel compiled for complex128
  (``h = 1e-20 L``), which differentiates through the Newton solver of the
  contact width (:func:`fricstab._numerics.cylinder_lambda`, whose final
  correction runs in complex arithmetic for complex inputs) and through the
  caps (the branch is chosen on real parts);
* float64 central differences at the best step of a sweep;
* central differences of the generated force source in 50-digit arithmetic
  (``mpmath``), with the contact width from Lambert W (an independent
  solution of Eq. A2: ``lam = -W_{-1}(-e delta/(4 (R_1 + R_2)))``);
* a Taylor test in 50 digits, remainder slope 2.

Every perturbation moves q and advances the trial histories by the increment
rule written here by hand from the paper, independently of the SymPy source:
``d ft = k_t d delta_t``, ``d delta_t = t . (dr_i - dr_j) - (R_i dth_i + R_j dth_j)``
with ``t = (-n_y, n_x)`` and Lai's ``k_t`` (A8, A9) at the base point, and
``d mr = -k_r (dth_i - dth_j)`` (A14, A15); at the wall (``n = (0, 1)``,
``t = (-1, 0)``, the wall does not move) ``d ft = -k_t (dx + R dth)``,
``d mr = -k_r dth``, with ``k_t``, ``k_r`` of the cylinders ``R`` and ``Rw``.

Cases (:class:`ShearCase`) are dimensionless: ``E* = 1``, ``R_i = R = 0.5``,
``radius_ratio`` is ``R_j/R_i`` (pair) or ``Rw/R`` (wall); the histories are
multiples of their caps, ``ft = t_ratio mu_s F_n``,
``mr = r_ratio mu_r R_r F_n`` (a ratio above 1 is a sliding contact).

**Histories on a cap.**  Ratios within 1e-6 of 1 are kept out of these
difference checks, and a ratio of exactly 1 is never sampled: a difference
step would cross the cap, where the block jumps by design.  A history exactly
on its cap takes the sliding branch (``|ft| >= cap``, the loading direction's
one-sided derivative); tests/test_lee_hurley.py checks that case by complex
step (which keeps the real part on the cap, so differentiates the sliding
branch) and by the limit from beyond the cap, and checks the jump between the
one-sided limits.

Run ``python -m fricstab.laws.verify_lee_hurley --cases 2000 --json out.json``
(both forms; ``--law lee_hurley_wall`` for one).
"""

import argparse
import json
import math
import sys
import types
from dataclasses import asdict

import mpmath
import numpy as np

from fricstab import signals
from fricstab._numerics import contact_halfwidth
from fricstab.generated import lee_hurley as _gen
from fricstab.generated import lee_hurley_wall as _gen_wall
from fricstab.laws.verify_common import (  # the bounds and steps of the kernel proofs, shared
    CENTRAL_BOUND, COMPLEX_STEP, EPS, EXACT_BOUND, MP_DPS, MP_STEP, ROUNDING_ULPS,
    TAYLOR_STEPS, row_relative_error)
from fricstab.laws.verify_lee_hurley_cases import (  # re-exported: the cases live there
    CENTRAL_STEPS, EXTREMES, LAWS, REGIMES, WALL_EXTREMES, ShearCase,
    _form, _geometry, _materials, _overlap, case_inputs, lai_kt, law_of, sample_cases)

__all__ = ["EXTREMES", "LAWS", "REGIMES", "WALL_EXTREMES", "ShearCase", "case_inputs",
           "central_jacobian", "central_resolvable", "complex_step_jacobian", "exact_bound",
           "failures", "generated_jacobian", "lai_kt", "law_of", "main", "mp_central_jacobian",
           "reference_increment", "row_terms", "sample_cases", "taylor_slope", "verify_case",
           "verify_cases"]

def reference_increment(args, mp=False):
    """``d(ft, mr)/dq`` (2 x 6 pair, 2 x 3 wall) from the paper's rules (module docstring)."""
    wall = _form(args).name == "lee_hurley_wall"
    e_star, nu = _materials(args)[:2]
    if wall:
        y, ri, rj = args[0], args[1], args[6]
    else:
        dx, dy, ri, rj = args[:4]
    if mp:
        if wall:
            delta = ri - y
        else:
            r = mpmath.sqrt(dx * dx + dy * dy)
            delta = ri + rj - r
        lam = -mpmath.lambertw(-mpmath.e * delta / (4 * (ri + rj)), -1).real
        a = 4 * mpmath.sqrt(ri * rj) * mpmath.exp(-(lam + 1) / 2)
        kt = lai_kt(a, ri, rj, e_star, nu, log=mpmath.log)
        kr = mpmath.pi * e_star * (ri * rj / (ri + rj)) ** 2 / 4
        zero = mpmath.mpf(0)
    else:
        if not wall:
            r = math.hypot(dx, dy)
        delta = ri - y if wall else _overlap(dx, dy, ri, rj)
        a = contact_halfwidth(delta, ri, rj)
        kt = lai_kt(a, ri, rj, e_star, nu)
        kr = math.pi * e_star * (ri * rj / (ri + rj)) ** 2 / 4
        zero = 0.0
    if wall:
        # t = (-1, 0): d ft = k_t (-dx - R dth); d mr = -k_r dth
        return np.array([[-kt, zero, -kt * ri], [zero, zero, -kr]])
    nx, ny = dx / r, dy / r
    return np.array([[-kt * ny, kt * nx, -kt * ri, kt * ny, -kt * nx, -kt * rj],
                     [zero, zero, -kr, zero, zero, kr]])


def _contact(args):
    f = _form(args)
    out = np.empty(9)
    getattr(f.gen, f"{f.name}_contact")(*(float(x) for x in args), out)
    return out


def _columns(args, shorten=True):
    """Per column: ((input index, sign) of the moved coordinate, or None; length).

    The length is the overlap delta (over the radius for a rotation), shortened
    (unless ``shorten`` is false) to a quarter of the distance to the nearer
    cap along that column, so that no difference step crosses a cap (where the
    block jumps by design): ``|d(|h| - cap)/dq_k| <= |A_k| + mu |dF_n/dq_k|``
    with ``|dF_n/dq_k| <= pi E*/(lam - 1)``.  At the wall the x column moves
    only the tangential history and the y column only the caps.
    """
    f = _form(args)
    e_star, _, mus, mur, ft, mr = _materials(args)
    delta, ri, rj, _ = _geometry(args)
    _, _, kn, kt, kr, fn, _, _, _ = _contact(args)
    stiff = math.pi * e_star / (math.pi * e_star / kn - 1.0)
    rr = ri * rj / (ri + rj)
    gaps = (abs(mus * fn - abs(ft)), abs(mur * rr * fn - abs(mr)))
    cols = []
    for k in range(f.nq):
        p, c = divmod(k, 3)
        arm = ri if p == 0 else rj
        if f.name == "lee_hurley":
            sign = 1.0 if p == 0 else -1.0
            geo = (c, sign) if c < 2 else None
            dfn = stiff if c < 2 else 0.0
            rates = ((kt * (1.0 if c < 2 else arm)) + mus * dfn,
                     (kr if c == 2 else 0.0) + mur * rr * dfn)
        else:
            geo = (0, 1.0) if c == 1 else None
            rates = ((kt, 0.0), (mus * stiff, mur * rr * stiff), (kt * arm, kr))[c]
        length = delta if c < 2 else delta / arm
        for gap, rate in zip(gaps, rates):
            if shorten and rate > 0.0:
                length = min(length, 0.25 * gap / rate)
        cols.append((geo, length))
    return cols


def central_resolvable(args):
    """Whether float64 differences can reach 1e-6: every column length >= 1e7 ulp(r).

    The rounding floor of a central difference is ~eps r / h and its truncation
    (h / L)^2; with L >= 1e7 ulp the best step leaves both below ~1e-7.  ``r``
    is the centre distance (pair) or the height y (wall); a rotation column's
    length is compared over the larger radius.
    """
    f = _form(args)
    size = math.hypot(args[0], args[1]) if f.name == "lee_hurley" else args[0]
    rmax = max(args[2], args[3]) if f.name == "lee_hurley" else args[1]
    return all(length >= 1e7 * math.ulp(size) * (1.0 / rmax if k in f.rotations else 1.0)
               for k, (_, length) in enumerate(_columns(args)))


def generated_jacobian(args):
    """Forces and block from the generated float64 kernel."""
    f = _form(args)
    fo, jac = np.empty(f.nq), np.empty((f.nq, f.nq))
    getattr(f.gen, f"{f.name}_force_jacobian")(*args, fo, jac)
    return fo, jac


def _moved(args, inc, k, geo, h):
    f = _form(args)
    z = list(args)
    if geo is not None:
        z[geo[0]] = z[geo[0]] + geo[1] * h
    z[f.hist[0]] = z[f.hist[0]] + inc[0, k] * h
    z[f.hist[1]] = z[f.hist[1]] + inc[1, k] * h
    return z


def complex_step_jacobian(args, inc, shorten=True):
    """``Im F(q + i h e_k, history + i h A e_k)/h``, column by column.

    The branches are chosen on real parts, which the step leaves unchanged:
    a history exactly on its cap is differentiated on its sliding branch.
    ``shorten=False`` keeps the full column lengths (:func:`_columns`), which
    a history on its cap needs (its distance to the cap is 0).
    """
    f = _form(args)
    force = getattr(f.gen, f"{f.name}_force")
    jac = np.empty((f.nq, f.nq))
    out = np.empty(f.nq, dtype=complex)
    for k, (geo, length) in enumerate(_columns(args, shorten)):
        h = COMPLEX_STEP * length
        z = _moved([complex(x) for x in args], inc, k, geo, 1j * h)
        force(*z, out)
        jac[:, k] = out.imag / h
    return jac


def _force(args):
    f = _form(args)
    out = np.empty(f.nq)
    getattr(f.gen, f"{f.name}_force")(*args, out)
    return out


def central_jacobian(args, inc, jac_generated):
    """float64 central differences at the best step per column (V-curve bottom)."""
    absj = np.abs(jac_generated)
    scale = np.where(absj.max(axis=1) > 0, absj.max(axis=1), absj.max())
    nq = _form(args).nq
    jac = np.empty((nq, nq))
    for k, (geo, length) in enumerate(_columns(args)):
        best, col_best = math.inf, np.zeros(nq)
        for s in CENTRAL_STEPS:
            h = s * length
            if geo is not None:  # the step representable in the moved input
                x0 = args[geo[0]]
                h = ((x0 + geo[1] * h) - x0) * geo[1]
                if h == 0.0:
                    continue
            col = (_force(_moved(args, inc, k, geo, h)) - _force(_moved(args, inc, k, geo, -h))) / (2 * h)
            err = float(np.max(np.abs(col - jac_generated[:, k]) / scale))
            if err < best:
                best, col_best = err, col
        jac[:, k] = col_best
    return jac


def _mp_lambda(delta, ri, rj):
    return -mpmath.lambertw(-mpmath.e * delta / (4 * (ri + rj)), -1).real


def _mp_function(which, law="lee_hurley"):
    """The generated kernel's Python source run with mpmath numbers."""
    gen = _gen if law == "lee_hurley" else _gen_wall
    py = getattr(gen, f"{law}_{which}").py_func
    shim = types.SimpleNamespace(sqrt=mpmath.sqrt, log=mpmath.log, exp=mpmath.exp, pi=mpmath.pi)
    names = {**py.__globals__, "np": shim, "overlap_correction": lambda *a: 0,
             "cylinder_lambda": _mp_lambda}
    return types.FunctionType(py.__code__, names, py.__name__)


def mp_central_jacobian(args):
    """Central differences of the generated force source in >= 50 digits."""
    f = _form(args)
    fn = _mp_function("force", f.name)
    jac = np.empty((f.nq, f.nq))
    # Steps of 1e-20 L on coordinates of size r: keep 30 digits of the
    # difference however short L is (near a cap, L ~ gap * delta).
    size = math.hypot(args[0], args[1]) if f.name == "lee_hurley" else args[0]
    shortest = min(length for _, length in _columns(args)) / size
    with mpmath.workdps(max(MP_DPS, int(50 - math.log10(shortest)))):
        base = [mpmath.mpf(x) for x in args]
        inc = reference_increment(base, mp=True)
        for k, (geo, length) in enumerate(_columns(args)):
            h = mpmath.mpf(MP_STEP) * mpmath.mpf(length)
            fp, fm = [mpmath.mpf(0)] * f.nq, [mpmath.mpf(0)] * f.nq
            fn(*_moved(base, inc, k, geo, h), fp)
            fn(*_moved(base, inc, k, geo, -h), fm)
            jac[:, k] = [float((p - m) / (2 * h)) for p, m in zip(fp, fm)]
    return jac


def taylor_slope(args, direction):
    """Slope of ``log|F(q + h dq) - F(q) - h K dq|`` against ``log h`` in 50 digits.

    ``direction`` is dq in units of each column's length; the histories move
    by the reference increment.  Returns (slope or None, remainders), the
    remainders relative to each row's largest block entry times |dq|.  A step
    that moves a history across its cap (the branch flags of the perturbed
    point differ from the base point's) is left out of the fit: the expansion
    holds within one branch, and at a small overlap a history within ~1e-4 of
    its cap crosses it even at the smallest step (the rolling stiffness does
    not shrink with the overlap, the cap does).  Its remainder is NaN.
    """
    f = _form(args)
    nq = f.nq
    fn, jfn = _mp_function("force", f.name), _mp_function("force_jacobian", f.name)
    cfn = _mp_function("contact", f.name)

    def branch(z):
        out = [mpmath.mpf(0)] * 9
        cfn(*z, out)
        return int(out[8])

    cols = _columns(args)
    dq = [d * length for d, (_, length) in zip(direction, cols)]
    errs = []
    with mpmath.workdps(MP_DPS):
        base = [mpmath.mpf(x) for x in args]
        f0 = [mpmath.mpf(0)] * nq
        jac = np.empty((nq, nq), dtype=object)
        jfn(*base, f0, jac)
        mdq = [mpmath.mpf(x) for x in dq]
        lin = [mpmath.fsum(jac[a, b] * mdq[b] for b in range(nq)) for a in range(nq)]
        rows = [max(abs(jac[a, b]) for b in range(nq)) for a in range(nq)]
        block = max(rows)
        rows = [(r if r > 0 else block) * max(abs(x) for x in mdq) for r in rows]
        inc = reference_increment(base, mp=True)
        dh = [mpmath.fsum(inc[row, k] * mdq[k] for k in range(nq)) for row in range(2)]
        branch0 = branch(base)
        for h in TAYLOR_STEPS:
            hh = mpmath.mpf(h)
            z = list(base)
            for k, (geo, _) in enumerate(cols):
                if geo is not None:
                    z[geo[0]] += geo[1] * hh * mdq[k]
            z[f.hist[0]] += hh * dh[0]
            z[f.hist[1]] += hh * dh[1]
            if branch(z) != branch0:
                errs.append(np.nan)
                continue
            f1 = [mpmath.mpf(0)] * nq
            fn(*z, f1)
            errs.append(float(max(abs(f1[a] - f0[a] - hh * lin[a]) / rows[a] for a in range(nq))))
        # A remainder is resolved above the rounding of the MP_DPS-digit evaluation of
        # F, 10^-MP_DPS |F| against the row scale times |dq|, with a margin of 1e3 (at a
        # tiny overlap |F| / (|K| |dq|) reaches 1e22: the floor is then ~1e-28).
        floor = float(max(abs(f0[a]) / rows[a] for a in range(nq))) * 1e3 * 10.0 ** -MP_DPS
    errs = np.array(errs)
    # ... and above 1e-20 of the linear term h |K dq| (at most h in these units): below
    # it lies the precision of the reference pipeline itself (a first-order term of
    # ~5e-24 relative was measured at delta = 1e-12 R), 1e4 below anything float64 can
    # hold, so such a remainder says nothing about the float64 block.
    ok = np.isfinite(errs) & (errs > np.maximum(max(1e-30, floor), 1e-20 * np.array(TAYLOR_STEPS)))
    if ok.sum() < 3:
        return None, errs
    use = np.flatnonzero(ok)[-4:]
    return float(np.polyfit(np.log(np.array(TAYLOR_STEPS)[use]), np.log(errs[use]), 1)[0]), errs


def row_terms(args):
    """Per row of the block, the size of the terms the row sums.

    A pair's force row: the normal tangent stiffness ``pi E*/(lam - 1)`` with
    ``mu_s`` times it (sliding), ``|F_n|/r`` and ``|ft_c|/r`` (rotation of n)
    and ``k_t``; a torque row ``R_max`` times that plus ``k_r`` and
    ``mu_r R_max`` times the normal stiffness.  At the wall (n fixed): the
    tangential row ``k_t max(1, R) + mu_s pi E*/(lam - 1)``, the normal row
    ``pi E*/(lam - 1)``, the torque row ``R (k_t R + mu_s ...) + k_r + mu_r R_r ...``.
    """
    f = _form(args)
    e_star, _, mus, mur, _, _ = _materials(args)
    delta, ri, rj, _ = _geometry(args)
    _, _, kn, kt, kr, fn, ftc, _, _ = _contact(args)
    lam = math.pi * e_star / kn
    stiff = math.pi * e_star / (lam - 1.0)
    if f.name == "lee_hurley_wall":
        rr = ri * rj / (ri + rj)
        return np.array([kt * max(1.0, ri) + mus * stiff, stiff,
                         ri * (kt * ri + mus * stiff) + kr + mur * rr * stiff])
    r = math.hypot(args[0], args[1])
    force_terms = stiff * (1 + mus) + (fn + abs(ftc)) / r + kt
    rmax = max(ri, rj)
    return np.array([force_terms, force_terms, rmax * force_terms + kr + mur * rmax * stiff] * 2)


def exact_bound(args, jac):
    """Bound against exact references: 64 eps of the terms a row sums.

    The terms are :func:`row_terms`; their sum over the row's largest entry is
    the cancellation factor kappa; the bound is ``max(1e-12, 64 eps kappa)``.
    """
    absj = np.abs(jac)
    rowmax = np.where(absj.max(axis=1) > 0, absj.max(axis=1), absj.max())
    kappa = max(1.0, float(np.max(row_terms(args) / rowmax)))
    return max(EXACT_BOUND, ROUNDING_ULPS * EPS * kappa)


def verify_case(args, direction, mp=True):
    """All comparisons for one configuration: a dict of errors."""
    f, jac = generated_jacobian(args)
    inc = reference_increment(args)
    res = {"finite": bool(np.all(np.isfinite(f)) and np.all(np.isfinite(jac)))}
    jcs = complex_step_jacobian(args, inc)
    res["complex_step"] = row_relative_error(jac, jcs)
    res["complex_step_bound"] = exact_bound(args, jcs)
    res["central_resolvable"] = central_resolvable(args)
    res["central"] = row_relative_error(jac, central_jacobian(args, inc, jac))
    if mp:
        jmp = mp_central_jacobian(args)
        res["central_mp"] = row_relative_error(jac, jmp)
        res["central_mp_bound"] = exact_bound(args, jmp)
        res["taylor_slope"], res["taylor_errs"] = taylor_slope(args, direction)
    return res


def verify_cases(cases, seed, progress=None, law="lee_hurley"):
    """Run the proof of ``law`` over ``cases``; a JSON-ready summary by regime."""
    if law not in LAWS:
        raise ValueError(f"unknown law {law!r}; this module proves {', '.join(LAWS)}")
    nq = 6 if law == "lee_hurley" else 3
    rng = np.random.default_rng([seed, 1])
    summary = {}
    for k, case in enumerate(cases):
        st, sr = abs(case.t_ratio) > 1, abs(case.r_ratio) > 1
        regime = [n for n, v in REGIMES.items() if v == (st, sr)][0]
        res = verify_case(case_inputs(case, law=law), rng.uniform(-1.0, 1.0, nq))
        s = summary.setdefault(regime, {
            "cases": 0, "nonfinite": 0, "max_rel_err_complex_step": 0.0,
            "complex_step_above_bound": 0, "max_rel_err_central": 0.0,
            "central_above_1e-6": 0, "central_unresolvable": 0, "max_rel_err_central_mp50": 0.0,
            "central_mp50_above_bound": 0, "taylor_slope_min": math.inf,
            "taylor_unresolved": 0, "worst_complex_step": None})
        s["cases"] += 1
        s["nonfinite"] += not res["finite"]
        if res["complex_step"] >= s["max_rel_err_complex_step"]:
            s["worst_complex_step"] = asdict(case)
        s["max_rel_err_complex_step"] = max(s["max_rel_err_complex_step"], res["complex_step"])
        s["complex_step_above_bound"] += res["complex_step"] > res["complex_step_bound"]
        if res["central_resolvable"]:
            s["max_rel_err_central"] = max(s["max_rel_err_central"], res["central"])
            s["central_above_1e-6"] += res["central"] > CENTRAL_BOUND
        else:
            s["central_unresolvable"] += 1
        s["max_rel_err_central_mp50"] = max(s["max_rel_err_central_mp50"], res["central_mp"])
        s["central_mp50_above_bound"] += res["central_mp"] > res["central_mp_bound"]
        if res["taylor_slope"] is None:
            s["taylor_unresolved"] += 1
        else:
            s["taylor_slope_min"] = min(s["taylor_slope_min"], res["taylor_slope"])
        if progress is not None:
            progress.update(1)
        signals.check()
    return {"law": law, "cases": len(cases), "seed": seed, "regimes": summary}


def main(argv=None):
    """``python -m fricstab.laws.verify_lee_hurley [--law NAME] --cases N --seed S [--json PATH]``.

    Prints (and writes) a JSON list with one report per form; exit 3 on failure.
    """
    parser = argparse.ArgumentParser(prog="python -m fricstab.laws.verify_lee_hurley",
                                     description="verify the lee_hurley Jacobian blocks "
                                                 "(pair and wall forms)")
    parser.add_argument("--law", choices=LAWS + ("all",), default="all")
    parser.add_argument("--cases", type=int, default=200)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--json", default=None)
    ns = parser.parse_args(argv)
    if ns.cases < 1:
        print("--cases must be >= 1", file=sys.stderr)
        return 2
    from tqdm import tqdm
    laws = LAWS if ns.law == "all" else (ns.law,)
    reports = []
    with tqdm(total=ns.cases * len(laws), disable=not sys.stderr.isatty()) as bar:
        for law in laws:
            reports.append(verify_cases(sample_cases(ns.cases, ns.seed, law=law), ns.seed, bar,
                                        law=law))
    text = json.dumps(reports, indent=2)
    print(text)
    if ns.json:
        with open(ns.json, "w") as fh:
            fh.write(text + "\n")
    return 3 if sum(failures(r) for r in reports) else 0


def failures(report):
    """Count of regime checks above their bounds in a :func:`verify_cases` report."""
    return sum(s["nonfinite"] + s["complex_step_above_bound"] + s["central_mp50_above_bound"]
               + s["central_above_1e-6"] + (s["taylor_slope_min"] < 1.9)
               for s in report["regimes"].values())


if __name__ == "__main__":
    sys.exit(main())
