"""LIGGGHTS reader: a per-atom dump plus a ``dump local`` of ``compute pair/gran/local``.

Column layout (LIGGGHTS-PUBLIC documentation ``doc/compute_pair_gran_local.txt``
and source ``src/compute_pair_gran_local.cpp``, github.com/CFDEMproject/LIGGGHTS-PUBLIC;
the force and torque are ``i_forces.delta_F`` / ``delta_torque``, those on
particle i, in ``pair_gran.h``): whatever order the keywords are
given in, the compute's columns come in this order, each keyword present
or not:

==================  ======  =====================================================
keyword             values  meaning
==================  ======  =====================================================
pos                 6       x, y, z of i then of j
vel                 6       velocities of i then of j
id                  3       id of i, id of j, 1 if across a periodic boundary
force               3       contact force on i
force_normal        3       its component along the line of centres
force_tangential    3       the rest
torque              3       contact torque on i (documented as "torque divided by
                            the particle diameter" for old versions)
history             n       the pair style's history (``tangential history``: 3
                            shear displacement components)
contactArea         1       contact area
delta               1       overlap
heatFlux            1       conductive heat flux
==================  ======  =====================================================

With no keyword the compute outputs ``pos vel id force torque history
contactArea``.  The dump names the columns ``c_ID[k]`` (k from 1); the
reader finds the compute's columns by that name (``compute_id`` when the
dump has several computes), so other columns and a subset of the compute's
columns may be dumped.  Read: ``id`` (required), ``force_normal`` and
``force_tangential`` (or, when only ``force`` is there, its split along the
line of centres, nearest periodic image), ``torque`` (z), ``history``
(its first two components, x and y, as the file states them).
"""

import re

import numpy as np

from fricstab.errors import ParameterError
from fricstab.io.imports._text import id_index, min_image_normal
from fricstab.io.imports.lammps import pair_frame, particle_box, particle_fields
from fricstab.io.imports.state import ImportedState

__all__ = ["DEFAULT_KEYWORDS", "read_liggghts"]

DEFAULT_KEYWORDS = ("pos", "vel", "id", "force", "torque", "history", "contactArea")
_ORDER = (("pos", 6), ("vel", 6), ("id", 3), ("force", 3), ("force_normal", 3),
          ("force_tangential", 3), ("torque", 3), ("history", None), ("contactArea", 1),
          ("delta", 1), ("heatFlux", 1))
_NAME = re.compile(r"^c_([^\[\]]+)\[(\d+)\]$")


def layout(keywords, n_history):
    """{keyword: first column (1-based) of the compute's output}."""
    known = [k for k, _ in _ORDER]
    for kw in keywords:
        if kw not in known:
            raise ParameterError(f"keywords: {kw!r} is not a compute pair/gran/local keyword "
                                 f"whose column position is documented ({', '.join(known)})")
    out, col = {}, 1
    for kw, n in _ORDER:
        if kw in keywords:
            out[kw] = col
            col += n_history if n is None else n
    return out


def _compute_columns(tf, fr, compute_id):
    """{k: column index in the dump} of ``c_<compute_id>[k]``."""
    found = {}
    for c, name in enumerate(fr.columns):
        m = _NAME.match(name)
        if m:
            found.setdefault(m.group(1), {})[int(m.group(2))] = c
    if compute_id is None:
        if len(found) != 1:
            tf.fail(fr.header_line, f"{'no' if not found else 'several'} c_ID[k] columns "
                                    f"({', '.join(found) or fr.columns[:4]}): give compute_id")
        compute_id = next(iter(found))
    if compute_id not in found:
        tf.fail(fr.header_line, f"no column c_{compute_id}[k]")
    return found[compute_id]


def _values(tf, fr, cols, start, count, what, required=False):
    idx = [start + i for i in range(count)]
    if any(k not in cols for k in idx):
        if required:
            tf.fail(fr.header_line, f"the dump lacks the {what} columns "
                                    f"c_ID[{idx[0]}]..c_ID[{idx[-1]}]")
        return None
    out = np.empty((len(fr.rows), count))
    for r, (k, toks) in enumerate(fr.rows):
        out[r] = tf.floats(k, [toks[cols[i]] for i in idx], what)
    return out


def read_liggghts(*, atoms, pairs, keywords=DEFAULT_KEYWORDS, n_history=3, compute_id=None,
                  frame=-1, periodic=None, fixed_types=(), units=None):
    """Read a LIGGGHTS packing: a per-atom dump and a pair/gran/local dump (module docstring).

    Parameters
    ----------
    atoms : str or Path
        Per-atom text dump (``id``, positions, ``radius``).
    pairs : str or Path
        ``dump local`` of the compute; its frame at the atoms' frame's timestep is read.
    keywords : sequence of str
        The keywords given to ``compute pair/gran/local`` (default: its default output).
    n_history : int
        The pair style's number of history values.
    compute_id : str, optional
        The compute's ID, when the dump has columns of several computes.
    frame, periodic, fixed_types, units
        As in :func:`fricstab.io.imports.read_lammps_dump`.

    Returns
    -------
    ImportedState
    """
    if isinstance(n_history, bool) or not isinstance(n_history, int) or n_history < 0:
        raise ParameterError(f"n_history = {n_history!r} must be an integer >= 0")
    lay = layout(tuple(keywords), n_history)
    if "id" not in lay:
        raise ParameterError("keywords: 'id' is required (the pair's particle ids)")
    pfields, sources, timestep = particle_fields(None, atoms, frame, periodic,
                                                 fixed_types=fixed_types, units=units)
    base = ImportedState(sources=sources, **pfields)
    tf, fr = pair_frame(pairs, timestep, frame, particle_box(pfields))
    cols = _compute_columns(tf, fr, compute_id)
    ids = _values(tf, fr, cols, lay["id"], 2, "id", required=True)
    index = id_index(base.ids, base.particle_lines)
    ci, cj = [], []
    for r, (k, _) in enumerate(fr.rows):
        for pid, out in ((ids[r, 0], ci), (ids[r, 1], cj)):
            if pid != int(pid) or int(pid) not in index:
                tf.fail(k, f"the pair names particle id {pid:g}, which the atoms dump lacks")
            out.append(index[int(pid)])
    ci, cj = np.array(ci, np.int64), np.array(cj, np.int64)
    fields = _forces(tf, fr, cols, lay, base, ci, cj)
    if "history" in lay and n_history >= 2:
        fields["history"] = _values(tf, fr, cols, lay["history"], 2, "history")
    if "torque" in lay:
        t = _values(tf, fr, cols, lay["torque"], 3, "torque")
        fields["torque"] = None if t is None else t[:, 2]
    kept = {k: v for k, v in fields.items() if v is not None}
    what = f"contacts ({', '.join(['ids'] + list(kept))}) at timestep {fr.timestep}"
    return ImportedState(ci=ci, cj=cj, contact_lines=tuple((tf.path, k) for k, _ in fr.rows),
                         sources=sources + [(tf.path, what)], **pfields, **kept)


def _forces(tf, fr, cols, lay, base, ci, cj):
    fn = ft = None
    if "force_normal" in lay:
        fn = _values(tf, fr, cols, lay["force_normal"], 2, "force_normal")
    if "force_tangential" in lay:
        ft = _values(tf, fr, cols, lay["force_tangential"], 2, "force_tangential")
    f = _values(tf, fr, cols, lay["force"], 2, "force") if "force" in lay else None
    if f is not None and (fn is None or ft is None):
        n, _ = min_image_normal(base.pos, base.box, base.periodic, base.le_offset, ci, cj)
        split = np.einsum("ka,ka->k", f, n)[:, None] * n
        fn = split if fn is None else fn
        ft = f - fn if ft is None else ft
    return {"force_n": fn, "force_t": ft}
