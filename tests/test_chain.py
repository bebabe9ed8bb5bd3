"""The chain scene of Charan et al. on the engine: equilibrium, laws, export, bad input."""

import json
from pathlib import Path

import numpy as np
import pytest

from fricstab.laws import PAIR_LAW_NAMES, ParameterError
from fricstab.protocols.ramp import ramped_equilibrium, relax_newton
from fricstab.scenes.chain import (LEE_HURLEY_E, ChainScene, chain_system, forces_and_jacobian,
                                   initial_state, legacy_order, mass_vector, pair_history,
                                   rest_overlap, time_unit, wall_history)
from fricstab.scenes.chain_io import load_scene

from tests.system_proof import central_jacobian


@pytest.fixture(scope="module")
def rest():
    scene = ChainScene()
    res = relax_newton(scene, initial_state(scene))
    assert res.converged and res.residual < 1e-12
    return scene, res.state


def test_wall_overlap_is_hertz(rest):
    scene, state = rest
    # Newton converged to max|F| < 1e-12 against F_y = 0.1 and a wall
    # stiffness 1.5 kn delta^{1/2} ~ 110: delta is exact to ~1e-14 / delta.
    delta = scene.radius - state.q[:, 1]
    assert np.allclose(delta, (scene.fy / 2000.0) ** (2 / 3), rtol=1e-10, atol=0)


@pytest.mark.parametrize("law", PAIR_LAW_NAMES)
def test_every_law_rests_at_the_papers_height(law):
    """Every law's defaults give the rest overlap of Hertz with kn = 2000 under F_y = 0.1.

    Hertz laws: by construction; lee_hurley: E* = 215.9759... solves the
    cylinder law at that overlap (brentq to 4 eps relative); Newton to
    max|F| < 1e-12 against a wall stiffness >= 80 leaves 1e-14 in y.
    """
    scene = ChainScene(law=law)
    hertz = (0.1 / 2000.0) ** (2 / 3)
    assert abs(rest_overlap(scene) / hertz - 1) < 1e-12
    res = relax_newton(scene, initial_state(scene))
    assert res.converged
    delta = scene.radius - res.state.q[:, 1]
    assert np.allclose(delta, hertz, rtol=1e-9, atol=0)
    # Charan's time unit uses the reference stiffness: kn = 2000 for every law.
    assert abs(time_unit(scene) / np.sqrt(1.0 / 2000.0) - 1) < 1e-12


def test_transverse_frequency_in_paper_units(rest):
    scene, state = rest
    f, jac = forces_and_jacobian(scene, state)
    lam = np.linalg.eigvals(-jac / mass_vector(scene)[:, None])
    omega = np.sqrt(lam.real.max()) * time_unit(scene)
    # Closed form: sqrt(1.5 kn (fy/kn)^(1/3) / m) * unit = 0.23508; paper 0.235.
    assert abs(omega - 0.235) < 1e-3


def test_ring_is_static_pairs_with_the_wrap_canonicalized():
    scene = ChainScene(n=4)
    c = initial_state(scene).contacts
    pairs = {(int(i), int(j), int(m)) for i, j, m in zip(c.i, c.j, c.m) if j >= 0}
    assert pairs == {(0, 1, 0), (1, 2, 0), (2, 3, 0), (0, 3, -1)}
    assert sorted(c.i[c.j < 0]) == [0, 1, 2, 3]
    rows, sign = legacy_order(initial_state(scene))
    assert sorted(rows) == list(range(8)) and sign[3] == -1 and sign.sum() == 6


def test_two_disks_have_two_distinct_contacts():
    scene = ChainScene(n=2, fx=0.01)
    state = ramped_equilibrium(scene, 0.01, 5e-3)
    f, jac = forces_and_jacobian(scene, state)
    assert np.abs(f).max() < 1e-12
    assert (state.contacts.j >= 0).sum() == 2


def test_pair_history_keeps_the_pre_engine_orientation():
    """Ring pair (N-1, 0): displacement of N-1 relative to 0, the negative of the engine's.

    Moving disk 0 by dx along the tangent of the wrapping pair changes the
    engine's (0, N-1) history by +A dq and the legacy one by -A dq (exact:
    a sum of one increment).
    """
    scene = ChainScene(n=3, fx=-0.01)   # disk 0 pushed back: the wrapping pair closes
    state = ramped_equilibrium(scene, -0.01, 5e-3)
    before = pair_history(scene, state)[2].copy()
    dq = np.zeros((3, 3))
    dq[0, 1] = 1e-9                     # normal is along x: y is tangential
    chain_system(scene).advance_history(state, dq)
    after = pair_history(scene, state)[2]
    assert after[1] - before[1] == pytest.approx(-1e-9, rel=1e-6)


def _smallest_overlap(scene, state):
    q, c = state.q, state.contacts
    pair = c.j >= 0
    jj = np.where(pair, c.j, 0)
    dx = q[c.i, 0] - q[jj, 0] - c.m * scene.period
    gap = np.where(pair, np.hypot(dx, q[c.i, 1] - q[jj, 1]) - 2 * scene.radius,
                   q[c.i, 1] - scene.radius)
    return (-gap[gap < 0]).min()


def test_exported_files_and_legacy_keys(rest, tmp_path):
    """Common files through write_state_jacobian, plus jacobian.npy and q, t.

    The exported dense Jacobian equals the engine's assembly of the reloaded
    state exactly, and central differences of the forces with the history
    advanced by the increment rule within 1e-6 (h = 1e-3 of the smallest
    overlap: truncation (h/delta)^2/24 ~ 4e-8; round-off eps |F|/(h max|K|)
    ~ 3e-12).
    """
    from fricstab.io.jacobian_export import read_state
    from fricstab.scenes.chain_io import export_state
    scene, state = rest
    scene = scene.with_fx(0.03)
    loaded = relax_newton(scene, state).state
    export_state(scene, loaded, tmp_path)
    dense = np.load(tmp_path / "jacobian.npy")
    d = read_state(tmp_path / "state.npz")
    assert d["law"] == "charan" and d["q"].shape == (10, 3) and d["t"].shape == (20, 2)
    np.testing.assert_array_equal(d["q"][:, :2], loaded.q[:, :2])
    np.testing.assert_array_equal(d["t"][:10], pair_history(scene, loaded))
    np.testing.assert_array_equal(d["t"][10:, 0], wall_history(scene, loaded)[:, 0])
    again = chain_system(scene).state(d["pos"], d["theta"])
    rows = np.searchsorted(again.keys, loaded.keys)
    again.contacts.hist[rows] = d["history"]
    np.testing.assert_array_equal(forces_and_jacobian(scene, again)[1], dense)
    fd = central_jacobian(chain_system(scene), again, 1e-3 * _smallest_overlap(scene, again))
    assert np.abs(dense - fd).max() / np.abs(dense).max() < 1e-6
    doc = json.loads((tmp_path / "dofs.json").read_text())
    assert doc["law"] == "charan" and doc["n_dof"] == 30 and "legacy" in doc


@pytest.mark.parametrize("kwargs, name", [
    ({"n": 1}, "n"), ({"fy": 0.0}, "fy"), ({"fy": -1.0}, "fy"),
    ({"params": {"kn": -2.0}}, "kn"), ({"params": {"mu": 0.0}}, "mu"),
    ({"radius": float("nan")}, "radius"), ({"law": "foam"}, "law"),
    ({"law": "ishima", "params": {"mu": 1.0}}, "mu"), ({"law": "hertz", "fx": 0.01}, "frictionless"),
    ({"law": "lee_hurley", "fy": 1e3}, "F_y"),
])
def test_bad_scene_names_the_parameter(kwargs, name):
    with pytest.raises(ParameterError, match=name):
        ChainScene(**kwargs)


def test_scene_file_unknown_key_and_laws(tmp_path):
    path = tmp_path / "s.toml"
    path.write_text("[chain]\nn = 6\nfriction = 3\n")
    with pytest.raises(ParameterError, match="unknown key 'friction'"):
        load_scene(path)
    path.write_text("n = 6\nmu = 3.0\n")
    scene = load_scene(path, fy=0.2)
    assert (scene.n, scene.params["mu"], scene.fy) == (6, 3.0, 0.2)
    assert scene.params["kt"] == 2 * 2000.0 / 7
    path.write_text('law = "lee_hurley"\nmus = 2.0\n')
    scene = load_scene(path, radius=0.25)
    assert scene.params == {"E": LEE_HURLEY_E, "nu": 0.2, "mus": 2.0, "mur": 0.0}
    assert scene.wall_params == {"Rw": 0.25}
    path.write_text('law = "ishima"\nmu = 3.0\n')
    with pytest.raises(ParameterError, match="mu is not a parameter of law ishima"):
        load_scene(path)


def test_chain_cli_ramp_and_jacobian(tmp_path):
    from fricstab.cli import main
    out = tmp_path / "ramp"
    assert main(["chain", "ramp", "--fx-max", "0.02", "--step", "2e-3", "--out", str(out),
                 "--no-progress"]) == 0
    doc = json.loads((out / "ramp.json").read_text())
    with np.load(out / "ramp.npz") as data:
        assert data["eigenvalues"].shape == (11, 30) and doc["events"]
    assert all(e["fx_hi"] - e["fx_lo"] <= 1e-6 for e in doc["events"] if e["located"])
    assert (out / "ramp.png").stat().st_size > 10000
    assert not list(out.glob(".*.tmp"))
    jout = tmp_path / "jac"
    assert main(["chain", "jacobian", "--fx", "0.01", "--out", str(jout)]) == 0
    assert np.load(jout / "jacobian.npy").shape == (30, 30)


@pytest.mark.parametrize("law, dof", [("hertz", 2), ("charan", 3), ("ishima", 3),
                                      ("lee_hurley", 3)])
def test_chain_cli_jacobian_every_law(law, dof, tmp_path):
    """``fricstab chain jacobian --law NAME --out DIR`` with the law's defaults."""
    import scipy.sparse as sps

    from fricstab.cli import main
    from fricstab.io.jacobian_export import FILES
    out = tmp_path / law
    assert main(["chain", "jacobian", "--law", law, "--n", "4", "--out", str(out),
                 "--quiet"]) == 0
    for name in (*FILES, "jacobian.npy", "jacobian.json"):
        assert (out / name).is_file(), name
    dense = np.load(out / "jacobian.npy")
    assert dense.shape == (4 * dof, 4 * dof)
    np.testing.assert_array_equal(sps.load_npz(out / "jacobian.npz").toarray(), dense)
    with np.load(out / "state.npz") as z:
        assert str(z["law"]) == law and z["q"].shape == (4, 3) and z["t"].shape == (8, 2)


@pytest.mark.parametrize("argv, name", [
    (["--n", "1"], "n"), (["--fy", "0"], "fy"), (["--fy", "-2"], "fy"),
    (["--step", "0"], "--step"), (["--scene", "/nonexistent.toml"], "scene file"),
    (["--law", "foam"], "--law"), (["--law", "ishima", "--param", "mu=3"], "mu"),
    (["--param", "kn=-1"], "kn"), (["--param", "E=1"], "E"), (["--param", "kn"], "KEY=VALUE"),
    (["--law", "hertz"], "frictionless"),
])
@pytest.mark.parametrize("command", ["ramp", "jacobian"])
def test_chain_cli_bad_input_is_one_line(command, argv, name, tmp_path, capsys):
    from fricstab.cli import main
    out = tmp_path / "o"
    if command == "jacobian" and name == "frictionless":
        argv = argv + ["--fx", "0.01"]
    assert main(["chain", command, *argv, "--out", str(out), "--no-progress"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("fricstab: error:") and err.count("\n") == 1
    assert name in err and "Traceback" not in err
    assert not out.exists()


def test_chain_cli_waves_refuses_a_law_without_a_cap(tmp_path, capsys):
    from fricstab.cli import main
    assert main(["chain", "waves", "--law", "ishima", "--out", str(tmp_path / "o")]) == 2
    assert "no Coulomb cap" in capsys.readouterr().err


def test_atomic_write_leaves_nothing_on_failure(tmp_path):
    from fricstab.io.files import atomic_write

    def broken(tmp):
        Path(tmp).write_text("half")
        raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        atomic_write(tmp_path / "result.json", broken)
    assert list(tmp_path.iterdir()) == []


def test_transverse_mode_frequency(rest):
    from fricstab.analysis.modes import transverse_mode
    scene, state = rest
    mode = transverse_mode(scene, state)
    # At F_x = 0 the y modes are uncoupled (neighbours only touch): all have
    # omega = sqrt(1.5 kn delta^{1/2} / m) = 0.235075 in paper units.
    assert mode.y_fraction == pytest.approx(1.0, abs=1e-12)
    assert abs(mode.omega - 0.235) < 1e-3
    loaded = relax_newton(scene.with_fx(0.01), state).state
    mode = transverse_mode(scene.with_fx(0.01), loaded)
    assert mode.y_fraction > 0.9 and abs(mode.omega - 0.235) < 5e-3


def test_chain_cli_dynamics(tmp_path):
    from fricstab.cli import main
    out = tmp_path / "dyn"
    assert main(["chain", "dynamics", "--fx", "0.03", "--duration", "500", "--seed", "2",
                 "--out", str(out), "--no-progress"]) == 0
    doc = json.loads((out / "dynamics.json").read_text())
    with np.load(out / "dynamics.npz") as npz:
        msd = npz["msd"]
        assert npz["wall_hist"].shape[1:] == (10, 1)
    assert len(doc["first_breach_paper_time"]) == 10
    assert msd[0] == 0 and np.all(np.isfinite(msd))
    # Undamped dynamics from a perturbed equilibrium: the perturbation (1e-9
    # of the wall overlap) grows, but over 500 time units stays far below R.
    assert 0 < msd[-1] < 1e-6
    assert main(["chain", "dynamics", "--fx", "0.03", "--disk", "12", "--out", str(out),
                 "--no-progress"]) == 2


def test_chain_cli_waves(tmp_path):
    from fricstab.cli import main
    out = tmp_path / "waves"
    assert main(["chain", "waves", "--fx", "0.09", "--realizations", "2", "--duration", "12000",
                 "--scheduler", "inline", "--out", str(out), "--no-progress"]) == 0
    doc = json.loads((out / "waves.json").read_text())
    (res,) = doc["results"]
    assert res["fx"] == 0.09 and res["growth_rate"] > 0 and np.isfinite(res["v1"])
    with np.load(out / "waves.npz") as npz:
        assert npz["tau_fx0.09"].shape == (2, 10)
    assert (out / "waves.png").stat().st_size > 10000


def test_chain_cli_unknown_toml_key_is_one_line(tmp_path, capsys):
    from fricstab.cli import main
    scene = tmp_path / "scene.toml"
    scene.write_text("[chain]\nn = 8\nfriction_coefficient = 3.0\n")
    assert main(["chain", "ramp", "--scene", str(scene), "--out", str(tmp_path / "o"),
                 "--no-progress"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "friction_coefficient" in err
    assert not (tmp_path / "o" / "ramp.json").exists()


def test_breach_is_the_cap_of_the_law_or_leaving_the_wall():
    """At the cap (to rtol), or off the wall (t* <= 0: the pre-engine |t| >= t*); never
    for a law without a cap.  Exact: the law's own projection decides."""
    from fricstab.analysis.observables import at_coulomb_limit
    scene = ChainScene(n=3)
    d = 1e-3
    tstar = 10 * 3.5 * d                       # mu kn / kt delta, kt = 2 kn / 7
    y = np.array([[0.5 - d, 0.5 - d, 0.5 + 1e-6]])
    hist = np.array([[[0.999 * tstar], [tstar], [0.0]]])
    np.testing.assert_array_equal(at_coulomb_limit(scene, y, hist), [[False, True, True]])
    assert not at_coulomb_limit(ChainScene(n=3, law="ishima"), y, hist).any()
