"""The rules of Lee & Hurley Sec. 4's statements (validation/shear_sec4.py) on tables built so
that each statement holds, fails or cannot be judged, with the Fisher-z distance checked by
hand."""

import math
import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent))

import shear_sec4 as s4  # noqa: E402
from fricstab.analysis.shear_phases import PAPER_BINS  # noqa: E402

SERIES = {"step_dtau": ("g", "g10"), "phase_all": ("mg", "mg10", "sg", "sg10"),
          "phase_long": ("mg", "mg10", "sg", "sg10"), "phase_short": ("mg", "mg10", "sg", "sg10"),
          "phase_tp": ("long", "short")}


def tables(rho=0.5, n=200, p=1e-6, **over):
    """Every cell rho, n, p; ``over``: {"table.series": {lo: rho or None}} (None: p > 0.05)."""
    out = {}
    for t, series in SERIES.items():
        out[t] = {}
        for s in series:
            cells = []
            for lo, hi in PAPER_BINS:
                r = over.get(f"{t}.{s}", {}).get(lo, rho)
                cells.append({"lo": lo, "hi": hi, "n": n, "rho": 0.1 if r is None else r,
                              "p": 0.5 if r is None else p, "significant": r is not None})
            out[t][s] = cells
    return out


def test_fisher_distance_by_hand():
    a, b = {"rho": -0.6, "n": 103}, {"rho": 0.3, "n": 53}
    want = (math.atanh(0.6) - math.atanh(0.3)) / math.sqrt(1.06 / 100 + 1.06 / 50)
    assert s4.fisher_d(a, b) == pytest.approx(want)


def test_stronger_rules():
    pairs = [(("phase_long", "sg10"), ("phase_long", "mg10"), lo) for lo in s4.SLIP_BINS]
    # equal everywhere: holds (>=) in every bin, none weaker
    for rule in ("mostly", "consistently", "not weaker"):
        assert s4.stronger(tables(), pairs, rule)[0] == "agrees"
    # sg10 far weaker in one bin of four: 'mostly' still agrees, 'consistently' and
    # 'not weaker' disagree (significantly weaker: d << -2 at n = 200)
    t = tables(**{"phase_long.sg10": {-1e-2: 0.1}})
    assert s4.stronger(t, pairs, "mostly")[0] == "agrees"
    assert s4.stronger(t, pairs, "consistently")[0] == "disagrees"
    assert s4.stronger(t, pairs, "not weaker")[0] == "disagrees"
    # weaker in three bins of four but within noise (n = 12): 'mostly' is undecided
    t = tables(n=12, **{"phase_long.sg10": {lo: 0.45 for lo in s4.SLIP_BINS[:3]}})
    v, detail = s4.stronger(t, pairs, "mostly")
    assert v == "undecided" and detail.startswith("1 of 4 hold, 0 significantly weaker")
    # a cell with p > 0.05 drops its pair; none left: not comparable
    t = tables(**{"phase_long.sg10": {lo: None for lo in s4.SLIP_BINS}})
    assert s4.stronger(t, pairs, "mostly")[0] == "not comparable"


def test_band_rules_and_small_cells():
    cells = [("phase_long", "mg10", -1e-1), ("phase_long", "sg10", -1e-1)]
    assert s4.bands(tables(rho=-0.75), cells, {"strong"}, "all")[0] == "agrees"
    assert s4.bands(tables(rho=-0.5), cells, {"strong"}, "all")[0] == "disagrees"
    # n < 10 does not enter even where p <= 0.05
    assert s4.bands(tables(rho=-0.5, n=9), cells, {"strong"}, "all")[0] == "not comparable"
    mostly = [("phase_long", "mg10", lo) for lo in s4.SLIP_BINS[1:]]
    t = tables(rho=-0.5, **{"phase_long.mg10": {-1e-4: -0.2}})
    assert s4.bands(t, mostly, {"moderate"}, "mostly")[0] == "agrees"     # 2 of 3
    t = tables(rho=-0.2, **{"phase_long.mg10": {-1e-4: -0.5}})
    assert s4.bands(t, mostly, {"moderate"}, "mostly")[0] == "disagrees"  # 1 of 3


def test_stick_tp_depends_on_mu_s():
    moderate = tables(**{"phase_tp.long": {1e-3: 0.5, 1e-2: 0.55}})
    weak = tables(**{"phase_tp.long": {1e-3: 0.2, 1e-2: None}})
    silent = tables(**{"phase_tp.long": {1e-3: None, 1e-2: None}})
    assert s4.stick_tp(moderate, 0.7)[0] == "agrees"
    assert s4.stick_tp(weak, 0.7)[0] == "disagrees"
    assert s4.stick_tp(silent, 0.5)[0] == "not comparable"
    assert s4.stick_tp(moderate, 0.1)[0] == "disagrees"
    assert s4.stick_tp(weak, 0.3)[0] == "agrees"
    assert s4.stick_tp(silent, 0.1)[0] == "agrees"


def test_judge_sweep_needs_every_mu_s():
    """'For all mu_s': one mu_s that disagrees makes the statement disagree; the table has one
    column per mu_s."""
    good = tables(rho=-0.75)
    for s in ("mg", "mg10", "sg", "sg10"):      # short phases weak: 4.5 holds
        for c in good["phase_short"][s]:
            c["rho"] = -0.3
    bad = tables(rho=-0.75)     # short phases strong: 4.5 fails
    judged = s4.judge_sweep({0.1: good, 0.7: bad})
    row = next(x for x in judged if x["id"] == "4.5")
    assert row["cells"][0.1]["verdict"] == "agrees"
    assert row["cells"][0.7]["verdict"] == "disagrees" and row["verdict"] == "disagrees"
    assert next(x for x in judged if x["id"] == "4.3")["verdict"] == "agrees"
    md = s4.markdown(judged)
    assert "| mu_s = 0.1 | mu_s = 0.7 |" in md and md.count("\n| 4.") == len(s4.STATEMENTS)


def test_sec33_short_phases_significantly_weaker():
    """3.4: short-phase cells far below the long ones (d << -2 at n = 200) agree; equal cells
    disagree (not weaker at all); weaker within noise (n = 12) is undecided."""
    import shear_sec33 as s33
    pairs = [(("phase_short", s), ("phase_long", s), lo)
             for s in s33.FOUR for lo in s33.SLIPS_33]
    low = {f"phase_short.{s}": {lo: -0.1 for lo in s33.SLIPS_33} for s in s33.FOUR}
    assert s33.significantly_weaker(tables(rho=-0.6, **low), pairs)[0] == "agrees"
    assert s33.significantly_weaker(tables(rho=-0.6), pairs)[0] == "disagrees"
    near = {f"phase_short.{s}": {lo: -0.5 for lo in s33.SLIPS_33} for s in s33.FOUR}
    assert s33.significantly_weaker(tables(rho=-0.6, n=12, **near), pairs)[0] == "undecided"
    judged = s33.judge(tables(rho=-0.6, **low))
    assert [x["id"] for x in judged] == ["3.1", "3.2", "3.3", "3.4"]
    assert judged[3]["verdict"] == "agrees" and "| 3.4 |" in s33.markdown(judged)
