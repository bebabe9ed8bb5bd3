"""Hypothesis strategies for contact configurations, reaching the extremes.

Each parameter draws its end points exactly (``|t|/t* = 0`` and ``1``,
``delta/R = 1e-12`` and ``0.1``, ``kt/kn = 1e-10`` and ``10``, ``mu = 0.1``
and ``100``, radius ratio 1 and 1.4) as well as values in between,
log-uniformly where the range spans decades.  :func:`shear_cases` does the
same for the Lee & Hurley law (:mod:`fricstab.laws.verify_lee_hurley`), in
either form; its history ratios stay 1e-6 away from the caps (a ratio of
exactly 1 has its own tests).
"""

import math

from hypothesis import strategies as st

from fricstab.laws import verify_lee_hurley as lh
from fricstab.laws.verify import EXTREMES, Case

__all__ = ["cases", "corrupt_jacobian", "directions", "shear_cases"]


def _ranged(key, log=True):
    lo, hi = EXTREMES[key]
    if log:
        inner = st.floats(math.log(lo), math.log(hi)).map(math.exp)
    else:
        inner = st.floats(lo, hi)
    return st.one_of(st.sampled_from([lo, hi]), inner.map(lambda v: min(max(v, lo), hi)))


_angle = st.floats(0.0, 2 * math.pi)


@st.composite
def cases(draw):
    """A :class:`fricstab.laws.verify.Case` anywhere in the verified ranges."""
    phi = draw(_angle)
    tangent = draw(st.booleans())
    psi = phi + math.pi / 2 if tangent else draw(_angle)
    return Case(
        delta_over_R=draw(_ranged("delta_over_R")),
        t_ratio=draw(_ranged("t_ratio", log=False)),
        phi=phi, psi=psi,
        kt_over_kn=draw(_ranged("kt_over_kn")),
        mu=draw(_ranged("mu")),
        radius_ratio=draw(_ranged("radius_ratio", log=False)),
    )


def directions(n):
    """A Taylor-test direction with n components in [-1, 1], not all tiny."""
    return st.lists(st.floats(-1.0, 1.0), min_size=n, max_size=n).filter(
        lambda v: max(abs(x) for x in v) > 0.1)


def corrupt_jacobian(original):
    """Wrap a verifier's ``_mp_function(..., which)``: its ``force_jacobian`` comes back
    1e-3 (relative) too large, for mutation tests of the Taylor check."""
    def corrupted(*key):
        fn = original(*key)
        if "force_jacobian" not in key:
            return fn

        def wrapped(*args):
            *inputs, f, jac = args
            fn(*inputs, f, jac)
            jac *= 1.001
        return wrapped
    return corrupted


def _shear_ranged(ranges, key, log=True):
    lo, hi = ranges[key]
    inner = st.floats(math.log(lo), math.log(hi)).map(math.exp) if log and lo > 0 else st.floats(lo, hi)
    return st.one_of(st.sampled_from([lo, hi]), inner.map(lambda v: min(max(v, lo), hi)))


def _cap_ratio(slides):
    mag = (st.one_of(st.just(1 + 1e-6), st.just(1e3), st.floats(1 + 1e-6, 1e3)) if slides
           else st.one_of(st.just(0.0), st.just(1 - 1e-6), st.floats(0.0, 1 - 1e-6)))
    return st.tuples(mag, st.sampled_from([1.0, -1.0])).map(lambda p: p[0] * p[1])


@st.composite
def shear_cases(draw, law="lee_hurley"):
    """A ShearCase of ``law`` (pair or wall form) in any regime, reaching every range end."""
    ranges = lh.WALL_EXTREMES if law == "lee_hurley_wall" else lh.EXTREMES
    return lh.ShearCase(
        delta_over_R=draw(_shear_ranged(ranges, "delta_over_R")),
        radius_ratio=draw(_shear_ranged(ranges, "radius_ratio")),
        phi=draw(st.floats(0.0, 2 * math.pi)), nu=draw(_shear_ranged(ranges, "nu", log=False)),
        mus=draw(_shear_ranged(ranges, "mus")), mur=draw(_shear_ranged(ranges, "mur")),
        t_ratio=draw(_cap_ratio(draw(st.booleans()))),
        r_ratio=draw(_cap_ratio(draw(st.booleans()))))
