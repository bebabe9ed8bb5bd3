"""The code stamp of a cached long computation (``claims.fingerprint.code_units`` and
``units_changed``, used by ``validation/precursor_study.py``): a cached run is reused only while
every function it executed is unchanged."""

import dataclasses
import importlib.util
import json
import sys
from pathlib import Path

import numpy as np
import pytest

VALIDATION = Path(__file__).resolve().parents[1] / "validation"
sys.path.insert(0, str(VALIDATION))

from claims import fingerprint as fp  # noqa: E402

SOURCE = '''"""A module of a toy checkout."""
SCALE = 2.0


def used(x):
    return SCALE * x


def unused(x):
    return x - 1
'''


@pytest.fixture
def toy(tmp_path, monkeypatch):
    (tmp_path / "fricstab").mkdir()
    path = tmp_path / "fricstab" / "toy_mod.py"
    path.write_text(SOURCE)
    spec = importlib.util.spec_from_file_location("toy_mod_for_stamps", path)
    mod = importlib.util.module_from_spec(spec)
    monkeypatch.setitem(sys.modules, "toy_mod_for_stamps", mod)
    spec.loader.exec_module(mod)
    return tmp_path, path, mod


def _stamp(root, mod):
    with fp.Tracer() as tracer:
        assert mod.used(3.0) == 6.0
    return fp.code_units(tracer, root)


def test_the_stamp_holds_what_ran_and_the_module_frame(toy):
    root, _, mod = toy
    units = _stamp(root, mod)
    assert set(units) == {"fricstab/toy_mod.py"}
    assert set(units["fricstab/toy_mod.py"]) == {"used", fp.FRAME}
    assert json.loads(json.dumps(units)) == units        # stored as JSON in a run


@pytest.mark.parametrize("edit, stale", [
    (lambda s: s.replace("return x - 1", "return x - 2"), False),     # a function not run
    (lambda s: s.replace('"""A module', '"""The module'), False),     # a docstring
    (lambda s: s.replace("SCALE * x", "SCALE * x * 1.0"), True),      # the function run
    (lambda s: s.replace("SCALE = 2.0", "SCALE = 3.0"), True),        # the module's frame
])
def test_only_a_change_of_the_executed_code_stales_the_stamp(toy, edit, stale):
    root, path, mod = toy
    units = _stamp(root, mod)
    assert fp.units_changed(units, root) == []
    path.write_text(edit(SOURCE))
    assert fp.units_changed(units, root) == (["fricstab/toy_mod.py"] if stale else [])


def test_a_removed_module_stales_the_stamp(toy):
    root, path, mod = toy
    units = _stamp(root, mod)
    path.unlink()
    assert fp.units_changed(units, root) == ["fricstab/toy_mod.py"]


def _precursor_study():
    spec = importlib.util.spec_from_file_location("precursor_study_for_store",
                                                  VALIDATION / "precursor_study.py")
    ps = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(ps)
    return ps


def test_precursor_runs_are_fresh_only_under_their_stamp():
    ps = _precursor_study()
    assert ps.fresh({"code": ps.code_hash()})
    assert not ps.fresh({"code": "0" * 16})
    assert not ps.fresh({})
    gone = {"fricstab/no_such_module.py": {"f": "0" * 16}}
    assert not ps.fresh({"units": json.dumps(gone), "code": ps.code_hash()})   # units decide


def test_a_record_carries_the_code_of_the_cached_runs_it_read(toy):
    """``add_units``: a claim that read cached runs is stale exactly when the code the runs
    executed changed (``changes`` of its fingerprint), not at any change of the package."""
    root, path, mod = toy
    units = _stamp(root, mod)
    rec = fp.add_units({"modules": {}, "claim": {"module": "fricstab/toy_mod.py",
                                                  "names": [], "hash": None},
                        "inputs": {}}, units)
    rec["claim"]["hash"] = fp.unit_hash("fricstab/toy_mod.py", [], root)
    assert fp.changes(rec, root) == []
    path.write_text(SOURCE.replace("return x - 1", "return x - 2"))     # not run: fresh
    assert fp.changes(rec, root) == []
    path.write_text(SOURCE.replace("SCALE * x", "SCALE * x * 1.0"))     # run: stale
    assert any(c.startswith("fricstab/toy_mod.py (") for c in fp.changes(rec, root))
    whole = fp.add_units({"modules": {}}, {"fricstab/toy_mod.py": {"*": "0" * 16}})
    assert whole["modules"] == {"fricstab/toy_mod.py": "0" * 16}       # a numba module whole
    assert fp.add_units({"modules": {}}, None) == {"modules": {}}


def test_a_checkpoint_continues_only_the_packing_it_was_made_on(tmp_path):
    """The committed store (``validation/runs/``) travels between machines, and seeded FIRE
    can reach another packing on another CPU: the packing is kept beside the runs
    (``_packing`` reads it back bit for bit), and a checkpoint carries its backbone's digest,
    so a path is never continued on other positions (a clear error, not a silent mix)."""
    from fricstab.errors import ParameterError
    from fricstab.scenes.packing_friction import backbone
    ps = _precursor_study()
    p = ps._packing(tmp_path, 32, 0)
    again = ps._packing(tmp_path, 32, 0)
    assert (tmp_path / "packings" / "n32_phi0.9_s0.npz").exists()
    assert np.array_equal(p.pos, again.pos) and np.array_equal(p.diameter, again.diameter)
    bb = backbone(p)
    ckpt = tmp_path / "run.checkpoints"
    ps.one_run(bb, "hertz", {}, 2e-3, 5e-4, ckpt, every=1)
    assert any(ckpt.iterdir())
    moved = dataclasses.replace(bb, pos=bb.pos + 1e-9)
    with pytest.raises(ParameterError, match="backbone"):
        ps.one_run(moved, "hertz", {}, 2e-3, 5e-4, ckpt, every=1)


def test_the_check_puts_back_the_files_a_recomputed_job_rewrites(tmp_path, monkeypatch):
    """``reproduce --check`` recomputes the seconds tier in place; another machine renders a
    figure to other bytes, so the job's outputs (those its record vouches for) are put back
    afterwards, or the next check would call them edited."""
    from claims import runner
    from claims.core import Result
    monkeypatch.setattr(runner, "ROOT", tmp_path)
    (tmp_path / "fig.png").write_bytes(b"committed")

    class Job:
        def compute(self):
            (tmp_path / "fig.png").write_bytes(b"rendered here")
            return Result({"x": 1.0})
    assert runner.recompute(Job(), keep={"fig.png": "digest"}) == {"x": 1.0}
    assert (tmp_path / "fig.png").read_bytes() == b"committed"
