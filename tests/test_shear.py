"""The plane-shear cell on the engine (fricstab.scenes.shear, fricstab.protocols.shear_run).

Scene (placement, laws and their defaults, units), the cell's System
(families, dashpot masses, contacts), collisions of two disks with the cell's
law and dashpots in the engine, the frames taken from the state, and the
named blow-up.  Tolerances carry their error model next to the assertion.
"""

import math

import numpy as np
import pytest

from fricstab.engine import Material, System, run
from fricstab.errors import NumericalError, ParameterError
from fricstab.generated.lee_hurley import lee_hurley_force
from fricstab.io.scenes import show, validate
from fricstab.protocols.shear_run import ShearRun, prepare
from fricstab.scenes.shear import (ISHIMA_KT_FACTOR, LAWS, _lee_hurley_contact, make_cell, material, restitution,
                                   typical_overlap, units_of)

SMALL = {"n": 40, "seed": 3}
EPS = np.finfo(float).eps


def test_cell_is_seeded_and_non_overlapping():
    a, b = make_cell(SMALL), make_cell(SMALL)
    assert np.array_equal(a.pos, b.pos) and np.array_equal(a.radius, b.radius)
    c = make_cell({**SMALL, "seed": 4})
    assert not np.array_equal(a.pos, c.pos)
    pos, r, lx = a.pos, a.radius, a.lx
    d = pos[:, None, :] - pos[None, :, :]
    d[..., 0] -= lx * np.round(d[..., 0] / lx)
    gap = np.hypot(d[..., 0], d[..., 1]) - (r[:, None] + r[None, :])
    np.fill_diagonal(gap, np.inf)
    both_wall = (a.kind[:, None] != 0) & (a.kind[None, :] != 0)
    # placement rejects any overlap; wall rows touch exactly (round-off 1e-12 radii)
    assert gap[~both_wall].min() > 0.0
    for k in (1, 2):
        row = np.sort(pos[a.kind == k, 0])
        rr = r[a.kind == k][np.argsort(pos[a.kind == k, 0])]
        assert math.isclose(2 * rr.sum(), lx, rel_tol=1e-12)
        assert np.allclose(np.diff(row), rr[:-1] + rr[1:], rtol=1e-12)
    bulk = r[a.kind == 0] * a.units.length
    assert bulk.min() >= 0.5e-6 and bulk.max() <= 1e-6
    # N = E* lx / kappa with E* the pressure unit
    assert math.isclose(a.n_target, a.lx / a.params["kappa"])


def test_bad_scene_values_name_the_key():
    for bad, key in (({"mus": -0.1}, "mus"), ({"kappa": -5.0}, "kappa"),
                     ({"n": 2}, "'n'"), ({"bogus": 1}, "bogus"), ({"nu": 0.7}, "nu"),
                     ({"law": "hertz", "mus": 0.5}, "mus is not a parameter of law hertz"),
                     ({"law": "charan", "kt": 0.0}, "kt")):
        with pytest.raises(ParameterError, match=key):
            make_cell({**SMALL, **bad})
    with pytest.raises(ParameterError, match="r_max"):
        make_cell({**SMALL, "r_min": 1e-6, "r_max": 0.5e-6})


@pytest.mark.parametrize("kappa", [10.0, 1e3, 1e4, 1e6])
def test_law_defaults_carry_the_force_of_lee_hurley_at_the_typical_overlap(kappa):
    """kn delta_0^(3/2) = f_n(lee_hurley, delta_0) = f_0 and kt delta_0^(1/2) = Lai's k_t.

    The kernel sees the overlap through dx = 2 - delta_0, rounded to eps: f_n
    is known to ~4 eps / delta_0 relative, so brentq meets f_0 to that (x8);
    the defaults are defined from the same kernel call, so they agree with it
    to a few roundings of the SI -> reduced conversion (64 eps).
    """
    p = validate("shear", {**SMALL, "kappa": kappa, "law": "charan"})
    u = units_of(p)
    m = material(p, u).params
    d0 = typical_overlap(kappa)
    fn, kt = _lee_hurley_contact(d0)
    assert math.isclose(fn, 2.0 / kappa, rel_tol=32 * EPS / d0)
    assert math.isclose(m["kn"] * d0 ** 1.5, fn, rel_tol=64 * EPS)
    assert math.isclose(m["kt"] * d0 ** 0.5, kt, rel_tol=64 * EPS)
    assert m["mu"] == 0.7
    ish = material(validate("shear", {**SMALL, "kappa": kappa, "law": "ishima"}), u).params
    assert math.isclose(ish["kt"], ISHIMA_KT_FACTOR * m["kt"], rel_tol=4 * EPS)
    lh = material(validate("shear", SMALL), u).params
    assert math.isclose(lh["E"], 1.0, rel_tol=4 * EPS) and lh["mus"] == 0.7


def test_every_law_is_listed_with_its_defaults():
    text = show("shear")
    for law in LAWS.names():
        assert f"law {law}:" in text
    assert "modulus" in text and "kn = f_n of lee_hurley" in text


def test_the_cell_system_has_families_dashpots_and_no_wall_wall_pairs():
    cell = make_cell(SMALL)
    system = cell.system()
    assert np.array_equal(system.family, cell.kind)
    wall_mass = cell.mass[cell.kind == 2].sum()
    assert np.all(system.damping_mass[cell.kind == 2] == wall_mass)
    assert np.all(np.isinf(system.damping_mass[cell.kind == 1]))
    assert np.all(np.isinf(system.damping_inertia[cell.kind != 0]))
    assert tuple(system.damping) == (0.1, 0.1, 0.3)
    state = system.state(cell.pos)
    c = state.contacts
    assert not np.any((cell.kind[c.i] != 0) & (cell.kind[c.j] != 0))
    # every pair within the skin is listed (brute force, minimum image in x)
    d = cell.pos[:, None] - cell.pos[None]
    d[..., 0] -= cell.lx * np.round(d[..., 0] / cell.lx)
    near = np.hypot(d[..., 0], d[..., 1]) < cell.radius[:, None] + cell.radius[None] + 0.2
    near &= (cell.kind[:, None] == 0) | (cell.kind[None] == 0)
    want = {(i, j) for i, j in zip(*np.nonzero(np.triu(near, 1)))}
    assert want == set(zip(c.i.tolist(), c.j.tolist()))


def _two_disks(v=1e-3, b=0.0, w=(0.0, 0.0), r=(1.0, 0.8), alpha=0.0, mus=0.7, mur=0.01):
    """Two free disks approaching along x with impact parameter b (reduced units)."""
    radius = np.array(r)
    mass = np.pi * radius ** 2
    inertia = 0.5 * mass * radius ** 2
    system = System(Material("lee_hurley", {"E": 1.0, "nu": 0.2, "mus": mus, "mur": mur}),
                    radius, mass, inertia, lx=1e3, skin=0.5,
                    damping=(alpha, alpha, 0.3 if alpha else 0.0))
    pos = np.array([[0.0, 0.0], [radius.sum() + 0.01, b]])
    vel = np.array([[v, 0.0], [-v * mass[0] / mass[1], 0.0]])
    return system, system.state(pos, vel=vel, omega=np.array(w, float))


def _energy(system, state):
    return 0.5 * np.sum(system.gmass * state.v ** 2)


def _momenta(system, state):
    m, q, v = system.mass, state.q, state.v
    p = (m[:, None] * v[:, :2]).sum(0)
    L = np.sum(m * (q[:, 0] * v[:, 1] - q[:, 1] * v[:, 0]) + system.inertia * v[:, 2])
    return p, L


def test_elastic_head_on_collision_conserves_energy_to_order_dt2():
    # Velocity Verlet: the energy after the contact ends differs from before by
    # O(dt^2), with a coefficient that depends on where the contact onset
    # falls between steps; averaged over onset phases (initial gaps) the error
    # must fall with slope 2 in dt (accept 1.5-2.6 from a fit over 8x in dt).
    dts = np.array([0.2, 0.1, 0.05, 0.025])
    errors = []
    for dt in dts:
        e = []
        for gap in np.linspace(0.0, dt * 1e-3, 5, endpoint=False):
            system, state = _two_disks()
            state.q[1, 0] += gap
            e0 = _energy(system, state)
            run(system, state, dt, int(round(60.0 / dt)))
            assert state.q[1, 0] - state.q[0, 0] > 1.8 + 0.01  # separated again
            e.append(abs(_energy(system, state) / e0 - 1.0))
        errors.append(np.mean(e))
    slope = np.polyfit(np.log(dts), np.log(errors), 1)[0]
    assert 1.5 < slope < 2.6, (errors, slope)
    assert errors[-1] < 1e-4


def test_oblique_frictional_collision_conserves_momenta():
    # Forces are equal and opposite: linear momentum is conserved to round-off.
    # Torque arms are the radii (T_i = R_i ft, T_j = R_j ft), not the distances
    # to the contact point, so angular momentum changes at the rate
    # delta * F_t per contact; |Delta L| must stay within the sum of
    # dt * delta * |F_t| over the steps (+5% for the Verlet staggering).
    system, state = _two_disks(v=2e-3, b=0.9, w=(0.01, -0.02), alpha=0.1, mus=0.3, mur=0.05)
    p0, L0 = _momenta(system, state)
    scale = np.abs(system.mass[:, None] * state.v[:, :2]).sum()
    dt, bound, f = 0.05, 0.0, None
    for _ in range(3000):
        out = run(system, state, dt, 1, forces=f)
        f = out.forces
        c = state.contacts
        if not c.n:
            continue
        cf = c.out[0, :2]
        d = state.q[0, :2] - state.q[1, :2]
        r = np.hypot(*d)
        delta = max(system.radius.sum() - r, 0.0)
        t = np.array([-d[1], d[0]]) / r
        bound += dt * delta * abs(cf @ t)
    p1, L1 = _momenta(system, state)
    assert np.allclose(p1, p0, atol=1e-12 * scale)
    assert bound > 0.0 and abs(L1 - L0) <= 1.05 * bound + 1e-14 * abs(L0), (L1 - L0, bound)
    assert np.any(state.v[:, 2] != [0.01, -0.02])   # the tangential force acted


def test_restitution_with_damping_is_below_one_and_near_linear_estimate():
    system, state = _two_disks(alpha=0.1)
    vrel0 = state.v[0, 0] - state.v[1, 0]
    run(system, state, 0.05, 3000)
    e = -(state.v[0, 0] - state.v[1, 0]) / vrel0
    # Hertz-cylinder stiffness is nearly linear (logarithmic in a), so e sits
    # near the linear spring-dashpot value 0.73; the band allows +-0.08 for the
    # stiffening of k_n(a) over the impact.
    assert abs(e - restitution(0.1)) < 0.08, e
    assert np.isclose((system.mass * state.v[:, 0]).sum(), 0.0, atol=1e-15)


def test_cell_forces_match_the_generated_kernel():
    # The engine's forces of a cell pair (no velocities) equal lee_hurley_force
    # (same sign conventions) to 1e-13 (a few roundings of one kernel call).
    rng = np.random.default_rng(7)
    for _ in range(20):
        ri, rj = rng.uniform(0.6, 1.4, 2)
        ang = rng.uniform(0, 2 * np.pi)
        r = (ri + rj) * (1 - rng.uniform(1e-5, 1e-2))
        pos = np.array([[0.0, 0.0], [r * np.cos(ang), r * np.sin(ang)]])
        ft, mr = rng.normal(0, 1e-3), rng.normal(0, 1e-5)
        radius = np.array([ri, rj])
        m = np.pi * radius ** 2
        system = System(Material("lee_hurley", {"E": 1.0, "nu": 0.2, "mus": 0.5, "mur": 0.01}),
                        radius, m, m * radius ** 2 / 2, lx=1e3, skin=0.1)
        state = system.state(pos)
        state.contacts.hist[0] = ft, mr
        got = system.forces(state)
        f = np.empty(6)
        lee_hurley_force(pos[0, 0] - pos[1, 0], pos[0, 1] - pos[1, 1], ri, rj, 1.0, 0.2, 0.5,
                         0.01, ft, mr, f)
        assert np.allclose(got.ravel(), f, rtol=1e-13, atol=1e-13 * np.abs(f).max())


@pytest.mark.parametrize("law", ["lee_hurley", "hertz", "charan", "ishima"])
def test_frames_hold_the_forces_on_the_top_row(law):
    """N and S of a frame are the summed contact forces on the top-row disks.

    Both are sums of the same contact forces in another order: 1e-12 of the
    largest contact force times the number of contacts.
    """
    cell = make_cell({**SMALL, "law": law, "kappa": 1e3, "inertial_number": 1e-3,
                      "prep_tol": 0.1, "prep_ke": 1e-5})
    sim = ShearRun(cell)
    prepare(sim)
    sim.start_shear()
    sim.advance(200)
    fr = sim.frame()
    assert fr["normal_force"] > 0
    ij, force = fr["contact_ij"], fr["contact_force"]
    top = cell.kind == 2
    on_top = np.where(top[ij[:, 0]], 1.0, 0.0) - np.where(top[ij[:, 1]], 1.0, 0.0)
    total = (on_top[:, None] * force).sum(0)
    scale = 1e-12 * max(np.abs(force).max(), 1e-300) * max(len(force), 1)
    assert abs(total[1] - fr["normal_force"]) <= scale
    assert abs(-total[0] - fr["shear_force"]) <= scale
    assert fr["contact_hist"].shape == (len(ij), {"hertz": 0}.get(law, 2))
    assert np.all(fr["contact_fn"] > 0)


def test_nan_stops_the_run_naming_step_and_particle():
    sim = ShearRun(make_cell(SMALL))
    sim.state.v[5, 1] = np.nan
    with pytest.raises(NumericalError, match=r"particle 5 at step 1"):
        sim.advance(3)


def test_an_overlap_beyond_the_law_stops_the_run_with_one_line():
    """A disk thrown at another at 50 sqrt(E*/rho): lee_hurley refuses the overlap
    (Lai's k_t beyond its fit) and the run stops with a NumericalError, not a
    ValueError from the kernel."""
    sim = ShearRun(make_cell(SMALL))
    b = np.flatnonzero(sim.cell.kind == 0)[:2]
    d = sim.state.q[b[1], :2] - sim.state.q[b[0], :2]
    sim.state.v[b[0], :2] = 50 * d / np.linalg.norm(d)
    with pytest.raises(NumericalError, match="reduce dt_frac") as info:
        sim.advance(2000)
    assert "\n" not in str(info.value)
