"""Chain (Charan et al.): complex-pair events under different ramp protocols.

The tangential history is path dependent, so where complex-conjugate pairs of
M^-1 J are born and die along the quasistatic F_x ramp depends on how each
equilibrium is reached.  This script ramps F_x from 0 to 0.1 on the N = 10
chain (F_y = 0.1, kn = 2000, kt = 2 kn / 7, mu = 10) under several protocols
and tabulates, for each, the event sequence, the first birth, the number of
complex pairs at the paper's F_x values (0.03, 0.04, 0.062, 0.083, 0.087,
0.090) and whether pairs exist for all F_x > 0.082 up to 0.1.  Writes
``chain_protocols.md`` and ``chain_protocols.png`` next to itself; :func:`run`
returns the numbers (the claims ``chain.protocol_*`` of
``validation/claims/chain.py``).

Variants
--------
* Newton ramps (:func:`fricstab.protocols.ramp.run_ramp`, events located by bisection
  to 1e-6): the default (step 1e-3, I = m R^2 / 2, as ``fricstab chain
  ramp``), steps 5e-4 / 2e-3 / 5e-3, I = m R^2 and I = 2 m R^2 / 5 (I changes
  the mass matrix only, not J or the equilibria).
* Damped ramps (the paper's protocol, :func:`fricstab.protocols.dynamics.relax_damped`,
  velocity Verlet with drag m nu v, history advanced every step): nu = 0.01,
  0.1, 0.447 (= 0.01 / sqrt(1/2000): nu = 0.01 read in the paper's stated
  time unit sqrt(m 2R / kn) instead of the simulation unit) and 1, step 1e-3,
  events at the step resolution (for nu = 0.447 located afterwards by
  bisection); nu = 0.447 also with steps 5e-4 and 2e-3.  A step whose damped
  relaxation does not reach max |F|, |T| < 1e-12 within the step cap is
  recorded as "no equilibrium" (the ramp continues from where it stopped);
  the ramp ends after three such steps in a row.  The extra nu values and
  steps (beyond nu = 0.01 and 0.1) test how far the damped result depends on
  them.
* Damped at F_x = 0 only, then Newton (events located).
* Two-stage jump (the Supplementary Material's Stage 1 / Stage 2 read
  literally): each probe F_x applied at once to the F_x = 0 damped
  equilibrium and relaxed with the damped protocol; probes only, no events.

A probe F_x that is not on the ramp grid is relaxed, with the variant's own
relaxer, from the equilibrium of the grid point below it (as the bisection
does).

    python validation/chain_protocols.py [--quick]

``--quick`` (about 1 minute) uses damped ramp steps 5 times coarser and a
smaller step cap; the full run takes a few minutes on one core.
"""

import argparse
import platform
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))

import numpy as np  # noqa: E402

from fricstab.analysis.spectrum import complex_pairs, decompose, growth_rate, tracking_radius  # noqa: E402
from fricstab.protocols.dynamics import relax_damped  # noqa: E402
from fricstab.protocols.ramp import _match, locate_event, relax_newton, run_ramp  # noqa: E402
from fricstab.scenes.chain import ChainScene, forces_and_jacobian, initial_state, mass_vector  # noqa: E402

FX_MAX = 0.1
PROBES = (0.03, 0.04, 0.062, 0.083, 0.087, 0.090)
# The paper: pair at 0.03 and 0.04 (Fig. 3), all eigenvalues real at 0.062,
# pairs at 0.083 / 0.087 / 0.090 (second regime) and for all F_x > 0.082 (SM).
PAPER = {0.03: True, 0.04: True, 0.062: False, 0.083: True, 0.087: True, 0.090: True}
THRESHOLD = 0.082
NU_PAPER_UNIT = 0.01 / np.sqrt(1.0 / 2000.0)  # nu = 0.01 per sqrt(m 2R / kn), in sim units


def log(msg):
    print(msg, flush=True)


class Progress:
    """Prints every ``every`` ramp steps (run_ramp calls ``update(1)``)."""

    def __init__(self, name, total, every=25):
        self.name, self.total, self.every, self.k, self.t0 = name, total, every, 0, time.time()

    def update(self, n=1):
        self.k += n
        if self.k % self.every == 0 or self.k == self.total:
            log(f"  [{self.name}] step {self.k}/{self.total} ({time.time() - self.t0:.1f} s)")


def spectrum_of(scene, state):
    _, jac = forces_and_jacobian(scene, state)
    return decompose(jac, mass_vector(scene), vectors=False).eigenvalues


def newton_relax(sc, st):
    return relax_newton(sc, st)


def damped_relax(nu, cap):
    def relax(sc, st):
        return relax_damped(sc, st, nu=nu, max_steps=cap)
    return relax


def damped_start_then_newton(nu):
    """The damped protocol for the F_x = 0 equilibrium (Stage 1), Newton after."""
    def relax(sc, st):
        if sc.fx == 0.0:
            return relax_damped(sc, st, nu=nu)
        return relax_newton(sc, st)
    return relax


def grid_index(grid, fx):
    k = int(np.argmin(np.abs(grid - fx)))
    return k if abs(grid[k] - fx) < 1e-9 else None


def probe_counts(scene, grid, counts, states, relax):
    """Number of complex pairs at each probe (None: no equilibrium reached)."""
    out = {}
    for p in PROBES:
        if p > grid[-1] + 1e-12:
            out[p] = None
            continue
        k = grid_index(grid, p)
        if k is not None:
            out[p] = counts[k]
            continue
        below = int(np.searchsorted(grid, p) - 1)
        if states[below] is None:
            out[p] = None
            continue
        sc = scene.with_fx(p)
        res = relax(sc, states[below])
        out[p] = len(complex_pairs(spectrum_of(sc, res.state))) if res.converged else None
    return out


def all_above(grid, counts, events, located):
    """Pairs for all F_x in (THRESHOLD, FX_MAX]?  Returns (bool or None, note)."""
    idx = [k for k, f in enumerate(grid) if f > THRESHOLD + 1e-12]
    if not idx or grid[-1] < FX_MAX - 1e-12:
        return None, "ramp ended before 0.1"
    bad = [grid[k] for k in idx if counts[k] is None]
    if bad:
        return False, f"no equilibrium at {fx3(bad[0])}"
    zero = [grid[k] for k in idx if counts[k] == 0]
    if zero:
        return False, f"none at {fx3(zero[0])}"
    if located:
        # Walk the located events from the last grid point <= THRESHOLD.
        k0 = max(k for k, f in enumerate(grid) if f <= THRESHOLD + 1e-12)
        cnt = counts[k0]
        for e in events:
            if e["fx"] <= grid[k0]:
                continue
            cnt += 1 if e["kind"] == "birth" else -1
            if e["fx"] > THRESHOLD and cnt <= 0:
                return False, f"none after {e['fx']:.5f}"
    return True, ""


def continuous_from(r):
    """Start of the final stretch with pairs at every step up to 0.1 (str)."""
    grid, counts = r["grid"], r["counts"]
    if r["events"] is None or len(grid) == 0 or grid[-1] < FX_MAX - 1e-12:
        return "n/a"
    k = len(counts)
    while k > 0 and counts[k - 1] is not None and counts[k - 1] > 0:
        k -= 1
    if k == len(counts):
        return "none at 0.1" if counts[-1] == 0 else "n/a (no eq. at 0.1)"
    if k == 0:
        return "0"
    lo, hi = grid[k - 1], grid[k]
    births = [e for e in r["events"] if e["kind"] == "birth" and e["located"]
              and lo - 1e-12 <= e["fx"] <= hi + 1e-12]
    if births:
        return f"{births[-1]['fx']:.6f}"
    return f"({fx3(lo)},{fx3(hi)}]"


def run_newton_variant(name, scene, step, relax=newton_relax):
    t0 = time.time()
    n_steps = int(round(FX_MAX / step)) + 1
    res = run_ramp(scene, FX_MAX, step, relax=relax, locate=True, keep_states=True,
                   progress=Progress(name, n_steps, every=max(1, n_steps // 4)))
    counts = [len(complex_pairs(w)) for w in res.eigenvalues]
    events = [{"kind": e.kind, "fx": e.fx, "lo": e.fx_lo, "hi": e.fx_hi, "located": e.located}
              for e in res.events]
    probes = probe_counts(scene, res.fx, counts, res.states, relax)
    return {"grid": res.fx, "counts": counts, "growth": list(res.growth), "events": events,
            "probes": probes, "located": all(e["located"] for e in events),
            "failures": [], "stopped": None, "seconds": time.time() - t0,
            "max_residual": float(res.residual.max())}


def run_damped_variant(name, scene, step, nu, cap, locate=False):
    """Damped ramp with events at the step resolution (see module docstring).

    With ``locate`` each event is then bisected to 1e-6 by
    :func:`fricstab.protocols.ramp.locate_event`, every trial relaxed by the damped
    protocol from the last converged step below it; an event whose trial does
    not converge within the cap stays at the step resolution.
    """
    t0 = time.time()
    relax = damped_relax(nu, cap)
    start = relax_damped(scene, initial_state(scene), nu=nu)
    if not start.converged:
        raise RuntimeError(f"{name}: no damped equilibrium at F_x = 0")
    state = start.state
    grid = np.round(np.arange(0.0, FX_MAX + 0.5 * step, step), 12)
    counts, growth, states, events, failures = [], [], [], [], []
    prev_pairs, prev_fx, prev_w, prev_k = None, None, None, None
    in_a_row, stopped, max_res = 0, None, 0.0
    for k, fx in enumerate(grid):
        sc = scene.with_fx(fx)
        res = relax(sc, state)
        state = res.state
        if not res.converged:
            counts.append(None)
            growth.append(np.nan)
            states.append(None)
            failures.append((fx, res.residual))
            in_a_row += 1
            if in_a_row >= 3:
                stopped = fx
                break
            continue
        in_a_row = 0
        max_res = max(max_res, res.residual)
        w = spectrum_of(sc, state)
        pairs = complex_pairs(w)
        counts.append(len(pairs))
        growth.append(growth_rate(w))
        states.append(state.copy())
        if prev_pairs is not None:
            scale = 0.1 * (np.abs(w.real).max() + 1e-300)
            born, died = _match(prev_pairs, pairs, scale)
            for kind, group, where in (("death", died, prev_w), ("birth", born, w)):
                events += [{"kind": kind, "fx": fx, "lo": prev_fx, "hi": fx, "located": False,
                            "k_lo": prev_k, "center": z.real,
                            "radius": tracking_radius(where, z.real)} for z in group]
        prev_pairs, prev_fx, prev_w, prev_k = pairs, fx, w, len(states) - 1
        if (k + 1) % 20 == 0:
            log(f"  [{name}] F_x = {fx:.3f} ({time.time() - t0:.1f} s, "
                f"{len(failures)} without equilibrium)")
    grid = grid[:len(counts)]
    if locate:
        for i, e in enumerate(events):
            try:
                lo, hi, _, _, ok = locate_event(scene, states[e["k_lo"]], e["lo"], e["hi"],
                                                e["center"], e["radius"], tol=1e-6,
                                                relax=relax)
            except RuntimeError as exc:
                log(f"  [{name}] {e['kind']} in ({e['lo']}, {e['hi']}]: {exc}; not located")
                continue
            if ok:
                e.update(fx=0.5 * (lo + hi), lo=lo, hi=hi, located=True)
            log(f"  [{name}] event {i + 1}/{len(events)} ({time.time() - t0:.1f} s)")
        events.sort(key=lambda e: e["fx"])
    probes = probe_counts(scene, grid, counts, states, relax)
    located = bool(events) and all(e["located"] for e in events) and not failures
    return {"grid": grid, "counts": counts, "growth": growth, "events": events,
            "probes": probes, "located": located, "failures": failures, "stopped": stopped,
            "seconds": time.time() - t0, "max_residual": max_res, "nu": nu}


def run_jump_variant(name, scene, nu, cap):
    """Stage 1 (F_x = 0, damped), then each probe F_x at once (Stage 2, damped)."""
    t0 = time.time()
    base = relax_damped(scene, initial_state(scene), nu=nu).state
    probes, failures, growth = {}, [], {}
    for p in PROBES:
        sc = scene.with_fx(p)
        res = relax_damped(sc, base, nu=nu, max_steps=cap)
        if res.converged:
            w = spectrum_of(sc, res.state)
            probes[p] = len(complex_pairs(w))
            growth[p] = growth_rate(w)
        else:
            probes[p] = None
            failures.append((p, res.residual))
        what = f"pairs {probes[p]}" if res.converged else "no equilibrium"
        log(f"  [{name}] F_x = {p}: {what} ({time.time() - t0:.1f} s)")
    return {"grid": np.array([]), "counts": [], "growth": [], "events": None, "probes": probes,
            "located": False, "failures": failures, "stopped": None,
            "seconds": time.time() - t0, "max_residual": np.nan, "nu": nu,
            "probe_growth": growth}


def fx3(x):
    """F_x on a ramp grid: 3 decimals, 4 where needed (step 5e-4)."""
    return f"{x:.3f}" if abs(x * 1000 - round(x * 1000)) < 1e-6 else f"{x:.4f}"


def fmt_events(r):
    if r["events"] is None:
        return "(probes only)"
    items = []
    for e in r["events"]:
        if e["located"]:
            items.append((e["fx"], f"{e['kind']}@{e['fx']:.6f}"))
        else:
            items.append((e["hi"], f"{e['kind']}@({fx3(e['lo'])},{fx3(e['hi'])}]"))
    for fx, _ in r["failures"]:
        items.append((fx, f"**no eq.@{fx3(fx)}**"))
    if r["stopped"] is not None:
        items.append((r["stopped"] + 1e-9, f"**ramp stopped@{fx3(r['stopped'])}**"))
    items.sort(key=lambda t: t[0])
    return ", ".join(s for _, s in items) if items else "none"


def first_birth(r):
    if r["events"] is None:
        return "n/a"
    births = [e for e in r["events"] if e["kind"] == "birth"]
    if not births:
        return "none"
    e = births[0]
    return f"{e['fx']:.6f}" if e["located"] else f"({fx3(e['lo'])},{fx3(e['hi'])}]"


def fmt_probe(n):
    return "no eq." if n is None else str(n)


def agreement(r):
    return sum(1 for p in PROBES if r["probes"][p] is not None
               and (r["probes"][p] > 0) == PAPER[p])


def figure(variants, results, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    rows = [(v, results[v["key"]]) for v in variants if results[v["key"]]["events"] is not None]
    fig, axes = plt.subplots(len(rows), 1, figsize=(8, 1.0 * len(rows) + 1), sharex=True)
    for ax, (v, r) in zip(axes, rows):
        grid = np.asarray(r["grid"])
        c = np.array([np.nan if n is None else n for n in r["counts"]], dtype=float)
        ax.step(grid, c, where="post", color="C0", lw=1.2)
        bad = [fx for fx, _ in r["failures"]]
        if bad:
            ax.plot(bad, np.zeros(len(bad)), "x", color="C3", ms=5, label="no equilibrium")
        for p in PROBES:
            ax.axvline(p, color="0.6" if PAPER[p] else "C2", lw=0.7, ls="--")
        ax.axvspan(THRESHOLD, FX_MAX, color="C1", alpha=0.08)
        ax.set_ylim(-0.3, max(3.5, np.nanmax(c) + 0.5) if np.isfinite(c).any() else 3.5)
        ax.set_ylabel("pairs [-]", fontsize=7)
        ax.tick_params(labelsize=7)
        ax.set_title(v["label"], fontsize=8, loc="left", pad=2)
    axes[-1].set_xlabel("F_x [k_n (2R)^(3/2) / 2000]")
    fig.suptitle("Complex-conjugate pairs of M^-1 J at the ramp steps (dashed: paper's F_x; "
                 "green: 0.062, paper: none; shaded: F_x > 0.082)", fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def code_version():
    import subprocess
    try:
        out = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=HERE, text=True,
                             capture_output=True, timeout=10)
        return out.stdout.strip() or "unknown"
    except (OSError, subprocess.SubprocessError):
        return "unknown"


def run(quick=False, no_figure=False):
    """Run every variant, write ``chain_protocols.md`` (and ``.png``); returns :func:`summary`."""
    ns = argparse.Namespace(quick=quick, no_figure=no_figure)
    t_start = time.time()
    damped_step = 5e-3 if ns.quick else 1e-3
    cap = 1_500_000 if ns.quick else 3_000_000
    fine, coarse = damped_step / 2, damped_step * 2
    base = ChainScene()
    m, R = base.mass, base.radius
    ring, sphere = ChainScene(inertia=m * R ** 2), ChainScene(inertia=0.4 * m * R ** 2)
    variants = [
        dict(key="default", label="1. default: Newton, step 1e-3, I = mR^2/2",
             run=lambda n: run_newton_variant(n, base, 1e-3)),
        dict(key="step5e-4", label="2a. Newton, step 5e-4",
             run=lambda n: run_newton_variant(n, base, 5e-4)),
        dict(key="step2e-3", label="2b. Newton, step 2e-3",
             run=lambda n: run_newton_variant(n, base, 2e-3)),
        dict(key="step5e-3", label="2c. Newton, step 5e-3",
             run=lambda n: run_newton_variant(n, base, 5e-3)),
        dict(key="ring", label="3a. Newton, step 1e-3, I = mR^2",
             run=lambda n: run_newton_variant(n, ring, 1e-3)),
        dict(key="sphere", label="3b. Newton, step 1e-3, I = 2mR^2/5",
             run=lambda n: run_newton_variant(n, sphere, 1e-3)),
        dict(key="damped0.01", label=f"4a. damped nu = 0.01, step {damped_step:g}",
             run=lambda n: run_damped_variant(n, base, damped_step, 0.01, cap)),
        dict(key="damped0.1", label=f"4b. damped nu = 0.1, step {damped_step:g}",
             run=lambda n: run_damped_variant(n, base, damped_step, 0.1, cap)),
        dict(key="damped0.447",
             label=f"4c. damped nu = {NU_PAPER_UNIT:.3f}, step {damped_step:g}, events located",
             run=lambda n: run_damped_variant(n, base, damped_step, NU_PAPER_UNIT, cap,
                                              locate=True)),
        dict(key="damped0.447-fine", label=f"4d. damped nu = {NU_PAPER_UNIT:.3f}, step {fine:g}",
             run=lambda n: run_damped_variant(n, base, fine, NU_PAPER_UNIT, cap)),
        dict(key="damped0.447-coarse",
             label=f"4e. damped nu = {NU_PAPER_UNIT:.3f}, step {coarse:g}",
             run=lambda n: run_damped_variant(n, base, coarse, NU_PAPER_UNIT, cap)),
        dict(key="damped1", label=f"4f. damped nu = 1, step {damped_step:g}",
             run=lambda n: run_damped_variant(n, base, damped_step, 1.0, cap)),
        dict(key="damped-start", label="5. damped (nu = 0.01) at F_x = 0, then Newton, step 1e-3",
             run=lambda n: run_newton_variant(n, base, 1e-3, damped_start_then_newton(0.01))),
        dict(key="jump0.01", label="6a. two-stage jump, damped nu = 0.01",
             run=lambda n: run_jump_variant(n, base, 0.01, cap)),
        dict(key="jump0.447", label=f"6b. two-stage jump, damped nu = {NU_PAPER_UNIT:.3f}",
             run=lambda n: run_jump_variant(n, base, NU_PAPER_UNIT, cap)),
    ]
    log("compiling kernels ...")
    relax_newton(base, initial_state(base))
    relax_damped(base, initial_state(base), tol=1e-6)
    results = {}
    for v in variants:
        log(f"{v['label']} ...")
        r = v["run"](v["key"])
        results[v["key"]] = r
        log(f"  done in {r['seconds']:.1f} s; first birth {first_birth(r)}; "
            f"probes {[fmt_probe(r['probes'][q]) for q in PROBES]}")
    total = time.time() - t_start

    rows = []
    for v in variants:
        r = results[v["key"]]
        if r["events"] is None:
            above, note = None, "probes only"
        else:
            above, note = all_above(r["grid"], r["counts"], r["events"], r["located"])
        above_s = {True: "yes", False: "no", None: "n/a"}[above] + (f" ({note})" if note else "")
        label = v["label"]
        if r.get("fallback"):
            label += " (not located: fell back to the step resolution, a relaxation failed)"
        rows.append(f"| {label} | {fmt_events(r)} | {first_birth(r)} | "
                    + " | ".join(fmt_probe(r["probes"][q]) for q in PROBES)
                    + f" | {above_s} | {continuous_from(r)} | {agreement(r)}/6 "
                    f"| {r['seconds']:.1f} |")
        r["above"] = above
        r["above_s"] = above_s

    def matching(pred):
        names = [v["label"].split(".")[0] for v in variants if pred(results[v["key"]])]
        return ", ".join(names) if names else "none"

    def has(r, q):
        return r["probes"][q] is not None and r["probes"][q] > 0

    def hasnt(r, q):
        return r["probes"][q] == 0

    default = results["default"]
    missing = []
    for key in ("step5e-4", "step2e-3", "step5e-3"):
        ev = results[key]["events"]
        gone = [e for e in default["events"] if e["located"] and not any(
            f["kind"] == e["kind"] and abs(f["fx"] - e["fx"]) < 1e-5 for f in ev)]
        if gone:
            label = next(v["label"].split(".")[0] for v in variants if v["key"] == key)
            missing.append(f"* {label} misses the default's "
                           + ", ".join(f"{e['kind']}@{e['fx']:.6f}" for e in gone)
                           + ": events are found only as changes between ramp steps, so a "
                           "birth and death within one step go unseen.")
    near_062 = []
    for v in variants:
        r = results[v["key"]]
        if r["probes"][0.062] == 0 and r["events"]:
            e = min(r["events"], key=lambda e: abs(e["fx"] - 0.062))
            where = (f"{e['fx']:.6f}" if e["located"]
                     else f"in ({fx3(e['lo'])}, {fx3(e['hi'])}]")
            near_062.append(f"* {v['label'].split('.')[0]}: no pair at 0.062; the nearest "
                            f"event is a {e['kind']} at F_x {where}"
                            + (f" ({abs(e['fx'] - 0.062):.1e} from 0.062)." if e["located"]
                               else "."))
    damped_lines, under_half_nu = [], []
    for key in ("damped0.01", "damped0.1", "damped0.447", "damped1"):
        r = results[key]
        g = [x for x, n in zip(r["growth"], r["counts"]) if n]
        under_half_nu.append(max(g, default=0.0) < r["nu"] / 2)
        damped_lines.append(
            f"  * nu = {r['nu']:.3g}: {sum(1 for n in r['counts'] if n)} of "
            f"{sum(1 for n in r['counts'] if n is not None)} converged equilibria have a pair, "
            f"largest growth rate among them {max(g) if g else 0:.3g} (nu/2 = {r['nu'] / 2:.3g}); "
            f"{len(r['failures'])} steps without equilibrium"
            + (f", ramp stopped at F_x = {fx3(r['stopped'])}" if r["stopped"] is not None else "")
            + ".")
    newton_growth_max = max(default["growth"])
    def same_events(r):
        a, b = r["events"], default["events"]
        return (a is not None and len(a) == len(b) and not r["failures"]
                and all(e["located"] and e["kind"] == f["kind"] and abs(e["fx"] - f["fx"]) < 1e-5
                        for e, f in zip(a, b)))

    same_as_default = [v["label"].split(".")[0] for v in variants
                       if v["key"] != "default" and same_events(results[v["key"]])]

    lines = [
        "# Chain: complex-pair events under different ramp protocols",
        "",
        f"`python validation/chain_protocols.py{' --quick' if ns.quick else ''}` "
        f"({total:.0f} s in all, {platform.machine()}, Python {platform.python_version()}, "
        f"{time.strftime('%Y-%m-%d')}, fricstab at commit {code_version()} plus any "
        "uncommitted changes; `--quick` for a shorter run). The event positions "
        "depend on the history-update details of the code (they moved when the Coulomb "
        "rescaling was changed), so rerun after such changes. N = 10, F_y = 0.1, "
        "kn = 2000, kt = 2kn/7, mu = 10, R = 0.5, m = 1; F_x ramped from 0 to 0.1. "
        "Stability: eigenvalues of M^-1 J (J with the tangential-history terms); the "
        "numbers below count complex-conjugate pairs (0: all eigenvalues real).",
        "",
        "**The defaults (`fricstab chain ramp`, `run_ramp`) are variant 1**: Newton "
        "relaxation from the previous equilibrium, ramp step 1e-3, I = m R^2 / 2, events "
        "located by bisection to 1e-6.",
        "",
        "How each variant is run:",
        "",
        "* Newton variants (1, 2, 3, 5): `run_ramp(..., locate=True)`; events are located "
        "to 1e-6 in F_x (6 decimals shown). Variant 5 relaxes the F_x = 0 state with the "
        "damped protocol (nu = 0.01; the paper's Stage 1) and ramps with Newton.",
        f"* Damped variants (4): velocity Verlet with drag m nu v (`relax_damped`, dt = "
        f"0.05/omega_wall, history advanced every step) to max |F|, |T| < 1e-12, step "
        f"{damped_step:g} unless stated, **events at the step resolution only** (`(lo,hi]`: "
        "the pair appears/disappears between the two steps; no bisection, to bound the "
        "time), except 4c: events bisected to 1e-6 afterwards (`fricstab.protocols.ramp.locate_event`, the "
        "same pair indicator as `run_ramp`), every trial relaxed by the damped protocol "
        "from the last converged step below (an event whose trial does not converge within "
        "the cap below stays at the step resolution). "
        "A step "
        f"whose relaxation does not converge within {cap:,} Verlet steps is listed as "
        "`no eq.@F_x` and the ramp continues from the state reached; after three in a row "
        f"the ramp stops. nu = {NU_PAPER_UNIT:.3f} is the paper's nu = 0.01 if it is "
        "measured per the paper's stated time unit sqrt(m 2R/kn) = sqrt(1/2000) rather "
        "than per simulation unit (the paper does not say which).",
        "* Two-stage jump (6, an extra): the Supplementary Material's protocol for Fig. 3 "
        "read literally (Stage 1: F_y only, damped; Stage 2: F_x added, damped): each probe "
        "F_x applied at once to the F_x = 0 equilibrium. Probes only.",
        "* A probe F_x off the ramp grid (steps 2e-3, 5e-3) is relaxed with the variant's "
        "relaxer from the grid equilibrium below it.",
        "* Not run: history t rotated with the contact (objective update). The verified "
        "Jacobian assumes the unrotated increment rule of both papers (Charan Eq. 2, SM "
        "Eq. 5), so the spectra would not be those of that variant's dynamics.",
        "",
        "| variant | events (kind@F_x) | first birth | 0.03 | 0.04 | 0.062 | 0.083 | 0.087 "
        "| 0.090 | pairs for all F_x > 0.082? | pairs without gap from | probes as paper | s |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|",
        *rows,
        "| **paper** | two births (Fig. 2); first pair dies before 0.062 | (Fig. 2) | yes | yes "
        "| no | yes | yes | yes | yes | in (0.062, 0.083) | 6/6 | |",
        "",
        "Columns 0.03 ... 0.090: number of complex pairs at that F_x (`no eq.`: the "
        "relaxation did not reach an equilibrium). \"probes as paper\": how many of the six "
        "agree with the paper on pair / no pair. \"pairs without gap from\": start of the "
        "last stretch of F_x, up to 0.1, with a pair at every step (the located birth that "
        "opens it, or its step bracket); the paper places that birth between 0.062 and "
        "0.083 and says unstable for all F_x > 0.082.",
        "",
        "## Comparison with the paper",
        "",
        f"* Pair at F_x = 0.03 and 0.04 (paper: yes): "
        f"{matching(lambda r: has(r, 0.03) and has(r, 0.04))}.",
        f"* All eigenvalues real at F_x = 0.062 (paper): {matching(lambda r: hasnt(r, 0.062))}.",
        f"* Pairs at 0.083, 0.087 and 0.090 (paper: yes): "
        f"{matching(lambda r: all(has(r, q) for q in (0.083, 0.087, 0.090)))}.",
        f"* Pairs for all F_x > 0.082 up to 0.1 (SM): "
        f"{matching(lambda r: r.get('above') is True)}.",
        f"* All six probes as the paper: {matching(lambda r: agreement(r) == 6)}.",
        *near_062,
        "* Step sensitivity of the damped ramp at nu = 0.447: "
        + "; ".join(f"step {st:g}: {agreement(results[k])}/6 probes as the paper, pairs for "
                    f"all F_x > 0.082: {results[k].get('above_s')}"
                    for st, k in ((fine, "damped0.447-fine"), (damped_step, "damped0.447"),
                                  (coarse, "damped0.447-coarse")))
        + ".",
        *missing,
        f"* Variants with the default's event sequence (located, within 1e-5): "
        f"{', '.join(same_as_default) if same_as_default else 'none'}.",
        "* The damped protocol selects equilibria. Near an equilibrium the damped "
        "dynamics has exponents s with s^2 + nu s = lambda, so an equilibrium whose "
        "conjugate pair grows at rate Im sqrt(-lambda) > nu/2 repels the relaxation, which "
        "presumably moves along the history-dependent family of equilibria until it "
        "settles on one that is stable for the damped dynamics, or on none (to first order "
        "in nu^2/|lambda|; "
        + ("consistent with this, every converged damped equilibrium below has its largest "
           "growth rate under nu/2" if all(under_half_nu) else
           "but not every converged damped equilibrium below has its largest growth rate "
           "under nu/2")
        + "). Along the Newton ramp the largest "
        f"growth rate reaches {newton_growth_max:.3g} (simulation units), far above nu/2 "
        "for nu = 0.01 and 0.1:",
        *damped_lines,
        "",
        "So on the damped ramps a pair is seen only where it happens to be slow enough, "
        "and a damped ramp past the point where no damped-stable equilibrium is found "
        "(`no eq.`) is no longer quasistatic (the chain moves). Statements about pairs "
        "\"at F_x\" therefore depend on the protocol; the Newton ramp gives the spectrum "
        "of the equilibrium reached continuously from the previous one, whether or not it "
        "is stable.",
        "",
        "![pairs along the ramp](chain_protocols.png)" if not ns.no_figure else "",
        "",
    ]
    if not ns.no_figure:
        figure(variants, results, HERE / "chain_protocols.png")
    (HERE / "chain_protocols.md").write_text("\n".join(lines))
    log("\n".join(lines))
    log(f"total {total:.1f} s")
    return summary(variants, results, damped_step)


def summary(variants, results, damped_step):
    """Per variant: pair counts at the probes, agreement with the paper, first birth,
    pairs for all F_x > 0.082, where a damped ramp stopped; and the nearest event to
    0.062 of each variant without a pair there (JSON values)."""
    out = {"probes": list(PROBES), "paper": [PAPER[q] for q in PROBES],
           "damped_step": damped_step, "variants": {}}
    for v in variants:
        r = results[v["key"]]
        births = [e for e in (r["events"] or []) if e["kind"] == "birth"]
        near = None
        if r["probes"][0.062] == 0 and r["events"]:
            e = min(r["events"], key=lambda e: abs(e["fx"] - 0.062))
            near = {"kind": e["kind"], "fx": float(e["fx"]), "located": bool(e["located"]),
                    "lo": float(e["lo"]), "hi": float(e["hi"])}
        out["variants"][v["key"]] = {
            "label": v["label"],
            "probes": [r["probes"][q] for q in PROBES],
            "agreement": agreement(r),
            "above": r.get("above"), "above_note": r.get("above_s"),
            "first_birth": first_birth(r),
            "first_birth_fx": float(births[0]["fx"]) if births and births[0]["located"] else None,
            "events": None if r["events"] is None else len(r["events"]),
            "event_fx": None if r["events"] is None else [round(float(e["fx"]), 9)
                                                           for e in r["events"]],
            "no_equilibrium": [float(fx) for fx, _ in r["failures"]],
            "stopped": None if r["stopped"] is None else float(r["stopped"]),
            "continuous_from": continuous_from(r),
            "nearest_to_0.062": near}
    return out


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--quick", action="store_true",
                   help="damped variants at step 5e-3 with a smaller step cap")
    p.add_argument("--no-figure", action="store_true")
    ns = p.parse_args(argv)
    run(ns.quick, ns.no_figure)


if __name__ == "__main__":
    main()
