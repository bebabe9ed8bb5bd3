"""Claims of issue 34, item 1: which reading of Lee & Hurley's protocol the evidence supports
(``validation/shear_protocol.py``).  Listed in ``shear.CLAIMS``.

The paper gives a restitution coefficient (0.9) and damping ratios (0.1), and kappa = 1e4
without saying E*/P or k_n/P; the four combinations run on the same cells and seeds at the
decide scale (1,000 disks, kappa = 1e4, I = 1e-4, frames 1e-5 apart, strain 0.12).  The
paper states one number its observables can be held against, the phase rate 0.323 of its own
cell; the reading's effect measured at the decide scale is carried to the paper's cell through
the paper-preset run (:func:`shear_protocol.transfer`, its assumption stated there).
"""

from .core import Claim, Result, Verdict, sigma_verdict

SEEDS = (0, 1, 2)
COMMAND = ("python validation/shear_protocol.py --scale decide --seeds "
           + " ".join(map(str, SEEDS)))
#: the observables kept per run and per reading (``shear_protocol.observables``)
KEEP = ("rate", "tau_mean", "tau_std", "slip_median", "slip_p90", "slip_big_fraction",
        "servo_rms")
#: each seed's phase rate may move by this factor on another machine (a new trajectory of a
#: chaotic cell): the largest ratio of two seeds' rates of one reading at the decide scale
#: (0.479 / 0.372 = 1.3 for damping, seeds 0-2); 1.6 as the quick preset's (claims.shear)
SEED_FACTOR = 1.6
READINGS = ("damping", "restitution", "kn", "restitution_kn")
#: the committed store of the runs' observables (``shear_protocol.STORE``)
STORED = tuple(f"validation/runs/shear_protocol/decide/{r}_s{s}.npz"
               for r in READINGS for s in SEEDS)


def _validation():
    from .shear import _validation as v
    v()


def protocol_decide():
    """``python validation/shear_protocol.py --scale decide --seeds 0 1 2``: from the committed
    store where its runs' code is unchanged (seconds), else the runs (~1 core-h each)."""
    _validation()
    import shear_protocol
    doc = shear_protocol.report(["--scale", "decide", "--seeds", *map(str, SEEDS)])
    if doc is None:
        raise RuntimeError("shear_protocol.py stored no run")
    runs = {r: {s: ({k: x.get(k) for k in KEEP} | {"steady_start": x.get("steady_start")}
                    if "failure" not in x else {"failure": x["failure"]})
                for s, x in seeds.items()} for r, seeds in doc["runs"].items()}
    summary = {r: {k: s[k] for k in KEEP if k in s} for r, s in doc["summary"].items()}
    _, supported, why = shear_protocol.chosen(doc["summary"], "decide", doc["paper_preset"])
    out = tuple(f"validation/shear_protocol_decide.{x}" for x in ("md", "json"))
    return Result({"runs": runs, "summary": summary, "paper_preset": doc["paper_preset"],
                   "transfer": doc["transfer"], "chosen": doc["chosen"],
                   "supported": supported, "why": why}, seeds=SEEDS, outputs=out,
                  units=doc["units"])


def _ms(s, k, d=3):
    x = s.get(k)
    if not x:
        return "-"
    return f"{x['mean']:.{d}g}" + ("" if x["se"] is None else f" +- {x['se']:.2g}")


def table(v):
    """The reading table of the shear reference page."""
    import shear_protocol as sp
    rows = ["| reading | phases per step | tau mean (steady) | tau std | steady start "
            "(strain, per seed) | slip p90 | slips > 1e-2 | in the paper's cell "
            "(predicted) | from 0.323 |", "|---|---|---|---|---|---|---|---|---|"]
    for r, s in v["summary"].items():
        starts = ", ".join("failed" if "failure" in x else
                           "none" if x["steady_start"] is None else f"{x['steady_start']:.3f}"
                           for x in v["runs"][r].values())
        t = v["transfer"].get(r)
        pred = "-" if t is None else f"{t['predicted']:.3f} +- {t['se']:.3f}"
        dist = "-" if t is None else f"{t['distance']:+.1f} se"
        rows.append(f"| {sp.WHAT[r]}{' (chosen)' if r == v['chosen'] else ''} | "
                    f"{_ms(s, 'rate')} | {_ms(s, 'tau_mean')} | {_ms(s, 'tau_std')} | {starts} | "
                    f"{_ms(s, 'slip_p90')} | {_ms(s, 'slip_big_fraction')} | {pred} | {dist} |")
    return "\n".join(rows)


def _show(v):
    return "; ".join(
        f"{r}: {s['rate']['mean']:.3f} +- {s['rate']['se']:.3f} per step"
        + (f" (paper's cell {v['transfer'][r]['predicted']:.3f} +- "
           f"{v['transfer'][r]['se']:.3f})" if r in v["transfer"] else "")
        for r, s in v["summary"].items() if s.get("rate") and s["rate"]["se"])


def _verdict(v):
    """The chosen reading's rate in the paper's cell against 0.323 (sigma rule), with the
    choice and its rule."""
    t = v["transfer"].get(v["chosen"])
    if t is None:
        return Verdict("undecided", v["why"])
    s = sigma_verdict([(t["predicted"], t["se"], 0.323, 0.0)])
    return Verdict(s.label, f"reading chosen: {v['chosen']}: {v['why']}; its rate in the "
                            f"paper's cell: {s.detail}")


def _check(old, new):
    """Each seed's rate within SEED_FACTOR; the chosen reading the same."""
    worst, where = 1.0, None
    for r, seeds in old["runs"].items():
        for s, x in seeds.items():
            y = new["runs"].get(r, {}).get(s, {})
            if "rate" not in x or "rate" not in y:
                if ("rate" in x) != ("rate" in y):
                    return False, f"{r} seed {s}: ran in one record, failed in the other"
                continue
            f = max(x["rate"] / y["rate"], y["rate"] / x["rate"])
            if f > worst:
                worst, where = f, f"{r} seed {s}"
    if worst > SEED_FACTOR:
        return False, f"{where}: rate moved by a factor {worst:.2f} > {SEED_FACTOR:g}"
    if old["chosen"] != new["chosen"]:
        return False, f"the chosen reading moved: {old['chosen']} -> {new['chosen']}"
    return True, ("identical" if where is None else
                  f"largest move a factor {worst:.2f} ({where}); same reading chosen")


CLAIMS = [
    Claim("shear.protocol_decide", "shear",
          "the protocol's four readings (damping ratio 0.1 or restitution 0.9; kappa as E*/P "
          "or k_n/P) at the decide scale (1,000 disks, kappa = 1e4, I = 1e-4, strain 0.12), "
          f"seeds {', '.join(map(str, SEEDS))}: the phase rate, carried to the paper's cell "
          "through the paper-preset run, and the reading chosen", "hours", COMMAND,
          protocol_decide, show=_show,
          tolerance=(f"chaotic cell: bit-identical on one machine; elsewhere each seed's rate "
                     f"within a factor {SEED_FACTOR:g} and the same reading chosen"),
          check=_check,
          paper="0.323 phases per step (~42,000 phases in ~130,000 output steps, Sec. 3.1); "
                "restitution 0.9 (Sec. 2) and damping ratios gamma_n = gamma_t = 0.1 (App. A); "
                "kappa = 1e4",
          verdict=_verdict, job="shear.protocol",
          inputs=("validation/shear_paper.json", *STORED),
          texts={"table": table,
                 "choice": lambda v: f"{v['chosen']}: {v['why']}"}),
]

from .shear_sweep_paper import CLAIMS as _SWEEP_PAPER  # noqa: E402

CLAIMS += _SWEEP_PAPER

from .shear_seeds import CLAIMS as _SEEDS  # noqa: E402

CLAIMS += _SEEDS
