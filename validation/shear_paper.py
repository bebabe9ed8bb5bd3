"""The paper-preset plane shear against Lee & Hurley Secs. 3.2-3.3 (Figs. 2, 8-10).

Reads the analysis of a ``fricstab shear run --preset paper`` run (``fricstab
shear analyze --out RUN``, or ``--partial DIR2`` while the run is still going)
and writes ``validation/shear_paper.md``, ``validation/shear_paper.json`` and
the figures ``validation/shear_paper_*.png``: the run's facts and wall time,
the phase statistics against the paper's ~42,000 phases in ~130,000 output
steps, the distribution of Delta tau_p (stick and slip), the paper's
statements on the Spearman correlations of Figs. 9-10 each against our
coefficients in the bins it names, and the Spearman tables.

Usage::

    fricstab shear run --preset paper --out RUN          # ~5 h on 2 idle cores
    fricstab shear analyze --out RUN                     # or --partial DIR2 while it runs
    python validation/shear_paper.py RUN [--analysis DIR2]

The paper names strengths in words; we read |rho| < 0.4 as weak, 0.4-0.7 as
moderate and >= 0.7 as strong (Dancey & Reidy's bands, a common reading; the
paper states none) and, as the paper does, keep only cells with p <= 0.05.
"""

import argparse
import json
import shutil
import sys
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))  # run from anywhere without installing

PAPER_PHASES, PAPER_STEPS = 42_000, 130_000
BANDS = ((0.4, "weak"), (0.7, "moderate"), (np.inf, "strong"))
# (figure, table, series, bins (lo of each bin), classes the paper states, its words)
STATEMENTS = [
    ("9a", "step_dtau", ("g", "g10"), (-1e-1,), {"weak"},
     "Delta tau vs gD2min, g_t10%D2min: weak for -1e-1 < Delta tau < -1e-2"),
    ("9a", "step_dtau", ("g", "g10"), (-1e-2,), {"moderate"},
     "moderate for -1e-2 < Delta tau < -1e-3"),
    ("9a", "step_dtau", ("g", "g10"), (1e-3,), {"moderate"},
     "moderate for 1e-3 < Delta tau < 1e-2"),
    ("9b", "phase_all", ("mg", "mg10", "sg", "sg10"), (-1e-1, -1e-2), {"moderate", "strong"},
     "all phases, four metrics: moderate to strong for -1e-1 < Delta tau_p < -1e-3"),
    ("10a", "phase_long", ("mg10", "sg10"), (-1e-1,), {"strong"},
     "long phases, mg_t10%, sg_t10%: strong for Delta tau_p < -1e-2"),
    ("10a", "phase_long", ("mg10", "sg10"), (-1e-2, -1e-3, -1e-4), {"moderate"},
     "mostly moderate for -1e-2 < Delta tau_p < 0"),
    ("10c", "phase_tp", ("long",), (1e-4, 1e-3, 1e-2), {"moderate"},
     "Delta tau_p vs t_p, long phases: moderate for Delta tau_p > 1e-4 (stick)"),
    ("10c", "phase_tp", ("long",), (-1e-1, -1e-2, -1e-3, -1e-4), {"weak"},
     "weak for slips (Delta tau_p < 0) in long phases"),
    ("10c", "phase_tp", ("short",), (-1e-1, -1e-2, -1e-3, -1e-4, 0.0, 1e-4, 1e-3, 1e-2),
     {"weak"}, "weak in short phases"),
]


def strength(rho):
    """The band of |rho| (weak, moderate, strong)."""
    return next(name for top, name in BANDS if abs(rho) < top)


def judge(tables, table, series, bins, classes):
    """Our cells in the named bins: (text, verdict) with verdict agrees/differs/no data."""
    cells, seen = [], []
    for s in series:
        for c in tables[table][s]:
            if c["lo"] not in bins:
                continue
            if c["rho"] is None:
                cells.append(f"{s} [{c['lo']:.0e}): n/a (n = {c['n']})")
                continue
            word = strength(c["rho"]) if c["significant"] else "p > 0.05"
            cells.append(f"{s} [{c['lo']:.0e}): {c['rho']:+.2f} ({word}, n = {c['n']})")
            if c["significant"]:
                seen.append(strength(c["rho"]))
    if not seen:
        return "; ".join(cells), "no significant cell"
    agree = sum(w in classes for w in seen)
    verdict = "agrees" if agree == len(seen) else ("partly" if agree else "differs")
    return "; ".join(cells), f"{verdict} ({agree} of {len(seen)} significant cells)"


def interval_table(strain, tau, gamma0, dgamma, every=(1, 2, 4, 7, 14, 28)):
    """Phases per output step with every k-th frame kept: the frame-interval knob.

    Subsampling the paper-interval run gives the same trajectory seen at a
    coarser output interval, so this one knob is varied alone (14 frames of
    7.2e-7 = 1.0e-5, the quick preset's interval).
    """
    from fricstab.analysis.shear import find_phases
    rows = []
    for k in every:
        t, s = tau[::k], strain[::k]
        ok = np.zeros(len(t), bool)
        ok[1:] = s[:-1] >= gamma0
        n = int(ok.sum())
        if n < 10:
            continue
        m = len(find_phases(t, ok))
        rows.append({"every": k, "dgamma": k * dgamma, "steps": n, "phases": m,
                     "per_step": m / n})
    return rows


def window_table(strain, tau, gamma0, width=0.02):
    """Phases per output step in consecutive strain windows of ``width`` from ``gamma0``:
    whether the rate is steady along the run (phases are found within each window)."""
    from fricstab.analysis.shear import find_phases
    rows, lo = [], gamma0
    while lo < strain[-1]:
        hi = min(lo + width, float(strain[-1]))
        ok = np.zeros(len(tau), bool)
        ok[1:] = (strain[:-1] >= lo) & (strain[:-1] < hi)
        n = int(ok.sum())
        if n:
            k = len(find_phases(tau, ok))
            rows.append({"from": lo, "to": hi, "steps": n, "phases": k, "per_step": k / n})
        lo += width
    return rows


def steadiness(strain, tau, gamma0, window_from):
    """Whether the analysed window (from ``window_from``) is a steady state: the steady start
    of tau from the paper's ``gamma0`` (or the window's start, if earlier) by
    :func:`fricstab.analysis.stationarity.steady_window` (what ``--steady-start`` prints),
    and the Mann-Kendall test of the window itself."""
    from fricstab.analysis.stationarity import memory_trend_test, steady_window
    from fricstab.errors import ParameterError
    _, info = steady_window(strain, tau, min(gamma0, window_from))
    out = {"start": info["start"], "p": info.get("p"), "window_from": float(window_from),
           "in_steady_state": info["steady"] and window_from >= info["start"] - 1e-12,
           "reason": info.get("reason")}
    if "p" not in info:                 # too few frames for the test
        return {**out, "error": info["reason"]}
    try:
        whole = memory_trend_test(tau[strain >= window_from])
    except ParameterError as exc:
        return {**out, "error": str(exc)}
    return {**out, "window_p": whole["p"], "window_drift_over_std": whole["drift_over_std"],
            "window_block_lag1": whole["block_lag1"], "window_blocks": whole["n_blocks"],
            "window_tau_int": whole["tau_int"], "window_frames": whole["n_values"],
            "window_independent": whole["independent"]}


def steady_window(run):
    """The steady start of a run's tau from the paper's 2.2 %
    (:func:`fricstab.analysis.stationarity.steady_window`; 2.2 % where none passes), from
    ``RUN/shear.npz`` or, for a run still going, its frames so far: (start, info)."""
    from fricstab.analysis.stationarity import steady_window as window
    from fricstab.cli.shear_analyze import frames_of
    from fricstab.io.frames import read_arrays
    run = Path(run)
    if (run / "shear.npz").exists():
        with np.load(run / "shear.npz") as z:
            strain, tau = z["strain"], z["tau"]
    else:
        parts = [read_arrays(f, ("strain", "tau"))[1] for f in frames_of(run, partial=True).files]
        strain = np.concatenate([a["strain"] for a in parts])
        tau = np.concatenate([a["tau"] for a in parts])
    return window(strain, tau, 0.022)       # the paper's stick-slip window starts at 2.2 %


def steadiness_text(st, run):
    """The sentence of :func:`steadiness` for the page."""
    if "error" in st:
        return f"Not tested: {st['error']}."
    head = (f"Mann-Kendall test of {st['window_blocks']} block means of tau over the analysed "
            f"window (strain >= {100 * st['window_from']:.2f} %, {st['window_frames']} frames; "
            f"tau's integrated autocorrelation time {st['window_tau_int']:.0f} frames, so the "
            f"blocks are {'' if st['window_independent'] else '**not** '}independent): "
            f"p = {st['window_p']:.2g}, drift {st['window_drift_over_std']:+.2f} std over the "
            f"window, lag-1 correlation of the block means {st['window_block_lag1']:.2f}. ")
    if st["start"] is None:
        return head + ("**Not a steady state**: no start from 2.2 % on passes the test on "
                       f"independent blocks ({st.get('reason') or 'no start passes'}); the "
                       "statistics average a drifting state. "
                       f"Extend the run: `fricstab shear run --out {run} --resume --strain S` "
                       "with a larger S.")
    if st["in_steady_state"]:
        return head + (f"**Steady** from strain {100 * st['start']:.2f} % (p = {st['p']:.2g}); "
                       "the window lies in it, so its statistics are steady-state ones.")
    return head + (f"Steady from strain {100 * st['start']:.2f} % (p = {st['p']:.2g}), but the "
                   "window starts before it: **its statistics include the transient**. For the "
                   f"steady state alone: `fricstab shear analyze --out {run} --gamma0 "
                   f"$(python validation/shear_paper.py {run} --steady-start) --force` and "
                   "this script again.")


def dtau_distribution(dtau, path):
    """Counts of |Delta tau_p| per decade for stick and slip phases, and its figure."""
    from fricstab.figures.common import finish, pyplot
    plt = pyplot()
    edges = 10.0 ** np.arange(-9, 0.5, 0.25)
    fig, ax = plt.subplots(figsize=(6, 3.6), constrained_layout=True)
    rows = {}
    for name, sel, color in (("stick", dtau > 0, "C0"), ("slip", dtau < 0, "C3")):
        a = np.abs(dtau[sel])
        h, _ = np.histogram(a, edges)
        ax.stairs(h / max(len(a), 1) / np.diff(np.log10(edges)), edges, color=color,
                  label=f"{name} ({len(a)} phases)")
        rows[name] = {"n": int(len(a)),
                      "quantiles_10_50_90": [float(q) for q in np.quantile(a, [.1, .5, .9])]
                      if len(a) else None,
                      "per_decade": {f"[1e{d}, 1e{d + 1})": int(((a >= 10.0 ** d) &
                                                                (a < 10.0 ** (d + 1))).sum())
                                     for d in range(-8, 0)}}
    ax.set(xscale="log", xlabel=r"$|\Delta\tau_p|$ [-]",
           ylabel="phases per decade / phases [-]",
           title="Distribution of the stress change of a phase (paper: none given)")
    ax.legend(fontsize=8)
    finish(fig, path, dpi=130)
    return rows


def run_wall(shear, prep):
    """The wall time of a complete run from its record: the process that finished it, and
    (when it resumed from a checkpoint) all its frames at that process's throughput."""
    n = shear["derived"]["n_particles"]
    total = (shear["frames"] - 1) * shear["derived"]["steps_per_frame"]   # sheared steps
    seconds, rate = shear["shear_seconds_this_process"], shear["throughput_particle_steps_per_s"]
    text = f"prepare {prep['seconds'] / 60:.0f} min + shear {seconds / 3600:.2f} h"
    own = round(seconds * rate / n) if rate else total
    if own < total:   # resumed: this process sheared only the last frames
        text += (f" in the last process (its {own / total:.0%} of the {total:,} sheared steps, "
                 f"{rate:.3g} particle-steps/s); all of them at that rate "
                 f"{total * n / rate / 3600:.1f} h")
    return text


def revisions(run, an_dir):
    """Which code made these numbers: the git revision recorded by the process that finished
    the run (``shear.json``), by the analysis (``analysis.json``), and of this checkout."""
    import subprocess

    def rev(path):
        try:
            g = json.loads(Path(path).read_text()).get("git") or {}
        except (OSError, ValueError):
            return "not recorded"
        return (g.get("revision") or "not recorded")[:7] + ("+" if g.get("dirty") else "")
    try:
        here = subprocess.run(["git", "-C", str(HERE), "rev-parse", "--short=7", "HEAD"],
                              capture_output=True, text=True, check=True).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        here = "unknown"
    return (f"Revisions: the run finished at {rev(run / 'shear.json')}, analysed at "
            f"{rev(an_dir / 'analysis.json')}, this page written at {here} (`+`: a dirty "
            "tree). A run resumed from checkpoints is bit-identical to one made in one go; the "
            "numbers below are not regenerated when the code changes: `python "
            "validation/reproduce.py --claim shear.paper_rate` (hours) reruns everything.")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("run", type=Path, help="the run directory (fricstab shear run --preset paper)")
    ap.add_argument("--analysis", type=Path, default=None,
                    help="the analysis directory (default: RUN; a --partial DIR2)")
    ap.add_argument("--md", type=Path, default=HERE / "shear_paper.md")
    ap.add_argument("--steady-start", action="store_true",
                    help="print the strain from which the run's tau is steady (2.2 %% where no "
                         "start passes the trend test), for `fricstab shear analyze --gamma0`, "
                         "and exit")
    ns = ap.parse_args(argv)
    if ns.steady_start:
        start, info = steady_window(ns.run)
        print(f"{start:.6f}")
        print("tau steady from there (p = {:.2g})".format(info["p"]) if info["steady"] else
              f"not steady: {info['reason']}; the paper's 2.2 %", file=sys.stderr)
        return 0
    from fricstab.analysis.shear import paper_tables
    from fricstab.figures.shear import fig_spearman_bins
    run, an_dir = ns.run, ns.analysis or ns.run
    rec = json.loads((an_dir / "analysis.json").read_text())
    with np.load(an_dir / "analysis.npz") as z:
        arrays = {k: z[k] for k in z.files}
    s, t, setting = rec["summary"], rec["tables"], rec["parameters"]
    complete = (run / "shear.json").exists() and "frames" not in setting
    shear = json.loads((run / "shear.json").read_text()) if complete else None
    prep = json.loads((run / "prepare.json").read_text())
    stem = ns.md.with_suffix("")
    stem.parent.mkdir(parents=True, exist_ok=True)
    figs = {}
    for src, name in (("analysis_stress_strain.png", "fig2"),
                      ("analysis_steps_largest_slip.png", "fig8"),
                      ("analysis_slip_spectra.png", "slip_spectra")):
        if (an_dir / src).exists():
            figs[name] = f"{stem.name}_{name}.png"
            shutil.copyfile(an_dir / src, stem.parent / figs[name])
    for key, name, title in (("step_dtau", "fig9a", "Delta tau per step (cf. Fig. 9a)"),
                             ("phase_all", "fig9b", "all phases (cf. Fig. 9b)"),
                             ("phase_long", "fig10a", "long phases (cf. Fig. 10a)"),
                             ("phase_short", "fig10b", "short phases (cf. Fig. 10b)"),
                             ("phase_tp", "fig10c", "Delta tau_p - t_p (cf. Fig. 10c)")):
        figs[name] = f"{stem.name}_{name}.png"
        fig_spearman_bins(t[key], stem.parent / figs[name], title)
    figs["dtau_p"] = f"{stem.name}_dtau_p.png"
    dist = dtau_distribution(arrays["phase_dtau_p"], stem.parent / figs["dtau_p"])
    strain = arrays["strain"]
    n_steps, rate = s["n_steps"], s["phases_per_step"]
    k0, k1 = s["largest_drop_steps"] or (0, 0)
    if complete:
        wall = run_wall(shear, prep)
        reach = f"{strain[-1]:.4f} (complete)"
    else:
        wall = f"prepare {prep['seconds'] / 60:.0f} min; shear still running"
        reach = (f"{strain[-1]:.4f} of {0.022 + PAPER_STEPS * 7.2e-7:.4f} "
                 f"(**partial**: the first {setting['frames']} frames)")
    rows = [
        ("frames analysed; strain reached", reach),
        (f"output steps in the window (strain >= {100 * s['gamma0']:.2f} %)",
         f"{n_steps} (paper ~{PAPER_STEPS:,} from 2.2 %)"),
        ("phases (stick + slip)", f"{s['n_phases']} ({s['n_stick']} + {s['n_slip']}); "
                                  f"paper ~{PAPER_PHASES:,}"),
        ("phases per output step", f"**{rate:.3f}** (paper {PAPER_PHASES / PAPER_STEPS:.3f})"),
        ("long phases (t_p > 3 dgamma)", f"{s['fraction_long']:.2f} of all"),
        ("slip |Delta tau_p|: median / mean", f"{s['slip_abs_dtau_median']:.2e} / "
                                             f"{s['slip_abs_dtau_mean']:.2e}"),
        ("largest drop of tau in one phase", f"{s['largest_drop']:.4f} at strain "
                                             f"{100 * strain[k0]:.4f}-{100 * strain[k1]:.4f} % "
                                             "(paper: Fig. 2b, 10.0555-10.0575 %)"),
        ("wall time (2-core AMD EPYC)", wall),
    ]
    sp = rec.get("slip_spectra")
    if sp:
        rows.append(("slips whose stick state has complex pairs (soft window)",
                     f"{sp['slips_with_complex_pairs']} of {sp['n_slips']}"))
    quick = json.loads((HERE / "shear_quick.json").read_text())["phases"]
    knob = interval_table(strain, arrays["tau"], s["gamma0"], 7.2e-7)
    along = window_table(strain, arrays["tau"], s["gamma0"])
    steady = steadiness(strain, arrays["tau"], 0.022, s["gamma0"])   # the paper's 2.2 %
    verdicts = [(fig, words, *judge(t, table, series, bins, classes))
                for fig, table, series, bins, classes, words in STATEMENTS]
    sys.path.insert(0, str(HERE))
    import shear_sec33
    compared = shear_sec33.judge(t)
    lines = [
        "# Plane shear at the paper's scale (Lee & Hurley Secs. 3.2-3.3)", "",
        f"Commands: `fricstab shear run --preset paper --out RUN`, `fricstab shear analyze "
        f"--out RUN{'' if complete else ' --partial DIR2'}`, `python validation/shear_paper.py "
        f"RUN{'' if complete else ' --analysis DIR2'}`. 1,000 bulk disks (+ 67 wall disks), "
        "I = 4e-6, kappa = 1e4, mu_s = 0.7, mu_r = 0.01, frames 7.2e-7 of strain apart.", "",
        revisions(run, an_dir), "",
        "| quantity | this run |", "|---|---|", *(f"| {a} | {b} |" for a, b in rows), "",
        "## Is the analysed window a steady state?", "", steadiness_text(steady, run), "",
        "## The frame interval: why the quick preset counts fewer phases per step", "",
        "The same trajectory with every k-th frame kept (one knob varied alone; k = 14 is the "
        f"quick preset's 1.0e-5). Quick preset (dgamma 1e-5, I 1e-4, kappa 1e3, 300 disks): "
        f"{quick['phases_per_step']:.3f} phases per step (seed 0, `validation/shear_quick.json`; "
        "its seed spread: `validation/shear_knobs.md`).", "",
        "| every k-th frame | dgamma | output steps | phases | phases per step |",
        "|---|---|---|---|---|",
        *(f"| {r['every']} | {r['dgamma']:.2e} | {r['steps']} | {r['phases']} | "
          f"{r['per_step']:.3f} |" for r in knob), "",
        "## Along the run: phases per step in windows of 2 % strain", "",
        "Phases found within each window (a phase cut by a window's edge counts in both).", "",
        "| strain window | output steps | phases | phases per step |", "|---|---|---|---|",
        *(f"| {100 * r['from']:.2f}-{100 * r['to']:.2f} % | {r['steps']} | {r['phases']} | "
          f"{r['per_step']:.3f} |" for r in along), "",
        "## The paper's statements on Figs. 9-10 against our coefficients", "",
        "Bands: |rho| < 0.4 weak, 0.4-0.7 moderate, >= 0.7 strong (the paper states none); "
        "cells with p > 0.05 are not judged, as the paper omits them.", "",
        "| Fig. | paper | ours (bin: rho, band, n) | verdict |", "|---|---|---|---|",
        *(f"| {f} | {w} | {c} | {v} |" for f, w, c, v in verdicts), "",
        "## The paper's comparisons on Figs. 9b-10b (Sec. 3.3)", "",
        "Rules of `validation/shear_sec33.py`: cells with p <= 0.05 and n >= 10; a pair holds "
        "where |rho_1| >= |rho_2|, is significantly weaker at d < -2 (Fisher's z of |rho|); "
        "'stronger' agrees where more than half of the pairs hold.", "",
        shear_sec33.markdown(compared), "",
        f"Figures: Fig. 2 ![]({figs.get('fig2', '')}), Fig. 8 around the largest slip "
        f"![]({figs.get('fig8', '')}), Figs. 9-10 ![]({figs['fig9a']}) ![]({figs['fig9b']}) "
        f"![]({figs['fig10a']}) ![]({figs['fig10b']}) ![]({figs['fig10c']}), the Delta tau_p "
        f"distribution ![]({figs['dtau_p']}).", "",
        "## Distribution of Delta tau_p (phases per decade of |Delta tau_p|)", "",
        "| decade | " + " | ".join(dist["stick"]["per_decade"]) + " |",
        "|---|" + "---|" * len(dist["stick"]["per_decade"]),
        *(f"| {name} | " + " | ".join(str(v) for v in dist[name]["per_decade"].values()) + " |"
          for name in ("stick", "slip")), "",
        "## Spearman tables", "",
        paper_tables(t),
    ]
    ns.md.write_text("\n".join(lines) + "\n")
    stem.with_suffix(".json").write_text(json.dumps(
        {"complete": complete, "strain_reached": float(strain[-1]), "summary": s,
         "frame_interval": knob, "along_the_run": along, "steady": steady,
         "verdicts": [{"figure": f, "paper": w, "ours": c, "verdict": v}
                      for f, w, c, v in verdicts], "comparisons": compared,
         "dtau_p": dist, "wall": wall}, indent=1))
    print(f"wrote {ns.md}: {s['n_phases']} phases in {n_steps} steps ({rate:.3f} per step; "
          f"paper {PAPER_PHASES / PAPER_STEPS:.3f}); strain {strain[-1]:.4f}"
          f"{'' if complete else ' (partial)'}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
