"""Orbits of the chain's disks and of its centre of mass (Charan Figs. 3, 4 and 7).

Measures on recorded frames (``times`` (T,), ``positions`` (T, N, >= 2): x, y
and optionally theta, as :func:`fricstab.protocols.dynamics.run_dynamics`
records them) and an equilibrium (``State`` or an (N, >= 2) array):

* :func:`winding`: the signed number of turns of a displacement about the
  equilibrium (the sum of the frame-to-frame angle increments
  ``atan2(r_k x r_k+1, r_k . r_k+1)``) and the *monotonic fraction*, the share
  of those increments with the dominant sign.  A spiral (Charan Fig. 4: "A
  spiral in the x-y plane leads in time to an increase in y_i to the point that
  breaching the Coulomb law ... becomes inevitable") winds one way: fraction ~1;
  a back-and-forth line has cross products of either sign (or zero): ~1/2 or less.
  For an ellipse sampled at a phase step ``delta < pi`` every cross product is
  ``a b sin(delta) > 0`` whatever its aspect, so the frames need only resolve
  the period (two or more frames per half period).
* :func:`envelope_rate`: the e-folding rate of the orbit radius, a least-squares
  line through the log of its envelope (the largest radius in bins of
  ``bin_time``) over the linear-growth stretch (:func:`growth_window`), to be
  compared with the Jacobian's :func:`fricstab.analysis.spectrum.growth_rate`.
* :func:`disk_orbit`: those for one disk with the orbit's angular frequency
  and its aspect (x over y RMS amplitude), an :class:`Orbit`;
  :func:`mode_ellipse` the aspect and sense the Jacobian's growing mode predicts.
* :func:`amplitude_growth` and :func:`centre_growth`: the oscillation amplitude
  of C_y (Charan Fig. 7: "the y component of the centre of mass that oscillates
  without growth") late over early, against the disks' own y amplitudes over
  the same windows; :func:`sliding_velocity`: the slope of C_x after the
  transition (Fig. 7's "fixed velocity").

Times are in whatever unit ``times`` carries (the validation passes Charan's
``sqrt(m 2R / k_n)``); rates come back per that unit.
"""

import math
from dataclasses import dataclass

import numpy as np

from fricstab.errors import ParameterError, check_finite_array, check_int, check_real

__all__ = ["MIN_FRAMES", "Orbit", "amplitude", "amplitude_growth", "centre_growth",
           "disk_orbit", "displacement", "envelope", "envelope_rate", "growth_window",
           "mode_ellipse", "sliding_velocity", "winding"]

#: Fewest frames any measure accepts.
MIN_FRAMES = 8


@dataclass(frozen=True)
class Orbit:
    """One disk's orbit about its equilibrium (see :func:`disk_orbit`)."""

    disk: int
    turns: float             # signed turns over the analysed frames
    monotonic: float         # share of angle increments with the dominant sign
    omega: float             # mean angular frequency 2 pi |turns| / duration
    rate: float              # envelope e-folding rate over the growth window
    window: tuple            # (t0, t1) of that fit
    residual: float          # RMS of log(envelope) about the fitted line
    aspect: float            # x over y RMS amplitude over the growth window


def _frames(times, positions=None):
    """Checked float arrays (times, positions); ParameterError on too few frames or NaN."""
    t = np.asarray(check_finite_array("times", times, ndim=1), dtype=float)
    if t.size < MIN_FRAMES:
        raise ParameterError(f"times: need at least {MIN_FRAMES} frames, got {t.size}")
    if np.any(np.diff(t) <= 0):
        raise ParameterError("times must increase strictly")
    if positions is None:
        return t, None
    p = np.asarray(check_finite_array("positions", positions, ndim=3), dtype=float)
    if p.shape[0] != t.size or p.shape[2] < 2:
        raise ParameterError(f"positions must have shape ({t.size}, N, >= 2), got {p.shape}")
    return t, p


def _equilibrium_xy(equilibrium, n):
    """(N, 2) equilibrium positions from a State (its ``q``) or an array."""
    q = getattr(equilibrium, "q", equilibrium)
    q = np.asarray(check_finite_array("equilibrium", q, ndim=2), dtype=float)
    if q.shape[0] != n or q.shape[1] < 2:
        raise ParameterError(f"equilibrium must have shape ({n}, >= 2), got {q.shape}")
    return q[:, :2]


def displacement(positions, equilibrium, disk):
    """(T, 2): ``(x - x0, y - y0)`` of ``disk`` about its equilibrium position."""
    p = np.asarray(check_finite_array("positions", positions, ndim=3), dtype=float)
    check_int("disk", disk, 0, p.shape[1] - 1)
    return p[:, disk, :2] - _equilibrium_xy(equilibrium, p.shape[1])[disk]


def winding(d):
    """(turns, monotonic fraction) of a displacement ``d`` (T, 2) about the origin.

    ``turns`` is the signed sum of the increments ``atan2(cross, dot)`` of
    consecutive frames over 2 pi (positive: anticlockwise; a reversal through
    the origin, cross = 0, counts 0); the fraction is the share of increments
    whose sign is the dominant one (zero counts against).
    """
    d = np.asarray(check_finite_array("displacement", d, ndim=2), dtype=float)
    if d.shape[0] < MIN_FRAMES or d.shape[1] != 2:
        raise ParameterError(f"displacement must have shape (>= {MIN_FRAMES}, 2), got {d.shape}")
    a, b = d[:-1], d[1:]
    cross = a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]
    dot = (a * b).sum(axis=1)
    # cross = 0 with dot < 0 is a reversal through the origin, +-pi alike: no turn.
    turns = float(np.where(cross == 0, 0.0, np.arctan2(cross, dot)).sum() / (2 * math.pi))
    sign = np.sign(cross)
    fraction = max((sign > 0).mean(), (sign < 0).mean())
    return turns, float(fraction)


def envelope(times, radius, bin_time):
    """(bin centre times, largest radius per bin) over consecutive bins of ``bin_time``."""
    t, _ = _frames(times)
    r = np.asarray(check_finite_array("radius", radius, shape=(t.size,)), dtype=float)
    check_real("bin_time", bin_time, 0.0, low_open=True)
    k = np.floor((t - t[0]) / bin_time).astype(int)
    edges = np.flatnonzero(np.diff(k)) + 1
    starts = np.concatenate([[0], edges])
    ends = np.concatenate([edges, [t.size]])
    centres = np.array([0.5 * (t[s] + t[e - 1]) for s, e in zip(starts, ends)])
    return centres, np.maximum.reduceat(r, starts)


def growth_window(times, env, low=10.0, high=1e-4):
    """(t0, t1): where an envelope has grown ``low`` x past its first bin, until it first
    exceeds ``high`` x its last bin (the transient before, the nonlinear end after).

    ParameterError if that leaves fewer than 3 bins (no linear-growth stretch).
    """
    t = np.asarray(check_finite_array("times", times, ndim=1), dtype=float)
    e = np.asarray(check_finite_array("envelope", env, shape=(t.size,)), dtype=float)
    check_real("low", low, 1.0)
    check_real("high", high, 0.0, 1.0, low_open=True)
    if t.size < 3 or np.any(e <= 0):
        raise ParameterError("envelope: need at least 3 positive bins")
    above = np.flatnonzero(e >= low * e[0])
    top = np.flatnonzero(e >= high * e[-1])
    i0 = int(above[0]) if above.size else t.size
    i1 = int(top[0]) if top.size else t.size - 1
    if i1 - i0 < 2:
        raise ParameterError(f"no linear-growth stretch: the envelope grows from {e[0]:.3g} to "
                             f"{e[-1]:.3g} (needs {low:g}x past the start below {high:g}x the end)")
    return float(t[i0]), float(t[i1])


def envelope_rate(times, radius, bin_time, window=None, low=10.0, high=1e-4):
    """(rate, (t0, t1), residual): slope of log(envelope) against time over ``window``.

    ``window`` defaults to :func:`growth_window`; ``residual`` is the RMS of
    log(envelope) about the line (0 for a pure exponential sampled at its peaks).
    """
    tc, env = envelope(times, radius, bin_time)
    if np.any(env <= 0):
        raise ParameterError("radius: the envelope must be positive (the disk never moved)")
    t0, t1 = growth_window(tc, env, low, high) if window is None else map(float, window)
    sel = (tc >= t0) & (tc <= t1)
    if sel.sum() < 3:
        raise ParameterError(f"window ({t0:g}, {t1:g}) holds fewer than 3 bins of {bin_time:g}")
    slope, icpt = np.polyfit(tc[sel], np.log(env[sel]), 1)
    resid = np.log(env[sel]) - (icpt + slope * tc[sel])
    return float(slope), (t0, t1), float(np.sqrt((resid ** 2).mean()))


def disk_orbit(times, positions, equilibrium, disk, t_end=None, bin_time=50.0, window=None,
               low=10.0, high=1e-4):
    """The :class:`Orbit` of ``disk`` about its equilibrium over frames with ``t <= t_end``.

    Winding and frequency over the growth window (the unstable mode dominates
    there; the seed's transient before it mixes all modes), the envelope rate by
    :func:`envelope_rate`, the aspect as the x over the y RMS displacement.
    """
    t, p = _frames(times, positions)
    if t_end is not None:
        check_real("t_end", t_end)
        keep = t <= t_end
        t, p = _frames(t[keep], p[keep])
    d = displacement(p, equilibrium, disk)
    rate, (t0, t1), resid = envelope_rate(t, np.hypot(d[:, 0], d[:, 1]), bin_time, window,
                                          low, high)
    sel = (t >= t0) & (t <= t1)
    if sel.sum() < MIN_FRAMES:
        raise ParameterError(f"growth window ({t0:g}, {t1:g}) holds fewer than {MIN_FRAMES} frames")
    turns, mono = winding(d[sel])
    ds = d[sel]
    aspect = float(np.sqrt((ds[:, 0] ** 2).mean() / (ds[:, 1] ** 2).mean()))
    omega = 2 * math.pi * abs(turns) / (t[sel][-1] - t[sel][0])
    return Orbit(int(disk), turns, mono, float(omega), rate, (t0, t1), resid, aspect)


def amplitude(times, signal, window):
    """Oscillation amplitude of ``signal`` in ``window``: sqrt(2) x its RMS about its mean
    (a sine's amplitude)."""
    t, _ = _frames(times)
    s = np.asarray(check_finite_array("signal", signal, shape=(t.size,)), dtype=float)
    t0, t1 = map(float, window)
    sel = (t >= t0) & (t <= t1)
    if sel.sum() < MIN_FRAMES:
        raise ParameterError(f"window ({t0:g}, {t1:g}) holds {int(sel.sum())} frames; "
                             f"need {MIN_FRAMES}")
    return float(math.sqrt(2.0) * s[sel].std())


def amplitude_growth(times, signal, early, late):
    """Late over early :func:`amplitude` (1: no growth); inf if the early one is 0."""
    a0, a1 = amplitude(times, signal, early), amplitude(times, signal, late)
    return a1 / a0 if a0 > 0 else math.inf


def centre_growth(times, positions, early, late):
    """(C_y growth, per-disk y growth (N,)) late over early (:func:`amplitude_growth`).

    C_y = (1/N) sum_i y_i (Charan Fig. 7).  If every disk's y grows by the same
    factor in one mode, C_y grows by it too unless the mode's y components sum
    to zero.
    """
    t, p = _frames(times, positions)
    cy = amplitude_growth(t, p[:, :, 1].mean(axis=1), early, late)
    disks = np.array([amplitude_growth(t, p[:, i, 1], early, late) for i in range(p.shape[1])])
    return cy, disks


def sliding_velocity(times, positions, t_from):
    """Slope of C_x = (1/N) sum_i x_i against time over ``t >= t_from`` (Fig. 7's V_mass^x)."""
    t, p = _frames(times, positions)
    check_real("t_from", t_from)
    sel = t >= t_from
    if sel.sum() < MIN_FRAMES:
        raise ParameterError(f"t_from = {t_from:g} leaves {int(sel.sum())} frames; "
                             f"need {MIN_FRAMES}")
    return float(np.polyfit(t[sel], p[sel, :, 0].mean(axis=1), 1)[0])


def mode_ellipse(eigenvalue, vector, disk, dof=3):
    """(aspect, sense) of ``disk``'s ellipse in the growing mode of an eigenpair of M^-1 J.

    The mode moves as ``Re(v exp(s t))`` with ``s = sqrt(lambda)`` (principal
    root, the growing one), so over a cycle the x and y RMS amplitudes are
    ``|v_x| / sqrt 2`` and ``|v_y| / sqrt 2``: aspect ``|v_x| / |v_y|``; the
    sense is the sign of ``x y' - y x'`` = ``Im(s) Im(v_x conj(v_y))`` (+1
    anticlockwise, the sign of :func:`winding`'s turns).  ``vector`` holds
    ``dof`` entries per disk, x and y first.
    """
    v = np.asarray(check_finite_array("vector", vector, ndim=1, complex_ok=True))
    check_int("dof", dof, 2)
    check_int("disk", disk, 0, v.size // dof - 1)
    vx, vy = complex(v[disk * dof]), complex(v[disk * dof + 1])
    if vy == 0:
        raise ParameterError(f"disk {disk} has no y motion in this mode")
    s = complex(np.sqrt(complex(eigenvalue)))
    return abs(vx) / abs(vy), int(np.sign(s.imag * (vx * vy.conjugate()).imag))
