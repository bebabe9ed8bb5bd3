"""Issue 36: the ranked precursor test of AQS stress drops, with its power, per law and size.

For charan (mu = 0.1, kT/kN = 1), ishima (kT/kN = 1) and hertz, each size and seed: AQS of the
rattler-free backbone at phi = 0.90 (:func:`fricstab.protocols.aqs.run_aqs`, births at step
resolution, ``on_failure="stop"``: strain 0.2 in steps of 5e-4, 400 relaxed states), each run
cached as one .npz in ``--cache`` (written atomically; ``--resume`` reuses finished runs).
Per law and N, for four candidates (pair count, largest growth rate, the largest real
eigenvalue, the smallest ``|Im|`` of the pairs) the ranked test of
:mod:`fricstab.analysis.precursors` (the onset's rank in its +-W neighbourhood, the permutation
null, p-value), its power at true preceded fractions 0.5 and 0.8, and the old 1-step and
4-step birth-window tests (issue 17's statistic, :func:`fricstab.analysis.aqs.compare`: the
drops with a pair birth in the window up to the onset, against the null of the same window at
every strain, exact one-sided binomial p) with their power against the same fractions.
Before running, the compute spent and left per size and law is printed (:func:`budget`;
``--budget-only`` stops there).

    python validation/precursor_study.py --sizes 64 128 --seeds 4 2 --cache DIR --resume
    python validation/precursor_study.py --sizes 64 --seeds 4 --prefix precursor_study_n64 \
        --cache DIR          # what the claims precursors.ranked_* record

Writes ``<prefix>.md`` (tables), ``.json`` and ``.png`` (onset-rank histograms) under ``--out``.
"""

import argparse
import hashlib
import json
import platform
import shutil
import sys
import time
from datetime import datetime, timezone
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from fricstab.analysis.aqs import compare, detect_drops  # noqa: E402
from fricstab.analysis.precursors import permutation_test, power, window_power  # noqa: E402
from fricstab.io.files import atomic_write, json_clean  # noqa: E402
from fricstab.protocols.aqs import run_aqs, spectrum  # noqa: E402
from fricstab.scenes.packing import Packing, make_packing  # noqa: E402
from fricstab.scenes.packing_friction import backbone, frictional, material  # noqa: E402

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
import _stamped  # noqa: E402

#: (label, law, parameters): the slipping, the no-slip and the frictionless law
LAWS = [("charan mu=0.1 kt=1", "charan", {"mu": 0.1, "kt": 1.0}),
        ("ishima kt=1", "ishima", {"kt": 1.0}),
        ("hertz", "hertz", {})]
#: (AQSResult field, the direction in which a precursor is extreme at the onset)
CANDIDATES = [("n_pairs", "greater"), ("growth", "greater"), ("min_real", "greater"),
              ("pair_min_imag", "less")]
FRACTIONS = (0.5, 0.8)
WINDOW_STEPS = (1, 4)
SERIES = ("strain", "stress") + tuple(c for c, _ in CANDIDATES)
SLOW_HOURS = 12.0   # a projection above this is reported as too slow for one sitting
CHECKPOINT_EVERY = 10   # strain steps between a path's checkpoints (N = 1,024: ~3 min)


_fingerprint = _stamped._fp      # claims.fingerprint, its source hashes memoised
code_hash = _stamped.code_hash    # the stamp of a run whose executed code was not traced
_merge = _stamped.merge


def fresh(stamp):
    """Whether a run or checkpoint stamped ``stamp`` (its ``units`` and ``code``) was made by
    the code of the checkout (:func:`_stamped.fresh`: every function it executed unchanged,
    or, without ``units``, every fricstab module)."""
    return _stamped.fresh(str(stamp.get("units", "")), str(stamp.get("code", "")))


def _key(n, seed, label, strain, dgamma):
    return f"n{n}_s{seed}_{label.replace(' ', '_')}_{strain:g}_{dgamma:g}"


def one_run(bb, law, params, strain, dgamma, ckpt_dir=None, every=CHECKPOINT_EVERY):
    """One AQS path: the per-state series, the births (step resolution), the wall time, and
    the stamp of the code that made it (``units``: the functions it executed, :func:`fresh`).

    ``ckpt_dir``: the path is checkpointed there every ``every`` steps and continued from its
    latest checkpoint (bit-identically, :func:`run_aqs`) when that was made by this code; the
    seconds and the executed code add up over sittings.
    """
    fp = _fingerprint()
    fr = frictional(bb, material(law, **params))
    ck = resume = None
    spent, prior = 0.0, {}
    if ckpt_dir is not None:
        from fricstab.io.checkpoint import Checkpointer
        # the backbone's digest: a checkpoint continues only the packing it was made on
        # (seeded FIRE is chaotic: another CPU can reach another packing of the same seed)
        digest = hashlib.sha256(np.ascontiguousarray(bb.pos).tobytes()
                                + np.ascontiguousarray(bb.radius).tobytes()).hexdigest()[:16]
        ck = Checkpointer(ckpt_dir, {"law": law, "params": params, "strain": strain,
                                     "dgamma": dgamma, "n": int(fr.system.n),
                                     "backbone": digest})
        resume = ck.latest()
        if resume is not None and "code" not in resume and (ckpt_dir / "code").exists():
            resume["code"] = (ckpt_dir / "code").read_text()     # adopted (_adopt)
        if resume is not None and not fresh(resume):
            print(f"    {ckpt_dir.name}: made by other code; started afresh", flush=True)
            shutil.rmtree(ckpt_dir, ignore_errors=True)
            resume = None
        if resume is not None:
            spent = float(resume.pop("seconds_so_far"))
            units = str(resume.pop("units", ""))
            prior = json.loads(units) if units else None
            for k in ("path", "code"):
                resume.pop(k, None)
    t0 = time.perf_counter()
    code = code_hash()

    def stamp():
        units = _merge(prior, fp.code_units(tracer))
        return {"units": np.str_("" if units is None else json.dumps(units)),
                "code": np.str_(code)}

    def save(k, arrays):
        now = spent + time.perf_counter() - t0
        ck.save(k, seconds_so_far=np.float64(now), **stamp(), **arrays)
        print(f"    N = {fr.system.n} {law}: step {k} checkpointed ({now:.0f} s)", flush=True)
    with fp.Tracer() as tracer:
        res = run_aqs(fr.system, fr.state, strain, dgamma, locate_events=False,
                      on_failure="stop", resume=resume, checkpoint=None if ck is None else save,
                      checkpoint_every=every if ck is not None else 0)
    out = {name: np.asarray(getattr(res, name), float) for name in SERIES}
    out["births"] = np.array([e.gamma for e in res.events if e.kind == "birth"], float)
    out["seconds"] = np.float64(spent + time.perf_counter() - t0)
    out["failure"] = np.str_(res.failure or "")
    out.update(stamp())
    return out


def load_run(path):
    with np.load(path) as z:
        return {k: (str(z[k]) if k in ("failure", "code", "units") else z[k]) for k in z.files}


def save_run(path, run):
    def write(tmp):
        with open(tmp, "wb") as f:
            np.savez(f, **run)
    atomic_write(path, write)


def probe(n, steps=3, dgamma=5e-4):
    """Seconds per state (relaxation + dense spectrum) and of the spectrum alone, charan, N."""
    bb = backbone(make_packing(n, 0.9, 0))
    fr = frictional(bb, material("charan", mu=0.1, kt=1.0))
    run_aqs(fr.system, fr.state, dgamma, dgamma, locate_events=False, on_failure="stop")
    t0 = time.perf_counter()          # warm now (compiled kernels, caches)
    spectrum(fr.system, fr.state)
    t_spec = time.perf_counter() - t0
    t0 = time.perf_counter()
    run_aqs(fr.system, fr.state, steps * dgamma, dgamma, locate_events=False,
            on_failure="stop")
    return (time.perf_counter() - t0) / (steps + 1), t_spec


def _checkpoint(ckpt_dir):
    """(seconds so far, steps) of a run's latest checkpoint, or None: also when other code
    made it (:func:`fresh`; the run starts afresh, so it is neither spent nor a rate)."""
    files = sorted(ckpt_dir.glob("ckpt_*.npz"))
    try:
        with np.load(files[-1]) as z:       # an estimate only: no checksum needed
            stamp = {k: str(z[k]) for k in ("units", "code") if k in z.files}
            got = float(z["seconds_so_far"]), int(z["step"])
    except (IndexError, OSError, KeyError, ValueError):
        return None
    if not stamp.get("code") and (ckpt_dir / "code").exists():
        stamp["code"] = (ckpt_dir / "code").read_text()     # adopted (_adopt)
    return got if fresh(stamp) else None


def _rate(known, n, label):
    """Seconds per state of ``label`` at ``n`` from ``known`` {(n, label): [rate, ...]}: the
    mean at that size, else the nearest smaller size's scaled by (n / n')^3 (the dense
    spectrum's and the dense least squares' order), else None.  Returns (rate, how)."""
    if known.get((n, label)):
        return float(np.mean(known[(n, label)])), "measured"
    smaller = sorted(m for (m, lab) in known if lab == label and m < n)
    if smaller:
        m = smaller[-1]
        return float(np.mean(known[(m, label)])) * (n / m) ** 3, f"N = {m} x (N / {m})^3"
    return None, "not measured"


def budget(sizes, seeds, laws, strain, dgamma, cache, log=print, probe_new=True):
    """Print, per N and law, the compute spent and the compute left (one core) and return it.

    Spent: the finished runs of this code in ``cache`` and the checkpoints of the unfinished
    ones.  Left: the states still owed, each at the law's measured seconds per state at that
    N (finished runs and checkpoints), else extrapolated from the nearest smaller N as N^3,
    else (unless ``probe_new`` is False) a 3-step probe of charan at that N."""
    states = int(np.floor(strain / dgamma + 1e-9)) + 1
    known, plan = {}, []
    for n, n_seeds in zip(sizes, seeds):
        for label, _, _ in laws:
            for seed in range(n_seeds):
                stem = _key(n, seed, label, strain, dgamma)
                path = cache / f"{stem}.npz" if cache else None
                if path is not None and path.exists():
                    r = load_run(path)
                    if fresh(r):
                        known.setdefault((n, label), []).append(
                            float(r["seconds"]) / len(r["strain"]))
                        plan.append((n, label, float(r["seconds"]), 0))
                        continue
                ck = _checkpoint(cache / f"{stem}.checkpoints") if cache else None
                if ck is not None and ck[1] > 0:
                    known.setdefault((n, label), []).append(ck[0] / ck[1])
                    plan.append((n, label, ck[0], states - ck[1]))
                else:
                    plan.append((n, label, 0.0, states))
    probed, out = {}, []
    spent_total = left_total = 0.0
    unknown = []
    for n in sizes:
        for label, _, _ in laws:
            rows = [x for x in plan if x[0] == n and x[1] == label]
            spent, owed = sum(x[2] for x in rows), sum(x[3] for x in rows)
            rate, how = _rate(known, n, label)
            if rate is None and owed and probe_new:
                if n not in probed:
                    probed[n] = probe(n)[0]
                rate, how = probed[n], "3-step probe, charan"
            left = None if rate is None else rate * owed
            spent_total += spent
            if owed and left is None:
                unknown.append(f"N = {n} {label}")
            left_total += left or 0.0
            out.append({"n": n, "law": label, "runs": len(rows), "spent_hours": spent / 3600,
                        "states_owed": owed, "seconds_per_state": rate,
                        "left_hours": None if left is None else left / 3600})
            log(f"N = {n} {label}: {spent / 3600:.2f} h spent, {owed} of "
                f"{len(rows) * states} states owed"
                + ("" if not owed else f", {left / 3600:.2f} h left ({rate:.3g} s per state, "
                   f"{how})" if left is not None else ", left unknown (--no-probe)"))
    log(f"compute: {spent_total / 3600:.2f} h spent, {left_total / 3600:.2f} h left on one core"
        + (f" (plus {', '.join(unknown)}: not measured)" if unknown else "")
        + (f" -- more than one sitting (> {SLOW_HOURS:g} h): run the sizes over several "
           "sittings (--resume) or in parallel processes (--laws)"
           if left_total > 3600 * SLOW_HOURS else ""))
    return out


def collect(sizes, seeds, laws, strain, dgamma, cache, resume, log=print):
    """All runs, from the cache where ``resume`` finds them made by this code (:func:`fresh`;
    a run of other code is run again); {(label, n): [run, ...]}."""
    todo = [(n, s, lab) for n, k in zip(sizes, seeds) for s in range(k) for lab, _, _ in laws]

    def cached(n, seed, label):
        path = None if cache is None else cache / f"{_key(n, seed, label, strain, dgamma)}.npz"
        if path is None or not resume or not path.exists():
            return path, None
        r = load_run(path)
        if not fresh(r):
            log(f"  {path.name}: made by other code; run again")
            return path, None
        return path, r
    done = sum(cached(n, s, lab)[1] is not None for n, s, lab in todo)
    log(f"{done} of {len(todo)} runs done" + (" (resumed)" if done else ""))
    runs, packings = {}, {}
    for n, seed, label in todo:
        law, params = next((w, p) for lab, w, p in laws if lab == label)
        path, r = cached(n, seed, label)
        if r is None:
            if (n, seed) not in packings:
                packings = {(n, seed): backbone(_packing(cache, n, seed))}
            ckpt = None if path is None else cache / f"{path.stem}.checkpoints"
            if ckpt is not None:
                _adopt(cache, path.stem, ckpt)
                if not resume:
                    shutil.rmtree(ckpt, ignore_errors=True)   # afresh: no partial path
            r = one_run(packings[(n, seed)], law, params, strain, dgamma, ckpt)
            if path is not None:
                cache.mkdir(parents=True, exist_ok=True)
                save_run(path, r)
                shutil.rmtree(ckpt, ignore_errors=True)
            log(f"  N = {n} seed {seed} {label}: {float(r['seconds']):.0f} s"
                + (f" (stopped: {r['failure']})" if r["failure"] else ""))
        runs.setdefault((label, n), []).append(dict(r, seed=seed))
    return runs


def _packing(cache, n, seed):
    """The phi = 0.90 packing of ``seed``, kept in ``cache/packings`` beside the runs and
    checkpoints made on it (a resumed path must meet the packing it started on)."""
    if cache is None:
        return make_packing(n, 0.9, seed)
    path = cache / "packings" / f"n{n}_phi0.9_s{seed}.npz"
    if path.exists():
        return Packing.load(path)
    p = make_packing(n, 0.9, seed)
    path.parent.mkdir(parents=True, exist_ok=True)

    def write(tmp):
        with open(tmp, "wb") as f:
            p.save(f)
    atomic_write(path, write)       # a killed process leaves no half packing
    return p


def _adopt(cache, stem, ckpt):
    """Checkpoints of the first stamped layout (``<stem>.<code hash>.checkpoints``): moved to
    ``ckpt`` if the hash is this code's, removed otherwise."""
    for old in cache.glob(f"{stem}.*.checkpoints"):
        if old == ckpt:
            continue
        if old.name == f"{stem}.{code_hash()}.checkpoints" and not ckpt.exists():
            (old / "code").write_text(code_hash())     # its name was its stamp
            old.rename(ckpt)
        else:
            shutil.rmtree(old, ignore_errors=True)


def run_units(runs):
    """The code the runs executed: their ``units`` stamps merged (:func:`one_run`); a run
    stamped with the coarse code hash only counts every fricstab module but the CLI whole."""
    fp = _fingerprint()
    out = {}
    for rs in runs.values():
        for r in rs:
            u = str(r.get("units", ""))
            out = _merge(out, json.loads(u) if u else
                         {m: {"*": fp.module_hash(m, HERE.parent)}
                          for m in fp.package_files(root=HERE.parent)})
    return out


def _old_runs(runs):
    """The runs in the form of fricstab.analysis.aqs.compare (onset strains, births)."""
    return [{"drops": [d.gamma for d in detect_drops(r["strain"], r["stress"])],
             "births": r["births"], "gamma_max": float(r["strain"][-1])} for r in runs]


def _constant(x):
    """No two different finite values (all NaN counts as constant)."""
    v = np.asarray(x, float)
    v = v[np.isfinite(v)]
    return v.size == 0 or v.min() == v.max()


POOLED = "all"   # the N of a law's pooled row


def pooled(runs):
    """``runs`` and, per law run at more than one size, its runs of every size as one group
    ``(label, POOLED)`` (last, so the per-size rows keep their random streams)."""
    groups = dict(runs)
    for label in dict.fromkeys(lab for lab, _ in runs):
        sizes = [rs for (lab, _), rs in runs.items() if lab == label]
        if len(sizes) > 1:
            groups[(label, POOLED)] = [r for rs in sizes for r in rs]
    return groups


def sizes_differ(ranks):
    """Kruskal-Wallis p that the onset ranks of the sizes (one list per size) come from one
    distribution: small where the sizes' preceded fractions differ, so the pooled row's
    assumption fails.  NaN with fewer than two sizes with ranks, or all ranks equal."""
    from scipy.stats import kruskal
    groups = [g for g in ranks if len(g)]
    if len(groups) < 2 or len({x for g in groups for x in g}) < 2:
        return float("nan")
    return float(kruskal(*groups).pvalue)


def analyse(runs, dgamma, half_width, n_perm, n_rep, seed=0):
    """Per (law, N): drops, the ranked test and power per candidate, the old birth-window
    tests' outcome (preceded drops, p) and power; per law run at several sizes, the same on
    all its drops pooled (N = ``POOLED``: each onset ranked in its own path's window, so
    ranks of different sizes are one sample of the null; pooling assumes one preceded
    fraction at every size, which ``sizes_pvalue`` tests: :func:`sizes_differ`)."""
    rows = []
    for i, ((label, n), rs) in enumerate(pooled(runs).items()):
        onsets = [[d.step - 1 for d in detect_drops(r["strain"], r["stress"])] for r in rs]
        row = {"law": label, "n": n, "runs": len(rs), "drops": sum(map(len, onsets)),
               "states": int(sum(len(r["strain"]) for r in rs)),
               # the compute of the runs, summed over the sittings each took (one core)
               "seconds": float(sum(float(r["seconds"]) for r in rs)), "candidates": {}}
        for j, (name, alt) in enumerate(CANDIDATES):
            paths = [(r[name], o) for r, o in zip(rs, onsets)]
            rng = np.random.default_rng([seed, i, j])
            t = permutation_test(paths, half_width, n_perm, rng, alt)
            t["alternative"] = alt
            # a series constant on every path (hertz's pair count) cannot rank: no power
            t["constant"] = all(_constant(r[name]) for r in rs)
            for f in FRACTIONS:
                t[f"power_{f:g}"] = float("nan") if t["constant"] else \
                    power(paths, f, half_width, n_rep, 199, rng, alt)["power"]
            if n == POOLED:
                t["sizes_pvalue"] = sizes_differ([r["candidates"][name]["ranks"] for r in rows
                                                  if r["law"] == label])
            row["candidates"][name] = t
        old = _old_runs(rs)
        for w in WINDOW_STEPS:
            # the old test itself (issue 17's statistic): drops with a birth in the w steps up
            # to the onset, against the drop-weighted null, one-sided exact binomial p
            obs = compare(old, w * dgamma)
            row[f"window{w}_tested"] = int(obs["drops"])
            row[f"window{w}_preceded"] = int(obs["preceded"])
            row[f"window{w}_pvalue"] = float(obs["pvalue_greater"])
            rng = np.random.default_rng([seed, i, 100 + w])
            for f in FRACTIONS:
                wp = window_power(old, w * dgamma, f, n_rep, rng)
                row[f"window{w}_power_{f:g}"] = wp["power"]
                row[f"window{w}_p0"] = wp["p0"]
        rows.append(row)
    return rows


def _g(x, fmt="{:.2f}"):
    return "-" if x is None or not np.isfinite(x) else fmt.format(x)


def tables(rows):
    """Markdown: the ranked test per candidate; the old tests' outcome and power, and the
    compute of the runs (core-hours)."""
    lines = ["| law | N | runs | drops | candidate | direction | drops ranked | mean rank "
             "(null mean +- sd) | p | power f = 0.5 | power f = 0.8 | sizes differ: p |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        for name, t in r["candidates"].items():
            lines.append(
                f"| {r['law']} | {r['n']} | {r['runs']} | {r['drops']} | {name} | "
                f"{'high' if t['alternative'] == 'greater' else 'low'} | {t['drops']} | "
                f"{_g(t['statistic'])} ({_g(t['null_mean'])} +- {_g(t['null_sd'])}) | "
                f"{_g(t['pvalue'], '{:.3g}')} | {_g(t['power_0.5'])} | {_g(t['power_0.8'])} | "
                f"{_g(t.get('sizes_pvalue'), '{:.2g}')} |")
    lines += ["", "| law | N | core-h | drops | " + " | ".join(
        f"{w} step{'s' if w > 1 else ''}: preceded | null p0 | p | power f = 0.5 / 0.8"
        for w in WINDOW_STEPS) + " |", "|---|---|---|---|" + "---|---|---|---|" * len(WINDOW_STEPS)]
    for r in rows:
        cells = [f"{r[f'window{w}_preceded']}/{r[f'window{w}_tested']} | "
                 f"{_g(r[f'window{w}_p0'])} | {_g(r[f'window{w}_pvalue'], '{:.2g}')} | "
                 f"{_g(r[f'window{w}_power_0.5'])} / {_g(r[f'window{w}_power_0.8'])}"
                 for w in WINDOW_STEPS]
        lines.append(f"| {r['law']} | {r['n']} | {r['seconds'] / 3600:.2g} | {r['drops']} | "
                     + " | ".join(cells) + " |")
    return "\n".join(lines)


def figure(rows, path):
    """Onset-rank histograms per candidate (columns) and law (rows), pooled over N."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    labels = list(dict.fromkeys(r["law"] for r in rows))
    fig, ax = plt.subplots(len(labels), len(CANDIDATES), figsize=(11, 2.2 * len(labels)),
                           squeeze=False)
    for i, label in enumerate(labels):
        for j, (name, alt) in enumerate(CANDIDATES):
            ranks = [x for r in rows if r["law"] == label and r["n"] != POOLED
                     for x in r["candidates"][name]["ranks"]]
            a = ax[i, j]
            if ranks:
                a.hist(ranks, bins=10, range=(0, 1), density=True, color="0.6")
            a.axhline(1.0, color="r", lw=0.8)
            a.set_title(f"{label}: {name} ({'high' if alt == 'greater' else 'low'}), "
                        f"{len(ranks)} drops", fontsize=7)
            a.set_xlim(0, 1)
    for a in ax[-1]:
        a.set_xlabel("onset rank in its window")
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)


def run(argv=None):
    """The study for ``argv``; writes PREFIX.md, .json, .png under --out; returns the JSON doc."""
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sizes", type=int, nargs="+", default=[64, 128, 256, 512, 1024])
    ap.add_argument("--seeds", type=int, nargs="+", default=None,
                    help="number of seeds per size (0, 1, ...); default 4, 2, 1, 1, 1")
    ap.add_argument("--laws", nargs="+", default=None, choices=[w for _, w, _ in LAWS])
    ap.add_argument("--strain", type=float, default=0.2)
    ap.add_argument("--dgamma", type=float, default=5e-4)
    ap.add_argument("--cache", type=Path, default=None, help="one .npz per run here")
    ap.add_argument("--resume", action="store_true", help="reuse the finished runs in --cache")
    ap.add_argument("--half-width", type=int, default=25, help="neighbourhood W in states")
    ap.add_argument("--n-perm", type=int, default=999)
    ap.add_argument("--n-rep", type=int, default=400, help="replicates per power estimate")
    ap.add_argument("--budget-only", action="store_true", help="print the projection, stop")
    ap.add_argument("--no-probe", action="store_true",
                    help="project only from cached runs and checkpoints (no 3-step probe)")
    ap.add_argument("--out", type=Path, default=HERE)
    ap.add_argument("--prefix", default="precursor_study")
    a = ap.parse_args(argv)
    seeds = a.seeds or [{64: 4, 128: 2}.get(n, 1) for n in a.sizes]
    if len(seeds) != len(a.sizes):
        ap.error("--seeds needs one count per size")
    laws = [x for x in LAWS if a.laws is None or x[1] in a.laws]
    t0 = time.perf_counter()
    bud = budget(a.sizes, seeds, laws, a.strain, a.dgamma, a.cache if a.resume else None,
                 probe_new=not a.no_probe)
    if a.budget_only:
        return {"budget": bud}
    runs = collect(a.sizes, seeds, laws, a.strain, a.dgamma, a.cache, a.resume)
    rows = analyse(runs, a.dgamma, a.half_width, a.n_perm, a.n_rep)
    text = tables(rows)
    print(text)
    stamp = (f"{datetime.now(timezone.utc):%Y-%m-%d %H:%M} UTC, {platform.node()}, "
             f"{time.perf_counter() - t0:.0f} s")
    stopped = [{"law": lab, "n": n, "seed": r["seed"], "gamma_max": float(r["strain"][-1])}
               for (lab, n), rs in runs.items() for r in rs if r["failure"]]
    run_s = sum(float(r["seconds"]) for rs in runs.values() for r in rs)
    doc = {"rows": rows, "budget": bud, "run_seconds": run_s, "sizes": a.sizes, "seeds": seeds,
           "strain": a.strain,
           "dgamma": a.dgamma, "half_width": a.half_width, "n_perm": a.n_perm,
           "n_rep": a.n_rep, "stopped": stopped, "stamp": stamp, "units": run_units(runs)}
    a.out.mkdir(parents=True, exist_ok=True)
    (a.out / f"{a.prefix}.json").write_text(json.dumps(json_clean(doc)) + "\n")
    figure(rows, a.out / f"{a.prefix}.png")
    (a.out / f"{a.prefix}.md").write_text(
        f"<!-- generated by validation/precursor_study.py ({stamp}) -->\n\n"
        f"# The ranked precursor test\n\nSizes {a.sizes}, seeds {seeds}, strain {a.strain:g} "
        f"in steps of {a.dgamma:g}, phi = 0.90 backbone; window +-{a.half_width} states, "
        f"{a.n_perm} permutations, power from {a.n_rep} replicates at alpha = 0.05. "
        f"Stopped paths: {len(stopped)}. The runs took {run_s:.0f} s in all.\n\n{text}\n")
    return doc


if __name__ == "__main__":
    run()
