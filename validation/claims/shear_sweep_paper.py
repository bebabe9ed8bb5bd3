"""Claims of issue 34, items 2-3: the mu_s sweep at the paper's scale (Lee & Hurley Sec. 4),
from the committed segmented members (``validation/shear_rolling.py``).  Listed in
``shear.CLAIMS`` through :mod:`claims.shear_protocol`.

The members (paper preset: 1,000 disks, I = 4e-6, kappa = 1e4, frames 7.2e-7 apart, strain
0.1156; one per mu_s = 0.7, 0.5, 0.3, 0.1, seed 0) run over sittings on whatever machine each
sitting gets; the claim reads the store as far as it got, each member analysed from its steady
start, and says the scale reached.  It runs nothing long itself: the runs are
``shear_rolling.py run`` (resumable), the claim regenerates from the store in minutes.
"""

from pathlib import Path

from .core import Claim, Result, Verdict

MUS = (0.7, 0.5, 0.3, 0.1)
_ROOT = Path(__file__).resolve().parents[2]
#: every file of the committed store now: a segment added makes the record stale (its numbers
#: are no longer what the command gives) until it is regenerated
STORED = tuple(sorted(p.relative_to(_ROOT).as_posix() for pattern in ("seg_*.npz", "member.json")
                      for p in (_ROOT / "validation" / "runs" / "shear_rolling").glob(
                          f"mus*_seed*/{pattern}")))
COMMAND = ("python validation/shear_rolling.py run --mus " + " ".join(map(str, MUS))
           + " (committed segments, ~6 h a member on one core, over sittings); python "
           "validation/shear_rolling.py export --out DIR; python validation/shear_sweep_paper.py "
           "DIR")
SHORT = {"agrees": "a", "disagrees": "d", "undecided": "u", "not comparable": "-"}


def sweep_paper(store=None, md=None):
    """Export every paper-preset member of ``store`` (default: the committed one) and write
    ``md`` (default ``validation/shear_sweep_paper.md``) and its ``.json``."""
    import tempfile

    from .shear import _validation
    _validation()
    import _stamped
    import shear_rolling
    import shear_sweep_paper
    dest = Path(tempfile.mkdtemp(prefix="claims_sweep_paper_"))
    units = {}
    for folder in sorted(Path(store or shear_rolling.STORE).glob("mus*_seed*")):
        if not shear_rolling.segments(folder):
            continue
        shear_rolling.export(folder, dest / "runs" / folder.name, log=lambda m: None)
        units = _stamped.merge(units, shear_rolling.arrays(folder)[-1])
    doc = shear_sweep_paper.report(dest, **({} if md is None else {"md": md}),
                                   log=lambda m: None)
    rates = {m: [{k: r[k] for k in ("seed", "rate", "phases", "steps", "strain", "partial")}
                 | {"window_from": r["steady"]["window_from"], "steady": r["steady"]["steady"]}
                 for r in rs] for m, rs in doc["rates"].items()}
    return Result({"rates": rates, "paper": doc["paper"], "sec4": doc["sec4"],
                   "done": doc["done"], "partial": doc["partial"], "missing": doc["missing"]},
                  seeds=(0,), units=units,
                  outputs=("validation/shear_sweep_paper.md", "validation/shear_sweep_paper.json"))


def reached(v):
    """The scale reached, in words."""
    out = []
    for m in MUS:
        rs = v["rates"].get(f"{m:g}")
        if not rs:
            out.append(f"mu_s = {m:g} not started")
            continue
        out += [f"mu_s = {m:g} seed {r['seed']} to strain {r['strain']:.4f}"
                + (" (partial)" if r["partial"] else "") for r in rs]
    return "; ".join(out)


def show(v):
    rates = "; ".join(f"mu_s = {m}: " + " / ".join(
        "no step past gamma0 yet" if r["rate"] is None else f"{r['rate']:.3f}" for r in rs)
                      + f" per step (paper {v['paper'][m]:.3f})"
                      for m, rs in sorted(v["rates"].items(), key=lambda kv: -float(kv[0])))
    sec4 = "; ".join(f"{x['id']} " + "/".join(
        SHORT[c] for _, c in sorted(x["cells"].items(), key=lambda kv: float(kv[0])))
        for x in v["sec4"])
    return (f"{rates}. Sec. 4 per mu_s run ({sec4}; a agrees, d disagrees, u undecided, - not "
            f"comparable). Scale reached: {reached(v)}")


def verdict(v):
    """Sec. 4's statements over the members run: agrees where every statement agrees at every
    mu_s, disagrees where one disagrees, not comparable where none can be judged yet, else
    undecided; with the scale reached."""
    said = [x["verdict"] for x in v["sec4"]]
    label = ("not comparable" if all(w == "not comparable" for w in said) else
             "agrees" if all(w == "agrees" for w in said) else
             "disagrees" if "disagrees" in said else "undecided")
    counts = ", ".join(f"{said.count(w)} {w}" for w in SHORT)
    return Verdict(label, f"{counts} of Sec. 4's statements at the scale reached ({reached(v)})")


def check(old, new):
    """Regenerated from the same store: the same numbers; a store that grew: stated."""
    grown = {m: [r["strain"] for r in rs] for m, rs in new["rates"].items()} != \
        {m: [r["strain"] for r in rs] for m, rs in old["rates"].items()}
    if grown:
        return True, "the store reached further: new numbers, judged afresh"
    same = old["rates"] == new["rates"] and old["sec4"] == new["sec4"]
    return same, "identical" if same else "the same store gave other numbers"


CLAIMS = [
    Claim("shear.sweep_paper", "shear",
          "the mu_s sweep at the paper's scale (paper preset, mu_s = 0.7 / 0.5 / 0.3 / 0.1, "
          "seed 0; committed segmented members, each analysed from its steady start): phase "
          "rates against the paper's and Sec. 4's eight statements per mu_s, at the scale "
          "reached", "hours", COMMAND, sweep_paper, show=show,
          tolerance=("the same store regenerates the same numbers to the bit (the analysis is "
                     "deterministic); a store that grew is judged afresh"),
          check=check,
          paper="18,000 / 46,000 / 52,000 / 42,000 phases in ~130,000 output steps at mu_s = "
                "0.1 / 0.3 / 0.5 / 0.7 (Sec. 4); the eight statements of Sec. 4 on Fig. 13",
          verdict=verdict, job="shear.sweep_paper", inputs=STORED),
]
