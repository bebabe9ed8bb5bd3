"""Issue 34, item 3: the mu_s sweep at the paper's scale against Lee & Hurley Sec. 4.

Reads the member runs of a sweep (``fricstab shear sweep --preset paper --out DIR``: one
paper-preset run per mu_s in ``DIR/runs/mus<M>_seed<S>/``; several sittings with
``--resume``), analyses each from its steady start
(:func:`fricstab.analysis.stationarity.steady_window` from the run's gamma0, the paper's 2.2 %
in the paper preset; kept in the
run folder and reused while the start is the same) and writes ``--md`` (default
``validation/shear_sweep_paper.md``) and its ``.json``: per mu_s the phase rate against the
paper's 18,000 / 46,000 / 52,000 / 42,000 phases in ~130,000 output steps (mean over the
seeds run), the steadiness of each member, Sec. 4's eight statements judged per mu_s
(:mod:`shear_sec4`), and the Spearman tables of every panel of Fig. 13.  A member still
running that ``shear_rolling.py export`` wrote enters as far as it got, marked partial with
the strain it reached; members with nothing analysed are listed as missing: the page states
the scale reached.

Usage::

    fricstab shear sweep --preset paper --out DIR --workers 2 [--resume]   # ~6 h per member
    python validation/shear_sweep_paper.py DIR

or, members run in committed segments across sittings and machines
(``validation/shear_rolling.py``)::

    python validation/shear_rolling.py export --out DIR
    python validation/shear_sweep_paper.py DIR
"""

import argparse
import json
import sys
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))
sys.path.insert(0, str(HERE))


def members(sweep_dir):
    """{(mu_s, seed): run folder} of the sweep's finished members, and the unfinished ones."""
    done, todo = {}, []
    for run in sorted((Path(sweep_dir) / "runs").glob("mus*_seed*")):
        mus, seed = run.name[3:].split("_seed")
        key = (float(mus), int(seed))
        if (run / "shear.json").exists():
            done[key] = run
        else:
            todo.append(key)
    return done, todo


def partial(sweep_dir, todo):
    """{(mu_s, seed): run folder} of the unfinished members with an analysis of their frames so
    far (``shear_rolling.py export`` of a member still running: ``analysis.json`` records its
    frame count)."""
    out = {}
    for mus, seed in todo:
        run = Path(sweep_dir) / "runs" / f"mus{mus!r}_seed{seed}"
        rec = run / "analysis.json"
        if rec.exists() and (run / "shear.npz").exists() and \
                "frames" in json.loads(rec.read_text()).get("parameters", {}):
            out[mus, seed] = run
    return out


def analysed(run, log=print):
    """The analysis of ``run`` from its steady start (made here, or the one in the folder
    when it starts there): (tables, summary, steady info)."""
    from fricstab.analysis.stationarity import steady_window
    from fricstab.cli import main
    with np.load(run / "shear.npz") as z:
        strain, tau = z["strain"], z["tau"]
    made = (json.loads((run / "shear.json").read_text())["parameters"]   # finished, or
            if (run / "shear.json").exists() else    # a running member's export
            json.loads((run / "analysis.json").read_text())["run_parameters"])
    gamma0 = made["gamma0"]                                                 # paper: 2.2 %
    start, info = steady_window(strain, tau, gamma0)
    rec = run / "analysis.json"
    have = json.loads(rec.read_text()) if rec.exists() else None
    if have is None or have["parameters"].get("gamma0") != start:
        log(f"{run.name}: analysing from strain {start:.5f}")
        argv = ["shear", "analyze", "--out", str(run), "--gamma0", repr(start), "--force",
                "--no-progress"]
        if main(argv) != 0:
            raise RuntimeError(f"fricstab {' '.join(argv)} failed")
        have = json.loads(rec.read_text())
    return have["tables"], have["summary"], {**info, "window_from": start}


def steady_cell(row):
    """A member's "steady" cell: yes or no, with the last tested window's p-value and how many
    of tau's integrated autocorrelation times it holds (20 needed: a "no" with p >= 0.05 is a
    window too short for tau's memory, not a trend)."""
    st = row["steady"]
    if st.get("p") is None:
        return "no (too few frames for the test)"
    return (f"{'yes' if st['steady'] else 'no'} (p = {st['p']:.2g}, "
            f"{st['n_values'] / st['tau_int']:.1f} integrated times)")


def report(sweep_dir, md=HERE / "shear_sweep_paper.md", log=print, source=None):
    """Analyse and judge the finished members; write ``md`` and its ``.json``; the document.
    ``source``: where the members come from, in words (default: the sweep folder, made by
    ``fricstab shear sweep --preset paper``)."""
    import shear_sec4
    import shear_sweep
    from fricstab.analysis.shear import tables_markdown
    done, todo = members(sweep_dir)
    part = partial(sweep_dir, todo)
    todo = [k for k in todo if k not in part]
    if not done and not part:
        raise SystemExit(f"{sweep_dir}: no finished member in runs/ (run `fricstab shear sweep "
                         f"--preset paper --out {sweep_dir}` first)")
    rows, tables = {}, {}
    for (mus, seed), run in sorted({**done, **part}.items()):
        t, s, st = analysed(run, log)
        with np.load(run / "shear.npz") as z:
            reached = float(z["strain"][-1])
        rows.setdefault(mus, []).append({"seed": seed, "rate": s["phases_per_step"],
                                         "phases": s["n_phases"], "steps": s["n_steps"],
                                         "steady": st, "strain": reached,
                                         "partial": (mus, seed) in part})
        tables.setdefault(mus, t)                  # the lowest seed's tables
    paper = {m: n / 130_000 for m, n in shear_sweep.PAPER.items()}
    judged = shear_sec4.judge_sweep(tables)
    lines = ["# Plane shear: friction sweep at the paper's scale (Lee & Hurley Sec. 4)", "",
             "Sweep: " + (source or f"`{sweep_dir}` (`fricstab shear sweep --preset paper`)")
             + ", analysed from each "
             "member's steady start by `python validation/shear_sweep_paper.py`. Finished: "
             + (", ".join(f"mu_s = {m:g} seed {s}" for m, s in sorted(done)) or "none")
             + "; partial (the scale reached): "
             + (", ".join(f"mu_s = {r['mus']:g} seed {r['seed']} to strain {r['strain']:.4f}"
                          for r in _partial_rows(rows)) or "none") + "; missing: "
             + (", ".join(f"mu_s = {m:g} seed {s}" for m, s in todo) or "none")
             + (" (not in runs/ yet: " + ", ".join(
                 f"{m:g}" for m in paper if m not in rows) + ")" if set(paper) - set(rows)
                else "") + ".", "",
             "| mu_s | seeds | phases per output step (each seed) | paper | ours / paper | "
             "window from (strain) | strain reached | steady |",
             "|---|---|---|---|---|---|---|---|"]
    for m, rs in sorted(rows.items()):
        got = [r["rate"] for r in rs if r["rate"] is not None]   # None: no step past gamma0
        rate = float(np.mean(got)) if got else None
        ref = paper.get(m)
        lines.append(f"| {m:g} | {len(rs)} | " + " / ".join(
            "no step past gamma0 yet" if r["rate"] is None else f"{r['rate']:.3f}" for r in rs)
                     + f" | {'-' if ref is None else f'{ref:.3f}'} | "
                     + ("-" if ref is None or rate is None else f"{rate / ref:.2f}") + " | "
                     + " / ".join(f"{r['steady']['window_from']:.4f}" for r in rs) + " | "
                     + " / ".join(f"{r['strain']:.4f}{' (partial)' if r['partial'] else ''}"
                                  for r in rs) + " | "
                     + " / ".join(map(steady_cell, rs)) + " |")
    lines += ["", "steady: whether tau from \"window from\" passes the Mann-Kendall test (p >= "
              "0.05) on blocks sized by its memory, the window holding at least 20 of tau's "
              "integrated autocorrelation times (`fricstab.analysis.stationarity.steady_window`); "
              "where no start passes, the window is the paper's (from 2.2 %) and the cell gives "
              "the last candidate start's test: the member is to be extended.",
              "", "## The paper's statements on Fig. 13 (Sec. 4)", "",
              "Rules: `validation/shear_sec4.py` (as `validation/shear_sweep.md`).", "",
              shear_sec4.markdown(judged), "",
              "## Fig. 13, every panel (Spearman rho (p, n) per bin; struck through: p > 0.05)",
              ""]
    for title, section, series in shear_sweep.PANELS:
        panel = {f"mu_s = {m:g}": tables[m][section][series] for m in sorted(tables)}
        lines.append(tables_markdown({title: panel}, title).split("\n", 2)[2])
    md = Path(md)
    md.write_text("\n".join(lines) + "\n")
    doc = {"sweep": str(sweep_dir), "done": [list(k) for k in sorted(done)],
           "partial": [list(k) for k in sorted(part)],
           "missing": [list(k) for k in todo],
           "rates": {f"{m:g}": rs for m, rs in sorted(rows.items())},
           "paper": {f"{m:g}": r for m, r in paper.items()},
           "sec4": [{k: x[k] for k in ("id", "panels", "paper", "verdict")}
                    | {"cells": {f"{m:g}": c["verdict"] for m, c in x["cells"].items()}}
                    for x in judged]}
    md.with_suffix(".json").write_text(json.dumps(doc, indent=1, default=float))
    log(f"wrote {md}")
    return doc


def _partial_rows(rows):
    return [{"mus": m, **r} for m, rs in sorted(rows.items()) for r in rs if r["partial"]]


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("sweep", type=Path, help="the --out DIR of `fricstab shear sweep`")
    ap.add_argument("--md", type=Path, default=HERE / "shear_sweep_paper.md")
    a = ap.parse_args(argv)
    report(a.sweep, a.md)
    return 0


if __name__ == "__main__":
    sys.exit(main())
