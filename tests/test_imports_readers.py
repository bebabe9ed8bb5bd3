"""Readers of packings made elsewhere (fricstab.io.imports): known content, round trips, bad files.

Every file is written here, in tmp_path, with known values.  Positions are
compared exactly where the file prints 17 significant digits (``%.17g``
round-trips an IEEE double), and to the printed digits otherwise.
"""

import math
from pathlib import Path

import numpy as np
import pytest

from fricstab.errors import ParameterError
from fricstab.io.export import write_extxyz, write_lammps_dump
from fricstab.io.imports import (FileFormatError, ImportedState, read_csv, read_extxyz,
                                 read_lammps, read_lammps_data, read_lammps_dump, read_liggghts)

from tests.lammps_util import load_lammps

DATA = """LAMMPS data file via write_data, timestep = 0

3 atoms
2 atom types

0 10 xlo xhi
-1 5 ylo yhi
-0.5 0.5 zlo zhi
0.75 0 0 xy xz yz

Pair Coeffs # granular

1 hooke 1000 0
2 hooke 1000 0

Atoms # sphere

1 1 1.0 2.0 1.5 2.0 0.0 0 0 0
3 2 0.5 2.0 4.0 2.0 0.0
2 1 1.0 2.0 2.5 2.0 0.0 1 0 0

Velocities

1 0 0 0 0 0 0
3 0 0 0 0 0 0
2 0 0 0 0 0 0
"""

DUMP = """ITEM: TIMESTEP
100
ITEM: NUMBER OF ATOMS
2
ITEM: BOX BOUNDS pp pp pp
0 10
0 5
-0.5 0.5
ITEM: ATOMS id x y radius
1 0 0 1
2 1 1 1
ITEM: TIMESTEP
200
ITEM: NUMBER OF ATOMS
3
ITEM: BOX BOUNDS xy xz yz pp ff pp
-1 10 0.5
0 4 0
-0.5 0.5 0
ITEM: ATOMS radius id ys type xs mass
0.5 7 0.25 1 0.5 3.0
0.5 8 0.5 2 0.1 3.0
0.25 9 0.75 1 0.9 1.5
"""

PAIRS = """ITEM: TIMESTEP
200
ITEM: NUMBER OF ENTRIES
3
ITEM: BOX BOUNDS xy xz yz pp ff pp
-1 10 0.5
0 4 0
-0.5 0.5 0
ITEM: ENTRIES c_pl[1] c_pl[2] c_pf[1] c_pf[2] c_pf[3] c_pf[4] c_pf[5] c_pf[6]
7 8 0.9 -1.5 0.25 0 0.1 0.6
8 9 0.8 2.0 -0.5 0 -0.2 -0.8
9 7 0.7 0.0 3.0 0 1.25 0
"""
PAIR_COLUMNS = ("id1", "id2", "dist", "fx", "fy", "fz", "p1", "p2")

CSV = """# particles measured on 2026-11-20
# units: length=mm force=N mass=g
# box: lx=10 ly=8 xlo=-1 periodic=x tilt=0.5
[particles]
id,x,y,radius,mass,fixed
10,1.0,2.0,1.0,0.5,1
20,2.9,2.0,1.0,0.5,0
30,4.0,3.5,0.8,0.25,0
[contacts]
i,j,tx,ty,fnx,fny,ftx,fty
20,10,0.001,0.002,0.5,0.0,0.0,0.1
30,20,0,0,-0.3,-0.4,0.04,-0.03
"""

XYZ_OVITO = """3
Lattice="10.0 0.0 0.0 0.5 8.0 0.0 0.0 0.0 2.0" Origin="-1 0 0" pbc="T F F" \
Properties=id:I:1:species:S:1:pos:R:3:Radius:R:1:Mass:R:1:fixed:L:1
5 A 1.0 2.0 0.0 0.5 2.0 T
6 A 2.0 2.0 0.0 0.5 2.0 F
9 B 3.0 2.5 0.0 0.25 1.0 F
"""

LIGGGHTS_ATOMS = """ITEM: TIMESTEP
5000
ITEM: NUMBER OF ATOMS
3
ITEM: BOX BOUNDS pp pp pp
0 4
0 4
-0.5 0.5
ITEM: ATOMS id type x y z radius
1 1 0.5 1.0 0 0.5
2 1 3.6 1.3 0 0.5
3 1 1.0 1.8 0 0.5
"""
# pos(6) vel(6) id(3) force(3) torque(3) history(3) contactArea(1): the compute's default
_L_ROWS = [  # id1 id2 per  Fx Fy  Tz   h1 h2
    (1, 2, 1, -2.0, 0.5, 0.1, 1e-3, -2e-3),
    (3, 1, 0, 0.6, 1.6, -0.2, 0.0, 4e-4),
]


def _liggghts_pairs():
    head = " ".join(f"c_cpgl[{k}]" for k in range(1, 26))
    lines = []
    for i, j, per, fx, fy, tz, h1, h2 in _L_ROWS:
        vals = [0] * 12 + [i, j, per, fx, fy, 0, 0, 0, tz, h1, h2, 0, 0.01]
        lines.append(" ".join(repr(float(v)) for v in vals))
    return ("ITEM: TIMESTEP\n5000\nITEM: NUMBER OF ENTRIES\n2\nITEM: BOX BOUNDS pp pp pp\n"
            "0 4\n0 4\n-0.5 0.5\nITEM: ENTRIES " + head + "\n" + "\n".join(lines) + "\n")


def _write(tmp_path, name, text):
    p = tmp_path / name
    p.write_text(text)
    return p


# ------------------------------------------------------------------ known content

def test_lammps_data_known_content(tmp_path):
    p = _write(tmp_path, "in.data", DATA)
    s = read_lammps_data(p, fixed_types=(2,), units="si")
    assert s.ids.tolist() == [1, 3, 2]
    assert np.array_equal(s.pos, [[1.5, 2.0], [4.0, 2.0], [2.5, 2.0]])
    assert np.array_equal(s.radius, [0.5, 0.25, 0.5])
    # LAMMPS' rule: density * 4/3 pi r^3 (one rounding per operation: rel 4 eps)
    assert np.allclose(s.mass, 2.0 * 4 / 3 * math.pi * s.radius ** 3, rtol=4e-16, atol=0)
    assert s.box == (10.0, 6.0) and s.origin == (0.0, -1.0) and s.le_offset == 0.75
    assert s.periodic == (True, True) and s.fixed.tolist() == [False, True, False]
    assert s.units["style"] == "si" and s.units["force"] == "N"
    disk = read_lammps_data(p, mass_rule="disk", periodic=(True, False))
    assert np.allclose(disk.mass, 2.0 * math.pi * s.radius ** 2, rtol=4e-16, atol=0)
    assert disk.periodic == (True, False)
    assert s.n_contacts == 0 and s.history is None


def test_lammps_dump_scaled_columns_any_order_and_frames(tmp_path):
    p = _write(tmp_path, "atoms.dump", DUMP)
    s = read_lammps_dump(p, fixed_types=(2,))
    # triclinic bounds: xlo = -1 - min(0, 0.5) = -1, xhi = 10 - 0.5 = 9.5, lx = 10.5
    lx, ly, xy = 10.5, 4.0, 0.5
    xs, ys = np.array([0.5, 0.1, 0.9]), np.array([0.25, 0.5, 0.75])
    # x = xlo + xs lx + ys xy: a few roundings of numbers of size 10 (rel 4 eps)
    assert np.allclose(s.pos[:, 0], -1 + xs * lx + ys * xy, rtol=0, atol=4 * 10 * 2.3e-16)
    assert np.allclose(s.pos[:, 1], ys * ly, rtol=0, atol=4 * 4 * 2.3e-16)
    assert s.ids.tolist() == [7, 8, 9] and s.radius.tolist() == [0.5, 0.5, 0.25]
    assert s.mass.tolist() == [3.0, 3.0, 1.5] and s.fixed.tolist() == [False, True, False]
    assert s.box == (lx, ly) and s.le_offset == xy and s.periodic == (True, False)
    first = read_lammps_dump(p, frame=0)
    assert first.ids.tolist() == [1, 2] and first.le_offset == 0.0 and first.mass is None


def test_lammps_dump_negative_tilt_bounds(tmp_path):
    """LAMMPS writes the bounding box of a tilted cell: xlo_bound = xlo + min(0, xy)."""
    text = DUMP.split("ITEM: TIMESTEP\n200")[0].replace(
        "BOX BOUNDS pp pp pp\n0 10\n0 5\n", "BOX BOUNDS xy xz yz pp pp pp\n-1.5 10 -0.5\n0 5 0\n")
    s = read_lammps_dump(_write(tmp_path, "t.dump", text.replace("-0.5 0.5\n", "-0.5 0.5 0\n")))
    assert s.origin == (-1.0, 0.0) and s.box == (11.0, 5.0) and s.le_offset == -0.5


def test_lammps_pair_local_three_particles(tmp_path):
    atoms, pairs = _write(tmp_path, "a.dump", DUMP), _write(tmp_path, "p.dump", PAIRS)
    s = read_lammps(dump=atoms, pairs=pairs, columns=PAIR_COLUMNS)
    assert s.ids[s.ci].tolist() == [7, 8, 9] and s.ids[s.cj].tolist() == [8, 9, 7]
    assert np.array_equal(s.force_n, [[-1.5, 0.25], [2.0, -0.5], [0.0, 3.0]])
    assert np.array_equal(s.force_t, [[0.1, 0.6], [-0.2, -0.8], [1.25, 0.0]])
    assert s.history is None and s.torque is None
    by_name = read_lammps(dump=atoms, pairs=pairs, columns={
        "c_pl[1]": "id1", "c_pl[2]": "id2", "c_pf[2]": "fx", "c_pf[3]": "fy"})
    assert np.array_equal(by_name.force_n, s.force_n) and by_name.force_t is None
    with pytest.raises(ParameterError, match="columns"):
        read_lammps(dump=atoms, pairs=pairs, columns=("id1", "id2", "fx") + (None,) * 5)


def test_lammps_data_with_dump_and_pairs_by_timestep(tmp_path):
    atoms = _write(tmp_path, "a.dump", DUMP.replace("mass\n", "\n").replace(" 3.0\n", "\n")
                   .replace(" 1.5\n", "\n"))
    data = _write(tmp_path, "d.data", DATA.replace("1 1 1.0", "7 1 1.0").replace(
        "3 2 0.5", "8 2 0.5").replace("2 1 1.0", "9 1 1.0"))
    s = read_lammps(data=data, dump=atoms, pairs=_write(tmp_path, "p.dump", PAIRS),
                    columns=PAIR_COLUMNS, frame=-1)
    assert s.mass[0] == pytest.approx(2.0 * 4 / 3 * math.pi * 0.125, rel=4e-16)
    assert s.radius.tolist() == [0.5, 0.5, 0.25]          # the dump's radii
    assert [src[0] for src in s.sources] == [str(data), str(atoms), str(tmp_path / "p.dump")]
    with pytest.raises(FileFormatError, match="no frame at timestep 100"):
        read_lammps(dump=atoms, pairs=tmp_path / "p.dump", columns=PAIR_COLUMNS, frame=0)


def test_liggghts_default_keywords(tmp_path):
    atoms = _write(tmp_path, "atoms.dump", LIGGGHTS_ATOMS)
    pairs = _write(tmp_path, "pairs.dump", _liggghts_pairs())
    s = read_liggghts(atoms=atoms, pairs=pairs)
    assert s.ids[s.ci].tolist() == [1, 3] and s.ids[s.cj].tolist() == [2, 1]
    # contact 1-2 is across the periodic x boundary: from 1 to 2 is (-0.9, 0.3), not (3.1, 0.3)
    f = np.array([[r[3], r[4]] for r in _L_ROWS])
    for c, d in ((0, [-0.9, 0.3]), (1, [-0.5, -0.8])):
        n = np.array(d) / math.hypot(*d)
        # a projection of |F| ~ 2 on a unit vector from differences of coordinates ~ 4:
        # a few roundings, 1e-15 absolute
        assert np.allclose(s.force_n[c], (f[c] @ n) * n, rtol=0, atol=1e-15)
    assert np.allclose(s.force_n + s.force_t, f, rtol=0, atol=1e-15)
    assert s.history.tolist() == [[1e-3, -2e-3], [0.0, 4e-4]]
    assert s.torque.tolist() == [0.1, -0.2]


def test_liggghts_force_components_keywords(tmp_path):
    atoms = _write(tmp_path, "atoms.dump", LIGGGHTS_ATOMS)
    cols = " ".join(f"c_c[{k}]" for k in range(1, 10))
    pairs = _write(tmp_path, "p.dump", "ITEM: TIMESTEP\n5000\nITEM: NUMBER OF ENTRIES\n1\n"
                   f"ITEM: ENTRIES {cols} v_other\n1 3 0 1 2 0 3 4 0 9\n")
    s = read_liggghts(atoms=atoms, pairs=pairs, keywords=("id", "force_normal",
                                                            "force_tangential"))
    assert s.force_n.tolist() == [[1.0, 2.0]] and s.force_t.tolist() == [[3.0, 4.0]]
    assert s.history is None
    with pytest.raises(ParameterError, match="contactPoint"):
        read_liggghts(atoms=atoms, pairs=pairs, keywords=("id", "contactPoint"))


def test_csv_one_file_and_two_files(tmp_path):
    s = read_csv(_write(tmp_path, "pack.csv", CSV))
    assert s.ids.tolist() == [10, 20, 30] and s.fixed.tolist() == [True, False, False]
    assert s.units == {"length": "mm", "force": "N", "mass": "g"}
    assert s.box == (10.0, 8.0) and s.origin == (-1.0, 0.0) and s.periodic == (True, False)
    assert s.le_offset == 0.5
    assert s.ids[s.ci].tolist() == [20, 30] and s.ids[s.cj].tolist() == [10, 20]
    assert s.history.tolist() == [[0.001, 0.002], [0.0, 0.0]]
    assert s.force_n.tolist() == [[0.5, 0.0], [-0.3, -0.4]]
    assert s.force_t.tolist() == [[0.0, 0.1], [0.04, -0.03]]
    part, cont = CSV.split("[contacts]\n")
    two = read_csv(_write(tmp_path, "p.csv", part),
                   _write(tmp_path, "c.csv", "# units: force=N\n" + cont))
    assert np.array_equal(two.force_t, s.force_t) and two.sources[1][0].endswith("c.csv")


def test_ovito_extxyz(tmp_path):
    s = read_extxyz(_write(tmp_path, "o.xyz", XYZ_OVITO), units={"length": "um"})
    assert s.ids.tolist() == [5, 6, 9] and s.radius.tolist() == [0.5, 0.5, 0.25]
    assert s.mass.tolist() == [2.0, 2.0, 1.0] and s.fixed.tolist() == [True, False, False]
    assert s.box == (10.0, 8.0) and s.le_offset == 0.5 and s.origin == (-1.0, 0.0)
    assert s.periodic == (True, False) and s.theta is None and s.units == {"length": "um"}


# ------------------------------------------------------------------ round trips

def _packing(seed=3, n=12):
    rng = np.random.default_rng(seed)
    pos = rng.uniform(0.5, 9.5, (2, n, 2)) * [1.0, 0.5]
    return pos, rng.uniform(0.1, 0.4, n), rng.uniform(-3, 3, (2, n))


def test_round_trip_write_extxyz(tmp_path):
    pos, radius, angle = _packing()
    p = tmp_path / "t.xyz"
    write_extxyz(p, pos, radius, angle=angle, kind=np.arange(12) % 3, box=(10.0, 5.0))
    for k in (0, 1):
        s = read_extxyz(p, frame=k)
        # %.17g round-trips a double: exact
        assert np.array_equal(s.pos, pos[k]) and np.array_equal(s.radius, radius)
        assert np.array_equal(s.theta, angle[k])
        assert s.box == (10.0, 5.0) and s.periodic == (True, False)
    assert np.array_equal(read_extxyz(p).pos, pos[1])


def test_round_trip_write_lammps_dump(tmp_path):
    pos, radius, angle = _packing()
    p = tmp_path / "t.dump"
    write_lammps_dump(p, pos, radius, angle=angle, kind=np.arange(12) % 3, box=(10.0, 5.0))
    s = read_lammps_dump(p, fixed_types=(3,))
    assert np.array_equal(s.pos, pos[1]) and np.array_equal(s.radius, radius)   # %.17g: exact
    assert np.array_equal(s.theta, angle[1]) and s.ids.tolist() == list(range(1, 13))
    assert s.fixed.tolist() == [k % 3 == 2 for k in range(12)]
    assert s.box == (10.0, 5.0) and s.periodic == (True, False) and s.le_offset == 0.0
    assert np.array_equal(read_lammps_dump(p, frame=0).pos, pos[0])


# ------------------------------------------------------------------ bad files

def _lammps_pairs(tmp_path, text):
    atoms = _write(tmp_path, "a.dump", DUMP)
    return lambda p: read_lammps(dump=atoms, pairs=p, columns=PAIR_COLUMNS)


def _csv(tmp_path, text):
    return read_csv


def _direct(reader):
    return lambda tmp_path, text: reader


def _liggghts(tmp_path, text):
    atoms = _write(tmp_path, "la.dump", LIGGGHTS_ATOMS)
    return lambda p: read_liggghts(atoms=atoms, pairs=p)


# (case, reader factory, good text, old, new, line of the error, words in the message)
BAD = [
    ("data missing column", _direct(read_lammps_data), DATA, "3 2 0.5 2.0 4.0 2.0 0.0",
     "3 2 0.5 2.0 4.0 2.0", 19, "expected 7 or 10 fields"),
    ("data NaN", _direct(read_lammps_data), DATA, "3 2 0.5 2.0 4.0", "3 2 0.5 2.0 nan", 19,
     "not finite"),
    ("data duplicate id", _direct(read_lammps_data), DATA, "2 1 1.0 2.0 2.5", "1 1 1.0 2.0 2.5",
     20, "appears twice"),
    ("data zero box", _direct(read_lammps_data), DATA, "-1 5 ylo", "5 5 ylo", 7, "no size"),
    ("data malformed", _direct(read_lammps_data), DATA, "1 1 1.0 2.0 1.5", "1 1 1.0 2.0 1.5x",
     18, "not a number"),
    ("data outside box", lambda t, x: lambda p: read_lammps_data(p, periodic=False), DATA,
     "3 2 0.5 2.0 4.0 2.0", "3 2 0.5 2.0 4.0 -2.0", 19, "outside the non-periodic box"),
    ("dump missing radius", _direct(read_lammps_dump), DUMP, "ITEM: ATOMS radius id ys type",
     "ITEM: ATOMS rad id ys type", 20, "no column radius"),
    ("dump inf", _direct(read_lammps_dump), DUMP, "0.5 8 0.5 2 0.1", "0.5 8 inf 2 0.1", 22,
     "not finite"),
    ("dump duplicate id", _direct(read_lammps_dump), DUMP, "0.25 9 0.75", "0.25 7 0.75", 23,
     "appears twice"),
    ("dump outside ff box", _direct(read_lammps_dump), DUMP, "0.5 8 0.5 2", "0.5 8 1.5 2", 22,
     "outside the non-periodic box"),
    ("dump zero box", _direct(read_lammps_dump), DUMP, "0 4 0\n", "4 4 0\n", 18, "no size"),
    ("dump short row", _direct(read_lammps_dump), DUMP, "0.5 7 0.25 1 0.5 3.0",
     "0.5 7 0.25 1 0.5", 21, "expected 6 fields"),
    ("pairs absent id", _lammps_pairs, PAIRS, "8 9 0.8", "8 99 0.8", 11, "particle id 99"),
    ("pairs NaN", _lammps_pairs, PAIRS, "9 7 0.7 0.0 3.0 0 1.25", "9 7 0.7 0.0 3.0 0 nan", 12,
     "not finite"),
    ("pairs malformed", _lammps_pairs, PAIRS, "-1.5 0.25", "-1.5 0.2.5", 10, "not a number"),
    ("xyz missing radius", _direct(read_extxyz), XYZ_OVITO, "Radius:R:1", "Size:R:1", 2,
     "no radius"),
    ("xyz NaN", _direct(read_extxyz), XYZ_OVITO, "6 A 2.0 2.0", "6 A nan 2.0", 4, "not finite"),
    ("xyz duplicate id", _direct(read_extxyz), XYZ_OVITO, "9 B", "5 B", 5, "appears twice"),
    ("xyz outside box", _direct(read_extxyz), XYZ_OVITO, "3.0 2.5 0.0", "3.0 9.5 0.0", 5,
     "outside the non-periodic box"),
    ("xyz zero box", _direct(read_extxyz), XYZ_OVITO, '"10.0 0.0', '"0.0 0.0', 2, "no size"),
    ("xyz short row", _direct(read_extxyz), XYZ_OVITO, "0.25 1.0 F", "0.25 1.0", 5,
     "expected 8 fields"),
    ("csv missing column", _csv, CSV, "id,x,y,radius,", "id,x,y,", 5, "radius"),
    ("csv absent id", _csv, CSV, "30,20,0,0", "30,21,0,0", 12, "particle id 21"),
    ("csv inf", _csv, CSV, "20,2.9,2.0", "20,inf,2.0", 7, "not finite"),
    ("csv duplicate id", _csv, CSV, "30,4.0", "20,4.0", 8, "appears twice"),
    ("csv outside box", _csv, CSV, "30,4.0,3.5", "30,4.0,9.5", 8, "outside the non-periodic"),
    ("csv zero box", _csv, CSV, "ly=8", "ly=0", 3, "no size"),
    ("csv malformed", _csv, CSV, "10,1.0,2.0,1.0,0.5,1", "10,1.0,2.0,1.0,0.5", 6,
     "expected 6 fields"),
    ("csv no units", _csv, CSV, "# units: length=mm force=N mass=g", "# measured", 1, "units"),
    ("liggghts absent id", _liggghts, None, "3.0 1.0 0.0", "3.0 4.0 0.0", 11, "particle id 4"),
    ("liggghts NaN", _liggghts, None, "-2.0 0.5", "nan 0.5", 10, "not finite"),
]


@pytest.mark.parametrize("case", BAD, ids=[c[0] for c in BAD])
def test_bad_file_names_path_and_line(tmp_path, case):
    _, factory, good, old, new, line, words = case
    good = _liggghts_pairs() if good is None else good
    assert good.count(old) == 1, "the case must change exactly one place"
    p = _write(tmp_path, "bad.txt", good.replace(old, new))
    with pytest.raises(FileFormatError) as err:
        factory(tmp_path, good)(p)
    assert str(err.value).startswith(f"{p}:{line}: "), str(err.value)
    assert words is None or words in str(err.value)
    assert isinstance(err.value, ParameterError)       # the CLI: 'fricstab: error: ...', exit 2


GOOD = [("data", DATA, _direct(read_lammps_data)), ("dump", DUMP, _direct(read_lammps_dump)),
        ("pairs", PAIRS, _lammps_pairs), ("xyz", XYZ_OVITO, _direct(read_extxyz)),
        ("csv", CSV, _csv), ("liggghts", None, _liggghts)]


@pytest.mark.parametrize("name,text,factory", GOOD, ids=[g[0] for g in GOOD])
def test_damaged_files_raise_only_file_format_error(tmp_path, name, text, factory):
    """Every truncation and every one-token corruption: a state or FileFormatError, nothing else."""
    text = _liggghts_pairs() if text is None else text
    read = factory(tmp_path, text)
    assert isinstance(read(_write(tmp_path, "good.txt", text)), ImportedState)
    lines = text.splitlines(keepends=True)
    variants = ["".join(lines[:k]) for k in range(len(lines))]
    for k, line in enumerate(lines):
        toks = line.replace(",", " ").split()
        for t in range(min(len(toks), 4)):
            for junk in ("x", "-1", "nan", ""):
                bad = line.replace(toks[t], junk, 1)
                variants.append("".join(lines[:k] + [bad] + lines[k + 1:]))
    failures = 0
    for v in variants:
        try:
            read(_write(tmp_path, "v.txt", v))
        except FileFormatError as err:
            assert ":" in str(err) and str(err).startswith(str(tmp_path / "v.txt"))
            failures += 1
    assert failures > len(lines) // 2


def test_missing_file(tmp_path):
    with pytest.raises(FileFormatError, match="cannot read"):
        read_extxyz(tmp_path / "absent.xyz")


# ------------------------------------------------------------------ LAMMPS itself



DECK = """units si
dimension 2
atom_style sphere
boundary p f p
read_data {data}
comm_modify vel yes
pair_style gran/hertz/history 2.0e5 1.5e5 0.0 0.0 0.5 0
pair_coeff * *
fix 1 all nve/sphere
fix 2 all enforce2d
fix 3 all wall/gran hertz/history 2.0e5 1.5e5 0.0 0.0 0.5 0 yplane 0.0 3.2
timestep 1.0e-5
compute pl all property/local patom1 patom2
compute pf all pair/local dist fx fy fz p1 p2 p3 p4 cutoff radius
dump a all custom 50 {atoms} id type x y z radius fx fy
dump_modify a format float %.17g units yes
dump p all local 50 {pairs} c_pl[1] c_pl[2] c_pf[*]
dump_modify p format float %.17g
run 200
"""


def test_lammps_gran_hertz_history_pair_local(tmp_path):
    lammps = load_lammps()
    pos = np.array([[1.0, 1.0], [1.95, 1.05], [1.5, 1.85], [3.2, 1.0]])
    radius = np.array([0.5, 0.5, 0.5, 0.45])
    vel = np.array([[0.2, 0.0], [-0.2, 0.05], [0.0, -0.3], [0.0, 0.0]])
    data = tmp_path / "pack.data"
    lines = ["4 disks", "", "4 atoms", "1 atom types", "0 4 xlo xhi", "0 3.2 ylo yhi",
             "-0.5 0.5 zlo zhi", "", "Atoms # sphere", ""]
    lines += [f"{i + 1} 1 {2 * r:.17g} 1000.0 {x:.17g} {y:.17g} 0.0" for i, ((x, y), r) in
              enumerate(zip(pos, radius))]
    lines += ["", "Velocities", ""] + [f"{i + 1} {vx:.17g} {vy:.17g} 0 0 0 0" for i, (vx, vy)
                                       in enumerate(vel)]
    data.write_text("\n".join(lines) + "\n")
    atoms, pairs = tmp_path / "atoms.dump", tmp_path / "pairs.dump"
    lmp = lammps(cmdargs=["-log", "none", "-screen", "none"])
    try:
        for cmd in DECK.format(data=data, atoms=atoms, pairs=pairs).splitlines():
            lmp.command(cmd)
        rmass = dict(zip(lmp.numpy.extract_atom("id")[:4].tolist(),
                         lmp.numpy.extract_atom("rmass")[:4].tolist()))
    finally:
        lmp.close()
    s = read_lammps(data=data, dump=atoms, pairs=pairs, units="si",
                    columns=("id1", "id2", "dist", "fx", "fy", "fz", "p1", "p2", "p3", "p4"))
    assert s.units["style"] == "si" and s.periodic == (True, False)
    # the sphere rule is LAMMPS' own: its rmass to 4 eps (density written with 17 digits)
    assert np.allclose(s.mass, [rmass[i] for i in s.ids], rtol=4 * 2.3e-16, atol=0)
    assert s.n_contacts >= 2 and np.abs(s.force_t).max() > 1e-3 * np.abs(s.force_n).max()
    # contacts listed = pairs that overlap (cutoff radius), nearest image in x
    n, r = __import__("fricstab.io.imports._text", fromlist=["x"]).min_image_normal(
        s.pos, s.box, s.periodic, 0.0, s.ci, s.cj)
    assert np.all(r < s.radius[s.ci] + s.radius[s.cj])
    # fx fy is the normal force on i: along -n (repulsion), no tangential part
    fn = s.force_n
    assert np.allclose(fn[:, 0] * n[:, 1] - fn[:, 1] * n[:, 0], 0.0,
                       atol=1e-12 * np.abs(fn).max())   # cross product: roundoff of |F|
    assert np.all(np.einsum("ka,ka->k", fn, n) < 0)
    # p1 p2 is the tangential force on i: perpendicular to n
    assert np.allclose(np.einsum("ka,ka->k", s.force_t, n), 0.0,
                       atol=1e-12 * np.abs(fn).max())
    # No damping (gamma 0): pair/local re-evaluates each pair at the dump, with the
    # end-of-step velocities; the forces integrated used the half-step ones, so a
    # damping term would differ by O(dt).  Elastic forces depend on positions and the
    # stored history only, hence are the same.
    # per-atom force (dumped fx fy) = sum over its contacts of (force_n + force_t) on i,
    # minus on j; the wall is the only other force.  Sums of a few doubles printed with
    # 17 digits: error ~ 8 eps * sum |F| per particle.
    fsum = np.zeros((s.n, 2))
    f = s.force_n + s.force_t
    np.add.at(fsum, s.ci, f)
    np.add.at(fsum, s.cj, -f)
    dumped = _dumped_forces(atoms, s.ids)
    touching_wall = (s.pos[:, 1] - s.radius < 0) | (s.pos[:, 1] + s.radius > 3.2)
    tol = 8 * 2.3e-16 * (np.abs(fsum).sum(axis=1) + np.abs(dumped).sum(axis=1)) + 1e-300
    free = ~touching_wall
    assert free.any()
    assert np.all(np.abs(fsum - dumped)[free].max(axis=1) <= tol[free])


def _dumped_forces(path, ids):
    text = Path(path).read_text().split("ITEM: TIMESTEP")[-1].splitlines()
    head = next(k for k, t in enumerate(text) if t.startswith("ITEM: ATOMS"))
    cols = text[head].split()[2:]
    rows = [t.split() for t in text[head + 1:] if t.strip()]
    by_id = {int(r[cols.index("id")]): (float(r[cols.index("fx")]), float(r[cols.index("fy")]))
             for r in rows}
    return np.array([by_id[int(i)] for i in ids])
