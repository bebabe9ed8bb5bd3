"""The engine on threads: every thread count gives the serial result to the bit.

The dynamics pass advances each contact into its own row and sums each
particle's rows in contact order (fricstab.engine.parallel), so 1 and 2
threads must agree exactly: ``np.array_equal`` on positions, velocities and
histories, no tolerance.  The threshold below which a system stays serial is
set to 0 here, so that even the chain's 10 disks take the threaded path.
"""

import copy
import functools
import json
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from fricstab.engine import Controls, fire, parallel, run
from fricstab.errors import NumericalError, ParameterError

pytestmark = pytest.mark.skipif(parallel.available_threads() < 2,
                                reason="needs NUMBA_NUM_THREADS >= 2")

REGRESSION = Path(__file__).resolve().parents[1] / "validation" / "regression"


@pytest.fixture
def threaded(monkeypatch):
    """Run a callable at 1 and at 2 threads (every system threaded); threads restored after."""
    monkeypatch.setattr(parallel, "PARALLEL_MIN", 0)
    top = parallel.available_threads()

    def at(threads, fn):
        parallel.set_threads(threads)
        try:
            return fn()
        finally:
            parallel.set_threads(top)
    return at


def _equal(a, b):
    assert len(a) == len(b)
    for x, y in zip(a, b):
        x, y = np.asarray(x), np.asarray(y)
        assert x.shape == y.shape and np.array_equal(x, y)


# Each scene is prepared once, on the first (1-thread) call; then advanced a few
# hundred steps on 1 and on 2 threads from copies of the same state.

@functools.lru_cache(maxsize=1)
def _chain_equilibrium():
    from fricstab.protocols.ramp import ramped_equilibrium
    from fricstab.scenes.chain import ChainScene
    sc = ChainScene()
    return sc, ramped_equilibrium(sc, 0.03)


def _chain():
    from fricstab.protocols.dynamics import default_dt
    from fricstab.scenes.chain import chain_system
    sc, eq = _chain_equilibrium()
    state = eq.copy()
    rec = run(chain_system(sc.with_fx(0.031)), state, default_dt(sc, 0.02), 300,
              record_every=50, record_hist=True)   # past F_c: the chain moves
    return state.q, state.v, state.contacts.hist, rec.q, rec.v, rec.hist, rec.forces


@functools.lru_cache(maxsize=1)
def _jammed():
    from fricstab.scenes.packing import make_packing
    return make_packing(64, 0.90, seed=0)


def _packing():
    from fricstab.scenes.packing_friction import material, packing_system
    p = _jammed()
    system = packing_system(p, material("ishima", kt=1.0), skin=0.1)
    state = system.state(p.pos)
    rng = np.random.default_rng(1)
    state.v[:] = 0.03 * rng.standard_normal((p.n, 3))   # enough to rebuild the list
    rec = run(system, state, 0.02, 200, Controls(drag=0.1), record_every=100)
    out = [state.q, state.v, state.contacts.hist, state.contacts.out, rec.q, rec.forces,
           state.rebuilds]
    state.q[:, :2] += 0.02 * rng.standard_normal((p.n, 2))
    system.rebuild(state)
    it, res = fire(system, state, 1e-9, 200)
    return out + [state.q, state.contacts.hist, it, res]


def _frictionless():
    """The frictionless ``hertz`` law: 2 dof a particle (the passes' variable-dof branch)."""
    from fricstab.scenes.packing_friction import material, packing_system
    p = _jammed()
    system = packing_system(p, material("hertz"), skin=0.1)
    state = system.state(p.pos)
    state.v[:] = 0.03 * np.random.default_rng(2).standard_normal((p.n, 3))
    rec = run(system, state, 0.02, 200, Controls(drag=0.1), record_every=100)
    return state.q, state.v, state.contacts.out, rec.q, rec.forces, state.rebuilds


@functools.lru_cache(maxsize=1)
def _prepared_cell():
    """A compressed 40-disk plane-shear cell at the start of shear (prepared once)."""
    from fricstab.protocols.shear_run import ShearRun, prepare
    from fricstab.scenes.shear import make_cell
    sim = ShearRun(make_cell({"n": 40, "seed": 3, "prep_tol": 0.1, "prep_ke": 1e-5}))
    prepare(sim)
    sim.start_shear()
    return sim


def _shear():
    sim = copy.deepcopy(_prepared_cell())
    sim.advance(200)   # servo lid, dashpots, walls of disks
    st = sim.state
    return st.q, st.v, st.contacts.hist, sim.forces, sim.meas, st.rebuilds


def _damped():
    """Damped to a force tolerance: the threads' residual and the step it stops at."""
    from fricstab.scenes.packing_friction import material, packing_system
    p = _jammed()
    system = packing_system(p, material("ishima", kt=1.0), skin=0.1)
    state = system.state(p.pos)
    state.v[:] = 0.01 * np.random.default_rng(3).standard_normal((p.n, 3))
    rec = run(system, state, 0.05, 20_000, Controls(drag=0.5), tol=1e-6, check_every=7)
    assert rec.converged
    return state.q, state.v, rec.forces, [rec.steps, rec.residual]


@pytest.mark.parametrize("scene", [_chain, _packing, _frictionless, _shear, _damped],
                         ids=["chain", "packing", "frictionless", "shear", "damped"])
def test_one_and_two_threads_agree_to_the_bit(threaded, scene):
    _equal(threaded(1, scene), threaded(2, scene))


def test_the_loop_with_a_parallel_region_per_pass_agrees_to_the_bit(threaded, monkeypatch):
    """Where the threads cannot share one region (parallel.team_ready false: numba's TBB
    layer), the loop meets them in a region per pass: the same bits."""
    one = threaded(1, _packing)
    monkeypatch.setattr(parallel, "team_ready", lambda n: False)
    _equal(one, threaded(2, _packing))


def test_threads_that_cannot_all_run_at_once_give_the_same_bits(threaded, monkeypatch):
    """A team of 3 on numba's 2 threads: one thread would run two members one after the
    other, and they would wait for each other forever.  The gate closes (every member
    returns before it changed anything), the run warns once and finishes with a region
    per pass: the same bits as 1 thread, and no later run tries a team again."""
    one = threaded(1, _packing)
    monkeypatch.setattr(parallel, "_team_failed", False)
    monkeypatch.setattr(parallel, "team_ready", lambda n: not parallel._team_failed)
    monkeypatch.setattr(parallel, "chunks", lambda n: 3)
    with pytest.warns(RuntimeWarning, match="did not run at once"):
        three = threaded(2, _packing)
    _equal(one, three)
    assert parallel._team_failed


@pytest.mark.parametrize("quantity", ["force", "position"])
def test_a_non_finite_value_on_a_thread_names_the_same_step_and_particle(threaded, quantity):
    """A NaN applied force (found by the second half kick: BAD_FORCE) or velocity (by the
    drift: BAD_STATE) on one particle: the same NumericalError at 1 and 2 threads (the
    step, the particle)."""
    from fricstab.scenes.packing_friction import material, packing_system
    p = _jammed()

    def failed():
        system = packing_system(p, material("ishima", kt=1.0), skin=0.1)
        state = system.state(p.pos)
        state.v[:] = 0.01 * np.random.default_rng(4).standard_normal((p.n, 3))
        rec = run(system, state, 0.02, 30)
        if quantity == "force":   # the saved (finite) forces: the drift of step 30 is fine
            system.external[41, 0] = np.nan
        else:
            state.v[41, 1] = np.nan
        with pytest.raises(NumericalError) as info:
            run(system, state, 0.02, 60, step0=30, forces=rec.forces)
        err = info.value
        return str(err), err.step, err.item, err.quantity
    one, two = threaded(1, failed), threaded(2, failed)
    assert one == two and one[2] == 41
    assert one[1:] == ((31, 41, "force") if quantity == "force" else (31, 41, "position"))


def test_packing_dynamics_at_two_threads_holds_the_pinned_regression(threaded):
    """The regression case (N = 256, 2,000 steps) on 2 threads: bit-equal to 1 thread,
    and within the pinned values' tolerances (validation/regression/tolerances.py)."""
    sys.path.insert(0, str(REGRESSION))
    from cases import CASES
    from tolerances import TOLERANCES
    one = threaded(1, CASES["packing_dynamics"])
    two = threaded(2, CASES["packing_dynamics"])
    pinned = json.loads((REGRESSION / "pinned.json").read_text())["packing_dynamics"]
    for key, (kind, value, _reason) in TOLERANCES["packing_dynamics"].items():
        new, old = np.asarray(two[key], float), np.asarray(pinned[key], float)
        assert np.array_equal(new, np.asarray(one[key], float))
        limit = {"exact": 0.0, "abs": value}.get(kind, value * float(np.max(np.abs(old))))
        assert np.max(np.abs(new - old)) <= limit


def test_a_law_refusing_an_overlap_on_a_thread_stops_the_run_with_one_line(threaded):
    """The kernel's ValueError cannot leave a thread: the engine raises it again
    outside, and the shear run turns it into its one-line NumericalError."""
    from fricstab.protocols.shear_run import ShearRun
    from fricstab.scenes.shear import make_cell

    def thrown():
        sim = ShearRun(make_cell({"n": 40, "seed": 3}))
        b = np.flatnonzero(sim.cell.kind == 0)[:2]
        d = sim.state.q[b[1], :2] - sim.state.q[b[0], :2]
        sim.state.v[b[0], :2] = 50 * d / np.linalg.norm(d)
        with pytest.raises(NumericalError, match="reduce dt_frac") as info:
            sim.advance(2000)
        return str(info.value)
    for text in (threaded(1, thrown), threaded(2, thrown)):
        assert "\n" not in text


def test_the_default_count_stays_serial_on_a_busy_machine_and_an_explicit_one_is_used(
        monkeypatch):
    monkeypatch.setattr(parallel, "_explicit", False)
    monkeypatch.setattr(parallel, "busy", lambda threads=None: True)
    assert parallel.chunks(10_000) == 1
    monkeypatch.setattr(parallel, "busy", lambda threads=None: False)
    assert parallel.chunks(10_000) == parallel.available_threads()
    assert parallel.chunks(parallel.PARALLEL_MIN - 1) == 1
    monkeypatch.setattr(parallel, "busy", lambda threads=None: True)
    parallel.set_threads(parallel.available_threads())
    assert parallel.chunks(10_000) == parallel.available_threads()


@pytest.mark.parametrize("bad", [0, -1, 10**6])
def test_a_thread_count_out_of_range_is_a_parameter_error(bad):
    with pytest.raises(ParameterError, match="threads must be between 1 and"):
        parallel.set_threads(bad)


def test_the_threads_option_of_the_command():
    from fricstab.cli import EXIT_OK, EXIT_USAGE, main
    top = parallel.available_threads()
    try:
        assert main(["--threads", "0", "laws"]) == EXIT_USAGE
        assert main(["--threads", str(top + 1), "laws"]) == EXIT_USAGE
        assert main(["--threads", "1", "laws"]) == EXIT_OK
    finally:
        parallel.set_threads(top)


def test_busy_counts_other_jobs_not_this_process(monkeypatch):
    """busy: the load average minus this process's own use, against the cores left free."""
    monkeypatch.setattr(parallel.os, "cpu_count", lambda: 2)
    monkeypatch.setattr(parallel.os, "getloadavg", lambda: (2.0, 2.0, 2.0))
    monkeypatch.setattr(parallel, "own_load", lambda: 1.9)   # the load is our own two threads
    assert not parallel.busy(2)
    monkeypatch.setattr(parallel, "own_load", lambda: 0.0)   # another job holds both cores
    assert parallel.busy(2)
    monkeypatch.setattr(parallel.os, "getloadavg", lambda: (1.0, 1.0, 1.0))
    assert parallel.busy(2)          # one core taken: two threads would wait for it
    assert not parallel.busy(1)      # one thread has the other core


def test_own_load_follows_this_process_cpu_use(monkeypatch):
    """A process that keeps one core busy for 1.2 s raises own_load by the exponential
    weight of that span: (1 - exp(-1.2/60)) (1 - before), exactly.

    The clocks are the test's own (wall and CPU time advance together, as for one
    busy core), so neither the machine's load nor its scheduler can move the result.
    """
    clock = {"wall": 1000.0, "cpu": 10.0}

    class FakeTime:
        @staticmethod
        def perf_counter():
            return clock["wall"]

        @staticmethod
        def process_time():
            return clock["cpu"]

    monkeypatch.setattr(parallel, "time", FakeTime)
    monkeypatch.setattr(parallel, "_own", [clock["wall"], clock["cpu"], 0.25])
    before = parallel.own_load()
    assert before == 0.25                      # under a second: no update
    clock["wall"] += 1.2
    clock["cpu"] += 1.2
    after = parallel.own_load()
    expected = before + (1.0 - np.exp(-1.2 / 60.0)) * (1.0 - before)
    assert abs(after - expected) <= 4 * np.finfo(float).eps   # a few roundings of O(1) terms
    clock["wall"] += 3.0                       # idle for 3 s: the estimate decays
    assert parallel.own_load() < after