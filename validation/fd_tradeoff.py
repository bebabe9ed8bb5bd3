"""Finite differences versus the generated Jacobian: accuracy and cost.

For every contact law and two configurations (a representative one and a hard
one: tiny overlap, history close to the Coulomb limit) this script measures
the row-relative error (:func:`fricstab.laws.verify.row_relative_error`) of the
whole Jacobian block ``K = dF/dq`` against the generated kernel, as a function
of the relative step ``h/L`` (``L`` the column's length scale from
:func:`fricstab.laws.verify.perturbation_columns`), for

* forward differences ``(F(q + h e_k) - F(q)) / h``;
* central differences ``(F(q + h e_k) - F(q - h e_k)) / 2h``
  (:func:`fricstab.laws.verify._central_column`);
* ``scipy.differentiate.jacobian``: an eighth-order central stencil on the
  geometric steps ``h, h/2, h/4, h/8`` (Richardson-type extrapolation), with
  ``maxiter`` fixed for the error-versus-step curve, and once with its
  adaptive defaults (``initial_step=0.5 L``, ``maxiter=10``, its own
  tolerance);
* complex step ``Im F(q + i h e_k) / h``
  (:func:`fricstab.laws.verify.complex_step_jacobian`).

Every perturbation moves the kernel inputs of column k by the geometric
coefficients times h *and* the tangential history by ``A[:, k] h``, with
``A = dt/dq`` the increment rule (:func:`fricstab.laws.verify.reference_increment`).

It then times each method at its best step against the generated
``force_jacobian`` kernel (median wall time per block, called from Python as
here) and estimates the ratio for compiled callers from the per-call cost of
the kernels inside a numba loop.  Results go to ``validation/fd_tradeoff.md``
and ``validation/fd_tradeoff.png``.

Run: ``python validation/fd_tradeoff.py`` (``--quick`` for a coarser grid and
fewer timing repeats).
"""

import argparse
import contextlib
import datetime
import math
import os
import platform
import sys
import time
from dataclasses import asdict
from pathlib import Path

import matplotlib
import numba
import numpy as np
import scipy
from scipy import differentiate

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from fricstab.laws import verify  # noqa: E402
from fricstab.laws import LAW_NAMES, get_law  # noqa: E402
from fricstab.laws.verify import (  # noqa: E402
    Case, _central_column, _force, _hist_index, case_inputs, complex_step_jacobian,
    generated_jacobian, mp_central_jacobian, perturbation_columns,
    reference_increment, row_relative_error)

HERE = Path(__file__).resolve().parent
EPS = float(np.finfo(float).eps)

CONFIGS = {
    "representative": Case(delta_over_R=1e-3, t_ratio=0.5, phi=0.7, psi=0.7 + math.pi / 2,
                           kt_over_kn=2 / 7, mu=10.0, radius_ratio=1.2),
    "hard": Case(delta_over_R=1e-9, t_ratio=0.9, phi=0.7, psi=0.7 + math.pi / 2,
                 kt_over_kn=2 / 7, mu=10.0, radius_ratio=1.2),
}

#: maxiter of scipy.differentiate.jacobian along the error-versus-step curve:
#: one eighth-order stencil (steps h, h/2, h/4, h/8), no adaptive refinement.
SCIPY_MAXITER = 1

METHODS = ("forward", "central", "scipy", "complex")
LABELS = {
    "forward": "forward difference",
    "central": "central difference",
    "scipy": f"scipy.differentiate (order 8, maxiter={SCIPY_MAXITER})",
    "scipy_adaptive": "scipy.differentiate (adaptive defaults)",
    "complex": "complex step",
    "generated": "generated force_jacobian",
}
STYLE = {
    "forward": dict(color="tab:red", marker="v"),
    "central": dict(color="tab:blue", marker="o"),
    "scipy": dict(color="tab:green", marker="s"),
    "complex": dict(color="black", marker="D", ls="--", lw=1.2, ms=3.0, zorder=1),
}


# --------------------------------------------------------------------------
# Jacobian blocks by each method; each recomputes the increment rule A and
# the column scales, which any caller without the generated kernel needs.
# --------------------------------------------------------------------------

def forward_jacobian(law, args, rel):
    """Forward differences, step ``rel * L`` per column; None below an ulp."""
    inc = reference_increment(law, args)
    hidx = _hist_index(law)
    f0 = _force(law, args)
    cols = perturbation_columns(law, args)
    jac = np.empty((len(f0), len(cols)))
    for k, (geo, length) in enumerate(cols):
        h = rel * length
        moved = list(args)
        for idx, coef in geo.items():
            moved[idx] = args[idx] + coef * h
            h = (moved[idx] - args[idx]) / coef  # the step actually taken
        if h == 0.0:
            return None
        for row, idx in enumerate(hidx):
            moved[idx] = args[idx] + inc[row, k] * h
        jac[:, k] = (_force(law, tuple(moved)) - f0) / h
    return jac


def central_jacobian(law, args, rel):
    """Central differences, step ``rel * L`` per column; None below an ulp."""
    inc = reference_increment(law, args)
    cols = perturbation_columns(law, args)
    jac = np.empty((len(law.outputs), len(cols)))
    for k, (geo, length) in enumerate(cols):
        col = _central_column(law, args, inc, k, geo, rel * length)
        if col is None:
            return None
        jac[:, k] = col
    return jac


@contextlib.contextmanager
def _complex_step(rel):
    saved = verify.COMPLEX_STEP
    verify.COMPLEX_STEP = rel
    try:
        yield
    finally:
        verify.COMPLEX_STEP = saved


def complex_jacobian(law, args, rel):
    """Complex step ``rel * L`` per column (fricstab.laws.verify.complex_step_jacobian)."""
    with _complex_step(rel):
        return complex_step_jacobian(law, args, reference_increment(law, args))


class _Counter:
    n = 0


def scipy_jacobian(law, args, rel, maxiter=SCIPY_MAXITER, tolerances=None, counter=None):
    """``scipy.differentiate.jacobian`` in units of the column scales.

    The variable is ``s`` with ``q = q0 + L s`` per column; the kernel inputs
    move by ``M s``, whose column k holds the geometric coefficients and
    ``A[:, k]`` (the history increment), times ``L_k``.  ``rel`` is the
    initial step in those units.  Returns the Jacobian in q (``df / L``) and
    scipy's result object.
    """
    inc = reference_increment(law, args)
    cols = perturbation_columns(law, args)
    hidx = _hist_index(law)
    m, nout = len(cols), len(law.outputs)
    move = np.zeros((len(args), m))
    for k, (geo, length) in enumerate(cols):
        for idx, coef in geo.items():
            move[idx, k] = coef * length
        for row, idx in enumerate(hidx):
            move[idx, k] = inc[row, k] * length
    base = np.array(args)

    def f(s):
        flat = s.reshape(m, -1)
        points = (base[:, None] + move @ flat).T.tolist()
        out = np.empty((len(points), nout))
        for p, x in enumerate(points):
            law.force(*x, out[p])
        if counter is not None:
            counter.n += len(points)
        return out.T.reshape((nout,) + s.shape[1:])

    res = differentiate.jacobian(f, np.zeros(m), initial_step=rel, maxiter=maxiter,
                                 tolerances=tolerances)
    return res.df / np.array([length for _, length in cols]), res


def scipy_fixed(law, args, rel):
    return scipy_jacobian(law, args, rel)[0]


def scipy_adaptive(law, args, rel=0.5):
    return scipy_jacobian(law, args, rel, maxiter=10)[0]


BLOCK = {"forward": forward_jacobian, "central": central_jacobian,
         "scipy": scipy_fixed, "complex": complex_jacobian}


def _error(jac, jref):
    if jac is None or not np.all(np.isfinite(jac)):
        return math.nan
    return row_relative_error(jac, jref)


def force_evals(law, method):
    """Force evaluations per block (counted for scipy)."""
    m = len(law.coords)
    return {"forward": m + 1, "central": 2 * m, "complex": m}[method]


# --------------------------------------------------------------------------
# Timing
# --------------------------------------------------------------------------

def time_per_call(fn, repeats, target):
    """Median wall time of ``fn()`` in seconds (``time.perf_counter``).

    After two warm-up calls the number of calls per repeat is chosen so that
    a repeat lasts about ``target`` seconds.
    """
    fn()
    fn()
    t0 = time.perf_counter()
    fn()
    once = max(time.perf_counter() - t0, 1e-7)
    inner = max(1, int(target / once))
    samples = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        for _ in range(inner):
            fn()
        samples.append((time.perf_counter() - t0) / inner)
    return float(np.median(samples))


@numba.njit
def _loop_force(fn, args, jitter, out, n):
    # jitter is zero; loading it defeats hoisting of the loop-invariant call.
    acc = 0.0
    for i in range(n):
        fn(args[0] + jitter[i & 7], *args[1:], out)
        acc += out[0].real
    return acc


@numba.njit
def _loop_force_jacobian(fn, args, jitter, f, jac, n):
    acc = 0.0
    for i in range(n):
        fn(args[0] + jitter[i & 7], *args[1:], f, jac)
        acc += jac[0, 0]
    return acc


def compiled_costs(law, args, repeats, n=20000):
    """Seconds per call of force (float64, complex128) and force_jacobian in a numba loop."""
    jitter = np.zeros(8)
    nf, m = len(law.outputs), len(law.coords)
    out, outc = np.empty(nf), np.empty(nf, dtype=complex)
    jac = np.empty((nf, m))
    cargs = tuple(complex(a) for a in args)
    costs = {}
    for key, call in (
            ("force", lambda: _loop_force(law.force, args, jitter, out, n)),
            ("force_complex", lambda: _loop_force(law.force, cargs, jitter, outc, n)),
            ("force_jacobian", lambda: _loop_force_jacobian(law.force_jacobian, args, jitter, out, jac, n))):
        call()  # compile
        costs[key] = time_per_call(call, repeats, 0.002) / n
    return costs


# --------------------------------------------------------------------------
# Measurement
# --------------------------------------------------------------------------

def grids(quick):
    per_decade = 2 if quick else 4
    fd = 10.0 ** (-np.arange(per_decade // 2, 16 * per_decade + 1) / per_decade)  # 10^-0.5 .. 1e-16
    cs = 10.0 ** (-np.arange(per_decade // 2, 30 * per_decade + 1, 2) / per_decade)  # .. 1e-30
    return {"forward": fd, "central": fd, "scipy": fd, "complex": cs}


def measure(name, case, grid, repeats, target):
    law = get_law(name)
    args = case_inputs(law, case)
    _, jref = generated_jacobian(law, args)
    inc = reference_increment(law, args)
    res = {
        "law": name,
        "case": asdict(case),
        "check_complex": row_relative_error(jref, complex_step_jacobian(law, args, inc)),
        "check_mp50": row_relative_error(jref, mp_central_jacobian(law, args, inc)),
        "curves": {}, "rows": {},
    }
    f = np.empty(len(law.outputs))
    jac = np.empty((len(law.outputs), len(law.coords)))
    t_gen = time_per_call(lambda: law.force_jacobian(*args, f, jac), repeats, target)
    res["t_force_py"] = time_per_call(lambda: law.force(*args, f), repeats, target)
    comp = compiled_costs(law, args, repeats)
    res["rows"]["generated"] = dict(h=None, err=0.0, nfev=1, t=t_gen, ratio=1.0, cratio=1.0)
    for method in METHODS:
        errs = np.array([_error(BLOCK[method](law, args, float(h)), jref) for h in grid[method]])
        res["curves"][method] = (grid[method], errs)
        ok = np.isfinite(errs)
        ibest = int(np.argmin(np.where(ok, errs, np.inf)))
        hbest = float(grid[method][ibest])
        if method == "scipy":
            counter = _Counter()
            scipy_jacobian(law, args, hbest, counter=counter)
            nfev = counter.n
        else:
            nfev = force_evals(law, method)
        t = time_per_call(lambda: BLOCK[method](law, args, hbest), repeats, target)
        per_eval = comp["force_complex" if method == "complex" else "force"]
        res["rows"][method] = dict(h=hbest, err=float(errs[ibest]), nfev=nfev, t=t,
                                   ratio=t / t_gen, cratio=nfev * per_eval / comp["force_jacobian"])
    counter = _Counter()
    jad, r = scipy_jacobian(law, args, 0.5, maxiter=10, counter=counter)
    t = time_per_call(lambda: scipy_adaptive(law, args), repeats, target)
    res["rows"]["scipy_adaptive"] = dict(
        h=0.5, err=_error(jad, jref), nfev=counter.n, t=t, ratio=t / t_gen,
        cratio=counter.n * comp["force"] / comp["force_jacobian"],
        status=sorted({int(s) for s in np.ravel(r.status)}),
        nit=int(np.max(r.nit)))
    res["compiled"] = comp
    return res


def slopes(h, err, hbest):
    """Fitted log-log slopes right (truncation) and left (round-off) of the minimum."""
    ok = np.isfinite(err) & (err > 0)
    out = []
    for sel in ((h >= 10 * hbest) & (h <= min(1e3 * hbest, 1e-1)),
                (h <= hbest / 10) & (h >= hbest / 1e3)):
        s = ok & sel
        out.append(float(np.polyfit(np.log(h[s]), np.log(err[s]), 1)[0]) if s.sum() >= 3 else math.nan)
    return out


# --------------------------------------------------------------------------
# Output
# --------------------------------------------------------------------------

def _fmt_e(x, digits=1):
    if x is None:
        return "-"
    if isinstance(x, float) and not math.isfinite(x):
        return "n/a"
    if x == 0:
        return "0 (reference)"
    return f"{x:.{digits}e}"


def plot(results, path):
    panels = [r for r in results if r["config"] == "representative"]
    panels += [r for r in results if r["config"] == "hard" and r["law"] == "charan"]
    fig, axes = plt.subplots(2, 3, figsize=(15, 9.2), sharey=True)
    for ax, res in zip(axes.flat, panels):
        for method in METHODS:
            h, err = res["curves"][method]
            ok = np.isfinite(err)
            style = {"lw": 1.6, "ms": 3.5, "zorder": 2, **STYLE[method]}
            ax.loglog(h[ok], np.maximum(err[ok], 1e-17), label=LABELS[method], **style)
        ax.axhline(math.sqrt(EPS), color="0.6", ls=":", lw=1)
        ax.axhline(EPS ** (2 / 3), color="0.6", ls="--", lw=1)
        ax.text(1e-29, math.sqrt(EPS) * 1.6, r"$\epsilon^{1/2}$", color="0.4", fontsize=10)
        ax.text(1e-29, EPS ** (2 / 3) * 1.6, r"$\epsilon^{2/3}$", color="0.4", fontsize=10)
        c = res["case"]
        title = f"{res['law']}"
        if res["config"] == "hard":
            title += f"  (hard: $\\delta/R$={c['delta_over_R']:g}, $|t|/t^*$={c['t_ratio']:g})"
        else:
            title += f"  ($\\delta/R$={c['delta_over_R']:g}"
            title += f", $|t|/t^*$={c['t_ratio']:g})" if get_law(res["law"]).history else ")"
        ax.set_title(title, fontsize=11)
        ax.set_xlim(1e-31, 0.6)
        ax.set_ylim(1e-17, 10.0)
        ax.invert_xaxis()
        ax.grid(True, which="major", alpha=0.3)
        ax.tick_params(labelsize=9)
    for ax in axes[1]:
        ax.set_xlabel("relative step h / L [-] (smaller to the right)", fontsize=10)
    for ax in axes[:, 0]:
        ax.set_ylabel("row-relative error of the Jacobian block [-]", fontsize=10)
    handles, labels = axes.flat[0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="lower center", ncol=4, fontsize=10.5, frameon=False)
    fig.suptitle("Finite-difference error vs step, against the generated Jacobian "
                 "(representative configuration; last panel: hard configuration)", fontsize=12.5)
    fig.tight_layout(rect=(0, 0.05, 1, 0.96))
    fig.savefig(path, dpi=110)
    plt.close(fig)


def write_md(results, path, png, args, runtime):
    rep = {r["law"]: r for r in results if r["config"] == "representative"}
    ch = rep["charan"]["rows"]
    fwd_sl = slopes(*rep["charan"]["curves"]["forward"], ch["forward"]["h"])
    cen_sl = slopes(*rep["charan"]["curves"]["central"], ch["central"]["h"])
    cs_h, cs_err = rep["charan"]["curves"]["complex"]
    hard = {r["law"]: r for r in results if r["config"] == "hard"}
    hc = hard["charan"]["rows"]
    hf, ef = hard["charan"]["curves"]["forward"]
    hmin = float(hf[np.isfinite(ef)].min())
    checks = max(max(r["check_complex"], r["check_mp50"]) for r in results)
    now = datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
    lines = [
        "# Finite differences versus the generated Jacobian",
        "",
        "Accuracy and cost of computing the contact Jacobian block `K = dF/dq` (with the",
        "tangential history advanced by the increment rule) by forward, central,",
        "`scipy.differentiate` and complex-step differences, against the generated",
        "`force_jacobian` kernel.  Written by `validation/fd_tradeoff.py`; rerun with",
        "",
        "    python validation/fd_tradeoff.py           # full run",
        "    python validation/fd_tradeoff.py --quick   # coarser step grid, fewer timing repeats",
        "",
        f"This file was written by a {'quick' if args.quick else 'full'} run ({runtime:.0f} s) on {now}:",
        f"{platform.platform()}, {platform.machine()}, {os.cpu_count()} CPUs, Python "
        f"{platform.python_version()}, numpy {np.__version__}, scipy {scipy.__version__}, "
        f"numba {numba.__version__}.",
        "",
        "## Method",
        "",
        "* **Reference**: the generated Jacobian.  It is verified against complex-step",
        "  differentiation and 50-digit (mpmath) central differences to about 1e-13",
        "  (`python -m fricstab verify --law all`); on the configurations below both agree with it",
        f"  to {checks:.1e} or better.",
        "* **Error**: `fricstab.laws.verify.row_relative_error` of the whole block: per row",
        "  (force or torque component) the largest absolute error over the largest",
        "  reference entry of that row; the maximum over rows.",
        "* **Step**: column k is perturbed by `h = (h/L) L_k`, with `L_k` from",
        "  `fricstab.laws.verify.perturbation_columns` (the overlap, or the Coulomb distance",
        "  `t*` where shorter; over the radius for rotations).  Every perturbation moves",
        "  the kernel inputs by the geometric coefficients times h and the history by",
        "  `A[:, k] h` (`fricstab.laws.verify.reference_increment`).  Forward and central",
        "  differences use the step actually representable in the perturbed input.",
        f"* **scipy.differentiate**: `jacobian(..., order=8, maxiter={SCIPY_MAXITER}, initial_step=h/L)` in",
        "  units of `L` per column: one eighth-order central stencil on the steps",
        "  `h, h/2, h/4, h/8` (the Richardson-type extrapolation scipy uses), and once",
        "  with its adaptive defaults (`initial_step=0.5`, i.e. `0.5 L`, `maxiter=10`,",
        "  `rtol = sqrt(eps)`), row *scipy adaptive*.  scipy evaluates the centre once",
        "  per column; the counts below are the force evaluations actually made.",
        "* **Complex step**: `Im F(q + i h e_k) / h` with the complex128 build of the",
        "  same force kernel (`fricstab.laws.verify.complex_step_jacobian`), h/L down to 1e-30.",
        "* **Best h/L** is the minimum of the error curve, known here only because the",
        "  reference is known; a user of finite differences has to guess it.  The",
        "  complex-step curve is flat below h/L ~ 1e-8, so its best h/L is arbitrary.",
        "* The forward and central curves end where the step falls below the last bit",
        "  of the perturbed input (the centre offset dx, dy, or y at a wall); errors of",
        "  exactly zero are drawn at the bottom edge of the plot.",
        "* **Time/block**: median (over repeats, after warm-up and compilation) of the",
        "  wall time (`time.perf_counter`) of one block computed from Python, including",
        "  the increment rule and column scales each method needs; the generated row is",
        "  one `force_jacobian` call from Python.  A kernel call from Python costs",
        "  under a microsecond of dispatch (listed per configuration), so from Python",
        "  the differences are dominated by interpreter work (increment rule, column",
        "  scales, argument packing; scipy's iteration machinery), not by the kernel.",
        "  The last column estimates the ratio for a compiled caller (numba loop):",
        "  evaluations times the cost of one compiled force call (complex128 for",
        "  the complex step) over the cost of one compiled `force_jacobian` call,",
        "  both timed in a numba loop (arithmetic of the differences not counted).",
        "",
        "![error versus step](" + png.name + ")",
        "",
        "## Results",
        "",
    ]
    for res in results:
        c = res["case"]
        law = get_law(res["law"])
        desc = f"delta/R = {c['delta_over_R']:g}"
        if law.history:
            desc += f", |t|/t* = {c['t_ratio']:g}, kt/kn = {c['kt_over_kn']:.4g}, mu = {c['mu']:g}"
            if not law.coulomb:
                desc += " (no Coulomb limit: t* = mu kn/kt delta only sets |t|)"
        if law.kind == "pair":
            desc += f", Rj/Ri = {c['radius_ratio']:g}"
        comp = res["compiled"]
        lines += [
            f"### {res['law']}, {res['config']} ({desc})",
            "",
            f"Reference check: complex step {res['check_complex']:.1e}, 50-digit central "
            f"{res['check_mp50']:.1e}.  One force call from Python: {res['t_force_py'] * 1e6:.2f} us.  "
            f"Compiled cost per call: force {comp['force'] * 1e9:.0f} ns, "
            f"complex force {comp['force_complex'] * 1e9:.0f} ns, force_jacobian "
            f"{comp['force_jacobian'] * 1e9:.0f} ns.",
            "",
            "| method | best h/L | best error | force evals/block | time/block (us) "
            "| time ratio vs generated kernel | est. ratio, compiled caller |",
            "|---|---|---|---|---|---|---|",
        ]
        for key in ("generated", "forward", "central", "scipy", "scipy_adaptive", "complex"):
            r = res["rows"][key]
            label = LABELS[key]
            if key == "scipy_adaptive":
                label += f" (nit {r['nit']}, status {','.join(map(str, r['status']))})"
            evals = "1 (force + Jacobian)" if key == "generated" else str(r["nfev"])
            hs = "-" if r["h"] is None else f"{r['h']:.1e}"
            err = "0 (reference)" if key == "generated" else _fmt_e(r["err"])
            lines.append(f"| {label} | {hs} | {err} | {evals} | {r['t'] * 1e6:.1f} "
                         f"| {r['ratio']:.1f} | {r['cratio']:.1f} |")
        lines.append("")
    lines += [
        "## Why the curves are V-shaped",
        "",
        "A difference quotient with step h makes two errors.  Truncation: the Taylor",
        "terms the formula drops, relative size ~ (h/L)^p with p = 1 for forward,",
        "p = 2 for central and p = 8 for scipy's stencil; it shrinks as h does.",
        "Round-off: each force value carries a relative error of a few eps",
        f"(eps = {EPS:.2e}), and the quotient divides the difference of two such",
        "values by h, so that error grows like eps/(h/L).  Their sum is smallest where",
        "the two balance: at h/L ~ eps^(1/2) for forward differences (error ~ eps^(1/2)",
        f"= {math.sqrt(EPS):.1e}), at h/L ~ eps^(1/3) for central differences (error",
        f"~ eps^(2/3) = {EPS ** (2 / 3):.1e}), and at h/L ~ eps^(1/9) for an order-8 stencil",
        f"(error ~ eps^(8/9) = {EPS ** (8 / 9):.1e}, times its large weights).  The",
        "complex step has no subtraction: `Im F(q + ih)` carries the derivative",
        "directly, so there is no round-off branch, and the truncation term (h/L)^2",
        "(the same magnitude as the central difference's, so on the plot the two",
        "curves coincide down to the central minimum) is below eps once h/L < 1e-8;",
        "the curve is flat at machine precision down to h/L = 1e-30.",
        "",
        f"Measured on charan, representative configuration: forward differences reach "
        f"{ch['forward']['err']:.1e} at h/L = {ch['forward']['h']:.0e} (slopes {fwd_sl[0]:+.1f} "
        f"on the truncation side, {fwd_sl[1]:+.1f} on the round-off side); central differences "
        f"reach {ch['central']['err']:.1e} at h/L = {ch['central']['h']:.0e} (slopes "
        f"{cen_sl[0]:+.1f} and {cen_sl[1]:+.1f}); scipy.differentiate with a fixed stencil "
        f"reaches {ch['scipy']['err']:.1e} at initial step {ch['scipy']['h']:.0e} L, and "
        f"{ch['scipy_adaptive']['err']:.1e} with its adaptive defaults "
        f"({ch['scipy_adaptive']['nfev']} force evaluations); the complex step stays between "
        f"{np.nanmin(cs_err[cs_h <= 1e-8]):.1e} and {np.nanmax(cs_err[cs_h <= 1e-8]):.1e} for all "
        f"h/L <= 1e-8.  The generated kernel agrees with the 50-digit reference to rounding at the "
        f"cost of one call: "
        f"from Python the differences cost {ch['forward']['ratio']:.0f}x (forward), "
        f"{ch['central']['ratio']:.0f}x (central), {ch['scipy']['ratio']:.0f}x (scipy fixed), "
        f"{ch['scipy_adaptive']['ratio']:.0f}x (scipy adaptive) and "
        f"{ch['complex']['ratio']:.0f}x (complex step) its time; for a compiled caller the "
        f"estimate is {ch['forward']['cratio']:.1f}x, {ch['central']['cratio']:.1f}x, "
        f"{ch['scipy']['cratio']:.0f}x, {ch['scipy_adaptive']['cratio']:.0f}x and "
        f"{ch['complex']['cratio']:.1f}x.",
        "",
        "At the hard configuration (delta/R = 1e-9, |t|/t* = 0.9) the overlap is 1e-9 R",
        "while the centre offset |d| is ~2 R, so steps below the last bit of the offset",
        f"(dx, dy), h/L < {hmin:.0e} for charan, cannot be taken: the forward-difference curve is",
        f"cut off before its optimum near eps^(1/2) and stops at {hc['forward']['err']:.1e}.  Central",
        "differences, whose optimum h/L ~ 1e-5 is still representable, keep",
        f"{hc['central']['err']:.1e}: the kernels recover the overlap to full relative",
        "precision (fricstab/_numerics.py) and the differences divide by the step",
        "actually taken.  scipy.differentiate moves the variable by its own nominal",
        "step and does not see the rounding of the kernel inputs, so its fixed",
        f"stencil reaches only {hc['scipy']['err']:.1e} and its adaptive run, which stops when",
        f"its error estimate grows (status {','.join(map(str, hc['scipy_adaptive']['status']))}), "
        f"{hc['scipy_adaptive']['err']:.1e}.  The complex step perturbs only the",
        f"imaginary part and keeps {hc['complex']['err']:.1e}; the generated kernel needs no step.",
        "",
    ]
    path.write_text("\n".join(lines))


def run(quick=False, out=HERE / "fd_tradeoff", log=print):
    """Measure every law at both configurations, write ``out``.md and .png; return
    the results (one dict per law and configuration: ``rows[method]["err"]`` the best
    error, ``rows[method]["h"]`` its step; the times are measurements)."""
    start = time.perf_counter()
    grid = grids(quick)
    repeats, target = (5, 0.002) if quick else (25, 0.01)
    results = []
    for name in LAW_NAMES:
        for config, case in CONFIGS.items():
            t0 = time.perf_counter()
            res = measure(name, case, grid, repeats, target)
            res["config"] = config
            results.append(res)
            log(f"{name:12s} {config:15s} " + "  ".join(
                f"{k} {r['err']:.1e}/{r['ratio']:.0f}x" for k, r in res["rows"].items()
                if k != "generated") + f"  [{time.perf_counter() - t0:.1f} s]")
    out = Path(out)
    png, md = out.with_suffix(".png"), out.with_suffix(".md")
    plot(results, png)
    runtime = time.perf_counter() - start
    write_md(results, md, png, argparse.Namespace(quick=quick), runtime)
    log(f"wrote {md} and {png} in {runtime:.0f} s")
    return results


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--quick", action="store_true",
                        help="two steps per decade and fewer timing repeats")
    parser.add_argument("--out", default=str(HERE / "fd_tradeoff"),
                        help="output path without extension (default: validation/fd_tradeoff)")
    args = parser.parse_args(argv)
    run(args.quick, args.out, log=lambda text: print(text, flush=True))


if __name__ == "__main__":
    main()
