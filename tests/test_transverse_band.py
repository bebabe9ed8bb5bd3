"""The chain's transverse band resolved by wavelength (fricstab.analysis.modes.transverse_band)."""

import numpy as np
import pytest

from fricstab.analysis.modes import resolve_band, transverse_band, transverse_mode
from fricstab.errors import ParameterError
from fricstab.protocols.ramp import ramped_equilibrium, relax_newton
from fricstab.scenes.chain import (CONVENTIONS, ChainScene, eigenvalue_unit, forces_and_jacobian,
                                   initial_state, mass_vector)

SCENE = ChainScene()
# LAPACK on a 3N = 30 matrix similar to a symmetric one: |d lambda| <~ 30 eps |A| with
# |A| / |lambda_y| < 10 here, so omega is good to ~1e-13 relative; 1e-9 leaves room.
REL = 1e-9


@pytest.fixture(scope="module")
def rest():
    res = relax_newton(SCENE, initial_state(SCENE))
    assert res.converged
    return res.state


@pytest.fixture(scope="module")
def pushed():
    return ramped_equilibrium(SCENE, 0.083)


def fourier_blocks(jac, mass, n, dof):
    """Eigenvalues (n//2 + 1, dof) of the dof x dof Fourier blocks of a block-circulant M^-1 J."""
    a = (jac / mass[:, None]).reshape(n, dof, n, dof)
    row = a[0]                                     # (dof, n, dof): disk 0 against disk d
    out = []
    for m in range(n // 2 + 1):
        phase = np.exp(2j * np.pi * m * np.arange(n) / n)
        out.append(np.linalg.eigvals(np.einsum("adb,d->ab", row, phase)))
    return np.array(out)


def check_against_blocks(band, jac, mass, n, dof, unit):
    a = (jac / mass[:, None]).reshape(n, dof, n, dof)
    for d in range(1, n):                          # block circulant: row i is row 0 shifted
        assert np.allclose(np.roll(a[d], -d, axis=1), a[0], rtol=0, atol=1e-12 * np.abs(a).max())
    lam = fourier_blocks(jac, mass, n, dof)
    for omega, m in zip(band.omega, band.m):
        block = np.sqrt(-lam[m] * unit + 0j)  # zero modes (free rolling) stay 0
        assert np.min(np.abs(block - omega)) <= REL * omega, (m, omega, block)
    assert np.all(band.purity > 1 - 1e-9)


def test_rest_band_is_the_fourier_blocks(rest):
    """F_x = 0: J is block circulant; each mode is one Fourier family with its block's omega."""
    _, jac = forces_and_jacobian(SCENE, rest)
    for conv in CONVENTIONS:
        band = transverse_band(SCENE, rest, conv)
        mass = mass_vector(SCENE, conv)
        check_against_blocks(band, jac, mass, SCENE.n, SCENE.dof, eigenvalue_unit(SCENE, conv))
        # the ten y modes are degenerate (neighbours only touch): the criterion must still
        # give each family its multiplicity, 0 and N/2 once, the others twice
        assert sorted(band.m) == [0, 1, 1, 2, 2, 3, 3, 4, 4, 5]
        assert band.mode(2.0).purity > 1 - 1e-9
        assert band.mode(2.0).speed == pytest.approx(band.omega[0] / np.pi, rel=REL)


def test_synthetic_dispersive_ring():
    """A block-circulant ring whose y band disperses: omega and m pair as in the blocks."""
    n, dof = 10, 3
    rng = np.random.default_rng(3)
    k0 = rng.normal(size=(dof, dof)) * 0.1
    k0 = k0 @ k0.T + np.diag([4.0, 1.0, 6.0])         # on-site: y the softest dof
    k1 = rng.normal(size=(dof, dof)) * 0.05
    k1[1, 1] = 0.2                                     # y couples to the neighbours' y
    jac = np.zeros((n * dof, n * dof))
    for i in range(n):
        j = (i + 1) % n
        jac[i*dof:(i+1)*dof, i*dof:(i+1)*dof] -= k0 + 2 * np.diag([0, 0.2, 0])
        jac[i*dof:(i+1)*dof, j*dof:(j+1)*dof] += k1
        jac[j*dof:(j+1)*dof, i*dof:(i+1)*dof] += k1.T
    mass = np.tile([1.0, 1.0, 0.5], n)
    band = resolve_band(jac, mass, n, dof)
    check_against_blocks(band, jac, mass, n, dof, 1.0)
    # distinct frequencies per family: omega rises with m (y springs to the neighbours)
    assert np.all(np.diff(band.omega_by_m) > 1e-3)


def test_pushed_band_has_a_wavelength_two_mode(pushed):
    """F_x = 0.083: the band's wavelength-2 content lies above the bare wall frequency
    (neighbours moving oppositely stretch their tangential springs most: the y dispersion
    rises from m = 0 to N/2) and below the band's top."""
    scene = SCENE.with_fx(0.083)
    band = transverse_band(scene, pushed)
    omega_wall = transverse_band(SCENE, ramped_equilibrium(SCENE, 0.0)).omega[0]   # 0.23508
    assert np.all(np.diff(band.omega_by_m) > 0)
    assert omega_wall < band.frequency(2.0) < band.omega.max()
    mode = band.mode(2.0)
    assert mode.m == 5 and mode.wavelength == 2.0
    # the mode carrying most of the band's wavelength-2 y power, and honest about it
    i = int(np.flatnonzero(band.omega == mode.omega)[0])
    assert band.power[i, 5] * band.y_fraction[i] == pytest.approx(
        (band.power[:, 5] * band.y_fraction).max())
    assert mode.dominant == (band.m[i] == 5)
    # the pushed chain's modes are localized: purity well below 1, above the 1/6 of
    # a y motion spread evenly over the six families
    assert 1 / 6 < mode.purity < 0.9
    assert mode.speed == pytest.approx(mode.omega / np.pi)
    assert band.speed(2.0) == pytest.approx(band.frequency(2.0) / np.pi)


def test_transverse_mode_convention(rest):
    assert transverse_mode(SCENE, rest, "physical").omega == transverse_mode(SCENE, rest).omega
    for conv in CONVENTIONS:
        assert transverse_mode(SCENE, rest, conv).omega == pytest.approx(0.23508, abs=1e-5)


@pytest.mark.parametrize("bad", ["lamps", None, 3])
def test_unknown_convention(rest, bad):
    with pytest.raises(ParameterError, match="convention"):
        transverse_band(SCENE, rest, bad)
    with pytest.raises(ParameterError, match="convention"):
        transverse_mode(SCENE, rest, bad)


def test_not_an_equilibrium():
    with pytest.raises(ParameterError, match="not an equilibrium"):
        transverse_band(SCENE, initial_state(SCENE))


@pytest.mark.parametrize("wavelength", [3.0, 0.0, -2.0, float("nan"), "2"])
def test_bad_wavelength(rest, wavelength):
    band = transverse_band(SCENE, rest)
    with pytest.raises(ParameterError, match="wavelength"):
        band.mode(wavelength)


def test_band_figure_has_units(pushed):
    import re

    from fricstab.figures.chain_band import transverse_band_figure
    from fricstab.figures.common import UNIT_PATTERN
    band = transverse_band(SCENE.with_fx(0.083), pushed)
    fig = transverse_band_figure(band, marks={"sm": 0.26})
    labels = [ax.get_xlabel() for ax in fig.axes] + [ax.get_ylabel() for ax in fig.axes]
    assert all(re.search(UNIT_PATTERN, lab) for lab in labels if lab), labels
    texts = " ".join(t.get_text() for t in fig.axes[0].get_legend().get_texts())
    assert "0.235" in texts and "0.075" in texts and "sm" in texts


def test_fourier_power_shares_follow_the_y_power():
    """A family's share is its part of sum y^2 (Parseval): cos k1 i carries N/2, (-1)^i N."""
    from fricstab.analysis.modes import fourier_power
    i = np.arange(10)
    y = np.column_stack([np.cos(2 * np.pi * 2 * i / 10 + 0.3),
                         np.cos(2 * np.pi * i / 10) + (-1.0) ** i])
    p = fourier_power(y)
    assert p.shape == (6, 2)
    assert np.allclose(p[:, 0], [0, 0, 1, 0, 0, 0], atol=1e-15)   # rounding of a 10-point FFT
    assert np.allclose(p[:, 1], [0, 1 / 3, 0, 0, 0, 2 / 3], atol=1e-15)
