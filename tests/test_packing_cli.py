"""``fricstab packing make|rigidity|dos|jacobian`` end to end, on one small packing, any law."""

import dataclasses
import json

import numpy as np
import pytest
import scipy.sparse as sps
import scipy.sparse.linalg as spla

from fricstab.cli import main

N, PHI = 32, 0.88
PNG = b"\x89PNG\r\n\x1a\n"


def _ok(argv, capsys):
    rc = main(argv + ["--no-progress"])
    captured = capsys.readouterr()
    assert rc == 0, captured.err
    return captured


@pytest.fixture(scope="module")
def made(tmp_path_factory):
    out = tmp_path_factory.mktemp("packing")
    assert main(["packing", "make", "--n", str(N), "--phi", str(PHI), "--seed", "0",
                 "--out", str(out), "--no-progress"]) == 0
    return out


@pytest.fixture(scope="module")
def rigid(made, tmp_path_factory):
    out = tmp_path_factory.mktemp("rigidity")
    assert main(["packing", "rigidity", "--packing", str(made), "--kt", "0", "1",
                 "--out", str(out), "--no-progress"]) == 0
    return out


def test_make_writes_packing_json_and_figure(made):
    from fricstab.scenes.packing import Packing
    for name in ("packing.npz", "packing.json", "packing.png"):
        assert (made / name).is_file()
    assert (made / "packing.png").read_bytes()[:8] == PNG
    doc = json.loads((made / "packing.json").read_text())
    assert doc["parameters"] == {"n": N, "phi": PHI, "seed": 0, "dphi": 1e-3, "f_tol": 1e-14,
                                 "f_tol_compress": 1e-6, "z_th": 2, "law": "ishima",
                                 "law_params": {"kn": 1.0, "kt": 1.0}, "wall_params": {}}
    assert doc["law"] == "ishima" and doc["friction"]["max_force"] < 1e-14
    assert doc["info"]["max_force"] < 1e-14
    assert doc["contacts"] > N and doc["z_th"] == 2
    assert doc["rattlers"] + doc["n_backbone"] == N
    assert 3.5 < doc["mean_contact_number_backbone"] < 6
    assert doc["command"].startswith("fricstab packing make --n 32")
    assert doc["seconds"] > 0 and doc["versions"]["numpy"] == np.__version__
    packing = Packing.load(made / "packing.npz")
    assert packing.n == N and packing.phi == PHI
    assert packing.box == pytest.approx(doc["box"])


def test_rigidity_theory_matches_step_strain(rigid):
    doc = json.loads((rigid / "rigidity.json").read_text())
    assert doc["passed"] and doc["n"] == N and doc["phi"] == PHI and doc["seed"] == 0
    assert doc["rattlers"] + doc["n_backbone"] == N and doc["box"] > 0
    assert doc["parameters"]["modes"] is True          # small backbone: mode sum on
    assert doc["command"].startswith("fricstab packing rigidity")
    assert [r["kt"] for r in doc["results"]] == [0.0, 1.0]
    for r in doc["results"]:
        assert r["g"] == pytest.approx(r["g_a"] + r["g_na_solve"])
        assert r["g_modes"] == pytest.approx(r["g"], rel=1e-8)
        assert abs(r["g_step"] - r["g"]) < 0.01 * abs(r["g"])
        assert abs(r["g_step"] - r["g"]) < 10 * r["g_step_error"] + 1e-12
        rel = r["relative_differences"]
        assert rel["solve_vs_step"] < 0.01 and rel["modes_vs_step"] < 0.01
        assert r["seconds"]["step_strain"] > 0 and r["checks"]["max_force"] < 1e-13
    assert (rigid / "rigidity.png").read_bytes()[:8] == PNG


@pytest.mark.parametrize("folder, ndof", [("kt_0", 2), ("kt_1", 3)])
def test_saved_jacobian_reproduces_g_na(rigid, folder, ndof):
    """The recipe of g.json, with scipy alone."""
    d = rigid / folder
    meta = json.loads((d / "g.json").read_text())
    assert meta["ndof"] == ndof and len(meta["recipe"]) == 3
    jac = sps.load_npz(d / "jacobian_tilde.npz")
    xi, theta, u_saved = (np.load(d / f"{name}.npy") for name in ("xi", "theta", "u"))
    nonaffine = np.load(d / "nonaffine_step.npy")
    n = meta["n"]
    assert jac.shape == (n * ndof, n * ndof) and xi.shape == theta.shape == (n * ndof,)
    assert nonaffine.shape == (n, ndof)
    c = np.zeros((n * ndof, 2))
    c[0::ndof, 0] = c[1::ndof, 1] = 1 / np.sqrt(n)
    a = sps.bmat([[jac, sps.csr_matrix(c)], [sps.csr_matrix(c.T), None]], format="csc")
    u = spla.spsolve(a, np.concatenate([xi, np.zeros(2)]))[:-2]
    g_na = -theta @ u / meta["box"] ** 2
    assert g_na == pytest.approx(meta["g_na_solve"], rel=1e-9)
    assert np.allclose(u, u_saved, rtol=0, atol=1e-9 * np.abs(u).max())
    # step strain's nonaffine rates follow the theory's (Ishima Fig. 3c)
    assert np.abs(nonaffine.ravel() - u).max() < 1e-2 * np.abs(u).max()


def test_rigidity_from_scene_makes_and_saves_the_packing(made, tmp_path, capsys):
    scene = tmp_path / "scene.toml"
    scene.write_text(f"n = 16\nseed = 0\n[packing]\nphi = {PHI}\nkt = 1.0\ndgamma = 1e-6\n")
    out = tmp_path / "r"
    rc = main(["packing", "rigidity", "--scene", str(scene), "--n", str(N), "--no-modes",
               "--out", str(out), "--no-progress"])
    assert rc in (0, 3), capsys.readouterr().err
    doc = json.loads((out / "rigidity.json").read_text())
    assert doc["n"] == N                                  # the command line wins
    assert doc["make"]["phi"] == PHI and doc["parameters"]["kt"] == [1.0]
    assert doc["parameters"]["modes"] is False and doc["results"][0]["g_modes"] is None
    # the same parameters as the fixture: the same packing, bit for bit
    with np.load(out / "packing.npz") as a, np.load(made / "packing.npz") as b:
        assert np.array_equal(a["pos"], b["pos"])
    assert rc == 0


def test_dos_files_and_normalization(made, tmp_path, capsys):
    out = tmp_path / "dos"
    _ok(["packing", "dos", "--packing", str(made / "packing.npz"), "--kt", "0", "1e-4", "1",
         "--bins", "30", "--out", str(out)], capsys)
    doc = json.loads((out / "dos.json").read_text())
    assert (out / "dos.png").read_bytes()[:8] == PNG
    nb = doc["n_backbone"]
    with np.load(out / "dos.npz") as z:
        edges = z["edges"]
        assert len(edges) == 31 and list(z["kt"]) == [0.0, 1e-4, 1.0]
        for i, r in enumerate(doc["results"]):
            k = r["ndof"]
            assert k == (2 if r["kt"] == 0 else 3)
            assert r["modes"] == k * nb - 2 == len(z[f"eigenvalues_{i}"])
            assert r["negative_eigenvalues"] == 0 and r["route"] == "symmetric"
            assert all(abs(v) < 1e-10 for v in r["dropped_translations"])
            psi_t, psi_r, p = z[f"psi_t_{i}"], z[f"psi_r_{i}"], z[f"p_{i}"]
            assert np.allclose(psi_t + psi_r, 1) and np.all((p > 0) & (p <= 1 + 1e-12))
            counted = z[f"dos_{i}"] * 3 * N * np.diff(edges)
            assert counted.sum() == pytest.approx(r["modes"] - r["modes_outside_bins"])
            assert r["modes_outside_bins"] == 0
    kt0, low, high = doc["results"]
    assert kt0["rotational_peak"] is None                 # no rotations without friction
    # rotation-dominated modes sit near sqrt(kt) times a stiffness scale
    assert low["rotational_peak"] < 0.1 < high["rotational_peak"]
    assert low["rotation_dominated_modes"] > 0


def test_force_is_needed_to_overwrite(made, tmp_path, capsys):
    out = tmp_path / "f"
    argv = ["packing", "dos", "--packing", str(made), "--kt", "1", "--bins", "5",
            "--out", str(out)]
    _ok(argv, capsys)
    before = (out / "dos.json").read_text()
    assert main(argv + ["--no-progress"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "--force" in err and "dos.json" in err
    assert (out / "dos.json").read_text() == before
    _ok(argv + ["--force"], capsys)
    # other results in the same directory do not block a different command
    _ok(["packing", "rigidity", "--packing", str(made), "--kt", "1", "--out", str(out)], capsys)


def _scene(tmp_path, text):
    path = tmp_path / "s.toml"
    path.write_text(text)
    return ["--scene", str(path)]


@pytest.mark.parametrize("cmd, extra, name", [
    ("make", ["--phi", "0.97"], "--phi"),
    ("make", ["--phi", "0"], "--phi"),
    ("make", ["--n", "2"], "--n"),
    ("make", ["--n", "33"], "--n"),
    ("make", ["--seed", "-1"], "--seed"),
    ("make", ["--dphi", "0"], "--dphi"),
    ("rigidity", ["--kt", "-1"], "--kt"),
    ("rigidity", ["--kt", "nan"], "--kt"),
    ("dos", ["--kt", "1", "-1"], "--kt"),
    ("rigidity", ["--dgamma", "0.5"], "--dgamma"),
    ("dos", ["--bins", "0"], "--bins"),
    ("dos", ["--route", "fast"], "--route"),
    ("dos", ["--z-th", "-1"], "--z-th"),
    ("rigidity", "scene:friction = 1\n", "'friction'"),
    ("make", "scene:[packing]\nphi = 'high'\n", "'phi'"),
    ("make", "scene:n = 32.0\n", "'n'"),
    ("dos", "scene:kt = [1, -2]\n", "'kt'"),
    ("rigidity", "scene:route = 3\n", "'route'"),
    ("make", "scene:n = \n", "--scene"),
    ("rigidity", ["--packing", "MISSING"], "--packing"),
    ("dos", ["--packing", "MADE", "--n", "64"], "--packing"),
    ("make", ["--scene", "MISSING.toml"], "--scene"),
    ("make", ["--law", "coulomb"], "--law"),
    ("jacobian", ["--law", "coulomb"], "--law"),
    ("jacobian", ["--param", "kt=-1"], "--param kt"),
    ("jacobian", ["--param", "mu=0.5"], "--param mu"),
    ("jacobian", ["--law", "lee_hurley", "--param", "nu=0.5"], "--param nu"),
    ("jacobian", ["--param", "kt"], "KEY=VALUE"),
    ("jacobian", ["--packing", "MISSING"], "--packing"),
    ("rigidity", ["--law", "hertz", "--kt", "1"], "has no kt"),
    ("dos", ["--kt", "1", "--param", "kt=2"], "--kt"),
    ("dos", "scene:law = 'lee_hurley'\nkt = 1\n", "kt"),
])
def test_bad_input_is_one_line_naming_the_parameter(cmd, extra, name, made, tmp_path, capsys):
    if isinstance(extra, str):
        extra = _scene(tmp_path, extra.removeprefix("scene:"))
    extra = [str(tmp_path / e) if e.startswith("MISSING") else str(made) if e == "MADE" else e
             for e in extra]
    out = tmp_path / "out"
    assert main(["packing", cmd, *extra, "--out", str(out), "--no-progress"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "Traceback" not in err
    assert err.startswith("fricstab: error:") and name in err
    assert not out.exists()                      # nothing is made for bad input


@pytest.mark.parametrize("law, ndof", [("hertz", 2), ("ishima", 3), ("charan", 3),
                                       ("lee_hurley", 3), ("ishima_fi", 3)])
def test_jacobian_of_every_law(made, tmp_path, capsys, law, ndof):
    """`packing jacobian --law NAME`: the common export, friction switched on and balanced.

    Checks from the files alone: the translations are zero modes of K (each row
    sums O(z) terms of size max|K|: 32 eps relative) and the recorded residual
    is below the force threshold.
    """
    from fricstab.io.jacobian_export import read_state
    out = tmp_path / law
    _ok(["packing", "jacobian", "--packing", str(made), "--law", law, "--out", str(out)], capsys)
    for name in ("state.npz", "jacobian.npz", "dofs.json", "mass.npy", "jacobian.json"):
        assert (out / name).is_file()
    k = sps.load_npz(out / "jacobian.npz")
    dofs = json.loads((out / "dofs.json").read_text())
    st = read_state(out / "state.npz")
    n = len(st["radius"])
    assert st["law"] == law and dofs["dof_per_particle"] == ndof and k.shape == (n * ndof,) * 2
    assert np.load(out / "mass.npy").shape == (n * ndof,) and len(st["keep"]) == n
    e = np.zeros((n * ndof, 2))
    e[0::ndof, 0] = e[1::ndof, 1] = 1.0
    assert np.abs(k @ e).max() <= 32 * np.finfo(float).eps * abs(k).max()
    assert dofs["max_abs_force_on_free_dof"] < 1e-14 and not st["history"].any()
    doc = json.loads((out / "jacobian.json").read_text())
    assert doc["law"] == law and doc["friction"]["relaxed"] == (law == "lee_hurley")


def test_law_options_and_kt_scan(made, tmp_path, capsys):
    """--param kt replaces the default scan; --kt 0 is the frictionless hertz; one run of a
    law without kt; the folders are named after the runs."""
    out = tmp_path / "runs"
    _ok(["packing", "dos", "--packing", str(made), "--law", "charan", "--param", "kt=0.5",
         "--param", "mu=2", "--bins", "5", "--out", str(out)], capsys)
    doc = json.loads((out / "dos.json").read_text())
    assert [r["kt"] for r in doc["results"]] == [0.5]
    assert doc["results"][0]["law_params"] == {"kn": 1.0, "kt": 0.5, "mu": 2.0}
    _ok(["packing", "rigidity", "--packing", str(made), "--law", "lee_hurley", "--no-modes",
         "--out", str(out)], capsys)
    doc = json.loads((out / "rigidity.json").read_text())
    (r,) = doc["results"]
    assert r["folder"] == "lee_hurley" and r["kt"] is None and r["ndof"] == 3
    assert r["relative_differences"]["solve_vs_step"] < 1e-4
    assert (out / "lee_hurley" / "g.json").is_file()
    dry = _ok(["packing", "rigidity", "--packing", str(made), "--kt", "0", "1", "--dry-run",
               "--out", str(tmp_path / "dry")], capsys).out
    runs = json.loads(dry)["runs"]
    assert [(r["law"], r["ndof"]) for r in runs] == [("hertz", 2), ("ishima", 3)]
    assert not (tmp_path / "dry").exists()


def test_scene_errors_say_what_is_allowed(tmp_path, capsys):
    argv = ["packing", "make", *_scene(tmp_path, "phi = 'high'\n"), "--out", str(tmp_path / "o")]
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert "'high'" in err and "[0.6, 0.95]" in err
    argv = ["packing", "make", *_scene(tmp_path, "[packing]\nfriction = 1\n"),
            "--out", str(tmp_path / "o")]
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert "friction" in err and "known keys: n, phi, seed" in err


def test_disagreement_exits_3_after_writing(made, tmp_path, capsys, monkeypatch):
    from fricstab.protocols import stepstrain
    real = stepstrain.step_strain

    def off(*args, **kwargs):
        res = real(*args, **kwargs)
        return dataclasses.replace(res, g=res.g * 1.05)

    monkeypatch.setattr(stepstrain, "step_strain", off)
    out = tmp_path / "bad"
    rc = main(["packing", "rigidity", "--packing", str(made), "--kt", "1", "--no-modes",
               "--out", str(out), "--no-progress"])
    err = capsys.readouterr().err
    assert rc == 3 and err.count("\n") == 1 and "kt = 1" in err
    doc = json.loads((out / "rigidity.json").read_text())
    assert doc["passed"] is False
    assert doc["results"][0]["relative_differences"]["solve_vs_step"] == pytest.approx(0.05,
                                                                                      rel=1e-3)
    assert (out / "kt_1" / "g.json").is_file()


def test_convergence_failure_exits_4(made, tmp_path, capsys, monkeypatch):
    from fricstab.protocols import stepstrain

    def fail(*args, **kwargs):
        raise stepstrain.ConvergenceError("Newton relaxation did not reach max|F| < 1e-14\n"
                                          "in 50 iterations")

    monkeypatch.setattr(stepstrain, "step_strain", fail)
    rc = main(["packing", "rigidity", "--packing", str(made), "--kt", "1",
               "--out", str(tmp_path / "c"), "--no-progress"])
    err = capsys.readouterr().err
    assert rc == 4 and err.count("\n") == 1 and err.startswith("fricstab: error:")
