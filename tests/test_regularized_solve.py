"""The regularized sparse solve of Newton's singular fallback (fricstab.engine.newton)."""

import numpy as np
import scipy.sparse as sps
from hypothesis import given, settings
from hypothesis import strategies as st

from fricstab.engine.newton import regularized_solve


def _singular(rng, n, zero):
    """A symmetric positive semi-definite sparse K with the dofs ``zero`` decoupled (zero rows
    and columns: a disk without contacts) and a consistent right-hand side."""
    a = sps.random(n, n, density=0.2, random_state=rng) + sps.identity(n)
    k = (a @ a.T).tolil()
    k[zero, :] = 0.0
    k[:, zero] = 0.0
    x = rng.standard_normal(n)
    x[zero] = 0.0
    return k.tocsc(), k.tocsc() @ x


@settings(max_examples=30, deadline=None)
@given(seed=st.integers(0, 2**31 - 1), n=st.integers(6, 60))
def test_a_consistent_singular_system_is_solved_like_least_squares(seed, n):
    """Against dense minimum-norm least squares: the residual at rounding (the error model:
    the LU's backward error ~ eps cond(K + sI) ||x||, with cond <= 1e12 before refinement and
    one refinement step; bounded here by 1e-9 of ||rhs||) and the decoupled dofs unmoved."""
    rng = np.random.default_rng(seed)
    zero = rng.choice(n, size=max(1, n // 6), replace=False)
    k, rhs = _singular(rng, n, zero)
    x = regularized_solve(k, rhs)
    ref = np.linalg.lstsq(k.toarray(), rhs, rcond=None)[0]
    assert np.linalg.norm(k @ x - rhs) <= 1e-9 * np.linalg.norm(rhs)
    assert np.abs(x[zero]).max() <= 1e-9 * np.abs(ref).max()
    assert np.allclose(x, ref, rtol=0, atol=1e-8 * np.abs(ref).max())
