"""A plain format for measured packings (a spreadsheet saved as CSV): :func:`read_csv`.

Specification (version 1)
-------------------------
Two CSV files, or one file with a ``[particles]`` and a ``[contacts]``
section.  Empty lines are ignored; a line starting with ``#`` is a comment,
except the two directives below.  In each section the first other line is
the header naming the columns (any order, case ignored), then one line per
row, fields separated by commas.

``# units: length=mm force=N mass=g``
    Required (in the particles file or section, before the rows): the unit
    names, as free text.  ``length`` always; ``mass`` when there is a mass
    column; ``force`` when the contacts have forces.  A contacts file may
    repeat the line; the names must then agree.  Nothing is converted.
``# box: lx=100 ly=50 xlo=0 ylo=0 periodic=x tilt=0``
    Optional: the cell ``[xlo, xlo + lx] x [ylo, ylo + ly]``; ``periodic``
    is ``xy`` (default), ``x``, ``y`` or ``none``; ``tilt`` the Lees-Edwards
    x offset of the image above.  No box line: no box.

Particles: ``id,x,y,radius`` required, ``mass``, ``theta`` (rotation,
radians) and ``fixed`` (0/1, a wall particle) optional.  Ids are integers,
each once.

Contacts: ``i,j`` (particle ids) required; optional ``tx,ty`` (the
tangential displacement, the history), ``fnx,fny`` (normal force on i
from j), ``ftx,fty`` (tangential force on i from j), ``torque`` (z).

Example::

    # units: length=mm force=N mass=g
    # box: lx=10 ly=10 periodic=none
    [particles]
    id,x,y,radius,fixed
    1,2.0,2.0,1.0,1
    2,3.9,2.0,1.0,0
    [contacts]
    i,j,fnx,fny,ftx,fty
    2,1,0.5,0.0,0.0,0.1
"""

import numpy as np

from fricstab.io.imports._text import TextFile, id_index, parse_units
from fricstab.io.imports.state import ImportedState

__all__ = ["read_csv"]

_PARTICLES = {"required": ("id", "x", "y", "radius"), "optional": ("mass", "theta", "fixed")}
_CONTACTS = {"required": ("i", "j"),
             "optional": ("tx", "ty", "fnx", "fny", "ftx", "fty", "torque")}
_PAIRS = (("history", "tx", "ty"), ("force_n", "fnx", "fny"), ("force_t", "ftx", "fty"))


def _scan(tf, default):
    """{section: [data line numbers]}, units (line, dict), box (line, dict)."""
    secs, units, box, cur = {}, None, None, default
    for k in range(1, len(tf) + 1):
        s = tf.line(k).strip()
        if not s:
            continue
        if s.startswith("["):
            cur = s.strip("[]").strip().lower()
            if cur not in ("particles", "contacts") or not s.endswith("]"):
                tf.fail(k, f"section {s!r}: expected [particles] or [contacts]")
            if cur in secs:
                tf.fail(k, f"section [{cur}] appears twice")
            secs[cur] = []
        elif s.startswith("#"):
            u = parse_units(tf, k)
            if u is not None:
                units = (k, u)
            elif s[1:].strip().lower().startswith("box:"):
                box = (k, _directive(tf, k, s[1:].strip()[4:]))
        else:
            secs.setdefault(cur, []).append(k)
    return secs, units, box


def _directive(tf, k, text):
    out = {}
    for item in text.replace(",", " ").split():
        key, eq, val = item.partition("=")
        if not eq:
            tf.fail(k, f"box: {item!r} is not key=value")
        out[key.lower()] = val
    return out


def _table(tf, lines, spec, what):
    """(column names, rows [(line, fields)]) of a section; checks the header."""
    if not lines:
        tf.fail(len(tf), f"no {what} header line ({','.join(spec['required'])})")
    k0 = lines[0]
    names = [c.strip().lower() for c in tf.line(k0).split(",")]
    for name in names:
        if name not in spec["required"] + spec["optional"] or names.count(name) > 1:
            tf.fail(k0, f"column {name!r} is unknown or repeated; {what} columns: "
                        f"{', '.join(spec['required'] + spec['optional'])}")
    for name in spec["required"]:
        if name not in names:
            tf.fail(k0, f"missing column {name!r} (required: {', '.join(spec['required'])})")
    rows = []
    for k in lines[1:]:
        fields = [f.strip() for f in tf.line(k).split(",")]
        if len(fields) != len(names):
            tf.fail(k, f"expected {len(names)} fields ({','.join(names)}), found {len(fields)}")
        rows.append((k, fields))
    return k0, names, rows


def _reals(tf, rows, names, name):
    c = names.index(name)
    return np.array([tf.floats(k, [f[c]], name)[0] for k, f in rows])


def _ints(tf, rows, names, name):
    c = names.index(name)
    return np.array([tf.ints(k, [f[c]], name)[0] for k, f in rows], np.int64)


def _box(tf, box):
    if box is None:
        return {}
    k, d = box
    unknown = set(d) - {"lx", "ly", "xlo", "ylo", "periodic", "tilt"}
    if unknown or "lx" not in d or "ly" not in d:
        tf.fail(k, f"box: needs lx= and ly= (and optional xlo, ylo, periodic, tilt); got "
                   f"{', '.join(sorted(d))}")
    lx, ly, xlo, ylo, tilt = tf.floats(k, [d["lx"], d["ly"], d.get("xlo", "0"),
                                           d.get("ylo", "0"), d.get("tilt", "0")], "box")
    if not (lx > 0 and ly > 0):
        tf.fail(k, f"box {lx} x {ly} has no size")
    per = d.get("periodic", "xy").lower()
    if per not in ("xy", "x", "y", "none"):
        tf.fail(k, f"box: periodic={per!r}; allowed: xy, x, y, none")
    return dict(box=(lx, ly), origin=(xlo, ylo), le_offset=tilt,
                periodic=("x" in per, "y" in per))


def _particles(tf, lines, units):
    k0, names, rows = _table(tf, lines, _PARTICLES, "particle")
    if "mass" in names and "mass" not in units:
        tf.fail(k0, "a mass column needs mass= in the '# units:' line")
    out = dict(ids=_ints(tf, rows, names, "id"), radius=_reals(tf, rows, names, "radius"),
               pos=np.column_stack([_reals(tf, rows, names, "x"), _reals(tf, rows, names, "y")])
               if rows else np.zeros((0, 2)))
    for name in ("mass", "theta"):
        out[name] = _reals(tf, rows, names, name) if name in names else None
    if "fixed" in names:
        fixed = _ints(tf, rows, names, "fixed")
        bad = np.flatnonzero((fixed != 0) & (fixed != 1))
        if bad.size:
            tf.fail(rows[bad[0]][0], f"fixed must be 0 or 1, got {fixed[bad[0]]}")
        out["fixed"] = fixed.astype(bool)
    out["particle_lines"] = tuple((tf.path, k) for k, _ in rows)
    return out


def _contacts(tf, lines, index, units):
    k0, names, rows = _table(tf, lines, _CONTACTS, "contact")
    ci, cj = [], []
    for k, f in rows:
        for name, col in (("i", ci), ("j", cj)):
            pid = tf.ints(k, [f[names.index(name)]], name)[0]
            if pid not in index:
                tf.fail(k, f"contact names particle id {pid}, which is not a particle")
            col.append(index[pid])
    out = dict(ci=np.array(ci, np.int64), cj=np.array(cj, np.int64),
               contact_lines=tuple((tf.path, k) for k, _ in rows))
    for field, cx, cy in _PAIRS:
        if (cx in names) != (cy in names):
            tf.fail(k0, f"give both {cx} and {cy}")
        if cx in names:
            out[field] = np.column_stack([_reals(tf, rows, names, cx),
                                          _reals(tf, rows, names, cy)]).reshape(len(rows), 2)
    if "torque" in names:
        out["torque"] = _reals(tf, rows, names, "torque")
    if any(n in names for n in ("fnx", "ftx", "torque")) and "force" not in units:
        tf.fail(k0, "force columns need force= in the '# units:' line")
    return out


def read_csv(particles, contacts=None):
    """Read the plain CSV format (specification in the module docstring).

    Parameters
    ----------
    particles : str or Path
        The particles file (or one file with both sections).
    contacts : str or Path, optional
        A separate contacts file.

    Returns
    -------
    ImportedState
    """
    tf = TextFile(particles)
    secs, units, box = _scan(tf, "particles")
    if units is None:
        tf.fail(1, "no '# units: length=... ' line: the units are never guessed")
    if "length" not in units[1]:
        tf.fail(units[0], "units: length= is required")
    fields = _particles(tf, secs.get("particles", []), units[1])
    fields.update(_box(tf, box))
    sources = [(tf.path, "particles" + (" and box" if box else ""))]
    index = id_index(fields["ids"], fields["particle_lines"])
    ctf, clines, cunits = tf, secs.get("contacts"), dict(units[1])
    if contacts is not None:
        if clines is not None:
            tf.fail(clines[0] if clines else 1, "a [contacts] section here and a contacts file")
        ctf = TextFile(contacts)
        csecs, cu, _ = _scan(ctf, "contacts")
        clines = csecs.get("contacts", [])
        for key, val in (cu[1] if cu else {}).items():
            if cunits.setdefault(key, val) != val:
                ctf.fail(cu[0], f"units: {key}={val}, but the particles file says "
                                f"{key}={units[1][key]}")
    if clines is not None:
        fields.update(_contacts(ctf, clines, index, cunits))
        sources.append((ctf.path, "contacts"))
    return ImportedState(units=cunits, sources=sources, **fields)
