"""Which departure of the quick preset from the paper changes its phase rate: one knob at a time.

The quick preset (300 disks, I = 1e-4, kappa = 1e3, frames 1e-5 of strain
apart) counts fewer stick and slip phases per output step than Lee & Hurley
(0.32).  Each row here sets one knob of the quick preset to the paper's value
and runs it for several seeds (the rate of this chaotic cell spreads between
seeds, so a knob counts only where it moves the mean by more than the seeds'
spread); the frame interval is varied alone by keeping every k-th frame of the
paper-preset run (``validation/shear_paper.json``, written by
``validation/shear_paper.py``).

Usage: ``python validation/shear_knobs.py [--seeds 0 1 2] [--knobs base kappa n I]
[--cache DIR]`` -> ``validation/shear_knobs.md``.  Runs already in the cache
folder (default ``validation/.shear_knobs``) with the same parameters are
reused.  Cost on one core: base ~1.5 min a seed, kappa ~4 min, n ~5 min, I
(4e-6: 25x the steps) ~20 min.
"""

import argparse
import json
import statistics
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))  # run from anywhere without installing

#: knob -> (scene overrides of the quick preset, the paper's value in words)
KNOBS = {"base": ({}, "the quick preset"),
         "kappa": ({"kappa": 1e4}, "kappa = 1e4 (quick 1e3)"),
         "n": ({"n": 1000}, "1,000 disks (quick 300)"),
         "I": ({"inertial_number": 4e-6}, "I = 4e-6 (quick 1e-4)")}


def rate(knob, seed, cache, run=True):
    """Phases per output step of the quick preset with ``knob`` at the paper's value (cached run).

    ``(rate, seconds run)``; ``(None, 0)`` when not cached and ``run`` is False.
    """
    from fricstab.cli.shear import resolve_params, run_shear
    p = resolve_params(None, "quick", {**KNOBS[knob][0], "seed": seed})
    out = cache / f"{knob}_s{seed}"
    rec_path = out / "shear.json"
    if rec_path.exists():
        rec = json.loads(rec_path.read_text())
        if rec["parameters"] == json.loads(json.dumps(p)):
            return rec["phases"]["phases_per_step"], 0.0
    if not run:
        return None, 0.0
    t0 = time.perf_counter()
    rec = run_shear(p, out, force=True, argv=["validation/shear_knobs.py"], log=lambda s: None)
    return rec["phases"]["phases_per_step"], time.perf_counter() - t0


def runs(knobs, seeds, cache, run=True, log=print):
    """{knob: {seed: {rate, largest_drop, tau_mean, servo_rms}}} of the (cached) runs, and the
    seconds spent running; a seed not cached is left out when ``run`` is False."""
    table, total = {}, 0.0
    for knob in knobs:
        for seed in seeds:
            r, sec = rate(knob, seed, cache, run)
            if r is None:
                continue
            total += sec
            rec = json.loads((cache / f"{knob}_s{seed}" / "shear.json").read_text())
            table.setdefault(knob, {})[str(seed)] = {
                "rate": r, "largest_drop": rec["phases"]["largest_drop"],
                "tau_mean": rec["tau_mean_window"], "servo_rms": rec["servo"]["rms_rel_error"]}
            log(f"{knob} seed {seed}: {r:.3f} phases per step ({sec:.0f} s)")
    runs.seconds = total
    return table


def write(table, seeds, knobs, md=HERE / "shear_knobs.md", no_run=False, minutes=None):
    """``md``: a row per knob (rates per seed, mean, spread), and the frame-interval row
    from ``shear_paper.json`` where the paper-preset run has written it."""
    lines = ["# Phase rate of the quick preset, one knob at the paper's value", "",
             f"Command: `python validation/shear_knobs.py --seeds {' '.join(map(str, seeds))} "
             f"--knobs {' '.join(knobs)}{' --no-run' if no_run else ''}`"
             + (f" ({minutes:.0f} min of runs this time, one core; cached runs reused)"
                if minutes is not None else "")
             + ". Phases per output step in the window from 2.2 % strain; paper 0.323 "
             "(~42,000 in ~130,000).", "",
             "| knob at the paper's value | phases per step, per seed | mean | seed spread |",
             "|---|---|---|---|"]
    for knob, per in table.items():
        rates = [x["rate"] for x in per.values()]
        lines.append(f"| {KNOBS[knob][1]} | {', '.join(f'{r:.3f}' for r in rates)} | "
                     f"{statistics.mean(rates):.3f} | {min(rates):.3f}-{max(rates):.3f} |")
    paper = HERE / "shear_paper.json"
    if paper.exists():
        doc = json.loads(paper.read_text())
        by = {r["every"]: r for r in doc.get("frame_interval", [])}
        if 1 in by and 14 in by:
            lines.append(f"| frame interval 7.2e-7 (quick 1e-5), the paper-preset run itself "
                         f"({'complete' if doc['complete'] else 'partial, to strain %.3f' % doc['strain_reached']}; "
                         "`validation/shear_paper.md` names its revision) "
                         f"| every frame {by[1]['per_step']:.3f}; every 14th (1.0e-5) "
                         f"{by[14]['per_step']:.3f} | - | one trajectory |")
    Path(md).write_text("\n".join(lines) + "\n")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", type=int, nargs="+", default=[0, 1, 2])
    ap.add_argument("--knobs", nargs="+", choices=tuple(KNOBS), default=["base", "kappa", "n"])
    ap.add_argument("--cache", type=Path, default=HERE / ".shear_knobs")
    ap.add_argument("--md", type=Path, default=HERE / "shear_knobs.md")
    ap.add_argument("--no-run", action="store_true",
                    help="tabulate the cached runs of these knobs and seeds only (start none)")
    ns = ap.parse_args(argv)
    table = runs(ns.knobs, ns.seeds, ns.cache, not ns.no_run,
                 log=lambda m: print(m, flush=True))
    write(table, ns.seeds, ns.knobs, ns.md, ns.no_run, runs.seconds / 60)
    print(f"wrote {ns.md}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
