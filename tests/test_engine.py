"""The engine: contact search, history store, passes, integrators, relaxers.

Tolerances are stated with their error model next to each assertion.
"""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from fricstab.engine import Controls, Material, System, fire, newton, run
from fricstab.engine.contacts import build, contact_keys
from fricstab.engine.jacobian import jacobian
from fricstab.errors import ParameterError

from tests.system_proof import central_jacobian, complex_step_jacobian, engine_jacobian

EPS = np.finfo(float).eps
LAWS = {"hertz": {"kn": 1.0}, "charan": {"kn": 1.0, "kt": 0.5, "mu": 0.3},
        "ishima": {"kn": 1.0, "kt": 0.5}}


def _brute(q, radius, free, lx, ly, shift, skin):
    """Every pair and image within reach, by enumeration (reference)."""
    n = len(q)
    found = set()
    reach = 4
    for i in range(n):
        for j in range(i + 1, n):
            if not (free[i] or free[j]):
                continue
            kc = int(np.rint((q[i, 1] - q[j, 1]) / ly)) if ly > 0 else 0
            for k in (range(kc - reach, kc + reach + 1) if ly > 0 else [0]):
                # the x image nearest to the sheared image row k, +- reach
                mc = int(np.rint(((q[i, 0] - q[j, 0]) - k * shift) / lx)) if lx > 0 else 0
                for m in (range(mc - reach, mc + reach + 1) if lx > 0 else [0]):
                    dx = ((q[i, 0] - q[j, 0]) - k * shift) - m * lx
                    dy = (q[i, 1] - q[j, 1]) - k * ly
                    lim = radius[i] + radius[j] + skin
                    if dx * dx + dy * dy < lim * lim:
                        found.add((i, j, m, k))
    return found


@settings(max_examples=60, deadline=None)
@given(n=st.integers(2, 40), lx=st.sampled_from([0.0, 2.5, 7.0, 15.0]),
       ly=st.sampled_from([0.0, 2.5, 7.0, 15.0]), shift=st.floats(-20, 20),
       skin=st.sampled_from([0.0, 0.1, 0.5]), seed=st.integers(0, 2**31),
       unfold=st.booleans())
def test_neighbour_search_finds_every_pair_once(n, lx, ly, shift, skin, seed, unfold):
    """Cell list (>= 3 cells per periodic direction) or all images: the same set as brute force.

    Positions may lie several boxes away (the engine never folds them), and a
    box of 2.5 (< 3 cutoffs) takes the all-images branch.  Exact: a set.
    """
    rng = np.random.default_rng(seed)
    span = np.array([lx or 10.0, ly or 10.0])
    q = np.zeros((n, 3))
    q[:, :2] = rng.uniform(0, 1, (n, 2)) * span
    if unfold:
        q[:, 0] += rng.integers(-3, 4, n) * lx
        q[:, 1] += rng.integers(-3, 4, n) * ly
    radius = rng.uniform(0.3, 0.5, n)
    free = rng.uniform(size=n) < 0.8
    if ly == 0:
        shift = 0.0
    rows, keys = build(q, radius, free, lx, ly, shift, skin)
    got = {tuple(int(v) for v in r) for r in rows}
    assert len(got) == len(rows)  # no pair listed twice
    assert got == _brute(q, radius, free, lx, ly, shift, skin)
    assert np.all(np.diff(keys) > 0)  # sorted by key, unique


@pytest.mark.parametrize("box", [3.0, 3.0 * (1 + 1e-11), 3.0 * (1 + 1e-9)])
def test_a_box_of_exactly_three_cutoffs_lists_each_pair_once(box):
    """At lx = 3 cutoffs the cell list would have 2 cells (its widths carry a 1e-10
    margin), where neighbour cells -1 and +1 coincide: the all-images branch takes
    it (found by hypothesis in tests/test_packing.py: box 3, radii 0.5, skin 0)."""
    rng = np.random.default_rng(1)
    q = np.zeros((12, 3))
    q[:, :2] = rng.uniform(0, box, (12, 2))
    radius = np.where(np.arange(12) % 2, 0.5, 0.5 / 1.4)
    free = np.ones(12, bool)
    rows, keys = build(q, radius, free, box, box, 0.0, 0.0)
    assert np.all(np.diff(keys) > 0)
    assert {tuple(int(v) for v in r) for r in rows} == _brute(q, radius, free, box, box, 0.0, 0.0)


def test_keys_order_pairs_before_walls_and_refuse_far_images():
    k = contact_keys([0, 0, 0], [1, -1, 1], [0, 0, 1], [0, 0, 0], 5, 1)
    assert k[0] < k[2] < k[1]
    with pytest.raises(ParameterError, match="fold"):
        contact_keys([0], [1], [5000], [0], 5, 0)


def _packing(law, n=30, box=5.0, shift=0.37, seed=0, skin=0.2):
    rng = np.random.default_rng(seed)
    pos = rng.uniform(0, box, (n, 2))
    rad = rng.uniform(0.5, 0.7, n)
    system = System(Material(law, LAWS[law]), rad, rad ** 2, rad ** 4 / 2, lx=box, ly=box,
                    skin=skin)
    return system, system.state(pos, shift=shift)


@pytest.mark.parametrize("law", sorted(LAWS))
def test_assembled_jacobian_matches_complex_step_and_central(law):
    """Random overlapping disks, Lees-Edwards offset, random histories.

    Complex step of the independent reference assembly: <= 1e-10 of max|K|
    (round-off of ~100-flop blocks, 64 eps per block, summed over < 10
    contacts per dof: 1e-13 expected).  Central differences at h = 1e-7 of the
    engine's force function: truncation (h/delta)^2 with overlaps >= ~1e-2 plus
    round-off eps |F|/h: 1e-6.  Translations are zero modes to 32 eps.
    """
    system, state = _packing(law)
    rng = np.random.default_rng(1)
    state.contacts.hist[:] = rng.normal(scale=1e-2, size=state.contacts.hist.shape)
    k = engine_jacobian(system, state)
    scale = np.abs(k).max()
    assert np.abs(k - complex_step_jacobian(system, state, 1.0)).max() <= 1e-10 * scale
    assert np.abs(k - central_jacobian(system, state, 1e-7)).max() <= 1e-6 * scale
    full = engine_jacobian(system, state, free_only=False)
    for axis in (0, 1):
        e = np.zeros(full.shape[0])
        e[axis::system.dof] = 1.0
        assert np.abs(full @ e).max() <= 32 * EPS * np.abs(full).max()


def test_history_is_carried_across_rebuilds_by_key():
    system, state = _packing("charan")
    c = state.contacts
    c.hist[:] = np.arange(c.hist.size).reshape(c.hist.shape)
    before = {int(k): h.copy() for k, h in zip(state.keys, c.hist)}
    state.q[0, :2] += 0.05  # still within the skin: the same contacts
    system.rebuild(state)
    for key, h in zip(state.keys, state.contacts.hist):
        np.testing.assert_array_equal(h, before[int(key)])
    state.q[0, :2] += 3.0  # far: new contacts of particle 0 start at zero
    system.rebuild(state)
    for key, i, j, h in zip(state.keys, state.contacts.i, state.contacts.j, state.contacts.hist):
        if int(key) not in before:
            assert (i == 0 or j == 0) and not h.any()


def test_verlet_conserves_energy_of_frictionless_disks_at_second_order():
    """Hertz disks: energy error of velocity Verlet ~ dt^2: halving dt divides it by ~4.

    Measured ratio within [3, 5] (second order; the Hertz force is C1 at
    contact opening, which adds a small first-order part).
    """
    def drift(dt):
        system, state = _packing("hertz", n=20, box=6.0, skin=0.3)
        rng = np.random.default_rng(3)
        state.v[:, :2] = rng.normal(scale=0.05, size=(system.n, 2))
        def energy(s):
            f = 0.5 * np.sum(system.mass[:, None] * s.v[:, :2] ** 2)
            c = s.contacts
            d = (s.q[c.i, :2] - s.q[c.j, :2])
            d[:, 0] -= c.k * s.shift + c.m * system.lx
            d[:, 1] -= c.k * system.ly
            xi = system.radius[c.i] + system.radius[c.j] - np.hypot(d[:, 0], d[:, 1])
            return f + np.sum(0.4 * np.clip(xi, 0, None) ** 2.5)
        e0 = energy(state)
        run(system, state, dt, int(round(20.0 / dt)))
        return abs(energy(state) - e0)
    ratio = drift(0.02) / drift(0.01)
    assert 3.0 < ratio < 5.0


@pytest.mark.parametrize("law", ["charan", "ishima"])
def test_restart_from_saved_state_is_bit_identical(law):
    """The loop visits contacts and particles in a fixed order: a run split at a step
    boundary (state saved as arrays, forces carried) equals the uninterrupted one."""
    from fricstab.engine import State
    system, state = _packing(law, n=25, box=5.5)
    state.v[:, :2] = np.random.default_rng(2).normal(scale=0.05, size=(system.n, 2))
    a = state.copy()
    full = run(system, a, 0.01, 400)
    b = state.copy()
    half = run(system, b, 0.01, 200)
    saved = {k: np.array(v) for k, v in b.arrays().items()}
    c = State.from_arrays(saved)
    f = system.forces(c)  # forces of the saved state: no dashpots here, so exact
    run(system, c, 0.01, 400, forces=f, step0=200, meas=half.driven_force)
    assert np.array_equal(a.q, c.q) and np.array_equal(a.v, c.v)
    assert np.array_equal(a.contacts.hist, c.contacts.hist)
    assert full.steps == 400


@pytest.mark.parametrize("law", ["charan", "ishima"])
def test_chunks_and_signals(law, monkeypatch):
    """Returning to Python every CHUNK particle-steps changes no bit (Verlet with
    records and drag, FIRE), and a pending SIGTERM stops a run at a chunk's end."""
    import signal
    import sys

    from fricstab import signals
    from fricstab.engine import verlet
    system, state = _packing(law, n=25, box=5.5)
    state.v[:, :2] = np.random.default_rng(3).normal(scale=0.05, size=(system.n, 2))
    results = []
    for chunk in (1 << 30, 25 * 7):    # one call, and a return every 7 steps
        monkeypatch.setattr(verlet, "CHUNK", chunk)
        monkeypatch.setattr(sys.modules["fricstab.engine.fire"], "CHUNK", chunk)
        a = state.copy()
        rec = run(system, a, 0.01, 300, Controls(drag=0.5), record_every=10)
        b = state.copy()
        it, res = fire(system, b, 1e-9, 3000)
        results.append((a.q, a.v, a.contacts.hist, rec.q, b.q, b.contacts.hist, it, res))
    for x, y in zip(*results):
        assert np.array_equal(x, y)
    with signals.interruptible():
        signals._handler(signal.SIGTERM, None)   # as if the signal had arrived
        with pytest.raises(signals.Interrupted) as err:
            run(system, state.copy(), 0.01, 300)
    assert err.value.exit_code == 143 and "at step 0" in str(err.value)


def test_fire_and_newton_relax_a_frictionless_packing():
    """FIRE to max|F| < 1e-10, then Newton to 1e-14 (quadratic: few iterations)."""
    system, state = _packing("hertz", n=40, box=5.0, shift=0.0)
    it, res = fire(system, state, 1e-10, 200000)
    assert res < 1e-10 and it <= 200000
    out = newton(system, state, 1e-14, solver="bordered")
    assert out.converged and out.iterations <= 8
    f, _ = jacobian(system, state)
    assert np.abs(f).max() < 1e-14


def test_servo_holds_the_force_on_a_driven_lid():
    """A lid of driven disks pressed on free disks over a fixed floor of disks.

    The servo v_y = -g (N_target - N) reaches N within 1 % once the kinetic
    energy has been drained by the drag (steady state of a first-order loop).
    """
    nx = 6
    r = 0.5
    floor = np.column_stack([np.arange(nx) * 2 * r + r, np.zeros(nx)])
    bulk = np.column_stack([np.arange(nx) * 2 * r + r, np.full(nx, 1.0)])
    lid = np.column_stack([np.arange(nx) * 2 * r + r, np.full(nx, 2.02)])
    pos = np.vstack([floor, bulk, lid])
    n = len(pos)
    family = np.array([1] * nx + [0] * nx + [2] * nx)
    rad = np.full(n, r)
    system = System(Material("hertz", {"kn": 100.0}), rad, np.ones(n), np.full(n, 0.125),
                    family=family, lx=2 * r * nx, skin=0.2)
    state = system.state(pos)
    ctl = Controls(drag=2.0, servo=(0.05, 3.0, 0.05))
    out = run(system, state, 0.01, 40000, ctl)
    assert abs(out.driven_force[1] / 3.0 - 1.0) < 0.01


def test_driven_force_reads_only_the_driven_contacts_with_the_same_sums():
    """The servo's measured force summed over the driven-contact list equals, to the bit, the
    same sum over every contact in contact order (what the engine did before the list)."""
    from fricstab.engine import parallel, passes

    rng = np.random.default_rng(3)
    n, k = 40, 300
    family = rng.choice([0, 1, 2], n, p=[0.7, 0.15, 0.15])
    ci = np.sort(rng.integers(0, n, k))
    cj = np.where(rng.random(k) < 0.1, -1, rng.integers(0, n, k))
    live = (rng.random(k) < 0.8).astype(np.int8)
    fcon = rng.standard_normal((k, 6))
    drv = passes.driven_contacts(ci, cj, family)
    assert 0 < len(drv) < k and np.all(np.diff(drv) > 0)
    meas = np.zeros(8)
    passes.driven_force(drv, ci, cj, live, fcon, family, meas)
    want = [0.0, 0.0]
    for c in range(k):   # the loop over every contact, as the engine had it
        if cj[c] < 0 or not live[c]:
            continue
        for b in range(2):
            if family[ci[c]] == 2:
                want[b] += fcon[c, b]
            if family[cj[c]] == 2:
                want[b] -= fcon[c, b]
    assert meas[0] == want[0] and meas[1] == want[1]
    contacts = type("C", (), {"n": k, "i": ci, "j": cj})()
    system = type("S", (), {"n": n, "family": family, "radius": np.ones(n),
                            "damping_mass": np.ones(n), "damping_inertia": np.ones(n)})()
    assert np.array_equal(parallel.workspace(contacts, system, 2)[4], drv)
