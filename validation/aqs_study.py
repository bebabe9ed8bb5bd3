"""Issue 17: do complex pairs precede the stress drops of quasistatic shear?

For each law (charan at two mu and two kT/kN, ishima at the same kT/kN,
hertz as the frictionless control), each packing size and seed: AQS with
history (:func:`fricstab.protocols.aqs.run_aqs`) of the rattler-free backbone
at phi = 0.90, the spectrum at every relaxed state, stress drops
(:func:`fricstab.analysis.aqs.detect_drops`) and pair births.  In this study
births are taken at step resolution (the step in which a pair appears; its
strain the step's midpoint, within dgamma/2, a fraction of every window):
the bisection to 1e-6 that ``fricstab packing aqs`` performs costs ten
relaxations per event and does not move a birth across a window edge by
more than dgamma/2.  Per law, pooled over runs: the fraction of drops with a
birth within a window before the onset, its Wilson interval, the null (the
same statistic at uniform strains, exact), the binomial p-value; the
fraction of drops whose onset state has a pair against the fraction of all
states with one; the growth rate at the onsets against the loading.

    python validation/aqs_study.py --quick         # CI: N = 64, strain 0.01
    python validation/aqs_study.py --cache /tmp/aqs_cache   # the study: aqs_study_tables.md,
                                                            # .png, .json
    python validation/aqs_study.py --sizes 256 --seeds 1 --laws 0 3 5 --no-dgamma-scan \
        --prefix aqs_study_n256 --cache /tmp/aqs_cache      # the size check

``python validation/reproduce.py --claim aqs.answer`` (aqs.size_check) runs the same
in a fresh cache and records the numbers that validation/aqs_study.md and the README
quote.
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

from fricstab.analysis.aqs import compare, detect_drops, preceded, wilson  # noqa: E402
from fricstab.io.files import json_clean  # noqa: E402
from fricstab.protocols.aqs import run_aqs  # noqa: E402
from fricstab.scenes.packing import make_packing  # noqa: E402
from fricstab.scenes.packing_friction import backbone, frictional, material  # noqa: E402

HERE = Path(__file__).resolve().parent

#: (label, law, parameters)
LAWS_FULL = [
    ("charan mu=0.1 kt=1", "charan", {"mu": 0.1, "kt": 1.0}),
    ("charan mu=0.3 kt=1", "charan", {"mu": 0.3, "kt": 1.0}),
    ("charan mu=0.1 kt=0.5", "charan", {"mu": 0.1, "kt": 0.5}),
    ("ishima kt=1", "ishima", {"kt": 1.0}),
    ("ishima kt=0.5", "ishima", {"kt": 0.5}),
    ("hertz", "hertz", {}),
]
LAWS_QUICK = [LAWS_FULL[0], LAWS_FULL[3], LAWS_FULL[5]]
WINDOW_STEPS = (1, 4)


def one_run(bb, law, params, strain, dgamma):
    fr = frictional(bb, material(law, **params))
    t0 = time.perf_counter()
    res = run_aqs(fr.system, fr.state, strain, dgamma, locate_events=False, on_failure="stop")
    drops = detect_drops(res.strain, res.stress)
    births = [e.gamma for e in res.events if e.kind == "birth"]
    onset = [d.step - 1 for d in drops]
    return {"drops": [d.gamma for d in drops], "drop_sizes": [d.size for d in drops],
            "births": births, "gamma_max": float(res.strain[-1]),
            "pairs_at_onset": [int(res.n_pairs[k]) for k in onset],
            "growth_at_onset": [float(res.growth[k]) for k in onset],
            "states_with_pairs": int(np.sum(res.n_pairs > 0)), "states": len(res.strain),
            "fire_steps": int(res.fire.sum()), "strain": res.strain, "stress": res.stress,
            "n_pairs": res.n_pairs, "failure": res.failure,
            "seconds": time.perf_counter() - t0}


def law_row(label, runs, dgamma):
    row = {"law": label, "runs": len(runs)}
    for w in WINDOW_STEPS:
        row[f"w{w}"] = compare(runs, w * dgamma)
    k = sum(sum(p > 0 for p in r["pairs_at_onset"]) for r in runs)
    n = sum(len(r["pairs_at_onset"]) for r in runs)
    ks = sum(r["states_with_pairs"] for r in runs)
    ns = sum(r["states"] for r in runs)
    row["pair_at_onset"] = (k, n, wilson(k, n))
    row["pair_any_state"] = (ks, ns, wilson(ks, ns))
    growth = [g for r in runs for g in r["growth_at_onset"] if g > 0]
    row["growth_at_onset_median"] = float(np.median(growth)) if growth else 0.0
    # loading: a pair born at strain b grows by one e-fold before the drop at g
    # only if the strain rate is below growth * (g - b): the critical rate
    rates = []
    for r in runs:
        _, lag = preceded(r["drops"], r["births"], np.inf)
        rates += [g * dl for g, dl in zip(r["growth_at_onset"], lag)
                  if g > 0 and np.isfinite(dl)]
    row["critical_rate_median"] = float(np.median(rates)) if rates else 0.0
    row["births_per_strain"] = sum(len(r["births"]) for r in runs) / sum(
        r["gamma_max"] for r in runs)
    row["drops_per_strain"] = sum(len(r["drops"]) for r in runs) / sum(
        r["gamma_max"] for r in runs)
    return row


def _fmt_ci(ci):
    return f"[{ci[0]:.2f}, {ci[1]:.2f}]" if np.isfinite(ci[0]) else "-"


def table(rows):
    w1, w4 = (f"w{w}" for w in WINDOW_STEPS)
    lines = ["| law | runs | drops | births / strain | preceded, 1 step (95 % CI) | null 1 step "
             "| p | preceded, 4 steps (95 % CI) | null 4 steps | p | pair at onset (CI) | "
             "states with a pair (CI) | median growth at onset (t0^-1) | median critical "
             "rate (t0^-1) |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        a, b = r[w1], r[w4]
        k, n, ci = r["pair_at_onset"]
        ks, ns, cis = r["pair_any_state"]
        lines.append(
            f"| {r['law']} | {r['runs']} | {a['drops']} | {r['births_per_strain']:.0f} | "
            f"{a['preceded']}/{a['drops']} {_fmt_ci(a['fraction_ci95'])} | "
            f"{a['null_fraction']:.2f} | {a['pvalue_greater']:.2g} | "
            f"{b['preceded']}/{b['drops']} {_fmt_ci(b['fraction_ci95'])} | "
            f"{b['null_fraction']:.2f} | {b['pvalue_greater']:.2g} | "
            f"{k}/{n} {_fmt_ci(ci)} | {ks}/{ns} {_fmt_ci(cis)} | "
            f"{r['growth_at_onset_median']:.2g} | {r['critical_rate_median']:.2g} |")
    return "\n".join(lines)


def _cached_run(cache, bb, key, law, params, strain, dgamma):
    """``one_run``, stored as JSON under ``cache`` (None: no cache) and reused."""
    path = None if cache is None else cache / f"{key}.json"
    if path is not None and path.exists():
        r = json.loads(path.read_text())
        for name in ("strain", "stress", "n_pairs"):
            r[name] = np.asarray(r[name])
        return r
    r = one_run(bb(), law, params, strain, dgamma)
    if path is not None:
        cache.mkdir(parents=True, exist_ok=True)
        path.write_text(json.dumps(json_clean(r)))
    return r


def study(sizes, seeds, laws, strain, dgamma, log=print, cache=None):
    """``seeds[i]``: the number of seeds (0, 1, ...) of ``sizes[i]``."""
    packings = {}
    runs = {label: [] for label, _, _ in laws}
    for n, n_seeds in zip(sizes, seeds):
        for seed in range(n_seeds):
            def bb(n=n, seed=seed):
                if (n, seed) not in packings:
                    t0 = time.perf_counter()
                    packings[(n, seed)] = backbone(make_packing(n, 0.9, seed))
                    log(f"packing N = {n} seed {seed}: {time.perf_counter() - t0:.1f} s")
                return packings[(n, seed)]
            for label, law, params in laws:
                key = f"n{n}_s{seed}_{label.replace(' ', '_')}_{strain:g}_{dgamma:g}"
                r = _cached_run(cache, bb, key, law, params, strain, dgamma)
                r.update(n=n, seed=seed)
                runs[label].append(r)
                log(f"  {label}: {len(r['drops'])} drops, {len(r['births'])} births, "
                    f"{r['seconds']:.1f} s"
                    + (f" (stopped: {r['failure']})" if r.get("failure") else ""))
    rows = [law_row(label, runs[label], dgamma) for label, _, _ in laws]
    return rows, runs, packings


def dgamma_dependence(bb, laws, strain, dgamma, cache=None):
    """Drops per unit strain and mean size at dgamma/2, dgamma, 2 dgamma (packing N, seed 0)."""
    out = []
    for label, law, params in laws:
        for dg in (dgamma / 2, dgamma, 2 * dgamma):
            key = f"n{bb.n_total}_s0_{label.replace(' ', '_')}_{strain:g}_{dg:g}"
            r = _cached_run(cache, lambda: bb, key, law, params, strain, dg)
            size = float(np.mean(r["drop_sizes"])) if r["drop_sizes"] else float("nan")
            out.append({"law": label, "dgamma": dg, "drops": len(r["drops"]),
                        "drops_per_strain": len(r["drops"]) / r["gamma_max"],
                        "mean_size": size,
                        "total_drop": float(np.sum(r["drop_sizes"]))})
    return out


def figure(runs, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    labels = list(runs)
    fig, ax = plt.subplots(len(labels), 1, figsize=(7, 1.8 * len(labels)), sharex=True)
    for a, label in zip(np.atleast_1d(ax), labels):
        r = runs[label][0]
        a.plot(r["strain"], r["stress"], "k-", lw=0.7)
        for g in r["drops"]:
            a.axvline(g, color="r", lw=0.5, alpha=0.6)
        for b in r["births"]:
            a.plot([b], [np.interp(b, r["strain"], r["stress"])], "g|", ms=5)
        a.set_title(f"{label} (N = {r['n']}, seed {r['seed']}): red drops, green births",
                    fontsize=8)
        a.set_ylabel(r"$\sigma_{xy}$")
    np.atleast_1d(ax)[-1].set_xlabel(r"strain $\gamma$")
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)


def run(argv=None):
    """The study for the command line ``argv``; writes ``<prefix>.json``, ``<prefix>.png``
    and ``<prefix>_tables.md`` under ``--out`` (not with ``--quick``) and returns the
    document of the JSON file (``rows``: one per law; ``dgamma_dependence``; ``runs``)."""
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="CI tier: N = 64, strain 0.01")
    ap.add_argument("--sizes", type=int, nargs="+", default=[64, 128])
    ap.add_argument("--seeds", type=int, nargs="+", default=[4, 2],
                    help="number of seeds per size (0, 1, ...)")
    ap.add_argument("--cache", type=Path, default=None,
                    help="store each run as JSON here and reuse it")
    ap.add_argument("--strain", type=float, default=0.2)
    ap.add_argument("--dgamma", type=float, default=5e-4)
    ap.add_argument("--out", type=Path, default=HERE)
    ap.add_argument("--no-dgamma-scan", action="store_true")
    ap.add_argument("--laws", type=int, nargs="+", default=None, metavar="I",
                    help="only these rows of LAWS_FULL (0-5)")
    ap.add_argument("--prefix", default="aqs_study",
                    help="names of the files written: PREFIX.json, PREFIX.png, "
                         "PREFIX_tables.md (default: aqs_study)")
    a = ap.parse_args(argv)
    if a.quick:
        a.sizes, a.seeds, a.strain, a.dgamma = [64], [1], 0.01, 5e-4
    laws = LAWS_QUICK if a.quick else LAWS_FULL
    if a.laws is not None:
        laws = [LAWS_FULL[i] for i in a.laws]
    t0 = time.perf_counter()
    if len(a.seeds) != len(a.sizes):
        ap.error("--seeds needs one count per size")
    rows, runs, packings = study(a.sizes, a.seeds, laws, a.strain, a.dgamma, cache=a.cache)
    text = table(rows)
    print(text)
    if a.quick:
        return {"rows": rows}
    dep = [] if a.no_dgamma_scan else dgamma_dependence(
        backbone(make_packing(a.sizes[0], 0.9, 0)), [LAWS_FULL[0], LAWS_FULL[5]], a.strain,
        a.dgamma, cache=a.cache)
    stamp = (f"{datetime.now(timezone.utc):%Y-%m-%d %H:%M} UTC, {platform.node()}, "
             f"{time.perf_counter() - t0:.0f} s")
    doc = {"rows": rows, "dgamma_dependence": dep, "sizes": a.sizes, "seeds": a.seeds,
           "strain": a.strain, "dgamma": a.dgamma, "stamp": stamp,
           "runs": {k: [{kk: vv for kk, vv in r.items() if kk not in ("strain", "stress",
                                                                        "n_pairs")}
                        for r in v] for k, v in runs.items()}}
    (a.out / f"{a.prefix}.json").write_text(json.dumps(json_clean(doc)) + "\n")
    figure(runs, a.out / f"{a.prefix}.png")
    dep_lines = ["| law | dgamma | drops | drops / strain | mean size | summed drop |",
                 "|---|---|---|---|---|---|"] + [
        f"| {d['law']} | {d['dgamma']:g} | {d['drops']} | {d['drops_per_strain']:.0f} | "
        f"{d['mean_size']:.2e} | {d['total_drop']:.2e} |" for d in dep]
    (a.out / f"{a.prefix}_tables.md").write_text(
        f"<!-- generated by validation/aqs_study.py ({stamp}) -->\n\n" + text + "\n\n"
        + "\n".join(dep_lines) + "\n")
    print("\n".join(dep_lines))
    return doc


def main(argv=None):
    return run(argv)["rows"]


if __name__ == "__main__":
    main()
