"""``fricstab import``: our packing through a LAMMPS data file and back, bad files, the record.

The readers' own cases are in tests/test_imports_readers.py; here the
command: what it writes (a state the analyses load, a record with a
manifest), and that a bad file or a law that cannot invert the file's
forces gives one line naming the file and line, exit 2, nothing written.
"""

import json
from pathlib import Path

import numpy as np
import pytest

from fricstab.cli import main
from fricstab.engine import jacobian
from fricstab.io.imports import read_csv, read_lammps, read_liggghts
from fricstab.io.imports.contacts import to_engine
from fricstab.io.jacobian_export import system_from_state
from fricstab.io.lammps import write_lammps
from fricstab.io.rundir import verify
from fricstab.scenes.packing import make_packing

from tests.lammps_util import sheared_state
from tests.test_imports_readers import CSV, DATA, DUMP, PAIR_COLUMNS, PAIRS


@pytest.fixture(scope="module")
def packing():
    return make_packing(16, 0.9, 0)


def _import(args, capsys):
    rc = main(["import", *map(str, args)])
    out, err = capsys.readouterr()
    return rc, out, err


@pytest.mark.parametrize("law", ["ishima", "linear"])
def test_our_packing_through_a_data_file_gives_the_same_jacobian(packing, law, tmp_path, capsys):
    """write_lammps, then ``fricstab import data.lmp``: the state.npz it writes rebuilds our
    System and State (Lees-Edwards, unfolded positions) and K agrees to 1e-12 of max |K|.

    Error model: positions pass through %.17g (exact) but are folded into the box and
    offset by its origin, which rounds each coordinate by <= 1 ulp of the box size L ~ 3.2;
    K depends on positions through delta^(1/2) / delta, so a relative change of order
    eps L / delta with delta ~ 1e-3: ~1e-12 at worst.
    """
    system, state = sheared_state(packing, law, True, 2e-3)
    write_lammps(tmp_path / "lmp", system, state)
    out = tmp_path / "imported"
    args = [tmp_path / "lmp" / "data.lmp", "--law", law, "--out", out]
    for key, value in system.material.params.items():
        args += ["--param", f"{key}={value!r}"]
    rc, text, err = _import(args, capsys)
    assert rc == 0, err
    assert "imported 16 particles" in text
    record = verify(out, "import")                      # a record with a manifest, intact
    assert set(record["files"]) == {"state.npz", "jacobian.npz", "dofs.json", "mass.npy"}
    s2, st2 = system_from_state(out / "state.npz")
    _, k1 = jacobian(system, state)
    _, k2 = jacobian(s2, st2)
    assert k1.shape == k2.shape
    assert abs(k1 - k2).max() <= 1e-12 * abs(k1).max()
    assert np.allclose(s2.mass, system.mass, rtol=1e-15, atol=0)
    assert record["counts"]["listed"] == 0 and record["history_source"] == "none"


def test_units_mapping_scales_the_state(packing, tmp_path, capsys):
    """--units length=2: every length doubles (radii, box), the record states the mapping."""
    system, state = sheared_state(packing, "ishima", False, 0.0)
    write_lammps(tmp_path / "lmp", system, state)
    out = tmp_path / "imported"
    rc, _, err = _import([tmp_path / "lmp" / "data.lmp", "--law", "ishima", "--param", "kn=1",
                          "--param", "kt=1", "--units", "length=2", "--out", out], capsys)
    assert rc == 0, err
    s2, _ = system_from_state(out / "state.npz")
    assert np.array_equal(s2.radius, 2 * system.radius)
    assert s2.lx == pytest.approx(2 * system.lx, rel=1e-15)
    units = json.loads((out / "import.json").read_text())["units"]
    assert units["length"] == {"file": None, "scale": 2.0, "given": True}


def _files(tmp_path, **texts):
    paths = []
    for name, text in texts.items():
        p = tmp_path / name.replace("_", ".")
        p.write_text(text)
        paths.append(p)
    return paths


# (case, files {name: text}, the file that is bad, old, new, line, extra args)
LAW = ["--law", "charan", "--param", "kn=1", "--param", "kt=1", "--param", "mu=0.5"]
BAD = [
    ("missing column", {"bad_data": DATA}, "bad.data", "3 2 0.5 2.0 4.0 2.0 0.0",
     "3 2 0.5 2.0 4.0 2.0", 19, LAW),
    ("absent particle", {"a_dump": DUMP, "bad_dump": PAIRS}, "bad.dump", "8 9 0.8", "8 99 0.8",
     11, LAW + ["--columns", ",".join(PAIR_COLUMNS)]),
    ("NaN", {"bad_csv": CSV}, "bad.csv", "20,2.9,2.0", "20,nan,2.0", 7, LAW),
    ("inconsistent box", {"bad_csv": CSV}, "bad.csv", "30,4.0,3.5", "30,4.0,9.5", 8, LAW),
    ("law cannot invert", {"bad_csv": CSV}, "bad.csv",   # hertz has no tangential force
     "i,j,tx,ty,fnx,fny,ftx,fty\n20,10,0.001,0.002,0.5,0.0,0.0,0.1\n30,20,0,0,",
     "i,j,fnx,fny,ftx,fty\n20,10,0.5,0.0,0.0,0.1\n30,20,", 11,
     ["--law", "hertz", "--param", "kn=1"]),
]


@pytest.mark.parametrize("case", BAD, ids=[c[0] for c in BAD])
def test_bad_file_one_line_exit_2_nothing_written(tmp_path, capsys, case):
    _, texts, bad, old, new, line, extra = case
    texts = dict(texts)
    key = bad.replace(".", "_")
    if old != new:
        assert texts[key].count(old) == 1
        texts[key] = texts[key].replace(old, new)
    files = _files(tmp_path, **texts)
    out = tmp_path / "out"
    rc, text, err = _import([*files, *extra, "--out", out], capsys)
    assert rc == 2, err
    assert text == "" and len(err.strip().splitlines()) == 1, err
    where = f"{tmp_path / bad}:" + (f"{line}: " if line is not None else "")
    assert err.startswith(f"fricstab: error: {where}"), err
    assert case[0] != "law cannot invert" or "tangential" in err, err
    assert not out.exists()


def test_law_parameters_are_all_required(tmp_path, capsys):
    """No defaults in the file's units: a missing parameter names itself and its unit."""
    files = _files(tmp_path, p_csv=CSV)
    rc, _, err = _import([*files, "--law", "linear", "--param", "kn=1", "--out",
                          tmp_path / "o"], capsys)
    assert rc == 2 and "--param kt=VALUE is needed" in err and "force/length" in err
    assert not (tmp_path / "o").exists()


def test_relax_is_recorded(packing, tmp_path, capsys):
    """--relax: the record says how far the state moved and the residual before and after."""
    system, state = sheared_state(packing, "ishima", False, 2e-3)
    write_lammps(tmp_path / "lmp", system, state)
    out = tmp_path / "imported"
    rc, text, err = _import([tmp_path / "lmp" / "data.lmp", *LAW[:1], "ishima", "--param",
                             "kn=1", "--param", "kt=1", "--relax", "--out", out], capsys)
    assert rc == 0, err
    rec = json.loads((out / "import.json").read_text())
    r = rec["relax"]
    assert r["converged"] and r["residual_before"] > 1e-3 and r["residual_after"] < 1e-10
    assert rec["residual"]["relative"] == pytest.approx(r["residual_after"])
    assert "relaxed: moved" in text


EXAMPLES = Path(__file__).resolve().parents[1] / "docs" / "examples" / "import"
ISHIMA = ["--law", "ishima", "--param", "kn=1", "--param", "kt=1"]
SHIPPED = {
    "lammps": ([EXAMPLES / "lammps" / f for f in ("packing.data", "atoms.dump", "pairs.dump")],
               ["--columns", "id1,id2,dist,fx,fy,fz,p1,p2,p3,p4", "--file-units", "lj"]),
    "liggghts": ([EXAMPLES / "liggghts" / f for f in ("atoms.dump", "pairs.dump")],
                 ["--keywords", "pos,id,force,torque,history,contactArea"]),
    "csv": ([EXAMPLES / "csv" / "packing.csv"], ["--units", "length=0.4,force=100,mass=20"]),
}


@pytest.mark.parametrize("name", sorted(SHIPPED))
def test_shipped_examples_through_the_command(name, tmp_path, capsys):
    """The shipped examples (made by LAMMPS, or written from its state) through ``fricstab
    import``: the state it writes is the Python route's to the bit (the same readers and
    to_engine), every listed contact kept, and the forces agree with the file's to round-off
    (bound as tests/test_import_examples.py: ~1e-13 relative with the CSV's unit scalings)."""
    files, extra = SHIPPED[name]
    out = tmp_path / name
    rc, text, err = _import([*files, *extra, *ISHIMA, "--out", out], capsys)
    assert rc == 0, err
    rec = verify(out, "import")
    assert rec["counts"]["kept"] == rec["counts"]["listed"] == 35
    assert rec["mismatch"]["checked"] and rec["mismatch"]["worst_relative"] < 1e-12
    assert rec["history_source"] == ("file" if name == "liggghts" else "force")
    assert [Path(p).name for p in rec["inputs"]] == [f.name for f in files]
    s_cli, st_cli = system_from_state(out / "state.npz")
    system, state, _ = to_engine(PYTHON[name](), "ishima", {"kn": 1.0, "kt": 1.0},
                                 units=UNITS.get(name))
    assert np.array_equal(st_cli.q, state.q) and st_cli.shift == state.shift
    assert np.array_equal(s_cli.radius, system.radius) and np.array_equal(s_cli.mass, system.mass)
    _, k_cli = jacobian(s_cli, st_cli)
    _, k_py = jacobian(system, state)
    assert abs(k_cli - k_py).max() == 0.0          # the same arrays, the same contacts


UNITS = {"csv": {"length": 0.4, "force": 100.0, "mass": 20.0}}
PYTHON = {
    "lammps": lambda: read_lammps(data=SHIPPED["lammps"][0][0], dump=SHIPPED["lammps"][0][1],
                                  pairs=SHIPPED["lammps"][0][2], units="lj",
                                  columns=("id1", "id2", "dist", "fx", "fy", "fz", "p1", "p2",
                                           "p3", "p4")),
    "liggghts": lambda: read_liggghts(atoms=SHIPPED["liggghts"][0][0],
                                      pairs=SHIPPED["liggghts"][0][1],
                                      keywords=("pos", "id", "force", "torque", "history",
                                                "contactArea")),
    "csv": lambda: read_csv(SHIPPED["csv"][0][0]),
}


@pytest.mark.parametrize("changed, old, new, named, line", [
    ("packing.data", "0 3.2470314813100916 xlo xhi", "0 3.3 xlo xhi", "atoms.dump", 7),
    ("pairs.dump", "6.4940629626201840e-02\n0.0", "6.6e-02\n0.0", "pairs.dump", 5),
], ids=["data_vs_dump", "pairs_vs_atoms"])
def test_files_of_two_boxes_are_refused(tmp_path, capsys, changed, old, new, named, line):
    """The files of one packing state one box: a data file written at the dump's timestep
    with another box, or a pair dump whose box is not the atoms', is refused naming the
    box line (the files are not one frame)."""
    files, extra = SHIPPED["lammps"]
    for f in files:
        text = f.read_text()
        if f.name == changed:
            assert text.count(old) == 1
            text = text.replace(old, new)
        (tmp_path / f.name).write_text(text)
    out = tmp_path / "out"
    rc, _, err = _import([*(tmp_path / f.name for f in files), *extra, *ISHIMA, "--out", out],
                         capsys)
    assert rc == 2 and err.startswith(f"fricstab: error: {tmp_path / named}:{line}: "), err
    assert "box" in err and not out.exists()


@pytest.mark.parametrize("name", ["lammps", "liggghts"])
def test_frame_indifferent_law_imports_the_tangential_part(name, tmp_path, capsys):
    """Under ishima_fi the history is xi = t . t_hat (t_hat = (n_y, -n_x)) of ishima's t.
    LAMMPS' tangential force is perpendicular to n (its history is projected onto the
    tangent), so nothing is lost: the forces agree with the file's to round-off as under
    ishima (bound as above), and xi t_hat is ishima's history to the same rounding."""
    files, extra = SHIPPED[name]
    out = {}
    for law in ("ishima", "ishima_fi"):
        out[law] = tmp_path / law
        args = [*files, *extra, "--law", law, "--param", "kn=1", "--param", "kt=1",
                "--out", out[law]]
        rc, _, err = _import(args, capsys)
        assert rc == 0, err
        assert verify(out[law], "import")["mismatch"]["worst_relative"] < 1e-12
    s_v, st_v = system_from_state(out["ishima"] / "state.npz")
    s_f, st_f = system_from_state(out["ishima_fi"] / "state.npz")
    assert st_f.contacts.hist.shape[1] >= 1
    c = st_f.contacts
    dx = st_f.q[c.i, 0] - st_f.q[c.j, 0] - c.k * st_f.shift - c.m * s_f.lx
    dy = st_f.q[c.i, 1] - st_f.q[c.j, 1] - c.k * s_f.ly
    r = np.hypot(dx, dy)
    t_hat = np.column_stack([dy / r, -dx / r])
    assert np.array_equal(np.column_stack([c.i, c.j]), np.column_stack([st_v.contacts.i,
                                                                        st_v.contacts.j]))
    t = st_v.contacts.hist[:, :2]
    assert np.abs(c.hist[:, :1] * t_hat - t).max() <= 1e-12 * np.abs(t).max()
