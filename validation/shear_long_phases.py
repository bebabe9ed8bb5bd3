"""Issue 34, item 4: Fig. 11 (contact angles of the GR regions against Delta tau_p in long
phases) and the long-slip statement sg_t10% >= mg_t10% (Sec. 4), computed for one analysed run.

    fricstab shear analyze --out RUN
    python validation/shear_long_phases.py RUN [--n-boot 2000]

Reads ``RUN/analysis.npz`` (:func:`fricstab.analysis.shear.analyze`), writes
``RUN/long_phases.md`` and ``.json``: the Fig. 11 cells per quartile range of mg_t10% and
sg_t10% (the paper's ranges are only in its figure) with the paper's statement (weak or not
significant everywhere) and a verdict per panel; and per slip bin of Delta tau_p the paired
bootstrap of |rho_sg10| - |rho_mg10| (:func:`fricstab.analysis.shear_long_phases.sg_versus_mg`)
with the statement's verdict per bin.
"""

import argparse
import json
import sys
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))

from fricstab.analysis.shear_long_phases import angle_correlations, sg_versus_mg  # noqa: E402

STRONG = 0.4    # |rho| >= 0.4: moderate or strong (the bands of validation/shear_paper.py)


def fig11_verdict(cells):
    """The paper: weak (|rho| < 0.4) or not significant in every cell.  Agrees when no
    significant cell reaches 0.4; the cells that do are named."""
    bad = [f"{key} [{c['lo']:.3g}, {c['hi']:.3g}) {name} rho {c[name]['rho']:+.2f}"
           for key, cs in cells.items() for c in cs for name in ("mean", "median")
           if c[name]["rho"] is not None and c[name]["significant"]
           and abs(c[name]["rho"]) >= STRONG]
    n = sum(c[name]["rho"] is not None for cs in cells.values() for c in cs
            for name in ("mean", "median"))
    if n == 0:
        return "not comparable (no cell has enough long phases)"
    return ("agrees: no significant cell reaches |rho| 0.4" if not bad else
            f"differs: {len(bad)} of {n} cells moderate or strong ({'; '.join(bad)})")


def sg_verdict(cells):
    judged = [c for c in cells if c["holds"] is not None]
    if not judged:
        return "not comparable (fewer than 10 long slips in every bin)"
    held = sum(c["holds"] for c in judged)
    return (f"{'agrees' if held == len(judged) else 'differs'}: the statement holds in {held} "
            f"of {len(judged)} slip bins (a bin fails when sg_t10% is significantly weaker)")


def report(run, n_boot=2000):
    with np.load(Path(run) / "analysis.npz") as z:
        arrays = {k: z[k] for k in z.files}
    fig11 = angle_correlations(arrays)
    sg = sg_versus_mg(arrays, n_boot=n_boot)
    doc = {"fig11": fig11, "fig11_verdict": fig11_verdict(fig11),
           "sg_versus_mg": sg, "sg_verdict": sg_verdict(sg), "n_boot": n_boot}

    def rho(c):
        return "n/a" if c["rho"] is None else f"{c['rho']:+.2f} (p {c['p']:.2g}, n {c['n']})"
    lines = ["# Long phases: Fig. 11 and sg_t10% against mg_t10%", "",
             f"Run: `{run}`. Long phases: t_p > 3 output steps.", "",
             "## Fig. 11", "", "Paper: the correlations of Delta tau_p with the mean and "
             "median |contact angle| of the GR regions are weak or not significant in every "
             "range.", "", "| range of | D2min range (m^2) | phases | rho with mean | "
             "rho with median |", "|---|---|---|---|---|"]
    for key, cs in fig11.items():
        for c in cs:
            lines.append(f"| {key} | {c['lo']:.3g} - {c['hi']:.3g} | {c['n_phases']} | "
                         f"{rho(c['mean'])} | {rho(c['median'])} |")
    lines += ["", f"Verdict: {doc['fig11_verdict']}.", "", "## sg_t10% against mg_t10% in "
              "long slips", "", "Paper (Sec. 4): almost equal to or stronger. Paired "
              f"bootstrap ({n_boot} resamples of the phases) of |rho_sg10| - |rho_mg10|.", "",
              "| Delta tau_p bin | long slips | abs rho mg10 | abs rho sg10 | difference "
              "(95 % interval) | reading |", "|---|---|---|---|---|---|"]
    for c in sg:
        if c["holds"] is None:
            lines.append(f"| [{c['lo']:g}, {c['hi']:g}) | {c['n']} | - | - | - | too few |")
            continue
        lines.append(f"| [{c['lo']:g}, {c['hi']:g}) | {c['n']} | {c['rho_mg10']:.2f} | "
                     f"{c['rho_sg10']:.2f} | {c['diff']:+.3f} ({c['interval'][0]:+.3f}, "
                     f"{c['interval'][1]:+.3f}) | {c['reading']} |")
    lines += ["", f"Verdict: {doc['sg_verdict']}."]
    (Path(run) / "long_phases.md").write_text("\n".join(lines) + "\n")
    (Path(run) / "long_phases.json").write_text(json.dumps(doc, indent=1, default=float))
    return doc


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("run", type=Path, help="a run folder analysed by `fricstab shear analyze`")
    ap.add_argument("--n-boot", type=int, default=2000)
    a = ap.parse_args(argv)
    if not (a.run / "analysis.npz").exists():
        ap.error(f"{a.run / 'analysis.npz'} not found: run `fricstab shear analyze --out "
                 f"{a.run}` first")
    doc = report(a.run, a.n_boot)
    print(f"Fig. 11: {doc['fig11_verdict']}\nsg vs mg: {doc['sg_verdict']}\n"
          f"wrote {a.run / 'long_phases.md'}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
