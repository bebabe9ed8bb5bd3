"""Orbit measures (fricstab.analysis.chain_orbits) on synthetic frames with known answers."""

import math

import numpy as np
import pytest

from fricstab.analysis.chain_orbits import (amplitude_growth, centre_growth, disk_orbit,
                                            envelope_rate, mode_ellipse, sliding_velocity,
                                            winding)
from fricstab.errors import ParameterError

OMEGA, SIGMA = 0.23, 0.01
T = np.arange(0.0, 2000.0, 1.0)   # a frame per time unit: 27 frames per period


def _frames(x, y, n=2):
    """(T, n, 3) positions: disk 1 moves by (x, y), the others stay at the origin."""
    p = np.zeros((T.size, n, 3))
    p[:, 1, 0], p[:, 1, 1] = x, y
    return p


def _spiral(aspect=0.5):
    g = np.exp(SIGMA * T)
    return aspect * g * np.cos(OMEGA * T), g * np.sin(OMEGA * T)


def test_exponential_spiral_gives_its_rate_turns_and_aspect():
    o = disk_orbit(T, _frames(*_spiral()), np.zeros((2, 3)), 1)
    sel = (T >= o.window[0]) & (T <= o.window[1])
    span = T[sel][-1] - T[sel][0]
    # The envelope's peaks sit up to half a period off the bin's end: log error
    # <= SIGMA * 27 / 2 ~ 0.14 per bin, random in sign over ~20 bins, so the
    # slope is good to ~0.14 / span ~ 1e-4 of 0.01: 2 % is loose.
    assert o.rate == pytest.approx(SIGMA, rel=0.02)
    # Anticlockwise; the polar angle of an ellipse lags or leads the phase by
    # less than a quarter turn at either end of the window.
    assert o.turns == pytest.approx(OMEGA * span / (2 * math.pi), abs=0.5)
    assert o.monotonic == 1.0
    # The RMS weights each frame by e^{2 sigma t}, which changes by e^{2 sigma P}
    # = 1.7 within a period P: the cos^2 and sin^2 means are biased by
    # O(sigma / omega) = 4 %: 6 %.
    assert o.aspect == pytest.approx(0.5, rel=0.06)
    assert o.omega == pytest.approx(OMEGA, rel=0.02)


def test_growth_window_leaves_out_a_faster_end():
    # The last 200 frames grow 4x faster (the nonlinear run-up to the breach),
    # 8 e-folds: the default window ends at 1e-4 of the final envelope, 9.2
    # e-folds below it, inside the exponential stretch.
    x, y = _spiral()
    boost = np.exp(np.where(T > 1800, 3 * SIGMA * (T - 1800), 0.0))
    o = disk_orbit(T, _frames(x * boost, y * boost), np.zeros((2, 3)), 1)
    assert o.window[1] < 1800
    assert o.rate == pytest.approx(SIGMA, rel=0.02)    # error model as above


def test_clockwise_spiral_has_negative_turns():
    x, y = _spiral()
    turns, mono = winding(np.column_stack([x, -y])[:500])
    assert turns < -15 and mono == 1.0


def test_line_oscillation_is_not_a_spiral():
    rng = np.random.default_rng(0)
    g = np.exp(SIGMA * T) * np.cos(OMEGA * T)
    # A back-and-forth line through the equilibrium, with noise 1e-6 of it.
    x = g + 1e-6 * np.abs(g).max() * rng.standard_normal(T.size)
    y = 2 * g + 1e-6 * np.abs(g).max() * rng.standard_normal(T.size)
    turns, mono = winding(np.column_stack([x, y]))
    # A spiral gives 1; the line's cross products are noise, either sign: ~1/2
    # (binomial, 2000 draws: sd 0.011).
    assert mono < 0.6
    assert abs(turns) < 0.05 * OMEGA * T[-1] / (2 * math.pi)
    # Without noise every cross product is exactly 0: no increment has a sign.
    assert winding(np.column_stack([g, 2 * g])) == (0.0, 0.0)


def test_rocking_on_a_circle_is_not_a_spiral():
    phase = 2.0 * np.sin(OMEGA * T)          # the angle swings back and forth
    turns, mono = winding(np.column_stack([np.cos(phase), np.sin(phase)]))
    assert abs(turns) < 0.5 and mono < 0.6


def test_centre_of_mass_without_and_with_growth():
    n, omega2, c = 4, 0.11, 1e-9
    g = 1e-6 * np.exp(SIGMA * T)       # small about y = R = 0.5, as the chain's
    early, late = (200.0, 500.0), (1200.0, 1500.0)
    # Equal windows: the RMS of g sin over each is e^{sigma t_start} times the
    # same factor, so the disks' ratio is e^{sigma * 1000} up to the sampled
    # sine's phase (~1 / 11 periods of RMS error, < 2 %).
    expected = math.exp(SIGMA * 1000.0)
    p = np.zeros((T.size, n, 3))
    for i in range(n):   # phases sum to zero: the growing mode leaves C_y alone
        p[:, i, 1] = 0.5 + g * np.sin(OMEGA * T + i * math.pi / 2) + c * np.sin(omega2 * T)
    cy, disks = centre_growth(T, p, early, late)
    assert cy == pytest.approx(1.0, rel=0.05)
    assert disks == pytest.approx(np.full(n, expected), rel=0.02)
    for i in range(n):   # in phase: C_y grows with the disks
        p[:, i, 1] = 0.5 + g * np.sin(OMEGA * T)
    cy, disks = centre_growth(T, p, early, late)
    assert cy == pytest.approx(expected, rel=0.02)


def test_amplitude_growth_of_a_steady_sine_is_one():
    s = 3.0 * np.sin(OMEGA * T)
    # 300 / 27.3 = 11 periods: the RMS of the sampled sine differs by < 2 %.
    assert amplitude_growth(T, s, (0, 300), (1500, 1800)) == pytest.approx(1.0, rel=0.02)


def test_sliding_velocity_is_the_slope_after_the_transition():
    p = np.zeros((T.size, 3, 3))
    p[:, :, 0] = np.where(T > 1000, 2.5e-5 * (T - 1000), 0.0)[:, None] + np.arange(3)
    assert sliding_velocity(T, p, 1000.0) == pytest.approx(2.5e-5, rel=1e-9)


def test_mode_ellipse_aspect_and_sense():
    s = SIGMA + 1j * OMEGA
    v = np.array([0, 0, 0, 0.5, -1j, 0.3])      # disk 1: x = 0.5 cos, y = sin: anticlockwise
    assert mode_ellipse(s * s, v, 1) == (pytest.approx(0.5), 1)
    assert mode_ellipse(s * s, v.conj(), 1) == (pytest.approx(0.5), -1)


def test_bad_input_is_refused():
    p = _frames(*_spiral())
    with pytest.raises(ParameterError, match="at least"):
        disk_orbit(T[:5], p[:5], np.zeros((2, 3)), 1)
    bad = p.copy()
    bad[10, 1, 0] = np.nan
    with pytest.raises(ParameterError, match="finite"):
        disk_orbit(T, bad, np.zeros((2, 3)), 1)
    with pytest.raises(ParameterError, match="finite"):
        sliding_velocity(T, bad, 0.0)
    with pytest.raises(ParameterError, match="finite"):
        winding(np.array([[1.0, 0.0]] * 9 + [[np.nan, 0.0]]))
    with pytest.raises(ParameterError, match="increase"):
        sliding_velocity(T[::-1], p, 0.0)
    with pytest.raises(ParameterError, match="shape"):
        disk_orbit(T, p, np.zeros((3, 3)), 1)
    with pytest.raises(ParameterError, match="linear-growth"):
        envelope_rate(T, np.ones(T.size), 50.0)     # no growth at all
    with pytest.raises(ParameterError, match="frames"):
        amplitude_growth(T, np.sin(T), (0, 3), (100, 400))
