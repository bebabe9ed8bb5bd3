"""The computed answers of the precursor claims (claims.precursors): a candidate is named where
p <= 0.05, a pair-count or growth test that found nothing carries its power; the old
birth-window test's outcome as the study computes it and as the claims state and check it."""

import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

from claims.precursors import CANDIDATES, RANKED_LAWS, scale_answer, scale_headline  # noqa: E402


def _cand(p, power=0.9, none=False):
    return {"statistic": None if none else 0.7, "null_sd": 0.05, "pvalue": None if none else p,
            "drops": 10, "power_0.5": power, "power_0.8": 0.99}


def test_scale_answer():
    v = {}
    for law, label in RANKED_LAWS.items():
        for n in (64, 1024):
            sig = 0.001 if (law == "ishima" or n == 64) else 0.3
            v[f"{label} N={n}"] = {"law": label, "n": n, "runs": 1, "drops": 10, "hours": n / 512,
                                  "window1_tested": 10, "window1_preceded": 4,
                                  "window1_pvalue": 0.9, "window1_power_0.8": 0.7,
                                  "candidates": {c: _cand(sig if c != "pair_min_imag" else 0.5,
                                                          none=(law == "hertz"
                                                                and c == "n_pairs"))
                                                 for c in CANDIDATES}}
    text = scale_answer(v)
    charan, ishima, hertz = text.split(". ")
    assert charan.startswith("charan: N = 64") and "N = 1024 (1 run, 10 drops): none" in charan
    assert "[not: n_pairs power 0.90, growth power 0.90 at f = 0.5]" in charan
    assert "n_pairs (p 0.001*), growth (p 0.001*), min_real (p 0.001*)" in ishima
    assert "not:" not in ishima
    assert "n_pairs" not in hertz.split("N = 1024")[1]     # no pair: neither named nor 'not'
    assert text.index("N = 64") < text.index("N = 1024")
    # named at p <= 0.05, starred only at p <= 0.05 / 4 (Bonferroni over four candidates)
    v["ishima kt=1 N=64"]["candidates"]["pair_min_imag"]["pvalue"] = 0.03
    assert "pair_min_imag (p 0.03)" in scale_answer(v).split(". ")[1]
    # a pooled row (N = "all") is named last, whatever the order of the record
    pool = {**v["charan mu=0.1 kt=1 N=64"], "n": "all", "runs": 2, "drops": 20}
    pool["candidates"] = {c: dict(t, sizes_pvalue=0.42) for c, t in pool["candidates"].items()}
    charan = scale_answer({"pooled": pool, **v}).split(". ")[0]
    assert charan.index("N = 1024") < charan.index("all N pooled (2 runs, 20 drops)")
    assert "min_real (p 0.001*; sizes differ p 0.42)" in charan.split("pooled")[1]
    from claims.precursors import _scale_show, scale_table
    # a record's rows come back in key order ('... N=1024' before '... N=64'): shown by N
    back = dict(reversed(list(v.items())))
    assert _scale_show(back, "charan mu=0.1 kt=1").index("N = 64") \
        < _scale_show(back, "charan mu=0.1 kt=1").index("N = 1024")
    assert scale_table(back).index("| charan mu=0.1 kt=1 | 64 |") \
        < scale_table(back).index("| charan mu=0.1 kt=1 | 1024 |") \
        < scale_table(back).index("| ishima kt=1 | 64 |")
    table = scale_table(v)
    assert "| charan mu=0.1 kt=1 | 1024 | 1 | 2 | 10 |" in table     # core-h 1024 / 512
    assert table.count("4/10, p 0.9, power 0.70") == 6


def test_scale_headline():
    """Per law from its pooled row: precedes (p <= 0.05 / 4, sizes agree), size-dependent
    (Kruskal p <= 0.05, the sizes where extreme named), weak (0.05 / 4 < p <= 0.05), not
    seen (p > 0.05, with its power at f = 0.5); a candidate never ranked is left out."""
    def row(label, n, ps, sizes_p=None):
        return {"law": label, "n": n, "runs": 3, "drops": 30,
                "candidates": {c: dict(_cand(p, power=0.93, none=p is None),
                                       **({} if sizes_p is None else {"sizes_pvalue": sizes_p[c]}))
                               for c, p in zip(CANDIDATES, ps)}}
    lab = RANKED_LAWS["ishima"]
    v = {"a": row(lab, 64, (0.001, 0.001, 0.001, 0.5)),
         "b": row(lab, 1024, (0.2, 0.001, 0.4, 0.5)),
         "c": row(lab, "all", (0.001, 0.03, 0.001, 0.5),
                  {"n_pairs": 0.3, "growth": 0.5, "min_real": 0.004, "pair_min_imag": 0.8}),
         "d": row(RANKED_LAWS["hertz"], "all", (None, 0.3, 0.001, None),
                  {"n_pairs": None, "growth": 0.2, "min_real": 0.6, "pair_min_imag": None})}
    text = scale_headline(v)
    ishima, hertz = text.split(". ")
    assert ishima.startswith("ishima (30 drops, 3 runs): n_pairs precedes (rank 0.70, p 0.001; "
                             "sizes agree p 0.3)")
    assert "growth weak (rank 0.70, p 0.03: not at 0.05 / 4)" in ishima
    assert "min_real size-dependent (rank 0.70, p 0.001; sizes differ p 0.004; extreme at " \
           "N = 64)" in ishima
    assert "pair_min_imag not seen (rank 0.70, p 0.5; power 0.93 against a preceded " \
           "fraction of 0.5)" in ishima
    assert "n_pairs" not in hertz and "pair_min_imag" not in hertz
    v["d"]["candidates"]["n_pairs"] = dict(_cand(1.0), **{"power_0.5": None})
    assert "n_pairs untestable (the same at every state: no power)" in scale_headline(v)
    assert "min_real precedes" in hertz and "growth not seen" in hertz
    # a law without a pooled row (one size) has no headline
    assert "charan" not in text


def test_fi_answer():
    from claims.precursors import FI_LAWS, fi_answer
    v = {}
    for law, (lab, fi) in FI_LAWS.items():
        v[lab] = {"drops": 13, "candidates": {c: _cand(0.001 if c == "min_real" else 0.5)
                                              for c in CANDIDATES}}
        v[fi] = {"drops": 20, "candidates": {c: _cand(0.03 if c == "growth" else 0.5)
                                             for c in CANDIDATES}}
    text = fi_answer(v)
    assert text.startswith("ishima (13 drops): min_real (p 0.001) against ishima_fi (20 drops): "
                           "growth (p 0.03)")
    assert "; charan (13 drops)" in text


def _path(births_at, drops_at, n=401, dgamma=5e-4):
    """A synthetic AQS path: stress rising by 1e-3 per step, falling by 1e-2 at the first
    dropping step of each drop (``drops_at``: its onset state), births at the states
    ``births_at``; candidate series flat noise."""
    strain = dgamma * np.arange(n)
    step = np.full(n - 1, 1e-3)
    step[np.asarray(drops_at)] = -1e-2          # the step after the onset drops
    stress = np.concatenate([[0.0], np.cumsum(step)])
    rng = np.random.default_rng(len(births_at))
    run = {"strain": strain, "stress": stress, "births": strain[np.asarray(births_at, int)],
           "seconds": 1800.0}
    run.update({c: rng.random(n) for c in CANDIDATES})
    return run


def test_the_study_reports_the_old_window_test():
    """Every drop preceded by a birth at its onset, the births rare (p0 = 1 step in 100):
    the old 1-step test finds 5/5 with a tiny p; births only far from the drops: 0/5, p 1."""
    import precursor_study as ps
    drops = [60, 120, 180, 240, 300]
    runs = {("preceded", 64): [_path(drops, drops)],
            ("far", 64): [_path([d + 30 for d in drops], drops)]}
    rows = {r["law"]: r for r in ps.analyse(runs, 5e-4, half_width=25, n_perm=99, n_rep=50)}
    hit, far = rows["preceded"], rows["far"]
    assert (hit["window1_preceded"], hit["window1_tested"]) == (5, 5)
    assert hit["window1_pvalue"] < 1e-6            # (1/80)^5 with p0 = 5 steps of 400
    assert (far["window1_preceded"], far["window1_tested"]) == (0, 5)
    assert far["window1_pvalue"] == 1.0
    assert hit["seconds"] == 1800.0                # the compute of its one run
    assert "| preceded | 64 | 0.5 | 5 | 5/5 |" in ps.tables(list(rows.values()))


def test_a_law_run_at_several_sizes_has_a_pooled_row():
    """The pooled row is the ranked test on every drop of the law's sizes: its drops are the
    sum, its onset ranks the union; the per-size rows are those of the sizes alone (the same
    random streams); a law at one size has none; the figure does not count a drop twice."""
    import precursor_study as ps
    a, b = [60, 180, 300], [100, 250]
    runs = {("law", 64): [_path([], a)], ("law", 128): [_path([], b)],
            ("other", 64): [_path([], a)]}
    rows = ps.analyse(runs, 5e-4, half_width=25, n_perm=99, n_rep=20)
    by = {(r["law"], r["n"]): r for r in rows}
    assert list(by) == [("law", 64), ("law", 128), ("other", 64), ("law", ps.POOLED)]
    pool = by[("law", ps.POOLED)]
    assert pool["drops"] == 5 and pool["runs"] == 2
    for c in CANDIDATES:
        ranks = by[("law", 64)]["candidates"][c]["ranks"] + by[("law", 128)]["candidates"][c]["ranks"]
        assert pool["candidates"][c]["ranks"] == ranks
        assert np.isclose(pool["candidates"][c]["statistic"], np.mean(ranks))
        assert 0 < pool["candidates"][c]["sizes_pvalue"] <= 1
        assert "sizes_pvalue" not in by[("law", 64)]["candidates"][c]
    assert "| law | all | 2 | 5 | n_pairs |" in ps.tables(rows)
    # Kruskal-Wallis across sizes: one distribution, or two far apart
    assert ps.sizes_differ([[0.1, 0.5, 0.9], [0.2, 0.5, 0.8]]) > 0.5
    assert ps.sizes_differ([[0.9, 0.95, 1.0, 0.92], [0.0, 0.05, 0.1, 0.02]]) < 0.05
    assert np.isnan(ps.sizes_differ([[0.5, 0.5], [0.5]])) and np.isnan(ps.sizes_differ([[0.3]]))
    alone = ps.analyse({("law", 64): runs[("law", 64)]}, 5e-4, half_width=25, n_perm=99, n_rep=20)
    assert alone[0]["candidates"] == by[("law", 64)]["candidates"]


def test_old_sentence_and_the_check_of_the_old_test():
    from claims.precursors import _check_ranked, old_sentence
    v = {label: {"drops": 20, "window1_tested": 20, "window1_preceded": k,
                 "window1_pvalue": p, "window1_power_0.8": 0.9, "window1_p0": 0.5 if k else 0.0,
                 "candidates": {c: _cand(0.5) for c in CANDIDATES}}
         for (label, k, p) in zip(RANKED_LAWS.values(), (11, 8, 0), (0.83, 0.76, 1.0))}
    text = old_sentence(v)
    assert text.startswith("charan: 11/20 drops preceded (p 0.83; power 0.90 at f = 0.8)")
    assert text.endswith("hertz: no pair born (20 drops)")
    ok, _ = _check_ranked(v, v)
    assert ok
    # 11/20 -> 19/20: 0.40 apart, beyond 3 combined binomial errors (3 hypot(0.111, 0.049) = 0.36)
    moved = {k: dict(r) for k, r in v.items()}
    moved["charan mu=0.1 kt=1"]["window1_preceded"] = 19
    ok, why = _check_ranked(v, moved)
    assert not ok and "old test" in why


def test_budget_counts_what_is_spent_and_projects_what_is_left(tmp_path, monkeypatch):
    """A finished charan run (40 s, 401 states) and an ishima checkpoint (10 s at step 100):
    spent 50 s; left: ishima's 301 states at 0.1 s, both laws at N = 128 at their N = 64 rate
    times 2^3, hertz unknown (never measured, no probe)."""
    import precursor_study as ps
    monkeypatch.setattr(ps, "fresh", lambda stamp: True)
    laws = ps.LAWS
    stem = {lab: ps._key(64, 0, lab, 0.2, 5e-4) for lab, _, _ in laws}
    charan, ishima, hertz = (lab for lab, _, _ in laws)
    ps.save_run(tmp_path / f"{stem[charan]}.npz",
                {"strain": np.zeros(401), "seconds": np.float64(40.0)})
    ck = tmp_path / f"{stem[ishima]}.checkpoints"
    ck.mkdir()
    np.savez(ck / "ckpt_000000000100.npz", seconds_so_far=np.float64(10.0), step=np.int64(100))
    lines = []
    out = {(r["n"], r["law"]): r for r in
           ps.budget([64, 128], [1, 1], laws, 0.2, 5e-4, tmp_path, log=lines.append,
                     probe_new=False)}
    assert out[(64, charan)]["states_owed"] == 0 and out[(64, charan)]["spent_hours"] == 40 / 3600
    assert out[(64, ishima)]["states_owed"] == 301
    assert np.isclose(out[(64, ishima)]["left_hours"] * 3600, 30.1)
    assert np.isclose(out[(128, charan)]["left_hours"] * 3600, 320.0)     # 401 x 40/401 x 8
    assert np.isclose(out[(128, ishima)]["left_hours"] * 3600, 320.8)     # 401 x 0.1 x 8
    assert out[(64, hertz)]["left_hours"] is None
    assert "not measured" in lines[-1] and "N = 64 hertz" in lines[-1]
    # a checkpoint made by other code is restarted: nothing spent, every state owed
    monkeypatch.setattr(ps, "fresh", lambda stamp: False)
    out = {(r["n"], r["law"]): r for r in
           ps.budget([64], [1], laws, 0.2, 5e-4, tmp_path, log=lines.append, probe_new=False)}
    assert out[(64, ishima)]["states_owed"] == 401 and out[(64, ishima)]["spent_hours"] == 0
