"""Where float64 central differences cannot reach 1e-6, and why.

Runs the per-case proof of :mod:`fricstab.laws.verify` for every law over the same
sampled configurations as ``fricstab verify`` and tabulates, by regime, the
largest float64 central-difference error at the best step next to the floor
predicted by :func:`fricstab.laws.verify.central_error_model`, and the 50-digit
and complex-step errors of the same cases.  Writes ``central_floor.md``.

    python validation/central_floor.py [--cases 2000] [--seed 20261121]
"""

import argparse
import sys
from collections import defaultdict
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))

import numpy as np  # noqa: E402

from fricstab.laws import LAW_NAMES, get_law  # noqa: E402
from fricstab.laws.verify import case_inputs, sample_cases, verify_case  # noqa: E402


def regime(law, case):
    """A label for the configuration: overlap decade and Coulomb kinks."""
    d = case.delta_over_R
    size = "delta/R <= 1e-9" if d <= 1e-9 else ("1e-9 < delta/R <= 1e-5" if d <= 1e-5 else "delta/R > 1e-5")
    if not law.coulomb:
        return size
    if case.t_ratio == 0.0:
        kink = "t = 0"
    elif case.t_ratio == 1.0:
        kink = "|t| = t*"
    else:
        kink = "0 < |t| < t*"
    tstar = "t* < delta" if case.mu / case.kt_over_kn < 1 else "t* >= delta"
    return f"{size}, {kink}, {tstar}"


def floor_tables(n_cases=2000, seed=20261121):
    """Per law, per regime: [cases, largest float64 central error at the best step,
    largest predicted floor, largest ratio measured/floor, largest complex-step error,
    largest 50-digit error] over the cases of ``fricstab verify --cases N --seed S``."""
    cases = sample_cases(n_cases, seed)
    rng = np.random.default_rng([seed, 1])
    out = {}
    for name in LAW_NAMES:
        law = get_law(name)
        rows = defaultdict(lambda: [0, 0.0, 0.0, 0.0, 0.0, 0.0])
        for case in cases:
            direction = rng.uniform(-1, 1, len(law.coords))
            res = verify_case(law, case_inputs(law, case), direction)
            r = rows[regime(law, case)]
            r[0] += 1
            r[4] = max(r[4], res["complex_step"])
            if res.get("on_cap"):   # linear on its circle: a difference step would cross the
                continue            # jump; complex step only, as `fricstab verify` does
            r[1] = max(r[1], res["central"])
            r[2] = max(r[2], res["central_model"])
            r[3] = max(r[3], res["central"] / max(res["central_model"], 1e-300))
            r[5] = max(r[5], res["central_mp"])
        out[name] = {key: rows[key] for key in sorted(rows)}
    return out


def report(tables, n_cases, seed):
    """The text of ``central_floor.md`` for :func:`floor_tables`."""
    lines = [
        "# float64 central differences: what they reach, by regime",
        "",
        f"Written by `python validation/central_floor.py --cases {n_cases} --seed {seed}`.",
        "Per regime: number of cases, the largest float64 central-difference error",
        "at the best step (row-relative, see docs/reference/verification.md), the largest predicted floor",
        "(`fricstab.laws.verify.central_error_model`), the largest ratio measured/floor,",
        "and the largest errors against the exact references of the same cases",
        "(complex step, 50-digit central differences).  The bound is 1e-6; a case",
        "above it is accepted only within 10x of its predicted floor.",
        "",
    ]
    for name, rows in tables.items():
        lines += [f"## {name}", "",
                  "| regime | cases | central (float64) | predicted floor | max ratio | complex step | 50-digit |",
                  "|---|---|---|---|---|---|---|"]
        for key, (n, c, m, ratio, cs, mp) in rows.items():
            flag = " **>1e-6**" if c > 1e-6 else ""
            lines.append(f"| {key} | {n} | {c:.1e}{flag} | {m:.1e} | {ratio:.2g} | {cs:.1e} | {mp:.1e} |")
        lines.append("")
    lines += [
        "## Why",
        "",
        "* The step cannot be smaller than the last bit of the centre distance,",
        "  ulp(|d|) ~ 2e-16 R, so at delta/R ~ 1e-12 the smallest relative step is",
        "  ~2e-4 of the overlap, and ~2e-2 of t* when t* = 0.01 delta (kt/kn = 10,",
        "  mu = 0.1): truncation (h/L)^2 then exceeds 1e-6.",
        "* At t = 0 the term |t| t of the smoothed Coulomb law is C1 but not C2, and",
        "  at |t| = t* sliding starts: central differences err at first order,",
        "  h/t* (and h/delta at the circle), wherever a step can reach those points.",
        "* Where normal and tangential terms nearly cancel within a row, the error",
        "  is measured against a small row (cancellation factor kappa).",
        "",
        "The exact references (complex step, 50-digit differences) have none of",
        "these limits: the largest errors against them are in the last two columns.",
    ]
    return "\n".join(lines) + "\n"


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--cases", type=int, default=2000)
    p.add_argument("--seed", type=int, default=20261121)
    ns = p.parse_args(argv)
    tables = floor_tables(ns.cases, ns.seed)
    text = report(tables, ns.cases, ns.seed)
    (HERE / "central_floor.md").write_text(text)
    print(text, end="")
    return tables


if __name__ == "__main__":
    main()
