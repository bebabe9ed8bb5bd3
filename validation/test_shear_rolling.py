"""``validation/shear_rolling.py``: a segmented shear run equals the uninterrupted one.

A tiny member (40 disks, 100 frames, a few slips) is run in segments of 30 frames, stopped
at half its strain and continued in a second call (as on the next sitting: the state comes
back from the stored segment, not from memory).  Its series and every array, table and
summary of its analysis equal, to the bit, those of ``run_shear`` and ``analyze`` on the
frames of one uninterrupted run of the same parameters; so does the analysis from another
gamma0.  A store made by other code, or holding other parameters, is refused with one line.
"""

import json
import sys
from pathlib import Path

import numpy as np
import pytest

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

import shear_rolling  # noqa: E402
from fricstab.analysis.shear import analyze  # noqa: E402
from fricstab.cli.shear import run_shear  # noqa: E402
from fricstab.cli.shear_analyze import frames_of  # noqa: E402

TINY = {"n": 40, "dgamma": 1e-4, "gamma0": 0.002}


def _same(a, b, where):
    if isinstance(a, dict):
        assert sorted(a) == sorted(b), where
        for k in a:
            _same(a[k], b[k], f"{where}.{k}")
    elif isinstance(a, (list, tuple)):
        assert len(a) == len(b), where
        for i, (x, y) in enumerate(zip(a, b)):
            _same(x, y, f"{where}[{i}]")
    elif isinstance(a, np.ndarray) or isinstance(b, np.ndarray):
        assert np.array_equal(a, b, equal_nan=True), where
    elif isinstance(a, float) and isinstance(b, float) and np.isnan(a):
        assert np.isnan(b), where
    else:
        assert a == b, where


@pytest.fixture(scope="module")
def member(tmp_path_factory):
    root = tmp_path_factory.mktemp("rolling")
    store = root / "store"
    quiet = dict(preset="quick", segment=30, store=store, log=lambda m: None)
    # half the strain now, the rest in a second call (the strain only stops a run)
    assert shear_rolling.run(0.7, overrides={**TINY, "strain": 0.005}, **quiet) == 50
    assert shear_rolling.run(0.7, overrides={**TINY, "strain": 0.01}, **quiet) == 100
    params = shear_rolling.member_params(0.7, 0, "quick", **TINY, strain=0.01)
    run_shear(params, root / "direct", log=lambda m: None)
    assert shear_rolling.label(params, "quick") == "quick-mus0.7_seed0"
    return store / shear_rolling.label(params, "quick"), root / "direct", params


def test_segments_continue_the_run_bit_identically(member):
    folder, direct, params = member
    names = [f.name for f in shear_rolling.segments(folder)]
    # frames 0..30, 31..50 (stopped at strain 0.005), 51..80, 81..100
    assert names == ["seg_0000.npz", "seg_0001.npz", "seg_0002.npz", "seg_0003.npz"]
    series, *_ = shear_rolling.arrays(folder)
    with np.load(direct / "shear.npz") as z:
        want = np.column_stack([z[n] for n in shear_rolling.SERIES])
    assert series.shape == (101, 6)
    assert np.array_equal(series, want)


@pytest.mark.parametrize("gamma0", [None, 0.004])
def test_analysis_equals_the_analysis_of_the_frames(member, gamma0):
    folder, direct, params = member
    res, _, _ = shear_rolling.analysis(folder, gamma0)
    want = analyze(frames_of(direct), params["gamma0"] if gamma0 is None else gamma0,
                   progress=False)
    assert res.summary["n_phases"] > 3 and res.summary["n_slip"] > 0   # something to compare
    _same(res.arrays, want.arrays, "arrays")
    _same(res.phases, want.phases, "phases")
    _same(res.tables, want.tables, "tables")
    _same(res.summary, want.summary, "summary")


def test_a_segment_reruns_to_the_frames_of_the_run(member):
    folder, direct, _ = member
    frames = shear_rolling.frames_of_segment(folder, 2)        # frames 50..80, 50 carried over
    want = frames_of(direct).subset(list(range(50, 81)))
    assert frames.n_frames == 31
    for name in ("pos", "vel", "contact_ij", "contact_force", "contact_hist", "tau"):
        assert np.array_equal(getattr(frames, name), getattr(want, name)), name
    first = shear_rolling.frames_of_segment(folder, 0)        # the preparation rerun, too
    assert np.array_equal(first.pos, frames_of(direct).subset(list(range(31))).pos)


def test_event_frames_span_segments(member):
    folder, direct, _ = member
    window = shear_rolling.event_frames(folder, 25, 70)        # segments 0, 1 and 2
    whole = frames_of(direct)
    for k in (25, 30, 31, 50, 51, 70, -31):
        assert np.array_equal(window.pos[k], whole.pos[k]), k
        for a, b in zip(window.contacts(k), whole.contacts(k)):
            assert np.array_equal(a, b), k
    with pytest.raises(IndexError, match="only frames 25..70"):
        window.pos[24]


def test_event_page_from_rerun_frames_equals_the_run_s(member, tmp_path):
    import shear_event
    from fricstab.analysis.shear_event import event_window
    from fricstab.cli import main
    folder, direct, _ = member
    run = shear_rolling.export(folder, tmp_path / "run", log=lambda m: None)
    with np.load(run / "analysis.npz") as z:
        steps = event_window({k: z[k] for k in z.files})["steps"]
    got = shear_rolling.event_frames(folder, steps[0] - 1, steps[-1])
    doc = shear_event.report(run, frames=got, n_perm=200)
    start = json.loads((run / "analysis.json").read_text())["parameters"]["gamma0"]
    assert main(["shear", "analyze", "--out", str(direct), "--gamma0", repr(start), "--force",
                 "--no-progress", "--no-spectra"]) == 0
    want = shear_event.report(direct, n_perm=200)
    assert doc["statements"] and doc["event"] == want["event"]
    _same(doc["statements"], want["statements"], "statements")


def test_export_is_a_finished_sweep_member(member, tmp_path):
    import shear_sweep_paper
    folder, _, params = member
    shear_rolling.export(folder, tmp_path / "runs" / shear_rolling.label(params),
                         log=lambda m: None)
    done, todo = shear_sweep_paper.members(tmp_path)
    assert list(done) == [(0.7, 0)] and todo == []
    tables, summary, steady = shear_sweep_paper.analysed(done[0.7, 0], log=None)
    rec = json.loads((done[0.7, 0] / "analysis.json").read_text())
    assert rec["parameters"]["gamma0"] == steady["window_from"] >= params["gamma0"]
    assert summary["n_phases"] > 0


def test_export_is_read_by_the_paper_page(member, tmp_path):
    import shear_paper
    folder, _, _ = member
    run = shear_rolling.export(folder, tmp_path / "run", log=lambda m: None)
    md = tmp_path / "page" / "shear_paper.md"
    assert shear_paper.main([str(run), "--md", str(md)]) == 0
    doc = json.loads(md.with_suffix(".json").read_text())
    res, _, _ = shear_rolling.analysis(folder, doc["summary"]["gamma0"])
    assert doc["complete"] and doc["summary"]["n_phases"] == res.summary["n_phases"]


def test_a_running_member_is_reported_as_far_as_it_got(member, tmp_path):
    import shutil

    import shear_sweep_paper
    folder, _, params = member
    running = tmp_path / "store" / folder.name
    shutil.copytree(folder, running)
    rec = json.loads((running / "member.json").read_text())
    rec["parameters"]["strain"] = 0.02                         # half way: 100 of 200 frames
    (running / "member.json").write_text(json.dumps(rec))
    sweep = tmp_path / "sweep"
    shear_rolling.export(running, sweep / "runs" / shear_rolling.label(params),
                         log=lambda m: None)
    assert not (sweep / "runs" / shear_rolling.label(params) / "shear.json").exists()
    doc = shear_sweep_paper.report(sweep, tmp_path / "p.md", log=lambda m: None)
    assert doc["done"] == [] and doc["partial"] == [[0.7, 0]]
    (r,) = doc["rates"]["0.7"]
    assert r["partial"] and r["strain"] == pytest.approx(0.01)
    text = (tmp_path / "p.md").read_text()
    assert "partial (the scale reached): mu_s = 0.7 seed 0 to strain 0.0100" in text


def test_the_sweep_claim_states_the_scale_reached(member, tmp_path):
    import shutil

    from claims import shear_sweep_paper as claim
    folder, _, _ = member
    shutil.copytree(folder, tmp_path / "store" / "mus0.7_seed0")
    res = claim.sweep_paper(tmp_path / "store", tmp_path / "p.md")
    v = res.values
    assert v["done"] == [[0.7, 0]] and v["partial"] == [] and res.units
    assert [x["id"] for x in v["sec4"]] == [f"4.{i}" for i in range(1, 9)]
    said = claim.verdict(v)
    words = [x["verdict"] for x in v["sec4"]]
    assert said.label == ("not comparable" if set(words) == {"not comparable"} else
                          "disagrees" if "disagrees" in words else
                          "agrees" if set(words) == {"agrees"} else "undecided")
    none = {**v, "sec4": [{**x, "verdict": "not comparable"} for x in v["sec4"]]}
    assert claim.verdict(none).label == "not comparable"
    one = {**v, "sec4": [{**x, "verdict": "agrees"} for x in v["sec4"]]}
    one["sec4"][3]["verdict"] = "disagrees"
    assert claim.verdict(one).label == "disagrees"
    assert "mu_s = 0.7 seed 0 to strain 0.0100; mu_s = 0.5 not started" in said.detail
    assert "per step (paper 0.323 per step)" in claim.show(v)
    nothing = {**v, "rates": {"0.7": [{**v["rates"]["0.7"][0], "rate": None}]}}
    assert "mu_s = 0.7: no step past gamma0 yet (paper 0.323 per step)" in claim.show(nothing)
    assert "Sweep: the committed segmented members of `validation/runs/shear_rolling/`" in \
        (tmp_path / "p.md").read_text()        # the store named, not the temporary export
    assert claim.check(v, v) == (True, "identical")
    grown = json.loads(json.dumps(v))
    grown["rates"]["0.7"][0]["strain"] = 0.02
    assert claim.check(v, grown) == (True, "the store reached further (0.7 to strain 0.01 -> "
                                     "0.02): new numbers, judged afresh")
    other = json.loads(json.dumps(v))
    other["rates"]["0.7"][0]["rate"] += 0.01
    assert claim.check(v, other) == (False, "the same store gave other numbers")


def test_a_store_of_other_parameters_or_other_code_is_refused(member, monkeypatch):
    folder, _, _ = member
    store = folder.parent
    with pytest.raises(SystemExit, match="other parameters"):
        shear_rolling.run(0.7, preset="quick", segment=30, store=store, log=lambda m: None,
                          overrides={**TINY, "strain": 0.02, "n": 41})
    monkeypatch.setattr(shear_rolling._stamped, "stored", lambda path: None)
    with pytest.raises(SystemExit, match="seg_0000.npz: made by other code.*--restart"):
        shear_rolling.run(0.7, preset="quick", segment=30, store=store, log=lambda m: None,
                          overrides={**TINY, "strain": 0.02})


def test_a_larger_strain_extends_the_member_and_it_stays_extended(member, tmp_path):
    import shutil
    folder, _, _ = member
    store = tmp_path / "store"
    shutil.copytree(folder, store / folder.name)
    quiet = dict(preset="quick", segment=30, store=store, log=lambda m: None, max_hours=1e-12)
    # stopped at once (max_hours spent): only member.json learns the strain
    assert shear_rolling.run(0.7, overrides={**TINY, "strain": 0.5}, **quiet) == 100
    extended = json.loads((store / folder.name / "member.json").read_text())
    assert extended["parameters"]["strain"] == 0.5 > shear_rolling.member_params(
        0.7, 0, "quick", **TINY)["strain"]
    shear_rolling.run(0.7, overrides=TINY, **quiet)              # no strain named: kept
    assert json.loads((store / folder.name / "member.json").read_text()) == extended
    with pytest.raises(SystemExit, match="holds frames to 100, past strain 0.005 .*--strain 0.5"):
        shear_rolling.run(0.7, overrides={**TINY, "strain": 0.005}, **quiet)


@pytest.mark.parametrize("argv, said", [
    (["--strain", "0"], "--strain must be > 0"),
    (["--strain", "1e-9"], "strain = 1e-09 must be >= dgamma"),
])
def test_a_bad_strain_is_a_usage_error(argv, said, tmp_path, capsys):
    with pytest.raises(SystemExit) as exc:
        shear_rolling.main(["run", "--mus", "0.7", "--preset", "quick", "--store",
                            str(tmp_path), *argv])
    assert exc.value.code == 2 and said in capsys.readouterr().err


def test_series_to_a_strain_reads_only_the_segments_that_reach_it(member):
    folder, _, _ = member
    whole, *_ = shear_rolling.arrays(folder)
    series, units, used = shear_rolling.series_to(folder, 0.005)
    # frames 0..50 lie in seg_0000 (0..30) and seg_0001 (31..50): strain 0.005 is frame 50
    assert [f.name for f in used] == ["seg_0000.npz", "seg_0001.npz"] and units
    assert np.array_equal(series, whole[:51])
    with pytest.raises(SystemExit, match=r"reaches strain 0.01000, not 0.02; .*--strain 0.02"):
        shear_rolling.series_to(folder, 0.02)


def test_the_paper_window_claim_judges_the_halves(member, tmp_path):
    """The claim on the tiny member (window 0.002-0.01): the halves' means and errors as
    computed by hand, and the verdict's two conditions each able to fail."""
    import shutil

    from claims import shear_sweep_paper as claim
    from fricstab.analysis.autocorrelation import integrated_time
    folder, _, _ = member
    shutil.copytree(folder, tmp_path / "store" / "mus0.7_seed0")
    v = claim.paper_window(tmp_path / "store", (0.002, 0.01)).values
    series, *_ = shear_rolling.arrays(folder)
    x = series[series[:, 1] >= 0.002, 4]
    a, b = np.array_split(x, 2)
    se = [p.std() * np.sqrt(integrated_time(p) / p.size) for p in (a, b)]
    assert v["frames"] == x.size and v["halves"][1]["mean"] == b.mean()
    assert v["distance"] == pytest.approx(abs(b.mean() - a.mean()) / np.hypot(*se), rel=1e-12)
    steady = {"steady": True, "start": 0.002}
    good = {**v, "distance": 1.5, "steady": steady}
    assert claim.window_verdict(good).label == "agrees"
    assert claim.window_verdict({**good, "distance": 2.5}).label == "disagrees"
    assert claim.window_verdict({**good, "steady": {**steady, "start": 0.004}}).label == "disagrees"
    assert claim.window_verdict({**good, "steady": {"steady": False, "start": None}}).label \
        == "disagrees"
    assert "combined s.e." in claim.window_show(v)


def test_the_memory_claim_reads_the_member_up_to_its_span(member, tmp_path):
    import shutil

    from claims import shear_sweep_paper as claim
    folder, _, _ = member
    shutil.copytree(folder, tmp_path / "store" / "mus0.7_seed0")
    v = claim.member_memory(tmp_path / "store", (0.002, 0.01), (0.002, 0.004)).values
    series, *_ = shear_rolling.series_to(folder, 0.01)
    assert {k: v[k] for k in ("rows", "slope", "needed")} == {
        k: claim.memory_of(series[:, 1], series[:, 4], (0.002, 0.01), (0.002, 0.004))[k]
        for k in ("rows", "slope", "needed")}
    assert v["segments"] == 4 and "a steady window needs" in claim.memory_show(v)
    # the verdict's words follow the library's call (memory_growth, tests/test_stationarity.py)
    assert "memory resolved" in str(claim.memory_verdict({**v, "resolved": True}))
    said = claim.memory_verdict({**v, "resolved": False})
    assert said.label == "measured" and "lower bound" in str(said)


def _in_store(member, tmp_path):
    """The tiny member copied into ``tmp_path / "store"`` as the paper-preset member; its folder."""
    import shutil
    folder, _, _ = member
    shutil.copytree(folder, tmp_path / "store" / "mus0.7_seed0")
    return folder


def test_the_scaling_claim_reads_the_member_and_says_when_its_test_is_blind(member, tmp_path):
    """The long-memory claim on the tiny member: its exponent and its mean's error are the
    library's on the same frames, and the verdict says the test is blind only where it
    accepts a window whose tau rises."""
    from claims import shear_sweep_paper as claim
    from fricstab.analysis.long_memory import aggregated_variance
    folder = _in_store(member, tmp_path)
    span, lengths = (0.002, 0.01), (0.0005, 0.001, 0.002)
    v = claim.member_scaling(tmp_path / "store", span, lengths, (0.0, 0.004)).values
    series, *_ = shear_rolling.series_to(folder, 0.01)
    agg = aggregated_variance(series[:, 1], series[:, 4], lengths, span)
    assert v["hurst"] == agg["hurst"] and v["rows"] == agg["rows"]
    last = agg["rows"][-1]
    h = min(agg["hurst"], 1.0)
    assert v["se"] == pytest.approx(np.sqrt(last["var"]) * ((span[1] - span[0]) / last["length"])
                                    ** (h - 1.0), rel=1e-12)
    assert [p["rise"] for p in v["power"]] == list(claim.SCALING_RISES)
    # the core-hours to each strain add the segments' stamps up to it (all 4 reach 0.01)
    assert list(v["core_hours_to"]) == ["0.004", "0.2", "0.01"]
    assert v["core_hours_to"]["0.004"] < v["core_hours_to"]["0.01"] == v["core_hours_to"]["0.2"]
    assert "H = " in claim.scaling_show(v)
    blind = {**v, "tests": {**v["tests"], "paper_window": {
        **v["tests"]["paper_window"], "steady": True, "drift_over_std": 2.9, "p": 0.08}},
        "power": [{"rise": 1.0, "rejected": 0.1}, {"rise": 3.0, "rejected": 0.55}]}
    said = str(claim.scaling_verdict(blind))
    # the power quoted is that at the smallest tabulated rise above the window's 2.9 std
    assert "does not show a steady state" in said and "3 std in only 55 % of series" in said
    sees = {**blind, "tests": {**blind["tests"], "paper_window": {
        **blind["tests"]["paper_window"], "steady": False, "p": 0.001}}}
    assert "it rejects the paper's window" in str(claim.scaling_verdict(sees))
    assert claim.scaling_verdict(sees).label == "measured"


def test_the_rate_claim_counts_the_phases_as_the_analysis_does(member, tmp_path):
    """The member's phase rate per window: the analysis' phases (find_phases on the steps
    whose frames lie in the window), its error on the phase starts' scaling, and a verdict
    that parts when the windows do."""
    from claims import shear_sweep_paper as claim
    from fricstab.analysis.shear_phases import find_phases
    folder = _in_store(member, tmp_path)
    span, lengths = (0.002, 0.01), (0.0005, 0.001, 0.002)
    v = claim.member_rate(tmp_path / "store", span, lengths, (0.0, 0.004)).values
    series, *_ = shear_rolling.series_to(folder, 0.01)
    strain, tau = series[:, 1], series[:, 4]
    ok = np.zeros(strain.size, bool)
    ok[1:] = (strain[:-1] >= 0.0) & (strain[1:] <= 0.004)
    assert v["windows"]["paper_window"]["steps"] == ok.sum() > 30
    assert v["windows"]["paper_window"]["rate"] == len(find_phases(tau, ok)) / ok.sum()
    assert v["paper"] == pytest.approx(42_000 / 130_000)
    assert "s.e. from the paper's 0.323" in claim.rate_show(v)
    far, near = {"distance": 3.0}, {"distance": 1.0}
    assert claim.rate_verdict({"windows": {"a": near, "b": near}}).label == "agrees"
    assert claim.rate_verdict({"windows": {"a": far, "b": far}}).label == "disagrees"
    assert claim.rate_verdict({"windows": {"a": near, "b": far}}).label == "undecided"


def test_the_seeds_claim_judges_only_once_enough_seeds_cover_the_span(member, tmp_path):
    """The claim across seeds: a seed still running is listed with the strain it reached and
    enters no number; the test runs once ``min_seeds`` seeds cover the span; each seed's
    numbers are the analysis' on its own frames; the verdict follows the test and the rate."""
    import shutil

    from claims import shear_seeds as claim
    from fricstab.analysis.shear_phases import find_phases
    folder = _in_store(member, tmp_path)
    store, span = tmp_path / "store", (0.002, 0.01)
    part = store / "mus0.7_seed1"
    part.mkdir()
    for f in (folder / "member.json", *shear_rolling.segments(folder)[:2]):
        shutil.copy(f, part)                 # frames 0..50: strain 0.005 of the span's 0.01
    v = claim.member_seeds(store, span, min_seeds=3).values
    assert [m["seed"] for m in v["members"]] == [0, 1] and v["test"] is None
    assert "mean" not in v["members"][1]
    assert v["members"][1]["reached"] == pytest.approx(0.005, rel=1e-9)
    # the record's check: the same segments give the same numbers; a seed that ran further
    # is stated as such, not as a failure to reproduce
    assert claim.seeds_check(v, claim.member_seeds(store, span, min_seeds=3).values)[0]
    shutil.copy(shear_rolling.segments(folder)[2], part)
    grown = claim.seeds_check(v, claim.member_seeds(store, span, min_seeds=3).values)
    with np.load(shear_rolling.segments(folder)[2]) as z:
        further = float(z["series"][-1, 1])
    assert grown[0] and f"seed 1 to strain 0.005 -> {further:.4g}" in grown[1]
    assert "store reached further" in grown[1] and further > 0.005
    said = claim.seeds_verdict(v)
    assert said.label == "not comparable"
    assert "1 of 3 seeds reach strain 0.01 (seed 1 at strain 0.0050)" in str(said)
    series, *_ = shear_rolling.series_to(folder, 0.01)
    strain, tau = series[:, 1], series[:, 4]
    ok = claim.inside(strain, *span)
    assert v["members"][0]["steps"] == ok.sum() > 60
    assert v["members"][0]["rate"] == len(find_phases(tau, ok)) / ok.sum()
    assert v["members"][0]["mean"] == tau[(strain >= 0.002) & (strain <= 0.01)].mean()
    # three seeds over the span: the tiny member run again with seeds 1 and 2
    shutil.rmtree(part)
    for s in (1, 2):
        shear_rolling.run(0.7, seed=s, overrides={**TINY, "strain": 0.01}, preset="quick",
                          segment=50, store=tmp_path / "runs", log=lambda m: None)
        shutil.copytree(tmp_path / "runs" / f"quick-mus0.7_seed{s}", store / f"mus0.7_seed{s}")
    v = claim.member_seeds(store, span, min_seeds=3).values
    assert v["test"]["members"] == 3 and v["rate"]["se"] > 0
    rates = [m["rate"] for m in v["members"]]
    assert len(set(rates)) == 3 and v["rate"]["mean"] == pytest.approx(np.mean(rates), rel=1e-12)
    assert "Across 3 seeds" in claim.seeds_show(v)
    # the verdict: a drift across seeds leaves it undecided; else the rate against the paper's
    # (the paper's 0.323: 0.32 +- 0.01 lies 0.3 s.e. off, 0.25 +- 0.01 7.3 s.e.)
    near, far = ({**v, "rate": {"mean": m, "se": 0.01}} for m in (0.32, 0.25))
    assert claim.seeds_verdict(near).label == "agrees"
    assert claim.seeds_verdict(far).label == "disagrees"
    drifts = {**near, "test": {**near["test"], "steady": False, "p": 0.01}}
    assert claim.seeds_verdict(drifts).label == "undecided"
    assert "still drifts across seeds" in str(claim.seeds_verdict(drifts))
