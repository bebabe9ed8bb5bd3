"""The computed answer of the scale claims (claims.precursors.scale_answer): a candidate is named
where p <= 0.05, and a pair-count or growth test that found nothing carries its power."""

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

from claims.precursors import CANDIDATES, RANKED_LAWS, scale_answer  # noqa: E402


def _cand(p, power=0.9, none=False):
    return {"statistic": None if none else 0.7, "null_sd": 0.05, "pvalue": None if none else p,
            "drops": 10, "power_0.5": power, "power_0.8": 0.99}


def test_scale_answer():
    v = {}
    for law, label in RANKED_LAWS.items():
        for n in (64, 1024):
            sig = 0.001 if (law == "ishima" or n == 64) else 0.3
            v[f"{label} N={n}"] = {"law": label, "n": n, "runs": 1, "drops": 10,
                                  "candidates": {c: _cand(sig if c != "pair_min_imag" else 0.5,
                                                          none=(law == "hertz"
                                                                and c == "n_pairs"))
                                                 for c in CANDIDATES}}
    text = scale_answer(v)
    charan, ishima, hertz = text.split(". ")
    assert charan.startswith("charan: N = 64") and "N = 1024 (1 runs, 10 drops): none" in charan
    assert "[not: n_pairs power 0.90, growth power 0.90 at f = 0.5]" in charan
    assert "n_pairs (p 0.001), growth (p 0.001), min_real (p 0.001)" in ishima
    assert "not:" not in ishima
    assert "n_pairs" not in hertz.split("N = 1024")[1]     # no pair: neither named nor 'not'
    assert text.index("N = 64") < text.index("N = 1024")


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
