"""Particle-scale analyses of plane-shear frames (Lee & Hurley, Secs. 3.2-3.3, App. B).

Pure functions over a :class:`fricstab.io.frames.Frames` (or plain
arrays), and :func:`analyze`, which runs them over a whole run and returns a
frozen :class:`ShearAnalysis` (arrays for NPZ, a JSON-serialisable summary).

Conventions
-----------
* A *step* k (1 <= k < T) goes from frame k - 1 (reference, strain
  gamma - dgamma) to frame k.  Per-step arrays have length T; entry 0 is NaN
  (or 0 for counts).
* Positions are (x unwrapped, y); a neighbour vector at the reference frame
  uses the minimum image in x, and the *same* image is used at the current
  frame, so vectors stay continuous across the periodic boundary.
* Rattlers (Sec. 3.2): bulk particles with <= 2 force-bearing contacts, wall
  particles with <= 1.  A contact is force-bearing when its elastic normal
  force ``contact_fn > 0``.  Rattlers (at the reference frame) are excluded
  from D2min both as centres (their D2min is NaN) and as neighbours.
* D2min (Eqs. B1-B4) uses neighbours within ``radius_cut`` = 5 r_p (r_p the
  mean radius of the bulk particles) of the centre at the reference frame.
  A neighbourhood with fewer than 2 neighbours, or with Y (B3) singular
  (det Y <= 1e-12 (tr Y)^2, collinear neighbours), gives NaN for that
  particle: D2min is undefined there.  With exactly 2 (non-collinear)
  neighbours Gamma fits both exactly and D2min is returned as exactly 0
  (instead of ill-conditioned rounding).  gD2min and g_t10%D2min are taken over
  bulk particles with finite D2min.
* Non-affine displacement: displacement minus the global best-fit affine map
  (least squares over the included particles, the B2-B4 fit applied to the
  whole sample about its centroid); it removes the shear profile and any
  dilation of the cell, so what remains is the Fig. 7 field.
* Differential force of contact (i, j) at step k: |f_k| - |f_{k-1}| (total
  contact force magnitudes); 0 for a contact that is created between the
  frames (and contacts destroyed are not in frame k, so they do not appear).
* GR (greatest reduction) contacts: the ``ceil(fraction * M_k)`` contacts of
  frame k with the most negative differential force (only negative ones);
  their particles (both ends, each once) are clustered by DBSCAN with
  eps = 5 r_p and ``min_samples=2`` on a periodic-in-x distance matrix.
  MATLAB's "at least 1 neighbour for a core point" equals sklearn's
  ``min_samples=2`` because sklearn counts the point itself.
* Contact angle theta (Fig. 8d): angle between the x-axis and the contact
  force line, folded into (-pi/2, pi/2] so that it does not depend on which
  particle of the pair the force acts on; the paper's |theta| lies in
  [0, pi/2].
* Particle stress: sigma_p = (1/A_p) sum_c r_c (x) f_c with A_p = pi R_p^2,
  r_c from the centre to the contact point (at R_i - delta/2 along the
  centre line), f_c the force on p: compression is negative.
* Phases (Sec. 3.2): maximal runs of steps with Delta tau > 0 (stick) or
  Delta tau < 0 (slip) among steps whose reference strain is >= gamma0; a step
  with Delta tau == 0 ends a run and belongs to none.  A phase over steps
  a..b has Delta tau_p = tau[b] - tau[a-1] and t_p = b - a + 1 (in units of
  the output strain step dgamma); long when t_p > 3.
* t_s of Eqs. 3-4: ``ts_rule="min_gr"`` (default) takes the first step of the
  phase at which the number of GR clusters is minimal over the phase (our
  reading of "the initial timestep when the GR regions are at their
  minimum"); ``ts_rule="start"`` takes the first step.
"""

import math
from dataclasses import dataclass

import numpy as np
from scipy.spatial import cKDTree

from fricstab import signals
from fricstab.analysis.shear_phases import (PAPER_BINS, binned_spearman, find_phases,
                                            phase_metrics, phase_summary, spearman_cell,
                                            step_metrics, tables_markdown)
from fricstab.errors import ParameterError, check_finite_array, check_real

__all__ = ["PAPER_BINS", "PER_STEP", "ShearAnalysis", "analyze", "binned_spearman",
           "check_previous", "contact_angle", "d2min", "differential_forces", "find_phases", "gr_regions",
           "neighbour_pairs", "nonaffine_displacement", "paper_tables", "particle_stress",
           "phase_metrics", "phase_summary", "rattler_mask", "spearman_cell", "step_metrics",
           "tables_markdown"]


def _min_image(dx, lx):
    return dx - lx * np.round(dx / lx)


def rattler_mask(frames, k):
    """Boolean (N,) mask of rattlers at frame ``k`` (Sec. 3.2).

    Bulk particles with <= 2 force-bearing contacts (``contact_fn > 0``) and
    wall particles with <= 1.
    """
    ij, _, fn, _, _ = frames.contacts(k)
    bearing = ij[fn > 0]
    count = np.bincount(bearing.ravel(), minlength=frames.n_particles)
    limit = np.where(frames.kind == 0, 2, 1)
    return count <= limit


def neighbour_pairs(pos, lx, radius_cut, include_mask=None):
    """All ordered pairs (i, j), i != j, with centres within ``radius_cut`` (min image in x).

    Returns
    -------
    i, j : ndarray of int64
        Both orders of each pair; only particles of ``include_mask``.
    shift : ndarray (P,)
        The image index s with ``d = pos[j] - pos[i] - (s lx, 0)`` the
        minimum-image vector (x unwrapped positions).
    """
    pos = np.asarray(pos, dtype=np.float64)
    if not radius_cut > 0 or not np.isfinite(radius_cut):
        raise ParameterError(f"radius_cut = {radius_cut!r} must be finite and > 0")
    if 2 * radius_cut >= lx:
        raise ParameterError(f"radius_cut = {radius_cut} must be < lx/2 = {lx / 2} "
                             "(minimum image)")
    idx = np.arange(pos.shape[0]) if include_mask is None else np.flatnonzero(include_mask)
    p = pos[idx]
    y0 = p[:, 1].min() if len(p) else 0.0
    span = (p[:, 1].max() - y0) if len(p) else 0.0
    wrapped = np.column_stack([np.mod(p[:, 0], lx), p[:, 1] - y0 + radius_cut])
    wrapped[:, 0] = np.where(wrapped[:, 0] >= lx, 0.0, wrapped[:, 0])
    tree = cKDTree(wrapped, boxsize=[lx, 2 * (span + 2 * radius_cut) + 1.0])
    pairs = tree.query_pairs(radius_cut, output_type="ndarray")
    a, b = idx[pairs[:, 0]], idx[pairs[:, 1]]
    i, j = np.concatenate([a, b]), np.concatenate([b, a])
    shift = np.round((pos[j, 0] - pos[i, 0]) / lx)
    return i.astype(np.int64), j.astype(np.int64), shift


def d2min(pos_ref, pos_cur, lx, radius_cut, include_mask=None):
    """D2min of every particle between two frames (Lee & Hurley App. B, Eqs. B1-B4).

    Parameters
    ----------
    pos_ref, pos_cur : ndarray, shape (N, 2)
        Positions at gamma - dgamma (defines neighbourhoods) and gamma; x
        unwrapped (any length unit; the runs use m).
    lx : float
        Box length in x (same unit).
    radius_cut : float
        Neighbourhood radius (same unit; the paper uses 5 r_p).
    include_mask : ndarray of bool, shape (N,), optional
        Particles used as centres and as neighbours (non-rattlers).

    Returns
    -------
    ndarray, shape (N,)
        D2min (Eq. B1, length^2) with ``Gamma = X Y^-1`` (Eqs. B2-B4); NaN for
        excluded particles and for degenerate neighbourhoods (< 2 neighbours
        or collinear).

    Raises
    ------
    ParameterError
        Positions not finite real (N, 2) arrays, ``lx`` not finite > 0,
        ``radius_cut`` not in (0, lx/2), a mask of another length.
    """
    check_finite_array("pos_ref", pos_ref, shape=(None, 2))
    check_finite_array("pos_cur", pos_cur, shape=(None, 2))
    check_real("lx", lx, 0.0, low_open=True)
    check_real("radius_cut", radius_cut, 0.0, low_open=True)
    if include_mask is not None and np.shape(include_mask) != (np.shape(pos_ref)[0],):
        raise ParameterError(f"include_mask must have shape ({np.shape(pos_ref)[0]},), got "
                             f"{np.shape(include_mask)}")
    pos_ref = np.asarray(pos_ref, dtype=np.float64)
    pos_cur = np.asarray(pos_cur, dtype=np.float64)
    if pos_ref.shape != pos_cur.shape or pos_ref.ndim != 2 or pos_ref.shape[1] != 2:
        raise ParameterError(f"d2min: positions must both be (N, 2), got {pos_ref.shape} "
                             f"and {pos_cur.shape}")
    n = pos_ref.shape[0]
    i, j, s = neighbour_pairs(pos_ref, lx, radius_cut, include_mask)
    off = np.column_stack([s * lx, np.zeros_like(s)])
    dr = pos_ref[j] - pos_ref[i] - off
    dc = pos_cur[j] - pos_cur[i] - off
    cnt = np.bincount(i, minlength=n).astype(np.float64)
    X = np.empty((n, 2, 2))
    Y = np.empty((n, 2, 2))
    for a in range(2):
        for b in range(2):
            X[:, a, b] = np.bincount(i, dc[:, a] * dr[:, b], minlength=n)
            Y[:, a, b] = np.bincount(i, dr[:, a] * dr[:, b], minlength=n)
    det = Y[:, 0, 0] * Y[:, 1, 1] - Y[:, 0, 1] * Y[:, 1, 0]
    trace = Y[:, 0, 0] + Y[:, 1, 1]
    ok = (cnt >= 2) & (det > 1e-12 * trace**2)
    if include_mask is not None:
        ok &= np.asarray(include_mask, dtype=bool)
    safe = np.where(ok, det, 1.0)
    yinv = np.empty_like(Y)
    yinv[:, 0, 0] = Y[:, 1, 1] / safe
    yinv[:, 1, 1] = Y[:, 0, 0] / safe
    yinv[:, 0, 1] = -Y[:, 0, 1] / safe
    yinv[:, 1, 0] = -Y[:, 1, 0] / safe
    gamma = X @ yinv
    res = dc - np.einsum("pab,pb->pa", gamma[i], dr)
    out = np.bincount(i, (res**2).sum(axis=1), minlength=n) / np.maximum(cnt, 1)
    out[cnt == 2] = 0.0  # Gamma maps both neighbours exactly: B1 is identically 0
    out[~ok] = np.nan
    return out


def nonaffine_displacement(pos_ref, pos_cur, include_mask=None):
    """Displacement minus the global best-fit affine map (Fig. 7), shape (N, 2).

    The map u = A (r - c) + b is fitted by least squares over the included
    particles (c their reference centroid); excluded particles get NaN.
    """
    pos_ref = np.asarray(pos_ref, dtype=np.float64)
    u = np.asarray(pos_cur, dtype=np.float64) - pos_ref
    mask = np.ones(len(pos_ref), bool) if include_mask is None else np.asarray(include_mask)
    if mask.sum() < 3:
        raise ParameterError("nonaffine_displacement: need >= 3 included particles")
    c = pos_ref[mask].mean(axis=0)
    dr = pos_ref - c
    design = np.column_stack([dr[mask], np.ones(mask.sum())])
    coef, *_ = np.linalg.lstsq(design, u[mask], rcond=None)
    out = u - (np.column_stack([dr, np.ones(len(dr))]) @ coef)
    out[~mask] = np.nan
    return out


def _pair_keys(ij, n):
    return ij[:, 0].astype(np.int64) * n + ij[:, 1]


def differential_forces(frames, k):
    """|f_k| - |f_{k-1}| per contact of frame ``k`` (0 for new contacts), shape (M_k,)."""
    if not 1 <= k < frames.n_frames:
        raise ParameterError(f"differential_forces: k={k} must lie in [1, {frames.n_frames})")
    ij1, f1, *_ = frames.contacts(k)
    ij0, f0, *_ = frames.contacts(k - 1)
    n = frames.n_particles
    key0, key1 = _pair_keys(ij0, n), _pair_keys(ij1, n)
    out = np.zeros(len(key1))
    if len(key0) == 0:
        return out
    order = np.argsort(key0)
    loc = np.minimum(np.searchsorted(key0[order], key1), len(key0) - 1)
    found = key0[order][loc] == key1
    prev = np.hypot(f0[:, 0], f0[:, 1])[order][loc]
    mag1 = np.hypot(f1[:, 0], f1[:, 1])
    out[found] = mag1[found] - prev[found]
    return out


def contact_angle(force):
    """Angle of the force line with the x-axis, folded into (-pi/2, pi/2] (Fig. 8d)."""
    th = np.arctan2(force[:, 1], force[:, 0])
    th = np.where(th > np.pi / 2, th - np.pi, th)
    return np.where(th <= -np.pi / 2, th + np.pi, th)


def gr_regions(frames, k, eps, fraction=0.01, min_samples=2):
    """GR regions at step ``k``: DBSCAN clusters of the particles of the GR contacts.

    Returns
    -------
    dict
        ``contacts`` (indices into frame k's contacts), ``particles``,
        ``labels`` (per particle, -1 noise), ``n_clusters``, ``abs_angle``
        (|theta| of the GR contacts), ``angle_mean``, ``angle_median``.
    """
    from sklearn.cluster import DBSCAN

    if not 0 < fraction <= 1:
        raise ParameterError(f"gr_regions: fraction = {fraction} must lie in (0, 1]")
    df = differential_forces(frames, k)
    ij, force, *_ = frames.contacts(k)
    n_gr = math.ceil(fraction * len(df))
    order = np.argsort(df, kind="stable")[:n_gr]
    sel = order[df[order] < 0]
    parts = np.unique(ij[sel].ravel())
    out = {"contacts": sel, "particles": parts, "labels": np.zeros(0, np.int64),
           "n_clusters": 0, "abs_angle": np.abs(contact_angle(force[sel])),
           "angle_mean": np.nan, "angle_median": np.nan}
    if len(sel):
        out["angle_mean"] = float(out["abs_angle"].mean())
        out["angle_median"] = float(np.median(out["abs_angle"]))
    if len(parts):
        p = frames.pos[k][parts]
        d = p[:, None, :] - p[None, :, :]
        d[..., 0] = _min_image(d[..., 0], frames.lx)
        dist = np.hypot(d[..., 0], d[..., 1])
        labels = DBSCAN(eps=eps, min_samples=min_samples, metric="precomputed").fit(dist).labels_
        out["labels"] = labels
        out["n_clusters"] = int(labels.max() + 1)
    return out


def particle_stress(frames, k):
    """Per-particle stress tensors (N, 2, 2) at frame ``k`` (Sec. 3.2, Fig. 8a)."""
    ij, force, *_ = frames.contacts(k)
    pos, rad, n = frames.pos[k], frames.radius, frames.n_particles
    i, j = ij[:, 0], ij[:, 1]
    d = pos[j] - pos[i]
    d[:, 0] = _min_image(d[:, 0], frames.lx)
    dist = np.hypot(d[:, 0], d[:, 1])
    nrm = d / np.where(dist > 0, dist, 1.0)[:, None]
    delta = rad[i] + rad[j] - dist
    ri = nrm * (rad[i] - delta / 2)[:, None]
    rj = -nrm * (rad[j] - delta / 2)[:, None]
    sig = np.zeros((n, 2, 2))
    for a in range(2):
        for b in range(2):
            sig[:, a, b] = (np.bincount(i, ri[:, a] * force[:, b], minlength=n)
                            + np.bincount(j, rj[:, a] * -force[:, b], minlength=n))
    return sig / (np.pi * rad**2)[:, None, None]


def _max_principal(sig):
    sym = 0.5 * (sig + np.swapaxes(sig, 1, 2))
    return np.linalg.eigvalsh(sym)[:, -1]


def paper_tables(tables):
    """The Spearman tables of :func:`analyze` under the names of the paper's figures (markdown)."""
    return tables_markdown({"Delta tau per step (Fig. 9a)": tables["step_dtau"],
                            "all phases (Fig. 9b)": tables["phase_all"],
                            "long phases, t_p > 3 dgamma (Fig. 10a)": tables["phase_long"],
                            "short phases (Fig. 10b)": tables["phase_short"],
                            "Delta tau_p - t_p (Fig. 10c)": tables["phase_tp"]},
                           "Lee & Hurley correlations")


@dataclass(frozen=True)
class ShearAnalysis:
    """Result of :func:`analyze`: per-step arrays, phases and Spearman tables."""

    arrays: dict
    phases: np.ndarray
    tables: dict
    summary: dict

    def to_json(self):
        """JSON-serialisable dict: summary, parameters and tables."""
        return {"summary": self.summary, "tables": self.tables}

    def npz_arrays(self):
        """Arrays for ``np.savez`` (per step and per phase)."""
        return {**self.arrays, "phases": self.phases}


#: Per-step arrays of :func:`analyze` that depend on the frames only (not on gamma0).
PER_STEP = ("g", "g10", "rho_sigma_d2", "n_clusters", "angle_mean", "angle_median",
            "n_rattlers")


def check_previous(frames, previous):
    """m, the frames of the earlier analysis ``previous`` (arrays), if they begin ``frames``.

    ParameterError unless its strain and tau series equal the first m of
    ``frames`` to the bit (a chaotic run that went another way differs
    within a few frames).
    """
    m, T = len(previous["tau"]), frames.n_frames
    if not (2 <= m <= T and np.array_equal(previous["strain"], frames.strain[:m]) and
            np.array_equal(previous["tau"], frames.tau[:m])):
        raise ParameterError(f"the earlier analysis ({m} frames) is not one of the first "
                             f"frames of these {T} (its strain and tau differ)")
    return m


def analyze(frames, gamma0, *, radius_factor=5.0, fraction=0.01, ts_rule="min_gr",
            frames_range=None, keep_d2min=False, progress=True, previous=None):
    """All analyses of a plane-shear run over its output steps (Lee & Hurley Secs. 3.2-3.3).

    Per step: rattlers, D2min (App. B), its maximum and top-10 % mean, GR
    regions (DBSCAN) and their contact angles, the Spearman correlation of the
    particle-stress change with D2min (Fig. 8a); per stick or slip phase
    (Eqs. 1-4) its metrics; and the Spearman tables of Figs. 9-10.

    Parameters
    ----------
    frames : Frames
        The run's frames (SI per unit thickness).
    gamma0 : float
        Start of the analysed window: steps with reference strain >= gamma0
        (dimensionless; the paper uses 2.2 %, i.e. 0.022).
    radius_factor : float
        D2min and DBSCAN radius in units of the mean radius r_p (paper: 5).
    fraction : float
        GR fraction of contacts (paper: 1 %, i.e. 0.01).
    ts_rule : {"min_gr", "start"}
        t_s of Eqs. 3-4: the step of the phase with the fewest GR clusters, or
        the whole phase.
    frames_range : (int, int), optional
        Restrict the per-step particle analyses to steps in [start, stop).
    keep_d2min : bool
        Also return the (T, N) D2min field (m^2).
    progress : bool
        tqdm progress bar.
    previous : mapping, optional
        The arrays (``analysis.npz``) of an earlier analysis, with the same
        ``radius_factor`` and ``fraction``, of the first m frames of these
        frames (a ``--partial`` analysis of a run that has gone on): its
        per-step arrays :data:`PER_STEP` are taken for steps 1..m-1 and only
        the steps from m are computed; the result is bit-identical to a
        fresh analysis.  ParameterError unless its strain and tau series
        equal these frames' first m to the bit.

    Returns
    -------
    ShearAnalysis
        ``arrays`` (per step and per phase), ``phases`` (P, 2: first and last
        step), ``tables`` (Spearman rho, p, n) and ``summary`` (phase counts,
        largest drop of tau, ...).

    Raises
    ------
    ParameterError
        Fewer than 2 frames, or no bulk particles.
    """
    from tqdm import tqdm

    T, N = frames.n_frames, frames.n_particles
    if T < 2:
        raise ParameterError(f"analyze: need >= 2 frames, got {T}")
    bulk = frames.kind == 0
    if not bulk.any():
        raise ParameterError("analyze: no bulk particles (kind == 0)")
    rp = float(frames.radius[bulk].mean())
    rcut = radius_factor * rp
    start, stop = frames_range or (1, T)
    if not 1 <= start < stop <= T:
        raise ParameterError(f"analyze: frames_range {frames_range} must satisfy 1 <= start < stop <= {T}")
    first = start    # the first step computed here
    if previous is not None:
        if frames_range is not None or keep_d2min:
            raise ParameterError("analyze: previous= goes with neither frames_range nor "
                                 "keep_d2min")
        first = check_previous(frames, previous)
    nan = np.full(T, np.nan)
    arr = {"strain": np.array(frames.strain), "tau": np.array(frames.tau),
           "dtau": np.concatenate([[np.nan], np.diff(frames.tau)]),
           "g": nan.copy(), "g10": nan.copy(), "rho_sigma_d2": nan.copy(),
           "n_clusters": np.zeros(T, np.int64), "angle_mean": nan.copy(),
           "angle_median": nan.copy(), "n_rattlers": np.zeros(T, np.int64)}
    field = np.full((T, N), np.nan) if keep_d2min else None
    if previous is not None:
        for name in PER_STEP:
            arr[name][:first] = previous[name]
    ratt_prev = rattler_mask(frames, first - 1)
    smax_prev = _max_principal(particle_stress(frames, first - 1))
    for k in tqdm(range(first, stop), disable=not progress, desc="shear analysis"):
        signals.check(f" at frame {k}")
        ratt = rattler_mask(frames, k)
        arr["n_rattlers"][k] = int(ratt.sum())
        d2 = d2min(frames.pos[k - 1], frames.pos[k], frames.lx, rcut, ~ratt_prev)
        if field is not None:
            field[k] = d2
        arr["g"][k], arr["g10"][k] = step_metrics(d2, bulk)
        gr = gr_regions(frames, k, rcut, fraction)
        arr["n_clusters"][k] = gr["n_clusters"]
        arr["angle_mean"][k], arr["angle_median"][k] = gr["angle_mean"], gr["angle_median"]
        smax = _max_principal(particle_stress(frames, k))
        cell = spearman_cell(np.abs(smax - smax_prev)[bulk], d2[bulk])
        arr["rho_sigma_d2"][k] = np.nan if cell["rho"] is None else cell["rho"]
        ratt_prev, smax_prev = ratt, smax
    if field is not None:
        arr["d2min"] = field
    in_window = np.zeros(T, bool)
    in_window[start:stop] = frames.strain[start - 1:stop - 1] >= gamma0
    phases = find_phases(frames.tau, in_window)
    pm = phase_metrics(phases, arr["tau"], arr["g"], arr["g10"], arr["n_clusters"], ts_rule)
    for name, v in pm.items():
        arr[f"phase_{name}"] = v
    dt, tp = pm["dtau_p"], pm["t_p"]
    long_, short = tp > 3, tp <= 3
    pvals = {"mg": pm["mg"], "mg10": pm["mg10"], "sg": pm["sg"], "sg10": pm["sg10"]}
    w = in_window
    tables = {
        "step_dtau": binned_spearman(arr["dtau"][w], {"g": arr["g"][w], "g10": arr["g10"][w]}),
        "phase_all": binned_spearman(dt, pvals),
        "phase_long": binned_spearman(dt[long_], {n: v[long_] for n, v in pvals.items()}),
        "phase_short": binned_spearman(dt[short], {n: v[short] for n, v in pvals.items()}),
        "phase_tp": {"long": binned_spearman(dt[long_], {"t_p": tp[long_]})["t_p"],
                     "short": binned_spearman(dt[short], {"t_p": tp[short]})["t_p"]},
    }
    n_steps = int(w.sum())
    span = float(frames.strain[stop - 1] - max(gamma0, frames.strain[start - 1])) if n_steps else 0.0
    summary = {"gamma0": gamma0, "r_p": rp, "radius_cut": rcut, "fraction": fraction,
               "ts_rule": ts_rule, "steps": [int(start), int(stop)],
               **phase_summary(phases, pm, n_steps, span)}
    return ShearAnalysis(arrays=arr, phases=phases, tables=tables, summary=summary)
