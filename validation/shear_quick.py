"""Quick default of ``fricstab shear run``: stick-slip phases against Lee & Hurley Sec. 3.3.

Runs the quick preset (``fricstab.shear_cli.QUICK``: 300 disks, I = 1e-4,
kappa = 1e3, strain 0.06, dgamma = 1e-5; see that module for each change
from the paper and its effect) and writes ``validation/shear_quick.md`` and
``validation/shear_quick.png`` (tau = S/N against strain).  Paper: about
42,000 phases in about 130,000 output steps for mu_s = 0.7 (0.32 phases per
step); 18,000 / 46,000 / 52,000 / 42,000 for mu_s = 0.1 / 0.3 / 0.5 / 0.7.

Usage: ``python validation/shear_quick.py [OUT_DIR]`` (default: a temporary
folder; the run's files stay there).
"""

import json
import shutil
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))  # run from anywhere without installing
PAPER_PHASES_PER_STEP = 42_000 / 130_000


def main(out=None, params=None, md=HERE / "shear_quick.md", png=HERE / "shear_quick.png"):
    from fricstab.shear_cli import resolve_params, run_shear
    out = Path(out or tempfile.mkdtemp(prefix="shear_quick_"))
    p = resolve_params(None, "quick", params or {})
    t0 = time.perf_counter()
    rec = run_shear(p, out, force=True, argv=["validation/shear_quick.py"])
    wall = time.perf_counter() - t0
    ph, sv, d = rec["phases"], rec["servo"], rec["derived"]
    thr = rec["throughput_particle_steps_per_s"]
    # cost of the paper run: 1,000 bulk disks (+ about 60 wall disks), 130,000
    # frames at the paper's I and kappa, from this run's throughput
    paper = resolve_params(None, "paper")
    from fricstab.shear import make_cell, Shear
    sim = Shear(make_cell(paper))
    sim.wall[1] = sim.cell.n_target
    h0 = sim.height * 0.45 / 0.82   # dense height estimate from the placement fraction
    import math
    gdot = paper["inertial_number"] * math.sqrt(sim.cell.n_target / sim.cell.lx) / 2.0
    spf = math.ceil(paper["dgamma"] / (gdot * paper["dt_frac"] * sim.cell.t_c))
    paper_steps = spf * round(paper["strain"] / paper["dgamma"])
    paper_hours = paper_steps * len(sim.cell.radius) / thr / 3600
    lines = [
        "# Plane shear, quick default: stick-slip (Lee & Hurley Sec. 3)", "",
        "Command: `python validation/shear_quick.py` (= `fricstab shear run --out DIR`, "
        "preset quick). Measured on the 2-core machine while other jobs shared the CPU.", "",
        "| quantity | this run | paper (mu_s = 0.7) |", "|---|---|---|",
        f"| bulk disks | {d['n_bulk']} | ~1,000 |",
        f"| I, kappa | {p['inertial_number']:g}, {p['kappa']:g} | 4e-6, 1e4 |",
        f"| output interval dgamma | {p['dgamma']:g} ({d['steps_per_frame']} steps) | 7.2e-7 |",
        f"| total strain | {p['strain']:g} | ~0.094 |",
        f"| output steps in window (strain >= {p['gamma0']:g}) | {ph['window_steps']} | ~130,000 |",
        f"| phases (stick + slip) | {ph['n_phases']} ({ph['n_stick']} + {ph['n_slip']}) | ~42,000 |",
        f"| phases per output step | {ph['phases_per_step'] or 0:.3f} | {PAPER_PHASES_PER_STEP:.3f} |",
        f"| largest drop of tau in a phase | {ph['largest_drop'] or 0:.4f} | - |",
        f"| mean tau in window (std) | {rec['tau_mean_window'] or 0:.3f} ({rec['tau_std_window'] or 0:.3f}) | not stated in the text (Fig. 2a only; the figure is not in our copy) |",
        f"| servo: mean / rms / max relative N error | {sv['mean_rel_error']:.1e} / {sv['rms_rel_error']:.1e} / {sv['max_abs_rel_error']:.1e} | - |",
        f"| wall time (prepare + shear) | {wall:.0f} s | - |",
        f"| throughput | {thr:.3g} particle-steps/s | - |",
        f"| paper-size run at this throughput | {paper_steps:.3g} steps x {len(sim.cell.radius)} disks = {paper_hours:.1f} h | - |",
        "", "Phases are counted with `fricstab.shear_analysis.find_phases` (a phase is a run "
        "of output steps with the same sign of d tau). The paper's count is for ~130,000 "
        "output steps; compare the rate per output step. ",
    ]
    md.write_text("\n".join(lines) + "\n")
    shutil.copyfile(out / "shear.png", png)
    (md.with_suffix(".json")).write_text(json.dumps({"phases": ph, "servo": sv,
                                                     "wall_s": wall, "throughput": thr,
                                                     "paper_hours": paper_hours}, indent=1))
    return rec


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else None)
    print((HERE / "shear_quick.md").read_text())
