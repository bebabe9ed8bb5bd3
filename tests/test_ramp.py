"""Pair events along the chain ramp: detection and location by bisection."""

import numpy as np
import pytest

from fricstab.analysis.spectrum import complex_pairs, decompose, growth_rate, pair_indicator
from fricstab.protocols.ramp import relax_newton, run_ramp
from fricstab.scenes.chain import ChainScene, forces_and_jacobian, initial_state, mass_vector


@pytest.fixture(scope="module")
def ramp():
    return run_ramp(ChainScene(), 0.1, 1e-3, tol=1e-6, keep_states=True)


def _indicator_at(scene, ramp, event, fx):
    k = int(np.searchsorted(ramp.fx, event.fx_lo, side="right")) - 1
    s = relax_newton(scene.with_fx(fx), ramp.states[k]).state
    _, jac = forces_and_jacobian(scene.with_fx(fx), s)
    w = decompose(jac, mass_vector(scene), vectors=False).eigenvalues
    return pair_indicator(w, event.pair_center, event.radius)[0]


def test_every_event_is_bracketed_to_the_tolerance(ramp):
    scene = ChainScene()
    assert ramp.events, "the default ramp has pair events"
    assert ramp.residual.max() < 1e-12
    for e in ramp.events:
        assert e.located
        assert e.fx_hi - e.fx_lo <= 1e-6
        d_lo = _indicator_at(scene, ramp, e, e.fx_lo)
        d_hi = _indicator_at(scene, ramp, e, e.fx_hi)
        # The indicator changes sign across the bracket, the right way round.
        assert d_lo * d_hi < 0
        assert (d_hi < 0) == (e.kind == "birth")


def test_event_counts_match_the_spectra(ramp):
    """Pairs counted per step change exactly by the located events."""
    counts = np.array([len(complex_pairs(w)) for w in ramp.eigenvalues])
    births = np.array([sum(e.kind == "birth" and e.fx <= fx for e in ramp.events) for fx in ramp.fx])
    deaths = np.array([sum(e.kind == "death" and e.fx <= fx for e in ramp.events) for fx in ramp.fx])
    assert np.array_equal(counts, counts[0] + births - deaths)


def test_biorthonormal_eigenvectors_and_growth_rate():
    scene = ChainScene(fx=0.03)
    base = relax_newton(ChainScene(), initial_state(ChainScene())).state
    s = relax_newton(scene, base).state
    _, jac = forces_and_jacobian(scene, s)
    spec = decompose(jac, mass_vector(scene))
    a = jac / mass_vector(scene)[:, None]
    # Precondition before values: biorthonormality and the eigen-equations,
    # to rounding times the condition numbers (all < 1e4 here).
    assert np.abs(spec.left.conj().T @ spec.right - np.eye(len(a))).max() < 1e-8
    assert np.abs(a @ spec.right - spec.right * spec.eigenvalues).max() < 1e-9 * np.abs(a).max()
    w = complex_pairs(spec.eigenvalues)
    assert len(w) > 0
    assert growth_rate(spec.eigenvalues) > 0


def test_coarse_ramp_claims_only_verified_brackets():
    """At a coarse step every event reported as located is truly bracketed.

    (Two events inside one step can cancel and go unseen: the ramp step is a
    knob of the speed/accuracy trade, see docs/concepts/knobs.md.)
    """
    scene = ChainScene()
    coarse = run_ramp(scene, 0.1, 5e-3, tol=1e-6, keep_states=True)
    for e in coarse.events:
        if e.located:
            d_lo = _indicator_at(scene, coarse, e, e.fx_lo)
            d_hi = _indicator_at(scene, coarse, e, e.fx_hi)
            assert d_lo * d_hi < 0 and (d_hi < 0) == (e.kind == "birth")
