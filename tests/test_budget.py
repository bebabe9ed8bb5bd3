"""The cost estimates that commands check before they allocate (fricstab.cli.budget)."""

import tracemalloc

import numpy as np
import pytest
import scipy.linalg

from fricstab.cli import budget
from fricstab.errors import ParameterError

D = 300


@pytest.mark.parametrize("kw, call", [
    (dict(vectors=True, left=True), lambda a: scipy.linalg.eig(a, left=True, right=True)),
    (dict(vectors=True), lambda a: scipy.linalg.eig(a)),
    (dict(vectors=False), lambda a: scipy.linalg.eigvals(a)),
    (dict(vectors=True, symmetric=True), lambda a: scipy.linalg.eigh((a + a.T) / 2)),
    (dict(vectors=False, symmetric=True), lambda a: scipy.linalg.eigvalsh((a + a.T) / 2)),
])
def test_the_memory_model_against_a_measurement(kw, call):
    """Error model: the model counts the d x d arrays alive together and bounds the O(d)
    ones (LAPACK's workspace, the eigenvalues) by 64 d words; it counts the complex form
    of the vectors as alive beside the real ones, which scipy may free first: 16 d^2 of
    at most 64 d^2 bytes. So measured <= model <= 4/3 measured, with 5 % either way for
    the O(d) bound (up to 10 % of the total at d = 300) and tracemalloc's bookkeeping."""
    a = np.random.default_rng(0).standard_normal((D, D))
    tracemalloc.start()
    try:
        call(a)
        peak = tracemalloc.get_traced_memory()[1] + a.nbytes
    finally:
        tracemalloc.stop()
    model, flops = budget.dense_eig(D, **kw)
    assert 0.95 <= model / peak <= 4 / 3 * 1.05, (model, peak)
    assert flops > 0


def test_too_big_is_refused_with_the_estimate(monkeypatch):
    monkeypatch.setenv("FRICSTAB_MEMORY", str(2**30))
    nbytes, flops = budget.dense_eig(20_000, vectors=True, left=True)
    with pytest.raises(ParameterError, match=r"needs about 23.9 GiB of memory, 1 GiB available"):
        budget.require("the spectrum of a 20000 x 20000 matrix", nbytes, flops)
    est = budget.require("small", 10**6, 1e6)
    assert est["peak_memory_bytes"] == 10**6 and est["available_memory_bytes"] == 2**30


@pytest.mark.parametrize("value", ["abc", "-1", "nan", "0"])
def test_a_bad_memory_override_is_named(monkeypatch, value):
    monkeypatch.setenv("FRICSTAB_MEMORY", value)
    with pytest.raises(ParameterError, match="FRICSTAB_MEMORY"):
        budget.available_memory()


def test_a_long_computation_is_announced(monkeypatch, capsys):
    monkeypatch.setattr(budget, "_RATE", 1e9)
    budget.require("work", 10, 1e12)
    err = capsys.readouterr().err
    assert err.startswith("fricstab: note: work: estimated 17 min") and err.count("\n") == 1
    budget.require("work", 10, 1e12, dry_run=True)
    assert capsys.readouterr().err == ""


def test_available_memory_is_positive():
    assert budget.available_memory() > 0


COMMANDS = [
    ["chain", "ramp"],
    ["chain", "jacobian", "--fx", "0.01"],
    ["packing", "dos", "--n", "16"],
    ["packing", "rigidity", "--n", "16", "--modes"],
    ["packing", "aqs", "--n", "16", "--law", "charan", "--strain", "0.002", "--dgamma", "1e-3"],
    ["shear", "run", "--n", "300"],
]


@pytest.mark.parametrize("args", COMMANDS, ids=lambda a: " ".join(a[:2]))
def test_a_command_too_big_refuses_before_allocating(args, tmp_path, monkeypatch, capsys):
    """With 10 kB available every one of these commands is too big: exit 2, one line with
    the estimate, nothing written; --dry-run shows the estimate instead."""
    from fricstab.cli import main
    monkeypatch.setenv("FRICSTAB_MEMORY", "1e4")
    out = tmp_path / "out"
    assert main([*args, "--out", str(out)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "needs about" in err[0] and "available" in err[0], err
    assert not out.exists()
    monkeypatch.setenv("FRICSTAB_MEMORY", "1e12")
    assert main([*args, "--out", str(out), "--dry-run"]) == 0
    doc = capsys.readouterr().out
    assert '"estimate"' in doc and '"peak_memory_bytes"' in doc
    assert not out.exists()
