"""Friction sweep of the plane shear (Lee & Hurley Sec. 4): phases and Spearman tables per mu_s.

For mu_s in {0.1, 0.3, 0.5, 0.7}: one quick-preset run each (members of
:func:`fricstab.io.ensemble.run_ensemble`, resumable: a finished member is kept),
then :func:`fricstab.analysis.shear.analyze` on its frames.  Writes
``validation/shear_sweep.md`` (phases per output step against the paper's
18,000 / 46,000 / 52,000 / 42,000 phases in ~130,000 steps, the paper's Sec. 4
statements each judged per mu_s (:mod:`shear_sec4`), and the Spearman tables of
every panel of Fig. 13).  Slow (about
four quick runs plus their analyses): ``python validation/shear_sweep.py [DIR]``.
The claims ``shear.sweep_*`` of ``validation/reproduce.py`` run :func:`sweep`
(in-process, ``scheduler="inline"``) and :func:`report`, which writes the
page and returns its numbers.
"""

import json
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))  # run from anywhere without installing
sys.path.insert(0, str(HERE))

import shear_sec4  # noqa: E402
PAPER = {0.1: 18_000, 0.3: 46_000, 0.5: 52_000, 0.7: 42_000}
#: Fig. 13's panels: (title, table, series) of :func:`fricstab.analysis.shear.analyze`
PANELS = (("(a) Delta tau - g_t10% D2min, every output step", "step_dtau", "g10"),
          ("(b) Delta tau_p - mg_t10% D2min, all phases", "phase_all", "mg10"),
          ("(c) Delta tau_p - mg_t10% D2min, long phases", "phase_long", "mg10"),
          ("(d) Delta tau_p - mg_t10% D2min, short phases", "phase_short", "mg10"),
          ("(e) Delta tau_p - mg D2min, long phases", "phase_long", "mg"),
          ("(f) Delta tau_p - sg_t10% D2min, all phases", "phase_all", "sg10"),
          ("(g) Delta tau_p - sg_t10% D2min, long phases", "phase_long", "sg10"),
          ("(h) Delta tau_p - sg_t10% D2min, short phases", "phase_short", "sg10"),
          ("(i) Delta tau_p - sg D2min, long phases", "phase_long", "sg"),
          ("(j) Delta tau_p - t_p, long phases", "phase_tp", "long"))
#: the Spearman series :func:`report` returns (Figs. 13 a, b, c, f, g)
USED = {"step_dtau": ("g10",), "phase_all": ("mg10", "sg10"), "phase_long": ("mg10", "sg10")}


def member(mu_s, out):
    """One sweep member: run, analyze; returns scalars and the Spearman table (JSON)."""
    from fricstab.analysis.shear import analyze
    from fricstab.cli.shear import resolve_params, run_shear
    from fricstab.cli.shear_analyze import frames_of
    p = resolve_params(None, "quick", {"mus": mu_s})
    rec = run_shear(p, out, force=True, log=lambda *a: None)
    res = analyze(frames_of(out), p["gamma0"], progress=False)
    return as_member(rec, res.to_json())


def as_member(rec, analysis_json):
    """A sweep member's arrays from a run record and its analysis (``ShearAnalysis.to_json()``)."""
    import numpy as np
    return {"phases_per_step": np.float64(rec["phases"]["phases_per_step"]),
            "n_phases": np.int64(rec["phases"]["n_phases"]),
            "window_steps": np.int64(rec["phases"]["window_steps"]),
            "tables": np.array(json.dumps(analysis_json, default=float))}


def sweep(out, scheduler="local", workers=2, progress=True, given=None):
    """Run (or take from ``out``) every member; ``given``: {mu_s: member arrays} already made
    (the quick run is the member at mu_s = 0.7).  Returns {"mu<m>": member arrays}."""
    from fricstab.io.ensemble import run_ensemble
    given = {f"mu{m:g}": v for m, v in (given or {}).items()}
    out = Path(out)
    jobs = {f"mu{m:g}": dict(mu_s=m, out=str(out / f"mu{m:g}")) for m in PAPER
            if f"mu{m:g}" not in given}
    res = run_ensemble(member, jobs, out, scheduler=scheduler, workers=workers,
                       progress=progress) if jobs else {}
    return {**res, **given}


def main(out=None):
    res = sweep(out or HERE / ".shear_sweep")
    report(res)
    return res


def tables_of(res):
    """{mu_s: the Spearman tables of its member's analysis}."""
    return {m: json.loads(str(res[f"mu{m:g}"]["tables"]))["tables"] for m in PAPER}


def report(res, md=HERE / "shear_sweep.md"):
    """Write ``md`` and the Fig. 13 c, g figures from the members; returns the numbers:
    per mu_s the phase count, steps and rate, and the Spearman tables (a), (c), (g)."""
    from fricstab.analysis.shear import tables_markdown
    lines = ["# Plane shear: friction sweep (Lee & Hurley Sec. 4, quick preset)", "",
             "Command: `python validation/shear_sweep.py` (one quick-preset run per mu_s, "
             "seed 0; the run at mu_s = 0.7 is the quick preset itself). Regenerated with "
             "its record by `python validation/reproduce.py --claim shear.sweep_rate`.", "",
             "| mu_s | phases | output steps | phases per output step | paper phases per step |",
             "|---|---|---|---|---|"]
    steps = {m: int(r["window_steps"]) if "window_steps" in r else   # members stored before
             round(int(r["n_phases"]) / float(r["phases_per_step"]))  # it was kept
             for m, r in ((m, res[f"mu{m:g}"]) for m in PAPER)}
    for m in PAPER:
        r = res[f"mu{m:g}"]
        lines.append(f"| {m:g} | {int(r['n_phases'])} | {steps[m]} | "
                     f"{float(r['phases_per_step']):.3f} | {PAPER[m] / 130_000:.3f} |")
    tables = tables_of(res)
    judged = shear_sec4.judge_sweep(tables)
    lines += ["", "## The paper's statements on Figs. 12-13 (Sec. 4)", "",
              "Each statement judged per mu_s by the rule of `validation/shear_sec4.py` "
              "(cells with p <= 0.05 and n >= 10; bands |rho| < 0.4 weak, 0.4-0.7 moderate, "
              ">= 0.7 strong; 'stronger' by Fisher's z of |rho|, significantly weaker at "
              "d < -2); overall: agrees where it agrees at every mu_s.", "",
              shear_sec4.markdown(judged), "",
              "Spearman rho (p, n) per bin, Fig. 13 a-j (rows are mu_s); struck through: "
              "p > 0.05, which the paper omits.", ""]
    for title, section, series in PANELS:
        rows = {f"mu_s = {m:g}": tables[m][section][series] for m in PAPER}
        lines.append(tables_markdown({title: rows}, title).split("\n", 2)[2])
    from fricstab.figures import shear as sf
    for tag, section, series, title in (
            ("c", "phase_long", "mg10", "Delta tau_p - mg_t10% D2min, long phases (Fig. 13c)"),
            ("g", "phase_long", "sg10", "Delta tau_p - sg_t10% D2min, long phases (Fig. 13g)")):
        sf.fig_spearman_bins({f"mu_s = {m:g}": tables[m][section][series] for m in PAPER},
                             Path(md).parent / f"shear_sweep_fig13{tag}.png", title)
    lines += ["", "Figures: `shear_sweep_fig13c.png`, `shear_sweep_fig13g.png` (abs rho per "
              "bin, only p <= 0.05 drawn)."]
    Path(md).write_text("\n".join(lines) + "\n")
    return {f"{m:g}": {"phases": int(res[f"mu{m:g}"]["n_phases"]),
                       "steps": steps[m],
                       "rate": float(res[f"mu{m:g}"]["phases_per_step"]),
                       "tables": {t: {s: tables[m][t][s] for s in series}
                                  for t, series in USED.items()}}
            for m in PAPER}


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else None)
