"""``validation/shear_event.py`` on a tiny run: `fricstab shear run` (40 disks, 100 frames),
`fricstab shear analyze`, then the script; its three files, and one line for a bad event."""

import json
import sys
from pathlib import Path

import numpy as np
import pytest

from fricstab.analysis.shear_event import VERDICTS
from fricstab.cli import main as fricstab

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

import shear_event  # noqa: E402

TINY = ["--n", "40", "--strain", "0.01", "--dgamma", "1e-4", "--gamma0", "0.002"]


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    out = tmp_path_factory.mktemp("event") / "run"
    assert fricstab(["shear", "run", "--preset", "quick", "--out", str(out), "--quiet",
                     "--no-progress", *TINY]) == 0
    assert fricstab(["shear", "analyze", "--out", str(out), "--no-progress",
                     "--no-spectra"]) == 0
    return out


def test_the_script_writes_the_table_json_and_figure(run, capsys):
    assert shear_event.main([str(run), "--n-perm", "199"]) == 0
    doc = json.loads((run / "event.json").read_text())
    assert [s["id"] for s in doc["statements"]] == ["1", "2", "3", "4", "5a", "5b", "5d"]
    assert all(s["verdict"] in VERDICTS and s["paper"] and s["rule"] for s in doc["statements"])
    with open(run / "analysis.json") as fh:
        largest = json.load(fh)["summary"]["largest_drop_steps"]
    assert [doc["event"]["first"], doc["event"]["last"]] == largest
    text = (run / "event.md").read_text()
    assert "| # | Fig. | the paper | ours | rule | verdict |" in text
    assert text.count("\n| 5") == 3 and "In any contact points other than" in text
    assert (run / "event.png").stat().st_size > 10_000
    assert "wrote" in capsys.readouterr().out


def test_a_named_slip_and_a_bad_event(run, capsys):
    with open(run / "analysis.json") as fh:
        n_phases = json.load(fh)["summary"]["n_phases"]
    assert shear_event.main([str(run), "--event", str(n_phases), "--n-perm", "199"]) == 2
    assert "phase index in [0," in capsys.readouterr().err
    with np.load(run / "analysis.npz") as z:
        dt = z["phase_dtau_p"]
    stick, slips = int(np.flatnonzero(dt > 0)[0]), np.flatnonzero(dt < 0)
    assert shear_event.main([str(run), "--event", str(stick)]) == 2
    assert "is a stick" in capsys.readouterr().err
    other = int(slips[np.argsort(dt[slips])[-1]])          # the smallest slip
    assert shear_event.main([str(run), "--event", str(other), "--n-perm", "199"]) == 0
    new = json.loads((run / "event.json").read_text())
    assert new["event"]["event"] == other and f"--event {other}" in new["command"]
