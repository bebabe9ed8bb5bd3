"""The exclusion rule of an ensemble (:mod:`fricstab.analysis.stability`): a saddle or a
packing unstable to shear is excluded, a zero mode or a complex pair is not; the dense and
sparse routes give one verdict."""

import numpy as np
import pytest

import fricstab.analysis.stability as st
from fricstab.analysis.sparse_spectrum import ZERO_CLUSTER
from fricstab.errors import ParameterError
from fricstab.scenes.packing import make_packing
from fricstab.scenes.packing_friction import backbone, frictional, material

STABLE = -np.array([1.0, 0.5, 0.1, 2e-3])          # 1/time^2, scale 1


def test_a_stable_spectrum():
    s = st.classify(STABLE, 1.0)
    assert s.stable and s.reason == "" and s.n_unstable == 0 and s.max_real == -2e-3


def test_a_saddle_is_excluded():
    s = st.classify(np.r_[STABLE, 3e-4], 1.0)
    assert not s.stable and s.n_unstable == 1 and "saddle" in s.reason


def test_zero_modes_and_pairs_are_not_held_against_a_packing():
    """An eigenvalue inside the zero cluster (either sign; a disk without contacts) is a zero
    mode; a conjugate pair with a positive real part is a pair (the physics under study)."""
    w = np.r_[STABLE, 0.5 * ZERO_CLUSTER, -0.5 * ZERO_CLUSTER, 1e-3 + 2e-2j, 1e-3 - 2e-2j]
    s = st.classify(w, 1.0)
    assert s.stable and s.n_zero == 2 and s.n_pairs == 1
    # just above the cluster, a real eigenvalue is a saddle
    assert not st.classify(np.r_[STABLE, 2 * ZERO_CLUSTER], 1.0).stable


def test_unstable_to_shear_is_excluded():
    """G < -G_TOL |G_A| excludes; a G within the solve's error of zero does not."""
    assert not st.classify(STABLE, 1.0, g=-0.0147, g_a=0.3).stable
    assert st.classify(STABLE, 1.0, g=-1e-12, g_a=0.3).stable
    assert "unstable to shear" in st.classify(STABLE, 1.0, g=-0.0147, g_a=0.3).reason


@pytest.mark.parametrize("w, scale, match", [
    (np.array([np.nan]), 1.0, "finite"), (STABLE, 0.0, "positive"), (STABLE, np.inf, "finite")])
def test_bad_input(w, scale, match):
    with pytest.raises(ParameterError, match=match):
        st.classify(w, scale)


@pytest.fixture(scope="module")
def packing():
    return backbone(make_packing(48, 0.9, 0))


@pytest.mark.parametrize("law, params", [("hertz", {}), ("ishima", {"kt": 1.0})])
def test_a_prepared_packing_is_stable_by_both_routes(packing, law, params, monkeypatch):
    """A FIRE-prepared backbone is stable with G > 0 (dense); the soft end (forced by
    lowering DENSE_MAX) gives the same verdict and the same largest real eigenvalue, to the
    error model of the soft end (backward error ~eps, condition ~1 for the symmetric hertz;
    1e-8 of |A| leaves room for the non-normal ishima)."""
    fr = frictional(packing, material(law, **params))
    dense = st.packing_stability(fr.system, fr.state)
    assert dense.stable and dense.route == "dense" and dense.g > 0
    monkeypatch.setattr(st, "DENSE_MAX", 10)
    sparse = st.packing_stability(fr.system, fr.state, with_g=False, k=12)
    assert sparse.stable and sparse.route == "soft end" and np.isfinite(sparse.searched_radius)
    assert abs(sparse.max_real - dense.max_real) <= 1e-8 * dense.scale
    assert dense.to_json()["stable"] is True
