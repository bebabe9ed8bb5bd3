"""The accurate overlap against 50-digit arithmetic.

Error model: the double-double accumulation of ``S^2 - dx^2 - dy^2`` is exact
to ~eps^2 S^2; one rounding for the sum, one for sqrt, one for the division
and one when the correction is added to the naive overlap: <= 8 eps relative.
The naive overlap would be off by up to eps S / delta (1e-4 at delta = 1e-12 S).
"""

import math

import mpmath
import numpy as np
from hypothesis import given
from hypothesis import strategies as st

from fricstab._numerics import overlap_correction

EPS = np.finfo(float).eps


@given(ri=st.floats(1e-3, 1e3), ratio=st.floats(1.0, 1.4), phi=st.floats(0, 2 * math.pi),
       log_rel=st.floats(-15.0, -1.0))
def test_overlap_is_accurate_to_a_few_ulps(ri, ratio, phi, log_rel):
    rj = ri * ratio
    r = (ri + rj) * (1 - 10.0 ** log_rel)
    dx, dy = r * math.cos(phi), r * math.sin(phi)
    naive = ri + rj - math.hypot(dx, dy)
    delta = naive + overlap_correction(dx, dy, ri, rj, naive)
    with mpmath.workdps(60):
        exact = mpmath.mpf(ri) + mpmath.mpf(rj) - mpmath.sqrt(mpmath.mpf(dx) ** 2 + mpmath.mpf(dy) ** 2)
        if exact <= 0:
            return
        rel = abs((mpmath.mpf(delta) - exact) / exact)
    assert rel <= 8 * EPS


@given(ri=st.floats(1e-3, 1e3), ratio=st.floats(0.2, 5.0), phi=st.floats(0, 2 * math.pi),
       log_rel=st.floats(-15.0, 0.0))
def test_overlap_from_a_known_distance_is_the_same_to_the_bit(ri, ratio, phi, log_rel):
    """overlap_correction_at with the caller's r = sqrt(dx*dx + dy*dy): the same operations."""
    from fricstab._numerics import overlap_correction_at

    rj = ri * ratio
    r = (ri + rj) * (1 - 10.0 ** log_rel)
    dx, dy = r * math.cos(phi), r * math.sin(phi)
    dist = float(np.sqrt(dx * dx + dy * dy))
    naive = ri + rj - dist
    assert overlap_correction_at(dx, dy, ri, rj, naive, dist) == overlap_correction(dx, dy, ri, rj, naive)


_SPLIT = 134217729.0  # 2^27 + 1


def _dekker_product(a, b):
    """Dekker's exact product without FMA (Veltkamp splitting): the reference."""
    p = a * b
    c = _SPLIT * a
    a_hi = c - (c - a)
    a_lo = a - a_hi
    c = _SPLIT * b
    b_hi = c - (c - b)
    b_lo = b - b_hi
    return p, ((a_hi * b_hi - p) + a_hi * b_lo + a_lo * b_hi) + a_lo * b_lo


@given(a=st.floats(-1e150, 1e150).filter(lambda x: x == 0 or abs(x) > 1e-140),
       b=st.floats(-1e150, 1e150).filter(lambda x: x == 0 or abs(x) > 1e-140))
def test_fused_exact_product_is_dekkers_to_the_bit(a, b):
    """The FMA product error equals the FMA-free one: both are the exact a b - fl(a b).

    Away from overflow and underflow (|a b| < 1e300, |a|, |b| > 1e-140) the
    error of a product is a double, unique, and both algorithms return it
    exactly: no tolerance.
    """
    from fricstab._numerics import _two_prod
    p, e = _two_prod(a, b)
    p_ref, e_ref = _dekker_product(a, b)
    assert (p, e) == (p_ref, e_ref)
    with mpmath.workdps(700):
        assert mpmath.mpf(a) * mpmath.mpf(b) == mpmath.mpf(p) + mpmath.mpf(e)
