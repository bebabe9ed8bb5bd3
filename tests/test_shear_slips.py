"""``fricstab shear analyze|export`` and the Jacobian before each slip (fricstab.analysis.shear_slips)."""

import json
import shutil
import sys
from pathlib import Path

import numpy as np
import pytest
import scipy.sparse.linalg

from fricstab.analysis.shear_spectrum import (SOFT_K, clamped_system, recorded_state,
                                              spectrum)
from fricstab.cli import main
from fricstab.cli.shear_analyze import frames_of
from tests.test_shear_spectrum import soft_error_bound

SMALL = ["--n", "40", "--strain", "0.01", "--dgamma", "1e-5", "--gamma0", "0.002"]


@pytest.fixture(scope="module")
def run_dir(tmp_path_factory):
    out = tmp_path_factory.mktemp("shear") / "run"
    assert main(["shear", "run", "--out", str(out), "--quiet", "--no-progress", *SMALL,
                 "--checkpoint-every", "300"]) == 0    # four chunks, for --partial
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
    assert rec["slip_spectra"]["route"] == "soft" and rec["slip_spectra"]["k"] == SOFT_K
    assert "smallest modulus" in rec["slip_spectra"]["statistics_over"]
    assert "soft route" in text and rec["parameters"]["spectra"] == "soft"
    for png in ("analysis_stress_strain.png", "analysis_slip_spectra.png"):
        assert (run_dir / png).stat().st_size > 1000


def _slip_state(run_dir, frame):
    frames = frames_of(run_dir)
    p = json.loads((run_dir / "shear.json").read_text())["parameters"]
    system = clamped_system(p["law"], p["law_params"], frames.radius, frames.mass,
                            frames.inertia, frames.kind, frames.lx)
    ij, _, _, hist, flag = frames.contacts(frame)
    return system, recorded_state(system, frames.pos[frame], frames.angle[frame], ij, hist, flag)


def test_soft_window_of_each_slip_matches_the_dense_one(run_dir):
    """Frames of a real run: the k softest before each slip (ARPACK) against dense."""
    with np.load(run_dir / "analysis.npz") as z:
        frame, soft, fell = z["slip_frame"], z["slip_softest"], z["slip_fallback"]
        pairs = z["slip_n_complex_pairs"]
    assert soft.shape == (len(frame), SOFT_K + 1) and not fell.any()
    for f, row, n_pairs in list(zip(frame, soft, pairs))[:4]:
        system, state = _slip_state(run_dir, int(f))
        dense = spectrum(system, state, SOFT_K)
        a, b = row[~np.isnan(row)], dense.softest
        assert len(a) == len(b)
        near = np.abs(a[:, None] - b[None, :]).min(axis=1)
        assert np.all(near <= soft_error_bound(system, state, a))    # its error model
        assert n_pairs <= dense.n_complex_pairs


def test_dense_route_and_the_window_on_the_command_line(run_dir, tmp_path, capsys):
    out = tmp_path / "run"
    shutil.copytree(run_dir, out)
    assert main(["shear", "analyze", "--out", str(out), "--no-progress", "--force",
                 "--spectra", "dense", "--spectra-k", "7"]) == 0
    assert "slip spectra (dense)" in capsys.readouterr().out
    rec = json.loads((out / "analysis.json").read_text())
    sp = rec["slip_spectra"]
    assert sp["route"] == "dense" and sp["k"] == 7 and sp["statistics_over"].startswith(
        "the whole spectrum")
    with np.load(out / "analysis.npz") as z, np.load(run_dir / "analysis.npz") as soft:
        assert z["slip_softest"].shape[1] == 8
        assert np.all(z["slip_n_complex_pairs"] >= soft["slip_n_complex_pairs"])
    assert main(["shear", "analyze", "--out", str(out), "--force", "--spectra-k", "0"]) == 2
    err = capsys.readouterr().err
    assert "--spectra-k" in err and err.strip().count("\n") == 0


def test_arpack_failure_is_recorded(run_dir, tmp_path, monkeypatch):
    """ARPACK fails: the dense window stands in, the record says where, never silently."""
    def no_convergence(*args, **kw):
        raise scipy.sparse.linalg.ArpackNoConvergence("No convergence (1 iterations)", [], [])
    out = tmp_path / "run"
    shutil.copytree(run_dir, out)
    monkeypatch.setattr(scipy.sparse.linalg, "eigs", no_convergence)
    assert main(["shear", "analyze", "--out", str(out), "--no-progress", "--force"]) == 0
    rec = json.loads((out / "analysis.json").read_text())
    assert rec["slip_spectra"]["fallbacks_to_dense"] == rec["slip_spectra"]["n_slips"]
    assert any("ARPACK failed" in w["message"] for w in rec["warnings"])
    with np.load(out / "analysis.npz") as z:
        assert z["slip_fallback"].all()


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


def test_partial_analysis_is_that_of_the_same_frames(run_dir, tmp_path, capsys):
    """--partial reads a run without its record (interrupted) and gives the full analysis."""
    part, dest = tmp_path / "run", tmp_path / "partial"
    shutil.copytree(run_dir / "frames", part / "frames")
    chunks = sorted((part / "frames").glob("chunk_*.npz"))
    assert len(chunks) >= 3, "the small run writes one chunk; lower its checkpoint interval"
    assert main(["shear", "analyze", "--out", str(part), "--partial", str(dest),
                 "--no-progress"]) == 0
    assert "partial: the first" in capsys.readouterr().out
    with np.load(run_dir / "analysis.npz") as a, np.load(dest / "analysis.npz") as b:
        assert set(a.files) == set(b.files)
        for name in a.files:
            np.testing.assert_array_equal(a[name], b[name], err_msg=name)
    rec = json.loads((dest / "analysis.json").read_text())
    n_frames = frames_of(run_dir).n_frames
    assert rec["parameters"]["frames"] == n_frames and not (part / "analysis.json").exists()
    chunks[1].unlink()
    for out, into, say in ((run_dir, tmp_path / "x", "is complete"), (part, part, "must differ"),
                           (part, tmp_path / "y", "gap before chunk_000002")):
        assert main(["shear", "analyze", "--out", str(out), "--partial", str(into)]) == 2
        err = capsys.readouterr().err
        assert say in err and err.strip().count("\n") == 0


def test_reuse_of_an_earlier_partial_analysis_is_bit_identical(run_dir, tmp_path, capsys):
    """--reuse: an analysis of the first two chunks, then of all with it reused, equals
    the fresh analysis of all; an analysis of other frames is refused (exit 2)."""
    first, whole = tmp_path / "first", tmp_path / "whole"
    chunks = sorted((run_dir / "frames").glob("chunk_*.npz"))
    (first / "frames").mkdir(parents=True)
    for c in chunks[:2]:
        shutil.copyfile(c, first / "frames" / c.name)
    shutil.copytree(run_dir / "frames", whole / "frames")
    assert main(["shear", "analyze", "--out", str(first), "--partial", str(tmp_path / "p1"),
                 "--no-progress"]) == 0
    assert main(["shear", "analyze", "--out", str(whole), "--partial", str(tmp_path / "p2"),
                 "--reuse", str(tmp_path / "p1"), "--no-progress"]) == 0
    with np.load(run_dir / "analysis.npz") as a, np.load(tmp_path / "p2/analysis.npz") as b:
        assert set(a.files) == set(b.files)
        for name in a.files:
            np.testing.assert_array_equal(a[name], b[name], err_msg=name)
    rec = json.loads((tmp_path / "p2/analysis.json").read_text())
    assert rec["parameters"]["reused"]["frames"] == frames_of(first, partial=True).n_frames
    capsys.readouterr()
    other = tmp_path / "other"       # the first chunks of another run
    (other / "frames").mkdir(parents=True)
    shutil.copyfile(chunks[2], other / "frames" / "chunk_000000.npz")
    assert main(["shear", "analyze", "--out", str(other), "--partial", str(tmp_path / "p3"),
                 "--no-progress", "--no-spectra"]) == 0
    capsys.readouterr()
    assert main(["shear", "analyze", "--out", str(whole), "--partial", str(tmp_path / "p4"),
                 "--reuse", str(tmp_path / "p3")]) == 2
    err = capsys.readouterr().err
    assert "--reuse" in err and "strain and tau differ" in err and not (tmp_path / "p4").exists()


def test_gamma0_steady_is_the_steady_window_of_the_runs_tau(run_dir, tmp_path, capsys):
    """--gamma0 steady analyses from steady_window's start on the run's tau from its gamma0
    (kept in the record with its test), to the bit the analysis given that start as a
    number; a misspelt word is bad input naming both forms."""
    from fricstab.analysis.stationarity import steady_window
    out = tmp_path / "run"
    shutil.copytree(run_dir, out)
    frames = frames_of(out)
    start, info = steady_window(frames.strain, frames.tau, 0.002)   # SMALL's gamma0
    capsys.readouterr()
    assert main(["shear", "analyze", "--out", str(out), "--no-progress", "--no-spectra",
                 "--force", "--gamma0", "steady"]) == 0
    said = capsys.readouterr()
    rec = json.loads((out / "analysis.json").read_text())
    assert rec["parameters"]["gamma0"] == start >= 0.002
    assert rec["parameters"]["steady"] == json.loads(json.dumps(info))
    if info["steady"]:
        assert f"steady start: strain {start:.6g}" in said.out
    else:
        assert "fricstab: warning: tau is not steady" in said.err
    with np.load(out / "analysis.npz") as z:
        steady = {k: z[k] for k in z.files}
    again = tmp_path / "again"
    shutil.copytree(run_dir, again)
    assert main(["shear", "analyze", "--out", str(again), "--no-progress", "--no-spectra",
                 "--force", "--gamma0", repr(start)]) == 0
    with np.load(again / "analysis.npz") as z:
        assert set(z.files) == set(steady)
        for k in z.files:
            np.testing.assert_array_equal(z[k], steady[k], err_msg=k)
    capsys.readouterr()
    assert main(["shear", "analyze", "--out", str(out), "--gamma0", "stedy"]) == 2
    err = capsys.readouterr().err
    assert "must be a number" in err and "'steady'" in err


def test_gamma0_steady_says_which_way_the_test_went(capsys):
    """Both branches of --gamma0 steady's message: a level series starts where the test
    accepts (on stdout), a drift to the end falls back to gamma0 with a warning on stderr."""
    from types import SimpleNamespace

    from fricstab.cli.shear_analyze import _steady
    rng = np.random.default_rng(3)
    strain = np.linspace(0.0, 0.1, 2000)
    level = SimpleNamespace(strain=strain, tau=0.2 + 0.01 * rng.normal(size=2000))
    start, info = _steady(level, 0.01)
    said = capsys.readouterr()
    assert info["steady"] and start == pytest.approx(0.01, abs=1e-4)
    assert said.out.startswith("steady start: strain") and said.err == ""
    drift = SimpleNamespace(strain=strain, tau=strain + 1e-4 * rng.normal(size=2000))
    start, info = _steady(drift, 0.01)
    said = capsys.readouterr()
    assert start == 0.01 and not info["steady"] and said.out == ""
    assert "warning: tau is not steady" in said.err and "extend the run" in said.err


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
    assert frames.n_history == (0 if law == "hertz" else 2)
    sp = rec["slip_spectra"]
    assert sp["n_slips"] == rec["summary"]["n_slip"] > 0
    with np.load(out / "analysis.npz") as z:
        assert np.all(z["slip_n_rolling"] == 0)        # only lee_hurley resists rolling
        if law != "charan":
            assert np.all(z["slip_n_sliding"] == 0)    # no Coulomb cap


def test_paper_comparison_script_reads_a_complete_and_a_partial_analysis(run_dir, tmp_path):
    """validation/shear_paper.py: one verdict row per paper statement, for both kinds."""
    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "validation"))
    import shear_paper
    part = tmp_path / "run"
    shutil.copytree(run_dir / "frames", part / "frames")
    shutil.copyfile(run_dir / "prepare.json", part / "prepare.json")
    assert main(["shear", "analyze", "--out", str(part), "--partial", str(tmp_path / "p"),
                 "--no-progress", "--no-spectra"]) == 0
    for args, word in (([str(run_dir)], "(complete)"),
                       ([str(part), "--analysis", str(tmp_path / "p")], "**partial**")):
        md = tmp_path / "out" / "paper.md"
        assert shear_paper.main([*args, "--md", str(md)]) == 0
        text = md.read_text()
        verdicts = [ln for ln in text.splitlines() if ln.startswith("| 9") or
                    ln.startswith("| 10")]
        assert len(verdicts) == len(shear_paper.STATEMENTS) and word in text
        doc = json.loads(md.with_suffix(".json").read_text())
        assert doc["complete"] == (word == "(complete)")
        # the strain windows share out the window's steps (a phase cut by an edge counts twice)
        along = doc["along_the_run"]
        assert sum(r["steps"] for r in along) == doc["summary"]["n_steps"]
        assert 0 <= sum(r["phases"]
                        for r in along) - doc["summary"]["n_phases"] <= max(len(along) - 1, 0)
        assert (tmp_path / "out" / "paper_dtau_p.png").stat().st_size > 1000
        assert "## Is the analysed window a steady state?" in text
        assert "## The paper's comparisons on Figs. 9b-10b (Sec. 3.3)" in text
        assert [x["id"] for x in doc["comparisons"]] == ["3.1", "3.2", "3.3", "3.4"]
        assert doc["steady"]["window_from"] == doc["summary"]["gamma0"]


def test_paper_script_prints_the_steady_start(run_dir, tmp_path, capsys):
    """``shear_paper.py RUN --steady-start``: the strain of steady_window on the run's tau from
    2.2 % (the small run ends before it: 2.2 % and the reason), the same from the frames of a
    run still going as from its shear.npz."""
    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "validation"))
    import shear_paper
    from fricstab.analysis.stationarity import steady_window
    with np.load(run_dir / "shear.npz") as z:
        want, _ = steady_window(z["strain"], z["tau"], 0.022)
    assert shear_paper.main([str(run_dir), "--steady-start"]) == 0
    out, err = capsys.readouterr()
    assert float(out) == pytest.approx(want, abs=1e-6) and err
    part = tmp_path / "run"
    shutil.copytree(run_dir / "frames", part / "frames")
    assert shear_paper.steady_window(part)[0] == want


def test_paper_comparison_says_whether_its_window_is_a_steady_state():
    """tau rising to strain 0.06 and flat after it (noise 1 % of the rise): steady from
    about 0.06 (a start a little before it passes: one low block of 20 is no trend); a window from 2.2 % includes the transient, one from 0.07 does not; a ramp
    to the end is no steady state, and the page says to extend the run."""
    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "validation"))
    from shear_paper import steadiness, steadiness_text
    rng = np.random.default_rng(3)
    strain = np.linspace(0.0, 0.2, 20_000)
    tau = 0.1 + 0.2 * np.minimum(strain, 0.06) / 0.06 + 0.002 * rng.standard_normal(strain.size)
    early = steadiness(strain, tau, 0.022, 0.022)
    assert early["start"] is not None and 0.04 <= early["start"] <= 0.09
    # the window's own test fails: it trends, or its ramp reads as memory longer than a block
    assert not early["in_steady_state"]
    assert early["window_p"] < 0.05 or not early["window_independent"]
    assert "include the transient" in steadiness_text(early, "RUN")
    late = steadiness(strain, tau, 0.022, 0.09)
    assert late["in_steady_state"] and "**Steady**" in steadiness_text(late, "RUN")
    ramp = steadiness(strain, 0.1 + strain + 0.002 * rng.standard_normal(strain.size),
                      0.022, 0.022)
    assert ramp["start"] is None and not ramp["in_steady_state"]
    assert "--resume --strain" in steadiness_text(ramp, "RUN")


def test_paper_comparison_states_the_wall_time_of_a_resumed_run():
    """A run finished by a resumed process: its own share and the whole run at its rate."""
    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "validation"))
    from shear_paper import run_wall
    rec = {"derived": {"n_particles": 1000, "steps_per_frame": 500}, "frames": 101,
           "shear_seconds_this_process": 3600.0, "throughput_particle_steps_per_s": 1e4}
    # 3,600 s at 1e4 particle-steps/s: 36,000 steps of the 50,000 (72 %); all at that rate 5000 s
    text = run_wall(rec, {"seconds": 600.0})
    assert text.startswith("prepare 10 min + shear 1.00 h in the last process (its 72% of the 50,000")
    assert text.endswith("all of them at that rate 1.4 h")
    rec["shear_seconds_this_process"] = 5000.0   # the whole run in one process
    assert run_wall(rec, {"seconds": 600.0}) == "prepare 10 min + shear 1.39 h"
