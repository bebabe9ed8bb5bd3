"""Every figure the CLI writes: labels with units, colour bars labelled, the issue-18 defects.

Built from small synthetic inputs (no protocol runs).  Convention
(docs/figures.md, :data:`fricstab.figures.common.UNIT_PATTERN`): each axis
and colour bar label ends with its unit in brackets, ``quantity [unit]``,
``[-]`` for a pure number.  An x label may be left to the bottom panel of
a column of panels sharing x.
"""

import re
from types import SimpleNamespace

import numpy as np
import pytest

from fricstab.figures import chain as cf
from fricstab.figures import packing as pf
from fricstab.figures import shear as sf
from fricstab.figures.common import UNIT_PATTERN, pyplot, si_scale
from fricstab.protocols.waves import Realization, fit_waves

plt = pyplot()


@pytest.fixture(autouse=True)
def _close_figures():
    yield
    plt.close("all")


def _colorbar(ax):
    return getattr(ax, "_colorbar", None)


def _assert_units(fig):
    """Non-empty labels ending in ``[unit]`` on every axis and colour bar of ``fig``."""
    assert fig.axes
    for ax in fig.axes:
        cb = _colorbar(ax)
        if cb is not None:
            label = ax.get_ylabel() if cb.orientation == "vertical" else ax.get_xlabel()
            assert re.search(UNIT_PATTERN, label), f"colour bar label {label!r}"
            continue
        assert re.search(UNIT_PATTERN, ax.get_ylabel()), f"y label {ax.get_ylabel()!r}"
        xlabel = ax.get_xlabel() or next(
            (o.get_xlabel() for o in ax.get_shared_x_axes().get_siblings(ax) if o.get_xlabel()),
            "")
        assert re.search(UNIT_PATTERN, xlabel), f"x label {xlabel!r} of {ax.get_title()!r}"


def _colorbar_count(fig):
    return sum(_colorbar(ax) is not None for ax in fig.axes)


# ------------------------------------------------------------------ chain


def _realizations(n_disks=10, n=4, v1=2e-3, v2=0.08, seed=0):
    """Waves with known speeds plus noise: breach at x_i = i after i / v1, sliding backwards."""
    rng = np.random.default_rng(seed)
    i = np.arange(n_disks, dtype=float)
    out = []
    for s in range(n):
        tau = 1000.0 + i / v1 + rng.normal(0, 50, n_disks)
        tau_s = 9000.0 + (n_disks - 1 - i) / v2 + rng.normal(0, 5, n_disks)
        out.append(Realization(s, tau, i + 0.5, tau_s, i + 0.6, 2e-5))
    return out


def test_ramp_figure_units_and_events():
    fx = np.linspace(0.0, 0.1, 11)
    w = -np.abs(np.random.default_rng(1).normal(size=(11, 6))).astype(complex) * 100
    w[5:, 0] += 0.5j
    w[5:, 1] -= 0.5j
    res = SimpleNamespace(fx=fx, eigenvalues=w)
    fig = cf.ramp_figure(res, [{"fx": 0.05, "kind": "birth"}, {"fx": 0.08, "kind": "death"}],
                         1e-3)
    _assert_units(fig)
    legend = [t.get_text() for t in fig.axes[0].get_legend().get_texts()]
    assert "birth of a pair" in legend and "death of a pair" in legend


def test_ramp_figure_starts_im_curves_at_the_located_birth():
    # a pair born at 0.043 between the grid points 0.04 and 0.05: its Im curve is drawn
    # from (0.043, 0) to the first grid point, not from the grid step 0.05
    fx = np.linspace(0.0, 0.1, 11)
    w = -np.ones((11, 4), complex) * 100
    w[5:, 0] += 0.5j
    w[5:, 1] -= 0.5j
    fig = cf.ramp_figure(SimpleNamespace(fx=fx, eigenvalues=w),
                         [{"fx": 0.043, "kind": "birth"}], 1.0)
    starts = [ln.get_xdata()[0] for ln in fig.axes[1].get_lines() if len(ln.get_xdata()) == 2]
    assert 0.043 in starts


def test_ramp_figure_without_pairs_says_so_and_names_the_scenes_kn():
    from fricstab.scenes.chain import ChainScene, reference_stiffness
    fx = np.linspace(0.0, 0.01, 3)
    res = SimpleNamespace(fx=fx, eigenvalues=-np.ones((3, 4), complex))
    scene = ChainScene(law="lee_hurley", params={"E": 100.0})   # not the default E
    fig = cf.ramp_figure(res, [], 1.0, scene=scene)
    texts = " ".join(t.get_text() for ax in fig.axes for t in ax.texts) + " ".join(
        t.get_text() for t in fig.texts)
    assert "no complex pair" in texts
    assert "simulation's $k_n = 2000$" not in texts and "no Hertz $k_n$" in texts
    assert f"{reference_stiffness(scene):.6g}" in texts
    # linear: its own k_n (force/length) and the Hertz k_n that sets the time unit
    linear = ChainScene(law="linear")
    note = cf.units_note(linear)
    assert f"linear $k_n = {linear.params['kn']:.6g}$" in note
    assert f"$k_n = {reference_stiffness(linear):.6g}$ is the Hertz" in note
    hertz = cf.units_note(ChainScene(law="hertz", params={"kn": 500.0}))
    assert "k_n = 500" in hertz


def test_dynamics_figure_numbers_disks_from_one_and_has_units():
    t = np.linspace(0.0, 100.0, 50)
    pos = np.random.default_rng(2).normal(size=(50, 10, 3))
    com = pos[:, :, :2].mean(axis=1)
    m = np.linspace(0.0, 1.0, 50)
    fig = cf.dynamics_figure(t, m, com, pos, 3, None)
    _assert_units(fig)
    assert _colorbar_count(fig) == 1
    titles = " ".join(ax.get_title() for ax in fig.axes)
    assert "disk 4 of 10" in titles and "disk 3" not in titles   # the paper's 4th disk


def test_wave_figure_draws_the_fitted_lines_whose_slopes_are_v1_and_v2():
    reals = {0.087: _realizations(seed=0), 0.09: _realizations(v1=3e-3, seed=1)}
    fits = {fx: fit_waves(r, n_boot=20) for fx, r in reals.items()}
    fig = cf.wave_figure(reals, None, fits)
    _assert_units(fig)
    top, bottom = fig.axes
    for ax, key, sign in ((top, "v1", 1.0), (bottom, "v2", -1.0)):
        lines = [ln for ln in ax.get_lines() if ln.get_label().startswith("$F_x$")]
        assert len(lines) == 2
        for ln, fx in zip(lines, reals):
            x, y = ln.get_data()
            slope = (y[-1] - y[0]) / (x[-1] - x[0])
            # The same least-squares fit of the same averaged points as fit_waves:
            # equal up to rounding of two polyfits (relative 1e-9).
            assert slope == pytest.approx(sign * getattr(fits[fx], key), rel=1e-9)
            assert f"{getattr(fits[fx], key):.3g}" in ln.get_label()


# ------------------------------------------------------------------ packing


def _packing():
    rng = np.random.default_rng(3)
    pos = rng.uniform(0, 4, (8, 2))
    return SimpleNamespace(box=4.0, diameter=np.where(np.arange(8) % 2, 1.0, 1.4), pos=pos,
                           n=8, phi=0.85, seed=3)


def test_packing_figure_units():
    p = _packing()
    pairs = np.array([[0, 1], [2, 3]])
    sep = p.pos[pairs[:, 0]] - p.pos[pairs[:, 1]]
    fig = pf.packing_figure(p, pairs, sep, np.array([1.0, 0.5]), np.zeros(8, bool))
    _assert_units(fig)


def test_rigidity_figure_units():
    rows = [{"kt": kt, "law": "charan", "g_a": 0.07, "g_na_solve": -0.05 + kt / 30,
             "g": 0.02 + kt / 30, "g_modes": None, "g_step": 0.02 + kt / 30,
             "g_step_error": 1e-4} for kt in (1e-8, 1e-4, 1.0)]
    rows.append({**rows[0], "kt": 0.0})
    u = np.random.default_rng(4).normal(size=(20, 3))
    fig = pf.rigidity_figure(rows, ("kT/kN = 1", u, u * 1.01))
    _assert_units(fig)


def test_dos_figure_keeps_equal_spectra_visible():
    """Two runs with the same translational band (kT/kN = 1e-8 and 1e-4): both visible."""
    edges = np.logspace(-3, 0, 13)
    omega = np.logspace(-2.5, -0.2, 40)
    same = {"omega": omega, "dos": np.histogram(omega, edges)[0] / 40.0, "k": 3,
            "psi_t_mean": np.full(12, 0.9), "psi_r_mean": np.full(12, 0.1)}
    spectra = [{**same, "label": "kT/kN = 1e-08"}, {**same, "label": "kT/kN = 0.0001"}]
    fig = pf.dos_figure(spectra, edges)
    _assert_units(fig)
    a = fig.axes[0]
    first, second = a.get_lines()[:2]
    assert np.array_equal(first.get_ydata(), second.get_ydata(), equal_nan=True)
    # Equal data, different marks: a larger open marker under a smaller one, other dashes.
    assert first.get_marker() != second.get_marker()
    assert first.get_markersize() > second.get_markersize()
    assert first.get_linestyle() != second.get_linestyle()
    assert first.get_markerfacecolor() == "none"


# ------------------------------------------------------------------ shear


@pytest.fixture(scope="module")
def shear_run():
    from fricstab.analysis import shear as sa
    from fricstab.io.frames import synthetic_frames
    f = synthetic_frames(n_frames=8, nx=10, ny=6, seed=7)
    return f, sa.analyze(f, gamma0=0.0, progress=False, fraction=0.05)


@pytest.mark.parametrize("name", ["stress", "d2min", "forces", "dforces", "gr", "nonaffine",
                                  "steps", "bins", "run", "spectra"])
def test_every_shear_figure_has_units_and_labelled_colour_bars(shear_run, name):
    f, res = shear_run
    k = 3
    figs = {
        "stress": lambda: sf.fig_stress_strain(f, result=res),
        "d2min": lambda: sf.fig_d2min_map(f, k),
        "forces": lambda: sf.fig_force_network(f, k),
        "dforces": lambda: sf.fig_differential_network(f, k),
        "gr": lambda: sf.fig_gr_clusters(f, k, fraction=0.05),
        "nonaffine": lambda: sf.fig_nonaffine(f, k),
        "steps": lambda: sf.fig_step_panels(res),
        "bins": lambda: sf.fig_spearman_bins(res.tables["phase_all"], title="all phases"),
        "run": lambda: sf.fig_shear_run(f.strain, f.tau, 2e-3),
        "spectra": lambda: sf.fig_slip_spectra({"slip_dtau_p": np.array([-1e-3, -2e-2]),
                                                "slip_n_complex_pairs": np.array([2, 5]),
                                                "slip_max_growth_rate": np.array([1e8, 5e8])}),
    }
    fig = figs[name]()
    fig.canvas.draw()   # the tick formatters compute their offsets when drawn
    _assert_units(fig)
    if name in ("d2min", "forces", "dforces", "gr"):
        assert _colorbar_count(fig) == 1
    # SI lengths are drawn in a prefixed unit, not as an axis offset.
    for ax in fig.axes:
        for axis in (ax.xaxis, ax.yaxis):
            assert axis.get_major_formatter().get_offset() == "", (name, ax.get_title())


def test_gr_map_fills_the_gr_disks_at_their_size_over_the_differential_network(shear_run):
    # the issue's "four dots": GR disks are now filled circles of the disks' own radius,
    # their contacts thick bonds, on the faint differential network of the same step
    from fricstab.analysis import shear as sa
    f, _ = shear_run
    k = 3
    gr = sa.gr_regions(f, k, 5.0 * f.radius[f.kind == 0].mean(), 0.05)
    fig = sf.fig_gr_clusters(f, k, fraction=0.05)
    ax = fig.axes[0]
    filled = [c for c in ax.collections if type(c).__name__ == "PatchCollection"
              and len(c.get_paths()) and c.get_facecolor().shape[0] and
              c.get_facecolor()[0][3] > 0]
    assert sum(len(c.get_paths()) for c in filled) == len(gr["particles"]) > 0
    thick = [c for c in ax.collections if type(c).__name__ == "LineCollection"
             and np.max(c.get_linewidth()) > 2]
    assert len(thick) == 1 and len(thick[0].get_segments()) == len(gr["contacts"])
    assert "GR: the 5 % of contacts" in " ".join(t.get_text() for t in fig.texts)


def test_step_panels_stay_readable_with_thousands_of_steps():
    """6,000 steps: lines without markers, rasterized (no solid bands of markers)."""
    rng = np.random.default_rng(5)
    T = 6000
    arrays = {"tau": rng.normal(size=T), "strain": np.arange(T) * 1e-5,
              "rho_sigma_d2": rng.uniform(-1, 1, T), "g": rng.lognormal(size=T),
              "g10": rng.lognormal(size=T) / 2, "n_clusters": rng.integers(0, 5, T),
              "angle_mean": rng.uniform(0, 1.5, T), "angle_median": rng.uniform(0, 1.5, T)}
    fig = sf.fig_step_panels(SimpleNamespace(arrays=arrays))
    _assert_units(fig)
    lines = [ln for ax in fig.axes for ln in ax.get_lines() if len(ln.get_xdata()) > 200]
    assert lines
    assert all(ln.get_marker() in ("None", "", None) and ln.get_rasterized() for ln in lines)
    # The six per-step series (rho, g, g10, clusters, mean and median angle) are thin lines.
    assert sum(ln.get_linewidth() <= 0.5 for ln in lines) == 6


def test_si_scale_picks_the_prefix():
    assert si_scale([3e-6], "m") == (pytest.approx(1e6), "µm")
    assert si_scale([2e-9], "N")[1] == "nN"
    assert si_scale([5e-12], "m", 2) == (pytest.approx(1e12), "µm$^{2}$")
    assert si_scale([1.5e8], "s", -1) == (pytest.approx(1e-6), "µs$^{-1}$")
    assert si_scale([np.nan, 0.0], "Pa") == (1.0, "Pa")
