"""Issue 34, item 1: which reading of Lee & Hurley's protocol do the observables support?

The paper lists both a restitution coefficient (0.9, with the material properties) and
damping ratios (0.1, 0.1 for gamma_n, gamma_t, Eqs. A4 and A12), and a contact stiffness
number kappa = 1e4 without saying whether it is E*/P or k_n/P (da Cruz et al. 2005).  The
preset reads damping ratio 0.1 (restitution 0.73) and E*/P.  Each reading here changes one
of these on the same cell and seeds:

- ``damping``: the preset (ratio 0.1; kappa = E*/P);
- ``restitution``: ratios alpha_n = alpha_t = 0.034, the linear spring-dashpot's for e = 0.9
  (:func:`fricstab.scenes.shear.damping_ratio`);
- ``kn``: kappa read as k_n / P: E*/P = :func:`fricstab.scenes.shear.kappa_from_kn` (kappa)
  (a pressure ~3-4x lower), prepared with the wall's speed scaled by the preset's kappa over
  the reading's and the step limit by the inverse (:data:`PREP_WHY`);
- ``restitution_kn``: both.

Per run, the observables that do not need the full paper run: the phase rate (phases per
output step in the window strain >= gamma0, the paper's 0.323), tau's mean and std from the
steady start (:func:`fricstab.analysis.stationarity.steady_start`, the Mann-Kendall test on
20 block means; the window from gamma0 when no start passes), the steady start itself, and the
shape of the slip sizes |Delta tau_p| (median, 90th percentile, largest; the fraction of slips
above 1e-2, the paper's 'significant decrease').  Per reading: seed mean, seed standard error
and the distance of the mean phase rate from the paper's in standard errors.  The paper's
value is for its own cell (1,000 disks, I = 4e-6, kappa = 1e4, frames 7.2e-7 apart): a
reading is judged against it only at ``--scale paper``; at smaller scales the table shows how
far each reading moves the observables, not which one is right.

    python validation/shear_protocol.py --scale quick --seeds 0 1 2     # ~1 h on one core
    python validation/shear_protocol.py --scale decide --seeds 0 1 2    # 1,000 disks, kappa 1e4

Each run's observables are kept in the committed store ``validation/runs/shear_protocol``
(``validation/runs/README.md``) with its parameters and the code it executed
(``validation/_stamped.py``), and reused while both are unchanged, so the study spreads over
sittings on any machine; the run itself (frames, series: too big for git) goes to ``--cache``
(default ``validation/.shear_protocol``, git-ignored).  ``--no-run`` tabulates the stored
runs.  A run whose preparation does not settle is stored as a failure with its message (and
seconds) and shown as such in the table; the other runs go on.  Writes
``<out>/shear_protocol_<scale>.md`` and ``.json``.
"""

import argparse
import json
import math
import sys
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))
sys.path.insert(0, str(HERE))

import _stamped  # noqa: E402

from fricstab.errors import ConvergenceError  # noqa: E402
from fricstab.scenes.shear import damping_ratio, kappa_from_kn  # noqa: E402

PAPER_RATE = 0.323          # ~42,000 phases in ~130,000 output steps (Sec. 3.1)
PAPER_RESTITUTION = 0.9
SLIP_BIG = 1e-2             # the paper's 'significant decrease' of Delta tau_p (Sec. 4)
#: scale -> overrides of the quick preset (``fricstab shear run`` defaults)
SCALES = {"quick": {},
          "decide": {"n": 1000, "kappa": 1e4, "strain": 0.12},
          "paper": "paper"}
READINGS = ("damping", "restitution", "kn", "restitution_kn")
WHAT = {"damping": "damping ratio 0.1, kappa = E*/P (the preset)",
        "restitution": f"restitution {PAPER_RESTITUTION} (ratio "
                       f"{damping_ratio(PAPER_RESTITUTION):.3f}), kappa = E*/P",
        "kn": "damping ratio 0.1, kappa = k_n/P",
        "restitution_kn": f"restitution {PAPER_RESTITUTION}, kappa = k_n/P"}


def params(scale, reading, seed):
    """The ``shear run`` parameters of one run."""
    from fricstab.cli.shear import resolve_params
    spec = SCALES[scale]
    preset = "paper" if spec == "paper" else "quick"
    over = {} if spec == "paper" else dict(spec)
    base = resolve_params(None, preset, {**over, "seed": seed})
    if reading.startswith("restitution"):
        a = damping_ratio(PAPER_RESTITUTION)
        over.update(alpha_n=a, alpha_t=a)
    if reading.endswith("kn"):
        over["kappa"] = kappa_from_kn(base["kappa"])
        # the preparation's wall speed (units sqrt(E*/rho)) slowed by base/new kappa (PREP_WHY)
        r = base["kappa"] / over["kappa"]
        over.update(prep_speed=base["prep_speed"] * r,
                    prep_max_steps=math.ceil(base["prep_max_steps"] / r))
    return resolve_params(None, preset, {**over, "seed": seed})


#: why the kn readings prepare with a slower wall (:func:`params`)
PREP_WHY = ("The dashpot and friction forces on the moving wall scale with its speed "
            "(prep_speed, units sqrt(E*/rho)) in units of E*, the target pressure with 1/kappa: "
            "at kappa = k_n/P (E*/P = 38,480 at the decide scale) the wall at full speed is "
            "pulled (N < 0, |N/N_target - 1| = 1.9 after 1.06e6 steps, 2.01 after 3e6), so "
            "its speed is scaled by the preset's kappa over the reading's (x 0.26) and the "
            "step limit by the inverse: prepared in 5.14e6 steps (|N/N_target - 1| = 0.010, "
            "kinetic energy 0.5 x tolerance), the preset's reading in 1.80e6")


def observables(folder, p):
    """The observables of one finished run (module docstring)."""
    from fricstab.analysis.shear_phases import find_phases
    from fricstab.analysis.stationarity import steady_start
    z = np.load(folder / "shear.npz")
    strain, tau = z["strain"], z["tau"]
    rec = json.loads((folder / "shear.json").read_text())
    g0 = p["gamma0"]
    win = strain >= g0
    start, test = steady_start(strain[win], tau[win])
    steady = strain >= (g0 if start is None else start)
    ok = np.zeros(len(tau), bool)
    ok[1:] = strain[:-1] >= g0
    ph = find_phases(tau, ok)
    dt = tau[ph[:, 1]] - tau[ph[:, 0] - 1] if len(ph) else np.zeros(0)
    slips = -dt[dt < 0]
    return {"rate": rec["phases"]["phases_per_step"],
            "steady_start": start, "steady_p": test["p"],
            "drift_over_std": test["drift_over_std"],
            "tau_mean": float(tau[steady].mean()), "tau_std": float(tau[steady].std()),
            "slip_median": float(np.median(slips)) if slips.size else None,
            "slip_p90": float(np.quantile(slips, 0.9)) if slips.size else None,
            "slip_max": float(slips.max()) if slips.size else None,
            "slip_big_fraction": float(np.mean(slips > SLIP_BIG)) if slips.size else None,
            "n_slips": int(slips.size), "servo_rms": rec["servo"]["rms_rel_error"],
            "pressure_over_estar": 1.0 / p["kappa"], "alpha_n": p["alpha_n"]}


#: the observables of finished runs, committed (module docstring)
STORE = HERE / "runs" / "shear_protocol"


def one(scale, reading, seed, cache, run=True, log=print, store=STORE):
    """The observables of one run: from ``store`` while its parameters and executed code are
    unchanged; else (``run``) the run into ``cache`` and its observables, stored; else None."""
    from fricstab.cli.shear import run_shear
    p = json.loads(json.dumps(params(scale, reading, seed)))
    path = Path(store) / scale / f"{reading}_s{seed}.npz"
    got = _stamped.stored(path)
    if got is not None and json.loads(got["params"]) == p:
        return json.loads(got["observables"])
    if not run:
        return None
    out = cache / scale / f"{reading}_s{seed}"

    def compute():          # under the tracer: the stamp names the code the run executed
        t0 = time.perf_counter()
        log(f"{scale} {reading} seed {seed}: running (kappa E*/P = {p['kappa']:.4g}, "
            f"alpha_n = {p['alpha_n']:.3g})")
        try:
            run_shear(p, out, force=True, argv=["validation/shear_protocol.py"],
                      log=lambda s: None)
            obs = observables(out, p)
        except ConvergenceError as exc:     # stored: the table says why the row is empty
            obs = {"failure": str(exc)}
        obs["seconds"] = time.perf_counter() - t0
        log(f"  {'failed' if 'failure' in obs else 'done'} in {obs['seconds']:.0f} s"
            + (f": {obs['failure']}" if "failure" in obs else ""))
        return {"observables": np.str_(json.dumps(obs)), "params": np.str_(json.dumps(p))}
    if path.exists():
        path.unlink()       # other parameters: cached() would reuse a fresh stamp
    return json.loads(_stamped.cached(path, compute, log=log)["observables"])


def summarise(rows):
    """Per reading: mean and standard error over seeds of each observable (of the runs that
    did not fail; ``failed``: seed -> the failure's message)."""
    out = {}
    for reading, seeds in rows.items():
        ran = [x for x in seeds.values() if "failure" not in x]
        keys = sorted({k for x in ran for k, v in x.items() if isinstance(v, (int, float))})
        s = {"failed": {seed: x["failure"] for seed, x in seeds.items() if "failure" in x}}
        for k in keys:
            v = np.array([x[k] for x in ran if x.get(k) is not None], float)
            if v.size:
                s[k] = {"mean": float(v.mean()),
                        "se": float(v.std(ddof=1) / math.sqrt(v.size)) if v.size > 1 else None,
                        "n": int(v.size)}
        r = s.get("rate")
        if r and r["se"]:
            s["rate_distance_se"] = (r["mean"] - PAPER_RATE) / r["se"]
        out[reading] = s
    return out


def paper_preset_rate(path=None):
    """The phase rate of the paper-preset run (the preset's reading: damping ratio 0.1, kappa =
    E*/P) and its standard error: the sample sd of the rates in the 2 % strain windows along
    the run over sqrt(windows) (the drift of the unsteady run inflates it: conservative).
    Read from ``validation/shear_paper.json`` (the run of 58a1724, not regenerated since)."""
    doc = json.loads(Path(path or HERE / "shear_paper.json").read_text())
    w = np.array([r["per_step"] for r in doc["along_the_run"]], float)
    return {"rate": float(doc["summary"]["phases_per_step"]),
            "se": float(w.std(ddof=1) / math.sqrt(w.size)), "windows": w.tolist()}


def transfer(summary, paper):
    """Each reading's phase rate in the paper's cell, predicted from the paper-preset run and
    the decide scale: ``paper["rate"]`` x (reading's seed mean / the damping reading's), the
    relative standard errors added in quadrature (the damping reading is the paper run itself).
    The assumption, stated where it is used: a reading moves the rate by the same factor at
    I = 1e-4, frames 1e-5 apart (the decide scale) as at the paper's I = 4e-6, frames 7.2e-7
    apart (same N and kappa).  ``distance``: (predicted - 0.323) / se."""
    base = summary.get("damping", {}).get("rate")
    if not base or not base["se"] or not paper:
        return {}
    out = {}
    for reading, s in summary.items():
        r = s.get("rate")
        if not r or not r["se"]:
            continue
        ratio = r["mean"] / base["mean"]
        rel2 = (paper["se"] / paper["rate"]) ** 2
        if reading != "damping":
            rel2 += (r["se"] / r["mean"]) ** 2 + (base["se"] / base["mean"]) ** 2
        pred = paper["rate"] * ratio
        se = pred * math.sqrt(rel2)
        out[reading] = {"ratio": ratio, "predicted": pred, "se": se,
                        "distance": (pred - PAPER_RATE) / se}
    return out


def chosen(summary, scale, paper=None):
    """The reading the phase rate supports, and why: at the paper's scale the readings whose
    seed mean lies within 2 standard errors of 0.323; at the decide scale the readings whose
    rate predicted by :func:`transfer` does.  The preset (damping ratio 0.1, kappa = E*/P)
    stays unless the evidence excludes it and supports another: where the rate does not
    separate the readings, the paper's Appendix A decides (gamma_n and gamma_t from the
    damping ratio alpha by Hu et al.'s linear model, Eqs. A4 and A12; the restitution 0.9 is
    listed with the material properties, which a LIGGGHTS input needs whatever the model).
    Returns (reading or None, supported readings, text)."""
    if scale == "paper":
        dist = {r: s["rate_distance_se"] for r, s in summary.items() if "rate_distance_se" in s}
        how = "seed mean within 2 standard errors of 0.323"
    elif scale == "decide":
        dist = {r: t["distance"] for r, t in transfer(summary, paper).items()}
        how = ("rate predicted in the paper's cell (paper-preset run x the decide scale's ratio "
               "to the damping reading) within 2 standard errors of 0.323")
    else:
        return None, [], ("not judged: the paper's 0.323 is for its own cell; at this scale "
                          "the table shows how far each reading moves the observables")
    ok = [r for r, d in dist.items() if abs(d) <= 2.0]
    if not dist:
        return None, [], "not judged: no reading has a rate with a standard error"
    if "damping" in ok or not ok:
        pick = "damping"
        why = ("the rate supports none of the readings; the preset stays" if not ok else
               "the rate supports only the preset" if ok == ["damping"] else
               "the rate does not separate " + ", ".join(ok) + "; the preset stays (Appendix A "
               "derives gamma_n and gamma_t from the damping ratio)")
    elif len(ok) == 1:
        pick, why = ok[0], f"the rate excludes the preset and supports '{ok[0]}' alone"
    else:
        pick, why = None, ("the rate excludes the preset and does not separate "
                           + ", ".join(ok))
    return pick, ok, f"{why} (rule: {how})"


def verdict(summary, scale, paper=None):
    """The sentence of :func:`chosen`, with the reading chosen."""
    pick, _, why = chosen(summary, scale, paper)
    if scale not in ("paper", "decide"):
        return why                                  # not judged at this scale
    return f"reading chosen: {pick or 'none'}: {why}"


def write(rows, summary, scale, seeds, out):
    def f(x, d=3):
        return "-" if x is None else f"{x:.{d}g}"
    lines = [f"# Lee & Hurley's protocol, four readings, scale '{scale}'", "",
             f"Command: `python validation/shear_protocol.py --scale {scale} --seeds "
             f"{' '.join(map(str, seeds))}`.  Seed mean +- standard error; the paper's phase "
             f"rate {PAPER_RATE} is for its own cell.", "",
             "| reading | E*/P | phases per step | tau mean (steady) | tau std | steady start "
             "(strain) | slip median | slip p90 | slips > 1e-2 | servo rms |",
             "|---|---|---|---|---|---|---|---|---|---|"]
    for reading, s in summary.items():
        def ms(k, d=3):
            if k not in s:
                return "-"
            return f(s[k]["mean"], d) + ("" if s[k]["se"] is None else f" +- {f(s[k]['se'], 2)}")
        starts = [x["steady_start"] for x in rows[reading].values() if "failure" not in x]
        kap = params(scale, reading, seeds[0])["kappa"]
        if s["failed"]:
            lines.append(f"| {WHAT[reading]} | {kap:.4g} | failed (seed "
                         + "; seed ".join(f"{k}: {v}" for k, v in s["failed"].items())
                         + ") |" + " |" * 7)
        if len(s["failed"]) == len(rows[reading]):
            continue
        lines.append(f"| {WHAT[reading]} | {kap:.4g} | {ms('rate')} | {ms('tau_mean')} | "
                     f"{ms('tau_std')} | "
                     + ", ".join("none" if x is None else f"{x:.3f}" for x in starts)
                     + f" | {ms('slip_median')} | {ms('slip_p90')} | {ms('slip_big_fraction')} "
                     f"| {ms('servo_rms')} |")
    paper = paper_preset_rate() if scale == "decide" else None
    moved = transfer(summary, paper) if paper else {}
    if moved:
        lines += ["", "In the paper's cell, predicted (the paper-preset run's "
                  f"{paper['rate']:.3f} +- {paper['se']:.3f} phases per step, damping "
                  "reading, x each reading's rate over the damping reading's at this scale; "
                  "assumes a reading moves the rate by the same factor at I = 1e-4, frames 1e-5 "
                  "apart as at the paper's 4e-6, 7.2e-7; the paper: 0.323):", "",
                  "| reading | ratio to damping | predicted phases per step | "
                  "distance from 0.323 (se) |", "|---|---|---|---|"]
        lines += [f"| {WHAT[r]} | {t['ratio']:.3f} | {t['predicted']:.3f} +- {t['se']:.3f} | "
                  f"{t['distance']:+.1f} |" for r, t in moved.items()]
    lines += ["", f"Verdict: {verdict(summary, scale, paper)}."]
    out.mkdir(parents=True, exist_ok=True)
    (out / f"shear_protocol_{scale}.md").write_text("\n".join(lines) + "\n")
    (out / f"shear_protocol_{scale}.json").write_text(json.dumps(
        {"scale": scale, "seeds": seeds, "runs": rows, "summary": summary,
         "paper_preset": paper, "transfer": moved,
         "chosen": chosen(summary, scale, paper)[0],
         "verdict": verdict(summary, scale, paper)}, indent=1, default=float))


def stored_units(scale, rows, store=STORE):
    """The merged code units of the stored runs behind ``rows`` (reading -> seed -> observables):
    a claim that tabulates them is stale exactly when the code that made one of them changed
    (None where a run was untraced)."""
    units = {}
    for reading, seeds in rows.items():
        for seed in seeds:
            path = Path(store) / scale / f"{reading}_s{seed}.npz"
            units = _stamped.merge(units, _stamped.units_of(_stamped.load(path)))
    return units


def report(argv=None):
    """``main(argv)``, then its report's JSON document (None where nothing is stored) with
    ``units``: :func:`stored_units` of its runs."""
    if main(argv) != 0:
        return None
    ap = argparse.ArgumentParser()
    ap.add_argument("--scale", default="quick")
    ap.add_argument("--out", type=Path, default=HERE)
    ap.add_argument("--store", type=Path, default=STORE)
    a, _ = ap.parse_known_args(argv)
    doc = json.loads((a.out / f"shear_protocol_{a.scale}.json").read_text())
    doc["units"] = stored_units(a.scale, doc["runs"], a.store)
    return doc


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--scale", choices=tuple(SCALES), default="quick")
    ap.add_argument("--readings", nargs="+", choices=READINGS, default=list(READINGS))
    ap.add_argument("--seeds", type=int, nargs="+", default=[0, 1, 2])
    ap.add_argument("--cache", type=Path, default=HERE / ".shear_protocol")
    ap.add_argument("--out", type=Path, default=HERE)
    ap.add_argument("--store", type=Path, default=STORE,
                    help="the committed observables of finished runs (default %(default)s)")
    ap.add_argument("--no-run", action="store_true", help="tabulate stored runs only")
    a = ap.parse_args(argv)
    rows = {}
    for reading in a.readings:
        for seed in a.seeds:
            o = one(a.scale, reading, seed, a.cache, not a.no_run,
                    log=lambda m: print(m, flush=True), store=a.store)
            if o is not None:
                rows.setdefault(reading, {})[str(seed)] = o
    if not rows:
        print("no runs stored for these readings and seeds (drop --no-run to run them)")
        return 1
    summary = summarise(rows)
    write(rows, summary, a.scale, a.seeds, a.out)
    print(f"wrote {a.out / f'shear_protocol_{a.scale}.md'}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
