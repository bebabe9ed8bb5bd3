"""``fricstab packing jacobian|rigidity|dos|aqs --state``: a written state analysed (issue 37).

A state written from our own packing (``packing jacobian``: a ``jacobian.json``
record; ``write_imported``: no record; an ``import`` record through ResultDir)
gives, via ``--state``, the numbers of the packing route; a changed file is
refused; options the state decides are refused; a fixed particle is refused by
rigidity and aqs and accepted by dos and jacobian.
"""

import json
import shutil

import numpy as np
import pytest
import scipy.sparse as sps

from fricstab.cli import main
from fricstab.engine import System
from fricstab.io import rundir
from fricstab.io.imports import load_state
from fricstab.io.imports.engine_check import write_imported
from fricstab.io.jacobian_export import system_from_state, write_state_jacobian
from fricstab.scenes.packing import Packing
from fricstab.scenes.packing_friction import backbone, frictional, material

SMALL = ["--n", "16", "--phi", "0.88", "--seed", "0"]
F_TOL = "1e-14"       # the packing route's default f_tol: both routes relax alike
# The two routes run the same arithmetic on the same arrays (asserted bit-equal below);
# 1e-10 relative leaves room for a different summation order of the contact list
# (16 x 3 dof, a few hundred terms of O(1): round-off ~1e-14) and no more.
REL = 1e-10


def _main(argv, capsys):
    rc = main(argv + ["--no-progress"])
    out = capsys.readouterr()
    return rc, out.out, out.err


def _one_line_error(rc, err, *words):
    """Exit 2, one error line (after the unchecked-state warning, where there is one)."""
    lines = err.splitlines()
    assert rc == 2 and lines[-1].startswith("fricstab: error:"), err
    assert all(line.startswith("fricstab: warning:") for line in lines[:-1]), err
    for w in words:
        assert w in lines[-1], err


def _close(a, b, rel=REL):
    a, b = np.asarray(a, complex), np.asarray(b, complex)
    assert a.shape == b.shape
    assert np.max(np.abs(a - b), initial=0.0) <= rel * np.max(np.abs(b), initial=1.0)


class _Report:
    """The part of an import report that write_imported uses (no units mapping)."""
    units = {}

    def as_dict(self):
        return {"note": "written by the test: no manifest"}


@pytest.fixture(scope="module")
def root(tmp_path_factory):
    """P: a packing; J: its backbone state (jacobian.json); U: the same, write_imported;
    I: the same with an ``import`` record written through ResultDir; X: one free disk
    added in a void (a rattler); F: disk 0 fixed."""
    from fricstab.cli.packing_make import write_jacobian
    from fricstab.io.results import ResultDir
    top = tmp_path_factory.mktemp("state")
    for argv in (["packing", "make", *SMALL, "--out", str(top / "P")],
                 ["packing", "jacobian", "--packing", str(top / "P"), "--out", str(top / "J")]):
        assert main(argv + ["--no-progress", "--quiet"]) == 0
    system, state = system_from_state(top / "J" / "state.npz")
    write_imported(top / "U", system, state, _Report())
    rd = ResultDir(top / "I", "import", fingerprint={"test": 1}).create()
    write_jacobian(rd, system, state, {})
    rd.finish({"n": system.n}, parameters={"test": 1})
    write_state_jacobian(top / "X", *_with_rattler(system, state))
    family = np.zeros(system.n, int)
    family[0] = 1
    fixed = System(system.material, system.radius, system.mass, system.inertia, family=family,
                   lx=system.lx, ly=system.ly, neighbours=False)
    st = fixed.state(*system.positions(state))
    st.contacts, st.keys = state.contacts, state.keys
    write_state_jacobian(top / "F", fixed, st)
    return top


def _with_rattler(system, state):
    """``system`` with one more free disk (radius 0.05) where it touches nothing."""
    pos, theta = system.positions(state)
    r = 0.05
    for x in np.linspace(0, system.lx, 60, endpoint=False):
        for y in np.linspace(0, system.ly, 60, endpoint=False):
            d = pos - [x, y]
            d -= np.round(d / system.lx) * system.lx
            if np.all(np.hypot(d[:, 0], d[:, 1]) > system.radius + 2 * r):
                break
        else:
            continue
        break
    m = (2 * r) ** 2
    big = System(system.material, np.append(system.radius, r), np.append(system.mass, m),
                 np.append(system.inertia, m * (2 * r) ** 2 / 8), lx=system.lx, ly=system.ly,
                 neighbours=False)
    st = big.state(np.vstack([pos, [x, y]]), np.append(theta, 0.0))
    st.contacts = state.contacts
    from fricstab.engine.contacts import contact_keys
    c = st.contacts
    st.keys = contact_keys(c.i, c.j, c.m, c.k, big.n, 0)
    return big, st


def test_the_imported_state_is_the_packing_routes_backbone_state(root):
    """The arrays of the packing route's state (backbone, friction on) are the file's, bitwise."""
    packing = Packing.load(root / "P" / "packing.npz")
    fr = frictional(backbone(packing, z_th=2), material("ishima"), f_tol=1e-14)
    for name in ("J", "U", "I"):
        system, state = load_state(root / name, z_th=2)
        assert np.array_equal(state.q, fr.state.q) and state.shift == fr.state.shift
        for key in ("i", "j", "m", "k", "hist"):
            assert np.array_equal(getattr(state.contacts, key),
                                  getattr(fr.state.contacts, key)), (name, key)
        assert np.array_equal(system.radius, fr.system.radius)
        assert dict(system.material.params) == dict(fr.system.material.params)


def test_rigidity_state_matches_packing(root, tmp_path, capsys):
    rc, _, _ = _main(["packing", "rigidity", "--packing", str(root / "P"), "--kt", "1",
                      "--out", str(tmp_path / "a")], capsys)
    assert rc == 0
    rc, out, err = _main(["packing", "rigidity", "--state", str(root / "U"), "--f-tol", F_TOL,
                          "--out", str(tmp_path / "b")], capsys)
    assert rc == 0 and "used unchecked" in err and err.count("\n") == 1, err
    a = json.loads((tmp_path / "a" / "rigidity.json").read_text())
    b = json.loads((tmp_path / "b" / "rigidity.json").read_text())
    assert "packing" not in b and b["state"]["record"] is None and b["state"]["rattlers"] == 0
    assert b["state"]["law"] == "ishima" and b["state"]["n_backbone"] == 16
    for key in ("g_a", "g_na_solve", "g", "g_modes", "g_step", "sigma0"):
        _close(b["results"][0][key], a["results"][0][key])
    assert b["results"][0]["folder"] == a["results"][0]["folder"] == "kt_1"
    assert (tmp_path / "b" / "kt_1" / "g.json").is_file()
    rundir.verify(tmp_path / "b", "rigidity")


def test_dos_state_matches_packing(root, tmp_path, capsys):
    rc, _, _ = _main(["packing", "dos", "--packing", str(root / "P"), "--kt", "1", "--bins",
                      "5", "--out", str(tmp_path / "a")], capsys)
    assert rc == 0
    rc, _, err = _main(["packing", "dos", "--state", str(root / "J"), "--bins", "5",
                        "--out", str(tmp_path / "b")], capsys)
    assert rc == 0 and err == "", err
    with np.load(tmp_path / "a" / "dos.npz") as za, np.load(tmp_path / "b" / "dos.npz") as zb:
        assert sorted(za.files) == sorted(zb.files)
        for key in ("eigenvalues_0", "omega_0", "dos_0", "edges"):
            _close(zb[key], za[key])
    b = json.loads((tmp_path / "b" / "dos.json").read_text())
    assert b["state"]["record"] == "jacobian.json" and b["translations_dropped"] == 2


def test_jacobian_state_matches_and_records_its_spectrum(root, tmp_path, capsys):
    from fricstab.analysis.spectrum import growth_rate
    from fricstab.protocols.aqs import pairs, spectrum
    rc, out, _ = _main(["packing", "jacobian", "--state", str(root / "I"),
                        "--out", str(tmp_path / "b")], capsys)
    assert rc == 0 and "complex pairs, largest growth rate" in out.splitlines()[0]
    ka = sps.load_npz(root / "J" / "jacobian.npz").toarray()
    kb = sps.load_npz(tmp_path / "b" / "jacobian.npz").toarray()
    _close(kb, ka)
    doc = rundir.verify(tmp_path / "b", "jacobian")
    sp = doc["spectrum"]
    w = spectrum(*system_from_state(root / "J" / "state.npz"))[0]
    _close(np.array(sp["eigenvalues_real"]) + 1j * np.array(sp["eigenvalues_imag"]), w)
    assert sp["complex_pairs"] == len(pairs(w)) and sp["growth_rate"] == growth_rate(w)
    assert doc["state"]["record"] == "import.json"


def test_aqs_state_matches_packing(root, tmp_path, capsys):
    path = ["--strain", "3e-3", "--dgamma", "1e-3"]
    rc, _, _ = _main(["packing", "aqs", "--packing", str(root / "P"), "--param", "kt=1", *path,
                      "--out", str(tmp_path / "a")], capsys)
    assert rc == 0
    rc, _, _ = _main(["packing", "aqs", "--state", str(root / "J"), "--f-tol", F_TOL, *path,
                      "--out", str(tmp_path / "b")], capsys)
    assert rc == 0
    a = json.loads((tmp_path / "a" / "aqs.json").read_text())
    b = json.loads((tmp_path / "b" / "aqs.json").read_text())
    assert len(b["stresses"]) == 4 and b["contacts"] == a["contacts"]
    _close(b["stresses"], a["stresses"])
    _close(b["largest_real_eigenvalue"], a["largest_real_eigenvalue"])


@pytest.mark.parametrize("name", ["J", "I"])
def test_a_changed_state_is_refused(root, tmp_path, capsys, name):
    src = tmp_path / "src"
    shutil.copytree(root / name, src)
    with np.load(src / "state.npz") as z:
        arrays = {k: z[k] for k in z.files}
    arrays["pos"][0, 0] += 1e-9
    with open(src / "state.npz", "wb") as fh:
        np.savez(fh, **arrays)
    rc, _, err = _main(["packing", "dos", "--state", str(src), "--out", str(tmp_path / "o")],
                       capsys)
    _one_line_error(rc, err, "--state", "state.npz", "does not match")
    assert not (tmp_path / "o").exists()


@pytest.mark.parametrize("extra,flag", [(["--kt", "1"], "--kt"), (["--law", "hertz"], "--law"),
                                        (["--param", "kt=2"], "--param"), (["--n", "16"], "--n"),
                                        (["--packing", "P"], "--packing")])
def test_options_the_state_decides_are_refused(root, tmp_path, capsys, extra, flag):
    rc, _, err = _main(["packing", "rigidity", "--state", str(root / "J"), *extra,
                        "--out", str(tmp_path / "o")], capsys)
    _one_line_error(rc, err, f"--state cannot be combined with {flag}")
    assert not (tmp_path / "o").exists()


@pytest.mark.parametrize("command", ["rigidity", "aqs"])
def test_a_fixed_particle_is_refused_by_rigidity_and_aqs(root, tmp_path, capsys, command):
    extra = ["--strain", "2e-3", "--dgamma", "1e-3"] if command == "aqs" else []
    rc, _, err = _main(["packing", command, "--state", str(root / "F"), *extra,
                        "--out", str(tmp_path / "o")], capsys)
    _one_line_error(rc, err, "1 fixed or driven particle(s)")
    assert not (tmp_path / "o").exists()


def test_a_fixed_particle_is_accepted_by_dos_and_jacobian(root, tmp_path, capsys):
    rc, _, _ = _main(["packing", "dos", "--state", str(root / "F"), "--bins", "5",
                      "--out", str(tmp_path / "d")], capsys)
    assert rc == 0
    doc = json.loads((tmp_path / "d" / "dos.json").read_text())
    # 15 free disks x 3 dof; no translation is a zero mode with a disk fixed: none dropped
    assert doc["translations_dropped"] == 0 and doc["results"][0]["modes"] == 45
    rc, _, _ = _main(["packing", "jacobian", "--state", str(root / "F"),
                      "--out", str(tmp_path / "j")], capsys)
    assert rc == 0
    assert sps.load_npz(tmp_path / "j" / "jacobian.npz").shape == (45, 45)
    sp = json.loads((tmp_path / "j" / "jacobian.json").read_text())["spectrum"]
    assert len(sp["eigenvalues_real"]) == 45


def test_rattlers_are_removed_and_counted(root, tmp_path, capsys):
    """A disk touching nothing is removed: the rest is J's state, and the record counts it."""
    loaded = load_state(root / "X", z_th=2, details=True)
    system, state = load_state(root / "J")
    assert loaded.rattlers == 1 and loaded.n_total == 17 and list(loaded.keep) == list(range(16))
    assert np.array_equal(loaded.state.q, state.q)
    assert np.array_equal(loaded.state.keys, state.keys)
    rc, _, _ = _main(["packing", "dos", "--state", str(root / "X"), "--bins", "5",
                      "--out", str(tmp_path / "d")], capsys)
    assert rc == 0
    doc = json.loads((tmp_path / "d" / "dos.json").read_text())
    assert doc["state"]["rattlers"] == 1 and doc["n"] == 17 and doc["n_backbone"] == 16


def test_a_packing_result_in_out_is_not_mixed_with_a_state(root, tmp_path, capsys):
    out = tmp_path / "o"
    shutil.copytree(root / "P", out)
    rc, _, err = _main(["packing", "dos", "--state", str(root / "J"), "--out", str(out)],
                       capsys)
    _one_line_error(rc, err, "holds results of another packing", "packing.json")
    assert not (out / "dos.json").exists()


def test_a_state_result_in_out_is_not_mixed_with_a_packing(root, tmp_path, capsys):
    out = tmp_path / "o"
    rc, _, _ = _main(["packing", "dos", "--state", str(root / "J"), "--bins", "5",
                      "--out", str(out)], capsys)
    assert rc == 0
    rc, _, err = _main(["packing", "rigidity", "--packing", str(root / "P"), "--kt", "1",
                        "--out", str(out)], capsys)
    _one_line_error(rc, err, "holds results of another packing", "dos.json")
    assert not (out / "rigidity.json").exists()


def test_the_loaded_system_finds_new_contacts(root):
    """A relaxation from a loaded state rebuilds its contacts with a neighbour list, as the
    packing's System does (system_from_state alone lists only the file's contacts)."""
    from fricstab.protocols.stepstrain import affine_step
    from fricstab.scenes.packing_friction import packing_system
    system, state = load_state(root / "J")
    sheared = affine_step(system, state, 0.05)
    system.rebuild(sheared)
    packing = Packing.load(root / "P" / "packing.npz")
    ref_system = packing_system(backbone(packing, z_th=2), material("ishima"))
    ref = ref_system.state(*system.positions(sheared), shift=sheared.shift)
    ref_system.rebuild(ref)
    ours = {tuple(r) for r in np.column_stack([sheared.contacts.i, sheared.contacts.j])}
    theirs = {tuple(r) for r in np.column_stack([ref.contacts.i, ref.contacts.j])}
    assert len(ours) > 0 and ours == theirs


def test_dry_run_resolves_f_tol_from_the_mean_contact_force(root, tmp_path, capsys):
    from fricstab.io.imports.engine_check import equilibrium
    rc, out, _ = _main(["packing", "aqs", "--state", str(root / "J"), "--strain", "2e-3",
                        "--dgamma", "1e-3", "--dry-run", "--out", str(tmp_path / "o")], capsys)
    assert rc == 0 and not (tmp_path / "o").exists()
    doc = json.loads(out)
    mean = equilibrium(*load_state(root / "J"))["mean_contact_force"]
    assert doc["f_tol"] == 1e-12 * mean and doc["state"]["record"] == "jacobian.json"
    rc, out, _ = _main(["packing", "aqs", "--state", str(root / "J"), "--strain", "2e-3",
                        "--dgamma", "1e-3", "--f-tol", "1e-13", "--dry-run",
                        "--out", str(tmp_path / "o")], capsys)
    assert rc == 0 and json.loads(out)["f_tol"] == 1e-13
