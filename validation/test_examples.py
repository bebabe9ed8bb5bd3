"""The worked examples run as written, print what the docs say, and are shown verbatim.

They are the code cells of the tutorial ``docs/tutorials/compose.md``."""

import runpy
from pathlib import Path

import pytest

HERE = Path(__file__).resolve().parent / "examples"
TUTORIAL = (Path(__file__).resolve().parent.parent / "docs" / "tutorials" / "compose.md").read_text()


@pytest.mark.parametrize("name", ["chain_ishima_ramp.py", "packing_charan_strain.py"])
def test_example_is_shown_verbatim_in_the_tutorial(name):
    assert (HERE / name).read_text().strip() in TUTORIAL


def test_chain_of_twenty_with_ishima_law_finds_its_first_birth(capsys):
    """Its claim: a birth is located (bracket <= 1e-8, the bisection tolerance) below
    F_x = 0.02; measured F_x = 0.00558659 (the value the tutorial states)."""
    runpy.run_path(str(HERE / "chain_ishima_ramp.py"), run_name="__main__")
    out = capsys.readouterr().out
    fx = float(out.split("F_x = ")[1].split()[0])
    bracket = float(out.split("bracket ")[1].rstrip(")\n"))
    assert 0 < fx < 0.02 and bracket <= 1e-8
    assert f"{fx:.8f}" in TUTORIAL


def test_packing_with_charan_law_has_complex_pairs_after_step_strain(capsys):
    """Its claims: Newton converges to the force threshold 1e-14, and the histories of
    the strained state make complex-conjugate pairs of M^-1 K (measured: 2 at
    N = 128, phi = 0.86, seed 0; the count is discrete, the threshold 1e-10 of
    max|lambda| far below the pairs' |Im| ~ 1e-4 max|lambda|)."""
    runpy.run_path(str(HERE / "packing_charan_strain.py"), run_name="__main__")
    out = capsys.readouterr().out
    residual = float(out.split("max |F| = ")[1].split(";")[0])
    assert residual < 1e-14
    assert "378 eigenvalues, 2 complex-conjugate pairs" in out
