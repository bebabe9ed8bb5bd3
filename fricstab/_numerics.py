"""Accurate overlap of two disks, hand-written and called by the generated kernels.

The overlap ``delta = R_i + R_j - sqrt(dx^2 + dy^2)`` of nearly touching disks
cancels catastrophically: with ``delta = 1e-12 R`` the naive float64 value has
a relative error up to ``eps (R_i + R_j) / delta ~ 1e-4``, and so do the force
(``delta^{3/2}``) and its Jacobian.  :func:`overlap_correction` returns the
difference between the overlap computed in double-double arithmetic
(error-free transformations of Dekker and Knuth, no FMA needed) and the naive
one; the kernels add it to the real part of their naive overlap, so the
imaginary part that carries a complex-step derivative is untouched.

    delta = (S^2 - D) / (S + sqrt(D)),  S = R_i + R_j,  D = dx^2 + dy^2,

with ``S^2 - D`` accumulated exactly enough that its relative error is a few
``eps`` however small ``delta`` is.
"""

import numpy as np

from fricstab._numba import kernel_jit

__all__ = ["overlap_correction"]

_SPLIT = 134217729.0  # 2^27 + 1, Veltkamp splitting of a double


@kernel_jit
def _two_sum(a, b):
    s = a + b
    bb = s - a
    return s, (a - (s - bb)) + (b - bb)


@kernel_jit
def _two_prod(a, b):
    p = a * b
    c = _SPLIT * a
    a_hi = c - (c - a)
    a_lo = a - a_hi
    c = _SPLIT * b
    b_hi = c - (c - b)
    b_lo = b - b_hi
    return p, ((a_hi * b_hi - p) + a_hi * b_lo + a_lo * b_hi) + a_lo * b_lo


@kernel_jit
def overlap_correction(dx, dy, ri, rj, naive):
    """``delta_accurate - naive`` for real float64 inputs.

    Always computed (no threshold), so the overlap is a smooth function of the
    inputs to the last bit and finite differences see no switch.
    """
    s_hi, s_lo = _two_sum(ri, rj)
    r2 = dx * dx + dy * dy
    ss_hi, ss_lo = _two_prod(s_hi, s_hi)
    ss_lo += 2.0 * s_hi * s_lo
    xx_hi, xx_lo = _two_prod(dx, dx)
    yy_hi, yy_lo = _two_prod(dy, dy)
    # S^2 - dx^2 - dy^2 as an unevaluated sum of the high parts (exact with
    # two_sum) plus the low parts.
    n1, e1 = _two_sum(ss_hi, -xx_hi)
    n2, e2 = _two_sum(n1, -yy_hi)
    num = n2 + (e1 + e2 + ss_lo - xx_lo - yy_lo)
    accurate = num / (s_hi + np.sqrt(r2))
    return accurate - naive
