"""Claim of issue 34, item 2: the paper-preset steady state judged across independent seeds.
Listed in ``shear.CLAIMS`` through :mod:`claims.shear_protocol`.

One member cannot show a steady state: tau's memory is long (``shear.member_scaling``:
H = 0.90), so a trend test on one series either ignores the memory or cannot see a rise of
3 std.  Independent seeds of the same protocol can: one slope of tau per seed over the span
after the transient, and Student's t across the seeds
(:func:`fricstab.analysis.long_memory.ensemble_trend_test`), exact whatever each seed's
memory.  The seeds run as the paper-preset member did (``python validation/shear_rolling.py
run --mus 0.7 --seed S --strain 0.2``, committed segments, resumable over sittings); the claim
reads every ``mus0.7_seed*`` member of the store as far as it got, judges once
:data:`MIN_SEEDS` reach :data:`SEED_STRAIN`, and until then says which seeds are owed and what
they cost.
"""

from pathlib import Path

from .core import Claim, Result, Verdict, sigma_verdict
from .shear_sweep_paper import PAPER_WINDOW, SEED_STRAIN, inside, stamped_seconds

_ROOT = Path(__file__).resolve().parents[2]
_STORE = _ROOT / "validation" / "runs" / "shear_rolling"
#: the span judged: from the paper's window's end (tau levels from ~0.12 in seed 0) to the
#: strain every seed runs to
SPAN = (PAPER_WINDOW[1], SEED_STRAIN)
#: seeds the judgement needs (the t test across seeds has M - 1 degrees of freedom: with 4,
#: a rise is seen half the time once it is 3.2 standard errors of the mean slope)
MIN_SEEDS = 4
#: equal bins of the span per seed for its slope
N_BINS = 20
#: seed 0's segments that reach SEED_STRAIN (5,000 frames of 7.2e-7 each: 56 segments), fixed
#: once written; every segment of the other seeds (they run to SEED_STRAIN and stop)
STORED = tuple(sorted(
    [f"validation/runs/shear_rolling/mus0.7_seed0/seg_{i:04d}.npz" for i in range(56)]
    + [p.relative_to(_ROOT).as_posix() for pattern in ("seg_*.npz", "member.json")
       for p in _STORE.glob(f"mus0.7_seed[1-9]*/{pattern}")]))
COMMAND = ("python validation/shear_rolling.py run --mus 0.7 --seed S --strain "
           f"{SEED_STRAIN:g} for S = 1 .. {MIN_SEEDS - 1} (~9 core-h a seed, committed "
           "segments, over sittings); python validation/reproduce.py --claim shear.member_seeds")


def member_seeds(store=None, span=SPAN, min_seeds=MIN_SEEDS, n_bins=N_BINS):
    """tau and the phase rate of the paper-preset member (mu_s = 0.7) over ``span`` of strain,
    per seed and across seeds.  ``members``: per seed, the strain reached and, for a seed that
    covers the span, its mean tau, its phases per output step (phases as the analysis finds
    them, steps whose frames both lie in the span) and its core-hours to ``span[1]`` (its
    segments' stamps).  With ``min_seeds`` seeds covering the span: ``test``, the trend test
    across seeds (:func:`fricstab.analysis.long_memory.ensemble_trend_test`, ``n_bins`` bins),
    and ``rate`` (mean over seeds, standard error from their spread, and the paper's)."""
    import numpy as np

    from .shear import PAPER_PHASES, PAPER_STEPS, _validation
    _validation()
    import _stamped
    import shear_rolling
    from fricstab.analysis.long_memory import ensemble_trend_test
    from fricstab.analysis.shear_phases import find_phases
    store = Path(store or shear_rolling.STORE)
    members, series, units = [], [], {}
    prefix = "mus0.7_seed"
    for folder in sorted(store.glob(prefix + "*"), key=lambda f: int(f.name[len(prefix):])):
        files = shear_rolling.segments(folder)
        if not files:
            continue
        seed = int(folder.name[len(prefix):])
        with np.load(files[-1]) as z:
            reached = float(z["series"][-1, 1])
        row = {"seed": seed, "reached": reached}
        if reached >= span[1] - 1e-12:
            got, u, used = shear_rolling.series_to(folder, span[1])
            units = _stamped.merge(units, u)
            strain, tau = got[:, 1], got[:, 4]
            ok = inside(strain, *span)
            keep = (strain >= span[0]) & (strain <= span[1])
            row |= {"mean": float(tau[keep].mean()), "steps": int(ok.sum()),
                    "rate": len(find_phases(tau, ok)) / int(ok.sum()),
                    "core_hours": sum(c for c, _ in stamped_seconds(used)) / 3600.0}
            series.append((strain, tau))
        members.append(row)
    out = {"span": list(span), "min_seeds": min_seeds, "members": members,
           "paper": PAPER_PHASES["0.7"] / PAPER_STEPS, "test": None, "rate": None}
    if len(series) >= min_seeds:
        t = ensemble_trend_test(series, span, n_bins)
        out["test"] = {k: t[k] for k in ("slope", "slope_se", "p", "steady", "alpha",
                                         "rise_over_std", "resolvable_rise", "mean", "mean_se",
                                         "members", "n_bins")}
        rates = np.array([m["rate"] for m in members if "rate" in m])
        out["rate"] = {"mean": float(rates.mean()),
                       "se": float(rates.std(ddof=1) / np.sqrt(rates.size))}
    return Result(out, seeds=tuple(m["seed"] for m in members), units=units)


def _owed(v):
    done = [m for m in v["members"] if "mean" in m]
    cost = max((m["core_hours"] for m in done), default=None)
    part = ", ".join(f"seed {m['seed']} at strain {m['reached']:.4f}"
                     for m in v["members"] if "mean" not in m)
    return (f"{len(done)} of {v['min_seeds']} seeds reach strain {v['span'][1]:g}"
            + (f" ({part})" if part else "")
            + (f"; a seed costs ~{cost:.1f} core-h" if cost else ""))


def seeds_show(v):
    lo, hi = (100 * x for x in v["span"])
    per = "; ".join(f"seed {m['seed']}: tau {m['mean']:.3f}, {m['rate']:.3f} phases per step"
                    for m in v["members"] if "mean" in m)
    head = f"strain {lo:.2f}-{hi:g} %, per seed: {per or 'none yet'}"
    if v["test"] is None:
        return f"{head}. {_owed(v)}: no test across seeds yet"
    t, r = v["test"], v["rate"]
    return (f"{head}. Across {t['members']} seeds ({t['n_bins']} bins each): tau's slope "
            f"{t['slope']:+.3g} +- {t['slope_se']:.2g} per unit strain (a rise of "
            f"{t['rise_over_std']:+.2f} std over the span, p = {t['p']:.2g}; the test sees "
            f"{t['resolvable_rise']:.2f} std half the time); mean tau {t['mean']:.3f} +- "
            f"{t['mean_se']:.3f}; {r['mean']:.3f} +- {r['se']:.3f} phases per step (paper "
            f"{v['paper']:.3f})")


def seeds_check(old, new):
    """The same segments: the same numbers to the bit; a seed that ran further: stated, and
    the numbers judged afresh (:func:`claims.core.judged_afresh`)."""
    from .core import judged_afresh
    then, now = ({m["seed"]: m["reached"] for m in v["members"]} for v in (old, new))
    grown = judged_afresh(then, now, ", ".join(
        f"seed {s} to strain {then.get(s, 0.0):.4g} -> {now[s]:.4g}"
        for s in now if then.get(s) != now[s]))
    if grown:
        return grown
    return old == new, "identical" if old == new else "the same segments gave other numbers"


def seeds_verdict(v):
    """Not comparable until :data:`MIN_SEEDS` seeds cover the span; undecided where the test
    across seeds rejects a steady state; else the phase rate against the paper's
    (:func:`claims.core.sigma_verdict`, the seeds' standard error, the paper's count taken
    exact)."""
    if v["test"] is None:
        return Verdict("not comparable", _owed(v) + " (the test across seeds needs "
                       f"{v['min_seeds']}; one member cannot show a steady state: "
                       "shear.member_scaling)")
    t = v["test"]
    if not t["steady"]:
        return Verdict("undecided", f"tau still drifts across seeds over the span (p = "
                       f"{t['p']:.2g} < {t['alpha']:g}): run the seeds further")
    got = sigma_verdict([(v["rate"]["mean"], v["rate"]["se"], v["paper"], 0.0)])
    return Verdict(got.label, f"steady across {t['members']} seeds (p = {t['p']:.2g}); phase "
                   f"rate {got.detail}")


CLAIMS = [
    Claim("shear.member_seeds", "shear",
          "the paper-preset statistics from a steady state that a test across independent "
          "seeds accepts: tau's trend over strain 11.56-20 % per seed (mu_s = 0.7), Student's "
          "t across the seeds, and the phase rate with the seeds' spread",
          "seconds", COMMAND, member_seeds, show=seeds_show,
          tolerance="the same segments give the same numbers to the bit (deterministic); "
                    "a seed's segment added makes the record stale until it is regenerated",
          check=seeds_check,
          paper="42,000 phases in ~130,000 output steps at mu_s = 0.7 (Sec. 4): 0.323 per "
                "step, taken in a steady state",
          verdict=seeds_verdict, texts={"verdict": lambda v: str(seeds_verdict(v))},
          inputs=STORED),
]
