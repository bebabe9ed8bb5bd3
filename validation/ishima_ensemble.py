"""Issue 35, item 1: Ishima's ensemble, made once, cached with its provenance, unstable
packings excluded by a stated rule.

The paper (Sec. II): N = 4096 with 10 samples per (phi, kT/kN), some results with N = 1024 and
5 samples, phi from 0.83 to 0.90.  Each packing is :func:`fricstab.scenes.packing.make_packing`
(compression by FIRE, App. A), cached by ``validation/_packings.py`` (keyed by every argument and
the protocol version); its rattler-free backbone is judged by the exclusion rule of
:mod:`fricstab.analysis.stability` under the frictionless law (the packing's own Hessian: a
saddle, or G(0) < 0, is a failed preparation; the frictional laws are switched on at this force
balance, App. A.2).  Per packing the manifest keeps: the seconds to make it (0 when it came from
the cache), the backbone size, rattlers, mean contact number, pressure, the verdict and its
reason.  Every later analysis (Figs. 4-16) reads the manifest and uses the packings it marks
``use``.

    python validation/ishima_ensemble.py                       # the paper's ensemble
    python validation/ishima_ensemble.py --sizes 1024 --samples 5 --phis 0.85 0.90
    python validation/ishima_ensemble.py --budget-only         # measured cost, no ensemble

Writes ``<out>/ishima_ensemble.json`` (the manifest) and ``.md`` (counts per N and phi,
exclusions with reasons).  Interrupted, it goes on from the cached packings.
"""

import argparse
import json
import platform
import sys
import time
from datetime import datetime, timezone
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))
sys.path.insert(0, str(HERE))

import _packings  # noqa: E402
from fricstab.analysis.stability import G_TOL, packing_stability  # noqa: E402
from fricstab.analysis.sparse_spectrum import ZERO_CLUSTER  # noqa: E402
from fricstab.engine.newton import touching  # noqa: E402
from fricstab.errors import ConvergenceError, ParameterError  # noqa: E402
from fricstab.scenes.packing_friction import backbone, frictional, material  # noqa: E402

PHIS = (0.83, 0.84, 0.85, 0.86, 0.87, 0.88, 0.89, 0.90)
SAMPLES = {1024: 5, 4096: 10}
RULE = ("excluded: no rigid backbone (unjammed), forces not balanced to 1e-6 of the mean "
        "contact force or a compression (FIRE) that does not converge (marginal, at the jamming "
        "threshold), a real eigenvalue of M^-1 K above "
        f"{ZERO_CLUSTER:g} |A|_inf beyond the translations (a saddle), or G(0) < -{G_TOL:g} "
        "|G_A| (unstable to shear); the frictionless backbone, fricstab.analysis.stability")


def _key(n, phi, seed):
    return f"n{n}_phi{phi:g}_s{seed}"


def _excluded(n, phi, seed, reason, log, *, make_seconds, judge_seconds, from_cache,
              backbone, rattlers, z_mean=None):
    """The manifest row of a packing the rule excludes before its stability is judged."""
    log(f"  N = {n} phi = {phi:g} seed {seed}: EXCLUDED ({reason})")
    return {"n": n, "phi": phi, "seed": seed, "make_seconds": make_seconds,
            "judge_seconds": judge_seconds, "from_cache": from_cache, "backbone": backbone,
            "rattlers": rattlers, "z_mean": z_mean,
            "stability": {"stable": False, "reason": reason}, "use": False}


def one(n, phi, seed, log=print):
    """The manifest row of one packing (made or read from the cache)."""
    cached = (_packings.CACHE / f"v{_packings.PROTOCOL}_n{n}_phi{phi:g}_s{seed}.npz").exists()
    t0 = time.perf_counter()
    try:
        p = _packings.packing(n, phi, seed)
    except ConvergenceError as exc:   # FIRE stalled: a packing at the jamming threshold
        return _excluded(n, phi, seed, f"marginal: the compression did not converge: {exc}",
                         log, make_seconds=time.perf_counter() - t0, judge_seconds=0.0,
                         from_cache=False, backbone=None, rattlers=None)
    made = 0.0 if cached else time.perf_counter() - t0
    t0 = time.perf_counter()
    try:
        bb = backbone(p)
    except ParameterError as exc:     # below jamming: nothing rigid to judge or to measure
        if "no rigid backbone" not in str(exc):
            raise
        return _excluded(n, phi, seed,
                         "unjammed: no rigid backbone (every particle a rattler, Z <= 2)", log,
                         make_seconds=made, judge_seconds=time.perf_counter() - t0,
                         from_cache=cached, backbone=0, rattlers=int(n), z_mean=0.0)
    fr = frictional(bb, material("hertz"))
    try:
        s = packing_stability(fr.system, fr.state)
    except ParameterError as exc:     # at the threshold: contact forces at rounding level
        if "not force-balanced" not in str(exc):
            raise
        return _excluded(n, phi, seed,
                         f"marginal: {str(exc).split(';')[0]} (a packing at the jamming threshold)",
                         log, make_seconds=made, judge_seconds=time.perf_counter() - t0,
                         from_cache=cached, backbone=int(bb.n), rattlers=int(n - bb.n))
    row = {"n": n, "phi": phi, "seed": seed, "make_seconds": made,
           "judge_seconds": time.perf_counter() - t0, "from_cache": cached,
           "backbone": int(bb.n), "rattlers": int(n - bb.n),
           "z_mean": 2.0 * len(touching(fr.system, fr.state)) / bb.n,
           "stability": s.to_json(), "use": bool(s.stable)}
    log(f"  N = {n} phi = {phi:g} seed {seed}: backbone {bb.n}, z {row['z_mean']:.2f}, "
        + ("stable" if s.stable else f"EXCLUDED ({s.reason})")
        + (f", made in {made:.0f} s" if made else " (cached)"))
    return row


def budget(sizes, log=print):
    """Seconds to make and judge one packing per N, measured at the densest phi (seed 999, a
    seed outside the ensemble, so the probe does not fill the cache with ensemble members)."""
    out = {}
    for n in sizes:
        r = one(n, max(PHIS), 999, log=lambda m: None)
        out[n] = {"make_seconds": r["make_seconds"], "judge_seconds": r["judge_seconds"]}
        log(f"N = {n}: {r['make_seconds']:.0f} s to make, {r['judge_seconds']:.1f} s to judge")
    return out


def summary(rows):
    """Per (N, phi): samples, used, excluded (with reasons)."""
    out = {}
    for r in rows:
        c = out.setdefault(f"{r['n']}/{r['phi']:g}", {"n": r["n"], "phi": r["phi"],
                                                      "samples": 0, "used": 0, "excluded": []})
        c["samples"] += 1
        c["used"] += r["use"]
        if not r["use"]:
            c["excluded"].append({"seed": r["seed"], "reason": r["stability"]["reason"]})
    return out


def write(rows, out, argv):
    stamp = f"{datetime.now(timezone.utc):%Y-%m-%d %H:%M} UTC, {platform.node()}"
    summ = summary(rows)
    doc = {"rule": RULE, "rows": rows, "summary": summ, "stamp": stamp,
           "command": "python validation/ishima_ensemble.py " + " ".join(argv)}
    out.mkdir(parents=True, exist_ok=True)
    (out / "ishima_ensemble.json").write_text(json.dumps(doc, indent=1) + "\n")
    lines = [f"<!-- generated by validation/ishima_ensemble.py ({stamp}) -->", "",
             "# Ishima's ensemble", "", f"Rule: {RULE}.", "",
             "| N | phi | samples | used | excluded (seed: reason) |", "|---|---|---|---|---|"]
    for c in summ.values():
        lines.append(f"| {c['n']} | {c['phi']:g} | {c['samples']} | {c['used']} | "
                     + ("; ".join(f"{e['seed']}: {e['reason']}" for e in c["excluded"]) or "-")
                     + " |")
    made = sum(r["make_seconds"] for r in rows)
    lines += ["", f"Packings made this time: {sum(not r['from_cache'] for r in rows)} "
              f"({made:.0f} s); read from the cache: {sum(r['from_cache'] for r in rows)}."]
    (out / "ishima_ensemble.md").write_text("\n".join(lines) + "\n")
    return doc


def main(argv=None):
    argv = sys.argv[1:] if argv is None else argv
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sizes", type=int, nargs="+", default=[1024, 4096])
    ap.add_argument("--samples", type=int, nargs="+", default=None,
                    help="samples per size (default: the paper's, 5 at 1,024 and 10 at 4,096)")
    ap.add_argument("--phis", type=float, nargs="+", default=list(PHIS))
    ap.add_argument("--out", type=Path, default=HERE)
    ap.add_argument("--budget-only", action="store_true")
    a = ap.parse_args(argv)
    samples = a.samples or [SAMPLES.get(n, 5) for n in a.sizes]
    if len(samples) != len(a.sizes):
        ap.error("--samples needs one count per size")
    if any(not 0.5 < p < 1.0 for p in a.phis):
        ap.error("--phis: area fractions in (0.5, 1)")
    if a.budget_only:
        budget(a.sizes)
        return 0
    rows = []
    for n, k in zip(a.sizes, samples):
        for phi in a.phis:
            for seed in range(k):
                rows.append(one(n, phi, seed, log=lambda m: print(m, flush=True)))
    write(rows, a.out, argv)
    print(f"wrote {a.out / 'ishima_ensemble.md'}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
