"""Line-level helpers the readers share: numbered lines, numbers and errors that name ``path:line``.

Every reader reads its file through :class:`TextFile`, converts tokens with
:meth:`TextFile.floats` / :meth:`TextFile.ints` and raises through
:meth:`TextFile.fail`, so that a bad file gives one
:class:`~fricstab.io.imports.state.FileFormatError` naming the file and the
line, never a ``ValueError`` or ``IndexError`` from the parsing.
"""

import math
import re

import numpy as np

from fricstab.io.imports.state import FileFormatError

__all__ = ["TextFile", "id_index", "min_image_normal", "parse_units"]


class TextFile:
    """The lines of a text file with their 1-based numbers (the file is read once, whole)."""

    def __init__(self, path):
        self.path = str(path)
        try:
            with open(path, encoding="utf-8", errors="strict") as fh:
                self.lines = fh.read().splitlines()
        except (OSError, UnicodeDecodeError) as err:
            raise FileFormatError(self.path, None,
                                  f"cannot read the file ({type(err).__name__}: {err})") from None

    def __len__(self):
        return len(self.lines)

    def line(self, k):
        """Line ``k`` (1-based); past the end raises 'the file ends early'."""
        if k < 1 or k > len(self.lines):
            self.fail(len(self.lines), "the file ends early (truncated?)")
        return self.lines[k - 1]

    def fail(self, k, what):
        raise FileFormatError(self.path, k, what)

    def tokens(self, k, count=None, at_least=None):
        """The whitespace-separated tokens of line ``k`` (a ``#`` comment removed)."""
        toks = self.line(k).split("#", 1)[0].split()
        if count is not None and len(toks) != count:
            self.fail(k, f"expected {count} fields, found {len(toks)}")
        if at_least is not None and len(toks) < at_least:
            self.fail(k, f"expected at least {at_least} fields, found {len(toks)}")
        return toks

    def floats(self, k, toks, what="value"):
        """Finite floats from ``toks``; a non-number or NaN/inf names line ``k``."""
        out = []
        for t in toks:
            try:
                v = float(t)
            except ValueError:
                self.fail(k, f"{what}: {t!r} is not a number")
            if not math.isfinite(v):
                self.fail(k, f"{what}: {t} is not finite")
            out.append(v)
        return out

    def ints(self, k, toks, what="integer"):
        """Integers from ``toks`` (``"3"`` or ``"3.0"``, as dumps of computes write ids)."""
        out = []
        for t in toks:
            try:
                v = int(t)
            except ValueError:
                try:
                    f = float(t)
                except ValueError:
                    f = math.nan
                if not (math.isfinite(f) and f == int(f)):
                    self.fail(k, f"{what}: {t!r} is not an integer")
                v = int(f)
            out.append(v)
        return out


def id_index(ids, lines):
    """{id: row}; an id seen twice raises at the line of the second (``lines[row]``)."""
    index = {}
    for row, pid in enumerate(ids):
        pid = int(pid)
        if pid in index:
            raise FileFormatError(*lines[row], f"particle id {pid} appears twice")
        index[pid] = row
    return index


_UNIT_RE = re.compile(r"^\s*#\s*units\s*:(.*)$", re.IGNORECASE)


def parse_units(tf, k):
    """``# units: length=mm force=N mass=g`` on line ``k`` -> dict; ``None`` if not a units line."""
    m = _UNIT_RE.match(tf.line(k))
    if not m:
        return None
    units = {}
    for item in m.group(1).replace(",", " ").split():
        key, eq, val = item.partition("=")
        if not eq or not key or not val:
            tf.fail(k, f"units: {item!r} is not name=unit")
        units[key.strip().lower()] = val.strip()
    return units


def min_image_normal(pos, box, periodic, le_offset, ci, cj):
    """Unit vectors from i to j (nearest periodic image, Lees-Edwards tilt in x) and distances."""
    d = pos[cj] - pos[ci]
    if box is not None:
        lx, ly = box
        if periodic[1]:
            shift = np.round(d[:, 1] / ly)
            d[:, 1] -= shift * ly
            d[:, 0] -= shift * le_offset
        if periodic[0]:
            d[:, 0] -= np.round(d[:, 0] / lx) * lx
    r = np.hypot(d[:, 0], d[:, 1])
    return d / np.where(r > 0, r, 1.0)[:, None], r
