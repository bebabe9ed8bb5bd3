"""The claims registry: RESULTS.md is what it writes, records are sound and fresh.

CI runs this module: it fails when RESULTS.md or a marked block of another
page differs from what the registry renders, when a record was edited by
hand, when the code a minutes- or hours-scale claim depends on changed since
it was recorded (naming the claim and the command that regenerates it), and
when a seconds-tier claim recomputed here moves beyond its stated tolerance.
"""

import json
import shutil
import sys
from pathlib import Path

import pytest

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

from claims import all_claims, jobs, records, render  # noqa: E402
from claims.fingerprint import ROOT, changes, source_hash  # noqa: E402
from claims.runner import recompute, values_of  # noqa: E402

import reproduce  # noqa: E402

JOBS = jobs()
SECONDS = [j for j, cs in JOBS.items() if cs[0].tier == "seconds"]


def test_the_packing_section_puts_the_paper_scale_first_and_labels_the_checks():
    """Ishima's rows: the paper-scale claims form the first table; the small-packing checks
    come last under a heading that says they are not reproductions, and every paper-scale
    claim that heading names for a figure exists in the first table."""
    import re
    parts = render._parts("packing", [c for c in all_claims() if c.section == "packing"])
    assert parts[0][0] == "At the paper's scale"
    first = {c.name for c in parts[0][2]}
    assert first and all(n.startswith("packing.paper_") and not n.endswith("_n1024")
                         for n in first)
    assert "not reproductions" in parts[-1][0]
    assert not any(c.name.startswith("packing.paper_") for c in parts[-1][2])
    named = re.findall(r"`(packing\.paper_\w+)`", parts[-1][1])
    assert len(named) >= 9 and set(named) <= first


def test_a_claim_that_no_part_takes_is_refused(monkeypatch):
    from claims import section_module
    monkeypatch.setattr(section_module("packing"), "PARTS", [("only", "x", lambda c: False)])
    with pytest.raises(ValueError, match="no part of section packing takes it"):
        render._parts("packing", [c for c in all_claims() if c.section == "packing"])


def test_results_md_is_what_the_registry_writes():
    diff = render.differences()
    assert not diff, f"{diff}: regenerate with python validation/reproduce.py --write"


def test_every_claim_below_hours_is_recorded():
    missing = [j for j, cs in JOBS.items() if cs[0].tier != "hours" and records.load(j) is None]
    assert not missing, f"never recorded: {missing}"


def test_records_are_sound():
    problems = [p for j in JOBS if (rec := records.load(j)) for p in records.verify(rec)]
    assert not problems, "\n".join(problems)


def test_no_long_claim_is_stale():
    stale = reproduce.stale_messages()
    assert not stale, "\n".join(stale)


@pytest.mark.parametrize("job", SECONDS)
def test_seconds_claim_recomputes_within_tolerance(job):
    _recomputes_within_tolerance(job)


def _recomputes_within_tolerance(job):
    rec = records.load(job)
    if rec is None:
        pytest.fail(f"{job} never recorded")
    # the job's outputs put back afterwards: this machine's rendering of a figure differs in
    # bytes from the recorded one, and the next test_records_are_sound would call it edited
    old, new = values_of(rec), recompute(JOBS[job][0], keep=tuple(rec.get("outputs", {})))
    for c in JOBS[job]:
        ok, text = c.check(old, new)
        assert ok, f"{c.name}: {text}"


@pytest.mark.slow   # reads ~600 pieces of the committed store: ~20 s a job when every piece
#                     is fresh (test_no_long_claim_is_stale says so), hours where one is not
@pytest.mark.parametrize("job", ["packing.ishima_paper", "packing.ishima_paper_1024"])
def test_the_ishima_paper_tiers_regenerate_from_the_committed_store(job):
    """Ishima's paper-scale tiers (hours): regenerated from the committed store, every claim
    within its tolerance of the record."""
    _recomputes_within_tolerance(job)


def test_every_verdict_is_computed():
    """A verdict comes from the claim's function of the recorded values."""
    for c in all_claims():
        rec = records.load(c.job_name)
        if rec is not None:
            v = c.judge(values_of(rec))
            assert v.label in {"agrees", "disagrees", "undecided", "meets", "fails",
                               "measured", "not comparable"}, (c.name, v)


# ------------------------------------------------------------ the checks can fail

def _copy_tree(fp, tmp):
    for rel in (list(fp["modules"]) + list(fp.get("functions", {})) + [fp["claim"]["module"]]
                + list(fp["inputs"])):
        if not (ROOT / rel).exists():
            continue    # a missing input: test_no_long_claim_is_stale names it and its command
        dst = tmp / rel
        dst.parent.mkdir(parents=True, exist_ok=True)
        shutil.copy(ROOT / rel, dst)


def _a_long_record():
    for j, cs in JOBS.items():
        rec = records.load(j)
        if rec is not None and cs[0].tier != "seconds":
            return j, rec
    # before any long claim is recorded, a seconds claim's record serves the same check
    j = SECONDS[0]
    return j, records.load(j)


def test_changing_a_dependency_marks_the_claim_stale(tmp_path):
    job, rec = _a_long_record()
    fp = rec["fingerprint"]
    _copy_tree(fp, tmp_path)
    assert changes(fp, root=tmp_path) == []
    # a docstring or comment changes nothing that runs: still fresh
    target = next(m for m in fp["modules"] if m.startswith("fricstab/engine/")
                  or m.startswith("fricstab/laws/"))
    path = tmp_path / target
    text = path.read_text()
    path.write_text("# a comment\n" + text.replace('"""', '"""An edited docstring. ', 1))
    assert changes(fp, root=tmp_path) == []
    # a changed function body: stale, and the path is named
    path.write_text(text + "\n\ndef _added_by_the_test():\n    return 1\n")
    assert target in changes(fp, root=tmp_path)
    # the claim's own compute changed: stale
    path.write_text(text)
    own = tmp_path / fp["claim"]["module"]
    src = own.read_text()
    name = JOBS[job][0].compute.__name__
    own.write_text(src.replace(f"def {name}(", f"def {name}(_unused=None, ", 1))
    assert any(fp["claim"]["module"] in c for c in changes(fp, root=tmp_path))


def test_ci_names_the_stale_claim_and_its_command(tmp_path):
    """The check CI runs turns red for a long claim whose code changed, naming the claim
    and the command that regenerates it."""
    job, rec = _a_long_record()
    for j in JOBS:                      # a checkout holding every recorded job's code
        if (r := records.load(j)) is not None:
            _copy_tree(r["fingerprint"], tmp_path)
    assert job not in reproduce.stale_jobs(root=tmp_path)
    target = next(m for m in rec["fingerprint"]["modules"] if m.startswith("fricstab/"))
    (tmp_path / target).write_text((tmp_path / target).read_text()
                                   + "\n\ndef _added_by_the_test():\n    return 1\n")
    assert target in reproduce.stale_jobs(root=tmp_path)[job]
    if JOBS[job][0].tier != "seconds":
        lines = reproduce.stale_messages(root=tmp_path)
        mine = [x for x in lines if f"--claim {JOBS[job][0].name}" in x]
        assert mine and JOBS[job][0].name in mine[0] and target in mine[0]


def test_a_hand_edited_record_fails(tmp_path):
    job, rec = _a_long_record()
    assert records.verify(rec) == []
    edited = json.loads(json.dumps(rec))
    first = next(iter(edited["values"]))
    edited["values"][first] = "edited by hand"
    assert any("digest" in p for p in records.verify(edited))


def test_a_hand_edited_results_md_fails(monkeypatch, tmp_path):
    fake = tmp_path / "RESULTS.md"
    fake.write_text(render.results_md().replace("| ", "| 1.0 ", 1))
    monkeypatch.setattr(render, "RESULTS", fake)
    monkeypatch.setattr(render, "pages", lambda: [])
    assert render.differences() != []


def test_source_hash_ignores_docstrings_not_code():
    a = 'def f(x):\n    """Doc."""\n    return x + 1\n'
    assert source_hash(a) == source_hash(a.replace("Doc.", "Other doc.") + "# comment\n")
    assert source_hash(a) != source_hash(a.replace("x + 1", "x + 2"))


# ---------------------------------------------------------------- function-level fingerprints

_DEMO = """
import math

SCALE = 2.0


def used(x):
    return helper(x) * SCALE


def helper(x):
    return math.sqrt(x)


def unused(x):
    return -x


class Box:
    size = 3

    def area(self):
        return self.size ** 2

    def volume(self):
        return self.size ** 3
"""

_SECTION = """
def compute():
    import _fp_demo
    return _fp_demo.used(4.0) + _fp_demo.Box().area()
"""


def _demo_fingerprint(tmp_path, spawn=False, git=False):
    """A module and a section module under a scratch checkout, a claim computed under
    the tracer, and its fingerprint."""
    import importlib

    from claims.core import Claim
    from claims.fingerprint import Tracer, fingerprint
    (tmp_path / "validation" / "claims").mkdir(parents=True)
    (tmp_path / "validation" / "_fp_demo.py").write_text(_DEMO)
    (tmp_path / "validation" / "claims" / "fp_section.py").write_text(_SECTION)
    sys.path.insert(0, str(tmp_path / "validation"))
    sys.path.insert(0, str(tmp_path / "validation" / "claims"))
    try:
        for m in ("_fp_demo", "fp_section"):
            sys.modules.pop(m, None)
        section = importlib.import_module("fp_section")
        claim = Claim("demo.x", "demo", "x", "minutes", "x", section.compute, str, "t",
                      lambda a, b: (True, ""))
        with Tracer() as tracer:
            claim.compute()
            import subprocess
            if spawn:
                subprocess.run([sys.executable, "-c", "pass"], check=True)
            if git:   # what a record's revision costs: not a process that runs our code
                subprocess.run(["git", "--version"], check=True, capture_output=True)
        return fingerprint(claim, root=tmp_path, tracer=tracer)
    finally:
        sys.path.remove(str(tmp_path / "validation"))
        sys.path.remove(str(tmp_path / "validation" / "claims"))
        for m in ("_fp_demo", "fp_section"):
            sys.modules.pop(m, None)


def _edit(path, old, new):
    text = path.read_text()
    assert old in text
    path.write_text(text.replace(old, new, 1))
    return text


@pytest.mark.parametrize("old, new, stale", [
    # a function that ran, or one it called: stale, named
    ("return math.sqrt(x)", "return math.sqrt(x) + 0", "helper"),
    ("return helper(x) * SCALE", "return helper(x) * SCALE * 1", "used"),
    ("return self.size ** 2", "return self.size * self.size", "Box.area"),
    # what runs at import: stale
    ("SCALE = 2.0", "SCALE = 2.5", "<frame>"),
    ("import math", "import math, cmath", "<frame>"),
    ("    size = 3", "    size = 4", "<frame>"),
    # a new method could override one that ran (a dataclass hook, say): stale
    ("    def volume(self):", "    def __eq__(self, o):\n        return False\n\n"
                             "    def volume(self):", "<frame>"),
    # a new function that shadows a binding: stale
    ("def unused(x):", "def math(x):\n    return x\n\n\ndef unused(x):", "<frame>"),
    # a function that did not run, edited or added, a method that did not run: fresh
    ("return -x", "return x", None),
    ("def unused(x):", "def added(y):\n    return y\n\n\ndef unused(x):", None),
    ("return self.size ** 3", "return 0", None),
])
def test_function_level_fingerprint(tmp_path, old, new, stale):
    fp = _demo_fingerprint(tmp_path)
    mod = "validation/_fp_demo.py"
    assert set(fp["functions"][mod]) == {"<frame>", "used", "helper", "Box.area"}
    assert changes(fp, root=tmp_path) == []
    _edit(tmp_path / mod, old, new)
    ch = changes(fp, root=tmp_path)
    if stale is None:
        assert ch == []
    else:
        assert len(ch) == 1 and ch[0].startswith(mod) and stale in ch[0], ch


def test_a_computation_that_starts_a_process_counts_modules_whole(tmp_path):
    fp = _demo_fingerprint(tmp_path, spawn=True)
    assert "functions" not in fp and "validation/_fp_demo.py" in fp["modules"]
    _edit(tmp_path / "validation" / "_fp_demo.py", "return -x", "return x")
    assert changes(fp, root=tmp_path) == ["validation/_fp_demo.py"]


def test_another_trace_function_counts_modules_whole(tmp_path, monkeypatch):
    """Code run while someone else held sys.settrace went unseen: whole modules."""
    from claims.fingerprint import Tracer
    with Tracer() as tracer:
        old = sys.gettrace()
        sys.settrace(None)
        sys.settrace(old)
    assert tracer.lost and sys.gettrace() is None


def test_a_thread_started_while_tracing_is_traced_not_lost():
    """A thread installs the tracer's own hook through sys.settrace (threading's
    bootstrap): its calls are seen, so it must not count as another trace function
    (it did, and made every job that started a progress thread whole-module)."""
    import threading

    from claims.fingerprint import Tracer

    def in_thread():
        return 1

    with Tracer() as tracer:
        t = threading.Thread(target=in_thread)
        t.start()
        t.join()
    assert not tracer.lost
    assert in_thread.__code__ in tracer.codes.values()


def test_git_is_not_a_process_that_hides_code(tmp_path):
    fp = _demo_fingerprint(tmp_path, git=True)
    assert "validation/_fp_demo.py" in fp["functions"]


def test_numba_modules_and_tests_count_whole():
    from claims.fingerprint import whole_module
    assert whole_module("fricstab/x.py", "from numba import njit\n")
    assert whole_module("fricstab/x.py", "from .._numba import njit\n")
    assert whole_module("tests/test_x.py", "") and whole_module("validation/test_x.py", "")
    assert not whole_module("fricstab/cli/x.py", "import numpy as np\n")
    assert not whole_module("fricstab/cli/x.py", "def version():\n    import numba\n")
    # every numba module of the package is hashed whole in a recorded fingerprint
    for job in JOBS:
        rec = records.load(job)
        if rec is not None and "functions" in rec["fingerprint"]:
            for m in rec["fingerprint"]["functions"]:
                assert not whole_module(m, (ROOT / m).read_text()), (job, m)


def test_a_sigma_verdict_within_its_own_spread_is_undecided():
    """d = |ours - paper| / combined; over new samples of ours d has sd m = ours_err /
    combined.  Agree if every d + z m <= 2, disagree if some d - z m > 2 (z = 0.674: a
    flip with probability 1/4), else undecided; a value of ours without sampling error
    keeps the plain rule (m = 0)."""
    from claims.core import sigma_verdict
    assert sigma_verdict([(2.1, 0.0, 0.0, 1.0)]).label == "disagrees"     # m = 0
    assert sigma_verdict([(1.9, 0.0, 0.0, 1.0)]).label == "agrees"
    # ours_err = paper_err = 1: combined 1.414, z m = 0.477; 2.5 / 1.414 = 1.77: 1.77 + 0.48
    v = sigma_verdict([(2.5, 1.0, 0.0, 1.0)])
    assert v.label == "undecided" and v.ok is None and "within 0.5 of 2" in v.detail
    assert sigma_verdict([(2.1, 1.0, 0.0, 1.0)]).label == "agrees"       # 1.48 + 0.48
    assert sigma_verdict([(4.0, 1.0, 0.0, 1.0)]).label == "disagrees"    # 2.83 - 0.48
    assert sigma_verdict([(3.5, 1.0, 0.0, 1.0)]).label == "undecided"    # 2.47 - 0.48
    # one decided disagreement decides the whole; an undecided item blocks "agrees"
    assert sigma_verdict([(0.5, 1.0, 0.0, 1.0), (4.0, 1.0, 0.0, 1.0)]).label == "disagrees"
    assert sigma_verdict([(0.5, 1.0, 0.0, 1.0), (2.5, 1.0, 0.0, 1.0)]).label == "undecided"


def test_a_comparison_under_tied_readings_that_differ_is_undecided():
    """chain.conv_*: the word under the reading with the most agreements; two readings tied
    for the most with different words leave it undecided, with the same word keep it."""
    from claims.chain_conventions import _verdict

    def values(a_agrees, b_agrees, best):
        row = lambda ok: {"what": "onset", "ours": "x", "distance": "1.0 sigma",  # noqa: E731
                          "agrees": ok, "undecided": False}
        return {"best": best, "readings": {"a": {"rows": [row(a_agrees)]},
                                           "b": {"rows": [row(b_agrees)]}}}
    assert _verdict("onset")(values(True, False, ["a", "b"])).label == "undecided"
    assert _verdict("onset")(values(True, True, ["a", "b"])).label == "agrees"
    assert _verdict("onset")(values(False, True, ["a"])).label == "disagrees"
    assert "tied" in _verdict("onset")(values(True, False, ["a", "b"])).detail


def test_chaotic_runs_over_seeds_are_judged_as_samples():
    """chain.fig3_*: a statement that every seed makes is judged exactly; one the seeds
    split on is undecided.  'About 10^-5' is judged in log10 with half a decade as the
    paper's error: ours at 10^-5 exactly agrees, three decades away disagrees, and the
    geometric mean of values 1e-6 and 1e-4 is 1e-5."""
    import math

    from claims.chain import _decade_verdict, _geo, _seeds_verdict
    runs = lambda *b: {"k": {"runs": [{"ok": x} for x in b]}}  # noqa: E731
    assert _seeds_verdict(runs(True, True), ("k",), lambda r: r["ok"], True, "x").label \
        == "agrees"
    assert _seeds_verdict(runs(False, False), ("k",), lambda r: r["ok"], True, "x").label \
        == "disagrees"
    v = _seeds_verdict(runs(True, False, True), ("k",), lambda r: r["ok"], True, "x")
    assert v.label == "undecided" and "2 of 3 runs" in v.detail
    g, e = _geo([1e-6, 1e-4])
    assert math.isclose(g, 1e-5) and math.isclose(e, 1.0)  # sd sqrt(2) over sqrt(2)
    assert math.isclose(_geo([3e-5])[0], 3e-5) and _geo([3e-5])[1] == 0.0
    assert _decade_verdict([(1e-5, 0.0)], 1e-5, "10^-5").label == "agrees"
    assert _decade_verdict([(1e-8, 0.0)], 1e-5, "10^-5").label == "disagrees"
    # 1.2 decades away with 0.6 decades of its own error: within its spread of the line
    assert _decade_verdict([(10 ** -3.8, 0.6)], 1e-5, "10^-5").label == "undecided"
