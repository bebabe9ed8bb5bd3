"""DEM of a frictional periodic packing (fricstab.protocols.pack_dynamics): invariants, no timings."""

import numpy as np
import pytest

from fricstab.protocols import pack_dynamics as pdyn
from fricstab.laws import ParameterError
from fricstab.scenes.pack_system import Network, assemble, carry_history, network
from fricstab.scenes.packing import make_packing

EPS = np.finfo(float).eps


@pytest.fixture(scope="module")
def packing():
    return make_packing(32, 0.9, 3)


def _start(p, kt=1.0, amp=1e-3, seed=1, skin=pdyn.SKIN):
    v = np.random.default_rng(seed).normal(size=(p.n, 3)) * amp
    return pdyn.init_state(p.pos, p.radius, p.box, kt, v, skin=skin)


def test_forces_are_the_verified_assembly(packing):
    s = _start(packing)
    pdyn.run(s, 0.02, 300)
    net = network(s.q[:, :2] % packing.box, packing.radius, packing.box)
    hist = carry_history(s.pairs[:, :2], s.hist, net.pairs, packing.n)
    assert np.abs(hist).max() > 0  # the history did build up
    ref, _ = assemble(Network(net.pairs, net.sep, hist), packing.radius, 1.0)
    f = pdyn.forces(s)
    # Same kernel and inputs; only the summation order and the wrap of the
    # positions (ulp(L) ~ 1e-15) differ: a few eps of the largest contact force.
    assert np.abs(f - ref).max() <= 100 * EPS * np.abs(ref).max()


def test_momentum_is_conserved(packing):
    s = _start(packing)
    p0 = (s.mass[:, None] * s.v[:, :2]).sum(axis=0)
    pdyn.run(s, 0.02, 500)
    p1 = (s.mass[:, None] * s.v[:, :2]).sum(axis=0)
    # Pair forces cancel exactly in each pair (f_j = -f_i in the kernel), so the
    # momentum changes only by round-off of the velocity updates: 500 steps of
    # N eps |m v| each, far below 1e-12.
    net_force = pdyn.forces(s)[:, :2].sum(axis=0)
    assert np.abs(net_force).max() < 1e3 * EPS * np.abs(s.force).max(), net_force
    assert np.abs(p1 - p0).max() < 1e-12


def test_rebuilds_do_not_change_the_trajectory(packing):
    # A small skin forces many neighbour-list rebuilds (with history carried
    # over); a large one none.  Same arithmetic per contact, so the runs agree
    # to round-off amplified over the run (Lyapunov growth over t = 20 is mild
    # at this amplitude): 1e-10 of the displacement scale.
    a = _start(packing, amp=2e-2, skin=0.02)
    b = _start(packing, amp=2e-2, skin=0.6)
    ra = pdyn.run(a, 0.02, 1000)
    rb = pdyn.run(b, 0.02, 1000)
    assert ra.rebuilds > 3 and rb.rebuilds == 0
    d = (a.q[:, :2] - b.q[:, :2] + packing.box / 2) % packing.box - packing.box / 2
    assert np.abs(d).max() < 1e-10
    assert np.abs(a.v - b.v).max() < 1e-10


def test_energy_error_is_second_order_in_dt(packing):
    # Nearly frictionless (kt = 1e-4), so the non-conservative part of the
    # tangential law is negligible; the energy at t = 20 then differs from the
    # finest run by C dt^2 (velocity Verlet), and halving dt divides the
    # difference by 4, up to O(dt^2) corrections and the reference's own
    # error (dt_ref / dt)^2 <= 1/16: the ratio lies in [3, 5.5].
    def e_end(dt):
        s = _start(packing, kt=1e-4)
        pdyn.run(s, dt, int(round(20 / dt)))
        return pdyn.energy(s)

    ref = e_end(0.025)
    err = [abs(e_end(dt) - ref) for dt in (0.4, 0.2, 0.1)]
    assert 3.0 < err[0] / err[1] < 5.5 and 3.0 < err[1] / err[2] < 5.5, err


@pytest.mark.parametrize("kw, key", [({"kt": 0.0}, "kt"), ({"box": 1.0}, "box"),
                                     ({"skin": -1.0}, "skin")])
def test_bad_input(packing, kw, key):
    args = {"kt": 1.0, "box": packing.box, "skin": 0.1} | kw
    with pytest.raises(ParameterError, match=key):
        pdyn.init_state(packing.pos, packing.radius, args["box"], args["kt"], skin=args["skin"])


def test_bad_time_step(packing):
    s = _start(packing)
    with pytest.raises(ParameterError, match="dt"):
        pdyn.run(s, -0.1, 10)
