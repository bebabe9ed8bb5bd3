"""The plane-shear DEM (fricstab.scenes.shear, fricstab.protocols.shear_dem): scene, neighbour list, integrator."""

import math

import numpy as np
import pytest

from fricstab.errors import NumericalError
from fricstab.laws import ParameterError
from fricstab.scenes.shear import Shear, make_cell, restitution
from fricstab.protocols import shear_dem as dem
from fricstab.generated.lee_hurley import lee_hurley_force

SMALL = {"n": 40, "seed": 3}


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
    assert math.isclose(a.n_target, a.lx / 1e4)


def test_bad_scene_values_name_the_key():
    for bad, key in (({"mu_s": -0.1}, "mu_s"), ({"kappa": -5.0}, "kappa"),
                     ({"n": 2}, "'n'"), ({"bogus": 1}, "bogus"), ({"nu": 0.7}, "nu")):
        with pytest.raises(ParameterError, match=key):
            make_cell({**SMALL, **bad})
    with pytest.raises(ParameterError, match="r_max"):
        make_cell({**SMALL, "r_min": 1e-6, "r_max": 0.5e-6})


def _brute_pairs(pos, radius, kind, lx, skin):
    out = []
    n = len(radius)
    for i in range(n):
        for j in range(i + 1, n):
            if kind[i] and kind[j]:
                continue
            dx = pos[i, 0] - pos[j, 0]
            dx -= lx * np.round(dx / lx)
            if math.hypot(dx, pos[i, 1] - pos[j, 1]) < radius[i] + radius[j] + skin:
                out.append((i, j))
    return out


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_neighbour_list_equals_brute_force(seed):
    rng = np.random.default_rng(seed)
    n, lx = 150, 20.0
    pos = np.column_stack([rng.uniform(-3 * lx, 3 * lx, n), rng.uniform(0, 15, n)])
    radius = rng.uniform(0.6, 1.3, n)
    kind = rng.choice(np.array([0, 0, 0, 1, 2], np.int8), n)
    pi, pj = dem.build_pairs(pos, radius, kind, lx, 0.3)
    assert list(zip(pi.tolist(), pj.tolist())) == _brute_pairs(pos, radius, kind, lx, 0.3)
    # narrow box (fewer than 3 cells in x): same answer, no duplicates
    pi, pj = dem.build_pairs(pos, radius, kind, 5.0, 0.3)
    assert list(zip(pi.tolist(), pj.tolist())) == _brute_pairs(pos, radius, kind, 5.0, 0.3)


def test_histories_follow_their_pair_key():
    oi, oj = np.array([0, 0, 2, 5]), np.array([1, 4, 3, 6])
    old = np.arange(8.0).reshape(4, 2) + 1
    ni, nj = np.array([0, 1, 2, 5, 5]), np.array([4, 2, 3, 6, 7])
    new = dem.carry_histories(10, oi, oj, old, ni, nj)
    assert np.array_equal(new, [[3, 4], [0, 0], [5, 6], [7, 8], [0, 0]])


def _two_disks(v=1e-3, b=0.0, w=(0.0, 0.0), r=(1.0, 0.8), alpha=0.0, mus=0.7, mur=0.01):
    """Two free bulk disks approaching along x with impact parameter b (reduced units)."""
    radius = np.array(r)
    mass = np.pi * radius ** 2
    inertia = 0.5 * mass * radius ** 2
    gap = 0.01
    pos = np.array([[0.0, 0.0], [radius.sum() + gap, b]])
    vel = np.array([[v, 0.0], [-v * mass[0] / mass[1], 0.0]])
    state = dict(pos=pos, vel=vel, angle=np.zeros(2), omega=np.array(w, float),
                 force=np.zeros((2, 2)), torque=np.zeros(2), radius=radius, mass=mass,
                 inertia=inertia, kind=np.zeros(2, np.int8),
                 law=np.array([1.0, 0.2, mus, mur, alpha, alpha, 0.3 if alpha else 0.0]))
    return state


def _collide(st, dt, nsteps):
    lx, skin = 1e3, 0.5
    pi, pj = dem.build_pairs(st["pos"], st["radius"], st["kind"], lx, skin)
    hist, cf, cfn = np.zeros((len(pi), 4)), np.zeros((len(pi), 2)), np.zeros(len(pi))
    csl = np.zeros(len(pi), np.int8)
    wall, ctrl = np.zeros(8), np.zeros(8)
    out = dem.run_steps(nsteps, st["pos"], st["vel"], st["angle"], st["omega"], st["force"],
                        st["torque"], st["radius"], st["mass"], st["inertia"], st["mass"],
                        st["inertia"], st["kind"], lx, pi, pj, hist, st["pos"].copy(), cf,
                        cfn, csl, st["law"], dt, skin, wall, ctrl)
    assert out[0] == dem.OK
    return out


def _energy(st):
    return 0.5 * (np.sum(st["mass"] * np.sum(st["vel"] ** 2, 1))
                  + np.sum(st["inertia"] * st["omega"] ** 2))


def _momenta(st):
    p = (st["mass"][:, None] * st["vel"]).sum(0)
    L = np.sum(st["mass"] * (st["pos"][:, 0] * st["vel"][:, 1] - st["pos"][:, 1] * st["vel"][:, 0])
               + st["inertia"] * st["omega"])
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
            st = _two_disks()
            st["pos"][1, 0] += gap
            e0 = _energy(st)
            _collide(st, dt, int(round(60.0 / dt)))
            assert st["pos"][1, 0] - st["pos"][0, 0] > 1.8 + 0.01  # separated again
            e.append(abs(_energy(st) / e0 - 1.0))
        errors.append(np.mean(e))
    slope = np.polyfit(np.log(dts), np.log(errors), 1)[0]
    assert 1.5 < slope < 2.6, (errors, slope)
    assert errors[-1] < 1e-4


def test_oblique_frictional_collision_conserves_momenta():
    # Forces are equal and opposite: linear momentum is conserved to round-off.
    # Torque arms are the radii (contract: T_i = R_i ft, T_j = R_j ft), not the
    # distances to the contact point, so angular momentum changes at the rate
    # delta * F_t per contact; |Delta L| must stay within the sum of
    # dt * delta * |F_t| over the steps (+5% for the Verlet staggering).
    st = _two_disks(v=2e-3, b=0.9, w=(0.01, -0.02), alpha=0.1, mus=0.3, mur=0.05)
    p0, L0 = _momenta(st)
    scale = np.abs(st["mass"][:, None] * st["vel"]).sum()
    dt, bound = 0.05, 0.0
    for _ in range(3000):
        out = _collide(st, dt, 1)
        cf = out[6][0]
        d = st["pos"][0] - st["pos"][1]
        r = np.hypot(*d)
        delta = max(st["radius"].sum() - r, 0.0)
        t = np.array([-d[1], d[0]]) / r
        bound += dt * delta * abs(cf @ t)
    p1, L1 = _momenta(st)
    assert np.allclose(p1, p0, atol=1e-12 * scale)
    assert bound > 0.0 and abs(L1 - L0) <= 1.05 * bound + 1e-14 * abs(L0), (L1 - L0, bound)
    assert np.any(st["omega"] != [0.01, -0.02])   # the tangential force acted


def test_restitution_with_damping_is_below_one_and_near_linear_estimate():
    st = _two_disks(alpha=0.1)
    m = st["mass"]
    vrel0 = st["vel"][0, 0] - st["vel"][1, 0]
    _collide(st, 0.05, 3000)
    e = -(st["vel"][0, 0] - st["vel"][1, 0]) / vrel0
    # Hertz-cylinder stiffness is nearly linear (logarithmic in a), so e sits
    # near the linear spring-dashpot value 0.73; the band allows +-0.08 for the
    # stiffening of k_n(a) over the impact.
    assert abs(e - restitution(0.1)) < 0.08, e
    assert np.isclose((m * st["vel"][:, 0]).sum(), 0.0, atol=1e-15)


def test_dem_forces_match_the_generated_kernel_without_damping():
    # With zero damping and zero velocities the DEM's assembly of the contact
    # quantities must equal lee_hurley_force (same sign conventions) to 1e-13.
    rng = np.random.default_rng(7)
    for _ in range(20):
        ri, rj = rng.uniform(0.6, 1.4, 2)
        ang = rng.uniform(0, 2 * np.pi)
        r = (ri + rj) * (1 - rng.uniform(1e-5, 1e-2))
        pos = np.array([[0.0, 0.0], [r * np.cos(ang), r * np.sin(ang)]])
        ft, mr = rng.normal(0, 1e-3), rng.normal(0, 1e-5)
        law = np.array([1.0, 0.2, 0.5, 0.01, 0.0, 0.0, 0.0])
        hist = np.array([[ft, mr, 0.0, 0.0]])
        force, torque = np.zeros((2, 2)), np.zeros(2)
        radius = np.array([ri, rj])
        m = np.pi * radius ** 2
        st = dem.compute_forces(pos, np.zeros((2, 2)), np.zeros(2), radius, m, m, np.zeros(2,
                                np.int8), 1e3, np.array([0]), np.array([1]), hist,
                                np.zeros((1, 2)), np.zeros(1), np.zeros(1, np.int8), law,
                                0.1, force, torque)
        assert st[0] == dem.OK
        f = np.empty(6)
        lee_hurley_force(pos[0, 0] - pos[1, 0], pos[0, 1] - pos[1, 1], ri, rj, 1.0, 0.2, 0.5,
                         0.01, ft, mr, f)
        got = np.array([force[0, 0], force[0, 1], torque[0], force[1, 0], force[1, 1],
                        torque[1]])
        assert np.allclose(got, f, rtol=1e-13, atol=1e-13 * np.abs(f).max())


def test_nan_stops_the_run_naming_step_and_particle():
    cell = make_cell(SMALL)
    sim = Shear(cell)
    cell.vel[5, 1] = np.nan
    with pytest.raises(NumericalError, match=r"particle 5 at step 1"):
        sim.advance(3)
