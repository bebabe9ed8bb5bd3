"""The LAMMPS text formats the readers share: dump frames (``ITEM:`` blocks) and unit styles.

A text dump is a sequence of frames, each opened by ``ITEM: TIMESTEP``;
:func:`dump_frame` parses one into a :class:`Frame`: timestep, the box
(``ITEM: BOX BOUNDS [xy xz yz] xx yy zz``, converted from the bounding box
LAMMPS writes for a triclinic cell to lo/hi plus the ``xy`` tilt), the
column names of ``ITEM: ATOMS`` (per-atom dump) or ``ITEM: ENTRIES``
(``dump local``) and the rows with their line numbers.  ``ITEM: UNITS``
(``dump_modify units yes``) gives the unit style.
"""

from dataclasses import dataclass

from fricstab.errors import ParameterError
from fricstab.io.imports._text import TextFile

__all__ = ["LAMMPS_UNITS", "Frame", "dump_frame", "frame_starts", "unit_names"]

#: The names of the units of the LAMMPS unit styles granular users use (LAMMPS ``units``).
LAMMPS_UNITS = {
    "lj": {"length": "sigma", "mass": "m", "time": "tau", "force": "epsilon/sigma"},
    "si": {"length": "m", "mass": "kg", "time": "s", "force": "N"},
    "cgs": {"length": "cm", "mass": "g", "time": "s", "force": "dyne"},
    "micro": {"length": "um", "mass": "pg", "time": "us", "force": "pg*um/us^2"},
    "nano": {"length": "nm", "mass": "ag", "time": "ns", "force": "ag*nm/ns^2"},
}


def unit_names(units, where="units"):
    """A unit style name (``"si"``) or a dict of names -> dict with ``style`` when a style."""
    if units is None:
        return {}
    if isinstance(units, dict):
        return {str(k): str(v) for k, v in units.items()}
    if isinstance(units, str) and units.lower() in LAMMPS_UNITS:
        return {"style": units.lower(), **LAMMPS_UNITS[units.lower()]}
    raise ParameterError(f"{where} = {units!r}: give a LAMMPS unit style "
                         f"({', '.join(LAMMPS_UNITS)}) or a dict of unit names")


@dataclass
class Frame:
    """One dump frame: ``rows`` = [(line, tokens)], ``columns`` the header names."""

    timestep: int
    columns: list
    header_line: int
    rows: list
    lo: tuple = None
    hi: tuple = None
    tilt: float = 0.0
    periodic: tuple = None
    box_line: int = None
    units: str = None
    units_line: int = None

    @property
    def box(self):
        return None if self.lo is None else (self.hi[0] - self.lo[0], self.hi[1] - self.lo[1])


def frame_starts(tf):
    """Line numbers of the ``ITEM: TIMESTEP`` lines (an empty file raises)."""
    starts = [k + 1 for k, s in enumerate(tf.lines) if s.strip() == "ITEM: TIMESTEP"]
    if not starts:
        tf.fail(1, "no 'ITEM: TIMESTEP' line: not a LAMMPS text dump")
    return starts


def pick_frame(tf, starts, frame):
    """The start line of frame ``frame`` (an index; negative counts from the end)."""
    if isinstance(frame, bool) or not isinstance(frame, int) or not -len(starts) <= frame \
            < len(starts):
        raise ParameterError(f"frame = {frame!r}: {tf.path} has {len(starts)} frame(s), "
                             f"give an integer in [{-len(starts)}, {len(starts)})")
    return starts[frame]


def _box(tf, k, fr):
    toks = tf.line(k).split()[3:]
    tilted = toks[:3] == ["xy", "xz", "yz"]
    flags = toks[3:] if tilted else toks
    if len(flags) != 3 or any(len(f) != 2 or set(f) - set("pfsm") for f in flags):
        tf.fail(k, f"BOX BOUNDS flags {' '.join(toks)!r}: expected three of pp, ff, fs, sm...")
    b = [tf.floats(k + i, tf.tokens(k + i, count=3 if tilted else 2), "box bound")
         for i in (1, 2, 3)]
    xy, xz, yz = (b[0][2], b[1][2], b[2][2]) if tilted else (0.0, 0.0, 0.0)
    if xz != 0.0 or yz != 0.0:
        tf.fail(k + 2, f"tilts xz = {xz}, yz = {yz}: a 2D packing has only xy")
    lo = (b[0][0] - min(0.0, xy), b[1][0])
    hi = (b[0][1] - max(0.0, xy), b[1][1])
    for axis in (0, 1):
        if not hi[axis] > lo[axis]:
            tf.fail(k + 1 + axis, f"box {'xy'[axis]} from {lo[axis]} to {hi[axis]} has no size")
    fr.lo, fr.hi, fr.tilt, fr.box_line = lo, hi, xy, k
    fr.periodic = (flags[0] == "pp", flags[1] == "pp")
    return k + 4


def dump_frame(tf, start, kind):
    """Parse the frame at line ``start``; ``kind`` is ``"ATOMS"`` or ``"ENTRIES"``."""
    fr = Frame(timestep=None, columns=None, header_line=None, rows=[])
    count, k, end, seen = None, start, len(tf) + 1, set()
    while k < end:
        s = tf.line(k).strip()
        if s == "ITEM: TIMESTEP" and k != start:
            break
        key = " ".join(s.split()[:2]) if s.startswith("ITEM:") else None
        if key is not None and key in seen:
            tf.fail(k, f"a second {key!r} in one frame (an 'ITEM: TIMESTEP' line missing?)")
        seen.add(key)
        if s == "ITEM: TIMESTEP":
            fr.timestep = tf.ints(k + 1, tf.tokens(k + 1, count=1), "timestep")[0]
            k += 2
        elif s.startswith("ITEM: NUMBER OF"):
            count = tf.ints(k + 1, tf.tokens(k + 1, count=1), "count")[0]
            if count < 0:
                tf.fail(k + 1, f"negative count {count}")
            k += 2
        elif s.startswith("ITEM: BOX BOUNDS"):
            k = _box(tf, k, fr)
        elif s == "ITEM: UNITS":
            fr.units, fr.units_line = tf.tokens(k + 1, count=1)[0].lower(), k + 1
            k += 2
        elif s.startswith("ITEM: " + kind):
            k = _rows(tf, k, fr, count, kind)
        elif s.startswith("ITEM:"):
            k = _skip_item(tf, k)
        else:
            tf.fail(k, f"unexpected line {s[:40]!r} in a dump frame")
    if fr.columns is None:
        tf.fail(start, f"frame has no 'ITEM: {kind}' block"
                       f"{' (a dump local file has ENTRIES)' if kind == 'ATOMS' else ''}")
    return fr


def _skip_item(tf, k):
    k += 1
    while k <= len(tf) and not tf.line(k).startswith("ITEM:"):
        k += 1
    return k


def _rows(tf, k, fr, count, kind):
    if count is None:
        tf.fail(k, f"'ITEM: {kind}' before 'ITEM: NUMBER OF ...'")
    fr.columns = tf.line(k).split()[2:]
    fr.header_line = k
    if len(set(fr.columns)) != len(fr.columns):
        tf.fail(k, f"a column name appears twice in {' '.join(fr.columns)}")
    for i in range(count):
        fr.rows.append((k + 1 + i, tf.tokens(k + 1 + i, count=len(fr.columns))))
    return k + 1 + count


def read_frame(path, frame, kind):
    """Open ``path`` and parse its frame ``frame`` (index); returns (TextFile, Frame, count)."""
    tf = TextFile(path)
    starts = frame_starts(tf)
    return tf, dump_frame(tf, pick_frame(tf, starts, frame), kind), starts
