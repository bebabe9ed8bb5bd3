"""Lee & Hurley Sec. 4 (Figs. 12-13): the paper's statements on the friction sweep, each judged
per mu_s from the Spearman tables of :func:`fricstab.analysis.shear.analyze`.

The paper draws |rho| per bin of Delta tau or Delta tau_p (Fig. 13 a-j, one symbol per mu_s)
and states in words what the panels show, "for all mu_s values".  Each statement is a rule on
our cells; a cell enters only where p <= 0.05 (the paper omits the others) and n >= 10.

Bands (as ``shear_paper.py``): |rho| < 0.4 weak, 0.4-0.7 moderate, >= 0.7 strong.

"Stronger" compares two coefficients by Fisher's z of |rho|:
d = (atanh|rho_1| - atanh|rho_2|) / sqrt(1.06/(n_1 - 3) + 1.06/(n_2 - 3)) (Fieller, Hartley &
Pearson's variance of Spearman's z).  A pair of bins *holds* where |rho_1| >= |rho_2| and is
*significantly weaker* where d < -2.  Two coefficients of the same phases (long-phase mg10 and
mg, say) are positively correlated, so the independent-sample variance overstates that of d: the
test of "significantly weaker" is conservative there (it rejects less often than 5 %).

Verdicts per mu_s: ``agrees``, ``disagrees``, ``undecided`` (weaker in most bins, none
significantly), ``not comparable`` (no cell, or no pair of cells, that enters); a statement
agrees overall where it agrees at every mu_s ("for all mu_s values"), disagrees where it
disagrees at one, and is otherwise undecided or not comparable.
"""

import math

SLIP_BINS = (-1e-1, -1e-2, -1e-3, -1e-4)     # lo of the bins with Delta tau_p < 0
MIN_N = 10
Z_WEAKER = 2.0


def _band(rho):
    a = abs(rho)
    return "weak" if a < 0.4 else "moderate" if a < 0.7 else "strong"


def _cell(tables, table, series, lo):
    """The cell of ``table`` / ``series`` whose bin starts at ``lo``, or None where it does
    not enter (absent, n/a, p > 0.05, n < MIN_N)."""
    for c in tables[table][series]:
        if c["lo"] == lo:
            ok = c["rho"] is not None and c["significant"] and c["n"] >= MIN_N
            return c if ok else None
    return None


def fisher_d(a, b):
    """(atanh|rho_a| - atanh|rho_b|) over its standard error (module docstring)."""
    z = [math.atanh(min(abs(c["rho"]), 0.999999)) for c in (a, b)]
    return (z[0] - z[1]) / math.sqrt(1.06 / (a["n"] - 3) + 1.06 / (b["n"] - 3))


def _text(c):
    return f"{c['rho']:+.2f} (n = {c['n']})"


def stronger(tables, pairs, rule):
    """Pairs ((table, series), (table, series), lo): the first stronger than the second.
    ``rule``: 'mostly' (more than half of the pairs hold), 'consistently' (every pair holds),
    'not weaker' (no pair significantly weaker: "almost equal to or stronger")."""
    held, weaker, texts = 0, 0, []
    n = 0
    for (t1, s1), (t2, s2), lo in pairs:
        a, b = _cell(tables, t1, s1, lo), _cell(tables, t2, s2, lo)
        if a is None or b is None:
            continue
        n += 1
        d = fisher_d(a, b)
        held += abs(a["rho"]) >= abs(b["rho"])
        weaker += d < -Z_WEAKER
        texts.append(f"[{lo:.0e}) {s1} {_text(a)} vs {s2} {_text(b)}: d = {d:+.1f}")
    if not n:
        return "not comparable", "no pair of significant cells"
    if rule == "not weaker":
        ok = weaker == 0
    elif rule == "consistently":
        ok = held == n
    else:
        ok = held > n / 2
    verdict = ("agrees" if ok else "disagrees" if weaker or rule == "not weaker"
               else "undecided")
    return verdict, f"{held} of {n} hold, {weaker} significantly weaker; " + "; ".join(texts)


def bands(tables, cells, want, rule):
    """Cells (table, series, lo) in the bands ``want``: ``rule`` 'all' (every cell that
    enters) or 'mostly' (more than half of them)."""
    got = []
    for t, s, lo in cells:
        c = _cell(tables, t, s, lo)
        if c is not None:
            got.append((s, lo, c))
    if not got:
        return "not comparable", "no significant cell"
    inside = sum(_band(c["rho"]) in want for _, _, c in got)
    ok = inside == len(got) if rule == "all" else inside > len(got) / 2
    text = "; ".join(f"{s} [{lo:.0e}) {_text(c)} {_band(c['rho'])}" for s, lo, c in got)
    return ("agrees" if ok else "disagrees"), f"{inside} of {len(got)} in band; {text}"


def stick_tp(tables, mu_s):
    """Fig. 13j: at mu_s >= 0.5 the significant long-phase cells of Delta tau_p - t_p in the
    bins from 1e-3 and 1e-2 are moderate (one at least); below, every one that is significant
    is weak (none significant: agrees, "weak or p > 0.05")."""
    cells = [("phase_tp", "long", lo) for lo in (1e-3, 1e-2)]
    if mu_s >= 0.5:
        return bands(tables, cells, {"moderate"}, "all")
    if not any(_cell(tables, *c) for c in cells):
        return "agrees", "no significant cell: weak or p > 0.05, as the paper says"
    return bands(tables, cells, {"weak"}, "all")


#: (id, panels, the paper's words, judge(tables, mu_s) -> (verdict, detail))
STATEMENTS = [
    ("4.1", "13a, b, f",
     "slips: all-phase correlations of Delta tau_p with mg_t10% and sg_t10% mostly stronger "
     "than the per-step one of Delta tau with g_t10% for -1e-1 < Delta tau < -1e-3",
     lambda t, m: stronger(t, [(("phase_all", s), ("step_dtau", "g10"), lo)
                               for s in ("mg10", "sg10") for lo in (-1e-1, -1e-2)], "mostly")),
    ("4.2", "13b-c, f-g",
     "slips: long phases mostly more highly correlated than all phases (mg_t10%, sg_t10%)",
     lambda t, m: stronger(t, [(("phase_long", s), ("phase_all", s), lo)
                               for s in ("mg10", "sg10") for lo in SLIP_BINS], "mostly")),
    ("4.3", "13c, g", "long phases: strong for Delta tau_p < -1e-2 (mg_t10%, sg_t10%)",
     lambda t, m: bands(t, [("phase_long", s, -1e-1) for s in ("mg10", "sg10")],
                        {"strong"}, "all")),
    ("4.4", "13c, g", "long phases: mostly moderate for -1e-2 < Delta tau_p < 0",
     lambda t, m: bands(t, [("phase_long", s, lo) for s in ("mg10", "sg10")
                            for lo in SLIP_BINS[1:]], {"moderate"}, "mostly")),
    ("4.5", "13d, h", "short phases: not strongly correlated in any bin (mg_t10%, sg_t10%)",
     lambda t, m: bands(t, [("phase_short", s, lo) for s in ("mg10", "sg10")
                            for lo in (*SLIP_BINS, 0.0, 1e-4, 1e-3, 1e-2)],
                        {"weak", "moderate"}, "all")),
    ("4.6", "13c, e, g, i",
     "slips, long phases: mg_t10% and sg_t10% consistently stronger than mg and sg",
     lambda t, m: stronger(t, [(("phase_long", f"{s}10"), ("phase_long", s), lo)
                               for s in ("mg", "sg") for lo in SLIP_BINS], "consistently")),
    ("4.7", "13c, g",
     "slips, long phases: sg_t10% almost equal to or stronger than mg_t10%",
     lambda t, m: stronger(t, [(("phase_long", "sg10"), ("phase_long", "mg10"), lo)
                               for lo in SLIP_BINS], "not weaker")),
    ("4.8", "13j",
     "long stick phases, 1e-3 < Delta tau_p < 1e-1: Delta tau_p - t_p moderate at mu_s = 0.5, "
     "0.7; weak or p > 0.05 at 0.1, 0.3", lambda t, m: stick_tp(t, m)),
]


def judge_sweep(tables_by_mu):
    """Every statement of :data:`STATEMENTS` per mu_s.  ``tables_by_mu``: {mu_s (float):
    the ``tables`` of an analysis}.  Returns a list of dicts (id, panels, paper, cells:
    {mu_s: {verdict, detail}}, verdict: the overall one, module docstring)."""
    out = []
    for sid, panels, words, rule in STATEMENTS:
        cells = {m: dict(zip(("verdict", "detail"), rule(t, m)))
                 for m, t in sorted(tables_by_mu.items())}
        v = [c["verdict"] for c in cells.values()]
        overall = ("agrees" if all(x == "agrees" for x in v) else
                   "disagrees" if "disagrees" in v else
                   "undecided" if "undecided" in v else "not comparable")
        out.append({"id": sid, "panels": panels, "paper": words, "cells": cells,
                    "verdict": overall})
    return out


def markdown(judged):
    """The statements table: one row per statement, one column per mu_s."""
    mus = list(judged[0]["cells"]) if judged else []
    lines = ["| # | Fig. | paper (for all mu_s) | " + " | ".join(f"mu_s = {m:g}" for m in mus)
             + " | verdict |", "|---|---|---|" + "---|" * len(mus) + "---|"]
    for s in judged:
        lines.append(f"| {s['id']} | {s['panels']} | {s['paper']} | "
                     + " | ".join(s["cells"][m]["verdict"] for m in mus)
                     + f" | **{s['verdict']}** |")
    return "\n".join(lines)
