"""Claims of section precursors (see claims/__init__.py): issue 36, the ranked test of
whether a candidate precursor is extreme at the onset of a stress drop of quasistatic shear."""

import math

from .aqs import _aqs_study, _checkout
from .core import Claim, Result

HEADING = "Precursors of stress drops: the ranked test, its sizes, sheared dynamics"
INTRO = ("`validation/precursor_study.py` (how-to: docs/howto/aqs.md, \"The ranked test\"): "
         "AQS with history of the phi = 0.90 backbone to strain 0.2 in steps of 5e-4; per drop, "
         "the normalised mid-rank of each candidate at the onset among the +-25 states around "
         "it; the mean rank against a permutation null (999 permutations, +1 corrected, exact "
         "in level) and the test's power at preceded fractions 0.5 and 0.8 by simulation (400 "
         "replicates, alpha = 0.05), beside the power of the old birth-window tests. "
         "`validation/precursor_dynamics.py` (how-to: \"Sheared dynamics\"): Newtonian shear "
         "of the N = 64 backbones by a Lees-Edwards offset at 1e-6 to 1e-3 t0^-1, no damping; "
         "the non-affine kinetic energy's growth against 2 g of the quasistatic states on the "
         "dynamic path.")

RANKED_COMMAND = ("python validation/precursor_study.py --sizes 64 --seeds 4 "
                  "--prefix precursor_study_n64 --cache validation/runs/precursors --resume "
                  "(strain 0.2, dgamma 5e-4)")
RANKED_LAWS = {"charan": "charan mu=0.1 kt=1", "ishima": "ishima kt=1", "hertz": "hertz"}


def ranked_run():
    """The ranked test at N = 64 (4 seeds, three laws; RANKED_COMMAND), its runs from the
    persistent cache of :func:`scale_run` where this code made them (the runs are shared)."""
    from fricstab.io.files import json_clean      # NaN (no ranked drop) -> None
    doc = _aqs_study("precursor_study").run(
        ["--sizes", "64", "--seeds", "4", "--prefix", "precursor_study_n64",
         "--cache", str(_checkout() / SCALE_CACHE), "--resume",
         "--out", str(_checkout() / "validation")])
    out = ("validation/precursor_study_n64" + x for x in (".md", ".json", ".png"))
    return Result(json_clean(_law_rows(doc)), seeds=(0, 1, 2, 3), outputs=tuple(out),
                  units=doc["units"])


KEEP = ("statistic", "null_sd", "pvalue", "drops", "power_0.5", "power_0.8", "sizes_pvalue")
#: the old 1-step birth-window test (issue 17): drops tested, preceded, p, power at f = 0.8,
#: and its null fraction p0 (0: no pair was ever born on the law's paths)
OLD = ("window1_tested", "window1_preceded", "window1_pvalue", "window1_power_0.8", "window1_p0")


def _row(r):
    """What a claim records of a study row: its drops, the old test and, per candidate, the
    ranked test's numbers."""
    return {"drops": r["drops"], **{k: r[k] for k in OLD},
            "candidates": {c: {k: t[k] for k in KEEP if k in t}
                           for c, t in r["candidates"].items()}}


def _law_rows(doc):
    """Per law of a study's document: :func:`_row` (what the ranked and frame-indifferent
    claims record)."""
    return {r["law"]: _row(r) for r in doc["rows"]}


def _no_birth(r):
    """No pair born on the row's paths (hertz): the old test has nothing to test."""
    return r.get("window1_p0") == 0 and r["window1_preceded"] == 0


def _old(r, cell=False):
    """The old 1-step test of a recorded row: a sentence, or (``cell``) a table cell."""
    t = r["window1_tested"]
    if _no_birth(r):
        return "no pair born" if cell else f"no pair born ({t} drops)"
    got, p, pw = r["window1_preceded"], r["window1_pvalue"], r["window1_power_0.8"]
    return (f"{got}/{t}, p {p:.2g}, power {pw:.2f}" if cell else
            f"{got}/{t} drops preceded (p {p:.2g}; power {pw:.2f} at f = 0.8)")


def _ranked_show(v, label):
    r = v[label]
    pw = lambda x: "-" if x is None else f"{x:.2f}"     # noqa: E731 (None: constant series)
    return "; ".join(f"{c} {t['statistic']:.2f} (p {t['pvalue']:.2g}, power "
                     f"{pw(t['power_0.5'])} / {pw(t['power_0.8'])})" if t["statistic"]
                     is not None else f"{c}: no ranked drop"
                     for c, t in r["candidates"].items()) + (f"; {r['drops']} drops; old 1-step "
                                                             f"test: {_old(r)}")


def _check_ranked(a, b):
    """Each mean rank within 3 combined null sd (its sampling error under the null); each
    power within 4 combined binomial errors of its 400 replicates (+ 0.05 for a drop
    count that another CPU's rounding moves); an undefined rank stays undefined; the old
    test's preceded fraction within 3 combined binomial errors (at least 1/drops each)."""
    worst = (0.0, "identical")
    for law, x in a.items():
        y = b.get(law, {})
        if "window1_tested" in x:
            fa, fb = (z["window1_preceded"] / max(z["window1_tested"], 1) for z in (x, y))
            e = 3 * math.hypot(*(max(math.sqrt(f * (1 - f) / max(z["window1_tested"], 1)),
                                     1 / max(z["window1_tested"], 1))
                                 for f, z in ((fa, x), (fb, y))))
            if abs(fa - fb) > e:
                return False, f"{law} old test: {fa:.2f} -> {fb:.2f} preceded"
        for c, t in x["candidates"].items():
            u = b.get(law, {}).get("candidates", {}).get(c)
            if u is None or (t["statistic"] is None) != (u["statistic"] is None):
                return False, f"{law} {c}: {t['statistic']} -> {u and u['statistic']}"
            if t["statistic"] is None:
                continue
            s = math.hypot(t["null_sd"], u["null_sd"]) or 1e-12
            d = abs(t["statistic"] - u["statistic"]) / s
            if d > 3:
                return False, f"{law} {c}: {t['statistic']:.3f} -> {u['statistic']:.3f}"
            for f in ("power_0.5", "power_0.8"):
                x, y = (-1.0 if p is None else p for p in (t[f], u[f]))  # None: constant
                e = 4 * math.sqrt(max(x * (1 - x) + y * (1 - y), 1e-3) / 400)
                if abs(x - y) > e + 0.05:
                    return False, f"{law} {c} {f}: {t[f]} -> {u[f]}"
            worst = max(worst, (d, f"largest move {d:.2f} null sd ({law} {c})"), key=lambda w: w[0])
    return True, worst[1]


CANDIDATES = ("n_pairs", "growth", "min_real", "pair_min_imag")


def ranked_table(v):
    """The mean onset rank, p and power at f = 0.5 per law and candidate (N = 64)."""
    lines = ["| law | drops | " + " | ".join(CANDIDATES)
             + " | old 1-step test: preceded, p, power f = 0.8 |",
             "|---|---|" + "---|" * len(CANDIDATES) + "---|"]
    for label in RANKED_LAWS.values():
        r = v[label]
        lines.append(f"| {label} | {r['drops']} | "
                     + " | ".join(_cell(r["candidates"][c]) for c in CANDIDATES) + " | "
                     + _old(r, cell=True) + " |")
    return "\n\n" + "\n".join(lines) + "\n\n"


def _cell(t):
    """One candidate's mean onset rank, p and power at f = 0.5 (a table cell)."""
    return ("no pair" if t["statistic"] is None else
            f"{t['statistic']:.2f}, p {t['pvalue']:.2g}, power "
            + ("-" if t["power_0.5"] is None else f"{t['power_0.5']:.2f}"))


def _p(v, label, c):
    return v[label]["candidates"][c]["pvalue"]


def ranked_sentence(v):
    """The answer per law, computed at alpha = 0.05 (the README's words)."""
    out = []
    for law, label in RANKED_LAWS.items():
        yes = [c for c in CANDIDATES if v[label]["candidates"][c]["statistic"] is not None
               and _p(v, label, c) <= 0.05]
        out.append(f"{law}: " + (", ".join(f"{c} (p {_p(v, label, c):.2g})" for c in yes)
                                 if yes else "none"))
    return "; ".join(out)


def old_sentence(v):
    """The old 1-step birth-window test per law (issue 17's answer), with its power."""
    return "; ".join(f"{law}: {_old(v[label])}" for law, label in RANKED_LAWS.items())


SCALE_SIZES = (64, 128, 256, 512, 1024)
SCALE_SEEDS = (4, 2, 2, 2, 1)
SCALE_CACHE = "validation/runs/precursors"
SCALE_COMMAND = ("python validation/precursor_study.py --sizes "
                 + " ".join(map(str, SCALE_SIZES)) + " --seeds " + " ".join(map(str, SCALE_SEEDS))
                 + f" --cache {SCALE_CACHE} --resume (strain 0.2, dgamma 5e-4; "
                 "tens of core-hours, the table's core-h column; add --budget-only for the "
                 "projection; resumable: every run and checkpoint is stamped with the code it "
                 "executed and reused only while that code is unchanged)")


def scale_run():
    """The ranked test at N = 64 to 1,024 (SCALE_COMMAND), in the persistent cache: an
    interrupted job resumes where it stopped, with runs of unchanged executed code only."""
    from fricstab.io.files import json_clean
    study = _aqs_study("precursor_study")
    doc = study.run(["--sizes", *map(str, SCALE_SIZES), "--seeds", *map(str, SCALE_SEEDS),
                     "--cache", str(_checkout() / SCALE_CACHE), "--resume",
                     "--out", str(_checkout() / "validation")])
    rows = {f"{r['law']} N={r['n']}": {"law": r["law"], "n": r["n"], "runs": r["runs"],
                                       "hours": r["seconds"] / 3600, **_row(r)}
            for r in doc["rows"]}
    out = ("validation/precursor_study" + x for x in (".md", ".json", ".png"))
    return Result(json_clean(rows), seeds=tuple(range(max(SCALE_SEEDS))), outputs=tuple(out),
                  units=doc["units"])


def _scale_show(v, label):
    """Per N: the candidates extreme at the onsets at alpha = 0.05, and the drops."""
    parts = []
    for r in _law_sizes(v, label):
        yes = [f"{c} {t['statistic']:.2f} (p {t['pvalue']:.2g})"
               for c, t in r["candidates"].items()
               if t["statistic"] is not None and t["pvalue"] <= 0.05]
        parts.append(f"{_size(r)} ({r['drops']} drops): " + (", ".join(yes) or "none"))
    head = law_headline(v, label)
    return (f"{head}. Per N at p <= 0.05: " if head else "") + "; ".join(parts)


def _law_sizes(v, label):
    """A law's rows by increasing N, its pooled row (N = 'all') last (a record's rows are in
    the order of their keys, '1024' before '64')."""
    return sorted((r for r in v.values() if r["law"] == label),
                  key=lambda r: (r["n"] == "all", 0 if r["n"] == "all" else r["n"]))


def scale_table(v):
    """Mean onset rank, p, power at f = 0.5 per law, N and candidate; the old 1-step test;
    the compute of the runs (core-hours, summed over sittings)."""
    lines = ["| law | N | runs | core-h | drops | " + " | ".join(CANDIDATES)
             + " | old 1-step test: preceded, p, power f = 0.8 |",
             "|---|---|---|---|---|" + "---|" * (len(CANDIDATES) + 1)]
    for r in (r for label in RANKED_LAWS.values() for r in _law_sizes(v, label)):
        lines.append(f"| {r['law']} | {r['n']} | {r['runs']} | {r['hours']:.2g} | {r['drops']} | "
                     + " | ".join(_cell(r["candidates"][c]) for c in CANDIDATES) + " | "
                     + _old(r, cell=True) + " |")
    return "\n\n" + "\n".join(lines) + "\n\n"


def _runs(n):
    return f"{n} run" + ("" if n == 1 else "s")


def _size(r):
    """'N = 512', or 'all N pooled' for a law's pooled row (precursor_study.POOLED)."""
    return "all N pooled" if r["n"] == "all" else f"N = {r['n']}"


def _sizes(t):
    """For a pooled row's candidate: whether its sizes' onset ranks differ (Kruskal-Wallis)."""
    p = t.get("sizes_pvalue")
    return "" if p is None else f"; sizes differ p {p:.2g}"


def scale_answer(v):
    """The answer per law and size, computed at alpha = 0.05: the candidates extreme at the
    onsets (p; starred where p <= 0.05 / 4, Bonferroni over the four candidates of a row;
    on the pooled row, the Kruskal-Wallis p that its sizes' ranks differ),
    and for a size where the pair count or growth rate is not, the power that test had at a
    preceded fraction of 0.5 (what its 'no' can exclude); the law's pooled row last."""
    out = []
    for label in RANKED_LAWS.values():
        parts = []
        for r in _law_sizes(v, label):
            c = r["candidates"]
            yes = [f"{k} (p {c[k]['pvalue']:.2g}{'*' if c[k]['pvalue'] <= 0.05 / 4 else ''}"
                   + _sizes(c[k]) + ")" for k in CANDIDATES
                   if c[k]["statistic"] is not None and c[k]["pvalue"] <= 0.05]
            miss = [f"{k} power {c[k]['power_0.5']:.2f}" for k in ("n_pairs", "growth")
                    if c[k]["statistic"] is not None and c[k]["pvalue"] > 0.05
                    and c[k]["power_0.5"] is not None]
            parts.append(f"{_size(r)} ({_runs(r['runs'])}, {r['drops']} drops): "
                         + (", ".join(yes) or "none")
                         + (f" [not: {', '.join(miss)} at f = 0.5]" if miss else ""))
        out.append(f"{label.split()[0]}: " + "; ".join(parts))
    return ". ".join(out)


def _significant_sizes(v, label, cand):
    """The sizes (per-size rows of a law) where ``cand`` is extreme at alpha = 0.05."""
    return [r["n"] for r in _law_sizes(v, label) if r["n"] != "all"
            and r["candidates"][cand]["pvalue"] is not None
            and r["candidates"][cand]["pvalue"] <= 0.05]


def law_headline(v, label):
    """One law's headline from its pooled row (every drop of every size; None without one):
    per candidate **precedes** where the pooled p <= 0.05 / 4 and the sizes' onset ranks do
    not differ (Kruskal-Wallis p > 0.05); **size-dependent** where they differ (the sizes
    where it is extreme named); **not seen** where the pooled p > 0.05, with the pooled test's
    power at a preceded fraction of 0.5 (what its 'no' excludes); **weak** between.  A
    candidate without a rank on any drop is left out; one the same at every state (hertz's
    pair count: no power) is named untestable."""
    pool = next((r for r in v.values() if r["law"] == label and r["n"] == "all"), None)
    if pool is None:
        return None
    words = []
    for k in CANDIDATES:
        t = pool["candidates"][k]
        if t["statistic"] is None:
            continue
        p, sp = t["pvalue"], t.get("sizes_pvalue")
        at = f"rank {t['statistic']:.2f}, p {p:.2g}"
        if sp is not None and sp <= 0.05:
            sizes = _significant_sizes(v, label, k)
            words.append(f"{k} size-dependent ({at}; sizes differ p {sp:.2g}; extreme at "
                         + (f"N = {', '.join(map(str, sizes))}" if sizes else "no single N")
                         + ")")
        elif p <= 0.05 / 4:
            words.append(f"{k} precedes ({at}; sizes agree p "
                         + ("-" if sp is None else f"{sp:.2g}") + ")")
        elif p <= 0.05:
            words.append(f"{k} weak ({at}: not at 0.05 / 4)")
        elif t["power_0.5"] is None:
            words.append(f"{k} untestable (the same at every state: no power)")
        else:
            words.append(f"{k} not seen ({at}; power {t['power_0.5']:.2f} against a preceded "
                         "fraction of 0.5)")
    return (f"{label.split()[0]} ({pool['drops']} drops, {_runs(pool['runs'])}): "
            + "; ".join(words))


def scale_headline(v):
    """Every law's :func:`law_headline` (laws run at one size only are left out)."""
    return ". ".join(h for h in (law_headline(v, label) for label in RANKED_LAWS.values())
                     if h is not None)


CLAIMS = [Claim(f"precursors.scale_{law}", "precursors",
                f"{law}: ranked test at N = 64 to 1,024 ({', '.join(map(str, SCALE_SEEDS))} seeds): "
                "per N the "
                "candidates whose onset rank is extreme at alpha = 0.05", "hours",
                SCALE_COMMAND, scale_run, show=lambda v, label=label: _scale_show(v, label),
                tolerance=" ".join(_check_ranked.__doc__.split()), check=_check_ranked,
                job="precursors.scale",
                texts={"table": scale_table, "answer": scale_answer,
                       "headline": scale_headline} if law == "charan"
                else {})
          for law, label in RANKED_LAWS.items()]

CLAIMS += [Claim(f"precursors.ranked_{law}", "precursors",
                f"{law}: ranked test at N = 64 (4 seeds): mean onset rank in a +-25-state "
                "window of n_pairs, growth, min_real (high) and pair_min_imag (low), "
                "permutation p, power at preceded fractions 0.5 / 0.8", "minutes",
                RANKED_COMMAND, ranked_run, show=lambda v, label=label: _ranked_show(v, label),
                tolerance=" ".join(_check_ranked.__doc__.split()), check=_check_ranked,
                job="precursors.ranked",
                texts={"table": ranked_table, "answer": ranked_sentence,
                       "old": old_sentence} if law == "charan"
                else {})
          for law, label in RANKED_LAWS.items()]


# ------------------------------------------------------------ item 3: frame-indifferent

FI_COMMAND = ("python validation/precursor_fi.py --cache validation/runs/precursors "
              "(N = 64, 4 seeds; ishima, charan beside ishima_fi, charan_fi)")
FI_LAWS = {"ishima": ("ishima kt=1", "ishima_fi kt=1"),
           "charan": ("charan mu=0.1 kt=1", "charan_fi mu=0.1 kt=1")}


def fi_run():
    """The ranked test of each vector law beside its frame-indifferent form (FI_COMMAND),
    its runs from the persistent cache of :func:`scale_run`."""
    from fricstab.io.files import json_clean
    doc = _aqs_study("precursor_fi").main(["--cache", str(_checkout() / SCALE_CACHE),
                                           "--out", str(_checkout() / "validation")])
    out = ("validation/precursor_fi" + x for x in (".md", ".json"))
    return Result(json_clean(_law_rows(doc)), seeds=(0, 1, 2, 3), outputs=tuple(out),
                  units=doc["units"])


def fi_answer(v):
    """Per vector law: the candidates extreme at the onsets (p <= 0.05) with the lab-frame
    history and with the frame-indifferent one, and the drops of each."""
    out = []
    for law, labels in FI_LAWS.items():
        parts = []
        for label in labels:
            r = v[label]
            yes = [f"{c} (p {t['pvalue']:.2g})" for c, t in r["candidates"].items()
                   if t["statistic"] is not None and t["pvalue"] <= 0.05]
            parts.append(f"{label.split()[0]} ({r['drops']} drops): {', '.join(yes) or 'none'}")
        out.append(" against ".join(parts))
    return "; ".join(out)


CLAIMS += [Claim(f"precursors.fi_{law}", "precursors",
                 f"{law} against {law}_fi: ranked test at N = 64 (4 seeds), the candidates "
                 "extreme at the onsets with a lab-frame and a frame-indifferent history",
                 "minutes", FI_COMMAND, fi_run,
                 show=lambda v, labels=labels: "; ".join(_ranked_show(v, x) for x in labels),
                 tolerance=" ".join(_check_ranked.__doc__.split()), check=_check_ranked,
                 job="precursors.fi", texts={"answer": fi_answer} if law == "ishima" else {})
           for law, labels in FI_LAWS.items()]


# ------------------------------------------------------------ item 4: sheared dynamics

DYN_COMMAND = ("python validation/precursor_dynamics.py --cache DIR (N = 64, 2 seeds, rates "
               "1e-6 to 1e-3 t0^-1, strain 0.2, Newtonian, Lees-Edwards)")
#: a rate is slow enough for a pair to show when 2 g times one quasistatic interval is >= 1
#: e-fold of E_na (the rows' two_g_interval)
SLOW = 1.0


def dynamics_run():
    """The dynamics study in a fresh cache (DYN_COMMAND); per law and rate its row."""
    import tempfile

    from fricstab.io.files import json_clean
    doc = _aqs_study("precursor_dynamics").run(
        ["--cache", tempfile.mkdtemp(), "--out", str(_checkout() / "validation")])
    rise = {(lab, rate): (dyn, aqs) for lab, rate, dyn, aqs in doc["slopes"]}
    rows = {f"{r['law']} rate={r['rate']:g}": {
        **{k: r[k] for k in ("law", "rate", "runs", "drops", "pairs_fraction", "g_median",
                             "two_g_interval", "e_na_median", "episodes", "ratio_median",
                             "largest", "first_drop", "pre_measured", "pre_predicted")},
        "test": {k: r["test"][k] for k in ("statistic", "null_sd", "pvalue", "drops",
                                           "power_0.5")},
        "rise_dynamics": rise[(r["law"], r["rate"])][0],
        "rise_aqs": rise[(r["law"], r["rate"])][1]} for r in doc["rows"]}
    out = ("validation/precursor_dynamics" + x for x in (".md", ".json", ".png"))
    return Result(json_clean(rows), seeds=tuple(range(doc["seeds"])), outputs=tuple(out))


def _check_dynamics(a, b):
    """Deterministic on one machine; on another CPU the chaotic dynamics after the first
    instability moves: each row's drop count within 4 sqrt(drops) + 2 (Poisson), its mean
    onset rank within 3 combined null sd, each largest episode's e-folds within 30 % + 1 and
    r / 2g within 30 % (the first growth, before the trajectories part), the stress rise
    before any drop within 1e-6 relative (rounding)."""
    worst = (0.0, "identical")
    for key, x in a.items():
        y = b.get(key)
        if y is None:
            return False, f"{key}: missing"
        if abs(x["drops"] - y["drops"]) > 4 * math.sqrt(max(x["drops"], 1)) + 2:
            return False, f"{key}: drops {x['drops']} -> {y['drops']}"
        s, t = x["test"], y["test"]
        if (s["statistic"] is None) != (t["statistic"] is None):
            return False, f"{key}: rank {s['statistic']} -> {t['statistic']}"
        if s["statistic"] is not None:
            d = abs(s["statistic"] - t["statistic"]) / (math.hypot(s["null_sd"], t["null_sd"])
                                                       or 1e-12)
            if d > 3:
                return False, f"{key}: rank {s['statistic']:.3f} -> {t['statistic']:.3f}"
            worst = max(worst, (d, f"largest rank move {d:.2f} null sd ({key})"),
                        key=lambda w: w[0])
        for (e1, r1, _), (e2, r2, _) in zip(x["largest"], y["largest"]):
            if abs(e1 - e2) > 0.3 * abs(e1) + 1 or abs(r1 - r2) > 0.3 * abs(r1):
                return False, f"{key}: largest episode {e1:.2f} ({r1:.2f}) -> {e2:.2f} ({r2:.2f})"
        if abs(x["rise_dynamics"] - y["rise_dynamics"]) > 1e-6 * abs(x["rise_dynamics"]):
            return False, f"{key}: stress rise {x['rise_dynamics']} -> {y['rise_dynamics']}"
    return True, worst[1]


def _by_law_and_rate(v):
    """The rows in the order of RANKED_LAWS, by rate (the record's keys sort as text)."""
    order = list(RANKED_LAWS.values())
    return sorted(v.values(), key=lambda r: (order.index(r["law"]), r["rate"]))


def _dyn_show(v, label):
    """Per rate: drops, the largest growth episode and r / 2g, the ranked test."""
    parts = []
    for r in _by_law_and_rate(v):
        if r["law"] != label:
            continue
        big = max(r["largest"], default=None)
        t = r["test"]
        parts.append(f"rate {r['rate']:g}: {r['drops']} drops; largest growth "
                     + ("none" if big is None else f"{big[0]:.1f} e-folds (r / 2g {big[1]:.2f})")
                     + ("" if t["statistic"] is None else
                        f"; onset rank {t['statistic']:.2f} (p {t['pvalue']:.2g})"))
    return "; ".join(parts)


def dynamics_table(v):
    """Per law and rate: the growth of E_na against 2 g, before drops, the ranked test."""
    lines = ["| law | rate (t0^-1) | drops | states with a pair | 2 g x interval (e-folds) | "
             "largest growth per run: e-folds (r / 2g) | median E_na (k_N d^5/2) | first drop "
             "per run: strain, E_na e-folds before it (predicted) | onset rank of the growth, "
             "all drops (p, power f = 0.5) |", "|" + "---|" * 9]
    for r in _by_law_and_rate(v):
        t = r["test"]
        lines.append(
            f"| {r['law']} | {r['rate']:g} | {r['drops']} | {r['pairs_fraction']:.2f} | "
            f"{r['two_g_interval']:.3g} | "
            + (", ".join(f"{a:.1f} ({b:.2f})" for a, b, _ in r["largest"]) or "none") + " | "
            + f"{r['e_na_median']:.2g} | "
            + (", ".join(f"{g:.4f}: {_num(m)} ({_num(p)})" for g, m, p in r["first_drop"])
               or "none") + " | "
            + ("-" if t["statistic"] is None else
               f"{t['statistic']:.2f} (p {t['pvalue']:.2g}, "
               + ("-" if t["power_0.5"] is None else f"{t['power_0.5']:.2f}") + ")") + " |")
    return "\n\n" + "\n".join(lines) + "\n\n"


def dynamics_rise(v):
    """Per law: the stress rise over strain 0-0.005, dynamics / AQS, its range over rates."""
    out = []
    for law, label in RANKED_LAWS.items():
        q = [r["rise_dynamics"] / r["rise_aqs"] for r in _by_law_and_rate(v)
             if r["law"] == label]
        out.append(f"{law} {min(q):.3f}-{max(q):.3f}")
    return "; ".join(out)


def _num(x, spec="{:.1f}"):
    """A number of a record (None: not defined there) as text."""
    return "-" if x is None else spec.format(x)


def dynamics_answer(v, law):
    """The answer for one law, computed at the slow rates (2 g x interval >= SLOW): the largest
    growth of E_na per run and its rate against 2 g, where E_na settles, the growth before each
    run's first drop (measured, predicted), and the ranked test over all drops."""
    label = RANKED_LAWS[law]
    rows = sorted((r for r in v.values() if r["law"] == label), key=lambda r: r["rate"])
    slow = [r for r in rows if r["two_g_interval"] >= SLOW]
    if not slow:
        return (f"{law}: no quasistatic pair could grow by an e-fold of E_na in one interval "
                f"at any rate (median g {max(r['g_median'] for r in rows):.2g} t0^-1)"
                + "; before each run's first drop E_na grew by "
                + ", ".join(_num(m) for r in rows[:1] for _, m, _ in r["first_drop"])
                + f" e-folds at the slowest rate, {rows[0]['rate']:g} t0^-1")
    out = []
    for r in slow:
        big = ", ".join(f"{e:.1f} e-folds at {q:.2f} of 2 g" for e, q, _ in r["largest"])
        first = ", ".join(f"by {_num(m)} e-folds ({_num(p)} predicted) at strain {g:.4f}"
                          for g, m, p in r["first_drop"])
        t = r["test"]
        out.append(f"at rate {r['rate']:g} t0^-1 the largest growth of E_na per run is {big}; "
                   f"E_na then stays near {r['e_na_median']:.1g} k_N d^5/2; before each run's "
                   f"first drop it grew {first}; over all {r['drops']} drops the onset "
                   f"rank of that growth is {t['statistic']:.2f} (p {t['pvalue']:.2g}, power "
                   f"{t['power_0.5']:.2f} at f = 0.5)")
    return f"{law}: " + "; ".join(out)


def _dyn_claim(law):
    label = RANKED_LAWS[law]
    return Claim(f"precursors.dynamics_{law}", "precursors",
                 f"{law}: Newtonian shear at 1e-6 to 1e-3 t0^-1 (N = 64, 2 seeds): the "
                 "non-affine kinetic energy's growth against 2 g of the quasistatic states on "
                 "the dynamic path, before drops and at any time", "minutes", DYN_COMMAND,
                 dynamics_run, show=lambda v: _dyn_show(v, label),
                 tolerance=" ".join(_check_dynamics.__doc__.split()), check=_check_dynamics,
                 job="precursors.dynamics",
                 texts={"answer": lambda v: dynamics_answer(v, law), "rise": dynamics_rise,
                        **({"table": dynamics_table} if law == "charan" else {})})


CLAIMS += [_dyn_claim(law) for law in RANKED_LAWS]
