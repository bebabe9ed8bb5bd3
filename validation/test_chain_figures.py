"""Quick tier (CI) of Charan et al. Figs. 2-7 with the default protocol.

Full tier: `python validation/chain_waves.py` (Fig. 5) and
`python validation/chain_protocols.py` (Fig. 2 under protocol variants), both
recorded as claims (`python validation/reproduce.py --claim chain.v1
chain.protocol_damped`; their run times are in their records);
`fricstab chain ramp` / `fricstab chain dynamics` for the figures themselves
(seconds).  Each assertion states the paper's claim and
the tolerance.
"""

import json
from pathlib import Path

import numpy as np
import pytest

from fricstab.analysis.modes import transverse_mode
from fricstab.analysis.observables import first_breach, msd
from fricstab.analysis.spectrum import complex_pairs
from fricstab.protocols.dynamics import perturbed, run_dynamics
from fricstab.protocols.ramp import ramped_equilibrium, run_ramp
from fricstab.protocols.waves import fit_waves, run_realization
from fricstab.scenes.chain import ChainScene, time_unit

SCENE = ChainScene()
UNIT = time_unit(SCENE)


def _run(fx, duration, seed=0, frames=4000):
    eq = ramped_equilibrium(SCENE, fx)
    start = perturbed(SCENE, eq, 1e-9, np.random.default_rng(seed))
    return run_dynamics(SCENE.with_fx(fx), start, duration=duration * UNIT, frames=frames)


def test_fig2_pairs_at_the_papers_forces():
    """Paper: pairs at 0.03, 0.04, 0.083, 0.087, 0.090; none at 0.062.

    The Newton ramp agrees except at 0.062 (protocol dependence:
    validation/chain_protocols.md); pair counts are exact (LAPACK's real
    Schur blocks), so the check is exact.
    """
    res = run_ramp(SCENE, 0.1, 1e-3)
    counts = {round(fx, 3): len(complex_pairs(w)) for fx, w in zip(res.fx, res.eigenvalues)}
    assert all(counts[f] > 0 for f in (0.03, 0.04, 0.083, 0.087, 0.09))
    assert all(e.located for e in res.events)


@pytest.mark.parametrize("fx", [0.03, 0.04])
def test_fig3_instability_saturates_below_the_transition(fx):
    """Paper: at 0.03 and 0.04 M(t) becomes stationary at a minute value.

    Stationary: over the last half of 40,000 time units M changes by less
    than a factor 2 (the oscillation of the saturated orbit); minute: below
    1e-3 (2R)^2; and no wall contact reaches the Coulomb limit.
    """
    r = _run(fx, 40000.0)
    m = msd(r.positions)
    late = m[len(m) // 2:]
    assert late.max() < 2 * late.min() and late.max() < 1e-3
    tau, _ = first_breach(SCENE.with_fx(fx), r.times, r.positions, r.wall_hist)
    assert np.all(np.isnan(tau))


def test_fig3_4_7_transition_to_sliding_at_0_083():
    """Paper: at 0.083 the Coulomb law is breached and the chain slides forward.

    The trajectory is chaotic: its floating-point path (and so which frame sees
    a disk's first breach) differs between CPUs, so this asserts what every
    path shares, over four realizations (perturbation seeds 0-3):

    * every disk slides forward along the substrate by more than 0.1 (2R) in
      40,000 time units.  A wall contact can displace elastically by at most
      mu F_y / k_t = 1.75e-3 (2R) before the Coulomb cap holds its force, so a
      displacement 57 times that is sliding, and sliding is a breached contact.
      Measured on one CPU: 0.646-0.856 for every disk of the four seeds (a
      margin of 6x over 0.1);
    * at least one disk's breach is seen at a recorded frame (5 time units
      apart, `first_breach`; measured: all 10 disks in every seed).
    """
    elastic = SCENE.params["mu"] * SCENE.fy / SCENE.params["kt"]
    assert 0.1 > 50 * elastic
    for seed in range(4):
        r = _run(0.083, 40000.0, seed=seed, frames=8000)
        slid = r.positions[-1, :, 0] - r.positions[0, :, 0]
        assert slid.min() > 0.1, (seed, slid)
        tau, _ = first_breach(SCENE.with_fx(0.083), r.times, r.positions, r.wall_hist)
        assert np.isfinite(tau).any(), seed


def _recorded_wave_row(fx):
    """The full tier's row at ``fx`` as recorded (validation/records/chain.waves.json)."""
    rec = json.loads((Path(__file__).resolve().parent / "records" / "chain.waves.json").read_text())
    return next(r for r in rec["values"]["rows"] if abs(r["fx"] - fx) < 1e-9)


def test_fig5_wave_speeds_agree_with_the_full_tier():
    """V1 at F_x = 0.09 from 10 realizations against the full tier (25).

    Full tier: the recorded claim chain.v1 (``python validation/reproduce.py
    --claim chain.v1``, which runs validation/chain_waves.py).  Statistical
    tolerance: 3 combined standard errors (this tier's bootstrap error and the
    full tier's).  V2 scatters more than its bootstrap error between disjoint
    sets of realizations (the split error of chain_waves.md), so only its sign
    is checked here: the backward wave starts at the last disk.
    """
    full = _recorded_wave_row(0.09)
    eq = ramped_equilibrium(SCENE, 0.09)
    reals = [run_realization(SCENE.with_fx(0.09), eq, seed) for seed in range(10)]
    fit = fit_waves(reals, n_boot=200)
    assert abs(fit.v1 - full["v1"]) < 3 * np.hypot(fit.v1_err, full["v1_err"])
    assert fit.v2 > 0


def test_fig6_transverse_mode_frequency():
    """Paper: the transverse (y) mode has omega ~ 0.235 (paper units).

    At F_x = 0.083 the pair contacts couple the disks and shift it; the
    paper quotes two to three digits: tolerance 0.01.
    """
    eq = ramped_equilibrium(SCENE, 0.083)
    mode = transverse_mode(SCENE.with_fx(0.083), eq)
    assert abs(mode.omega - 0.235) < 0.01 and mode.y_fraction > 0.5
