"""The ensemble manifest of issue 35 (validation/ishima_ensemble.py) on a tiny ensemble: every
packing judged, an unstable one marked unused with its reason, the counts per (N, phi)."""

import json
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))


def test_the_manifest_excludes_what_the_rule_rejects(tmp_path, monkeypatch):
    import _packings
    import ishima_ensemble as ens
    from fricstab.analysis import stability as st
    monkeypatch.setattr(_packings, "CACHE", tmp_path / "packings")
    real = ens.packing_stability
    calls = []

    def judged(system, state):
        calls.append(1)
        if len(calls) == 2:        # the second packing: feign G(0) < 0 on it
            return st.classify([-1.0], 1.0, g=-0.0147, g_a=0.3)
        return real(system, state)
    monkeypatch.setattr(ens, "packing_stability", judged)
    rows = [ens.one(32, phi, seed, log=lambda m: None) for phi in (0.86, 0.9) for seed in (0, 1)]
    doc = ens.write(rows, tmp_path, ["--sizes", "32"])
    assert [r["use"] for r in rows] == [True, False, True, True]
    assert "unstable to shear" in rows[1]["stability"]["reason"]
    assert all(r["stability"]["route"] == "dense" and r["stability"]["g"] > 0
               for r in rows if r["use"])
    cell = doc["summary"]["32/0.86"]
    assert (cell["samples"], cell["used"], cell["excluded"][0]["seed"]) == (2, 1, 1)
    md = (tmp_path / "ishima_ensemble.md").read_text()
    assert "Rule: excluded" in md and "1: " in md and "unstable to shear" in md
    assert json.loads((tmp_path / "ishima_ensemble.json").read_text())["rule"] == ens.RULE
    # a second pass reads every packing from the cache
    again = [ens.one(32, 0.9, 0, log=lambda m: None)]
    assert again[0]["from_cache"] and again[0]["make_seconds"] == 0.0


def test_a_packing_below_jamming_is_excluded_as_unjammed(tmp_path, monkeypatch):
    """Below jamming every disk is a rattler: the row says so and is not used (the paper's
    phi = 0.83 at N = 1,024 is such a packing for our frictionless compression)."""
    import _packings
    import ishima_ensemble as ens
    monkeypatch.setattr(_packings, "CACHE", tmp_path / "packings")
    row = ens.one(32, 0.70, 0, log=lambda m: None)
    assert not row["use"] and row["backbone"] == 0
    assert row["stability"]["reason"].startswith("unjammed")
    assert ens.summary([row])["32/0.7"]["excluded"][0]["reason"].startswith("unjammed")


def test_a_marginal_packing_is_excluded_not_fatal(tmp_path, monkeypatch):
    """At the jamming threshold the contact forces are at rounding level and the backbone's
    force balance cannot be judged relative to them (N = 1,024, phi = 0.84, seed 2: mean
    contact force 1e-17): the row says so and the ensemble goes on."""
    import _packings
    import ishima_ensemble as ens
    from fricstab.errors import ParameterError
    monkeypatch.setattr(_packings, "CACHE", tmp_path / "packings")

    def marginal(system, state):
        raise ParameterError("the state is not force-balanced: max |F| = 4.4e-15 (tolerance "
                             "1.04e-23 = 1e-06 x the mean contact force 1.04e-17); relax it")
    monkeypatch.setattr(ens, "packing_stability", marginal)
    row = ens.one(32, 0.9, 0, log=lambda m: None)
    assert not row["use"] and row["stability"]["reason"].startswith("marginal")
    assert "4.4e-15" in row["stability"]["reason"]


def test_a_compression_that_does_not_converge_is_excluded_not_fatal(tmp_path, monkeypatch):
    """FIRE can stall at the jamming threshold (N = 4,096, phi = 0.84, seed 0: max |F| =
    4.5e-10 after 5e6 iterations, against 1e-14): the row is marked marginal with the
    solver's message, nothing is cached, and the paper run skips that packing's pieces.
    Here FIRE is given 50 iterations, which cannot reach 1e-14 from a random start."""
    import _packings
    import ishima_ensemble as ens
    monkeypatch.setattr(_packings, "CACHE", tmp_path / "packings")
    real = _packings.make_packing
    monkeypatch.setattr(_packings, "make_packing",
                        lambda n, phi, seed, **k: real(n, phi, seed, max_iter=50, **k))
    row = ens.one(32, 0.9, 0, log=lambda m: None)
    assert not row["use"] and row["backbone"] is None
    reason = row["stability"]["reason"]
    assert reason.startswith("marginal: the compression did not converge")
    assert "did not converge" in reason.split("converge:", 1)[1]      # the solver's own words
    assert not list((tmp_path / "packings").glob("*.npz"))             # no half-made packing
    assert ens.summary([row])["32/0.9"]["excluded"][0]["reason"] == reason
