"""The neutral in-memory packing every reader returns: :class:`ImportedState`.

A packing made elsewhere (LAMMPS, LIGGGHTS, OVITO, an experiment) becomes
particles (positions, radii, the file's ids, optional masses, rotations and
fixed flags), a box, and contacts with whatever tangential state the file
has.  Units are the file's, by name (``units``); nothing is converted here.

Conventions
-----------
* ``ci``, ``cj`` index the particle arrays (not the file's ids); a contact's
  ``force_n`` and ``force_t`` are the normal and tangential force **on i
  from j**; ``history`` is the tangential displacement (or whatever the
  file's history holds, see the reader) as the file states it; ``torque`` is
  the z torque the file gives for the contact.
* ``box`` = (lx, ly) of the cell with lower corner ``origin``; ``periodic``
  = (x, y) flags (default both, when a box is given); ``box is None`` means
  no cell at all.  ``le_offset`` is the x shift of the image above (the
  LAMMPS triclinic ``xy`` tilt, Lees-Edwards).
* ``particle_lines`` / ``contact_lines``: optional ``(path, line)`` per row,
  where it was read; the checks name them.

Bad content raises :class:`FileFormatError` (a
:class:`~fricstab.errors.ParameterError`: the command line prints
``fricstab: error: path:line: what`` and exits 2).
"""

from dataclasses import dataclass, field

import numpy as np

from fricstab.errors import ParameterError

__all__ = ["FileFormatError", "ImportedState", "contact_where"]


class FileFormatError(ParameterError):
    """A file that cannot be read as its format says; the message is ``path:line: what``."""

    def __init__(self, path, line, what):
        self.path, self.line, self.what = str(path), line, what
        where = self.path if line is None else f"{self.path}:{line}"
        super().__init__(f"{where}: {what}")


def _where(lines, k, sources):
    if lines is not None and 0 <= k < len(lines):
        return lines[k]
    return (sources[0][0] if sources else "<imported state>", None)


@dataclass(frozen=True, eq=False)
class ImportedState:
    """Particles, box and contacts read from a file (see the module docstring)."""

    pos: np.ndarray
    radius: np.ndarray
    ids: np.ndarray
    mass: np.ndarray = None
    theta: np.ndarray = None
    fixed: np.ndarray = None
    box: tuple = None
    origin: tuple = (0.0, 0.0)
    le_offset: float = 0.0
    periodic: tuple = None
    ci: np.ndarray = None
    cj: np.ndarray = None
    history: np.ndarray = None
    force_n: np.ndarray = None
    force_t: np.ndarray = None
    torque: np.ndarray = None
    units: dict = field(default_factory=dict)
    sources: list = field(default_factory=list)
    particle_lines: tuple = None
    contact_lines: tuple = None

    @property
    def n(self):
        """Number of particles."""
        return len(self.radius)

    @property
    def n_contacts(self):
        """Number of contacts."""
        return len(self.ci)

    def _fail(self, lines, k, what):
        path, line = _where(lines, k, self.sources)
        raise FileFormatError(path, line, what)

    def _set(self, name, value):
        object.__setattr__(self, name, value)

    def _array(self, name, shape, dtype, lines):
        value = getattr(self, name)
        if value is None:
            return
        try:
            a = np.array(value, dtype=dtype)
        except (TypeError, ValueError):
            self._fail(None, 0, f"{name} is not an array of numbers")
        if a.shape != shape:
            self._fail(None, 0, f"{name} has shape {a.shape}, expected {shape}")
        if a.dtype.kind == "f" and a.size and not np.isfinite(a).all():
            row = int(np.flatnonzero(~np.isfinite(a.reshape(len(a), -1)).any(axis=1))[0])
            self._fail(lines, row, f"{name} is not finite: {a[row]}")
        a.flags.writeable = False
        self._set(name, a)

    def __post_init__(self):
        pl, cl = self.particle_lines, self.contact_lines
        try:
            n = len(self.radius)
        except TypeError:
            self._fail(None, 0, "radius is not an array")
        self._array("pos", (n, 2), float, pl)
        self._array("radius", (n,), float, pl)
        self._array("ids", (n,), np.int64, pl)
        self._array("mass", (n,), float, pl)
        self._array("theta", (n,), float, pl)
        if self.fixed is None:
            self._set("fixed", np.zeros(n, bool))
        self._array("fixed", (n,), bool, pl)
        bad = np.flatnonzero(self.radius <= 0)
        if bad.size:
            self._fail(pl, int(bad[0]), f"radius {self.radius[bad[0]]} is not positive")
        if self.mass is not None and (self.mass <= 0).any():
            k = int(np.flatnonzero(self.mass <= 0)[0])
            self._fail(pl, k, f"mass {self.mass[k]} is not positive")
        order = np.argsort(self.ids, kind="stable")
        dup = np.flatnonzero(np.diff(self.ids[order]) == 0)
        if dup.size:
            k = int(order[dup[0] + 1])
            self._fail(pl, k, f"particle id {self.ids[k]} appears twice")
        self._check_box(pl)
        self._check_contacts(cl)
        self._set("units", dict(self.units))
        self._set("sources", list(self.sources))

    def _check_box(self, pl):
        self._set("origin", tuple(float(v) for v in self.origin))
        self._set("le_offset", float(self.le_offset))
        if not np.isfinite(self.origin).all() or not np.isfinite(self.le_offset):
            self._fail(None, 0, "origin and le_offset must be finite")
        if self.box is None:
            self._set("periodic", (False, False))
            return
        box = tuple(float(v) for v in self.box)
        if len(box) != 2 or not all(np.isfinite(box)) or min(box) <= 0:
            self._fail(None, 0, f"box {self.box} must be two positive lengths")
        self._set("box", box)
        per = (True, True) if self.periodic is None else tuple(bool(p) for p in self.periodic)
        self._set("periodic", per)
        for axis in (0, 1):
            if per[axis]:
                continue
            lo, hi = self.origin[axis], self.origin[axis] + box[axis]
            out = np.flatnonzero((self.pos[:, axis] < lo) | (self.pos[:, axis] > hi))
            if out.size:
                k = int(out[0])
                self._fail(pl, k, f"particle {self.ids[k]} at {'xy'[axis]} = "
                                  f"{self.pos[k, axis]} lies outside the non-periodic box "
                                  f"[{lo}, {hi}]")

    def _check_contacts(self, cl):
        n = self.n
        if self.ci is None:
            self._set("ci", np.zeros(0, np.int64))
            self._set("cj", np.zeros(0, np.int64))
        k = len(self.ci) if self.cj is not None else -1
        self._array("ci", (k,), np.int64, cl)
        self._array("cj", (k,), np.int64, cl)
        for name in ("ci", "cj"):
            a = getattr(self, name)
            bad = np.flatnonzero((a < 0) | (a >= n))
            if bad.size:
                self._fail(cl, int(bad[0]), f"contact {name} = {a[bad[0]]} is not a particle "
                                            f"index in [0, {n})")
        same = np.flatnonzero(self.ci == self.cj)
        if same.size:
            c = int(same[0])
            self._fail(cl, c, f"contact of particle {self.ids[self.ci[c]]} with itself")
        for name in ("history", "force_n", "force_t"):
            self._array(name, (k, 2), float, cl)
        self._array("torque", (k,), float, cl)


def contact_where(imported, c):
    """Where contact ``c`` of ``imported`` was read: ``path:line``, or the first source."""
    lines = imported.contact_lines
    if lines is not None and 0 <= c < len(lines):
        return f"{lines[c][0]}:{lines[c][1]}"
    return f"{imported.sources[0][0] if imported.sources else '<imported state>'} contact {c}"
