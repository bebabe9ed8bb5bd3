"""The claim: one number (or a few) that fricstab states about what it computed.

A :class:`Claim` says how to compute its values (``compute``), how to show
them (``show``), how far a regenerated value may move and why (``tolerance``
and ``check``), what the paper says (``paper``) and how agreement with it is
decided (``verdict``: a computed distance, never a typed word).  The recorded
values live in ``validation/records/<name>.json`` (written by
``python validation/reproduce.py --claim NAME``); RESULTS.md and the marked
blocks of the other pages are rendered from them.

Tiers by cost on the 2-core reference machine: ``seconds`` (recomputed in
CI), ``minutes`` (the whole tier under an hour: ``--tier minutes``),
``hours`` (checked for staleness only).

Helpers below build the two kinds of computed judgement:

* ``check(old, new) -> (ok, text)``: is a regenerated value the recorded one
  within the stated tolerance (``same``, ``within_sigma``)?
* ``verdict(values) -> Verdict``: ours against the paper (``sigma_verdict``,
  ``rel_verdict``, ``bound_verdict``, ``exact_verdict``) or ``measured``.
"""

import math
import statistics
from dataclasses import dataclass, field
from typing import Callable

TIERS = ("seconds", "minutes", "hours")


@dataclass(frozen=True)
class Verdict:
    """A computed judgement: ``label`` (agrees, disagrees, undecided, meets, fails,
    measured, not comparable) and the distance or test behind it."""

    label: str
    detail: str = ""

    @property
    def ok(self):
        """True where the label says agreement, False where it says the opposite,
        None where nothing is compared or the comparison is undecided."""
        return {"agrees": True, "meets": True, "disagrees": False, "fails": False}.get(self.label)

    def __str__(self):
        return f"**{self.label}**" + (f" ({self.detail})" if self.detail else "")


@dataclass(frozen=True)
class Result:
    """What ``compute`` returns: JSON values, the seeds that produced them, and
    the files it wrote (their hashes go into the record)."""

    values: dict
    seeds: tuple = ()
    outputs: tuple = ()
    #: the code that made cached computations the values read (``{module: {unit: hash}}``,
    #: :func:`claims.fingerprint.code_units`): part of the record's dependence, so the claim
    #: is stale exactly when that code changed, not at every change of the package
    units: dict = None


@dataclass(frozen=True)
class Claim:
    """One row of RESULTS.md (see the module docstring)."""

    name: str                 # "section.short", unique; records/<name>.json
    section: str              # key of claims.SECTIONS
    title: str                # the row's "claim" cell
    tier: str                 # seconds | minutes | hours
    command: str              # what a user runs to see it (reproduce.py --claim NAME also does)
    compute: Callable         # () -> Result
    show: Callable            # values -> str, the "ours" cell
    tolerance: str            # how far a regenerated value may move, and why
    check: Callable           # (old values, new values) -> (ok, text)
    paper: str = "(none)"     # the paper's value or statement, as printed there
    verdict: Callable = None  # values -> Verdict; None: measured, nothing to compare
    inputs: tuple = ()        # data files (relative to the checkout) the values depend on
    texts: dict = field(default_factory=dict)   # key -> (values -> str), for blocks in other pages
    job: str = None           # claims that share one computation share a job (and a record);
                              # default: the claim's own name
    trace: bool = True        # False: values are timings, so the job runs untraced and its
                              # fingerprint counts every loaded module whole (fingerprint.py)

    def __post_init__(self):
        if self.tier not in TIERS:
            raise ValueError(f"claim {self.name}: tier {self.tier!r} not in {TIERS}")
        if "." not in self.name:
            raise ValueError(f"claim {self.name}: name must be 'section.short'")

    @property
    def job_name(self):
        """The record this claim reads: ``validation/records/<job_name>.json``."""
        return self.job or self.name

    def judge(self, values):
        """The verdict against the paper, computed from ``values``."""
        if self.verdict is None:
            return Verdict("measured")
        return self.verdict(values)


# ------------------------------------------------------------ reproducibility checks

def _leaves(x, prefix=""):
    """Flatten nested dicts/lists of values into {path: leaf}."""
    if isinstance(x, dict):
        out = {}
        for k, v in x.items():
            out.update(_leaves(v, f"{prefix}.{k}" if prefix else str(k)))
        return out
    if isinstance(x, (list, tuple)):
        out = {}
        for i, v in enumerate(x):
            out.update(_leaves(v, f"{prefix}[{i}]"))
        return out
    return {prefix: x}


def same(rel=0.0, abs=0.0, keys=None):
    """Check: every numeric leaf (or those under ``keys``) within ``abs + rel |old|``;
    other leaves equal.  ``same()`` is an exact match."""
    def check(old, new):
        a, b = _leaves(old), _leaves(new)
        if keys is not None:
            a = {k: v for k, v in a.items() if k.split(".")[0].split("[")[0] in keys}
            b = {k: v for k, v in b.items() if k in a}
        if set(a) != set(b):
            return False, f"values differ in shape: {sorted(set(a) ^ set(b))[:4]}"
        worst, where = 0.0, None
        for k, x in a.items():
            y = b[k]
            if isinstance(x, bool) or isinstance(y, bool) or isinstance(x, str) or isinstance(y, str) \
                    or x is None or y is None:
                if x != y:
                    return False, f"{k}: {x!r} -> {y!r}"
                continue
            if not (math.isfinite(x) and math.isfinite(y)):
                if not (x == y or (math.isnan(x) and math.isnan(y))):
                    return False, f"{k}: {x!r} -> {y!r}"
                continue
            d = math.fabs(x - y)
            bound = abs + rel * math.fabs(x)
            if d > bound:
                return False, f"{k}: {x:.6g} -> {y:.6g} (moved {d:.2g}, allowed {bound:.2g})"
            if d > worst:
                worst, where = d, k
        return True, ("identical" if where is None else f"largest move {worst:.2g} at {where}")
    return check


def within_sigma(k, pairs):
    """Check for statistical values: each (value key, error key) in ``pairs`` moves by
    at most ``k`` combined standard errors (old and new)."""
    def check(old, new):
        worst, text = 0.0, "identical"
        for vk, ek in pairs:
            a, b = _leaves(old)[vk], _leaves(new)[vk]
            ea, eb = _leaves(old)[ek], _leaves(new)[ek]
            s = math.hypot(ea, eb)
            d = math.fabs(a - b) / s if s > 0 else (0.0 if a == b else math.inf)
            if d > k:
                return False, f"{vk}: {a:.4g} -> {b:.4g} ({d:.1f} combined sigma > {k})"
            if d > worst:
                worst, text = d, f"largest move {d:.2f} combined sigma ({vk})"
        return True, text
    return check


def judged_afresh(then, now, what):
    """The check of a claim read from a store that long runs grow (a segmented member, an
    ensemble's pieces), when the scale reached differs (``then`` != ``now``, ``what`` says
    how): the regenerated numbers are new ones, judged afresh by the claim's verdict, not a
    reproduction of the recorded ones.  None when the store is the one recorded (the claim's
    own comparison applies)."""
    if then == now:
        return None
    return True, f"the store reached further ({what}): new numbers, judged afresh"


# ------------------------------------------------------------ verdicts against the paper

def half_unit(printed):
    """Half a unit of the last digit of a number as printed ('0.00024' -> 5e-6): the
    standard error given to a value a paper prints without one."""
    s = printed.lower().split("e")[0]
    decimals = len(s.split(".")[1]) if "." in s else 0
    exp = int(printed.lower().split("e")[1]) if "e" in printed.lower() else 0
    return 0.5 * 10.0 ** (exp - decimals)


def sigma_distance(ours, ours_err, paper, paper_err):
    """|ours - paper| in combined standard errors."""
    s = math.hypot(ours_err, paper_err)
    return math.fabs(ours - paper) / s if s > 0 else (0.0 if ours == paper else math.inf)


#: a statistical verdict is undecided where a new sample of ours would flip it with at least
#: this probability
FLIP = 0.25


def sigma_verdict(items, k=2.0):
    """Verdict over (ours, ours_err, paper, paper_err) items: agrees where every
    distance is at most ``k`` combined standard errors, disagrees where one is beyond.

    A distance is itself uncertain: a new set of realizations moves ours by about
    ``ours_err``, so the distance ``d`` by ``m = ours_err / combined`` (0 for a value of
    ours without sampling error).  Where a new sample would flip the label with probability
    ``FLIP`` or more (normal: ``|d - k| < z m``, ``z`` = 0.67 for 1/4) on an item that
    decides it, the verdict is **undecided**: more realizations, not the rounding of one
    machine, must decide it."""
    z = statistics.NormalDist().inv_cdf(1.0 - FLIP)
    d = [sigma_distance(*it) for it in items]
    m = [z * _spread(*it) for it in items]
    if all(x + e <= k for x, e in zip(d, m)):
        label = "agrees"
    elif any(x - e > k for x, e in zip(d, m)):
        label = "disagrees"
    else:
        label = "undecided"
    text = " / ".join(f"{x:.1f}" for x in d) + f" combined sigma; agree if <= {k:g}"
    if label == "undecided":
        text += (f"; undecided: a new sample flips it with probability >= {FLIP:g} (within "
                 + " / ".join(f"{e:.1f}" for e in m) + f" of {k:g})")
    return Verdict(label, text)


def _spread(ours, ours_err, paper, paper_err):
    """The standard deviation of a distance over new samples of ours: ours_err / combined."""
    s = math.hypot(ours_err, paper_err)
    return ours_err / s if s > 0 else 0.0


def rel_verdict(ours, paper, tol):
    """Verdict: |ours / paper - 1| <= tol."""
    r = math.fabs(ours / paper - 1.0)
    return Verdict("agrees" if r <= tol else "disagrees", f"relative {r:.2g}; agree if <= {tol:g}")


def bound_verdict(value, bound, what="error"):
    """Verdict for a bound we set ourselves (an error model, an issue's floor): value <= bound."""
    return Verdict("meets" if value <= bound else "fails", f"{what} {value:.2g} <= {bound:g}"
                   if value <= bound else f"{what} {value:.2g} > {bound:g}")


def floor_verdict(value, floor, what="value"):
    """Verdict for a floor: value >= floor."""
    return Verdict("meets" if value >= floor else "fails",
                   f"{what} {value:.3g} {'>=' if value >= floor else '<'} {floor:g}")


def exact_verdict(ours, paper, what=""):
    """Verdict: equal (counts, booleans, yes/no lists)."""
    return Verdict("agrees" if ours == paper else "disagrees",
                   (what + ": " if what else "") + ("equal" if ours == paper
                                                    else f"ours {ours!r}, paper {paper!r}"))
