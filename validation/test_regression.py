"""Regression tier: numbers pinned before the engine restructuring, recomputed now.

``validation/regression/pinned.json`` was written by the code before "One
engine, composable scenes" (revision in the file); each case of
``validation/regression/cases.py`` is recomputed and compared within the
tolerance and error model of ``validation/regression/tolerances.py``.  A
number that moves beyond it is a change of physics, not of structure.
"""

import json
import sys
from pathlib import Path

import numpy as np
import pytest

HERE = Path(__file__).resolve().parent / "regression"
sys.path.insert(0, str(HERE))

from cases import CASES  # noqa: E402
from tolerances import TOLERANCES  # noqa: E402

PINNED = json.loads((HERE / "pinned.json").read_text())


@pytest.mark.parametrize("case", sorted(CASES))
def test_pinned_numbers_hold(case):
    got, want = CASES[case](), PINNED[case]
    bad = []
    for key, (kind, value, reason) in TOLERANCES[case].items():
        new, old = np.asarray(got[key], float), np.asarray(want[key], float)
        if new.shape != old.shape:
            bad.append(f"{key}: shape {new.shape} != pinned {old.shape}")
            continue
        diff = float(np.max(np.abs(new - old))) if new.size else 0.0
        if kind == "exact":
            limit = 0.0
        elif kind == "abs":
            limit = value
        elif kind == "rel":
            limit = value * float(np.max(np.abs(old)))
        else:  # abs_key: a bound the case reports itself
            limit = float(want[value])
        if not diff <= limit:
            bad.append(f"{key}: max diff {diff:.3g} > {limit:.3g} ({reason})")
    assert not bad, "; ".join(bad)
