"""Claims of section engine (see claims/__init__.py): what the tests show of the engine,
the product surface and the results' freshness."""

from .core import Claim, Result, Verdict, bound_verdict

HEADING = 'The engine, the product surface and the tests'
INTRO = ("System-level proofs of every law in every scene, the pinned regression tier, and the product's promises (records, resume, bad input, figures), each shown by a committed test run in the claim's own process (`validation/claims/_testrun.py`): the claim records what the test showed.")

PROOF_LAWS = ("hertz", "charan", "ishima", "lee_hurley", "linear", "ishima_fi", "charan_fi",
              "linear_fi")
PROOF_SCENES = {"chain": "tests/test_chain_proof.py", "packing": "tests/test_packing_proof.py",
                "shear": "tests/test_shear_proof.py"}
HYPOTHESIS_SEED = "20261121"

#: the test files of the minutes-tier job, and the tests of each claim (by id fragment)
TEST_FILES = ("tests/test_matrix.py", "tests/test_threads.py", "tests/test_result_records.py",
              "tests/test_checkpoint.py", "tests/test_shear_cli.py", "tests/test_ensemble.py",
              "tests/test_named_failures.py", "tests/test_packing_rundir.py",
              "tests/test_chain_rundir.py", "tests/test_figures.py", "tests/test_docstrings.py",
              "tests/test_numerics.py", "tests/test_lee_hurley.py",
              "validation/test_regression.py")
TEST_SELECTION = ("not (test_shear_cli and not (signal or sigkill)) "
                  "and not (test_numerics and not fused) and not (test_lee_hurley and not lanes)")


# ------------------------------------------------------------ hours: the system-level proofs

def system_proof():
    """The three proof modules under the thorough hypothesis profile (2,000 examples per
    law where the module does not fix its own count), seeded; the worst errors each
    module's ``WORST`` collected, and the test outcomes."""
    import sys

    from ._testrun import run_tests, summary
    status, tests = run_tests(["-s", f"--hypothesis-seed={HYPOTHESIS_SEED}",
                               *PROOF_SCENES.values()],
                              env={"FRICSTAB_HYPOTHESIS_PROFILE": "thorough"})
    worst = {}
    for scene, path in PROOF_SCENES.items():
        mod = sys.modules[path[:-3].replace("/", ".")]
        worst[scene] = {law: dict(w) for law, w in mod.WORST.by_law.items()}
    return Result({"status": status, "worst": worst,
                   "tests": {scene: summary(tests, [path]) for scene, path in PROOF_SCENES.items()}},
                  seeds=(int(HYPOTHESIS_SEED),))


def _proof_show(v, scene):
    w = v["worst"][scene]
    text = ", ".join(f"{law} {w[law]['complex_step']:.1e}" for law in PROOF_LAWS)
    cases = sorted({w[law]["cases"] for law in PROOF_LAWS})
    text += f" ({'/'.join(f'{c:,}' for c in cases)} states per law); central differences within " \
            f"their model (largest error / model {max(w[law]['central_over_bound'] for law in PROOF_LAWS):.2f})"
    zm = max(w[law]["zero_mode"] for law in PROOF_LAWS)
    if zm:
        text += f"; translations <= {zm:.1f} eps"
    t = v["tests"][scene]
    return text + f"; {t['passed']} tests passed, {t['failed']} failed"


def _states_text(v):
    """'2,000 hypothesis states per law and scene (packing: 65)': the cases each module's
    WORST counted, the most common count first."""
    counts = {scene: sorted({v["worst"][scene][law]["cases"] for law in PROOF_LAWS})
              for scene in PROOF_SCENES}
    main = max(counts.values(), key=lambda c: sum(c == x for x in counts.values()))
    text = "/".join(f"{c:,}" for c in main) + " hypothesis states per law and scene"
    others = [f"{scene}: {'/'.join(f'{c:,}' for c in c_)}" for scene, c_ in counts.items()
              if c_ != main]
    return text + (f" ({'; '.join(others)})" if others else "")


def _proof_verdict(v, scene):
    w = v["worst"][scene]
    worst = max(w[law]["complex_step"] for law in PROOF_LAWS)
    ratio = max(w[law]["central_over_bound"] for law in PROOF_LAWS)
    zm = max(w[law]["zero_mode"] for law in PROOF_LAWS)
    ok = worst <= 1e-10 and ratio <= 1 and zm <= 32 and v["tests"][scene]["failed"] == 0
    return Verdict("meets" if ok else "fails",
                   f"complex step {worst:.1e} <= 1e-10 of max|K|, central error / model "
                   f"{ratio:.2f} <= 1" + (f", translations {zm:.1f} <= 32 eps" if zm else ""))


def _check_proof(a, b):
    """Round-off: each worst error within 10x (another CPU's rounding of the same seeded
    states); the bounds hold; the outcomes as recorded."""
    for scene in PROOF_SCENES:
        if a["tests"][scene]["failed"] != b["tests"][scene]["failed"]:
            return False, f"{scene}: failed {a['tests'][scene]['failed']} -> {b['tests'][scene]['failed']}"
        for law in PROOF_LAWS:
            x, y = a["worst"][scene][law], b["worst"][scene][law]
            for key in ("complex_step", "central"):
                if y[key] > 10 * max(x[key], 1e-16):
                    return False, f"{scene} {law} {key}: {x[key]:.1e} -> {y[key]:.1e}"
            if y["central_over_bound"] > 1 or y["zero_mode"] > 32:
                return False, f"{scene} {law}: beyond its bound"
    return True, "worst errors within 10x, bounds hold"


PROOF_TOLERANCE = ("each worst error within 10x: the states are seeded (hypothesis seed "
                   "20261121), so the values move only with another CPU's rounding; the bounds "
                   "(1e-10 of max|K|: a block rounds to ~64 eps of terms up to ~1e3 max|K| at "
                   "1e-12 R on a cap; the central model; 32 eps for a zero mode) always hold")


# ------------------------------------------------------------ hours: the acceptance fuzzing

def fuzz_cli():
    """``FRICSTAB_FUZZ_EXAMPLES=10000``: the command-line property and the named bad
    scene values (tests/test_fuzz_cli.py -k 'traceback or named')."""
    from ._testrun import run_tests, summary
    status, tests = run_tests(["tests/test_fuzz_cli.py", "-k", "traceback or named",
                               f"--hypothesis-seed={HYPOTHESIS_SEED}"],
                              env={"FRICSTAB_FUZZ_EXAMPLES": "10000"})
    examples = {k.split("::")[-1]: v.get("examples") for k, v in tests.items()}
    return Result({"status": status, "tests": summary(tests, ["test_fuzz_cli"]),
                   "examples": examples}, seeds=(int(HYPOTHESIS_SEED),))


def fuzz_rundir():
    """``FRICSTAB_FUZZ_EXAMPLES=2000``: random sequences of run / kill / --force / --resume /
    hand edit / second writer on one result directory (tests/test_fuzz_rundir.py)."""
    from ._testrun import run_tests, summary
    status, tests = run_tests(["tests/test_fuzz_rundir.py", f"--hypothesis-seed={HYPOTHESIS_SEED}"],
                              env={"FRICSTAB_FUZZ_EXAMPLES": "2000"})
    examples = {k.split("::")[-1]: v.get("examples") for k, v in tests.items()}
    return Result({"status": status, "tests": summary(tests, ["test_fuzz_rundir"]),
                   "examples": examples}, seeds=(int(HYPOTHESIS_SEED),))


def _fuzz_show(v):
    parts = []
    for name, e in v["examples"].items():
        if e:
            parts.append(f"{name}: {e['passing']:,} passing, {e['failing']} failing"
                         + (f" ({e['invalid']:,} generated inputs rejected as invalid by "
                            "hypothesis)" if e["invalid"] else ""))
    t = v["tests"]
    return "; ".join(parts) + f"; {t['passed']} tests passed, {t['failed']} failed"


def _fuzz_verdict(v):
    failing = sum(e["failing"] for e in v["examples"].values() if e)
    return Verdict("meets" if v["tests"]["failed"] == 0 and failing == 0 else "fails",
                   f"{v['tests']['failed']} tests failed, {failing} failing examples")


# ------------------------------------------------------------ minutes: the tests of the product

def product_tests():
    """The product's promises, each a committed test (``TEST_FILES``, ``TEST_SELECTION``),
    run here with two engine threads (tests/test_threads.py compares 1 and 2)."""
    import os

    from ._testrun import run_tests
    os.environ["NUMBA_NUM_THREADS"] = "2"      # before numba is imported; the record says so
    status, tests = run_tests([*TEST_FILES, "-k", TEST_SELECTION,
                               f"--hypothesis-seed={HYPOTHESIS_SEED}"])
    return Result({"status": status,
                   "tests": {k: v["outcome"] for k, v in sorted(tests.items())}})


def _outcomes(v, select):
    tests = {k: o for k, o in v["tests"].items() if any(s in k for s in select)}
    n = {o: sum(x == o for x in tests.values()) for o in ("passed", "failed", "skipped")}
    return n, sorted(k for k, o in tests.items() if o != "passed")


def _tests_show(select):
    def show(v):
        n, bad = _outcomes(v, select)
        text = f"{n['passed']} of {sum(n.values())} passed"
        if n["skipped"]:
            text += f", {n['skipped']} skipped"
        if n["failed"]:
            text += f", {n['failed']} FAILED: " + ", ".join(b.split("::")[-1] for b in bad)
        return text
    return show


def _tests_verdict(select):
    def verdict(v):
        n, _ = _outcomes(v, select)
        total = sum(n.values())
        return Verdict("meets" if n["failed"] == 0 and n["passed"] > 0 else "fails",
                       f"{n['passed']} of {total} passed")
    return verdict


def _tests_check(select):
    def check(a, b):
        na, _ = _outcomes(a, select)
        nb, bad = _outcomes(b, select)
        if nb["failed"]:
            return False, f"{nb['failed']} failed: {', '.join(bad)[:200]}"
        if na != nb:
            return False, f"outcomes {na} -> {nb}"
        return True, "the same tests pass"
    return check


def _test_claim(short, title, select, command, tolerance="exact: each test's outcome, the "
                "test's own assertions the tolerance", issue=None):
    """A claim of the product_tests job; ``issue``: what the issue asked (no paper states
    these), said in the title."""
    return Claim(f"engine.{short}", "engine", title + (f" ({issue})" if issue else ""),
                 "minutes", command, product_tests, _tests_show(select), tolerance,
                 _tests_check(select), verdict=_tests_verdict(select),
                 job="engine.product_tests")


# ------------------------------------------------------------ seconds: generated vs lambdify

def lambdify_values():
    """The generated Ishima kernels against ``sympy.lambdify`` of the same expressions on
    the contacts of a seeded packing (N = 64, phi = 0.9): largest relative difference of
    the forces and of the Jacobian blocks (validation/benchmarks/bench_kernels.py's check,
    without its timings)."""
    import importlib
    import sys

    import numpy as np

    from fricstab.scenes.packing import make_packing
    from fricstab.scenes.packing_friction import material, packing_system
    from fricstab.scenes.packing_relax import separations

    from .fingerprint import ROOT
    bench = str(ROOT / "validation" / "benchmarks")
    if bench not in sys.path:
        sys.path.insert(0, bench)
    bk = importlib.import_module("bench_kernels")
    p = make_packing(64, 0.9, 0)
    system = packing_system(p, material("ishima", kt=bk.KT))
    state = system.state(p.pos)
    c = state.contacts
    sep = separations(system, state)
    r = system.radius
    touch = np.flatnonzero(np.hypot(sep[:, 0], sep[:, 1]) < r[c.i] + r[c.j])
    c.hist[touch] = np.random.default_rng(0).normal(size=(len(touch), 2)) * 1e-3
    pairs = np.ascontiguousarray(np.column_stack([c.i, c.j])[touch])
    sept, hist = np.ascontiguousarray(sep[touch]), np.ascontiguousarray(c.hist[touch])
    m = len(touch)
    out = np.empty((m, 6))
    bk._force_loop(sept, r, pairs, 1.0, bk.KT, hist, out)
    lam_f, lam_fj = bk._lambdified()
    args = (sept[:, 0], sept[:, 1], r[pairs[:, 0]], r[pairs[:, 1]], 1.0, bk.KT,
            hist[:, 0], hist[:, 1])
    ref = np.column_stack([np.broadcast_to(v, m) for v in lam_f(*args)])
    err_f = float(np.abs(ref - out).max() / np.abs(out).max())
    jl = np.column_stack([np.broadcast_to(v, m) for v in lam_fj(*args)[6:]]).reshape(m, 6, 6)
    _, blocks = system.forces(state, want_blocks=True)
    key = {(int(i), int(j)): b for i, j, b in zip(c.i, c.j, blocks)}
    blocks1 = np.array([key[int(i), int(j)] for i, j in pairs])
    err_j = float(np.abs(jl - blocks1).max() / np.abs(blocks1).max())
    return Result({"contacts": int(m), "forces": err_f, "jacobian": err_j}, seeds=(0,))


# ------------------------------------------------------------ seconds: import of the shipped examples

IMPORT_EXAMPLES = "docs/examples/import"
#: (files, options) of each shipped example, as docs/howto/analyse_imported.md imports them
IMPORT_CASES = {
    "lammps": (("lammps/packing.data", "lammps/atoms.dump", "lammps/pairs.dump"),
               ("--columns", "id1,id2,dist,fx,fy,fz,p1,p2,p3,p4", "--file-units", "lj")),
    "liggghts": (("liggghts/atoms.dump", "liggghts/pairs.dump"),
                 ("--keywords", "pos,id,force,torque,history,contactArea")),
    "csv": (("csv/packing.csv",), ("--units", "length=0.4,force=100,mass=20")),
}


def import_examples():
    """``fricstab import`` of the shipped examples (made by LAMMPS gran/hertz/history, and
    its state in LIGGGHTS' layout and as a lab's CSV) under ishima: per format the worst
    relative force mismatch against the file, the contacts listed and kept, the residual."""
    import contextlib
    import io
    import json
    import tempfile
    from pathlib import Path

    from fricstab.cli import main

    from .fingerprint import ROOT
    out = {}
    with tempfile.TemporaryDirectory() as tmp:
        for name, (files, options) in IMPORT_CASES.items():
            args = ["import", *(str(ROOT / IMPORT_EXAMPLES / f) for f in files), *options,
                    "--law", "ishima", "--param", "kn=1", "--param", "kt=1", "--quiet",
                    "--out", str(Path(tmp) / name)]
            with contextlib.redirect_stdout(io.StringIO()):
                rc = main(args)
            if rc != 0:
                raise RuntimeError(f"fricstab {' '.join(args)} exited {rc}")
            rec = json.loads((Path(tmp) / name / "import.json").read_text())
            out[name] = {"worst": rec["mismatch"]["worst_relative"],
                         "listed": rec["counts"]["listed"], "kept": rec["counts"]["kept"],
                         "residual": rec["residual"]["relative"]}
    return Result(out)


def _import_files():
    return tuple(f"{IMPORT_EXAMPLES}/{f}" for files, _ in IMPORT_CASES.values() for f in files)


# ------------------------------------------------------------ the claims

def _proof_claim(scene, title, texts=None):
    """A claim of the system-level proof run (one job, three scenes)."""
    return Claim(f"engine.proof_{scene}", "engine", title, "hours",
                 "FRICSTAB_HYPOTHESIS_PROFILE=thorough python -m pytest -s "
                 "tests/test_chain_proof.py tests/test_packing_proof.py tests/test_shear_proof.py "
                 f"--hypothesis-seed={HYPOTHESIS_SEED}", system_proof,
                 show=lambda v: _proof_show(v, scene), tolerance=PROOF_TOLERANCE,
                 check=_check_proof, verdict=lambda v: _proof_verdict(v, scene),
                 job="engine.system_proof", texts=texts or {})


CLAIMS = [
    # --- system-level proofs (hours)
    _proof_claim("chain",
          "system-level proof, chain on a substrate: assembled K vs complex step of an "
          "independent reference assembly, worst over hypothesis states (overlaps to 1e-12 R, "
          "histories at 0, inside, on and past the caps), relative to max|K| (issue: <= 1e-10 of max|K|)",
                 texts={**{f"{law}_{scene}": (lambda law, scene: lambda v:
                                              f"{v['worst'][scene][law]['complex_step']:.1e}")(
                     law, scene) for law in PROOF_LAWS for scene in PROOF_SCENES},
                        "states": _states_text}),
    _proof_claim("packing",
          "same, periodic packing with a Lees-Edwards offset (complex step and central "
          "differences on separate draws); translations as zero modes (issue: <= 1e-10; 32 eps)"),
    _proof_claim("shear",
          "same, plane-shear cell (walls of disks, images, clamped rows); translations (issue: <= 1e-10; 32 eps)"),
    # --- the product's promises (minutes, one test run)
    _test_claim("matrix",
                "every cell of (hertz, charan, ishima, lee_hurley, linear and the _fi forms) x "
                "(chain, packing, shear) "
                "runs from the command line with its defaults; the Jacobian recomputed from "
                "state.npz alone equals jacobian.npz; every record's manifest verifies",
                ["test_every_law_runs_in_every_scene"],
                "python -m pytest tests/test_matrix.py", issue="issue: 15 cells, exit 0"),
    _test_claim("bad_law",
                "bad law input (unknown law, unknown parameter, a parameter of another law, "
                "out of range) in each scene: one line, exit 2, nothing written",
                ["test_bad_law_input"], "python -m pytest tests/test_matrix.py -k bad_law",
                issue="issue: one line, exit 2, nothing written"),
    _test_claim("regression",
                "numbers pinned before the engine's restructuring (chain events and "
                "equilibria, growth rate, transverse frequency, packing rigidity, DOS and "
                "dynamics on a stored packing, shear spectrum of a stored state)",
                ["validation/test_regression.py"], "python -m pytest validation/test_regression.py",
                tolerance="per case, its error model in validation/regression/tolerances.py",
                issue="issue: unchanged"),
    _test_claim("threads",
                "results independent of the thread count: chain, packing with rebuilds and "
                "FIRE, the plane-shear cell, pinned packing dynamics, a team that cannot all "
                "run at once, at 1 and 2 threads (np.array_equal)",
                ["tests/test_threads.py"], "NUMBA_NUM_THREADS=2 python -m pytest tests/test_threads.py",
                tolerance="exact: one summation order at every thread count",
                issue="issue: bit-identical"),
    _test_claim("bit_identities",
                "the engine's shortcuts give the reference's bits: the fused exact product "
                "equals Dekker's; pair geometry in lanes equals one contact's",
                ["test_fused_exact_product", "test_geometry_in_lanes"],
                "python -m pytest tests/test_numerics.py tests/test_lee_hurley.py -k "
                "\"fused or lanes\"", tolerance="exact (hypothesis cases)"),
    _test_claim("chain_resume",
                "chain dynamics: SIGKILL at a random moment after the first checkpoint, then "
                "--resume: every array of dynamics.npz, breach and slide numbers bit-identical",
                ["test_sigkill_then_resume_is_bit_identical"],
                "python -m pytest tests/test_checkpoint.py -k sigkill",
                tolerance="exact: same machine, deterministic serial Verlet restarted from "
                          "the saved state", issue="issue: identical results"),
    _test_claim("shear_resume",
                "shear run: SIGKILL, SIGTERM or SIGINT at a random moment of the shear stage, "
                "then --resume: every frame chunk and shear.npz bit-identical; SIGTERM and "
                "SIGINT exit 143 and 130 with one line",
                ["test_shear_cli.py"], "python -m pytest tests/test_shear_cli.py -k \"signal or sigkill\"",
                issue="issue: exit 143 / 130, last checkpoint kept, identical result"),
    _test_claim("ensemble",
                "25 chain realizations on a local dask cluster (2 worker processes), one worker "
                "SIGKILLed mid-run, then rerun: all stored, each completed once",
                ["tests/test_ensemble.py"], "python -m pytest tests/test_ensemble.py",
                tolerance="exact counts (marker files per member)",
                issue="issue: all 25, none twice"),
    _test_claim("records",
                "result.json of every protocol (chain ramp, jacobian, dynamics, waves; packing "
                "make, rigidity, dos; shear run, analyze) carries versions, seed, parameters, "
                "timings", ["tests/test_result_records.py"],
                "python -m pytest tests/test_result_records.py",
                issue="issue: versions, seed, parameters, timings"),
    _test_claim("named_failures",
                "the issue's named examples (--out '', --scene /dev/zero, a key twice, "
                "--dgamma 1e-320, absurd verify ranges, --alpha-n 1, scene show shear, "
                "warnings) and the result-directory rules of packing and chain",
                ["tests/test_named_failures.py", "tests/test_packing_rundir.py",
                 "tests/test_chain_rundir.py"],
                "python -m pytest tests/test_named_failures.py tests/test_packing_rundir.py "
                "tests/test_chain_rundir.py", issue="issue: one line exit 2, or a run"),
    _test_claim("figures",
                "every figure the command line writes has a unit on every axis and colour bar "
                "and every colour bar labelled (ramp, dynamics, waves, packing, rigidity, dos, "
                "ten shear figures, the step panels at 6,000 steps); waves.png draws the "
                "fitted V1 and -V2; dos.png keeps equal spectra visible",
                ["tests/test_figures.py"], "python -m pytest tests/test_figures.py",
                tolerance="exact: label pattern `[unit]`; slopes to 1e-9 (two least-squares "
                          "fits of the same points)", issue="issue 18: every figure"),
    _test_claim("docstrings",
                "every front-door name documents each argument and its return value, and the "
                "API page lists every name",
                ["tests/test_docstrings.py"], "python -m pytest tests/test_docstrings.py"),
    # --- acceptance fuzzing (hours)
    Claim("engine.fuzz_cli", "engine",
          "fuzzed scene files and command lines (chain, packing, shear; valid, invalid, "
          "absurd): no traceback, exit in {0, 2, 3, 4}, a bad input one line naming the key (issue: 10,000, zero tracebacks)",
          "hours", "FRICSTAB_FUZZ_EXAMPLES=10000 python -m pytest tests/test_fuzz_cli.py -k "
          "\"traceback or named\"", fuzz_cli, show=_fuzz_show,
          tolerance="exact: a traceback, an exit 70 or a bad input not exiting 2 with one line "
                    "fails the test; the example counts are hypothesis' (seeded)",
          check=lambda a, b: (b["tests"]["failed"] == 0, f"{b['tests']['failed']} failed"),
          verdict=_fuzz_verdict),
    Claim("engine.fuzz_rundir", "engine",
          "random sequences of run / kill / --force / --resume / hand edit / second writer on "
          "one result directory (chain ramp, chain dynamics): the invariant of the test's "
          "docstring (issue: 2,000 sequences, 0 violations)", "hours",
          "FRICSTAB_FUZZ_EXAMPLES=2000 python -m pytest tests/test_fuzz_rundir.py", fuzz_rundir,
          show=_fuzz_show,
          tolerance="exact: any violation fails the test (CI runs 100 sequences per command)",
          check=lambda a, b: (b["tests"]["failed"] == 0, f"{b['tests']['failed']} failed"),
          verdict=_fuzz_verdict),
    # --- generated kernels against lambdify (seconds)
    Claim("engine.lambdify_values", "engine",
          "generated Ishima kernels against sympy.lambdify of the same expressions, contacts "
          "of a seeded packing (N = 64): largest relative difference of forces and of the "
          "Jacobian blocks", "seconds",
          "python validation/reproduce.py --claim engine.lambdify_values "
          "(the check of validation/benchmarks/bench_kernels.py)", lambdify_values,
          show=lambda v: f"forces {v['forces']:.1e}, Jacobian {v['jacobian']:.1e} "
          f"({v['contacts']} contacts)",
          tolerance="within 10x: round-off of another operation order (and another CPU)",
          check=lambda a, b: (all(b[k] <= 10 * max(a[k], 1e-16) for k in ("forces", "jacobian"))
                              and a["contacts"] == b["contacts"], "within 10x"),
          verdict=lambda v: bound_verdict(max(v["forces"], v["jacobian"]), 1e-12,
                                          "largest relative difference (round-off)")),
    # --- fricstab import of the shipped examples (seconds)
    Claim("engine.import_examples", "engine",
          "`fricstab import` of the shipped examples under ishima (a 16-disk packing sheared "
          "by LAMMPS gran/hertz/history to rest; its state in LIGGGHTS' layout with history "
          "columns, and as a CSV in mm/N/g): worst relative force mismatch against the file",
          "seconds",
          "fricstab import docs/examples/import/lammps/{packing.data,atoms.dump,pairs.dump} "
          "--columns id1,id2,dist,fx,fy,fz,p1,p2,p3,p4 --law ishima --param kn=1 --param kt=1 "
          "--out DIR (docs/howto/analyse_imported.md)", import_examples,
          show=lambda v: ", ".join(f"{k} {x['worst']:.1e} ({x['kept']}/{x['listed']} kept)"
                                   for k, x in v.items()),
          tolerance="within 10x of 1e-14: round-off of the law's inverse and forward (another "
                    "operation order, another CPU); the contact counts exactly",
          check=lambda a, b: (all(b[k]["worst"] <= 10 * max(a[k]["worst"], 1e-15)
                                  and b[k]["kept"] == a[k]["kept"] for k in a), "within 10x"),
          verdict=lambda v: bound_verdict(max(x["worst"] for x in v.values()), 1e-10,
                                          "issue 37: our forces equal the file's to 1e-10"),
          inputs=_import_files(),
          texts={"lammps": lambda v: f"{v['lammps']['worst']:.1e}"}),
]
