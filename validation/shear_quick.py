"""Quick default of ``fricstab shear run``: stick-slip phases against Lee & Hurley Sec. 3.3.

Runs the quick preset (``fricstab.cli.shear.QUICK``: 300 disks, I = 1e-4,
kappa = 1e3, strain 0.06, dgamma = 1e-5; see that module for each change
from the paper and its effect) and writes ``validation/shear_quick.md`` and
``validation/shear_quick.png`` (tau = S/N against strain).  Paper: about
42,000 phases in about 130,000 output steps for mu_s = 0.7 (0.32 phases per
step); 18,000 / 46,000 / 52,000 / 42,000 for mu_s = 0.1 / 0.3 / 0.5 / 0.7.

Then analyses the run (:func:`fricstab.analysis.shear.analyze`) and computes
the Jacobian spectrum before every slip (:mod:`fricstab.analysis.shear_slips`),
adding the phase statistics, the slip-spectrum statistics and the Spearman
tables to the markdown.

The spectra come from the soft route by default (the k = 50 softest
eigenvalues, as ``fricstab shear analyze``); ``--spectra dense`` takes the
whole spectrum before every slip (~20x slower).  :func:`report` returns the
numbers the claims ``shear.quick_*`` of ``validation/reproduce.py`` record.

Usage: ``python validation/shear_quick.py [OUT_DIR] [--reuse] [--spectra soft|dense]``
(default: a temporary folder; the run's files stay there; ``--reuse`` analyses
an existing run of the same parameters in OUT_DIR instead of running again).
"""

import json
import shutil
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))  # run from anywhere without installing
PAPER_PHASES_PER_STEP = 42_000 / 130_000


def main(out=None, params=None, md=HERE / "shear_quick.md", png=HERE / "shear_quick.png",
         reuse=False, spectra="soft"):
    """Run (or reuse) the quick preset, analyse it, write ``md``, ``png`` and the JSON; the record."""
    return report(out, params, md, png, reuse, spectra)["record"]


def report(out=None, params=None, md=HERE / "shear_quick.md", png=HERE / "shear_quick.png",
           reuse=False, spectra="soft"):
    """What :func:`main` does; returns ``record`` (shear.json), ``analysis``
    (``ShearAnalysis.to_json()``), ``spectra`` (the slip-spectra summary), ``rows``."""
    from fricstab.cli.shear import resolve_params, run_shear
    out = Path(out or tempfile.mkdtemp(prefix="shear_quick_"))
    p = resolve_params(None, "quick", params or {})
    t0 = time.perf_counter()
    if reuse and (out / "shear.json").is_file():
        rec = json.loads((out / "shear.json").read_text())
        if rec["parameters"] != json.loads(json.dumps(p)):
            raise SystemExit(f"--reuse: {out} was run with other parameters")
        wall = sum(t["wall_s"] for t in rec["timings"].values())
    else:
        rec = run_shear(p, out, force=True, argv=["validation/shear_quick.py"])
        wall = time.perf_counter() - t0
    t1 = time.perf_counter()
    an = _analyze(out, p, spectra)
    t_an = time.perf_counter() - t1
    ph, sv, d = rec["phases"], rec["servo"], rec["derived"]
    thr = rec["throughput_particle_steps_per_s"]
    # cost of the paper run: 1,000 bulk disks (+ about 60 wall disks), 130,000
    # frames at the paper's I and kappa, from this run's throughput
    paper = resolve_params(None, "paper")
    from fricstab.scenes.shear import make_cell
    import math
    cell = make_cell(paper)
    gdot = paper["inertial_number"] * math.sqrt(cell.n_target / cell.lx) / 2.0
    spf = math.ceil(paper["dgamma"] / (gdot * paper["dt_frac"] * cell.t_c))
    paper_steps = spf * round(paper["strain"] / paper["dgamma"])
    paper_hours = paper_steps * len(cell.radius) / thr / 3600
    lines = [
        "# Plane shear, quick default: stick-slip (Lee & Hurley Sec. 3)", "",
        "Command: `python validation/shear_quick.py` (= `fricstab shear run --out DIR`, "
        "preset quick; then `fricstab shear analyze`"
        f"{' --spectra dense' if spectra == 'dense' else ''}). Regenerated with its record "
        "by `python validation/reproduce.py --claim shear.quick_rate` (the record names the "
        "revision, machine and seeds). Wall times are those of the run that wrote this page, "
        "on a machine that may have run other jobs beside it.", "",
        "| quantity | this run | paper (mu_s = 0.7) |", "|---|---|---|",
        f"| bulk disks | {d['n_bulk']} | ~1,000 |",
        f"| I, kappa | {p['inertial_number']:g}, {p['kappa']:g} | 4e-6, 1e4 |",
        f"| output interval dgamma | {p['dgamma']:g} ({d['steps_per_frame']} steps) | 7.2e-7 |",
        f"| total strain | {p['strain']:g} | ~0.116 (0.022 + 130,000 x 7.2e-7) |",
        f"| output steps in window (strain >= {p['gamma0']:g}) | {ph['window_steps']} | ~130,000 |",
        f"| phases (stick + slip) | {ph['n_phases']} ({ph['n_stick']} + {ph['n_slip']}) | ~42,000 |",
        f"| phases per output step | {ph['phases_per_step'] or 0:.3f} | {PAPER_PHASES_PER_STEP:.3f} |",
        f"| largest drop of tau in a phase | {ph['largest_drop'] or 0:.4f} | - |",
        f"| mean tau in window (std) | {rec['tau_mean_window'] or 0:.3f} ({rec['tau_std_window'] or 0:.3f}) | not stated in the text (Fig. 2a only; the figure is not in our copy) |",
        f"| servo: mean / rms / max relative N error | {sv['mean_rel_error']:.1e} / {sv['rms_rel_error']:.1e} / {sv['max_abs_rel_error']:.1e} | - |",
        f"| wall time (prepare + shear) | {wall:.0f} s | - |",
        f"| throughput | {thr:.3g} particle-steps/s | - |",
        f"| paper-size run at this throughput | {paper_steps:.3g} steps x {len(cell.radius)} disks = {paper_hours:.1f} h | - |",
        "", "Phases are counted with `fricstab.analysis.shear.find_phases` (a phase is a run "
        "of output steps with the same sign of d tau). The paper's count is for ~130,000 "
        "output steps; compare the rate per output step. ", "",
        "## Analysis (`fricstab shear analyze`) and the Jacobian before every slip", "",
        f"Analysis of the same run: {t_an:.0f} s (D2min, GR regions, phases, Spearman; then "
        f"the spectrum before every slip: {an['scope']}).", "",
        "| quantity | this run |", "|---|---|",
        *(f"| {k} | {v} |" for k, v in an["rows"]), "", an["tables"],
    ]
    md.write_text("\n".join(lines) + "\n")
    shutil.copyfile(out / "shear.png", png)
    (md.with_suffix(".json")).write_text(json.dumps({"phases": ph, "servo": sv,
                                                     "wall_s": wall, "throughput": thr,
                                                     "paper_hours": paper_hours}, indent=1))
    return {"record": rec, "analysis": an["analysis"], "spectra": an["spectra"],
            "rows": an["rows"]}


def _analyze(out, p, route="soft"):
    """Lee & Hurley analyses of the run and the spectrum before each slip (rows, markdown)."""
    from fricstab.analysis.shear import analyze, tables_markdown
    from fricstab.cli.shear_analyze import frames_of
    from fricstab.analysis.shear_slips import slip_spectra
    frames = frames_of(out)
    res = analyze(frames, p["gamma0"], progress=False)
    # the soft end (default, as `fricstab shear analyze`) or the whole spectrum (dense)
    sp = slip_spectra(frames, res.phases, res.arrays["phase_dtau_p"], p, route=route)
    s, c = res.summary, sp.summary()
    corr = c["correlations_with_following_dtau_p"]["all"]

    def cell(x):
        return "n/a" if x["rho"] is None else f"{x['rho']:+.2f} (p = {x['p']:.1e}, n = {x['n']})"
    rows = [("phases (stick / slip)", f"{s['n_phases']} ({s['n_stick']} / {s['n_slip']})"),
            ("long phases (t_p > 3 dgamma)", f"{s['fraction_long']:.2f} of all"),
            ("median / mean abs Delta tau_p of slips",
             f"{s['slip_abs_dtau_median']:.2e} / {s['slip_abs_dtau_mean']:.2e}"),
            ("slips with a spectrum (every slip)", f"{c['n_slips']} of {s['n_slip']}"),
            ("slips whose stick state has complex pairs"
             + (" among its 50 softest modes" if route == "soft" else ""),
             f"{c['slips_with_complex_pairs']}"),
            ("complex pairs per state: median / max",
             f"{int(np.median(sp.n_complex_pairs))} / {c['n_complex_pairs_max']}"),
            ("contacts on the slide branch per state: tangential / rolling (median)",
             f"{int(np.median(sp.n_sliding))} / {int(np.median(sp.n_rolling))}"),
            ("largest growth rate, median (1/s)", f"{c['max_growth_rate_median_per_s']:.3g}"),
            ("Spearman(Delta tau_p, complex pairs)", cell(corr["n_complex_pairs"])),
            ("Spearman(Delta tau_p, largest growth rate)", cell(corr["max_growth_rate"])),
            ("Spearman(Delta tau_p, lowest real eigenvalue)", cell(corr["lowest_real_eigenvalue"]))]
    t = res.tables
    tables = tables_markdown({"Delta tau - gD2min, g_t10%D2min per step (Fig. 9a)": t["step_dtau"],
                              "all phases (Fig. 9b)": t["phase_all"],
                              "long phases (Fig. 10a)": t["phase_long"],
                              "short phases (Fig. 10b)": t["phase_short"],
                              "Delta tau_p - t_p (Fig. 10c)": t["phase_tp"]},
                             "Spearman tables (struck through: p > 0.05)")
    c = {**c, "n_complex_pairs_median": float(np.median(sp.n_complex_pairs)),
         "n_sliding_median": float(np.median(sp.n_sliding)),
         "n_rolling_median": float(np.median(sp.n_rolling))}
    return {"rows": rows, "tables": tables, "analysis": res.to_json(), "spectra": c,
            "scope": c["statistics_over"]}


if __name__ == "__main__":
    import argparse
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("out", nargs="?", default=None)
    ap.add_argument("--reuse", action="store_true")
    ap.add_argument("--spectra", choices=("soft", "dense"), default="soft")
    ns = ap.parse_args()
    main(ns.out, reuse=ns.reuse, spectra=ns.spectra)
    print((HERE / "shear_quick.md").read_text())
