"""Newtonian dynamics of a frictional periodic packing: ``fricstab.engine.run`` on a packing System.

Invariants, no timings: the forces are the verified law's, momentum is
conserved, neighbour-list rebuilds do not change the trajectory, the energy
error of velocity Verlet is second order.
"""

import numpy as np
import pytest

from fricstab.analysis.packing_energy import energy
from fricstab.engine import run
from fricstab.laws import ParameterError
from fricstab.scenes.packing import make_packing
from fricstab.scenes.packing_friction import material, packing_system

from tests.system_proof import reference_forces

EPS = np.finfo(float).eps


@pytest.fixture(scope="module")
def packing():
    return make_packing(32, 0.9, 3)


def _start(p, kt=1.0, amp=1e-3, seed=1, skin=0.1):
    system = packing_system(p, material("ishima", kt=kt), skin=skin)
    state = system.state(p.pos)
    state.v[:] = np.random.default_rng(seed).normal(size=(p.n, 3)) * amp  # (v_x, v_y, v_l)
    return system, state


def test_forces_are_the_verified_law(packing):
    system, state = _start(packing)
    run(system, state, 0.02, 300)
    assert np.abs(state.contacts.hist).max() > 0  # the history did build up
    ref = reference_forces(system, state)
    f = system.forces(state)
    # Same scalar kernels and inputs (the reference calls <law>_force contact by
    # contact); only the summation order differs: a few eps of the largest force.
    assert np.abs(f - ref).max() <= 100 * EPS * np.abs(ref).max()


def test_momentum_is_conserved(packing):
    system, state = _start(packing)
    p0 = (system.mass[:, None] * state.v[:, :2]).sum(axis=0)
    run(system, state, 0.02, 500)
    p1 = (system.mass[:, None] * state.v[:, :2]).sum(axis=0)
    # Pair forces cancel exactly in each pair (f_j = -f_i in the kernel), so the
    # momentum changes only by round-off of the velocity updates: 500 steps of
    # N eps |m v| each, far below 1e-12.
    f = system.forces(state)
    assert np.abs(f[:, :2].sum(axis=0)).max() < 1e3 * EPS * np.abs(f).max()
    assert np.abs(p1 - p0).max() < 1e-12


def test_rebuilds_do_not_change_the_trajectory(packing):
    # A small skin forces many neighbour-list rebuilds (with history carried
    # over by key); a large one none.  The engine sums the contacts in key
    # order, the same touching contacts either way, so the runs agree to
    # round-off amplified over the run: 1e-10 of the displacement scale.
    sa, a = _start(packing, amp=2e-2, skin=0.02)
    sb, b = _start(packing, amp=2e-2, skin=0.6)
    run(sa, a, 0.02, 1000)
    run(sb, b, 0.02, 1000)
    assert a.rebuilds > 3 and b.rebuilds == 0
    assert np.abs(a.q - b.q).max() < 1e-10
    assert np.abs(a.v - b.v).max() < 1e-10


def test_energy_error_is_second_order_in_dt(packing):
    # Nearly frictionless (kt = 1e-4), so the non-conservative part of the
    # tangential law is negligible; the energy at t = 20 then differs from the
    # finest run by C dt^2 (velocity Verlet), and halving dt divides the
    # difference by 4, up to O(dt^2) corrections and the reference's own
    # error (dt_ref / dt)^2 <= 1/16: the ratio lies in [3, 5.5].
    def e_end(dt):
        system, state = _start(packing, kt=1e-4)
        run(system, state, dt, int(round(20 / dt)))
        return energy(system, state)

    ref = e_end(0.025)
    err = [abs(e_end(dt) - ref) for dt in (0.4, 0.2, 0.1)]
    assert 3.0 < err[0] / err[1] < 5.5 and 3.0 < err[1] / err[2] < 5.5, err


def test_energy_needs_a_law_with_an_energy(packing):
    system = packing_system(packing, material("charan"))
    with pytest.raises(ParameterError, match="charan has no energy"):
        energy(system, system.state(packing.pos))


def _sheared_stress(fr, rate, strain, dt):
    """Newtonian shear at ``rate`` (Lees-Edwards offset rate ``rate L_y``, affine start):
    the shear stress at the strains 0, 5e-4, ... ``strain``."""
    from fricstab.engine import Controls
    from fricstab.protocols.stepstrain import shear_stress
    sy, st = fr.system, fr.state.copy()
    st.v[:] = 0.0
    st.v[:, 0] = rate * st.q[:, 1]
    steps = int(round(5e-4 / rate / dt))
    out = [shear_stress(sy, st)[0]]
    for _ in range(int(round(strain / 5e-4))):
        run(sy, st, dt, steps, Controls(shear_rate=rate * sy.ly))
        out.append(shear_stress(sy, st)[0])
    assert abs(st.shift - rate * st.time * sy.ly) <= 1e-12 * sy.ly  # the offset's rate
    return np.array(out)


def test_lees_edwards_shear_tends_to_the_quasistatic_path():
    """Frictionless (no history, so AQS is the quasistatic limit whatever the history
    convention): the stress of Newtonian shear at a constant Lees-Edwards rate approaches the
    AQS stress at the same strains linearly in the rate.  Error model: the dynamic stress is
    the quasistatic one plus a lag and elastic oscillations excited by the start, both
    O(rate) (measured 4.9, 0.54, 0.057 of the stress rise at rates 1e-3, 1e-4, 1e-5); a
    tenfold slower rate must shrink the largest deviation at least fivefold, and at 1e-5 it
    is below 0.15 of the stress rise."""
    from fricstab.protocols.aqs import run_aqs, spectrum
    from fricstab.scenes.packing_friction import backbone, frictional
    fr = frictional(backbone(make_packing(16, 0.9, 0)), material("hertz"))
    aqs = run_aqs(fr.system, fr.state, 0.004, 5e-4, locate_events=False)
    dt = 0.05 / np.sqrt(np.abs(spectrum(fr.system, fr.state)[0]).max())
    dev = {rate: np.abs(_sheared_stress(fr, rate, 0.004, dt) - aqs.stress).max()
           / np.ptp(aqs.stress) for rate in (1e-4, 1e-5)}
    assert dev[1e-5] <= 0.2 * dev[1e-4], dev
    assert dev[1e-5] <= 0.15, dev
