"""Cases of the ``lee_hurley`` proofs: the two forms' argument layouts, the
sampled configuration space (:data:`EXTREMES`, :data:`REGIMES`), the kernel
arguments of a case and the geometry read back from them.

Split from :mod:`fricstab.laws.verify_lee_hurley` (which re-exports every name
here); the module docstring there states the references and the case layout.
"""

import math
from dataclasses import dataclass

import mpmath
import numpy as np

from fricstab._numerics import contact_halfwidth, overlap_correction
from fricstab.generated import lee_hurley as _gen
from fricstab.generated import lee_hurley_wall as _gen_wall
from fricstab.laws.verify_common import pick_extreme

__all__ = ["EXTREMES", "LAWS", "LAW_INPUTS", "REGIMES", "WALL_EXTREMES", "ShearCase",
           "case_inputs", "lai_kt", "law_of", "sample_cases"]

#: The two forms this module proves.
LAWS = ("lee_hurley", "lee_hurley_wall")

#: Central-difference steps, times the column length: 1e-1 down to 1e-12 (the
#: other laws go down to 1e-14).
CENTRAL_STEPS = tuple(10.0 ** (-k / 2) for k in range(2, 25))

#: Ranges of the configuration space (ends sampled exactly).  The overlap is
#: relative to the smaller radius; Lai's k_t fit stays positive to
#: delta/R ~ 0.3 over these ranges, so 0.1 is the verified top.
EXTREMES = {
    "delta_over_R": (1e-12, 1e-1),
    "radius_ratio": (0.2, 5.0),
    "nu": (0.0, 0.49),
    "mus": (0.01, 2.0),
    "mur": (1e-4, 0.5),
}
#: The wall form: ``radius_ratio`` is Rw/R, up to a nearly flat wall (100 R).
WALL_EXTREMES = {**EXTREMES, "radius_ratio": (0.2, 100.0)}
#: (tangential slides, rolling slides) per regime.
REGIMES = {"stick": (False, False), "slide_t": (True, False),
           "slide_r": (False, True), "slide_both": (True, True)}
LAW_INPUTS = _gen.INPUTS


@dataclass(frozen=True)
class _Form:
    """Layout of one form's kernel arguments."""

    name: str
    gen: object
    n_args: int
    nq: int
    hist: tuple      # indices of ft, mr in the arguments
    rotations: tuple  # rotation columns


_FORMS = {
    10: _Form("lee_hurley", _gen, 10, 6, (8, 9), (2, 5)),
    9: _Form("lee_hurley_wall", _gen_wall, 9, 3, (7, 8), (2,)),
}


def _form(args):
    try:
        return _FORMS[len(args)]
    except KeyError:
        raise ValueError(f"{len(args)} arguments: neither lee_hurley (10) nor "
                         "lee_hurley_wall (9)") from None


def law_of(args):
    """The law (``lee_hurley`` or ``lee_hurley_wall``) whose kernel takes ``args``."""
    return _form(args).name


@dataclass(frozen=True)
class ShearCase:
    """One dimensionless ``lee_hurley`` configuration (module docstring).

    ``phi`` (the orientation of the pair) is unused by the wall form.
    """

    delta_over_R: float
    radius_ratio: float
    phi: float
    nu: float
    mus: float
    mur: float
    t_ratio: float
    r_ratio: float


def _pick(rng, ranges, key, p, log=True):
    return pick_extreme(rng, *ranges[key], p, log)


def _ratio(rng, slides, p):
    """|ratio| in [0, 1 - 1e-6] (stick) or [1 + 1e-6, 1e3] (slide), random sign."""
    u = rng.uniform()
    if slides:
        mag = 1 + 1e-6 if u < p / 2 else (1e3 if u < p else math.exp(rng.uniform(1e-6, math.log(1e3))))
    else:
        mag = 0.0 if u < p / 2 else (1 - 1e-6 if u < p else rng.uniform(0.0, 1 - 1e-6))
    return float(mag if rng.uniform() < 0.5 else -mag)


def sample_cases(n, seed, p_extreme=0.15, law="lee_hurley"):
    """``n`` cases, a quarter in each regime of :data:`REGIMES`, seeded.

    ``law`` picks the ranges (:data:`EXTREMES` or :data:`WALL_EXTREMES`); the
    pair's draws are those of the single-form sampler before the wall form.
    """
    ranges = WALL_EXTREMES if law == "lee_hurley_wall" else EXTREMES
    rng = np.random.default_rng(seed)
    names = list(REGIMES)
    out = []
    for k in range(n):
        st, sr = REGIMES[names[k % 4]]
        out.append(ShearCase(
            delta_over_R=_pick(rng, ranges, "delta_over_R", p_extreme),
            radius_ratio=_pick(rng, ranges, "radius_ratio", p_extreme),
            phi=float(rng.uniform(0.0, 2 * math.pi)),
            nu=_pick(rng, ranges, "nu", p_extreme, log=False),
            mus=_pick(rng, ranges, "mus", p_extreme), mur=_pick(rng, ranges, "mur", p_extreme),
            t_ratio=_ratio(rng, st, p_extreme), r_ratio=_ratio(rng, sr, p_extreme)))
    return out


def lai_kt(a, ri, rj, e_star, nu, log=math.log):
    """Lai's tangential stiffness (Lee & Hurley Eqs. A8, A9), written by hand."""
    def w(x):
        return 0.22 + 2.89 * x + 0.18 * nu - 10.31 * x * x + 1.75 * x * nu + 0.36 * nu * nu
    c = nu / (2 * (1 - nu))
    den = (log(2 * ri / a) + log(2 * rj / a) + 1 + w(a / ri) * (log(4 * ri / a) + c)
           + w(a / rj) * (log(4 * rj / a) + c))
    return math.pi * e_star / den if log is math.log else mpmath.pi * e_star / den


def _overlap(dx, dy, ri, rj):
    naive = ri + rj - math.hypot(dx, dy)
    return naive + overlap_correction(dx, dy, ri, rj, naive)


def _geometry(args):
    """(delta as the kernel sees it, radius 1, radius 2, normal (nx, ny)) of ``args``."""
    if _form(args).name == "lee_hurley":
        dx, dy, ri, rj = args[:4]
        r = math.hypot(dx, dy)
        return _overlap(dx, dy, ri, rj), ri, rj, (dx / r, dy / r)
    y, rad, rw = args[0], args[1], args[6]
    return rad - y, rad, rw, (0.0, 1.0)


def _materials(args):
    """(E*, nu, mus, mur, ft, mr) of ``args``."""
    f = _form(args)
    e_star, nu, mus, mur = args[4:8] if f.name == "lee_hurley" else args[2:6]
    return e_star, nu, mus, mur, args[f.hist[0]], args[f.hist[1]]


def case_inputs(case, radius=0.5, e_star=1.0, law="lee_hurley"):
    """Kernel arguments of a case: ``dx, dy, Ri, Rj, E, nu, mus, mur, ft, mr`` (pair) or
    ``y, R, E, nu, mus, mur, Rw, ft, mr`` (wall)."""
    r1, r2 = radius, radius * case.radius_ratio
    if law == "lee_hurley_wall":
        y = r1 - case.delta_over_R * min(r1, r2)
        delta = r1 - y  # as the kernel sees it
    else:
        r = r1 + r2 - case.delta_over_R * min(r1, r2)
        dx, dy = r * math.cos(case.phi), r * math.sin(case.phi)
        delta = _overlap(dx, dy, r1, r2)
    a = contact_halfwidth(delta, r1, r2)
    fn = math.pi * e_star * a * a * (r1 + r2) / (4 * r1 * r2)  # = k_n delta (A2, Johnson)
    rr = r1 * r2 / (r1 + r2)
    ft, mr = case.t_ratio * case.mus * fn, case.r_ratio * case.mur * rr * fn
    if law == "lee_hurley_wall":
        return (y, r1, e_star, case.nu, case.mus, case.mur, r2, ft, mr)
    return (dx, dy, r1, r2, e_star, case.nu, case.mus, case.mur, ft, mr)
