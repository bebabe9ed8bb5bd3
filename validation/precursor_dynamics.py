"""Issue 36, item 4: do oscillatory modes grow before stress drops in sheared Newtonian dynamics?

For charan (mu = 0.1, kT/kN = 1), ishima (kT/kN = 1) and hertz, the phi = 0.90 backbone of the
precursor study (``validation/precursor_study.py``; N = 64, seeds 0, 1, ...) is sheared at a
constant rate by a Lees-Edwards offset growing at ``rate L_y`` (:class:`fricstab.engine.Controls`
``shear_rate``), Newtonian: velocity Verlet with no damping, ``dt = 0.05 / sqrt(max |lambda|)``
of the start (Verlet's phase error per period ~ 1e-4), histories by the law's increment rule
every step (the affine motion included: the history sees every relative displacement).  The
start is the relaxed backbone with the affine velocity profile ``v_x = rate y``.

Recorded every ``1e-4`` of strain: the shear stress (Ishima Eq. 14) and the non-affine kinetic
energy ``E_na = 1/2 sum m (v - rate y e_x)^2`` (rotations included).  Every 5 records (the AQS
study's step, ``5e-4``) the *quasistatic state on the dynamic path*: the dynamic state at rest,
relaxed by Newton (histories carried by the increment rule), and its spectrum of ``M^-1 K``
(:func:`fricstab.protocols.aqs.spectrum`): pair count, growth rate ``g`` (t0^-1), largest real
part.  These are "the Jacobian's pairs at the preceding quasistatic states" of the dynamics
itself.  (The AQS path of the precursor study is not the quasistatic limit of this dynamics for
a law with history: Ishima's step applies the affine move at frozen history, the dynamics
carries it into the history; the script prints the stress rise of both over strain 0.005.)

Per law and rate:

* ``r``: the growth rate of ``E_na`` over each 5-record interval (least squares of ``ln E_na``
  against time), beside ``2 g`` of the quasistatic state at the interval's start: a mode that
  grows as ``exp(g t)`` in amplitude grows as ``exp(2 g t)`` in energy; growth episodes (at
  least ``EPISODE_MIN`` consecutive intervals with ``r dt > GROW_MIN``), their e-folds and
  ``r / 2g``;
* stress drops located in strain (time = strain / rate) on the interval-mean stress (the AQS
  step's resolution; elastic oscillations averaged out) by
  :func:`fricstab.analysis.aqs.detect_drops` with the AQS threshold;
* the e-folds of ``E_na`` over the ``LEAD`` intervals before each drop, measured and predicted
  (sum of ``2 g dt``), and the ranked test (:mod:`fricstab.analysis.precursors`) of that
  growth at the onsets against +-W intervals: permutation null, power at a preceded fraction
  0.5.

    python validation/precursor_dynamics.py --cache DIR      # N = 64, 2 seeds, 4 rates
    python validation/precursor_dynamics.py --seeds 4 --rates 1e-5 1e-4 --cache DIR

Writes ``<prefix>.md``, ``.json`` and ``.png`` under ``--out``.
"""

import argparse
import json
import platform
import sys
import time
from datetime import datetime, timezone
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from fricstab.analysis.aqs import detect_drops  # noqa: E402
from fricstab.analysis.precursors import permutation_test, power  # noqa: E402
from fricstab.engine import Controls  # noqa: E402
from fricstab.engine import run as run_dynamics  # noqa: E402
from fricstab.io.files import atomic_write, json_clean  # noqa: E402
from fricstab.protocols.aqs import _newton, pairs, spectrum  # noqa: E402
from fricstab.analysis.spectrum import growth_rate  # noqa: E402
from fricstab.protocols.stepstrain import shear_stress  # noqa: E402
from fricstab.scenes.packing import make_packing  # noqa: E402
from fricstab.scenes.packing_friction import backbone, frictional, material  # noqa: E402

HERE = Path(__file__).resolve().parent
LAWS = [("charan mu=0.1 kt=1", "charan", {"mu": 0.1, "kt": 1.0}),
        ("ishima kt=1", "ishima", {"kt": 1.0}),
        ("hertz", "hertz", {})]
REC_STRAIN = 1e-4     # strain between records
QS_EVERY = 5          # records between quasistatic states (5e-4: the AQS study's step)
DT_FACTOR = 0.05      # dt = DT_FACTOR / sqrt(max |lambda|)
F_TOL = 1e-13         # the quasistatic states' force tolerance (the AQS study's)
EPISODE_MIN = 3       # consecutive growing intervals that make a growth episode
GROW_MIN = 0.01       # e-folds of E_na in an interval that count as growth (1 %; a steady
                      # E_na fits to ~1e-16, the driven fluctuations to ~0.1-1)
LEAD = 5              # intervals before a drop over which the growth of E_na is summed
T_SKIP = 50.0         # t0: intervals ending before it are the start's transient (the affine
                      # start settles in a few sound crossings of the cell, L / c ~ 7 t0)


def sheared(fr, rate, strain, log=print):
    """Newtonian shear of ``fr`` at ``rate`` to ``strain``: the record and quasistatic spectra."""
    sy, st = fr.system, fr.state.copy()
    w0, _ = spectrum(sy, st)
    dt = DT_FACTOR / np.sqrt(np.abs(w0).max())
    st.v[:] = 0.0
    st.v[:, 0] = rate * st.q[:, 1]
    ctrl = Controls(shear_rate=rate * sy.ly)
    steps = max(1, int(round(REC_STRAIN / rate / dt)))
    n_rec = int(round(strain / REC_STRAIN))
    rec = {k: [] for k in ("time", "strain", "stress", "e_na")}
    qs = {k: [] for k in ("strain", "n_pairs", "growth", "min_real", "residual")}
    t0 = time.perf_counter()
    for k in range(n_rec + 1):
        if k:
            run_dynamics(sy, st, dt, steps, ctrl)
        v = st.v[:, :sy.dof].copy()
        v[:, 0] -= rate * st.q[:, 1]
        rec["time"].append(st.time)
        rec["strain"].append(rate * st.time)
        rec["stress"].append(shear_stress(sy, st)[0])
        rec["e_na"].append(0.5 * np.sum(sy.gmass[:, :sy.dof] * v ** 2))
        if k % QS_EVERY == 0:
            s = st.copy()
            s.v[:] = 0.0
            res = _newton(sy, s, F_TOL)
            w = spectrum(sy, s)[0] if res.converged else np.full(1, np.nan)
            qs["strain"].append(rate * st.time)
            qs["n_pairs"].append(len(pairs(w)) if res.converged else np.nan)
            qs["growth"].append(growth_rate(w) if res.converged else np.nan)
            qs["min_real"].append(float(w.real.max()))
            qs["residual"].append(res.residual)
    out = {k: np.asarray(v, float) for k, v in {**rec, **{f"qs_{k}": v
                                                        for k, v in qs.items()}}.items()}
    out.update(dt=dt, steps_per_record=steps, seconds=time.perf_counter() - t0)
    return out


def _save(path, r):
    def write(tmp):
        with open(tmp, "wb") as f:
            np.savez(f, **r)
    atomic_write(path, write)


def interval_rates(r):
    """``ln E_na`` slope (1/t0) over each quasistatic interval (records QS_EVERY i .. i+1)."""
    t, e = r["time"], r["e_na"]
    out = []
    for i in range(len(r["qs_strain"])):
        sl = slice(QS_EVERY * i, QS_EVERY * (i + 1) + 1)
        tt, ee = t[sl], e[sl]
        ok = ee > 0
        out.append(np.polyfit(tt[ok], np.log(ee[ok]), 1)[0] if ok.sum() >= 3 else np.nan)
    return np.asarray(out)


def interval_stress(r):
    """The mean stress over each quasistatic interval (its records): the AQS step's resolution,
    elastic oscillations averaged out."""
    st = r["stress"]
    return np.array([st[QS_EVERY * i:QS_EVERY * (i + 1) + 1].mean()
                     for i in range(len(r["qs_strain"]))])


def episodes(rr, dt, min_len=EPISODE_MIN):
    """Maximal runs of at least ``min_len`` consecutive intervals (of duration ``dt``) where
    ``E_na`` grows by more than ``GROW_MIN`` e-folds."""
    out, start = [], None
    for i, x in enumerate(np.append(rr, np.nan)):
        if np.isfinite(x) and x * dt > GROW_MIN:
            start = i if start is None else start
        else:
            if start is not None and i - start >= min_len:
                out.append((start, i))
            start = None
    return out


def pre_drop_growth(r, rr, lead=LEAD):
    """Per interval i: e-folds of ``E_na`` over the ``lead`` intervals ending with i, measured
    (sum of r dt) and predicted by the quasistatic states (sum of 2 g dt)."""
    dt = QS_EVERY * REC_STRAIN / r["rate"]
    m, p = np.full(len(rr), np.nan), np.full(len(rr), np.nan)
    two_g = 2 * np.nan_to_num(r["qs_growth"][:len(rr)])
    for i in range(lead - 1, len(rr)):
        m[i] = np.sum(rr[i - lead + 1:i + 1]) * dt
        p[i] = np.sum(two_g[i - lead + 1:i + 1]) * dt
    return m, p


def analyse(runs, half_width, n_perm, n_rep, seed=0):
    """Per (law, rate): drops, growth episodes against 2 g, growth before drops, ranked test."""
    rows = []
    for i, ((label, rate), rs) in enumerate(runs.items()):
        ratios, amps, drops, pre_m, pre_p, paths, firsts = [], [], 0, [], [], [], []
        for r in rs:
            r = dict(r, rate=rate)
            rr = interval_rates(r)
            t_end = r["time"][::QS_EVERY][:len(rr)] + QS_EVERY * REC_STRAIN / rate
            rr[t_end < T_SKIP] = np.nan      # the start's transient
            two_g = 2 * r["qs_growth"][:len(rr)]
            ep = []
            for a, b in episodes(rr, QS_EVERY * REC_STRAIN / rate):
                if np.nansum(two_g[a:b]) > 0:
                    ratios.append(float(np.sum(rr[a:b]) / np.nansum(two_g[a:b])))
                    ep.append((float(np.sum(rr[a:b]) * QS_EVERY * REC_STRAIN / rate),
                               ratios[-1], float(r["qs_strain"][a])))
            if ep:
                amps.append(max(ep))      # the run's largest episode: e-folds, r / 2g, start
            d = detect_drops(r["qs_strain"], interval_stress(r))
            drops += len(d)
            on = [x.step - 1 for x in d]       # the last interval before the stress falls
            m, p = pre_drop_growth(r, rr)
            if on:       # the first drop: strain, e-folds before it measured / predicted
                firsts.append([float(r["qs_strain"][on[0]]), float(m[on[0]]), float(p[on[0]])])
            pre_m += [m[o] for o in on if np.isfinite(m[o])]
            pre_p += [p[o] for o in on if np.isfinite(p[o])]
            paths.append((m, on))
        g_all = np.concatenate([r["qs_growth"] for r in rs])
        rng = np.random.default_rng([seed, i])
        t = permutation_test(paths, half_width, n_perm, rng, "greater")
        t["power_0.5"] = power(paths, 0.5, half_width, n_rep, 199, rng, "greater")["power"] \
            if t["drops"] else float("nan")
        t.pop("ranks", None)
        q = lambda x, k: float(np.percentile(x, k)) if len(x) else float("nan")  # noqa: E731
        rows.append({
            "law": label, "rate": rate, "runs": len(rs), "drops": drops,
            "g_median": float(np.nanmedian(g_all)),
            "pairs_fraction": float(np.nanmean(np.concatenate([r["qs_n_pairs"] > 0
                                                               for r in rs]))),
            "two_g_interval": float(2 * np.nanmedian(g_all) * QS_EVERY * REC_STRAIN / rate),
            "e_na_median": float(np.median(np.concatenate([r["e_na"][1:] for r in rs]))),
            "episodes": len(ratios), "ratio_median": q(ratios, 50),
            "ratio_q": [q(ratios, 25), q(ratios, 75)],
            "largest": [list(x) for x in amps],     # per run: e-folds, r / 2g, start strain
            "first_drop": firsts,     # per run: onset strain, e-folds before, predicted
            "pre_measured": q(pre_m, 50), "pre_predicted": q(pre_p, 50),
            "seconds": float(sum(r["seconds"] for r in rs)), "test": t})
    return rows


def _g(x, fmt="{:.2f}"):
    return "-" if x is None or not np.isfinite(x) else fmt.format(x)


def tables(rows, slopes):
    """Markdown: growth against 2 g and before drops per law and rate; the stress rises."""
    lines = ["| law | rate (t0^-1) | runs | drops | states with a pair | median g (t0^-1) | "
             "2 g x interval (e-folds) | median E_na (k_N d^5/2) | growth episodes | "
             f"r / 2g in episodes, median [IQR] | largest episode per run: e-folds at strain "
             f"(r / 2g) | E_na e-folds in "
             f"the {LEAD} intervals before a drop: measured / predicted (medians) | first drop "
             "per run: strain, e-folds before it (predicted) | rank at onsets (p) | power "
             "f = 0.5 |", "|" + "---|" * 15]
    for r in rows:
        t = r["test"]
        lines.append(
            f"| {r['law']} | {r['rate']:g} | {r['runs']} | {r['drops']} | "
            f"{_g(r['pairs_fraction'])} | {_g(r['g_median'], '{:.2g}')} | "
            f"{_g(r['two_g_interval'], '{:.3g}')} | {_g(r['e_na_median'], '{:.2g}')} | "
            f"{r['episodes']} | {_g(r['ratio_median'])} [{_g(r['ratio_q'][0])}, "
            f"{_g(r['ratio_q'][1])}] | "
            + ", ".join(f"{a:.1f} at {c:.3f} (r / 2g {b:.2f})" for a, b, c in r["largest"])
            + " | "
            f"{_g(r['pre_measured'])} / {_g(r['pre_predicted'])} | "
            + ", ".join(f"{a:.4f}: {_g(b, '{:.1f}')} ({_g(c, '{:.1f}')})"
                        for a, b, c in r["first_drop"])
            + f" | {_g(t['statistic'])} ({_g(t['pvalue'], '{:.3g}')}) | {_g(t['power_0.5'])} |")
    lines += ["", "| law | rate (t0^-1) | stress rise over strain 0-0.005, dynamics "
              "(k_N d^-1/2) | the same, AQS path (affine step at frozen history) | "
              "dynamics / AQS |", "|---|---|---|---|---|"]
    for (label, rate), (dyn, aqs) in slopes.items():
        lines.append(f"| {label} | {rate:g} | {_g(dyn, '{:.4g}')} | {_g(aqs, '{:.4g}')} | "
                     f"{_g(dyn / aqs, '{:.3f}')} |")
    return "\n".join(lines)


def _rise(strain, stress, upto=0.005):
    """The stress increase from the start to strain ``upto`` (interpolated)."""
    return float(np.interp(upto, strain, stress) - stress[0])


def aqs_rise(n, seed, law, params, upto=0.005, dgamma=5e-4):
    """The same on the AQS path (Ishima's step: the affine move at frozen history)."""
    from fricstab.protocols.aqs import run_aqs
    fr = frictional(backbone(make_packing(n, 0.9, seed)), material(law, **params))
    res = run_aqs(fr.system, fr.state, upto, dgamma, locate_events=False, on_failure="stop")
    return _rise(res.strain, res.stress, upto)


def figure(runs, path):
    """Per law (row pairs) and rate (columns), first seed: the interval-mean stress with the
    drops the analysis locates (red), and E_na (log) with the quasistatic 2 g e-folds."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    labels = list(dict.fromkeys(k[0] for k in runs))
    rates = sorted({k[1] for k in runs})
    fig, ax = plt.subplots(2 * len(labels), len(rates), figsize=(3.0 * len(rates),
                           2.0 * 2 * len(labels)), squeeze=False, sharex=True)
    for i, label in enumerate(labels):
        for c, rate in enumerate(rates):
            r = runs[(label, rate)][0]
            top, bottom = ax[2 * i, c], ax[2 * i + 1, c]
            stress = interval_stress(r)
            top.plot(r["qs_strain"], stress, lw=0.6)
            for d in detect_drops(r["qs_strain"], stress):
                top.axvline(d.gamma, color="r", lw=0.3, alpha=0.5)
            top.set_title(f"{label}, rate {rate:g} t0^-1", fontsize=7)
            bottom.semilogy(r["strain"][1:], r["e_na"][1:], lw=0.6)
            if c == 0:
                top.set_ylabel("sigma_xy (k_N d^-1/2)", fontsize=7)
                bottom.set_ylabel("E_na (k_N d^5/2)", fontsize=7)
    for a in ax[-1]:
        a.set_xlabel("strain")
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)


def run(argv=None):
    """The study for ``argv``; writes PREFIX.md, .json, .png under --out; the JSON doc."""
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=64)
    ap.add_argument("--seeds", type=int, default=2)
    ap.add_argument("--rates", type=float, nargs="+", default=[1e-6, 1e-5, 1e-4, 1e-3])
    ap.add_argument("--laws", nargs="+", default=None, choices=[w for _, w, _ in LAWS])
    ap.add_argument("--strain", type=float, default=0.2)
    ap.add_argument("--half-width", type=int, default=25)
    ap.add_argument("--n-perm", type=int, default=999)
    ap.add_argument("--n-rep", type=int, default=200)
    ap.add_argument("--cache", type=Path, default=None,
                    help="one .npz per run here; a run found there is reused")
    ap.add_argument("--out", type=Path, default=HERE)
    ap.add_argument("--prefix", default="precursor_dynamics")
    a = ap.parse_args(argv)
    if not all(np.isfinite(x) and x > 0 for x in a.rates):
        ap.error("--rates must be finite and > 0")
    laws = [x for x in LAWS if a.laws is None or x[1] in a.laws]
    t0 = time.perf_counter()
    runs, slopes = {}, {}
    for seed in range(a.seeds):
        bb = backbone(make_packing(a.n, 0.9, seed))
        for label, law, params in laws:
            fr = frictional(bb, material(law, **params))
            for rate in a.rates:
                path = None if a.cache is None else \
                    a.cache / f"n{a.n}_s{seed}_{law}_{rate:g}_{a.strain:g}.npz"
                if path is not None and path.exists():
                    with np.load(path) as z:
                        r = {k: z[k] for k in z.files}
                else:
                    r = sheared(fr, rate, a.strain)
                    if path is not None:
                        a.cache.mkdir(parents=True, exist_ok=True)
                        _save(path, r)
                runs.setdefault((label, rate), []).append(r)
                print(f"N = {a.n} seed {seed} {label} rate {rate:g}: {r['seconds']:.0f} s, "
                      f"{len(detect_drops(r['qs_strain'], interval_stress(r)))} drops", flush=True)
                if seed == 0:
                    slopes[(label, rate)] = [_rise(r["strain"], r["stress"]), None]
            aqs = aqs_rise(a.n, 0, law, params) if seed == 0 else None
            for rate in a.rates:
                if seed == 0:
                    slopes[(label, rate)][1] = aqs
    rows = analyse(runs, a.half_width, a.n_perm, a.n_rep)
    text = tables(rows, slopes)
    print(text)
    stamp = (f"{datetime.now(timezone.utc):%Y-%m-%d %H:%M} UTC, {platform.node()}, "
             f"{time.perf_counter() - t0:.0f} s")
    doc = {"rows": rows, "slopes": [[k[0], k[1], *v] for k, v in slopes.items()], "n": a.n,
           "seeds": a.seeds, "rates": a.rates, "strain": a.strain, "stamp": stamp}
    a.out.mkdir(parents=True, exist_ok=True)
    (a.out / f"{a.prefix}.json").write_text(json.dumps(json_clean(doc)) + "\n")
    figure(runs, a.out / f"{a.prefix}.png")
    (a.out / f"{a.prefix}.md").write_text(
        f"<!-- generated by validation/precursor_dynamics.py ({stamp}) -->\n\n"
        f"# Sheared Newtonian dynamics against the Jacobian's pairs\n\nN = {a.n}, seeds "
        f"{a.seeds}, strain {a.strain:g}, rates {a.rates}; records every {REC_STRAIN:g} of "
        f"strain, quasistatic states every {QS_EVERY} records; window +-{a.half_width} "
        f"intervals, {a.n_perm} permutations.\n\n{text}\n")
    return doc


if __name__ == "__main__":
    run()
