"""From an imported packing to our engine (fricstab.io.imports.contacts): histories, checks, files.

A sheared 16-disk packing of ours is written as a CSV with per-contact forces
only (no histories) at 17 significant digits (exact round trip of a double),
read back by ``read_csv`` and converted by ``to_engine``: the histories come
from the law's inverse of the tangential force.  ``force_n`` is written as the
law's elastic normal force along the line of centres and ``force_t`` as the
rest, so that a lab-frame history's small normal part is carried too.
"""

import math
from pathlib import Path

import numpy as np
import pytest

from fricstab.engine import jacobian
from fricstab.errors import ParameterError
from fricstab.io.imports import ImportedState, read_csv
from fricstab.io.imports.contacts import charan_s, to_engine
from fricstab.io.imports.engine_check import relax, write_imported
from fricstab.io.jacobian_export import system_from_state
from fricstab.laws import evaluate

from tests.lammps_util import load_lammps

EPS = np.finfo(float).eps


@pytest.fixture(scope="module")
def sheared():
    """{law: (system, state)}: the 16-disk backbone with friction, sheared by 1e-3, relaxed."""
    from fricstab.protocols.stepstrain import strain
    from fricstab.scenes.packing import make_packing
    from fricstab.scenes.packing_friction import backbone, frictional, material
    bb = backbone(make_packing(16, 0.9, 0))
    out = {}
    for law in ("ishima", "linear"):
        fr = frictional(bb, material(law))
        state, _ = strain(fr.system, fr.state, 1e-3)
        out[law] = (fr.system, state)
    return out


def _touching(system, state):
    c = state.contacts
    dx = (state.q[c.i, 0] - state.q[c.j, 0]) - c.k * state.shift - c.m * system.lx
    dy = (state.q[c.i, 1] - state.q[c.j, 1]) - c.k * system.ly
    r = np.hypot(dx, dy)
    return np.flatnonzero(r < system.radius[c.i] + system.radius[c.j]), np.column_stack(
        [dx, dy]) / r[:, None]


def write_csv(path, system, state, reverse=(), scale=1.0):
    """Our state as the plain CSV (forces only); contacts in ``reverse`` written as (j, i).

    Lengths divided by ``scale`` (the file's length unit is ``scale`` of ours).
    """
    rows, n = _touching(system, state)
    cf = system.contact_forces(state)
    zero = state.copy()
    zero.contacts.hist[:] = 0.0
    f0 = system.contact_forces(zero)
    pos, theta = system.positions(state)
    g = "%.17g"
    lines = ["# units: length=d force=kN mass=m",
             f"# box: lx={g % (system.lx / scale)} ly={g % (system.ly / scale)} "
             f"tilt={g % (state.shift / scale)} periodic=xy",
             "[particles]", "id,x,y,radius,mass,theta"]
    lines += [",".join([str(a + 1)] + [g % v for v in (pos[a, 0] / scale, pos[a, 1] / scale,
                                                      system.radius[a] / scale,
                                                      system.mass[a], theta[a])])
              for a in range(system.n)]
    lines += ["[contacts]", "i,j,fnx,fny,ftx,fty"]
    for r in rows:
        i, j = state.contacts.i[r], state.contacts.j[r]
        fn, ft = f0[r, :2], cf[r, :2] - f0[r, :2]
        if r in reverse:
            i, j, fn, ft = j, i, -fn, -ft
        lines.append(",".join([str(i + 1), str(j + 1)] + [g % v for v in (*fn, *ft)]))
    Path(path).write_text("\n".join(lines) + "\n")
    return rows


def _by_key(state_a, state_b, rows):
    """Rows of state_b holding the contacts ``rows`` of state_a (same keys)."""
    pos = np.searchsorted(state_b.keys, state_a.keys[rows])
    assert np.array_equal(state_b.keys[pos], state_a.keys[rows])
    return pos


@pytest.mark.parametrize("law", ["ishima", "linear"])
def test_csv_forces_only_round_trip(sheared, tmp_path, law):
    system, state = sheared[law]
    rows = write_csv(tmp_path / "p.csv", system, state, reverse=(0, 3))
    s = read_csv(tmp_path / "p.csv")
    assert s.history is None and s.force_t is not None
    sys2, st2, rep = to_engine(s, law, system.material.params)
    assert rep.history_source == "force" and rep.flagged == []
    assert rep.counts == dict(listed=len(rows), kept=len(rows), dropped_apart=0,
                              dropped_fixed=0, added=0)
    b = _by_key(state, st2, rows)
    ours, back = state.contacts.hist[rows], st2.contacts.hist[b]
    assert np.abs(ours).max() > 1e-5          # the contacts do carry history
    # Error model: F_t = F - F_n (a difference of doubles ~ |F|), divided by the
    # stiffness k (kt sqrt(delta) or kt): |dt| <= 16 eps (|F| / k + |t|).
    f = system.contact_forces(state)[rows, :2]
    _, n = _touching(system, state)
    c = state.contacts
    delta = system.radius[c.i] + system.radius[c.j] - np.hypot(
        *((state.q[c.i, :2] - state.q[c.j, :2]) - np.column_stack(
            [c.k * state.shift + c.m * system.lx, c.k * system.ly])).T)
    kt = system.material.params["kt"] * (np.sqrt(delta[rows]) if law == "ishima" else 1.0)
    tol = 16 * EPS * (np.hypot(*f.T) / kt + np.hypot(*ours.T))
    assert np.all(np.hypot(*(back - ours).T) <= tol)
    # forces: the law at equal geometry and histories equal to 16 eps
    f2 = sys2.contact_forces(st2)[b]
    assert np.abs(f2 - system.contact_forces(state)[rows]).max() <= 16 * EPS * np.abs(f).max()
    assert rep.mismatch["worst_relative"] <= 1e-13
    # the Jacobian (free particles, histories by the increment rule): to 1e-12 relative
    _, k1 = jacobian(system, state)
    _, k2 = jacobian(sys2, st2)
    assert abs(k1 - k2).max() <= 1e-12 * abs(k1).max()
    # the imported state is the balanced one: residual ~ the relax tolerance of the fixture
    assert rep.residual["relative"] < 1e-9


def test_charan_inverse_grid():
    s = np.concatenate([np.linspace(0.0, 0.999, 1000), 1 - np.logspace(-3, -8, 6)])
    y = s + s * s - s ** 3
    back = charan_s(y)
    # y carries ~2 eps of rounding; ds = dy / phi'(s), phi' = (1 - s)(1 + 3 s): the
    # inverse is as good as y allows (plus 2 eps of its own)
    tol = 4 * EPS * (1 + 1 / ((1 - s) * (1 + 3 * s)))
    assert np.all(np.abs(back - s) <= tol)
    # through the law: the tangential force of history s t* inverted back to it
    kn, kt, mu, ri, rj, d = 1.0, 0.7, 0.4, 0.5, 0.35, 0.84
    delta = ri + rj - d
    tstar = mu * kn * delta / kt
    from fricstab.io.imports.contacts import history_from_force
    ft, t = [], []
    for sv in s[::10]:
        tv = sv * tstar * np.array([0.0, 1.0])        # tangential at n = (1, 0)
        f, _ = evaluate("charan", dx=d, dy=0.0, Ri=ri, Rj=rj, kn=kn, kt=kt, mu=mu,
                        tx=tv[0], ty=tv[1])
        ft.append([0.0, f[1]])
        t.append(tv)
    fn = np.full(len(t), kn * delta ** 1.5)
    hist, flags = history_from_force("charan", dict(kn=kn, kt=kt, mu=mu), fn, np.array(ft),
                                     np.tile([1.0, 0.0], (len(t), 1)), np.full(len(t), delta),
                                     np.full(len(t), ri), np.full(len(t), rj))
    sg = s[::10]
    assert not flags.any()
    assert np.all(np.abs(hist[:, 1] - np.array(t)[:, 1])
                  <= 8 * EPS * tstar * (1 + 1 / ((1 - sg) * (1 + 3 * sg))))


def _pair(ft, law_fn):
    """Two disks touching along x with the tangential force ``ft`` (y) on i."""
    return ImportedState(pos=np.array([[0.0, 0.0], [0.9, 0.0]]), radius=np.array([0.5, 0.5]),
                         ids=np.array([1, 2]), mass=np.ones(2), ci=np.array([1]),
                         cj=np.array([0]), force_n=np.array([[law_fn, 0.0]]),
                         force_t=np.array([[0.0, ft]]), units={"length": "m"},
                         sources=[("two.csv", "test")], contact_lines=(("two.csv", 7),))


@pytest.mark.parametrize("law", ["linear", "charan"])
def test_saturated_contact_flagged(law):
    kn, kt, mu = 2.0, 1.5, 0.5
    delta = 0.1
    fn = kn * delta ** (1.0 if law == "linear" else 1.5)
    # i = particle 1 (x = 0.9) pushed +x by j: normal force on i along +x
    for ft, flagged in ((mu * fn, True), (0.5 * mu * fn, False), (mu * fn * (1 - 1e-6), False)):
        sys_, st, rep = to_engine(_pair(ft, fn), law, dict(kn=kn, kt=kt, mu=mu))
        assert (rep.flagged != []) == flagged
        if flagged:
            assert rep.flagged[0]["where"] == "two.csv:7"
            tstar = mu * kn * delta / kt
            assert abs(np.hypot(*st.contacts.hist[0]) - tstar) <= 4 * EPS * tstar
        # our law's force at the stored history is the file's (4 eps: a few roundings)
        assert rep.mismatch["worst_relative"] <= 4 * EPS


def test_hertz_refuses_tangential_force(sheared, tmp_path):
    system, state = sheared["ishima"]
    write_csv(tmp_path / "p.csv", system, state)
    text = (tmp_path / "p.csv").read_text().splitlines()
    first = text.index("i,j,fnx,fny,ftx,fty") + 2          # 1-based line of the first contact
    s = read_csv(tmp_path / "p.csv")
    with pytest.raises(ParameterError, match=rf"p\.csv:{first}: contact .* law hertz"):
        to_engine(s, "hertz", {"kn": 1.0})


def test_length_unit_scales_jacobian(sheared, tmp_path):
    system, state = sheared["ishima"]
    write_csv(tmp_path / "p.csv", system, state)
    s = read_csv(tmp_path / "p.csv")
    p = system.material.params
    sys1, st1, rep1 = to_engine(s, "ishima", p)
    # the same packing with lengths counted in units half as large: L = 2; the
    # stiffnesses (force / length^(3/2)) are then 2^-3/2 of theirs, forces alike
    p2 = {k: v / 2 ** 1.5 for k, v in p.items()}
    sys2, st2, rep2 = to_engine(s, "ishima", p2, units={"length": 2.0})
    assert rep2.units["length"] == {"file": "d", "scale": 2.0, "given": True}
    assert rep1.units["force"]["scale"] == 1.0 and not rep1.units["force"]["given"]
    f1, k1 = jacobian(sys1, st1)
    f2, k2 = jacobian(sys2, st2)
    # every coordinate is a length (x, y, l = R theta), every force a force: K' = K / 2
    assert abs(k2 * 2 - k1).max() <= 1e-12 * abs(k1).max()
    assert np.abs(f2 - f1).max() <= 1e-12 * np.abs(sys1.contact_forces(st1)).max()
    b = _by_key(st1, st2, np.arange(st1.contacts.n))
    assert np.allclose(st2.contacts.hist[b], 2 * st1.contacts.hist, rtol=1e-13, atol=0)


def test_write_imported_rebuilds_and_relax(sheared, tmp_path):
    system, state = sheared["linear"]
    write_csv(tmp_path / "p.csv", system, state)
    sys2, st2, rep = to_engine(read_csv(tmp_path / "p.csv"), "linear", system.material.params)
    _, info = relax(sys2, st2)
    rep.relax = info
    assert info["converged"] and info["moved"] < 1e-9 and info["residual_after"] < 1e-12
    paths = write_imported(tmp_path / "out", sys2, st2, rep)
    assert all(p.exists() for p in paths)
    import json
    import scipy.sparse as sps
    doc = json.loads((tmp_path / "out" / "import.json").read_text())
    assert doc["counts"]["kept"] == rep.counts["kept"] and doc["history_source"] == "force"
    s3, st3 = system_from_state(tmp_path / "out" / "state.npz")
    _, k3 = jacobian(s3, st3)
    saved = sps.load_npz(tmp_path / "out" / "jacobian.npz")
    assert (abs(k3 - saved)).max() == 0.0


def test_dropped_and_added_contacts(sheared, tmp_path):
    system, state = sheared["ishima"]
    rows = write_csv(tmp_path / "p.csv", system, state)
    touch = {(int(state.contacts.i[r]), int(state.contacts.j[r])) for r in rows}
    apart = next((a, b) for a in range(system.n) for b in range(a + 1, system.n)
                 if (a, b) not in touch)
    lines = (tmp_path / "p.csv").read_text().splitlines()
    k = lines.index("i,j,fnx,fny,ftx,fty")
    del lines[k + 1]                                # a touching contact not listed: added
    lines.append(f"{apart[0] + 1},{apart[1] + 1},0,0,0,0")   # a pair apart: dropped
    (tmp_path / "q.csv").write_text("\n".join(lines) + "\n")
    _, _, rep = to_engine(read_csv(tmp_path / "q.csv"), "ishima", system.material.params)
    assert rep.counts == dict(listed=len(rows), kept=len(rows) - 1, dropped_apart=1,
                              dropped_fixed=0, added=1)
    assert rep.dropped[0]["where"].endswith(f"q.csv:{len(lines)}")
    assert rep.dropped[0]["why"].startswith("apart")


# ------------------------------------------------------------------ LAMMPS itself



# gran/hertz/history without damping (gamma 0) and a friction coefficient no contact
# reaches (xmu 1e4, the largest LAMMPS takes): Ishima's law with
# k_N = Kn sqrt(R_eff), k_T = Kt sqrt(R_eff).
LAMMPS_DECK = """units si
dimension 2
atom_style sphere
boundary p p p
read_data {data}
comm_modify vel yes
pair_style gran/hertz/history {kn} {kt} 0.0 0.0 1.0e4 0
pair_coeff * *
fix 1 all nve/sphere
fix 2 all enforce2d
timestep 1.0e-5
compute pl all property/local patom1 patom2
compute pf all pair/local dist fx fy fz p1 p2 p3 p4 cutoff radius
dump a all custom 100 {atoms} id type x y z radius
dump_modify a format float %.17g units yes
dump p all local 100 {pairs} c_pl[1] c_pl[2] c_pf[*]
dump_modify p format float %.17g
run 300
"""


def test_lammps_gran_hertz_history_forces(tmp_path):
    lammps = load_lammps()
    from fricstab.io.imports import read_lammps
    rng = np.random.default_rng(3)
    a, n_side, radius = 0.97, 3, 0.5          # a square lattice, every neighbour overlapping
    box = a * n_side
    pos = np.array([[a * (c + 0.5), a * (r + 0.5)] for r in range(n_side)
                    for c in range(n_side)])
    vel = rng.normal(0.0, 0.05, (len(pos), 2))
    omega = rng.normal(0.0, 0.2, len(pos))
    data = tmp_path / "pack.data"
    lines = ["9 disks", "", f"{len(pos)} atoms", "1 atom types", f"0 {box:.17g} xlo xhi",
             f"0 {box:.17g} ylo yhi", "-0.5 0.5 zlo zhi", "", "Atoms # sphere", ""]
    lines += [f"{i + 1} 1 {2 * radius:.17g} 1000.0 {x:.17g} {y:.17g} 0.0"
              for i, (x, y) in enumerate(pos)]
    lines += ["", "Velocities", ""] + [f"{i + 1} {v[0]:.17g} {v[1]:.17g} 0 0 0 {w:.17g}"
                                       for i, (v, w) in enumerate(zip(vel, omega))]
    data.write_text("\n".join(lines) + "\n")
    kn_l, kt_l = 2.0e5, 1.5e5
    atoms, pairs = tmp_path / "atoms.dump", tmp_path / "pairs.dump"
    lmp = lammps(cmdargs=["-log", "none", "-screen", "none"])
    try:
        for cmd in LAMMPS_DECK.format(data=data, atoms=atoms, pairs=pairs, kn=kn_l,
                                      kt=kt_l).splitlines():
            lmp.command(cmd)
    finally:
        lmp.close()
    s = read_lammps(data=data, dump=atoms, pairs=pairs, units="si",
                    columns=("id1", "id2", "dist", "fx", "fy", "fz", "p1", "p2", "p3", "p4"))
    assert s.n_contacts == 18                 # 2 per disk on the periodic lattice
    ratio = np.hypot(*s.force_t.T) / np.hypot(*s.force_n.T)
    assert ratio.min() > 1e-4                 # the contacts carry tangential history
    r_eff = math.sqrt(radius * radius / (2 * radius))
    params = {"kn": kn_l * r_eff, "kt": kt_l * r_eff}
    system, state, rep = to_engine(s, "ishima", params)
    assert rep.counts["kept"] == 18 and rep.counts["added"] == 0
    # Our forces at the imported state against LAMMPS' (fx fy + p1 p2): the normal
    # force is Hertz's with the same overlap from 17-digit positions, the tangential
    # one comes back through its history: a few roundings of each, far below 1e-10.
    f = system.contact_forces(state)
    ours = np.where(rep.swapped[:, None], f[rep.order, 3:5], f[rep.order, :2])
    theirs = s.force_n + s.force_t
    rel = np.hypot(*(ours - theirs).T) / np.hypot(*theirs.T)
    assert rel.max() <= 1e-10
    assert rep.mismatch["worst_relative"] == pytest.approx(rel.max(), rel=1e-6, abs=1e-16)
