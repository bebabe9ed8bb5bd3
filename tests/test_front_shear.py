"""``fricstab.run_shear``: the plane-shear cell in one front-door call (issue 32).

A tiny cell (20 disks, loose preparation, five frames: seconds) returns finite
named series of one length, equal to the bit to a :class:`ShearRun` driven by
hand with the same parameters (the same operations in the same order); bad
arguments raise :class:`ParameterError`.
"""

import numpy as np
import pytest

import fricstab as fs
from fricstab.cli.shear import resolve_params
from fricstab.protocols.shear_run import FRAME, SPF, prepare

TINY = {"n": 20, "seed": 3, "strain": 5e-5, "dgamma": 1e-5, "kappa": 100.0, "prep_ke": 1e-3,
        "prep_tol": 0.1}
SERIES = ("gamma", "shear_stress", "normal_stress", "tau", "time", "servo_error", "height")


@pytest.fixture(scope="module")
def result():
    return fs.run_shear(**TINY)


def test_named_series_are_finite_and_consistent(result):
    n = round(TINY["strain"] / TINY["dgamma"]) + 1
    for name in SERIES:
        a = getattr(result, name)
        assert a.shape == (n,) and np.isfinite(a).all(), name
    assert result.gamma[-1] == pytest.approx(TINY["strain"], rel=1e-9)
    assert np.all(np.diff(result.time) > 0) and result.time[0] == 0.0
    # tau = S / N is the same ratio as the stresses (one division of each: 2 ulp)
    np.testing.assert_allclose(result.tau, result.shear_stress / result.normal_stress,
                               rtol=4e-16, atol=0)
    assert result.steps_per_frame >= 1 and result.state is result.run.state
    assert result.params["n"] == 20 and result.frames is None


def test_equals_shear_run_by_hand_to_the_bit(result):
    cell = fs.make_cell(resolve_params(overrides=TINY))
    sim = fs.ShearRun(cell)
    prepare(sim)
    sim.start_shear()
    frames = [sim.frame()]
    for k in range(1, round(TINY["strain"] / TINY["dgamma"]) + 1):
        sim.advance(int(sim.scalars[SPF]))
        sim.scalars[FRAME] = k
        frames.append(sim.frame())
    u = cell.units
    lx = cell.lx * u.length
    assert np.array_equal(result.gamma, [f["strain"] for f in frames])
    assert np.array_equal(result.tau, [f["tau"] for f in frames])
    assert np.array_equal(result.shear_stress, [f["shear_force"] / lx for f in frames])
    assert np.array_equal(result.state.q, sim.state.q)


@pytest.mark.parametrize("kwargs", [{"n": float("nan")}, {"n": -4}, {"strain": "x"},
                                    {"no_such_key": 1}, {"preset": "huge"},
                                    {"progress": "yes"}, {"keep_frames": 1},
                                    {"scene": "/no/such/file.toml"}, {"scene": 3.0},
                                    {"dgamma": 0.0}, {"strain": 1e-6, "dgamma": 1e-5}])
def test_bad_arguments_raise_parameter_error(kwargs):
    with pytest.raises(fs.ParameterError):
        fs.run_shear(**kwargs)


def test_the_dry_run_step_model_is_the_run_s_step_count(result):
    """``fricstab shear run --dry-run``'s time model counts the shear steps by the rule of
    ``start_shear`` (a copy of that rule in fricstab.cli.budget, which must not drift): the
    steps per frame of the run times its frames, exactly."""
    from fricstab.cli import budget
    frames = round(TINY["strain"] / TINY["dgamma"])
    assert budget.shear_steps(result.params) == frames * result.steps_per_frame
    est = budget.shear(result.params, count=3, dry_run=True)
    assert est["estimated_seconds"] == pytest.approx(
        3 * frames * result.steps_per_frame * TINY["n"] / budget.SHEAR_PARTICLE_STEPS, abs=0.1)
