"""Accurate overlap of two disks, hand-written and called by the generated kernels.

The overlap ``delta = R_i + R_j - sqrt(dx^2 + dy^2)`` of nearly touching disks
cancels catastrophically: with ``delta = 1e-12 R`` the naive float64 value has
a relative error up to ``eps (R_i + R_j) / delta ~ 1e-4``, and so do the force
(``delta^{3/2}``) and its Jacobian.  :func:`overlap_correction` returns the
difference between the overlap computed in double-double arithmetic
(error-free transformations: Knuth's two-sum, and the exact product error
from one fused multiply-add, which is the same number Dekker's FMA-free
splitting gives, to the bit, but 8 flops cheaper) and the naive one; the
kernels add it to the real part of their naive overlap, so the imaginary part that carries a complex-step derivative is untouched.

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
from numba.extending import intrinsic, overload

from fricstab._numba import hot_inline_jit, kernel_jit

__all__ = ["LANE_COLUMNS", "contact_halfwidth", "cylinder_lambda", "overlap_correction",
           "overlap_correction_at", "pair_geometry", "pair_geometry_lanes", "pair_overlap",
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


#: Start of :func:`cylinder_lambda`: ``lam_0 = 1 + p P(p)/Q(p)`` with
#: ``p = sqrt(2 (B - 1))``, ``P = 1 + P1 p + ... + P5 p^5``, ``Q = 1 + Q1 p + ...
#: + Q4 p^4``.  The factor ``p`` and ``P1 - Q1 = 1/3`` give the expansion at the
#: turning point, ``lam = 1 + p + p^2/3 + O(p^3)``.  Fitted (iteratively
#: reweighted least squares towards minimax) to ``lam - 1`` from Lambert W
#: (mpmath, 30 digits) on 3,200 points of ``1 < B <= 50``: there
#: ``|lam_0 - lam| <= 1.9e-10 (lam - 1)`` (tests/test_lee_hurley.py checks it
#: with 4 eps for the rounding of ``1 + p P/Q``); for ``50 < B < 746`` (overlaps
#: below 1e-20 of the radius) ``<= 1e-6 (lam - 1)``.
_START_P = (0.9437952775552002, 0.3828234693460676, 0.07931520096951943,
            0.007781402799398173, 0.0002097403559440087)
_START_Q = (0.6104619511368012, 0.15155829746184796, 0.015542486393208915,
            0.00041956190862684156)
#: Largest B of the fit: one Newton step is enough up to it, two beyond.
_START_FIT_B = 50.0


@kernel_jit
def _lambda_start(b):
    """``lam_0`` of :func:`cylinder_lambda` for ``B = b > 1`` (see ``_START_P``)."""
    p = np.sqrt(2.0 * (b - 1.0))
    p2 = p * p
    p4 = p2 * p2
    # Estrin's scheme: three dependent steps instead of Horner's five
    num = (1.0 + _START_P[0] * p) + p2 * (_START_P[1] + _START_P[2] * p) \
        + p4 * (_START_P[3] + _START_P[4] * p)
    den = (1.0 + _START_Q[0] * p) + p2 * (_START_Q[1] + _START_Q[2] * p) + p4 * _START_Q[3]
    return 1.0 + p * num / den


@kernel_jit
def cylinder_lambda(delta, ri, rj):
    """``lam = ln(4 R_i/a) + ln(4 R_j/a) - 1`` of a Hertz cylinder contact.

    Solves ``h(lam) = lam - ln lam - B = 0``, ``B = ln(4 (R_i + R_j)/delta) - 1``
    (module docstring) on the real parts: a rational start ``lam_0(B)``
    (``_START_P``: within 1.9e-10 (lam - 1) of the root for B <= 50, i.e.
    overlaps down to 1e-20 of the radii), then Newton's method, which
    converges quadratically, ``e' = e^2 h''/(2 h') = e^2/(2 lam (lam - 1))``:
    after one step the error is below 2e-20 (lam - 1)/lam, far below an ulp,
    so one step is made and no stopping test is needed (two for B > 50,
    where the start is within 1e-6 (lam - 1)).  The step is the only
    logarithm besides B's; the old start ``2 B`` needed about five.  Last,
    the derivative in the inputs' own arithmetic: for complex inputs (a
    complex step ``delta + i h``) ``lam + lam/(lam - 1) (B_z - B)`` with
    ``B_z - B = i Im ln q = (q - Re q)/Re q + O(h^3)``, ``q = 4 (R_i + R_j)/delta``,
    so ``Im lam = h d lam/d delta`` to first order (the Newton correction of
    a converged real root, without a second logarithm of B); for real inputs
    ``B_z - B = 0`` and the compiled code returns lam as solved
    (:func:`_complex_step`).

    A deterministic cold start on purpose: warm-starting from the contact's
    width at the previous step would make lam (to the last bit) depend on the
    history of the solve, and a run resumed from a checkpoint, which does not
    store the width, would no longer be bit-identical to an uninterrupted
    one; the fitted start costs no logarithm and leaves one Newton step, as
    a warm start would.

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
    lam = _newton(_lambda_start(b), b)
    if b > _START_FIT_B:
        lam = _newton(lam, b)
    return _complex_step(lam, ri, rj, delta)


@kernel_jit
def _newton(lam, b):
    """One Newton step of ``lam - ln(lam) - B = 0`` (:func:`cylinder_lambda`)."""
    return lam - (lam - np.log(lam) - b) * lam / (lam - 1.0)


@kernel_jit
def pair_geometry(dx, dy, ri, rj, width):
    """``(r, delta, lam)`` of one pair contact, as a pair law's ``<law>_advance`` takes them.

    One lane of :func:`pair_geometry_lanes` (the engine's values to the bit);
    ``lam`` is 0.0 without a contact width (``width`` False: the law does not
    read it) or without contact (``delta <= 0``).
    """
    g = np.zeros((1, len(LANE_COLUMNS)))
    g[0, 0] = dx
    g[0, 1] = dy
    g[0, 2] = ri
    g[0, 3] = rj
    pair_geometry_lanes(g, 1, width)
    return g[0, 4], g[0, 5], g[0, 6]


@hot_inline_jit
def pair_overlap(dx, dy, ri, rj):
    """``(r, delta)``: centre distance ``sqrt(dx^2 + dy^2)`` and accurate overlap of a pair.

    ``delta = R_i + R_j - r`` plus :func:`overlap_correction_at`: what the
    generated kernels compute, to the bit.  The engine's contact loop calls
    it per contact for a law without a contact width and per lane
    (:func:`pair_geometry_lanes`) for one with.
    """
    r = np.sqrt(dx * dx + dy * dy)
    d = ri + rj - r
    return r, d + overlap_correction_at(dx, dy, ri, rj, d, r)


#: Columns of a lane of :func:`pair_geometry_lanes`.
LANE_COLUMNS = ("dx", "dy", "Ri", "Rj", "r", "delta", "lam", "B")


@hot_inline_jit
def pair_geometry_lanes(g, n, width):
    """The geometry of ``n`` pair contacts at once, each to the bit as one contact's.

    Row ``k`` of ``g`` is a lane (:data:`LANE_COLUMNS`): the caller fills
    ``dx, dy, Ri, Rj``; this writes ``r = sqrt(dx^2 + dy^2)``, the accurate
    overlap ``delta`` (:func:`overlap_correction_at`) and, if ``width``, for
    lanes with ``delta > 0`` the Hertz-cylinder ``lam`` of
    :func:`cylinder_lambda` (column ``B`` is its scratch).  Every lane takes
    the same operations in the same order as the scalar functions, so the
    values are theirs to the last bit; the lanes go through each stage
    together, so the processor overlaps their long chains of square roots,
    divisions and logarithms, which one contact at a time leaves waiting on
    each other (the solve of ``lam`` alone: 37.6 ns a contact one by one, 16.3
    in lanes of 16; docs/concepts/performance.md).  A lane with NaN ``delta``
    raises as :func:`cylinder_lambda` does.
    """
    for k in range(n):
        r, delta = pair_overlap(g[k, 0], g[k, 1], g[k, 2], g[k, 3])
        g[k, 4] = r
        g[k, 5] = delta
    if not width:
        return
    for k in range(n):
        d = g[k, 5]
        if d <= 0.0:   # no contact: no width (the kernels return before they need it)
            continue
        if not d > 0.0:
            raise ValueError("cylinder_lambda: the overlap delta must be > 0")
        b = np.log(4.0 * (g[k, 2] + g[k, 3]) / d) - 1.0
        if not b > 1.0:
            raise ValueError("cylinder_lambda: overlap delta at or beyond the turning point "
                             "4 (Ri + Rj)/e^2 of the Hertz cylinder law (no contact width)")
        g[k, 7] = b
        g[k, 6] = _lambda_start(b)
    for k in range(n):
        if g[k, 5] > 0.0:
            g[k, 6] = _newton(g[k, 6], g[k, 7])
    for k in range(n):
        if g[k, 5] > 0.0 and g[k, 7] > _START_FIT_B:
            g[k, 6] = _newton(g[k, 6], g[k, 7])


def _complex_step(lam, ri, rj, delta):
    """``lam + lam/(lam - 1) (B_z - B)`` (:func:`cylinder_lambda`).

    In Python this general form; compiled by numba (:func:`_complex_step_typed`)
    it is ``lam`` itself for real inputs, where ``B_z - B`` is exactly 0, so
    no division is spent on it.
    """
    q = 4.0 * (ri + rj) / delta
    return lam + lam * (q - q.real) / ((lam - 1.0) * q.real)


@overload(_complex_step, jit_options={"error_model": "numpy"})
def _complex_step_typed(lam, ri, rj, delta):
    if isinstance(delta, types.Complex):
        return _complex_step
    return lambda lam, ri, rj, delta: lam


@kernel_jit
def contact_halfwidth(delta, ri, rj):
    """Half-width ``a = 4 sqrt(R_i R_j) exp(-(lam + 1)/2) = sqrt(4 R* delta/lam)`` (cylinder_lambda).

    The second form, as the generated kernels compute it
    (symbolic.geometry.half_width): one square root, and a relative error e
    of lam moves it by e/2 instead of e lam/2.
    """
    lam = cylinder_lambda(delta, ri, rj)
    return np.sqrt(4.0 * ri * rj * delta / ((ri + rj) * lam))


def turning_overlap(ri, rj):
    """The largest overlap with a contact width, ``4 (R_i + R_j)/e^2``."""
    return 4.0 * (ri + rj) / np.e ** 2
