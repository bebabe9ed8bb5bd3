"""Readers of packings made elsewhere (LAMMPS, LIGGGHTS, OVITO/extxyz, a plain CSV format).

Each ``read_<format>(path, ...)`` returns one :class:`ImportedState`: the
particles, the box and the contacts with their tangential state, in the
file's units (named in ``units``, never guessed or converted).  A bad file
raises :class:`FileFormatError` (``path:line: what``).  See
``docs/howto/import.md``.
"""

from fricstab.io.imports.extxyz import read_extxyz
from fricstab.io.imports.lammps import read_lammps, read_lammps_data, read_lammps_dump
from fricstab.io.imports.liggghts import read_liggghts
from fricstab.io.imports.load import load_state
from fricstab.io.imports.state import FileFormatError, ImportedState
from fricstab.io.imports.table import read_csv

__all__ = ["FileFormatError", "ImportedState", "load_state", "read_csv", "read_extxyz",
           "read_lammps", "read_lammps_data", "read_lammps_dump", "read_liggghts"]
