"""Issue 35: the one-command pipeline of Ishima's figures (``validation/ishima_paper.py``),
its quick tier (N = 64, 3 samples, phi = 0.84, 0.87, 0.90) on fresh caches.

What is checked: the exclusion rule keeps the unstable packing out of every mean; the cache is
reused while its code is unchanged and recomputed when the stamp says otherwise; and two
statements that carry physics, each with its error model next to it.  The paper-scale tier
(``--tier paper``) is the hours claim ``packing.ishima_paper`` (not run here).
"""

import json
import math
import sys
from pathlib import Path

import numpy as np
import pytest

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

import _packings  # noqa: E402
import _stamped  # noqa: E402
import ishima_paper as ip  # noqa: E402


@pytest.fixture(scope="module")
def quick(tmp_path_factory):
    base = tmp_path_factory.mktemp("ishima_paper")
    mp = pytest.MonkeyPatch()
    mp.setattr(_packings, "CACHE", base / "packings")
    mp.setattr(ip, "CACHE", base / "pieces")
    doc = ip.run("quick", out=base / "out", log=lambda m: None)
    yield doc, base
    mp.undo()


def test_the_report_says_how_far_it_got_and_lists_every_figure(quick):
    doc, base = quick
    md = (base / "out" / "ishima_paper_quick.md").read_text()
    assert doc["pieces_done"] == doc["pieces_total"] and "(complete)" in md
    for head in ("## Ensemble", "Fig. 4", "Fig. 5", "Fig. 6", "read as Fig. 6 shows it",
                 "Bands (Figs. 7-9)",
                 "Fig. 7 b2", "Fig. 10", "Fig. 14", "Fig. 16", "Factorisation"):
        assert head in md, head
    assert (base / "out" / "ishima_paper_quick.png").stat().st_size > 10_000
    assert json.loads((base / "out" / "ishima_paper_quick.json").read_text())["tier"] == "quick"


def test_an_excluded_packing_enters_no_mean(quick):
    """The rule's verdict (ishima_ensemble) decides which seeds the tables use: every excluded
    (n, phi, seed) is absent from every table's seeds, the others present."""
    doc, _ = quick
    excluded = {(r["n"], r["phi"], r["seed"]) for r in doc["ensemble"]["excluded"]}
    n = doc["sizes"]["fig4"]
    for phi, t in doc["fig4"].items():
        samples = ip.TIERS["quick"]["samples"][n]
        want = [s for s in range(samples) if (n, float(phi), s) not in excluded]
        assert t["seeds"] == want, phi
        assert t["g"][0]["count"] == len(want)
    for r in doc["ensemble"]["excluded"]:
        assert r["stability"]["reason"]                  # a reason is given


def test_a_piece_is_reused_while_fresh_and_recomputed_when_its_code_changed(quick, tmp_path):
    calls = []

    def make():
        calls.append(1)
        return {"x": np.arange(3.0)}
    path = tmp_path / "piece.npz"
    first = _stamped.cached(path, make, log=lambda m: None)
    again = _stamped.cached(path, make, log=lambda m: None)
    assert len(calls) == 1 and np.array_equal(first["x"], again["x"])
    stored = _stamped.load(path)
    units = json.loads(stored[_stamped.UNITS])
    assert "validation/test_ishima_paper.py" in units      # the code it ran: this file
    # a stamp naming a function that no longer hashes the same: stale, recomputed
    stale = dict(stored)
    stale[_stamped.UNITS] = np.str_(json.dumps({"validation/ishima_paper.py":
                                                {"analyse": "0" * 16}}))
    _stamped.save(path, stale)
    msgs = []
    _stamped.cached(path, make, log=msgs.append)
    assert len(calls) == 2 and "made by other code" in msgs[0]


def test_the_rotational_band_sits_at_its_prefactor(quick):
    """The median frequency of the rotation-dominated modes over sqrt(kT/kN), kT/kN <= 1e-4
    (the decoupled regime, where the prefactor is all the physics: the exponent 1/2 is an
    identity there).  Error model: at N = 256 and 1,024 it is 0.76-0.78 with a per-packing
    sd of 0.01 (validation/packing_dos_*.md); the window [0.6, 1.0] is wider than 10 sd, so
    sampling cannot fail it, while a rotational inertia off by a factor 2 (m d^2/4 for
    m d^2/8, say: a factor sqrt 2 in omega, 0.55 or 1.1) does."""
    doc, _ = quick
    for kt in ("1e-08", "1e-06", "0.0001"):
        m = doc["fig10"]["rows"][kt]["median"]
        assert 0.6 <= m["mean"] <= 1.0, (kt, m)


def test_the_sign_change_of_g_na_per_phi_against_its_spread(quick):
    """Each used packing's G_NA changes sign once in [1e-2, 10^1.5] (negative at the bracket's
    low end, positive at its high end); the per-phi mean root lies within 3 combined standard
    errors of the paper's 2.0 (its half-unit 0.05 and our sample s.e.: a 0.3 % false-alarm
    rate per phi for a normal mean).  A law whose tangential stiffness entered G_NA with the
    wrong weight moves the root by a factor of its error, far beyond the spread."""
    doc, _ = quick
    kts = doc["rig_kts"]
    lo, hi = kts.index(1e-2), kts.index(10.0)
    for phi, t in doc["fig4"].items():
        for seed, row in zip(t["seeds"], t["g_na_per_seed"]):
            assert row[lo] < 0 < row[hi], (phi, seed)
        r = doc["sign_change"][phi]
        assert r["count"] == len(t["seeds"])
        assert math.fabs(r["mean"] - 2.0) <= 3 * math.hypot(r["se"], 0.05), (phi, r)


def _na_table(curves, se=1e-4, count=5):
    """A rigidity table of per-phi G_NA means (``curves[phi](kT)``) with one s.e."""
    ms = lambda m: {"mean": m, "sd": se * math.sqrt(count), "se": se, "count": count}  # noqa: E731
    return {phi: {"g_na": [ms(f(k)) for k in ip.RIG_KTS]} for phi, f in curves.items()}


def test_the_figure_reading_of_the_sign_change():
    """Fig. 6 read as a figure: a phi whose root sits at 3 (G_NA(2.0) small against the
    figure's range, every grid sign the paper's) agrees; G_NA(2.0) beyond 2 % of the range,
    or a sign opposite the paper's beyond 2 s.e., disagrees; a sign within 2 s.e. of zero is
    'unresolved' and does not; too few packings is not comparable."""
    base = lambda k: -0.05 + 0.02 * k           # noqa: E731  range over the grid: 0.25
    tab = _na_table({"0.84": lambda k: 0.001 * (k - 3.0),    # root 3, G_NA(2) = -0.001
                     "0.9": base})
    f = ip.sign_figure(tab)
    assert f["range"] == pytest.approx(base(10.0) - base(1e-8))
    r = f["rows"]["0.84"]
    assert r["label"] == "agrees" and r["at_2_over_range"] == pytest.approx(0.001 / f["range"])
    assert r["signs"]["1"] == "as the paper" and r["signs"]["5"] == "as the paper"
    assert f["rows"]["0.9"]["signs"]["1"] == "as the paper"   # -0.03 < -2 s.e.
    # G_NA(2.0) at 4 % of the range: not ~= 0 on the figure
    far = ip.sign_figure(_na_table({"0.84": lambda k: -0.01 if k == 2.0 else base(k),
                                    "0.9": base}))
    assert far["rows"]["0.84"]["label"] == "disagrees" and "of the figure's range" in \
        far["rows"]["0.84"]["why"]
    # a sign opposite the paper's at kT/kN = 5 beyond 2 s.e.; one within 2 s.e. is unresolved
    odd = ip.sign_figure(_na_table({"0.84": lambda k: -0.001 if k == 5.0 else
                                    (1e-4 if k == 1.0 else base(k)), "0.9": base}))
    r = odd["rows"]["0.84"]
    assert r["signs"]["5"] == "opposite" and r["signs"]["1"] == "unresolved"
    assert r["label"] == "disagrees" and "opposite sign at kT/kN = 5" in r["why"]
    few = ip.sign_figure(_na_table({"0.84": base}, count=1))
    assert few["rows"]["0.84"]["label"] == "not comparable"


def test_fig5_is_judged_per_phi_with_its_sample_error_under_both_readings():
    """Fig. 5's 'only little': per phi, G(1e-4)/G(0) - 1 against a reading's bound with 2 s.e.
    of the mean over packings.  A mean above 1 % by more than 2 s.e. disagrees strictly; one
    within 1 % but less than 2 s.e. from it is unresolved (without the error it would agree);
    one packing is unresolved whatever its value; the figure's bound is half a marker (2 %) of
    the G axis's decades, from the per-phi mean G at kT/kN > 0 (here 2.8 decades: 13.8 %)."""
    def ms(mean, sd, count):
        return {"mean": mean, "sd": sd, "se": sd / math.sqrt(count), "count": count}
    limit = {"0.84": {"0.0001": ms(0.30, 0.0, 1)},        # one packing: unresolved
             "0.86": {"0.0001": ms(0.03, 0.01, 5)},       # 0.03 - 2 x 0.0045 > 1 %
             "0.88": {"0.0001": ms(0.009, 0.005, 5)},     # 0.009 + 2 x 0.0022 > 1 %
             "0.9": {"0.0001": ms(0.002, 0.001, 5)}}      # within 1 % by 2 s.e.
    g = lambda lo, hi: [ms(x, 0.0, 5) for x in np.geomspace(lo, hi, len(ip.RIG_KTS))]  # noqa: E731
    table = {"0.84": {"g": g(1e-4, 1e-2)}, "0.9": {"g": g(1e-3, 1e-1)}}
    table["0.84"]["g"][0] = ms(1e-7, 0.0, 5)      # kT/kN = 0 is not on the figure's log axis
    x = ip.limit_readings(limit, table)
    r = x["readings"]
    assert ip.RIG_KTS[0] == 0.0 and x["decades"] == pytest.approx(
        math.log10(1e-1 / np.geomspace(1e-4, 1e-2, len(ip.RIG_KTS))[1]))
    assert r["strict"]["bound"] == 0.01
    assert r["strict"]["rows"] == {"0.84": "unresolved", "0.86": "disagrees",
                                   "0.88": "unresolved", "0.9": "agrees"}
    assert r["strict"]["label"] == "disagrees"
    assert r["figure"]["bound"] == pytest.approx(10 ** (ip.FIG_ZERO * x["decades"]) - 1)
    assert r["figure"]["rows"]["0.86"] == "agrees" and r["figure"]["rows"]["0.84"] == \
        "unresolved" and r["figure"]["label"] == "undecided"
    limit["0.84"]["0.0001"] = ms(0.30, 0.02, 3)
    assert ip.limit_readings(limit, table)["readings"]["figure"]["label"] == "disagrees"


def test_fig14_says_why_no_mode_is_carried_by_rattlers():
    """Fig. 14's accounting on two made-up phi = 0.90 packings of N = 10: one whose rattler
    is free (its three modes are exact zeros, dropped with the two translations: 3N - 5
    kept) and one whose rattler touches a neighbour (one zero mode, one mode on it with
    p N = 1).  The zero modes beyond the translations (3 + 1) against 3 x the rattlers (6)
    tell the two apart; the verdict says 'every rattler is free' only when they are equal."""
    from claims import _packing_paper
    n, phi = 10, ip.FIG_PHI

    def packing(seed, kept, w_on):
        row = {"use": True, "rattlers": 1}
        w = np.zeros(kept)
        w[:len(w_on)] = w_on
        p = np.full(kept, 0.5)
        p[:len(w_on)] = 1.0 / n
        return {(n, phi, seed, "ensemble"): {"row": json.dumps(row)},
                (n, phi, seed, "rigidity"): {},
                **{(n, phi, seed, f"rattlers{kt:g}"): {"omega": np.linspace(1e-3, 1, kept),
                                                       "w_rattler": w, "p": p}
                   for kt in ip.RATTLER_KTS}}
    free = packing(0, 3 * n - 5, [])
    x = ip.rattler_table(free, n)["1e-08"]
    assert (x["rattlers"], x["zero_modes"], x["modes"]) == (1, 3, 0)
    v = {"fig14": ip.rattler_table(free, n)}
    assert "every rattler is free" in _packing_paper._fig14_verdict(v).detail
    both = {**free, **packing(1, 3 * n - 3, [1.0])}
    x = ip.rattler_table(both, n)["1e-08"]
    assert (x["rattlers"], x["zero_modes"], x["modes"]) == (2, 4, 1)
    assert x["pN_median"] == pytest.approx(1.0)
    assert _packing_paper._fig14_verdict({"fig14": ip.rattler_table(both, n)}).label == "agrees"
    contact = packing(0, 3 * n - 3, [0.3])         # a touching rattler, its mode not on it
    v = {"fig14": ip.rattler_table(contact, n)}
    verdict = _packing_paper._fig14_verdict(v)
    assert verdict.label == "not comparable" and "free" not in verdict.detail


def test_the_cost_of_an_owed_packing_is_priced_by_packings_made_not_read():
    """An ensemble piece judged again on a cached packing (1 s) says nothing of what making
    one costs (300 s here, the compression): the owed packing is priced at 300 s, not at the
    mean 150 s; a kind never measured is counted unpriced."""
    row = lambda cached: {"row": json.dumps({"from_cache": cached})}  # noqa: E731
    got = {(64, 0.9, 0, "ensemble"): {**row(True), "stamp_seconds": 1.0},
           (64, 0.9, 1, "ensemble"): {**row(False), "stamp_seconds": 300.0}}
    c = ip.cost_table(got, [(64, 0.9, 2, "ensemble"), (64, 0.9, 2, "rigidity")])
    assert c["rows"]["64/ensemble"] == {"mean": 300.0, "count": 1}
    assert c["projected_seconds"] == 300.0 and c["unpriced"] == 1


def test_every_paper_claim_shows_and_judges_the_quick_values(quick):
    """The hours claims read the same document at the paper's scale: their cells and verdicts
    are computed here on the quick tier's (a claim that cannot render would be found after
    days of compute otherwise).  Every verdict is computed, never typed: its label is one of
    the registry's."""
    from claims import _packing_paper
    from fricstab.io.files import json_clean
    doc, _ = quick
    values = json.loads(json.dumps(json_clean(_packing_paper.values_of(doc))))
    for claim in _packing_paper.claims():
        assert claim.show(values)
        verdict = claim.judge(values)
        assert verdict.label in ("agrees", "disagrees", "undecided", "not comparable"), \
            claim.name
        ok, _ = claim.check(values, values)
        assert ok, claim.name


def test_the_report_of_what_is_done_computes_nothing(quick, tmp_path):
    """``--report-only``: the same tables from the cache alone; a piece missing from it is
    counted as owed and priced at its kind's measured mean, not computed."""
    doc, base = quick
    again = ip.run("quick", out=tmp_path, log=lambda m: None, figures=False,
                   compute_missing=False)
    assert again["fig4"] == doc["fig4"] and again["pieces_done"] == doc["pieces_done"]
    gone = ip._path(64, 0.87, 1, "dos0.0001")
    gone.rename(tmp_path / "kept.npz")
    try:
        part = ip.run("quick", out=tmp_path, log=lambda m: None, figures=False,
                      compute_missing=False)
    finally:
        (tmp_path / "kept.npz").rename(gone)
    assert part["pieces_done"] == doc["pieces_done"] - 1
    assert part["cost"]["pending"] == 1 and part["cost"]["projected_seconds"] > 0
    assert "(the scale reached" in (tmp_path / "ishima_paper_quick.md").read_text()


def test_the_paper_tier_record_reports_the_store_as_far_as_it_got(quick, monkeypatch):
    """The paper tier's claims (days of compute) record the committed store's report: their
    compute asks for no missing piece, their inputs are the store's pieces (a piece added
    makes the record stale), every N = 4,096 cell states the pieces done, and a store that
    grew is judged afresh rather than failing the 3-s.e. check."""
    from claims import _packing_paper
    from fricstab.io.files import json_clean
    seen = {}

    def fake_run(tier, out, compute_missing=True):
        seen.update(tier=tier, compute_missing=compute_missing)
        return {**quick[0], "units": {}}
    monkeypatch.setattr(ip, "run", fake_run)
    values = json.loads(json.dumps(json_clean(_packing_paper.compute().values)))
    assert seen == {"tier": "paper", "compute_missing": False}
    claims = {c.name: c for c in _packing_paper.claims()}
    store = _packing_paper.stored()
    assert store and all(p.startswith("validation/runs/ishima_paper/n") for p in store)
    for name in ("g_little", "bands", "rot_prefactor", "rattlers", "dos_phi"):
        c = claims[f"packing.paper_{name}"]
        assert c.inputs == store and "--report-only" in c.command
        assert f"{values['pieces'][0]} of {values['pieces'][1]} pieces" in c.show(values)
    assert claims["packing.paper_sign_change"].inputs == ()
    grown = {**values, "pieces": [values["pieces"][0] + 1, values["pieces"][1]],
             "g": {}, "sign_change": {}}
    ok, said = claims["packing.paper_g_little"].check(values, grown)
    assert ok and "reached further" in said
    moved = {**values, "g": {phi: {k: {**m, "mean": (m["mean"] or 0) + 1}
                                   for k, m in row.items()} for phi, row in values["g"].items()}}
    assert not claims["packing.paper_g_little"].check(values, moved)[0]


def test_the_paper_tier_keeps_its_pieces_in_the_committed_store(monkeypatch):
    """The paper tier runs over many sittings, possibly on other machines: its pieces and the
    packings they were computed on go to ``validation/runs/ishima_paper`` (committed), the
    quick tier's stay in the git-ignored cache; per-mode arrays are stored as float32."""
    monkeypatch.setattr(ip, "CACHE", ip.CACHE)
    monkeypatch.setattr(_packings, "CACHE", _packings.CACHE)
    before = ip.CACHE
    ip.use_store("quick")
    assert ip.CACHE == before          # the git-ignored cache (or a test's)
    ip.use_store("paper")
    assert ip.CACHE == HERE / "runs" / "ishima_paper"
    assert _packings.CACHE == ip.CACHE / "packings"
    assert ip._path(1024, 0.9, 0, "rigidity").parent == ip.CACHE
    out = ip._modes(omega=np.array([1e-3, 2.0]), psi_r=[0.5, 1.0])
    assert {v.dtype for v in out.values()} == {np.dtype(np.float32)}
    np.testing.assert_allclose(out["omega"], [1e-3, 2.0], rtol=1e-7)


def test_a_step_strain_that_breaks_the_packing_is_reported_not_fatal(tmp_path, monkeypatch):
    """At the jamming threshold a strain of 1e-6 can open contacts and leave the relaxation a
    singular Jacobian (N = 4,096, phi = 0.84, seed 1 raised ConvergenceError and stopped the
    paper run): the piece keeps the solve and the mode sum, the step-strain check of that kT
    is NaN with the solver's message, and the Fig. 4 route check uses the other packings and
    lists the failure."""
    from fricstab.errors import ConvergenceError
    from fricstab.scenes.packing_friction import backbone
    monkeypatch.setattr(_packings, "CACHE", tmp_path)
    bb = backbone(_packings.packing(32, 0.9, 0))
    real = ip.step_strain

    calls = []

    def brittle(system, state, dgamma):       # called once per CHECK_KTS, in order
        calls.append(1)
        if ip.CHECK_KTS[len(calls) - 1] > 0.5:        # kT/kN = 1 and 10
            raise ConvergenceError("Newton relaxation: singular Jacobian (sparse LU: Matrix "
                                   "is exactly singular)")
        return real(system, state, dgamma)
    monkeypatch.setattr(ip, "step_strain", brittle)
    bad = ip.rigidity_piece(bb)
    monkeypatch.setattr(ip, "step_strain", real)
    good = ip.rigidity_piece(bb)
    broke = [k > 0.5 for k in ip.CHECK_KTS]
    assert np.isnan(bad["g_step"][broke]).all() and np.isnan(bad["step_err"][broke]).all()
    assert np.isfinite(bad["g_step"][~np.array(broke)]).all()
    assert "kT/kN = 1: Newton relaxation: singular Jacobian" in str(bad["step_failed"])
    assert str(good["step_failed"]) == ""
    np.testing.assert_array_equal(bad["g_check"], good["g_check"])     # the solve stands
    got = {(32, 0.9, s, p): x for s, x in ((0, good), (1, bad))
           for p, x in (("rigidity", x), ("ensemble", {"row": json.dumps({"use": True})}))}
    t = ip.rigidity_tables(got, 32, [0.9])["0.9"]
    assert t["step_failed"] == {"1": str(bad["step_failed"])}
    want = float(np.max(np.abs(good["g_step"] / good["g_check"] - 1)))
    assert t["step_vs_solve"] == pytest.approx(want, rel=1e-12)          # from seed 0 alone


def test_two_runs_share_the_work_a_packing_at_a_time(tmp_path, monkeypatch):
    """Started once per core, runs share the store: a packing another live run holds is left
    to it (its pieces pending here, no piece computed twice); a hold whose run is gone is
    taken over; a run lets go of every packing when it ends."""
    import os
    import platform
    import subprocess

    from fricstab.io.rundir import LOCK, _start_time
    monkeypatch.setattr(ip, "CACHE", tmp_path)
    todo = [(64, 0.84, 0, "ensemble"), (64, 0.84, 0, "rigidity"), (64, 0.87, 0, "ensemble")]
    monkeypatch.setattr(ip, "plan", lambda tier: list(todo))
    monkeypatch.setattr(_stamped, "stored", lambda path: None)
    made = []

    def fake(n, phi, seed, piece, log=print):
        made.append((n, phi, seed, piece))
        return {"row": json.dumps({"use": True})}
    monkeypatch.setattr(ip, "compute", fake)
    other = subprocess.Popen([sys.executable, "-c", "import time; time.sleep(60)"])
    try:
        folder = tmp_path / ".held" / ip.ishima_ensemble._key(64, 0.84, 0)
        folder.mkdir(parents=True)
        (folder / LOCK).write_text(json.dumps({
            "pid": other.pid, "host": platform.node(), "start": _start_time(other.pid),
            "protocol": "ishima_paper", "command": "the other run", "since": "now"}))
        said = []
        got, _, pending = ip.run_pieces("quick", log=said.append)
        assert made == [(64, 0.87, 0, "ensemble")]
        assert pending == todo[:2] and set(got) == {todo[2]}
        assert sum("left to another run" in m and "the other run" in m for m in said) == 1
        assert (folder / LOCK).exists()                      # the other run's hold stands
        assert not (tmp_path / ".held" / ip.ishima_ensemble._key(64, 0.87, 0)).exists()
    finally:
        other.kill()
        other.wait()
    made.clear()
    got, _, pending = ip.run_pieces("quick", log=lambda m: None)   # its run is gone
    assert made == todo and pending == [] and set(got) == set(todo)
    assert not folder.exists() and os.listdir(tmp_path / ".held") == []
