"""``fricstab shear analyze|export`` and the Jacobian before each slip (fricstab.analysis.shear_slips)."""

import json

import numpy as np
import pytest

from fricstab.cli import main
from fricstab.cli.shear_analyze import frames_of

SMALL = ["--n", "40", "--strain", "0.01", "--dgamma", "1e-5", "--gamma0", "0.002"]


@pytest.fixture(scope="module")
def run_dir(tmp_path_factory):
    out = tmp_path_factory.mktemp("shear") / "run"
    assert main(["shear", "run", "--out", str(out), "--quiet", "--no-progress", *SMALL]) == 0
    assert main(["shear", "analyze", "--out", str(out), "--no-progress"]) == 0
    return out


def test_every_slip_gets_its_spectrum(run_dir):
    rec = json.loads((run_dir / "analysis.json").read_text())
    with np.load(run_dir / "analysis.npz") as z:
        dtau, phases = z["phase_dtau_p"], z["phases"]
        frame, pairs = z["slip_frame"], z["slip_n_complex_pairs"]
        growth, dtau_s = z["slip_max_growth_rate"], z["slip_dtau_p"]
    slips = dtau < 0
    assert slips.sum() > 0, "the small run shows no slip; lengthen SMALL"
    assert rec["slip_spectra"]["n_slips"] == slips.sum() == len(frame)
    # the stick state is the frame before the slip's first step, where tau peaked
    np.testing.assert_array_equal(frame, phases[slips, 0] - 1)
    np.testing.assert_array_equal(dtau_s, dtau[slips])
    assert (pairs >= 0).all() and np.isfinite(growth).all() and (growth >= 0).all()
    with np.load(run_dir / "analysis.npz") as z:
        sliding = z["slip_n_sliding"]
    # the frames' flags give the branches: the tangential caps the run recorded
    frames = frames_of(run_dir)
    for f, n in zip(frame, sliding):
        assert n == int(((frames.contacts(int(f))[4] & 1) != 0).sum())
    corr = rec["slip_spectra"]["correlations_with_following_dtau_p"]["all"]
    assert set(corr) == {"n_complex_pairs", "max_growth_rate", "lowest_real_eigenvalue"}
    text = (run_dir / "analysis.md").read_text()
    assert "Fig. 9b" in text and "Jacobian before each slip" in text
    for png in ("analysis_stress_strain.png", "analysis_slip_spectra.png"):
        assert (run_dir / png).stat().st_size > 1000


def test_export_loads_in_ovito(run_dir, capsys, ovito_io):
    assert main(["shear", "export", "--out", str(run_dir), "--every", "100"]) == 0
    assert main(["shear", "export", "--out", str(run_dir)]) == 2      # exists, no --force
    assert "--force" in capsys.readouterr().err
    pipe = ovito_io.import_file(str(run_dir / "frames.xyz"))
    with np.load(run_dir / "shear.npz") as z:
        n_frames = len(z["tau"])
    assert pipe.source.num_frames == len(range(0, n_frames, 100))
    data = pipe.compute(0)
    rec = json.loads((run_dir / "shear.json").read_text())
    assert data.particles.count == rec["derived"]["n_particles"]


def test_analyze_without_a_run_is_bad_input(tmp_path, capsys):
    assert main(["shear", "analyze", "--out", str(tmp_path)]) == 2
    err = capsys.readouterr().err
    assert "shear.json" in err and err.strip().count("\n") == 0


@pytest.mark.parametrize("law", ["hertz", "charan", "ishima"])
def test_analyze_with_the_law_of_the_run(tmp_path, law):
    """A run with another law analyses with that law: its dof per disk in the spectra."""
    out = tmp_path / law
    small = ["--n", "40", "--strain", "0.003", "--dgamma", "1e-5", "--gamma0", "0.001"]
    assert main(["shear", "run", "--out", str(out), "--quiet", "--no-progress", "--law", law,
                 *small]) == 0
    assert main(["shear", "analyze", "--out", str(out), "--no-progress"]) == 0
    rec = json.loads((out / "analysis.json").read_text())
    frames = frames_of(out)
    assert frames.meta["law"] == law
    assert frames.contact_hist.shape[1] == (0 if law == "hertz" else 2)
    sp = rec["slip_spectra"]
    assert sp["n_slips"] == rec["summary"]["n_slip"] > 0
    with np.load(out / "analysis.npz") as z:
        assert np.all(z["slip_n_rolling"] == 0)        # only lee_hurley resists rolling
        if law != "charan":
            assert np.all(z["slip_n_sliding"] == 0)    # no Coulomb cap
