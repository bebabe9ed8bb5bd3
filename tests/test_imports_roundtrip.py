"""Round trips through LAMMPS itself (issue 37): our state out and back, LAMMPS' states in.

1. **Out and back.**  A 16-disk packing of ours (``make_packing(16, 0.9, 0)``,
   two radii), affinely sheared so that it carries forces, zero history, under
   ``ishima`` (``gran/hertz/history`` through ``pair_style hybrid``, one
   sub-style per pair of radii) and ``linear`` (``gran/hooke/history``), plain
   and with a Lees-Edwards offset: :func:`~fricstab.io.lammps.write_lammps`,
   the deck run by LAMMPS as written (``run 0``), ``data.lmp`` and
   ``contacts.dump`` read back by :func:`~fricstab.io.imports.read_lammps`,
   :func:`~fricstab.io.imports.contacts.to_engine` with the law and its
   parameters: every touching pair comes back with zero history, the
   per-particle forces equal ours and LAMMPS', the Jacobian equals ours.
2. **Made by LAMMPS.**  The same packing exported with random velocities and
   spins and a small tilt, then moved by LAMMPS for 300 steps without damping
   (``gamma_n = gamma_t = 0``) while ``fix deform`` shears the box (Lees-Edwards
   through the tilt, ``remap v``), so the contacts carry shear history; the
   atoms (``dump custom``) and pairs (``compute pair/local``) of the last step
   are imported: our forces at the imported state equal LAMMPS' and the
   imported state's Jacobian passes the system-level proof (complex step of the
   independent reference assembly, ``tests/system_proof.py``).

   Mapping back: ``ishima`` (``k_N = Kn sqrt(R_eff)``, ``k_T = Kt
   sqrt(R_eff)`` per type pair, i.e. the exported ``kn``, ``kt``), history
   ``xi = -F_t / (k_T delta^(1/2))``; ``linear``: ``Kn = kn``, ``Kt = kt``,
   ``xmu = mu``, no damping, history ``t = -F_t / kt``; a contact at
   LAMMPS' Coulomb cap (``|F_t| = mu |F_n|``, where LAMMPS rescaled its shear
   history) is flagged and stored on our cap ``|t| = t* = mu kn delta / kt``.

Skipped, saying why, where the ``lammps`` module cannot be loaded.
"""

import numpy as np
import pytest

from fricstab.engine.jacobian import jacobian
from fricstab.io.imports import read_lammps
from fricstab.io.imports.contacts import to_engine
from fricstab.io.lammps import write_lammps
from fricstab.scenes.packing import make_packing
from fricstab.scenes.packing_friction import material, packing_system
from fricstab.scenes.packing_relax import separations

from tests.lammps_util import load_lammps, sheared_state
from tests.system_proof import complex_step_jacobian, engine_jacobian

EPS = np.finfo(float).eps
GAMMA = 2e-3        # affine shear of test 1: net forces ~1e-3 k_N d^(3/2)
#: The columns of write_lammps' ``dump local`` (c_ids[1] c_ids[2] c_pf[1..5]).
DUMP_COLUMNS = ("id1", "id2", "force", "fx", "fy", "p1", "p2")
EXPONENT = {"ishima": 1.5, "linear": 1.0}   # F ~ delta^p




@pytest.fixture(scope="module")
def packing():
    return make_packing(16, 0.9, 0)


def _run(lammps, out, deck, monkeypatch):
    """Run ``out/deck``; per-atom (F_x, F_y) and T_z in id order."""
    monkeypatch.chdir(out)
    lmp = lammps(cmdargs=["-log", "none", "-screen", "none"])
    try:
        lmp.file(deck)
        nl = lmp.extract_global("nlocal")
        o = np.argsort(lmp.numpy.extract_atom("id")[:nl])
        return (lmp.numpy.extract_atom("f")[:nl][o, :2].copy(),
                lmp.numpy.extract_atom("torque")[:nl][o, 2].copy())
    finally:
        lmp.close()


def _overlaps(system, state):
    c = state.contacts
    sep = separations(system, state)
    return system.radius[c.i] + system.radius[np.maximum(c.j, 0)] - np.hypot(*sep.T)


def _fold_bound(system, state, law, size):
    """Per-particle bound on the force change when each coordinate moves by ``eps size``.

    Error model: LAMMPS' folded coordinates (and its ghost images ``x + L``,
    ``x + xy``) and ours differ by a rounding of a coordinate of size ``size``,
    so an overlap differs by up to ``4 eps size`` and a force ``F = k
    delta^p`` by ``p F 4 eps size / delta``, plus ``8 eps F`` for the power,
    the ``sqrt(R_eff)`` factor and the normal (validation/benchmarks/_lammps.py
    ``roundoff_tolerance``); summed over a particle's contacts, with a floor of
    ``8 eps max |F|`` (summation order).
    """
    c = state.contacts
    xi = _overlaps(system, state)
    on = (c.j >= 0) & (xi > 0)
    fc = system.contact_forces(state)
    per = np.hypot(fc[on, 0], fc[on, 1]) * (EXPONENT[law] * 4 * EPS * size / xi[on] + 8 * EPS)
    tol = np.zeros(system.n)
    np.add.at(tol, c.i[on], per)
    np.add.at(tol, c.j[on], per)
    return tol + 8 * EPS * np.abs(system.forces(state)[:, :2]).max()


def _sheared(packing, law, lees_edwards):
    return sheared_state(packing, law, lees_edwards, GAMMA)


@pytest.mark.parametrize("lees_edwards", [False, True], ids=["plain", "lees_edwards"])
@pytest.mark.parametrize("law", ["ishima", "linear"])
def test_our_packing_through_lammps_and_back(packing, law, lees_edwards, tmp_path, monkeypatch):
    lammps = load_lammps()
    system, state = _sheared(packing, law, lees_edwards)
    write_lammps(tmp_path, system, state, dt=0.01)
    f_lmp, t_lmp = _run(lammps, tmp_path, "in.lmp", monkeypatch)
    s = read_lammps(data=tmp_path / "data.lmp", pairs=tmp_path / "contacts.dump",
                    columns=DUMP_COLUMNS, units="lj")
    # the tilt comes back folded: GAMMA L, up to the rounding of (GAMMA + 1) L - L (eps L)
    assert abs(s.le_offset - (GAMMA * packing.box if lees_edwards else 0.0)) <= EPS * packing.box
    sys2, st2, rep = to_engine(s, law, system.material.params)
    touching = int(np.count_nonzero((_overlaps(system, state) > 0) & (state.contacts.j >= 0)))
    assert rep.counts == dict(listed=touching, kept=touching, dropped_apart=0, dropped_fixed=0,
                              added=0)
    assert rep.history_source == "force" and rep.flagged == []
    assert np.all(st2.contacts.hist == 0.0)   # LAMMPS' tangential forces at zero history: 0
    # per-particle forces: ours, LAMMPS' and ours at the imported state
    size = 2 * system.radius.max() + 2 * np.abs(state.q[:, :2]).max()
    tol = _fold_bound(system, state, law, size)
    ours, back = system.forces(state), sys2.forces(st2)
    assert np.abs(ours[:, :2]).max() > 1e-4             # the shear loads the packing
    assert np.all(np.abs(back[:, :2] - ours[:, :2]).max(axis=1) <= tol)
    assert np.all(np.abs(f_lmp - back[:, :2]).max(axis=1) <= tol)
    assert np.abs(t_lmp).max() == 0.0 and np.abs(back[:, 2]).max() == 0.0
    assert abs(sys2.mass / system.mass - 1).max() <= 4 * EPS   # densities with 17 digits
    # the Jacobian (free particles, increment rule).  Error model: an overlap
    # moved by 4 eps size (size ~17 L unfolded, ~8 L plain) moves ishima's entries
    # (1.5 kn delta^(1/2), kt delta^(1/2), F / r) by ~0.75 k delta^(-1/2) 4 eps
    # size: at the smallest overlap here (3.4e-3) 2e-13, 1.5e-13 of max|K| (1.36);
    # linear's (kn, kt constant, F / r) by kn 4 eps size / r ~ 4e-15 of max|K|;
    # plus ~6 blocks summed per diagonal entry (8 eps): both below 1e-12
    _, k1 = jacobian(system, state)
    _, k2 = jacobian(sys2, st2)
    err = abs(k1 - k2).max() / abs(k1).max()
    assert err <= 1e-12


# ------------------------------------------------------------------ made by LAMMPS

STEPS, EVERY = 300, 100
RATE = 2e-2          # engineering shear rate of fix deform (per time unit): 6% strain


def _moving_deck(deck, dt):
    """in.lmp with a per-atom dump, ``fix deform`` shear and STEPS steps instead of ``run 0``.

    ``fix deform`` changes the box at the end of a step, after the forces and
    before the dumps: a dump of a deforming step holds the tilt of the next
    step with the forces of this one (k = +-1 pairs then differ by ``RATE ly
    dt`` of tilt).  So the last step runs without it: box, positions and
    forces of the dumps belong together.
    """
    lines = []
    for line in deck.splitlines():
        if line.startswith("dump contacts all local 1 "):
            line = line.replace("local 1 ", f"local {EVERY} ", 1)
        if line == "run 0":
            lines += [f"dump atoms all custom {EVERY} atoms.dump id type x y z radius",
                      "dump_modify atoms format float %.17g",
                      f"fix shear all deform 1 xy erate {RATE} remap v",
                      f"run {STEPS - 1}", "unfix shear", "run 1"]
            continue
        lines.append(line)
    assert "run 1" in lines and f"timestep {dt:.17g}" in lines
    return "\n".join(lines) + "\n"


@pytest.mark.parametrize("law", ["ishima", "linear"])
def test_lammps_sheared_state_imported(packing, law, tmp_path, monkeypatch):
    lammps = load_lammps()
    mat = material(law, mu=0.2) if law == "linear" else material(law)
    system = packing_system(packing, mat)
    rng = np.random.default_rng(7)
    state = system.state(packing.pos, vel=rng.normal(0.0, 0.02, (system.n, 2)),
                         omega=rng.normal(0.0, 0.05, system.n), shift=1e-3 * packing.box)
    dt = 0.02
    write_lammps(tmp_path, system, state, dt=dt)
    (tmp_path / "run.lmp").write_text(_moving_deck((tmp_path / "in.lmp").read_text(), dt))
    _run(lammps, tmp_path, "run.lmp", monkeypatch)
    s = read_lammps(data=tmp_path / "data.lmp", dump=tmp_path / "atoms.dump",
                    pairs=tmp_path / "contacts.dump", columns=DUMP_COLUMNS, units="lj")
    assert s.le_offset > 0.05 * packing.box      # the box was sheared
    mag_t, mag_n = np.hypot(*s.force_t.T), np.hypot(*s.force_n.T)
    assert (mag_t > 1e-3 * mag_n).sum() >= s.n_contacts // 2   # contacts carry history
    p = system.material.params
    sys2, st2, rep = to_engine(s, law, p)
    assert rep.counts["kept"] == s.n_contacts and rep.counts["added"] == 0
    # Our forces at the imported state against LAMMPS' (fx fy + p1 p2), per
    # contact.  Error model: the same 17-digit positions, but LAMMPS' ghost
    # images (x + L, x + xy) and our separation round differently: the overlap
    # by up to 4 eps size, the normal force by p 4 eps size / delta relative;
    # the tangential force goes through its history and back at our overlap
    # (t = -F_t / (k_T delta^(1/2)), then -k_T delta^(1/2) t): a few roundings;
    # 16 eps for those.  Under the brief's 1e-10 for any overlap above 1e-4 d.
    size = 2 * sys2.radius.max() + 2 * np.abs(st2.q[:, :2]).max()
    delta = _overlaps(sys2, st2)[rep.order]
    f = sys2.contact_forces(st2)
    ours = np.where(rep.swapped[:, None], f[rep.order, 3:5], f[rep.order, :2])
    theirs = s.force_n + s.force_t
    rel = np.hypot(*(ours - theirs).T) / np.hypot(*theirs.T)
    assert np.all(rel <= EXPONENT[law] * 4 * EPS * size / delta + 16 * EPS)
    assert rel.max() <= 1e-10
    if law == "linear":
        # LAMMPS rescales a sliding contact's shear so |F_t| = mu |F_n| (to ~2 eps);
        # ours flags those (|F_t| >= mu F_n (1 - 1e-9)) and stores |t| = t*
        at_cap = mag_t >= p["mu"] * mag_n * (1 - 1e-9)
        flagged = np.array([d["contact"] for d in rep.flagged], int)
        assert at_cap.sum() >= 2 and np.array_equal(flagged, np.flatnonzero(at_cap))
        assert np.all(np.abs(mag_t[at_cap] / (p["mu"] * mag_n[at_cap]) - 1) <= 8 * EPS)
        tstar = p["mu"] * p["kn"] * delta[at_cap] / p["kt"]
        got = np.hypot(*st2.contacts.hist[rep.order[at_cap]].T)
        # t* here from separations(), to_engine's from the law's kernel: the same
        # doubles, the overlap rounded apart by up to 4 eps size; 8 eps of roundings
        assert np.all(np.abs(got / tstar - 1) <= 4 * EPS * size / delta[at_cap] + 8 * EPS)
    else:
        assert rep.flagged == []                  # xmu = 1e4: ishima has no cap
    # the system-level proof: engine K against the complex step of the reference
    # assembly, exact to round-off: <= 1e-10 max|K| (tests/test_packing_proof.py)
    k = engine_jacobian(sys2, st2)
    err = np.abs(k - complex_step_jacobian(sys2, st2, 1.0)).max() / np.abs(k).max()
    assert err <= 1e-10
