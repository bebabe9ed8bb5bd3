"""The shipped import examples (docs/examples/import, issue 37) read back as they should.

One 16-disk ``ishima`` packing made by LAMMPS (``gran/hertz/history``, sheared
2 % with Lees-Edwards, then damped to rest: the contacts carry history) and the
same state written by ``make_examples.py`` as LIGGGHTS dumps, OVITO extxyz and
a CSV in mm / N / g.  Each is read with the Python API and mapped to our law by
``to_engine``: counts, the force mismatch against the file, the equilibrium
residual, and that the three derived examples are what the script writes now
(regenerated into tmp_path, compared byte for byte).  No LAMMPS needed.
"""

import importlib.util
from pathlib import Path

import numpy as np
import pytest

from fricstab.io.imports import read_csv, read_extxyz, read_liggghts
from fricstab.io.imports.contacts import to_engine
from fricstab.io.imports.engine_check import relax
from fricstab.scenes.packing_relax import separations

EXAMPLES = Path(__file__).resolve().parents[1] / "docs" / "examples" / "import"
EPS = np.finfo(float).eps
DERIVED = ("liggghts/atoms.dump", "liggghts/pairs.dump", "extxyz/packing.xyz",
           "csv/packing.csv")
LAMMPS_FILES = ("lammps/in.shear", "lammps/start.data", "lammps/packing.data",
                "lammps/atoms.dump", "lammps/pairs.dump")


def _script():
    spec = importlib.util.spec_from_file_location("make_examples",
                                                  EXAMPLES / "make_examples.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


mx = _script()
PARAMS = mx.law_params()


@pytest.fixture(scope="module")
def lammps_import():
    s = mx.read_lammps_example(EXAMPLES / "lammps")
    return (s, *to_engine(s, "ishima", PARAMS))


def _rel_mismatch(s, system, state, rep, force_scale=1.0):
    """Per listed contact |F_ours - F_file| / |F_file| and the overlap, in the law's units."""
    f = system.contact_forces(state)[rep.order]
    ours = np.where(rep.swapped[:, None], f[:, 3:5], f[:, :2])
    theirs = (s.force_n + s.force_t) * force_scale
    sep = separations(system, state)[rep.order]
    delta = system.radius[s.ci] + system.radius[s.cj] - np.hypot(*sep.T)
    return np.hypot(*(ours - theirs).T) / np.hypot(*theirs.T), delta


def _size(system, state):
    return 2 * system.radius.max() + 2 * np.abs(state.q[:, :2]).max()


def test_lammps_example(lammps_import):
    s, system, state, rep = lammps_import
    assert s.n == 16 and s.n_contacts == 35
    assert rep.counts == dict(listed=35, kept=35, dropped_apart=0, dropped_fixed=0, added=0)
    assert rep.history_source == "force" and rep.flagged == []
    # sheared 2 % (erate 1e-3 for 20 time units): the tilt is 0.02 L
    assert abs(s.le_offset / s.box[0] - 0.02) <= 1e-12
    mag_t, mag_n = np.hypot(*s.force_t.T), np.hypot(*s.force_n.T)
    assert (mag_t > 1e-2 * mag_n).sum() >= 30          # the contacts carry shear history
    # Error model (tests/test_imports_roundtrip.py): LAMMPS' ghost images and our
    # separations round the overlap apart by up to 4 eps size, the Hertz force
    # (p = 3/2) by p 4 eps size / delta relative; the tangential force goes
    # through its history and back at our overlap: 16 eps of roundings
    rel, delta = _rel_mismatch(s, system, state, rep)
    assert np.all(rel <= 1.5 * 4 * EPS * _size(system, state) / delta + 16 * EPS)
    assert rep.mismatch["worst_relative"] == pytest.approx(rel.max(), rel=1e-6)
    # At rest: LAMMPS damped it for 20,000 steps (fix viscous, viscous/sphere, 400 t0);
    # the residual left is the damping's reach, 3.0e-12 of the mean contact force
    # when written, not round-off: 1e-10 bounds it
    assert rep.residual["relative"] <= 1e-10
    _, info = relax(system, state)
    assert info["converged"] and info["moved"] <= 1e-10
    assert info["contacts_gained"] == info["contacts_lost"] == 0


def test_liggghts_example(lammps_import):
    s0, _, st0, rep0 = lammps_import
    s = read_liggghts(atoms=EXAMPLES / "liggghts" / "atoms.dump",
                      pairs=EXAMPLES / "liggghts" / "pairs.dump",
                      keywords=mx.LIGGGHTS_KEYWORDS, units="lj")
    system, state, rep = to_engine(s, "ishima", PARAMS)
    assert rep.counts == dict(listed=35, kept=35, dropped_apart=0, dropped_fixed=0, added=0)
    assert rep.history_source == "file" and rep.flagged == []
    # the file's history is xi = -F_t / (k_T delta^(1/2)) of the LAMMPS forces at our
    # overlap, as to_engine inverts it from LAMMPS: equal up to the split of
    # `force` along the line of centres (a few eps of |F| over |F_t| >= 1e-2 |F|)
    h0 = st0.contacts.hist[rep0.order]
    h0 = np.where(rep0.swapped[:, None], -h0, h0)
    h = state.contacts.hist[rep.order]
    h = np.where(rep.swapped[:, None], -h, h)
    assert np.abs(h - h0).max() <= 1e-12 * np.abs(h0).max()
    rel, delta = _rel_mismatch(s, system, state, rep)
    assert np.all(rel <= 1.5 * 4 * EPS * _size(system, state) / delta + 16 * EPS)
    # the torque column is our law's at this state: only the summation differs
    assert rep.mismatch["torque_worst_relative"] <= 8 * EPS
    assert rep.residual["relative"] <= 1e-10


def test_csv_example_in_mm_newton_gram(lammps_import):
    _, sys0, st0, _ = lammps_import
    s = read_csv(EXAMPLES / "csv" / "packing.csv")
    assert s.units == {"length": "mm", "force": "N", "mass": "g"}
    system, state, rep = to_engine(s, "ishima", PARAMS, units=mx.CSV_MAPPING)
    assert {q: v["scale"] for q, v in rep.units.items()
            if q in mx.CSV_MAPPING} == mx.CSV_MAPPING
    assert rep.counts == dict(listed=35, kept=35, dropped_apart=0, dropped_fixed=0, added=0)
    # positions x 2.5 (written) x 0.4 (mapped): two more roundings of each coordinate
    size = _size(system, state)
    assert np.abs(state.q[:, :2] - st0.q[:, :2]).max() <= 4 * EPS * size
    assert np.all(np.abs(system.mass / sys0.mass - 1) <= 4 * EPS)
    # Error model: the LAMMPS one (above) with the overlap rounded by 4 eps size
    # more (the two scalings) and the forces x 0.01 x 100 (4 eps more)
    rel, delta = _rel_mismatch(s, system, state, rep, mx.CSV_MAPPING["force"])
    assert np.all(rel <= 1.5 * 8 * EPS * size / delta + 20 * EPS)
    assert rep.residual["relative"] <= 1e-10


def test_extxyz_example_finds_contacts_with_zero_history(lammps_import):
    _, sys0, st0, _ = lammps_import
    s = read_extxyz(EXAMPLES / "extxyz" / "packing.xyz", units={"length": "lj"})
    system, state, rep = to_engine(s, "ishima", PARAMS)
    assert rep.counts == dict(listed=0, kept=0, dropped_apart=0, dropped_fixed=0, added=35)
    assert np.all(state.contacts.hist == 0.0)
    # 17 digits: the same doubles as the LAMMPS import
    assert np.array_equal(state.q, st0.q) and np.array_equal(system.mass, sys0.mass)
    # without the shear history the state is not in equilibrium; Newton relaxes it
    assert rep.residual["relative"] > 0.1
    _, info = relax(system, state)
    assert info["converged"] and info["residual_after"] <= 1e-10
    assert 1e-4 < info["moved"] < 0.1


def test_derived_examples_are_what_the_script_writes(tmp_path):
    mx.write_derived(EXAMPLES / "lammps", tmp_path)
    for name in DERIVED:
        assert (tmp_path / name).read_bytes() == (EXAMPLES / name).read_bytes(), name


def test_examples_are_small():
    sizes = {n: (EXAMPLES / n).stat().st_size for n in DERIVED + LAMMPS_FILES}
    assert max(sizes.values()) < 20_000 and sum(sizes.values()) < 100_000
