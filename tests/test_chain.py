"""The chain scene of Charan et al.: equilibrium, Jacobian, export, bad input."""

from pathlib import Path

import numpy as np
import pytest

from fricstab.scenes.chain import (ChainScene, ChainState, advance_history, forces,
                            forces_and_jacobian, initial_state, mass_vector)
from fricstab.scenes.chain_io import export_state, load_scene
from fricstab.laws import ParameterError
from fricstab.protocols.quasistatic import relax_newton


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
    assert np.allclose(delta, (scene.fy / scene.kn) ** (2 / 3), rtol=1e-10, atol=0)


def test_transverse_frequency_in_paper_units(rest):
    scene, state = rest
    f, jac = forces_and_jacobian(scene, state)
    lam = np.linalg.eigvals(-jac / mass_vector(scene)[:, None])
    unit = np.sqrt(scene.mass * 2 * scene.radius / scene.kn)  # Charan's time unit
    omega = np.sqrt(lam.real.max()) * unit
    # Closed form: sqrt(1.5 kn (fy/kn)^(1/3) / m) * unit = 0.23508; paper 0.235.
    assert abs(omega - 0.235) < 1e-3


def _smallest_overlap(scene, state):
    q = state.q
    dx = q[:, 0] - np.roll(q[:, 0], -1)
    dx[-1] -= scene.period
    pair = 2 * scene.radius - np.hypot(dx, q[:, 1] - np.roll(q[:, 1], -1))
    overlaps = np.concatenate([pair, scene.radius - q[:, 1]])
    return overlaps[overlaps > 0].min()


def _fd_jacobian(scene, state, h):
    """Central differences of the forces, history advanced by the increment rule."""
    n = scene.n
    jac = np.empty((3 * n, 3 * n))
    for k in range(3 * n):
        cols = []
        for sign in (1, -1):
            s = state.copy()
            dq = np.zeros((n, 3))
            dq.flat[k] = sign * h
            advance_history(scene, s, dq)
            s.q += dq
            cols.append(forces(scene, s).ravel())
        jac[:, k] = (cols[0] - cols[1]) / (2 * h)
    return jac


def test_exported_jacobian_matches_finite_differences(rest, tmp_path):
    scene, state = rest
    scene = scene.with_fx(0.03)
    loaded = relax_newton(scene, state).state
    f, jac = forces_and_jacobian(scene, loaded)
    export_state(scene, loaded, jac, tmp_path)
    exported = np.load(tmp_path / "jacobian.npy")
    n = scene.n
    with np.load(tmp_path / "state.npz") as npz:
        data = {k: npz[k] for k in ("q", "t", "contacts")}
    again = ChainState(data["q"].copy(), data["t"][:n].copy(), data["t"][n:, 0].copy())
    # Central differences with h = 1e-3 of the smallest overlap (here ~3e-6):
    # truncation (h/delta)^2 / 24 ~ 4e-8 of the softest contact's entries;
    # round-off eps |F| / (h max|J|) ~ 1e-16 * 0.1 / (3e-9 * 1e3) ~ 3e-12.
    fd = _fd_jacobian(scene, again, 1e-3 * _smallest_overlap(scene, again))
    err = np.abs(exported - fd).max() / np.abs(exported).max()
    assert err < 1e-6
    assert np.array_equal(data["contacts"][:n, 1], (np.arange(n) + 1) % n)
    assert np.all(data["contacts"][n:, 1] == -1)


@pytest.mark.parametrize("kwargs, name", [
    ({"n": 1}, "n"), ({"fy": 0.0}, "fy"), ({"fy": -1.0}, "fy"), ({"kn": -2.0}, "kn"),
    ({"mu": 0.0}, "mu"), ({"radius": float("nan")}, "radius"),
])
def test_bad_scene_names_the_parameter(kwargs, name):
    with pytest.raises(ParameterError, match=name):
        ChainScene(**kwargs)


def test_scene_file_unknown_key(tmp_path):
    path = tmp_path / "s.toml"
    path.write_text("[chain]\nn = 6\nfriction = 3\n")
    with pytest.raises(ParameterError, match="unknown key 'friction'"):
        load_scene(path)
    path.write_text("n = 6\nmu = 3.0\n")
    scene = load_scene(path, fy=0.2)
    assert (scene.n, scene.mu, scene.fy) == (6, 3.0, 0.2)


def test_two_disks_have_two_distinct_contacts():
    scene = ChainScene(n=2, fx=0.01)
    res = relax_newton(scene, initial_state(scene))
    assert res.converged
    f, jac = forces_and_jacobian(scene, res.state)
    assert np.abs(f).max() < 1e-12


def test_chain_cli_ramp_and_jacobian(tmp_path, capsys):
    import json

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


@pytest.mark.parametrize("argv, name", [
    (["--n", "1"], "n"), (["--fy", "0"], "fy"), (["--fy", "-2"], "fy"),
    (["--step", "0"], "--step"), (["--scene", "/nonexistent.toml"], "scene file"),
])
def test_chain_cli_bad_input_is_one_line(argv, name, tmp_path, capsys):
    from fricstab.cli import main
    assert main(["chain", "ramp", *argv, "--out", str(tmp_path), "--no-progress"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and name in err and "Traceback" not in err


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
    import json

    from fricstab.cli import main
    out = tmp_path / "dyn"
    assert main(["chain", "dynamics", "--fx", "0.03", "--duration", "500", "--seed", "2",
                 "--out", str(out), "--no-progress"]) == 0
    doc = json.loads((out / "dynamics.json").read_text())
    with np.load(out / "dynamics.npz") as npz:
        msd = npz["msd"]
    assert len(doc["first_breach_paper_time"]) == 10
    assert msd[0] == 0 and np.all(np.isfinite(msd))
    # Undamped dynamics from a perturbed equilibrium: the perturbation (1e-9
    # of the wall overlap) grows, but over 500 time units stays far below R.
    assert 0 < msd[-1] < 1e-6
    assert main(["chain", "dynamics", "--fx", "0.03", "--disk", "12", "--out", str(out),
                 "--no-progress"]) == 2


def test_chain_cli_waves(tmp_path):
    import json

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
