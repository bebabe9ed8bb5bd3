"""Wave machinery on a few short realizations (the full study: validation/chain_waves.py)."""

import numpy as np

from fricstab.protocols.ramp import ramped_equilibrium
from fricstab.protocols.waves import fit_waves, run_realization
from fricstab.scenes.chain import ChainScene


def test_breaches_and_sliding_are_found_and_fitted():
    scene = ChainScene(fx=0.09)
    eq = ramped_equilibrium(ChainScene(), 0.09)
    reals = [run_realization(scene, eq, seed, duration=12000.0, frames=4000) for seed in range(3)]
    for r in reals:
        # Disk 0 is pushed: it reaches the Coulomb limit before the chain moves.
        assert np.isfinite(r.tau[0]) and np.nanmin(r.tau) == r.tau[0]
        assert np.all(np.isfinite(r.tau_slide))
        assert r.v_com > 0
    fit = fit_waves(reals, n_boot=50)
    assert fit.v1 > 0 and fit.v2 > 0 and fit.realizations == 3
    assert np.isfinite(fit.v1_err) and np.isfinite(fit.v2_err)
