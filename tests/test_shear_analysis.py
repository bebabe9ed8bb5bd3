"""Plane-shear analyses: D2min against a brute-force reference, rattlers, GR
regions (DBSCAN semantics, periodic x), stress, phases and Spearman tables."""

import json

import numpy as np
import pytest
from scipy.stats import spearmanr
from hypothesis import given
from hypothesis import strategies as st

from fricstab.analysis import shear as sa
from fricstab.laws import ParameterError
from fricstab.io.frames import FrameWriter, synthetic_frames


def d2min_brute(pos_ref, pos_cur, lx, rcut, mask):
    """Eqs. B1-B4 by plain loops, one np.linalg.solve per particle."""
    n = len(pos_ref)
    out = np.full(n, np.nan)
    for i in range(n):
        if not mask[i]:
            continue
        dr, dc = [], []
        for j in range(n):
            if j == i or not mask[j]:
                continue
            d = pos_ref[j] - pos_ref[i]
            s = np.round(d[0] / lx)
            d = d - np.array([s * lx, 0.0])
            if np.hypot(*d) < rcut:
                dr.append(d)
                dc.append(pos_cur[j] - pos_cur[i] - np.array([s * lx, 0.0]))
        if len(dr) < 2:
            continue
        dr, dc = np.array(dr), np.array(dc)
        X = sum(np.outer(c, r) for c, r in zip(dc, dr))  # B2
        Y = sum(np.outer(r, r) for r in dr)  # B3
        if np.linalg.det(Y) <= 1e-12 * np.trace(Y) ** 2:
            continue
        if len(dr) == 2:
            out[i] = 0.0  # exactly determined: B1 vanishes identically
            continue
        gamma = np.linalg.solve(Y, X.T).T  # B4: Gamma = X Y^-1 (Y symmetric)
        out[i] = np.mean([np.sum((c - gamma @ r) ** 2) for c, r in zip(dc, dr)])  # B1
    return out


@st.composite
def displaced_frames(draw):
    seed = draw(st.integers(0, 2**32 - 1))
    rng = np.random.default_rng(seed)
    n = draw(st.integers(12, 60))
    lx = draw(st.floats(8.0, 20.0))
    ly = draw(st.floats(4.0, 12.0))
    radius = rng.uniform(0.3, 0.7, n)
    rcut = draw(st.floats(2.0, 3.5)) * radius.mean()
    pos = np.column_stack([rng.uniform(0, lx, n), rng.uniform(0, ly, n)])
    # Cluster some particles at the periodic edge, and unwrap some by whole boxes.
    edge = rng.random(n) < 0.3
    pos[edge, 0] = rng.choice([0.02, lx - 0.02], edge.sum()) + rng.normal(0, 0.3, edge.sum())
    pos[:, 0] += lx * rng.integers(-2, 3, n)
    A = np.eye(2) + rng.normal(0, draw(st.floats(1e-6, 0.2)), (2, 2))
    noise = draw(st.floats(1e-3, 1e-1)) * rcut
    cur = pos @ A.T + rng.normal(0, 1.0, 2) + rng.normal(0, noise, (n, 2))
    mask = rng.random(n) < 0.9
    return pos, cur, lx, rcut, mask


@given(displaced_frames())
def test_d2min_matches_brute_force(case):
    pos, cur, lx, rcut, mask = case
    fast = sa.d2min(pos, cur, lx, rcut, mask)
    ref = d2min_brute(pos, cur, lx, rcut, mask)
    assert np.array_equal(np.isnan(fast), np.isnan(ref))
    assert np.all(np.isnan(fast[~mask]))
    ok = np.isfinite(ref)
    # Error model: both evaluate the residual c - Gamma r explicitly; rounding
    # in c and Gamma r is ~1e-16 |c| (|c| <= 2 rcut) with a residual >= ~1e-3
    # rcut (the noise), and Gamma differs by ~1e-16 cond(Y): relative error of
    # the squared residual ~1e-12, bounded here by 1e-10.
    assert np.allclose(fast[ok], ref[ok], rtol=1e-10, atol=0)


@given(displaced_frames(), st.floats(0.1, 10.0))
def test_d2min_is_affine_invariant_and_quadratic_in_the_nonaffine_part(case, scale):
    pos, cur, lx, rcut, mask = case
    xi = cur - pos  # any displacement field
    # A keeps the periodic box vector (A e_x = e_x: shear and y-dilation, the
    # maps of the shear cell), so images stay consistent with unwrapped x.
    A = np.array([[1.0, 0.3], [0.0, 0.95]])
    # cur = A pos + b + s xi: Gamma absorbs A, the residual scales with s (Eq. B1).
    cur2 = pos @ A.T + 0.7 + scale * (xi - xi.mean(axis=0))
    base = sa.d2min(pos, pos + xi, lx, rcut, mask)
    scaled = sa.d2min(pos, cur2, lx, rcut, mask)
    ok = np.isfinite(base)
    assert np.array_equal(ok, np.isfinite(scaled))
    # Rounding of A pos (|pos| <= ~3 lx from unwrapping) is ~1e-15 * 60
    # against residuals >= 1e-4 of rcut: 1e-8 relative is a loose bound.
    assert np.allclose(scaled[ok], scale**2 * base[ok], rtol=1e-8, atol=0)
    # A pure affine map has D2min = 0 up to that rounding (|c| ~ rcut).
    zero = sa.d2min(pos, pos @ A.T + 0.7, lx, rcut, mask)
    assert np.array_equal(np.isfinite(zero), ok)
    assert np.all(zero[ok] < 1e-20 * 100 * rcut**2)


def test_d2min_degenerate_neighbourhoods_are_nan():
    # Three collinear particles (Y singular) and a pair (1 neighbour each).
    pos = np.array([[0.0, 0.0], [1.0, 0.0], [2.0, 0.0], [5.0, 5.0], [5.5, 5.0]])
    out = sa.d2min(pos, pos * 1.01, 20.0, 2.5)
    assert np.all(np.isnan(out))
    with pytest.raises(ParameterError, match="radius_cut"):
        sa.d2min(pos, pos, 4.0, 2.5)
    with pytest.raises(ParameterError, match="positions"):
        sa.d2min(pos, pos[:3], 20.0, 1.0)


def _frames_from(pos_list, contacts_list, kind, lx=10.0):
    n = len(kind)
    w = FrameWriter(lx, np.full(n, 0.5), np.ones(n), np.ones(n), kind)
    for k, (pos, (ij, force, fn)) in enumerate(zip(pos_list, contacts_list)):
        m = len(ij)
        w.append(time=k, strain=k * 1e-3, normal_force=1.0, shear_force=0.5, height=3.0,
                 pos=pos, angle=np.zeros(n), vel=np.zeros((n, 2)), omega=np.zeros(n),
                 contact_ij=np.reshape(ij, (m, 2)), contact_force=np.reshape(force, (m, 2)),
                 contact_fn=fn, contact_hist=np.zeros((m, 2)),
                 contact_flag=np.zeros(m, np.int8))
    return w.finish()


def test_rattlers_count_force_bearing_contacts_only():
    # 0: bulk with 3 bearing contacts; 1: bulk with 2 (+1 with fn = 0);
    # 2: wall with 2; 3: wall with 1; 4: bulk with 4; 5: bulk with 2 (+1 with fn = 0).
    kind = [0, 0, 1, 2, 0, 0]
    ij = [[0, 1], [0, 4], [0, 5], [1, 4], [1, 5], [2, 4], [2, 5], [3, 4]]
    fn = [1.0, 1.0, 1.0, 1.0, 0.0, 1.0, 1.0, 1.0]
    f = _frames_from([np.zeros((6, 2))], [(ij, np.ones((8, 2)), fn)], kind)
    r = sa.rattler_mask(f, 0)
    assert r.tolist() == [False, True, False, True, False, True]


def test_differential_forces_zero_for_new_contacts():
    pos = np.zeros((4, 2))
    f0 = ([[0, 1], [1, 2]], [[3.0, 4.0], [1.0, 0.0]], [5.0, 1.0])
    f1 = ([[0, 1], [2, 3]], [[0.0, 2.0], [7.0, 0.0]], [2.0, 7.0])
    f = _frames_from([pos, pos], [f0, f1], [0, 0, 0, 0])
    assert sa.differential_forces(f, 1).tolist() == [2.0 - 5.0, 0.0]
    with pytest.raises(ParameterError, match="k=0"):
        sa.differential_forces(f, 0)


def test_dbscan_min_samples_two_means_one_neighbour_and_periodic_x():
    # Particles 0, 1 sit across the periodic boundary (distance 0.4 via the
    # image), 2 and 3 are 1.0 apart, 4 is alone.  With eps = 1.5 and
    # min_samples = 2 (one neighbour besides itself, MATLAB's minpts = 1
    # neighbour) pairs are clusters and a lone point is noise.
    lx = 20.0
    pos = np.array([[0.2, 1.0], [19.8, 1.0], [8.0, 1.0], [9.0, 1.0], [14.0, 1.0]])
    ij = [[0, 1], [2, 3], [3, 4]]
    before = (ij, [[5.0, 0.0], [5.0, 0.0], [1.0, 0.0]], [5.0, 5.0, 1.0])
    after = (ij, [[1.0, 0.0], [0.0, 2.0], [1.0, 0.0]], [1.0, 2.0, 1.0])
    f = _frames_from([pos, pos], [before, after], [0] * 5, lx=lx)
    gr = sa.gr_regions(f, 1, eps=1.5, fraction=1.0)
    assert gr["contacts"].tolist() == [0, 1]  # the two reduced contacts, 3 unchanged
    assert gr["n_clusters"] == 2
    labels = dict(zip(gr["particles"].tolist(), gr["labels"].tolist()))
    assert labels[0] == labels[1] != labels[2] == labels[3]
    # |theta|: force along x -> 0, along y -> pi/2.
    assert np.allclose(sorted(gr["abs_angle"]), [0.0, np.pi / 2])
    # Same points, min_samples = 3: nobody has two neighbours -> all noise.
    assert sa.gr_regions(f, 1, eps=1.5, fraction=1.0, min_samples=3)["n_clusters"] == 0
    # A lone GR particle is noise with min_samples = 2.
    from sklearn.cluster import DBSCAN
    lab = DBSCAN(eps=1.0, min_samples=2).fit(np.array([[0.0, 0.0], [0.5, 0.0], [5.0, 0.0]]))
    assert lab.labels_.tolist() == [0, 0, -1]


def test_contact_angle_is_folded_and_sign_free():
    f = np.array([[1.0, 0.0], [-1.0, 0.0], [0.0, 1.0], [0.0, -1.0], [1.0, 1.0], [-1.0, -1.0]])
    th = sa.contact_angle(f)
    assert np.allclose(th, [0.0, 0.0, np.pi / 2, np.pi / 2, np.pi / 4, np.pi / 4])
    assert np.all((th > -np.pi / 2) & (th <= np.pi / 2))


def test_particle_stress_of_a_compressed_pair():
    # Two disks of radius 0.5 at distance 0.9 (overlap 0.1), force F on 0 from 1
    # pushing 0 in -x.  Branch vector of 0: +0.45 x; sigma_xx = -F 0.45 / (pi 0.25).
    F = 2.0
    pos = np.array([[0.0, 0.0], [0.9, 0.0]])
    f = _frames_from([pos], [([[0, 1]], [[-F, 0.0]], [F])], [0, 0])
    sig = sa.particle_stress(f, 0)
    expect = -F * 0.45 / (np.pi * 0.25)
    assert np.allclose(sig[:, 0, 0], expect, rtol=1e-14)
    assert np.allclose(sig[:, [0, 1, 1], [1, 0, 1]], 0.0)


def test_phases_from_a_hand_series():
    tau = np.array([0.0, 1.0, 2.0, 1.0, 0.0, 0.0, 1.0, 3.0, 2.5])
    ok = np.ones(len(tau), bool)
    ph = sa.find_phases(tau, ok)
    assert ph.tolist() == [[1, 2], [3, 4], [6, 7], [8, 8]]
    ok[:4] = False  # window starts at step 4: the slip is cut to its last step
    assert sa.find_phases(tau, ok).tolist() == [[4, 4], [6, 7], [8, 8]]
    g = np.array([np.nan, 1.0, 2.0, 5.0, 4.0, 0.0, 1.0, 1.0, 3.0])
    g10 = g / 2
    ncl = np.array([0, 3, 1, 2, 1, 0, 2, 2, 1])
    m = sa.phase_metrics(ph, tau, g, g10, ncl)
    assert m["dtau_p"].tolist() == [2.0, -2.0, 3.0, -0.5]
    assert m["t_p"].tolist() == [2, 2, 2, 1]
    assert m["mg"].tolist() == [2.0, 5.0, 1.0, 3.0]
    # t_s: first step of minimal GR count (steps 2, 4, 6, 8) -> sums from there.
    assert m["ts"].tolist() == [2, 4, 6, 8]
    assert m["sg"].tolist() == [2.0, 4.0, 2.0, 3.0]
    assert np.allclose(m["sg10"], m["sg"] / 2)
    start = sa.phase_metrics(ph, tau, g, g10, ncl, ts_rule="start")
    assert start["sg"].tolist() == [3.0, 9.0, 2.0, 3.0]
    with pytest.raises(ParameterError, match="ts_rule"):
        sa.phase_metrics(ph, tau, g, g10, ncl, ts_rule="end")


def test_spearman_cells_and_bins():
    x = np.array([-5e-3, -4e-3, -3e-3, -2e-3, 5e-5, 0.0])
    y = np.array([4.0, 3.0, 2.0, 1.0, 7.0, 9.0])
    table = sa.binned_spearman(x, {"y": y})["y"]
    by_bin = {(c["lo"], c["hi"]): c for c in table}
    cell = by_bin[(-1e-2, -1e-3)]
    assert cell["n"] == 4 and cell["rho"] == pytest.approx(-1.0)
    assert cell["significant"] is (cell["p"] <= 0.05)
    assert by_bin[(0.0, 1e-4)]["status"] == "n/a (n<3)" and by_bin[(0.0, 1e-4)]["n"] == 1
    assert sa.spearman_cell([1, 2, 3], [1, 1, 1])["status"] == "n/a (constant input)"
    assert sa.spearman_cell([1, 2, 3, 4], [1, 3, 2, 4])["rho"] == pytest.approx(0.8)


def test_spearman_small_n_p_is_exact_and_never_significant_at_n3():
    # exact two-sided permutation p of a perfect rank order is 2/n!: 1/3 at n = 3 (never
    # <= 0.05), 1/12 at n = 4, 2/8! at n = 8; the t approximation said p = 0 at any n
    for n, want in ((3, 2 / 6), (4, 2 / 24), (8, 2 / 40320)):
        cell = sa.spearman_cell(np.arange(n), np.arange(n) ** 2)
        assert cell["rho"] == pytest.approx(1.0) and cell["p"] == pytest.approx(want, rel=1e-12)
    assert not sa.spearman_cell([1, 2, 3], [3, 2, 1])["significant"]
    # from EXACT_BELOW on, scipy's approximation (close to the exact p for n ~ 10)
    big = sa.spearman_cell(np.arange(12), np.arange(12) % 5)
    assert big["p"] == pytest.approx(spearmanr(np.arange(12), np.arange(12) % 5).pvalue)


def test_step_metrics_top_ten_percent():
    d2 = np.concatenate([np.arange(1.0, 21.0), [np.nan, 100.0]])
    bulk = np.ones(len(d2), bool)
    bulk[-1] = False  # a wall particle with a large value does not count
    g, g10 = sa.step_metrics(d2, bulk)
    assert (g, g10) == (20.0, 19.5)


def test_nonaffine_displacement_removes_affine_part():
    rng = np.random.default_rng(1)
    pos = rng.uniform(0, 10, (40, 2))
    xi = rng.normal(0, 1e-3, (40, 2))
    cur = pos + pos @ np.array([[0.0, 0.01], [0.0, 0.0]]).T + xi
    na = sa.nonaffine_displacement(pos, cur)
    # The fitted part is the least-squares projection: na is xi minus its own
    # affine fit, so it is orthogonal to the affine basis.
    assert np.allclose(na.sum(axis=0), 0.0, atol=1e-15)
    assert np.allclose((pos - pos.mean(0)).T @ na, 0.0, atol=1e-13)
    assert np.linalg.norm(na) <= np.linalg.norm(xi - xi.mean(0))


def test_analyze_synthetic_run_is_consistent_and_serialisable():
    f = synthetic_frames(n_frames=10, nx=10, ny=6, seed=5)
    res = sa.analyze(f, gamma0=2e-3, progress=False, keep_d2min=True)
    a = res.arrays
    assert a["d2min"].shape == (f.n_frames, f.n_particles)
    assert np.all(np.isnan(a["g"][0])) and np.all(np.isfinite(a["g"][1:]))
    assert np.all(a["g10"][1:] <= a["g"][1:])
    assert np.array_equal(res.phases, sa.find_phases(f.tau, np.arange(f.n_frames) >= 3))
    json.dumps(res.to_json())
    s = res.summary
    assert s["n_steps"] == f.n_frames - 3 and s["n_phases"] == len(res.phases)
    assert s["n_stick"] + s["n_slip"] == s["n_phases"]
    # Pure shear without noise: D2min is rounding noise against the noisy run
    # (noise 0.02 dgamma per particle -> D2min ~ (0.02 dgamma)^2).
    clean = sa.analyze(synthetic_frames(n_frames=3, nx=10, ny=6, seed=5, noise=0.0),
                       gamma0=0.0, progress=False)
    assert np.nanmax(clean.arrays["g"]) < 1e-6 * np.nanmin(a["g"][1:])
    with pytest.raises(ParameterError, match="frames_range"):
        sa.analyze(f, 0.0, frames_range=(0, 3), progress=False)


def test_every_figure_writes_a_png(tmp_path):
    from fricstab.figures import shear as sf

    f = synthetic_frames(n_frames=8, nx=10, ny=6, seed=7)
    res = sa.analyze(f, gamma0=0.0, progress=False, fraction=0.05)
    k = 3
    jobs = {
        "stress": lambda p: sf.fig_stress_strain(f, p, result=res),
        "d2min": lambda p: sf.fig_d2min_map(f, k, p),
        "force": lambda p: sf.fig_force_network(f, k, p),
        "dforce": lambda p: sf.fig_differential_network(f, k, p),
        "gr": lambda p: sf.fig_gr_clusters(f, k, p, fraction=0.05),
        "nonaffine": lambda p: sf.fig_nonaffine(f, k, p),
        "panels": lambda p: sf.fig_step_panels(res, p, window=(1, 8)),
        "bins": lambda p: sf.fig_spearman_bins(res.tables["phase_all"], p, "all phases"),
    }
    for name, job in jobs.items():
        path = tmp_path / f"{name}.png"
        job(path)
        assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n", name
        assert path.stat().st_size > 2000, name
    with pytest.raises(ParameterError, match="step k=0"):
        sf.fig_d2min_map(f, 0, tmp_path / "x.png")
