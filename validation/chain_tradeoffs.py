"""Speed/accuracy trade of the chain protocol's knobs, measured.

1. Ramp step and bisection tolerance against the accuracy of the first
   pair birth and the cost of the ramp (reference: step 2.5e-4, tol 1e-9).
2. Verlet time step (in units of 1/omega_wall) against the accuracy of the
   growth rate of the unstable mode (reference: the Jacobian) and its cost.
3. Verlet time step against the wave speeds V1, V2 (10 realizations; the
   difference to the finest step against the statistical uncertainty).

Writes ``chain_tradeoffs.md``; :func:`run` returns the numbers the report's
statements rest on (the claim ``chain.knobs`` of ``validation/claims/chain.py``).
``python validation/chain_tradeoffs.py [--quick]``
"""

import argparse
import math
import platform
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))

import numpy as np  # noqa: E402

from fricstab.protocols.dynamics import default_dt  # noqa: E402
from fricstab.protocols.growth import measure_growth  # noqa: E402
from fricstab.protocols.ramp import ramped_equilibrium, run_ramp  # noqa: E402
from fricstab.protocols.waves import fit_waves, run_realization  # noqa: E402
from fricstab.scenes.chain import ChainScene  # noqa: E402

REPORT = HERE / "chain_tradeoffs.md"
STEPS = (5e-3, 2e-3, 1e-3, 5e-4)
TOLS = (1e-4, 1e-6, 1e-8)
GROWTH_DTS = (0.005, 0.01, 0.02, 0.05, 0.1, 0.2)
WAVE_DTS = (0.01, 0.02, 0.05, 0.1)


def _first_birth(res):
    births = [e for e in res.events if e.kind == "birth"]
    return births[0].fx if births else np.nan


def measure(quick=False):
    """The three tables; returns (summary dict, table rows per part)."""
    scene = ChainScene()
    run_ramp(scene, 0.01, 1e-3)  # compile
    t0 = time.perf_counter()
    ref = _first_birth(run_ramp(scene, 0.1, 2.5e-4, tol=1e-9))
    ramp_rows = []
    for step in STEPS:
        for tol in TOLS:
            t = time.perf_counter()
            res = run_ramp(scene, 0.1, step, tol=tol)
            ramp_rows.append((step, tol, _first_birth(res), len(res.events),
                              time.perf_counter() - t))
    eq = ramped_equilibrium(scene, 0.03)
    omega = 1.0 / default_dt(scene, 1.0)   # the wall's normal frequency at rest
    growth_rows = []
    for f in GROWTH_DTS:
        t = time.perf_counter()
        g = measure_growth(scene.with_fx(0.03), eq, dt=f / omega)
        growth_rows.append((f, g.measured, g.predicted, g.relative_difference,
                            time.perf_counter() - t))
    n_real = 4 if quick else 10
    eq = ramped_equilibrium(scene, 0.09)
    wave_rows = []
    for f in WAVE_DTS:
        t = time.perf_counter()
        reals = [run_realization(scene.with_fx(0.09), eq, seed, dt=f / omega)
                 for seed in range(n_real)]
        sec = time.perf_counter() - t
        wave_rows.append((f, fit_waves(reals, n_boot=100), sec))
    # what the report's statements rest on
    loc = max(abs(fb - ref) / tol for _, tol, fb, _, _ in ramp_rows)
    big = [(f, e) for f, _, _, e, _ in growth_rows if f >= 0.05]
    order = float(np.polyfit(np.log([f for f, _ in big]), np.log([e for _, e in big]), 1)[0])
    fine = wave_rows[0][1]

    def dist(a, ea, b, eb):
        s = math.hypot(ea, eb)
        return abs(a - b) / s if s > 0 else 0.0

    d1 = max(dist(w.v1, w.v1_err, fine.v1, fine.v1_err) for _, w, _ in wave_rows[1:])
    d2 = max(dist(w.v2, w.v2_err, fine.v2, fine.v2_err) for _, w, _ in wave_rows[1:])
    summary = {"reference_birth": float(ref), "worst_error_over_tol": float(loc),
               "events_per_step": {f"{s:g}": n for s, tol, _, n, _ in ramp_rows if tol == 1e-6},
               "growth_error_order": order,
               "growth_error_default": next(e for f, _, _, e, _ in growth_rows if f == 0.02),
               "waves_realizations": n_real, "v1_max_sigma": float(d1), "v2_max_sigma": float(d2),
               "seconds_per_realization_default": next(s for f, _, s in wave_rows if f == 0.02)
               / n_real, "seconds": time.perf_counter() - t0}
    return summary, (ramp_rows, growth_rows, wave_rows)


def report(summary, tables):
    """The text of ``chain_tradeoffs.md``."""
    ramp_rows, growth_rows, wave_rows = tables
    s = summary
    ref = s["reference_birth"]
    lines = ["# Chain: the speed/accuracy trade of each knob", "",
             f"`python validation/chain_tradeoffs.py` ({platform.machine()}, Python "
             f"{platform.python_version()}, {time.strftime('%Y-%m-%d')}); timings are single runs"
             " on a machine shared with other jobs.",
             "", "## Ramp step and bisection tolerance (Newton ramp to F_x = 0.1)", "",
             f"Reference first birth: {ref:.10f} (step 2.5e-4, tol 1e-9).", "",
             "| step | tol | first birth | error | events | s |", "|---|---|---|---|---|---|"]
    for step, tol, fb, n, sec in ramp_rows:
        lines.append(f"| {step:g} | {tol:g} | {fb:.10f} | {abs(fb - ref):.1e} | {n} | {sec:.2f} |")
    within = s["worst_error_over_tol"] <= 1.0
    lines += ["", f"The location error {'stays within' if within else 'exceeds'} the bisection "
              f"tolerance at every step (largest error / tol: {s['worst_error_over_tol']:.2f}): "
              "the bracket halves to `tol`; the step changes which events are seen (two in one "
              "step cancel: events at tol 1e-6 per step "
              + ", ".join(f"{k}: {v}" for k, v in s["events_per_step"].items())
              + ") but not where a seen event is, because each trial relaxes from the step below.",
              "", "## Verlet time step against the growth rate (F_x = 0.03)", "",
              "| dt omega_wall | growth (sim units) | Jacobian | relative error | s |",
              "|---|---|---|---|---|"]
    for f, meas, pred, err, sec in growth_rows:
        lines.append(f"| {f} | {meas:.7f} | {pred:.7f} | {err:.1e} | {sec:.2f} |")
    lines += ["", "Velocity Verlet has a second-order phase error: over dt omega_wall >= 0.05 the "
              f"growth-rate error falls as (dt omega)^{s['growth_error_order']:.2f} (fitted); "
              "below, it reaches the fit's own floor.", "",
              "## Verlet time step against the wave speeds (F_x = 0.09)", "",
              f"{s['waves_realizations']} realizations each (same seeds).", "",
              "| dt omega_wall | V1 | V2 | s |", "|---|---|---|---|"]
    for f, fit, sec in wave_rows:
        lines.append(f"| {f} | {fit.v1:.5f} +- {fit.v1_err:.5f} | {fit.v2:.3f} +- {fit.v2_err:.3f} "
                     f"| {sec:.1f} |")
    lines += ["", "The post-instability dynamics is chaotic: each realization changes with dt. "
              "Against the finest step the wave speeds of the other steps lie within "
              f"{s['v1_max_sigma']:.1f} (V1) and {s['v2_max_sigma']:.1f} (V2) combined "
              "bootstrap errors; the default dt = 0.02 / omega_wall cost "
              f"{s['seconds_per_realization_default']:.2f} s per realization here.", "",
              f"Total {s['seconds']:.0f} s."]
    return "\n".join(lines) + "\n"


def run(quick=False):
    """Measure, write ``chain_tradeoffs.md``; returns the summary."""
    summary, tables = measure(quick)
    REPORT.write_text(report(summary, tables))
    return summary


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--quick", action="store_true")
    ns = p.parse_args(argv)
    run(ns.quick)
    print(REPORT.read_text(), end="")


if __name__ == "__main__":
    main()
