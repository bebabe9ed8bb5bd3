"""Claims of section precursors (see claims/__init__.py): issue 36, the ranked test of
whether a candidate precursor is extreme at the onset of a stress drop of quasistatic shear."""

import math

from .aqs import _aqs_study, _checkout
from .core import Claim, Result

HEADING = "Precursors of stress drops: the ranked test"
INTRO = ("`validation/precursor_study.py` (how-to: docs/howto/aqs.md, \"The ranked test\"): "
         "AQS with history of the phi = 0.90 backbone to strain 0.2 in steps of 5e-4; per drop, "
         "the normalised mid-rank of each candidate at the onset among the +-25 states around "
         "it; the mean rank against a permutation null (999 permutations, +1 corrected, exact "
         "in level) and the test's power at preceded fractions 0.5 and 0.8 by simulation (400 "
         "replicates, alpha = 0.05), beside the power of the old birth-window tests.")

RANKED_COMMAND = ("python validation/precursor_study.py --sizes 64 --seeds 4 "
                  "--prefix precursor_study_n64 --cache DIR (strain 0.2, dgamma 5e-4)")
RANKED_LAWS = {"charan": "charan mu=0.1 kt=1", "ishima": "ishima kt=1", "hertz": "hertz"}


def ranked_run():
    """The ranked test at N = 64 (4 seeds, three laws) in a fresh cache (RANKED_COMMAND)."""
    import tempfile

    from fricstab.io.files import json_clean      # NaN (no ranked drop) -> None
    doc = _aqs_study("precursor_study").run(
        ["--sizes", "64", "--seeds", "4", "--prefix", "precursor_study_n64",
         "--cache", tempfile.mkdtemp(), "--out", str(_checkout() / "validation")])
    keep = ("statistic", "null_sd", "pvalue", "drops", "power_0.5", "power_0.8")
    rows = {r["law"]: {"drops": r["drops"], "window1_power_0.8": r["window1_power_0.8"],
                       "candidates": {c: {k: t[k] for k in keep}
                                      for c, t in r["candidates"].items()}}
            for r in doc["rows"]}
    out = ("validation/precursor_study_n64" + x for x in (".md", ".json", ".png"))
    return Result(json_clean(rows), seeds=(0, 1, 2, 3), outputs=tuple(out))


def _ranked_show(v, label):
    r = v[label]
    pw = lambda x: "-" if x is None else f"{x:.2f}"     # noqa: E731 (None: constant series)
    return "; ".join(f"{c} {t['statistic']:.2f} (p {t['pvalue']:.2g}, power "
                     f"{pw(t['power_0.5'])} / {pw(t['power_0.8'])})" if t["statistic"]
                     is not None else f"{c}: no ranked drop"
                     for c, t in r["candidates"].items()) + \
        f"; {r['drops']} drops; old 1-step test power {r['window1_power_0.8']:.2f} at f = 0.8"


def _check_ranked(a, b):
    """Each mean rank within 3 combined null sd (its sampling error under the null); each
    power within 4 combined binomial errors of its 400 replicates (+ 0.05 for a drop
    count that another CPU's rounding moves); an undefined rank stays undefined."""
    worst = (0.0, "identical")
    for law, x in a.items():
        for c, t in x["candidates"].items():
            u = b.get(law, {}).get("candidates", {}).get(c)
            if u is None or (t["statistic"] is None) != (u["statistic"] is None):
                return False, f"{law} {c}: {t['statistic']} -> {u and u['statistic']}"
            if t["statistic"] is None:
                continue
            s = math.hypot(t["null_sd"], u["null_sd"]) or 1e-12
            d = abs(t["statistic"] - u["statistic"]) / s
            if d > 3:
                return False, f"{law} {c}: {t['statistic']:.3f} -> {u['statistic']:.3f}"
            for f in ("power_0.5", "power_0.8"):
                x, y = (-1.0 if p is None else p for p in (t[f], u[f]))  # None: constant
                e = 4 * math.sqrt(max(x * (1 - x) + y * (1 - y), 1e-3) / 400)
                if abs(x - y) > e + 0.05:
                    return False, f"{law} {c} {f}: {t[f]} -> {u[f]}"
            worst = max(worst, (d, f"largest move {d:.2f} null sd ({law} {c})"), key=lambda w: w[0])
    return True, worst[1]


CANDIDATES = ("n_pairs", "growth", "min_real", "pair_min_imag")


def ranked_table(v):
    """The mean onset rank, p and power at f = 0.5 per law and candidate (N = 64)."""
    lines = ["| law | drops | " + " | ".join(CANDIDATES) + " | old 1-step test, power f = 0.8 |",
             "|---|---|" + "---|" * len(CANDIDATES) + "---|"]
    for label in RANKED_LAWS.values():
        r = v[label]
        cells = []
        for c in CANDIDATES:
            t = r["candidates"][c]
            cells.append("no pair" if t["statistic"] is None else
                         f"{t['statistic']:.2f}, p {t['pvalue']:.2g}, power "
                         + ("-" if t["power_0.5"] is None else f"{t['power_0.5']:.2f}"))
        lines.append(f"| {label} | {r['drops']} | " + " | ".join(cells)
                     + f" | {r['window1_power_0.8']:.2f} |")
    return "\n\n" + "\n".join(lines) + "\n\n"


def _p(v, label, c):
    return v[label]["candidates"][c]["pvalue"]


def ranked_sentence(v):
    """The answer per law, computed at alpha = 0.05 (the README's words)."""
    out = []
    for law, label in RANKED_LAWS.items():
        yes = [c for c in CANDIDATES if v[label]["candidates"][c]["statistic"] is not None
               and _p(v, label, c) <= 0.05]
        out.append(f"{law}: " + (", ".join(f"{c} (p {_p(v, label, c):.2g})" for c in yes)
                                 if yes else "none"))
    return "; ".join(out)


CLAIMS = [Claim(f"precursors.ranked_{law}", "precursors",
                f"{law}: ranked test at N = 64 (4 seeds): mean onset rank in a +-25-state "
                "window of n_pairs, growth, min_real (high) and pair_min_imag (low), "
                "permutation p, power at preceded fractions 0.5 / 0.8", "minutes",
                RANKED_COMMAND, ranked_run, show=lambda v, label=label: _ranked_show(v, label),
                tolerance=" ".join(_check_ranked.__doc__.split()), check=_check_ranked,
                job="precursors.ranked",
                texts={"table": ranked_table, "answer": ranked_sentence} if law == "charan"
                else {})
          for law, label in RANKED_LAWS.items()]
