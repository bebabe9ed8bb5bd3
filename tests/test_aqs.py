"""fricstab packing aqs: brackets re-checked from the exported files, bad input, resume."""

import json

import numpy as np
import pytest

from fricstab.cli import main
from fricstab.protocols import aqs as aqs_protocol
from fricstab.scenes.packing import make_packing
from fricstab.scenes.packing_friction import backbone, frictional, material

# N = 64 at phi = 0.90, seed 0, charan: the first pair births lie near strain
# 2.8e-3 and 4.5e-3 (measured), so 20 steps of 2.5e-4 hold at least one.
ARGS = ["packing", "aqs", "--law", "charan", "--n", "64", "--strain", "5e-3",
        "--dgamma", "2.5e-4", "--no-progress", "--quiet"]


@pytest.fixture(scope="module")
def run_dir(tmp_path_factory):
    out = tmp_path_factory.mktemp("aqs")
    assert main(ARGS + ["--out", str(out)]) == 0
    return out


def _csr_dense(path):
    """The CSR matrix of a ``scipy.sparse.save_npz`` file, with numpy alone."""
    with np.load(path) as z:
        data, indices, indptr, shape = z["data"], z["indices"], z["indptr"], z["shape"]
    dense = np.zeros(tuple(shape))
    rows = np.repeat(np.arange(shape[0]), np.diff(indptr))
    dense[rows, indices] = data
    return dense


def _pair_count(folder):
    """Complex pairs of M^-1 K off the translations, by the rule aqs.json states (numpy only)."""
    k = _csr_dense(folder / "jacobian.npz")
    mass = np.load(folder / "mass.npy")
    dof = json.loads((folder / "dofs.json").read_text())["dof_per_particle"]
    c = np.zeros((len(mass), 2))
    c[0::dof, 0] = c[1::dof, 1] = 1.0
    q, _ = np.linalg.qr(c * mass[:, None], mode="complete")
    basis = q[:, 2:]
    w = np.linalg.eigvals(basis.T @ (k / mass[:, None]) @ basis)
    upper = w[w.imag > 0]
    return int(np.sum(np.abs(upper) > aqs_protocol.ZERO_CLUSTER * np.abs(w).max()))


def test_every_birth_bracket_recounted_from_its_files(run_dir):
    doc = json.loads((run_dir / "aqs.json").read_text())
    births = [e for e in doc["events"] if e["kind"] == "birth" and e["located"]]
    assert births, "the path of the fixture holds births (see ARGS)"
    for e in births:
        # bisection halves the step until the bracket is below --tol (1e-6)
        assert e["gamma_hi"] - e["gamma_lo"] <= 1e-6
        lo, hi = (run_dir / d for d in e["directories"])
        for d in (lo, hi):
            assert {p.name for p in d.iterdir()} >= {"state.npz", "jacobian.npz",
                                                       "dofs.json", "mass.npy"}
        # a birth: one more pair at the upper end.  The pair's |Im| at 1e-6 from
        # its exceptional point is ~1e-5 (D linear in strain), far above the
        # round-off of eig, O(eps |A|) ~ 1e-15.
        assert _pair_count(hi) == _pair_count(lo) + 1, e
        with np.load(hi / "state.npz") as z:
            assert float(z["le_offset"]) == pytest.approx(e["gamma_hi"] * z["box"][1],
                                                          rel=1e-12)


def test_record_lists_path_and_events(run_dir):
    doc = json.loads((run_dir / "aqs.json").read_text())
    n = len(doc["strains"])
    assert n == 21 and len(doc["stresses"]) == n and len(doc["n_pairs"]) == n
    assert doc["max_bracket"] <= 1e-6
    # the elastic branch: stress rises by G dgamma per step, G > 0
    assert np.all(np.diff(doc["stresses"]) > 0)


@pytest.mark.parametrize("extra, needle", [
    (["--dgamma", "0"], "--dgamma"),
    (["--dgamma", "-1e-4"], "--dgamma"),
    (["--strain", "1e-5"], "--strain"),
    (["--law", "ishima_wall"], "--law"),
])
def test_bad_input_one_line_exit_2(tmp_path, capsys, extra, needle):
    args = list(ARGS)
    for i in range(0, len(extra), 2):
        if extra[i] in args:
            args[args.index(extra[i]) + 1] = extra[i + 1]
        else:
            args += extra[i:i + 2]
    assert main(args + ["--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and needle in err[0], err
    assert not (tmp_path / "o").exists()


def test_hertz_runs_as_the_control(run_dir, tmp_path):
    out = tmp_path / "h"
    args = [a if a != "charan" else "hertz" for a in ARGS if a not in ("--n", "64")]
    assert main(args + ["--packing", str(run_dir), "--out", str(out)]) == 0
    doc = json.loads((out / "aqs.json").read_text())
    # the frictionless Hessian is symmetric: no complex pair anywhere
    assert max(doc["n_pairs"]) == 0 and doc["births"] == 0


@pytest.fixture(scope="module")
def charan64():
    bb = backbone(make_packing(64, 0.9, 0))
    fr = frictional(bb, material("charan"))
    return fr.system, fr.state


def test_non_convergence_names_the_step(charan64, monkeypatch, tmp_path):
    system, state = charan64
    # Newton capped at 1e-12 per iteration cannot cover the step's relaxation
    # (~1e-4) in 60 iterations, and FIRE gets 5 iterations
    monkeypatch.setattr(aqs_protocol, "MAX_STEP", 1e-12)
    monkeypatch.setattr(aqs_protocol, "FIRE_MAX_ITER", 5)
    with pytest.raises(aqs_protocol.ConvergenceError, match="strain step 1 "):
        aqs_protocol.run_aqs(system, state, 1e-3, 2.5e-4)


def test_resume_is_bit_identical(charan64):
    system, state = charan64
    saved = {}
    full = aqs_protocol.run_aqs(system, state, 2e-3, 2.5e-4, checkpoint=saved.__setitem__,
                                checkpoint_every=4)
    arrays = dict(saved[4], step=np.int64(4))
    cont = aqs_protocol.run_aqs(system, state, 2e-3, 2.5e-4, resume=arrays)
    assert np.array_equal(cont.stress, full.stress)
    assert [e.row() for e in cont.events] == [e.row() for e in full.events]


def test_cli_non_convergence_exit_4_names_the_step(run_dir, tmp_path, monkeypatch, capsys):
    monkeypatch.setattr(aqs_protocol, "MAX_STEP", 1e-12)
    monkeypatch.setattr(aqs_protocol, "FIRE_MAX_ITER", 5)
    args = [a for a in ARGS if a not in ("--n", "64")]
    assert main(args + ["--packing", str(run_dir), "--out", str(tmp_path / "o")]) == 4
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "strain step 1 " in err[0], err


def test_event_folders_match_the_record_when_a_birth_is_not_located(tmp_path):
    """Every folder aqs.json names holds the state at its event's bracket ends, and no
    other birth folder exists, also after a birth that bisection could not locate (the
    folders were numbered over all births and the record over the located ones)."""
    pk = tmp_path / "P32"
    assert main(["packing", "make", "--n", "32", "--out", str(pk), "--quiet",
                 "--no-progress"]) == 0
    out = tmp_path / "A"
    assert main(["packing", "aqs", "--law", "charan", "--packing", str(pk), "--strain",
                 "0.028", "--dgamma", "2e-3", "--out", str(out), "--quiet",
                 "--no-progress"]) == 0
    doc = json.loads((out / "aqs.json").read_text())
    births = [e for e in doc["events"] if e["kind"] == "birth"]
    assert any(not e["located"] for e in births[:-1]), \
        "this path has an unlocated birth before a located one (the case under test)"
    named = set()
    for e in births:
        if not e["located"]:
            assert "directories" not in e
            continue
        for d, g in zip(e["directories"], (e["gamma_lo"], e["gamma_hi"])):
            named.add(d)
            with np.load(out / d / "state.npz") as z:
                assert float(z["le_offset"]) == pytest.approx(g * z["box"][1], rel=1e-12)
    on_disk = {f"events/{p.name}" for p in (out / "events").iterdir()}
    assert on_disk == named


def test_a_singular_jacobian_gets_few_least_squares_iterations_before_fire(charan64,
                                                                          monkeypatch):
    """A singular bordered solve (a disk that lost its contacts) is retried by least squares
    for at most ``singular_iter`` (default 8) iterations, then FIRE and a polish with the full 60: a
    least-squares Newton that wanders along near-zero modes cost 2 s an iteration at
    N = 512 for 60 iterations a step."""
    system, state = charan64
    calls = []
    real = aqs_protocol.newton

    def spy(system, state, tol, *, max_iter, solver, max_step, raise_on_failure):
        calls.append((solver, max_iter))
        if solver == "bordered" and len(calls) == 1:
            raise aqs_protocol.ConvergenceError("singular")   # as singular_guard reports
        if solver != "bordered" and len(calls) == 2:
            return real(system, state, tol, max_iter=0, solver=solver, max_step=max_step,
                        raise_on_failure=False)           # not converged
        return real(system, state, tol, max_iter=max_iter, solver=solver,
                    max_step=max_step, raise_on_failure=raise_on_failure)
    monkeypatch.setattr(aqs_protocol, "newton", spy)
    _, used_fire = aqs_protocol.relax_step(system, state, 2.5e-4, 1e-13)
    assert used_fire
    assert calls[:2] == [("bordered", 60), ("regularized", 8)]
    assert calls[2] == ("bordered", 60)      # the polish after FIRE: the full budget

def test_a_stalled_polish_is_restarted_by_least_squares_from_the_fire_state(charan64,
                                                                            monkeypatch):
    """A bordered Newton that ends unconverged without raising (a nearly singular Jacobian:
    N = 512 hertz, strain step 34, stalled at 8.7e-10 where least squares converges in 2) is
    restarted by least squares from the state it started from, with the full 60."""
    system, state = charan64
    calls, starts = [], []
    real = aqs_protocol.newton

    def spy(system, st, tol, *, max_iter, solver, max_step, raise_on_failure):
        calls.append((solver, max_iter))
        starts.append(st.q.copy())
        if solver == "bordered":        # a stall: it moves the state, ends unconverged
            st.q[:, :2] += 1e-7
            return real(system, st, tol, max_iter=0, solver=solver, max_step=max_step,
                        raise_on_failure=False)
        return real(system, st, tol, max_iter=max_iter, solver=solver, max_step=max_step,
                    raise_on_failure=raise_on_failure)
    monkeypatch.setattr(aqs_protocol, "newton", spy)
    relaxed, used_fire = aqs_protocol.relax_step(system, state, 2.5e-4, 1e-13)
    assert used_fire
    # before FIRE a stall goes to FIRE (a plastic event: least squares would wander)
    assert calls == [("bordered", 60), ("bordered", 60), ("regularized", 60)]
    assert np.array_equal(starts[2], starts[1])     # restarted from the FIRE state
    assert np.abs(aqs_protocol.jacobian(system, relaxed)[0]).max() < 1e-13


def test_the_polish_runs_when_fire_runs_out(charan64, monkeypatch):
    """FIRE at its iteration limit short of 1e-9 (ishima, N = 64, seed 3, step 125: 5.6e-8
    after 2e6 iterations) still hands its state to the Newton polish."""
    system, state = charan64
    monkeypatch.setattr(aqs_protocol, "FIRE_MAX_ITER", 5)
    relaxed, used_fire = aqs_protocol.relax_step(system, state, 2.5e-4, 1e-13, use_fire=True)
    assert used_fire
    assert np.abs(aqs_protocol.jacobian(system, relaxed)[0]).max() < 1e-13

