"""Validation tiers of the kernel proof (`fricstab verify`) and the errata.

Quick tier (CI): 150 configurations per law of the (kn, kt, [mu], t) family
(hertz, hertz_wall, charan, charan_wall, ishima, ishima_wall), 100 per form
of the capped law (lee_hurley, lee_hurley_wall).  Slow tier
(``pytest -m slow``): 2,000 per law, the acceptance run of docs/reference/verification.md.
Bounds and why:

* complex step and 50-digit central differences: 1e-12 wherever the row is
  well conditioned; elsewhere within 64 eps times the cancellation factor
  (fricstab.laws.verify.exact_reference_bound): ``*_unexplained_cases == 0``;
* float64 central differences at the best step: 1e-6, except within 10x of
  the floor that the error model predicts (central_unexplained_cases == 0);
* Taylor test: slope >= 1.9 or a remainder at the rounding level of the
  block (taylor_failed_cases == 0);
* no NaN or inf anywhere;
* capped laws (fricstab.laws.verify_lee_hurley, per regime stick, slide_t,
  slide_r, slide_both): complex step and 50-digit differences within 64 eps
  of the terms each row sums (``*_above_bound == 0``), float64 central
  differences within 1e-6 wherever the column length is >= 1e7 ulp (the
  others are counted as unresolvable, covered by the exact references),
  Taylor slope >= 1.9.  Histories within 1e-6 of a cap are not sampled (a
  difference step would cross it); tests/test_lee_hurley.py checks a history
  exactly on its cap (sliding branch) and the jump between the one-sided
  limits.
"""

import re
import subprocess
import sys
from pathlib import Path

import pytest

from fricstab.laws import CAPPED_LAW_NAMES, LAW_NAMES
from fricstab.laws import verify_lee_hurley as capped
from fricstab.laws.verify import sample_cases, verify_law

HERE = Path(__file__).resolve().parent


def _check(res):
    assert res["nonfinite"] == 0
    assert res["complex_step_unexplained_cases"] == 0
    assert res["central_mp50_unexplained_cases"] == 0
    assert res["max_rel_err_complex_step_well_conditioned"] <= 1e-12
    assert res["max_rel_err_central_mp50_well_conditioned"] <= 1e-12
    assert res["central_unexplained_cases"] == 0
    assert res["max_rel_err_central_where_float64_can_resolve"] <= 1e-6
    assert res["taylor_failed_cases"] == 0


@pytest.mark.parametrize("name", LAW_NAMES)
def test_quick_tier(name):
    _check(verify_law(name, sample_cases(150, 2024), 2024))


@pytest.mark.slow
@pytest.mark.parametrize("name", LAW_NAMES)
def test_acceptance_tier(name):
    _check(verify_law(name, sample_cases(2000, 20261121), 20261121))


def _check_capped(report, cases):
    assert report["cases"] == cases
    assert set(report["regimes"]) == set(capped.REGIMES)
    for s in report["regimes"].values():
        assert s["nonfinite"] == 0
        assert s["complex_step_above_bound"] == 0 and s["central_mp50_above_bound"] == 0
        assert s["central_above_1e-6"] == 0
        assert s["taylor_slope_min"] >= 1.9
    assert capped.failures(report) == 0


@pytest.mark.parametrize("name", CAPPED_LAW_NAMES)
def test_quick_tier_capped(name):
    _check_capped(capped.verify_cases(capped.sample_cases(100, 2024, law=name), 2024, law=name),
                  100)


@pytest.mark.slow
@pytest.mark.parametrize("name", CAPPED_LAW_NAMES)
def test_acceptance_tier_capped(name):
    report = capped.verify_cases(capped.sample_cases(2000, 20261121, law=name), 20261121,
                                 law=name)
    _check_capped(report, 2000)


def test_errata_cover_every_listed_equation():
    out = subprocess.run([sys.executable, str(HERE / "errata_check.py")], check=True,
                         capture_output=True, text=True).stdout
    seen = set(re.findall(r"^(Charan|Ishima) Eq\. ([A-Z]?\d+)", out, re.M))
    charan = {("Charan", str(n)) for n in list(range(9, 36)) + list(range(45, 62))}
    ishima = {("Ishima", "36"), ("Ishima", "37")}
    ishima |= {("Ishima", f"D{n}") for n in range(8, 24)}
    ishima |= {("Ishima", f"F{n}") for n in range(1, 37)}
    assert not (charan | ishima) - seen
    # The markdown tables' first cells, with ranges ("53-55", "F19-F22") and
    # lists ("17, 18") expanded, must name every equation as well.
    cells = re.findall(r"^\|\s*\**([^|*]+?)\**\s*\|", (HERE / "errata.md").read_text(), re.M)
    listed = set()
    for cell in cells:
        for part in re.split(r",\s*", cell):
            m = re.fullmatch(r"(?:SM |main )?([A-Z]?)(\d+)(?:\s*-\s*([A-Z]?)(\d+))?", part.strip())
            if m:
                first, last = int(m.group(2)), int(m.group(4) or m.group(2))
                listed |= {f"{m.group(1)}{n}" for n in range(first, last + 1)}
    assert not {eq for _, eq in charan | ishima} - listed
