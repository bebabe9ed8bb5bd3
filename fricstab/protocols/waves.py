"""Forward and backward waves of the chain (Charan Fig. 5, Eq. 9) over realizations.

Definitions (paper units: length 2R, time sqrt(m 2R / kn)):

* *breach* of disk i: the first time its wall contact reaches the Coulomb
  limit of the law (:func:`fricstab.analysis.observables.first_breach`; a law
  without a cap has no breach), tau_i, at
  position x_i(tau_i).  Forward wave (Eq. 9): ``x_i(tau_i) - x_0(tau_0) =
  V1 (tau_i - tau_0)``, disk 0 being the pushed disk.
* *sliding* of disk i: the first time its x has moved by more than
  ``slide_threshold`` (default 0.02 of 2R) from the equilibrium, tau*_i, at
  x*_i.  The paper does not define "sliding"; the threshold is a knob whose
  effect is reported.  Backward wave: times measured from the first sliding
  of the last disk, ``x*_i - x*_last = -V2 (tau*_i - tau*_last)``.
* Fits, as the paper: times and positions are averaged over realizations
  per disk, then fitted by least squares; the uncertainty is the standard
  deviation of the same fit over bootstrap resamples of the realizations.
* Sliding velocity of the centre of mass: slope of x_cm(t) over the last 30 %
  of each run, mean and standard error over realizations.
"""

import warnings
from dataclasses import dataclass

import numpy as np

from fricstab.analysis.observables import centre_of_mass, first_breach, paper_time
from fricstab.errors import MAX_STEPS, ParameterError, check_int, check_real
from fricstab.protocols.dynamics import perturbed, run_dynamics
from fricstab.scenes.chain import check_chain, time_unit

__all__ = ["Realization", "WaveFit", "first_slide", "fit_waves", "nanmean",
           "realization_member", "realization_from_arrays", "run_realization"]


@dataclass(frozen=True)
class Realization:
    """Per-disk breach and sliding times (paper units) of one run."""

    seed: int
    tau: np.ndarray
    x_tau: np.ndarray
    tau_slide: np.ndarray
    x_slide: np.ndarray
    v_com: float


@dataclass(frozen=True)
class WaveFit:
    """Wave speeds with bootstrap uncertainties (paper units)."""

    v1: float
    v1_err: float
    v2: float
    v2_err: float
    v_com: float
    v_com_err: float
    realizations: int
    breached_fraction: float


def run_realization(scene, equilibrium, seed, duration=25000.0, amplitude=1e-9,
                    slide_threshold=0.02, frames=20000, dt=None):
    """One seeded run of the chain from an equilibrium: breach and sliding times per disk.

    The equilibrium is perturbed (Gaussian, ``amplitude`` times the rest wall
    overlap in every generalized coordinate) and run undamped; the forward wave
    of Coulomb breaching and the backward wave of sliding are read from it
    (Charan Fig. 5, Eq. 9; definitions in the module docstring).  Paper units:
    length 2R, time ``sqrt(m 2R / k_n)``.

    Parameters
    ----------
    scene : ChainScene
        The scene, carrying F_x.
    equilibrium : State
        The equilibrium at that F_x (:func:`ramped_equilibrium`).
    seed : int
        Seed of the perturbation.
    duration : float
        Run length (paper time units).
    amplitude : float
        Perturbation, in units of the rest wall overlap.
    slide_threshold : float
        A disk slides once its x moved by more than this (units of 2R).
    frames : int
        Recorded frames.
    dt : float, optional
        Verlet step in simulation units (default :func:`run_dynamics`'s
        ``0.02 / omega_wall``).

    Returns
    -------
    Realization
        ``seed``, per disk the breach time ``tau`` and position ``x_tau``, the
        sliding time ``tau_slide`` and position ``x_slide`` (paper units), and
        the centre-of-mass velocity ``v_com`` (2R per time unit).
    """
    check_chain(scene, equilibrium, "equilibrium")
    check_int("seed", seed, 0)
    check_real("duration", duration, 0.0, low_open=True)
    check_real("amplitude", amplitude, 0.0)
    check_real("slide_threshold", slide_threshold, 0.0, low_open=True)
    check_int("frames", frames, 2, MAX_STEPS)
    start = perturbed(scene, equilibrium, amplitude, np.random.default_rng(seed))
    res = run_dynamics(scene, start, dt=dt, duration=duration * time_unit(scene),
                       frames=frames)
    t = paper_time(scene, res.times)
    tau, x_tau = first_breach(scene, res.times, res.positions, res.wall_hist)
    length = 2 * scene.radius
    tau_s, x_s = first_slide(scene, t, res.positions, equilibrium.q, slide_threshold)
    late = t >= 0.7 * t[-1]
    if np.unique(t[late]).size < 2:
        raise ParameterError(f"duration = {duration!r} is too short: fewer than 2 frames in the "
                             "last 30% of the run for the centre-of-mass velocity")
    v = float(np.polyfit(t[late], centre_of_mass(res.positions)[late, 0], 1)[0]) / length
    return Realization(seed, paper_time(scene, tau), x_tau / length, tau_s, x_s / length, v)


def realization_member(scene, equilibrium, seed, duration=25000.0, slide_threshold=0.02):
    """:func:`run_realization` as a dict of arrays: an ensemble member (fricstab.io.ensemble)."""
    r = run_realization(scene, equilibrium, seed, duration=duration,
                        slide_threshold=slide_threshold)
    return {"seed": r.seed, "tau": r.tau, "x_tau": r.x_tau, "tau_slide": r.tau_slide,
            "x_slide": r.x_slide, "v_com": r.v_com}


def realization_from_arrays(d):
    """The :class:`Realization` of a stored member dict (see :func:`realization_member`)."""
    return Realization(int(d["seed"]), d["tau"], d["x_tau"], d["tau_slide"], d["x_slide"],
                       float(d["v_com"]))


def first_slide(scene, t, positions, q_eq, threshold=0.02):
    """Per disk: (time, x) of the first frame with |x - x_eq| > threshold (2R)."""
    moved = np.abs(positions[:, :, 0] - q_eq[None, :, 0]) > threshold * 2 * scene.radius
    tau = np.full(scene.n, np.nan)
    x = np.full(scene.n, np.nan)
    for i in range(scene.n):
        hit = np.flatnonzero(moved[:, i])
        if hit.size:
            tau[i], x[i] = t[hit[0]], positions[hit[0], i, 0]
    return tau, x


def nanmean(values):
    """Mean over realizations ignoring NaN; NaN (no warning) where no realization has a value.

    A disk that never breaches (or never slides) in any realization has no
    time: its mean is NaN and the fit below leaves it out; with fewer than
    three such disks the speed is NaN, reported as ``null`` with the number of
    breaching realizations next to it.
    """
    with warnings.catch_warnings():
        warnings.filterwarnings("ignore", "Mean of empty slice", RuntimeWarning)
        return np.nanmean(values, axis=0)


def _fit(reals, pick):
    """Slope of the realization-averaged (dt, dx) of the disks, see module doc."""
    dts, dxs = zip(*(pick(r) for r in reals))
    dt, dx = nanmean(dts), nanmean(dxs)
    ok = np.isfinite(dt) & np.isfinite(dx)
    if ok.sum() < 3 or np.ptp(dt[ok]) == 0:
        return np.nan
    return float(np.polyfit(dt[ok], dx[ok], 1)[0])


def _forward(r):
    return r.tau - r.tau[0], r.x_tau - r.x_tau[0]


def _backward(r):
    return r.tau_slide - r.tau_slide[-1], -(r.x_slide - r.x_slide[-1])


def fit_waves(reals, n_boot=400, seed=0):
    """V1, V2 and the centre-of-mass velocity over realizations."""
    rng = np.random.default_rng(seed)
    v1, v2 = _fit(reals, _forward), _fit(reals, _backward)
    boot1, boot2 = [], []
    for _ in range(n_boot):
        sample = [reals[k] for k in rng.integers(0, len(reals), len(reals))]
        boot1.append(_fit(sample, _forward))
        boot2.append(_fit(sample, _backward))
    vcom = np.array([r.v_com for r in reals])
    breached = np.mean([np.isfinite(r.tau).mean() for r in reals])
    with warnings.catch_warnings():   # all bootstrap fits NaN: no wave, the error is NaN too
        warnings.filterwarnings("ignore", "Degrees of freedom <= 0", RuntimeWarning)
        e1, e2 = float(np.nanstd(boot1)), float(np.nanstd(boot2))
    return WaveFit(v1, e1, v2, e2,
                   float(vcom.mean()), float(vcom.std(ddof=1) / np.sqrt(len(vcom))),
                   len(reals), float(breached))
