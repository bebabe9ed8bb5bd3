"""Lee & Hurley Sec. 3.3: the comparisons the paper makes on Figs. 9b-10b of its mu_s = 0.7
run (its band statements are ``shear_paper.STATEMENTS``), each judged on one run's Spearman
tables by the rules of :mod:`shear_sec4` (cells with p <= 0.05 and n >= 10; "stronger" by
Fisher's z of |rho|, a pair holding where |rho_1| >= |rho_2|, significantly weaker at
d < -2).  Written out by ``validation/shear_paper.py``.
"""

from shear_sec4 import SLIP_BINS, Z_WEAKER, _cell, _text, fisher_d, stronger

FOUR = ("mg", "mg10", "sg", "sg10")
SLIPS_33 = (-1e-1, -1e-2, -1e-3)            # -1e-1 < Delta tau_p < -1e-4 (Sec. 3.3)


def significantly_weaker(tables, pairs):
    """Pairs as :func:`shear_sec4.stronger`, the claim reversed: the first significantly
    weaker than the second (d < -2) in more than half of the pairs that enter; disagrees where
    more than half are not weaker at all (|rho_1| >= |rho_2|), else undecided."""
    weaker, held, texts = 0, 0, []
    for (t1, s1), (t2, s2), lo in pairs:
        a, b = _cell(tables, t1, s1, lo), _cell(tables, t2, s2, lo)
        if a is None or b is None:
            continue
        d = fisher_d(a, b)
        weaker += d < -Z_WEAKER
        held += abs(a["rho"]) >= abs(b["rho"])
        texts.append(f"[{lo:.0e}) {t1} {s1} {_text(a)} vs {t2} {_text(b)}: d = {d:+.1f}")
    n = len(texts)
    if not n:
        return "not comparable", "no pair of significant cells"
    verdict = ("agrees" if weaker > n / 2 else "disagrees" if held > n / 2 else "undecided")
    return verdict, f"{weaker} of {n} significantly weaker, {held} not weaker; " + "; ".join(texts)


#: (id, figure, the paper's words, judge(tables) -> (verdict, detail))
STATEMENTS = [
    ("3.1", "9b, 10a",
     "slips: long phases stronger than all phases, particularly for -1e-1 < Delta tau_p < "
     "-1e-4 (mg, mg_t10%, sg, sg_t10%)",
     lambda t: stronger(t, [(("phase_long", s), ("phase_all", s), lo)
                            for s in FOUR for lo in SLIPS_33], "mostly")),
    ("3.2", "10a", "slips, long phases: mg_t10% and sg_t10% stronger than mg and sg",
     lambda t: stronger(t, [(("phase_long", f"{s}10"), ("phase_long", s), lo)
                            for s in ("mg", "sg") for lo in SLIP_BINS], "mostly")),
    ("3.3", "10a", "slips, long phases: sg_t10% stronger than mg_t10%",
     lambda t: stronger(t, [(("phase_long", "sg10"), ("phase_long", "mg10"), lo)
                            for lo in SLIP_BINS], "mostly")),
    ("3.4", "10a-b",
     "short phases significantly weaker than long phases for -1e-1 < Delta tau_p < -1e-4 "
     "(mg, mg_t10%, sg, sg_t10%)",
     lambda t: significantly_weaker(t, [(("phase_short", s), ("phase_long", s), lo)
                                        for s in FOUR for lo in SLIPS_33])),
]


def judge(tables):
    """Every statement on one run's ``tables``: a list of dicts (id, figure, paper, verdict,
    detail)."""
    return [{"id": sid, "figure": fig, "paper": words,
             **dict(zip(("verdict", "detail"), rule(tables)))}
            for sid, fig, words, rule in STATEMENTS]


def markdown(judged):
    """One row per statement."""
    return "\n".join(["| # | Fig. | paper | verdict | ours |", "|---|---|---|---|---|"]
                     + [f"| {x['id']} | {x['figure']} | {x['paper']} | **{x['verdict']}** | "
                        f"{x['detail']} |" for x in judged])
