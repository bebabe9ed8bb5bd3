"""``fricstab shear sweep``: the friction sweep of Lee & Hurley Sec. 4 as a dask ensemble.

``fricstab shear sweep --out DIR [--mus 0.1 0.3 0.5 0.7] [--seeds K] [--seed S]
[--scheduler local|inline|tcp://HOST:PORT] [--workers N] [--window gamma0|steady] [--resume]
[scene options]``
    One member per (mu_s, seed), seeds S..S+K-1 (default 0 only): a full
    ``shear run`` of the scene (the options of ``shear run``, with ``--param
    mus`` set from ``--mus``) in ``DIR/runs/mus<M>_seed<S>/`` (M as Python's
    ``repr``), then :func:`fricstab.analysis.shear.analyze` on its frames
    from the run's gamma0 or (``--window steady``) from the start of tau's
    steady window (:func:`fricstab.analysis.stationarity.steady_window`, as
    ``shear analyze --gamma0 steady``), each member's start and test kept.
    Members run through :func:`fricstab.io.ensemble.run_ensemble` on a local
    cluster, in this process (``inline``) or on a running dask scheduler, whose
    workers must see DIR at the same path.  Each member's numbers are stored
    when it finishes as ``DIR/members/mus<M>_seed<S>_<12 hex>.npz`` (the hex:
    the member's fingerprint, every parameter of its run); ``--resume``
    computes only the members not soundly stored, and a member whose run was
    interrupted continues from that run's last checkpoint.  Writes
    ``sweep.md`` (per mu_s: mean and sample sd over the seeds of each
    quantity) and the record ``sweep.json`` (the same numbers, per-seed
    values, parameters, manifest) last.
"""

import json
import math
import sys
from pathlib import Path

import numpy as np

from fricstab.errors import ParameterError

__all__ = ["QUANTITIES", "add_sweep_parser", "member_arrays", "sweep", "sweep_member"]

#: The paper's friction coefficients (Sec. 4).
DEFAULT_MUS = (0.1, 0.3, 0.5, 0.7)
#: The quantities of a member that the tables summarise over seeds, and what each is.
QUANTITIES = {
    "phases_per_step": "stick and slip phases per output step in the window",
    "n_phases": "stick and slip phases in the window",
    "n_slip": "slip phases (tau drops) in the window",
    "largest_drop": "change of tau over the largest slip (< 0) in the window",
    "slip_abs_dtau_mean": "mean |change of tau| over the slips in the window",
    "window_start": "strain where the analysed window starts (gamma0, or the steady start)",
    "steady": "1 if tau is steady from the window start (the trend test of --window steady), "
              "0 if not; not defined with --window gamma0",
    "tau_mean_half": "mean of tau = S/N over the second half of the strain",
    "tau_sd_half": "standard deviation of tau over the second half of the strain",
    "servo_rms_window": "rms relative error of N, strain >= gamma0 (the run's record)",
}
#: Keys of an analysis summary stored with each member (None there: NaN here).
_SUMMARY = ("n_steps", "n_phases", "n_stick", "n_slip", "phases_per_step",
            "phases_per_unit_strain", "fraction_long", "slip_abs_dtau_mean", "largest_drop")
MAX_SEEDS = 10_000


def add_sweep_parser(sub, scene_options, positive_float):
    """Register ``sweep`` on the ``shear`` subparsers, with the scene options of ``run``."""
    from fricstab.cli.imports import _int_in as _count    # an integer in [low, high]
    r = sub.add_parser("sweep", help="the mu_s sweep (Sec. 4): one shear run and analysis "
                       "per mu_s and seed, as a dask ensemble",
                       description="One shear run and its analysis per (mu_s, seed) on "
                       "dask.distributed; tables of mean and sd over seeds per mu_s.")
    scene_options(r, checkpoints=False)
    r.add_argument("--mus", type=positive_float(), nargs="+", default=list(DEFAULT_MUS),
                   metavar="MU", help="static friction coefficients mu_s, each > 0 (default "
                   "the paper's 0.1 0.3 0.5 0.7); one shear run per value and seed")
    r.add_argument("--seeds", type=_count(1, MAX_SEEDS), default=1, metavar="K",
                   help="seeds per mu_s: --seed .. --seed + K - 1 (default 1); the sd over "
                        "seeds needs K >= 2, and falls as 1/sqrt(K)")
    r.add_argument("--scheduler", default="local", metavar="ADDRESS",
                   help="dask scheduler: 'local' (a LocalCluster of processes, default), "
                        "'inline' (no dask, in this process), or the address of a running "
                        "scheduler (tcp://host:8786; its workers must see --out)")
    r.add_argument("--workers", type=_count(1, 1024), default=None,
                   help="worker processes of the local cluster (default: CPU count, at most "
                        "the members to run)")
    r.add_argument("--window", choices=("gamma0", "steady"), default="gamma0",
                   help="the analysed window of each member: from the run's gamma0 "
                        "(default) or from the start of tau's steady window (the trend test "
                        "of `shear analyze --gamma0 steady`; gamma0 where no start passes, "
                        "with 'steady' 0 in the tables)")
    r.add_argument("--resume", action="store_true",
                   help="continue an interrupted sweep in --out (same parameters): stored "
                        "members are kept, interrupted member runs continue from their "
                        "last checkpoint")
    return r


def _quiet(*args):
    """The members' log: nothing (a worker has no terminal)."""


def _run_or_resume(params, out, run_shear):
    """``run_shear`` (:func:`fricstab.cli.shear.run_shear`, passed in: this module does not
    import the shear command that registers it) into ``out``: an interrupted run of the same
    parameters continues.

    A failed run's lock is released, so that a retry in the same worker process
    can take the folder again.
    """
    from fricstab.io import results, rundir
    out = Path(out)
    try:
        if rundir.journal_path(out, "shear").exists() and not (out / "shear.json").exists():
            try:
                return run_shear(params, out, resume=True, log=_quiet)
            except ParameterError:   # made with other parameters: start afresh
                _release(results, out)
        return run_shear(params, out, force=True, log=_quiet)
    except BaseException:
        _release(results, out)
        raise


def _release(results, out):
    """Close the ResultDirs of ``out`` this process still holds (a run that raised)."""
    for rd in list(results._HELD):   # noqa: SLF001 (a failed run keeps its lock)
        if rd.path.resolve() == out.resolve():
            rd.close()


def sweep_member(params, out, run_shear, window="gamma0"):
    """One member (module level, for dask): run the shear in ``out`` by ``run_shear``
    (:func:`fricstab.cli.shear.run_shear`, pickled by reference), analyze from the run's
    gamma0 or (``window="steady"``) from tau's steady start; small arrays."""
    from fricstab.analysis.shear import analyze
    from fricstab.analysis.stationarity import steady_window
    from fricstab.cli.shear_analyze import frames_of
    rec = _run_or_resume(params, out, run_shear)
    with np.load(Path(out) / "shear.npz", allow_pickle=False) as z:
        strain, tau = z["strain"], z["tau"]
    start, steady = params["gamma0"], None
    if window == "steady":
        start, info = steady_window(strain, tau, start)
        steady = info["steady"]
    res = analyze(frames_of(out), start, progress=False)
    return member_arrays(params, rec, res.summary, strain, tau, start, steady)


def member_arrays(params, rec, summary, strain, tau, start=None, steady=None):
    """A member's arrays: its mu_s and seed, the analysis summary, tau over the second half.

    Only what the parameters fix (no timings), so that a member is the same
    wherever it ran.  Undefined values (no slip, an empty window) are NaN.  ``start``:
    where the analysed window starts (default the run's gamma0); ``steady``: the trend
    test's verdict there (None: not tested).
    """
    half = strain >= 0.5 * strain[-1]
    out = {"mus": np.float64(params["law_params"]["mus"]), "seed": np.int64(params["seed"]),
           "frames": np.int64(len(strain)),
           "tau_mean_half": np.float64(tau[half].mean()),
           "tau_sd_half": np.float64(tau[half].std()),
           "tau_mean_window": _f(rec["tau_mean_window"]),
           "servo_rms_window": _f(rec["quality"]["servo_rms_window"]),
           "window_start": np.float64(params["gamma0"] if start is None else start),
           "steady": _f(None if steady is None else float(steady))}
    out.update({k: _f(summary[k]) for k in _SUMMARY})
    if not summary["n_slip"]:   # the analysis's "largest drop" is then a stick's rise
        out["largest_drop"] = np.float64(np.nan)
    return out


def _f(value):
    return np.float64(np.nan if value is None else value)


def _label(mus, seed):
    return f"mus{mus!r}_seed{seed}"


def _member_params(ns, mus, seed, shear):
    """Validated parameters of one member (a refusal names the option); ``shear``: the
    functions of the shear command (:func:`sweep`)."""
    from fricstab.io.scenes import law_overrides
    from fricstab.scenes.shear import SCHEMA
    overrides = {f.key: getattr(ns, f.key) for f in SCHEMA.fields
                 if f.key not in shear["skip"]}
    labels = {f.key: f.option for f in SCHEMA.fields if overrides.get(f.key) is not None}
    laws = law_overrides(ns)
    labels.update({k: "--law" if k == "law" else f"--param {k}" for k, v in laws.items()
                   if v is not None})
    labels.update({"mus": "--mus", "seed": "--seed"})
    return shear["resolve_params"](ns.scene, ns.preset,
                                   {**overrides, **laws, "seed": seed, "mus": mus}, labels)


def _check(ns):
    twice = sorted({m for m in ns.mus if ns.mus.count(m) > 1})
    if twice:
        raise ParameterError(f"--mus {twice[0]!r} is given {ns.mus.count(twice[0])} times; "
                             "give each mu_s once")
    if any(item.partition("=")[0].strip() == "mus" for item in ns.param or []):
        raise ParameterError("--param mus: the sweep sets mu_s from --mus; drop --param mus")
    if ns.workers is not None and ns.scheduler != "local":
        raise ParameterError(f"--workers: the worker processes of --scheduler local; with "
                             f"--scheduler {ns.scheduler} drop it")


def _fingerprint(params):
    """A member's fingerprint: every parameter of its run (not the checkpoint interval)."""
    return {"member": "shear_sweep.sweep_member", **{k: v for k, v in params.items()
                                                    if k != "checkpoint_every"}}


def sweep(ns, argv, shear):
    """Run ``fricstab shear sweep``; returns the exit status.  ``shear``: the shear command's
    ``run_shear``, ``resolve_params`` and ``skip`` (the scene keys that are no options), passed
    in by :mod:`fricstab.cli.shear` so that this module does not import it back."""
    from fricstab import progress
    from fricstab.cli import budget
    from fricstab.io.ensemble import member_key, run_ensemble
    from fricstab.io.results import ResultDir

    _check(ns)
    first = 0 if ns.seed is None else ns.seed
    seeds = list(range(first, first + ns.seeds))
    mus = list(ns.mus)
    params = {(m, s): _member_params(ns, m, s, shear) for m in mus for s in seeds}
    base = params[mus[0], seeds[0]]
    estimate = budget.shear(base, count=len(params), dry_run=ns.dry_run)  # one thread
    common = {k: v for k, v in base.items() if k not in ("seed", "law_params")}
    common["law_params"] = {k: v for k, v in base["law_params"].items() if k != "mus"}
    protocol = {"mus": mus, "seeds": seeds, **({"window": "steady"} if ns.window == "steady"
                                               else {})}
    if ns.dry_run:
        print(json.dumps({**common, **protocol, "estimate": estimate}, indent=2))
        return 0
    rd = ResultDir(ns.out, "sweep", force=ns.force, resume=ns.resume,
                   outputs=("members", "runs", "sweep.md"),
                   fingerprint={**_fingerprint(common), **protocol}).create()
    rd.register("members", folder=True)
    rd.register("runs", folder=True)
    root = rd.path.absolute()   # the workers of a remote scheduler get absolute paths
    steady = {"window": "steady"} if ns.window == "steady" else {}
    keys = {ms: member_key(_label(*ms), {**_fingerprint(params[ms]), **steady})
            for ms in params}
    members = {keys[ms][0]: {"params": params[ms], "out": str(root / "runs" / _label(*ms)),
                             "run_shear": shear["run_shear"], "window": ns.window}
               for ms in params}
    loud = not ns.no_progress
    with rd.stage("members"), progress.heartbeat(   # tqdm's bar: on a terminal only
            "shear sweep: members", loud and not sys.stderr.isatty()):
        stored = run_ensemble(sweep_member, members, root, scheduler=ns.scheduler,
                              workers=ns.workers, progress=loud, desc="shear sweep",
                              fingerprints=dict(keys.values()))
    table = {m: summarize([stored[keys[m, s][0]] for s in seeds]) for m in mus}
    doc = {"mus": mus, "seeds": seeds, "quantities": QUANTITIES,
           "results": [{"mus": m, **table[m]} for m in mus],
           "members": "members/mus<M>_seed<S>_<12 hex of the member's fingerprint>.npz; "
                      "runs/mus<M>_seed<S>/: the member's shear run"}
    with rd.stage("write"):
        rd.write_with("sweep.md", lambda tmp: Path(tmp).write_text(markdown(doc)))
    rd.finish(doc, parameters={**common, **protocol}, seed=first, argv=argv)
    for r in doc["results"]:
        q = r["quantities"]["phases_per_step"]
        print(f"mu_s = {r['mus']!r}: {len(seeds)} seed(s), phases per step "
              f"{_cell(q['mean'], q['sd'])}, tau (2nd half) "
              f"{_cell(r['quantities']['tau_mean_half']['mean'], None)}")
    print(f"wrote {rd.path}/sweep.json, sweep.md, members/, runs/")
    return 0


def summarize(members):
    """Per quantity: per-seed values, their mean and sample sd (ddof 1) over finite values.

    A mean of no finite value, or an sd of fewer than two, is None.
    """
    out = {"seeds": [int(m["seed"]) for m in members], "quantities": {}}
    for name in QUANTITIES:
        # a member stored before a quantity existed: not defined there
        v = np.array([float(m[name]) if name in m else math.nan for m in members])
        ok = v[np.isfinite(v)]
        out["quantities"][name] = {
            "values": [float(x) if math.isfinite(x) else None for x in v],
            "mean": float(ok.mean()) if ok.size else None,
            "sd": float(ok.std(ddof=1)) if ok.size >= 2 else None,
            "n_defined": int(ok.size)}
    return out


def _cell(mean, sd):
    if mean is None:
        return "not defined"
    return f"{mean:.4g}" + ("" if sd is None else f" +- {sd:.2g}")


def markdown(doc):
    """``sweep.md``: one table per mu_s (mean, sample sd and the values over the seeds)."""
    lines = ["# Plane shear: friction sweep (Lee & Hurley Sec. 4)", "",
             f"Seeds {doc['seeds'][0]}..{doc['seeds'][-1]} per mu_s; sd: sample standard "
             "deviation over the seeds (not defined for one seed); a value not defined "
             "for a seed (no slip, an empty window) is left out of the mean.", ""]
    for r in doc["results"]:
        lines += [f"## mu_s = {r['mus']!r}", "", "| quantity | mean | sd | per seed | what |",
                  "|---|---|---|---|---|"]
        for name, q in r["quantities"].items():
            vals = ", ".join("-" if x is None else f"{x:.4g}" for x in q["values"])
            lines.append(f"| {name} | {_cell(q['mean'], None)} | "
                         f"{'-' if q['sd'] is None else format(q['sd'], '.2g')} | {vals} | "
                         f"{QUANTITIES[name]} |")
        lines.append("")
    return "\n".join(lines)
