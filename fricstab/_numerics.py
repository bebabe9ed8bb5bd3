"""Accurate overlap of two disks, hand-written and called by the generated kernels.

The overlap ``delta = R_i + R_j - sqrt(dx^2 + dy^2)`` of nearly touching disks
cancels catastrophically: with ``delta = 1e-12 R`` the naive float64 value has
a relative error up to ``eps (R_i + R_j) / delta ~ 1e-4``, and so do the force
(``delta^{3/2}``) and its Jacobian.  :func:`overlap_correction` returns the
difference between the overlap computed in double-double arithmetic
(error-free transformations: Knuth's two-sum, and the exact product error
from one fused multiply-add, which is the same number Dekker's FMA-free
splitting gives, to the bit, but 8 flops cheaper) and the naive one; the kernels add it to the real part of their naive overlap, so the
imaginary part that carries a complex-step derivative is untouched.

    delta = (S^2 - D) / (S + sqrt(D)),  S = R_i + R_j,  D = dx^2 + dy^2,

with ``S^2 - D`` accumulated exactly enough that its relative error is a few
``eps`` however small ``delta`` is.

:func:`cylinder_lambda` solves the implicit contact half-width ``a`` of two
parallel cylinders (Hertz for cylinders, Johnson 1985; Lee & Hurley Eq. A2):
``delta = a^2/(4 R*) [ln(4 R_i/a) + ln(4 R_j/a) - 1]`` with
``1/R* = 1/R_i + 1/R_j``, written as an equation for
``lam = ln(4 R_i/a) + ln(4 R_j/a) - 1 = ln(16 R_i R_j) - 1 - 2 ln a`` (an
affine function of ``ln a``, so Newton in ``lam`` is Newton in ``ln a``)::

    lam - ln(lam) = B,   B = ln(4 (R_i + R_j)/delta) - 1,
    a = 4 sqrt(R_i R_j) exp(-(lam + 1)/2).

The physical branch is ``lam > 1`` (``d delta/da > 0``, i.e.
``a < 4 sqrt(R_i R_j)/e``); it exists for ``B > 1``, i.e. below the turning
point ``delta < 4 (R_i + R_j)/e^2``.  In closed form ``lam = -W_{-1}(-e^{-B})``
(Lambert W, lower branch), which the tests use as the reference.
"""

import numpy as np
from llvmlite import ir
from numba import types
from numba.core import cgutils
from numba.extending import intrinsic

from fricstab._numba import kernel_jit

__all__ = ["contact_halfwidth", "cylinder_lambda", "overlap_correction", "overlap_correction_at",
           "turning_overlap"]

@intrinsic
def _fma(typingctx, a, b, c):
    """``a b + c`` rounded once (LLVM's fma: one instruction where the CPU has it, else libm)."""
    sig = types.float64(types.float64, types.float64, types.float64)

    def codegen(context, builder, signature, args):
        d = ir.DoubleType()
        fn = cgutils.get_or_insert_function(builder.module, ir.FunctionType(d, [d, d, d]),
                                            "llvm.fma.f64")
        return builder.call(fn, args)
    return sig, codegen


@kernel_jit
def _two_sum(a, b):
    s = a + b
    bb = s - a
    return s, (a - (s - bb)) + (b - bb)


@kernel_jit
def _two_prod(a, b):
    """``(p, e)`` with ``p = fl(a b)`` and ``a b = p + e`` exactly (no overflow or underflow)."""
    p = a * b
    return p, _fma(a, b, -p)


@kernel_jit
def overlap_correction(dx, dy, ri, rj, naive):
    """``delta_accurate - naive`` for real float64 inputs.

    Always computed (no threshold), so the overlap is a smooth function of the
    inputs to the last bit and finite differences see no switch.
    """
    return overlap_correction_at(dx, dy, ri, rj, naive, np.sqrt(dx * dx + dy * dy))


@kernel_jit
def overlap_correction_at(dx, dy, ri, rj, naive, r):
    """:func:`overlap_correction` with the centre distance ``r`` already known.

    ``r`` must be ``np.sqrt(dx * dx + dy * dy)`` exactly as the caller computed
    it (the generated ``<law>_advance``, ``_project`` and ``_rate`` kernels pass
    theirs, so the contact costs one square root); the result is then the same
    to the bit as :func:`overlap_correction`'s.
    """
    s_hi, s_lo = _two_sum(ri, rj)
    ss_hi, ss_lo = _two_prod(s_hi, s_hi)
    ss_lo += 2.0 * s_hi * s_lo
    xx_hi, xx_lo = _two_prod(dx, dx)
    yy_hi, yy_lo = _two_prod(dy, dy)
    # S^2 - dx^2 - dy^2 as an unevaluated sum of the high parts (exact with
    # two_sum) plus the low parts.
    n1, e1 = _two_sum(ss_hi, -xx_hi)
    n2, e2 = _two_sum(n1, -yy_hi)
    num = n2 + (e1 + e2 + ss_lo - xx_lo - yy_lo)
    accurate = num / (s_hi + r)
    return accurate - naive


#: Newton iterations allowed in :func:`cylinder_lambda`; from the start
#: ``lam = 2 B`` the iteration descends monotonically and needs < 10 steps
#: except within ~1e-6 of the turning point (linear convergence there).
_LAMBDA_MAXITER = 200


@kernel_jit
def cylinder_lambda(delta, ri, rj):
    """``lam = ln(4 R_i/a) + ln(4 R_j/a) - 1`` of a Hertz cylinder contact.

    Solves ``lam - ln lam = ln(4 (R_i + R_j)/delta) - 1`` (module docstring)
    by Newton's method on the real parts, from ``lam_0 = 2 B`` (to the right
    of the root: ``h(lam) = lam - ln lam - B`` is convex and increasing for
    ``lam > 1``, so the iterates decrease monotonically to the root), then
    one Newton correction in the inputs' own arithmetic so that a complex
    step ``delta + i h`` yields ``Im lam = h d lam/d delta`` to O(h^2).

    Parameters
    ----------
    delta, ri, rj : float64 or complex128
        Overlap (> 0) and radii (> 0), any consistent length unit.

    Returns
    -------
    lam : same type as ``delta``
        ``> 1``; ``d lam/d delta = -lam / ((lam - 1) delta)``.

    Raises
    ------
    ValueError
        When ``delta >= 4 (R_i + R_j)/e^2`` (the turning point of
        ``delta(a)``, beyond which no contact width exists on the physical
        branch), or ``delta <= 0``.
    """
    d, r1, r2 = delta.real, ri.real, rj.real
    if not d > 0.0:
        raise ValueError("cylinder_lambda: the overlap delta must be > 0")
    b = np.log(4.0 * (r1 + r2) / d) - 1.0
    if not b > 1.0:
        raise ValueError("cylinder_lambda: overlap delta at or beyond the turning point "
                         "4 (Ri + Rj)/e^2 of the Hertz cylinder law (no contact width)")
    lam = 2.0 * b
    for _ in range(_LAMBDA_MAXITER):
        step = (lam - np.log(lam) - b) * lam / (lam - 1.0)
        lam -= step
        if abs(step) <= 2.0e-16 * lam:
            break
    # One correction in the callers' arithmetic: exact residual 0 on the
    # real part, first-order imaginary part for complex-step differentiation.
    bz = np.log(4.0 * (ri + rj) / delta) - 1.0
    lz = lam + 0.0 * bz
    return lz - (lz - np.log(lz) - bz) * lz / (lz - 1.0)


@kernel_jit
def contact_halfwidth(delta, ri, rj):
    """Half-width ``a = 4 sqrt(R_i R_j) exp(-(lam + 1)/2)`` (see cylinder_lambda)."""
    lam = cylinder_lambda(delta, ri, rj)
    return 4.0 * np.sqrt(ri * rj) * np.exp(-0.5 * (lam + 1.0))


def turning_overlap(ri, rj):
    """The largest overlap with a contact width, ``4 (R_i + R_j)/e^2``."""
    return 4.0 * (ri + rj) / np.e ** 2
