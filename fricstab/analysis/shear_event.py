"""Verdicts on Lee & Hurley's statements about the largest slip (Sec. 3.2, Figs. 3-8; Sec. 5).

Frames and the per-step arrays of :func:`fricstab.analysis.shear.analyze` in, plain
JSON-serialisable dicts out.  A *statement* is a dict: ``id``, ``figure``, ``paper`` (the
paper's words), ``ours`` (text), ``values``, ``rule``, ``verdict`` (one of
:data:`VERDICTS`) and ``why``.  :func:`judge_event` runs them all.  Conventions of steps,
rattlers, D2min and GR regions: :mod:`fricstab.analysis.shear`; here:

* The *event* is a slip phase (:func:`fricstab.analysis.shear_phases.find_phases`), by
  default the one with the most negative ``Delta tau_p``.  Stage II is its steps a..b
  (tau decreasing), Stage I the ``pad`` steps before it, Stage III the ``pad`` steps after
  it, clipped to the frames (Fig. 2b: the paper's window is ~28 output steps around a slip
  of ~6-10, hence ``pad = 10``).
* The *onset* of Stage II is its first ``onset`` steps (the paper's Steps 4-5; Stage II
  begins at Step 4).  The *single run* is the first run of consecutive Stage II steps with
  exactly one GR cluster (the paper's Steps 4-5); the Stage II steps after it are the
  paper's Steps 6-9.
* r_p is the mean bulk radius; distances are minimum-image in x; centroids are periodic in
  x (circular mean).  The top 1 % of D2min are the ``ceil(0.01 n)`` largest of the n
  finite bulk values (as ``g_t10%`` takes the top 10 %).
* A statement of several parts agrees when every part holds, disagrees when one fails, and
  is not comparable when none fails but one cannot be evaluated (too few steps, ...).
"""

import math

import numpy as np

from fricstab.analysis.shear import (d2min, differential_forces, gr_regions,
                                     nonaffine_displacement, rattler_mask)
from fricstab.analysis.shear_fields import (QUADRUPOLAR, angular_modes, concentration,
                                           distance as _dist, periodic_centroid as _centroid)
from fricstab.analysis.shear_phases import spearman_cell
from fricstab.errors import ParameterError
from fricstab.io.files import json_clean

__all__ = ["PAPER", "VERDICTS", "angular_modes", "concentration", "event_window",
           "force_localisation", "gr_consolidation", "judge_event", "rearrangement_site",
           "stage_courses", "step_spans", "stz_quadrupole"]

#: The verdict labels.
VERDICTS = ("agrees", "disagrees", "not comparable")
HIGH_RHO = 0.4       # rho >= 0.4: moderate or strong, "high" (validation/shear_paper.py)
NEAR_SHARE = 0.8     # statement 2: the GR neighbourhood carries >= 80 % of the force change
NEAR_MAX = 0.5       # ... judged only where it holds <= half of the contacts
CONCENTRATED = 2.0   # statement 4: >= 2x its share of the non-affine motion within 5 r_p
ALPHA = 0.05
TOP_D2 = 0.01        # the paper's top 1 % of D2min

#: Statement id -> (figure, the paper's words).
PAPER = {
    "1": ("Figs. 3-4, 8c", "Initially, in Stage I, the GR regions were multiple and spatially "
          "dispersed (Fig. 3). At the onset of Stage II, they converged into a single region "
          "before dispersing once again in Stage III (Figs. 4-5). [...] A single GR region was "
          "first established at Steps 4-5. [...] From Step 6 of this stress drop event, the "
          "single GR region no longer existed"),
    "2": ("Fig. 4", "In any contact points other than those in the single GR region, "
          "inter-particle force change was almost zero during Steps 4-5 (Fig. 4)."),
    "3": ("Figs. 4-5", "the D2min distribution shows that particle rearrangements continued "
          "occurring at the location where the single GR region was first established in "
          "Steps 6-9 (Fig. 4)."),
    "4": ("Fig. 7", "There was a distinct region of concentrated non-affine displacement at "
          "each of Steps 5-6. This region coincided with the single clustered region of high "
          "D2min, or STZ, in Figure 4. During these steps, the non-affine displacement field "
          "exhibited quadrupolar symmetry"),
    "5a": ("Fig. 8a", "the correlation between |Delta sigma_p| and D2min was high during "
           "Steps 4-5 [...] However, from Step 6 in Stage II, the correlation between "
           "|Delta sigma_p| and D2min became weak because the single GR region collapsed"),
    "5b": ("Fig. 8b", "the sample exhibited stability in Stage I marked by low gD2min values. "
           "At the onset of Stage II, we observed an increase in gD2min [...] in Stage III, "
           "gD2min gradually decreased [...] The g_t10%D2min shows the same trend with gD2min"),
    "5d": ("Fig. 8d", "Both the average and median of the absolute values of contact angles "
           "in the GR force regions fluctuated significantly from Stage II, indicating no "
           "discernible trends once particle rearrangement started to occur."),
}
NEEDED = ("tau", "phases", "phase_dtau_p", "n_clusters", "g", "g10", "rho_sigma_d2",
          "angle_mean", "angle_median")


def _f(x, fmt=".3g"):
    return "n/a" if x is None else format(x, fmt)


def step_spans(steps, values=None):
    """Steps as runs: "3-5, 8" (with ``values``: runs of equal values, "3-5: 1, 8: 2")."""
    out, i = [], 0
    while i < len(steps):
        j = i
        while j + 1 < len(steps) and steps[j + 1] == steps[j] + 1 and (
                values is None or values[j + 1] == values[i]):
            j += 1
        out.append(f"{steps[i]}" + (f"-{steps[j]}" if j > i else "")
                   + ("" if values is None else f": {values[i]}"))
        i = j + 1
    return ", ".join(out) or "none"


def _verdict(parts):
    """(verdict, why) of a statement of several parts (True, False, None: not evaluable)."""
    vals = list(parts.values())
    verdict = ("disagrees" if False in vals else "not comparable" if None in vals or not vals
               else "agrees")
    why = "; ".join(f"{k}: {'holds' if v else 'not evaluable' if v is None else 'fails'}"
                    for k, v in parts.items())
    return verdict, why or "nothing to evaluate"


def _statement(sid, ours, values, rule, verdict, why):
    fig, words = PAPER[sid]
    return json_clean({"id": sid, "figure": fig, "paper": words, "ours": ours, "values": values,
                "rule": rule, "verdict": verdict, "why": why})


def _rp(frames):
    return float(frames.radius[np.asarray(frames.kind) == 0].mean())


def _top_d2(frames, k, rcut):
    """Bulk particles with finite D2min at step ``k`` and the top 1 % of them (as analyze)."""
    d2 = d2min(frames.pos[k - 1], frames.pos[k], frames.lx, rcut, ~rattler_mask(frames, k - 1))
    elig = np.flatnonzero((np.asarray(frames.kind) == 0) & np.isfinite(d2))
    return elig, elig[np.argsort(-d2[elig], kind="stable")[:math.ceil(TOP_D2 * len(elig))]]


def _cluster(frames, k, eps, fraction):
    """The particles of the single GR cluster of step ``k``."""
    gr = gr_regions(frames, k, eps, fraction)
    if gr["n_clusters"] != 1:
        raise ParameterError(f"step {k}: the analysis counts one GR cluster, these frames "
                             f"{gr['n_clusters']}: another analysis, radius or fraction?")
    return gr["particles"][gr["labels"] == 0]


def event_window(arrays, event=None, pad=10, onset=2):
    """The event (a slip phase), its window and its stages, from the analysis arrays.

    Parameters
    ----------
    arrays : mapping
        The arrays of :func:`fricstab.analysis.shear.analyze` (``analysis.npz``).
    event : int, optional
        Index into ``arrays["phases"]`` of a slip phase; default the largest slip.
    pad, onset : int
        Steps of Stages I and III each side of the slip; steps of the onset.

    Returns
    -------
    dict
        ``event``, ``first``/``last`` step, ``t_p``, ``dtau_p``, ``at_end`` (the slip
        reaches the last frame: it may go on), ``strain``, ``steps``,
        ``stages``, ``stage_steps``, ``onset``, ``single_steps`` (Stage II steps with one GR
        cluster), ``single_run``.

    Raises
    ------
    ParameterError
        Arrays missing, no slip, ``event`` out of range or a stick, bad ``pad``/``onset``.
    """
    missing = [k for k in NEEDED if k not in arrays]
    if missing:
        raise ParameterError(f"the analysis arrays lack {', '.join(missing)}: give the arrays "
                             "of fricstab.analysis.shear.analyze (RUN/analysis.npz)")
    for name, v, low in (("pad", pad, 0), ("onset", onset, 1)):
        if isinstance(v, bool) or not isinstance(v, (int, np.integer)) or v < low:
            raise ParameterError(f"{name} = {v!r}: an integer >= {low}")
    phases = np.asarray(arrays["phases"], np.int64).reshape(-1, 2)
    dt, T = np.asarray(arrays["phase_dtau_p"], float), len(arrays["tau"])
    slips = np.flatnonzero(dt < 0)
    largest = int(slips[np.argmin(dt[slips])]) if len(slips) else None
    if event is None:
        if largest is None:
            raise ParameterError(f"no slip phase (Delta tau_p < 0) among the {len(phases)} "
                                 "phases of the analysed window: no event to judge")
        event = largest
    elif isinstance(event, bool) or not isinstance(event, (int, np.integer)) or \
            not 0 <= event < len(phases):
        raise ParameterError(f"event = {event!r}: a phase index in [0, {len(phases)}) "
                             f"({len(slips)} slips; the largest is phase {largest})")
    elif dt[event] >= 0:
        raise ParameterError(f"event = {event}: phase {event} is a stick (Delta tau_p = "
                             f"{dt[event]:+.3g}), not a slip")
    a, b = (int(v) for v in phases[event])
    steps = list(range(max(1, a - pad), min(T - 1, b + pad) + 1))
    stages = ["I" if k < a else "II" if k <= b else "III" for k in steps]
    single = [k for k in range(a, b + 1) if arrays["n_clusters"][k] == 1]
    run = single[:1]
    while run and run[-1] + 1 in single:
        run.append(run[-1] + 1)
    strain = arrays.get("strain")
    return json_clean({"event": event, "n_phases": len(phases), "first": a, "last": b,
                "t_p": b - a + 1, "dtau_p": dt[event], "at_end": b == T - 1,
                "strain": None if strain is None else [strain[a - 1], strain[b]],
                "pad": pad, "steps": steps, "stages": stages,
                "stage_steps": {s: [k for k, t in zip(steps, stages) if t == s]
                                for s in ("I", "II", "III")},
                "onset": list(range(a, min(a + onset, b + 1))), "single_steps": single,
                "single_run": run})


def gr_consolidation(arrays, window, frames=None, fraction=0.01):
    """Statement 1 (Figs. 3-4, 8c): several GR clusters in Stage I, one at the onset of
    Stage II, several again in Stage III.

    Rule: the median cluster count over Stage I is >= 2, some onset step has exactly 1,
    the median over Stage III is >= 2.  Not comparable where ``ceil(fraction M)`` is one
    contact at every step (``frames`` given): then one cluster is all there can be.

    Parameters
    ----------
    arrays, window, frames, fraction
        As :func:`judge_event` (``frames`` optional: to count the GR contacts possible).

    Returns
    -------
    dict
        The statement.
    """
    nc, st = np.asarray(arrays["n_clusters"]), window["stage_steps"]
    med = {s: float(np.median(nc[st[s]])) if st[s] else None for s in st}
    parts = {"Stage I several": None if med["I"] is None else med["I"] >= 2,
             "one at the onset": any(nc[k] == 1 for k in window["onset"]),
             "Stage III several": None if med["III"] is None else med["III"] >= 2}
    verdict, why = _verdict(parts)
    most = None
    if frames is not None:
        most = max(math.ceil(fraction * len(frames.contacts(k)[0])) for k in window["steps"])
        if most < 2:
            verdict, why = "not comparable", (f"{fraction:.0%} of the contacts is {most} "
                                              f"contact: one cluster at most ({why})")
    counts = {k: int(nc[k]) for k in window["steps"]}
    ours = (f"GR clusters (steps: count) {step_spans(window['steps'], list(counts.values()))}; "
            f"medians I / II / III {_f(med['I'])} / {_f(med['II'])} / {_f(med['III'])}")
    return _statement("1", ours, {"counts": counts, "medians": med, "gr_contacts_max": most,
                                  "parts": parts},
                      "median GR clusters over Stage I >= 2; exactly 1 at one of the onset "
                      "steps; median over Stage III >= 2", verdict, why)


def force_localisation(frames, window, radius_factor=5.0, fraction=0.01):
    """Statement 2 (Fig. 4): the force change is almost zero away from the single GR region.

    At each Stage II step with one GR cluster, the share of the total ``|df|``
    (:func:`fricstab.analysis.shear.differential_forces`) on contacts with a particle within
    ``radius_factor`` r_p of a particle of the cluster.  Rule: >= :data:`NEAR_SHARE` at every
    such step.  Then the other contacts (most of them) carry at most a fifth of the change,
    a mean per contact under a tenth of the near ones' where the neighbourhood holds < 30 %
    of the contacts: blank on Fig. 4's colour scale, which the GR changes set.  Not
    comparable without such a step, or where the neighbourhood holds more than
    :data:`NEAR_MAX` of the contacts (no "elsewhere") or no force changes.

    Parameters
    ----------
    frames, window, radius_factor, fraction
        As :func:`judge_event`.

    Returns
    -------
    dict
        The statement.
    """
    rp, lx, rows = _rp(frames), frames.lx, []
    for k in window["single_steps"]:
        cl, pos = _cluster(frames, k, radius_factor * rp, fraction), frames.pos[k]
        near = _dist(pos[:, None, :], pos[None, cl, :], lx).min(1) <= radius_factor * rp
        ij, df = frames.contacts(k)[0], np.abs(differential_forces(frames, k))
        nc = near[ij[:, 0]] | near[ij[:, 1]]
        ratio = (df[~nc].mean() / df[nc].mean() if nc.any() and (~nc).any()
                 and df[nc].sum() > 0 else None)
        rows.append({"step": k, "share_near": df[nc].sum() / df.sum() if df.sum() > 0 else None,
                     "contacts_near": nc.mean(), "far_over_near": ratio})
    judged = [r for r in rows if r["share_near"] is not None and r["contacts_near"] <= NEAR_MAX]
    if not judged:
        verdict, why = "not comparable", (
            "no Stage II step with a single GR cluster" if not rows else
            f"the {radius_factor:g} r_p neighbourhood holds more than {NEAR_MAX:.0%} of the "
            "contacts, or no force changes")
    else:
        bad = [r["step"] for r in judged if r["share_near"] < NEAR_SHARE]
        verdict = "disagrees" if bad else "agrees"
        why = (f"share < {NEAR_SHARE} at steps {step_spans(bad)}" if bad else
               f"share >= {NEAR_SHARE} at all {len(judged)} single-cluster steps")
    ours = "; ".join(f"step {r['step']}: share near {_f(r['share_near'])} (contacts near "
                     f"{_f(r['contacts_near'])}, mean far / near {_f(r['far_over_near'])})"
                     for r in rows) or "no Stage II step with one GR cluster"
    if len(rows) > 4:
        v = {n: [r[n] for r in rows if r[n] is not None] for n in ("share_near", "contacts_near")}
        ours = (f"{len(rows)} steps ({step_spans([r['step'] for r in rows])}): share near, median "
                f"{_f(_stat(v['share_near'], None, np.median))} (range "
                f"{_f(_stat(v['share_near'], None, np.min))}-"
                f"{_f(_stat(v['share_near'], None, np.max))}); contacts near, median "
                f"{_f(_stat(v['contacts_near'], None, np.median))}")
    return _statement("2", ours, {"steps": rows}, "share of the total absolute force change on "
                      f"contacts within {radius_factor:g} r_p of the single GR cluster >= "
                      f"{NEAR_SHARE} at every Stage II step with one cluster (judged where those "
                      f"contacts are <= {NEAR_MAX:.0%} of all)", verdict, why)


def rearrangement_site(frames, window, radius_factor=5.0, fraction=0.01, n_perm=2000, seed=0):
    """Statement 3 (Figs. 4-5): rearrangements continue where the single GR region formed.

    At each Stage II step after the single run (the paper's Steps 6-9): the distance, in
    r_p, from the centroid of the top 1 % D2min particles to the centroid of the GR cluster
    at the run's first step.  Reference: the same mean distance for as many bulk particles
    with finite D2min drawn at random per step, ``n_perm`` times.  Rule: agrees when the
    one-sided p = (1 + #{random <= ours}) / (1 + n_perm) <= 0.05 (Monte Carlo error of p
    at 0.05 with 2000 draws: 0.005).  Not comparable without a single run, or without a
    Stage II step after it.

    Parameters
    ----------
    frames, window, radius_factor, fraction, n_perm, seed
        As :func:`judge_event`.

    Returns
    -------
    dict
        The statement.
    """
    if isinstance(n_perm, bool) or not isinstance(n_perm, (int, np.integer)) or n_perm < 19:
        raise ParameterError(f"n_perm = {n_perm!r}: an integer >= 19 (p can reach 0.05)")
    rp, lx, run = _rp(frames), frames.lx, window["single_run"]
    after = [k for k in window["stage_steps"]["II"] if run and k > run[-1]]
    rule = ("mean distance from the top-1 % D2min centroid to the first single GR cluster's "
            "centroid over the Stage II steps after the single run, against random draws of "
            f"as many particles: one-sided p <= {ALPHA}")
    if not after:
        why = "no single GR cluster in Stage II" if not run else "no Stage II step after it"
        return _statement("3", why, {"single_run": run}, rule, "not comparable", why)
    centre = _centroid(frames.pos[run[0]][_cluster(frames, run[0], radius_factor * rp,
                                                   fraction)], lx)
    rng, obs, ref = np.random.default_rng(seed), [], np.zeros(int(n_perm))
    for k in after:
        elig, top = _top_d2(frames, k, radius_factor * rp)
        if not len(top):
            why = f"no finite bulk D2min at step {k}"
            return _statement("3", why, {}, rule, "not comparable", why)
        pos = frames.pos[k]
        obs.append(float(_dist(_centroid(pos[top], lx), centre, lx)) / rp)
        keys = rng.random((int(n_perm), len(elig)))
        pick = elig[np.argpartition(keys, len(top) - 1, axis=1)[:, :len(top)]]
        ref += _dist(_centroid(pos[pick], lx), centre, lx) / rp / len(after)
    mean = float(np.mean(obs))
    p = float((1 + np.sum(ref <= mean)) / (1 + n_perm))
    med, q05 = float(np.median(ref)), float(np.quantile(ref, 0.05))
    ours = (f"steps {step_spans(after)}: distances {[round(d, 2) for d in obs]} r_p, mean "
            f"{mean:.2f} r_p; "
            f"random: median {med:.2f} r_p, 5 % quantile {q05:.2f} r_p; p = {p:.3g}")
    values = {"steps": after, "distance_rp": obs, "mean_rp": mean, "random_median_rp": med,
              "random_q05_rp": q05, "p": p, "single_run": run, "centre": centre}
    return _statement("3", ours, values, rule, "agrees" if p <= ALPHA else "disagrees",
                      f"p = {p:.3g} {'<=' if p <= ALPHA else '>'} {ALPHA}")


def stz_quadrupole(frames, arrays, window, radius_factor=5.0, r_in=1.0, r_out=6.0):
    """Statement 4 (Fig. 7): concentrated, quadrupolar non-affine displacement at the STZ.

    Steps: the last step of the single run and the next, within Stage II (the paper's Steps
    5-6); without a single run, the Stage II step of greatest gD2min and the next.  Per
    step, over bulk non-rattlers (:func:`fricstab.analysis.shear.nonaffine_displacement`):
    the STZ centre is the centroid of the top 1 % D2min particles within ``radius_factor``
    r_p of the greatest; :func:`concentration` within ``radius_factor`` r_p and
    :func:`angular_modes` in ``r_in``-``r_out`` r_p.  Rule: at every step an enrichment
    >= :data:`CONCENTRATED` (a field without structure: 1 +- ~0.2) and quadrupolar.

    Parameters
    ----------
    frames, arrays, window, radius_factor
        As :func:`judge_event`.
    r_in, r_out : float
        The annulus of :func:`angular_modes`, in r_p.

    Returns
    -------
    dict
        The statement.
    """
    rp, lx, two = _rp(frames), frames.lx, window["stage_steps"]["II"]
    if window["single_run"]:
        k0, source = window["single_run"][-1], "the end of the single run"
    else:
        g = np.asarray(arrays["g"], float)[two]
        k0 = two[int(np.nanargmax(g))] if np.isfinite(g).any() else None
        source = "the greatest gD2min of Stage II (no single run)"
    rows = []
    for k in [k for k in (k0, None if k0 is None else k0 + 1) if k in two]:
        _, top = _top_d2(frames, k, radius_factor * rp)
        keep, ref = ~rattler_mask(frames, k - 1), np.asarray(frames.pos[k - 1], float)
        if not len(top):
            rows.append({"step": k, "enrichment": None, "modes": None, "ok": None})
            continue
        na = nonaffine_displacement(ref, frames.pos[k], keep)
        centre = _centroid(ref[top[_dist(ref[top], ref[top[0]], lx) <= radius_factor * rp]], lx)
        bulk = keep & (np.asarray(frames.kind) == 0)
        e = concentration(ref[bulk], na[bulk], centre, radius_factor * rp, lx)
        m = angular_modes(ref[bulk], na[bulk], centre, lx, r_in * rp, r_out * rp)
        ok = None if e is None or m["quadrupolar"] is None else bool(
            e >= CONCENTRATED and m["quadrupolar"])
        rows.append({"step": k, "centre": centre, "enrichment": e, "modes": m, "ok": ok})
    verdict, why = _verdict({f"step {r['step']}": r["ok"] for r in rows})
    ours = "; ".join(f"step {r['step']}: enrichment {_f(r['enrichment'], '.2f')}, shares m = 0-4 "
                     + (str([round(s, 2) for s in r["modes"]["shares"]])
                        if r["modes"] and r["modes"]["shares"] else
                        f"n/a ({r['modes']['status'] if r['modes'] else 'no D2min'})")
                     for r in rows) or "no step"
    return _statement("4", ours, {"steps": rows, "source": source},
                      f"at each STZ step: enrichment of the non-affine motion within "
                      f"{radius_factor:g} r_p of the STZ >= {CONCENTRATED:g}, and m = 2 the "
                      f"largest angular share of r u_r, >= {QUADRUPOLAR} ({r_in:g}-{r_out:g} r_p)",
                      verdict, f"steps from {source}; {why}")


def _stat(a, steps, f, least=1):
    """``f`` of the finite ``a[steps]`` (all of ``a`` for None); None if too few or not finite."""
    v = np.asarray(a, float)
    v = v if steps is None else v[steps] if steps else np.zeros(0)
    v = v[np.isfinite(v)]
    out = float(f(v)) if len(v) >= least else None
    return out if out is not None and math.isfinite(out) else None


def stage_courses(arrays, window):
    """Statements 5a, 5b, 5d (Fig. 8 a, b, d): the course of the per-step series.

    * 5a: the max of ``rho_sigma_d2`` over the onset >= :data:`HIGH_RHO`; its median over
      the later Stage II steps < :data:`HIGH_RHO` and below that max.
    * 5b: for ``g`` and ``g10``: the window's maximum lies in Stage II; the medians over
      Stages I and III are each below half of it (D2min spans decades in a slip).
    * 5d: for ``angle_mean`` and ``angle_median``: the sd over Stages II-III >= the sd over
      Stage I (about 10 steps each: a ratio without change is F-distributed, 95 % within
      ~0.25-4, so this part is weak) and no Spearman trend with the step there (p > 0.05).

    Parameters
    ----------
    arrays, window
        As :func:`judge_event`.

    Returns
    -------
    list of dict
        The three statements.
    """
    st, on = window["stage_steps"], window["onset"]
    later = [k for k in st["II"] if k not in on]
    hi = _stat(arrays["rho_sigma_d2"], on, np.max)
    lat = _stat(arrays["rho_sigma_d2"], later, np.median)
    parts = {"high at the onset": None if hi is None else hi >= HIGH_RHO,
             "weak later in Stage II": None if lat is None or hi is None else
             (lat < HIGH_RHO and lat < hi)}
    out = [_statement("5a", f"rho max over the onset {_f(hi, '.2f')} (steps {step_spans(on)}); "
                      f"median later in Stage II {_f(lat, '.2f')} (steps {step_spans(later)})",
                      {"onset_max": hi, "later_median": lat, "parts": parts},
                      f"max rho over the onset >= {HIGH_RHO}; median over the later Stage II "
                      f"steps < {HIGH_RHO} and below that max", *_verdict(parts))]
    parts, vals, txt = {}, {}, []
    for name in ("g", "g10"):
        top = _stat(arrays[name], st["II"], np.max)
        full = np.asarray(arrays[name], float)[window["steps"]]
        peak = window["steps"][int(np.nanargmax(full))] if np.isfinite(full).any() else None
        med = {s: _stat(arrays[name], st[s], np.median) for s in ("I", "III")}
        parts[f"{name} peaks in Stage II"] = None if peak is None else peak in st["II"]
        for s in ("I", "III"):
            parts[f"{name} low in Stage {s}"] = (None if med[s] is None or top is None
                                                 else med[s] < top / 2)
        vals[name] = {"peak_step": peak, "stage_II_max": top, "median_I": med["I"],
                      "median_III": med["III"]}
        txt.append(f"{name}: peak at step {peak}, Stage II max {_f(top)} m^2, medians I "
                   f"{_f(med['I'])} / III {_f(med['III'])} m^2")
    out.append(_statement("5b", "; ".join(txt), {**vals, "parts": parts},
                          "for gD2min and g_t10%D2min: the window's maximum in Stage II; the "
                          "Stage I and Stage III medians each < half the Stage II maximum",
                          *_verdict(parts)))
    parts, vals, txt = {}, {}, []
    after = st["II"] + st["III"]
    for name in ("angle_mean", "angle_median"):
        sd = [_stat(arrays[name], s, lambda v: np.std(v, ddof=1), n)
              for s, n in ((st["I"], 2), (after, 3))]
        ratio = None if None in sd or sd[0] == 0 else sd[1] / sd[0]
        cell = spearman_cell(np.asarray(after, float), np.asarray(arrays[name], float)[after])
        parts[f"{name} fluctuates more"] = None if ratio is None else ratio >= 1
        parts[f"{name} without trend"] = None if cell["rho"] is None else not cell["significant"]
        vals[name] = {"sd_ratio": ratio, "trend_rho": cell["rho"], "trend_p": cell["p"]}
        txt.append(f"{name}: sd II-III / sd I {_f(ratio, '.2f')}, trend rho "
                   f"{_f(cell['rho'], '+.2f')} (p {_f(cell['p'], '.2g')})")
    out.append(_statement("5d", "; ".join(txt), {**vals, "parts": parts},
                          "for the mean and the median GR angle: sd over Stages II-III >= sd "
                          f"over Stage I, and no Spearman trend with the step there (p > {ALPHA})",
                          *_verdict(parts)))
    return out


def judge_event(frames, arrays, event=None, *, pad=10, onset=2, radius_factor=5.0,
                fraction=0.01, n_perm=2000, seed=0):
    """Every statement on the largest slip (or on ``event``): the paper's words, our values,
    the rule and the verdict.

    Parameters
    ----------
    frames : Frames or FrameStore
        The frames analysed (or more: the analysis may be of the first ones).
    arrays : mapping
        The arrays of :func:`fricstab.analysis.shear.analyze` of these frames.
    event, pad, onset
        See :func:`event_window`; ``window`` elsewhere is its result.
    radius_factor, fraction : float
        The analysis' D2min and DBSCAN radius (in r_p) and GR fraction.
    n_perm, seed : int
        Random draws of the reference of :func:`rearrangement_site`, and their seed.

    Returns
    -------
    dict
        ``event`` (:func:`event_window`), ``parameters``, ``series`` (per window step:
        stage, tau, n_clusters, g, g10, rho_sigma_d2, angle_mean, angle_median) and
        ``statements`` (1, 2, 3, 4, 5a, 5b, 5d).

    Raises
    ------
    ParameterError
        The arrays are not of these frames (tau, or a GR cluster count, differs), or see
        :func:`event_window`.
    """
    window = event_window(arrays, event, pad, onset)      # checks the arrays first
    tau = np.asarray(arrays["tau"], float)
    if not 2 <= len(tau) <= frames.n_frames or not np.array_equal(tau, frames.tau[:len(tau)]):
        raise ParameterError(f"the analysis ({len(tau)} frames) is not of these frames "
                             f"({frames.n_frames}): its tau series differs")
    eps = radius_factor * _rp(frames)
    for k in window["steps"]:
        n = gr_regions(frames, k, eps, fraction)["n_clusters"]
        if n != int(arrays["n_clusters"][k]):
            raise ParameterError(f"step {k}: the analysis counts {int(arrays['n_clusters'][k])} "
                                 f"GR clusters, these frames {n} (radius {radius_factor:g} r_p, "
                                 f"fraction {fraction:g}): another analysis?")
    statements = [gr_consolidation(arrays, window, frames, fraction),
                  force_localisation(frames, window, radius_factor, fraction),
                  rearrangement_site(frames, window, radius_factor, fraction, n_perm, seed),
                  stz_quadrupole(frames, arrays, window, radius_factor),
                  *stage_courses(arrays, window)]
    names = ("tau", "n_clusters", "g", "g10", "rho_sigma_d2", "angle_mean", "angle_median")
    series = {"step": window["steps"], "stage": window["stages"],
              **{n: np.asarray(arrays[n])[window["steps"]] for n in names}}
    return json_clean({"event": window, "series": series, "statements": statements,
                "parameters": {"pad": pad, "onset": onset, "radius_factor": radius_factor,
                               "fraction": fraction, "n_perm": n_perm, "seed": seed,
                               "r_p": _rp(frames)}})
