"""Extended XYZ reader: the files of :func:`fricstab.io.export.write_extxyz` and of OVITO / ASE.

A frame is a count line, a comment line of ``key=value`` pairs (values in
double quotes may hold spaces) and one line per particle, whose columns the
``Properties`` key lists as ``name:type:count`` (type ``S`` string, ``R``
real, ``I`` integer, ``L`` logical; default ``species:S:1:pos:R:3``).

Read: ``pos`` (x, y; z is ignored), ``radius`` (required: a disk packing),
``id`` (else the ids are 1..N), ``mass`` or ``masses``, ``angle`` or
``theta`` (radians), ``fixed`` (logical or 0/1).  Property names are matched
without regard to case.  ``Lattice="ax ay az bx by bz cx cy cz"`` gives the
box: ``a`` must lie along x (``ay = az = 0``), ``ly = by`` and the tilt
``bx`` is the Lees-Edwards offset; ``Origin="x y z"`` its lower corner
(default 0); ``pbc="T F F"`` the periodicity (default ``T T T`` with a
Lattice).  No Lattice: no box.  The last frame unless ``frame`` is given.
Units are not in the format: pass ``units`` (a dict of names) to record them.
"""

import shlex

import numpy as np

from fricstab.errors import ParameterError
from fricstab.io.imports._text import TextFile
from fricstab.io.imports.state import ImportedState

__all__ = ["read_extxyz"]

_LOGICAL = {"t": True, "true": True, "1": True, "f": False, "false": False, "0": False}


def _frames(tf):
    """Start lines of the frames (count lines)."""
    starts, k = [], 1
    while k <= len(tf):
        if not tf.line(k).strip():
            k += 1
            continue
        n = tf.ints(k, tf.tokens(k, count=1), "particle count")[0]
        if n < 0:
            tf.fail(k, f"negative particle count {n}")
        if k + 1 + n > len(tf):
            tf.fail(len(tf), f"the frame of line {k} announces {n} particles; the file ends early")
        starts.append(k)
        k += n + 2
    if not starts:
        tf.fail(1, "empty file")
    return starts


def _keys(tf, k):
    try:
        items = shlex.split(tf.line(k))
    except ValueError as err:
        tf.fail(k, f"comment line: {err}")
    out = {}
    for item in items:
        key, eq, val = item.partition("=")
        out[key.lower()] = val if eq else "T"
    return out


def _properties(tf, k, spec):
    parts = spec.split(":")
    if len(parts) % 3:
        tf.fail(k, f"Properties={spec!r} is not name:type:count triples")
    props, col = {}, 0
    for name, kind, count in zip(parts[0::3], parts[1::3], parts[2::3]):
        if kind not in "SRIL" or len(kind) != 1 or not count.isdigit() or int(count) < 1:
            tf.fail(k, f"Properties: {name}:{kind}:{count} is not name:S|R|I|L:count")
        props[name.lower()] = (col, int(count), kind)
        col += int(count)
    return props, col


def _column(tf, rows, props, names, what, count=1, required=False):
    for name in names:
        if name in props:
            col, n, kind = props[name]
            if n != count or kind not in "RIL":
                tf.fail(rows[0][0] - 1 if rows else 1,
                        f"property {name} has {n} {kind} column(s), expected {count} number(s)")
            if kind == "L":
                return _logical(tf, rows, col)
            return np.array([tf.floats(j, t[col:col + count], name) for j, t in rows]
                            ).reshape(len(rows), count)
    if required:
        tf.fail(rows[0][0] - 1 if rows else 1, f"no {what} property (Properties has "
                                               f"{', '.join(props)})")
    return None


def _logical(tf, rows, col):
    out = []
    for j, t in rows:
        if t[col].lower() not in _LOGICAL:
            tf.fail(j, f"{t[col]!r} is not a logical (T/F)")
        out.append(_LOGICAL[t[col].lower()])
    return np.array(out, float)[:, None]


def _cell(tf, k, keys):
    if "lattice" not in keys:
        return None, (0.0, 0.0), 0.0, None
    lat = tf.floats(k, keys["lattice"].split(), "Lattice")
    if len(lat) != 9:
        tf.fail(k, f"Lattice has {len(lat)} numbers, expected 9")
    (ax, ay, az), (bx, by, bz) = lat[0:3], lat[3:6]
    if ay or az or bz:
        tf.fail(k, "Lattice: the first vector must lie along x and the second in the xy plane")
    if not (ax > 0 and by > 0):
        tf.fail(k, f"Lattice: box {ax} x {by} has no size")
    origin = tf.floats(k, keys.get("origin", "0 0 0").split(), "Origin")[:2]
    flags = keys.get("pbc", "T T T").split()
    if len(flags) != 3 or any(f.lower() not in _LOGICAL for f in flags):
        tf.fail(k, f"pbc={keys.get('pbc')!r}: expected three of T/F")
    return (ax, by), tuple(origin), bx, tuple(_LOGICAL[f.lower()] for f in flags[:2])


def read_extxyz(path, *, frame=-1, units=None):
    """Read one frame of an extended XYZ file (see the module docstring).

    Parameters
    ----------
    path : str or Path
    frame : int
        Frame index (default -1, the last).
    units : dict, optional
        Unit names to record (the format has none).

    Returns
    -------
    ImportedState
    """
    tf = TextFile(path)
    starts = _frames(tf)
    if isinstance(frame, bool) or not isinstance(frame, int) or \
            not -len(starts) <= frame < len(starts):
        raise ParameterError(f"frame = {frame!r}: {tf.path} has {len(starts)} frame(s)")
    k0 = starts[frame]
    n = tf.ints(k0, tf.tokens(k0), "count")[0]
    keys = _keys(tf, k0 + 1)
    props, ncols = _properties(tf, k0 + 1, keys.get("properties", "species:S:1:pos:R:3"))
    rows = [(j, tf.tokens(j, count=ncols)) for j in range(k0 + 2, k0 + 2 + n)]
    pos = _column(tf, rows, props, ("pos",), "pos", count=3, required=True)[:, :2]
    radius = _column(tf, rows, props, ("radius",), "radius", required=True)[:, 0]
    ids = _column(tf, rows, props, ("id",), "id")
    ids = np.arange(1, n + 1) if ids is None else ids[:, 0]
    if not np.all(ids == np.round(ids)):
        tf.fail(k0 + 2, "ids must be integers")
    mass, theta, fixed = (_column(tf, rows, props, names, names[0])
                          for names in (("mass", "masses"), ("angle", "theta"), ("fixed",)))
    box, origin, tilt, per = _cell(tf, k0 + 1, keys)
    return ImportedState(pos=pos, radius=radius, ids=ids.astype(np.int64),
                         mass=None if mass is None else mass[:, 0],
                         theta=None if theta is None else theta[:, 0],
                         fixed=None if fixed is None else fixed[:, 0].astype(bool),
                         box=box, origin=origin, le_offset=tilt, periodic=per,
                         units=dict(units or {}),
                         sources=[(tf.path, f"particles (frame {starts.index(k0)} of "
                                            f"{len(starts)})")],
                         particle_lines=tuple((tf.path, j) for j, _ in rows))
