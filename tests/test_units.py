"""One unit system per scene: a quantity has the same label and the same value in the
CLI's figure and record, the tutorial and RESULTS.md (issue: 'two unit systems for one
quantity', Im lambda 4.26 in the tutorial and 0.0021 in ramp.png)."""

import inspect
import json
import re
from pathlib import Path

import numpy as np

from fricstab.cli import main
from fricstab.figures import chain as chain_figures

ROOT = Path(__file__).resolve().parents[1]
CHAIN_DOCS = [ROOT / "docs" / "tutorials" / "charan_chain.md"]


def _labels(text):
    """The arguments of every set_xlabel / set_ylabel call in ``text``."""
    return re.findall(r"set_[xy]label\((.*?)\)\s*$", text, flags=re.M)


def test_chain_labels_come_from_one_table():
    """Every axis label of the chain's figures, in the package and in the tutorials,
    is built from ``fricstab.figures.chain.LABELS`` for F_x and the eigenvalues (a
    literal unit beside them would be a second unit system)."""
    sources = {"fricstab/figures/chain.py": inspect.getsource(chain_figures)}
    sources.update({str(p.relative_to(ROOT)): p.read_text() for p in CHAIN_DOCS})
    for name, text in sources.items():
        for arg in _labels(text):
            if re.search(r"F_x|lambda", arg):
                assert "LABELS[" in arg, f"{name}: label {arg} is typed, not LABELS"
    for doc in CHAIN_DOCS:
        text = doc.read_text()
        assert "tau^{-2}" not in text and r"\tau" not in text, doc


def test_im_lambda_has_one_value_in_the_cli_record_and_results(tmp_path):
    """The CLI's ramp.npz times its eigenvalue_unit (what ramp.png plots, in t_0^-2)
    equals the record RESULTS.md shows (the Python route times time_unit**2, what the
    tutorial plots). Error model: both are the same Newton equilibria and LAPACK
    eigenvalues, well conditioned (condition numbers 3-4): 1e-9 relative covers
    another CPU's round-off."""
    out = tmp_path / "ramp"
    assert main(["chain", "ramp", "--out", str(out), "--quiet"]) == 0
    with np.load(out / "ramp.npz") as npz:
        w = npz["eigenvalues"] * npz["eigenvalue_unit"]
        fxs = npz["fx"]
    rec = json.loads((ROOT / "validation" / "records" / "chain.ramp.json").read_text())
    for fx, want in zip((0.083, 0.087, 0.090), rec["values"]["im_lambda"]):
        k = int(np.argmin(np.abs(fxs - fx)))
        got = float(np.abs(w[k].imag).max())
        assert abs(got / want - 1) < 1e-9, (fx, got, want)
    results = (ROOT / "validation" / "RESULTS.md").read_text()
    assert f"{rec['values']['im_lambda'][0]:.2e}" in results
