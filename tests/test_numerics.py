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
