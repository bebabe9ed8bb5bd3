"""A packing that is not force-balanced is refused before the LU (issue 32).

:func:`fricstab.rigidity` factorizes ``J`` (bordered sparse LU); at a state
out of balance it used to answer a silently wrong G or fail inside SuperLU.
It now raises :class:`ParameterError` naming max |F| and the tolerance
(:data:`fricstab.analysis.rigidity.FORCE_BALANCE_TOL`, its error model).
"""

import re

import pytest

import fricstab as fs
from fricstab.analysis.rigidity import FORCE_BALANCE_TOL, check_force_balance


@pytest.fixture(scope="module")
def pack():
    bb = fs.backbone(fs.make_packing(16, 0.86, seed=1))
    return fs.frictional(bb, fs.packing_material("ishima"))


def test_relaxed_packing_passes(pack):
    fmax, tol = check_force_balance(pack.system, pack.state)
    # relaxed to f_tol = 1e-14 k_N d^(3/2); the tolerance is 1e-6 of the mean
    # contact force (~1e-3 here): at least four decades of room
    assert fmax < 1e-4 * tol
    assert fs.rigidity(pack.system, pack.state).g > 0


@pytest.mark.parametrize("law", ["ishima", "lee_hurley"])
def test_displaced_disk_is_refused_naming_max_force(law):
    fr = fs.frictional(fs.backbone(fs.make_packing(16, 0.86, seed=1)), fs.packing_material(law))
    state = fr.state.copy()
    state.q[0, 0] += 1e-3          # a thousandth of d: forces ~ 1e-4, far above 1e-9
    with pytest.raises(fs.ParameterError, match="not force-balanced: max [|]F[|] = ") as exc:
        fs.rigidity(fr.system, state)
    fmax, tol = map(float, re.search(r"max \|F\| = (\S+) \(tolerance (\S+) ",
                                     str(exc.value)).groups())
    assert fmax > tol > 0 and "relax it first" in str(exc.value)
    assert tol < 10 * FORCE_BALANCE_TOL   # relative to a contact force of order 1e-3


def test_overlap_outside_the_law_is_refused():
    fr = fs.frictional(fs.backbone(fs.make_packing(16, 0.86, seed=1)),
                       fs.packing_material("lee_hurley"))
    state = fr.state.copy()
    state.q[2, 1] += 0.5           # half a diameter: beyond the Hertz cylinder's turning point
    with pytest.raises(fs.ParameterError, match="not force-balanced"):
        fs.rigidity(fr.system, state)


@pytest.mark.parametrize("shift", [1e-3, 0.05, 0.2])
def test_unbalanced_packing_is_refused_by_backbone_and_the_cli(tmp_path, shift):
    """The issue's path: a packing file with a displaced disk into ``packing rigidity``.

    Before, the backbone's Newton relaxation met it: a singular sparse LU (shift
    >= 0.1) or a disk "more than 1024 box lengths away" (0.05).  Now one line,
    exit 2, naming max |F| (the packing records f_tol = 1e-14; its mean contact
    force is ~1e-3, so the tolerance is ~1e-9 and a shift of 1e-3 d gives ~1e-4).
    """
    import dataclasses
    import subprocess
    import sys
    p = fs.make_packing(16, 0.86, seed=1)
    pos = p.pos.copy()
    pos[0, 0] += shift
    bad = dataclasses.replace(p, pos=pos)
    with pytest.raises(fs.ParameterError, match="not force-balanced: max [|]F[|] = "):
        fs.backbone(bad)
    bad.save(tmp_path / "bad.npz")
    out = subprocess.run([sys.executable, "-m", "fricstab", "packing", "rigidity", "--packing",
                          str(tmp_path / "bad.npz"), "--out", str(tmp_path / "r")],
                         capture_output=True, text=True)
    assert out.returncode == 2, out.stderr
    lines = out.stderr.strip().splitlines()
    assert len(lines) == 1 and "not force-balanced: max |F| = " in lines[0]
    assert not (tmp_path / "r").exists()
