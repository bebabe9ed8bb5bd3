"""LAMMPS readers: data file (``atom_style sphere``), per-atom dump, ``compute pair/local`` dump.

**Data file** (:func:`read_lammps_data`): the header's ``xlo xhi``, ``ylo
yhi`` (and ``xy xz yz``: the ``xy`` tilt is the Lees-Edwards offset) and
the ``Atoms # sphere`` section, lines ``id type diameter density x y z
[ix iy iz]``; other sections (``Velocities``, coefficients) are skipped.
LAMMPS computes a sphere's mass as ``density * 4/3 pi r^3`` even in 2D
(``mass_rule="sphere"``, the default); a 2D user who gave density per area
(``set density/disc``) says ``mass_rule="disk"``: ``density * pi r^2``.
Periodic in x and y unless ``periodic`` says otherwise.

**Per-atom dump** (:func:`read_lammps_dump`): ``ITEM: ATOMS`` with columns in
any order: ``id`` and ``radius`` (or ``diameter``) are required, positions
``x y`` (or ``xu yu``, or scaled ``xs ys`` / ``xsu ysu``, converted with the
box and tilt), optional ``mass`` and ``angle`` or ``theta`` (radians).
``BOX BOUNDS`` flags give the periodicity (``pp`` periodic), the ``xy`` tilt
the Lees-Edwards offset.  The last frame unless ``frame`` (an index) is given.

**Pair dump** (:func:`read_lammps`, ``pairs=``): a ``dump local`` of
``compute property/local patom1 patom2`` and ``compute pair/local``; LAMMPS
names the columns ``c_ID[k]``, so the caller names them, in order
(``columns=("id1", "id2", "fx", "fy", "fz", "p1", "p2", ...)``, ``None`` for
a column to ignore) or as ``{"c_pl[1]": "id1", ...}``.  What the names mean
(LAMMPS documentation, "Restart, min, output info" / "Mixing, shift, ...
info" sections of https://docs.lammps.org/pair_granular.html and
https://docs.lammps.org/pair_gran.html; checked against LAMMPS 22 Jul 2025
in tests/test_imports_readers.py):

* ``fx fy fz``: the force of the pair on I from J.  The ``single()`` of the
  granular styles returns only the **normal** component, so these are the
  normal force: read into ``force_n``.  ``force`` is its signed magnitude.
* ``pair_style granular``: p1-p3 tangential force on I (components), p4 its
  magnitude, p5-p7 rolling torque on I, p8 its magnitude, p9 the magnitude
  of the twisting torque, p10-p12 ``x_I - x_J``.
* ``pair_style gran/hooke``, ``gran/hooke/history``, ``gran/hertz/history``:
  p1-p3 tangential force on I, p4 its magnitude, p5-p7 the normal relative
  velocity, p8-p10 the tangential relative velocity.
* So ``p1 p2`` (both families) are read into ``force_t``.  Neither family
  outputs its tangential history (the spring displacement); columns named
  ``hx hy`` (from another source) are read into ``history``.

Use ``compute pair/local ... cutoff radius``: otherwise pairs within the
neighbor cutoff that do not touch are listed too (with zero force).
"""

import math
from pathlib import Path

import numpy as np

from fricstab.errors import ParameterError
from fricstab.io.imports._text import TextFile, id_index
from fricstab.io.imports.lammps_text import LAMMPS_UNITS, dump_frame, read_frame, unit_names
from fricstab.io.imports.state import FileFormatError, ImportedState

__all__ = ["PAIR_COLUMNS", "read_lammps", "read_lammps_data", "read_lammps_dump"]

#: The names a pair-dump column may be given (``None`` ignores a column).
PAIR_COLUMNS = ("id1", "id2", "dist", "eng", "force", "fx", "fy", "fz", "hx", "hy",
                *(f"p{k}" for k in range(1, 13)))

_MASS_RULES = {"sphere": lambda r: 4.0 / 3.0 * math.pi * r ** 3,
               "disk": lambda r: math.pi * r ** 2}


def _periodic(periodic, default):
    if periodic is None:
        return default
    if isinstance(periodic, (bool, np.bool_)):
        return (bool(periodic), bool(periodic))
    try:
        p = tuple(bool(v) for v in periodic)
    except TypeError:
        p = ()
    if len(p) != 2:
        raise ParameterError(f"periodic = {periodic!r}: give True, False or (x, y) flags")
    return p


def _check_mass_rule(mass_rule):
    if mass_rule not in _MASS_RULES:
        raise ParameterError(f"mass_rule = {mass_rule!r}; allowed: sphere (LAMMPS' "
                             "density * 4/3 pi r^3), disk (density * pi r^2)")


def _fixed(types, fixed_types):
    return np.isin(np.asarray(types), np.asarray(list(fixed_types), dtype=np.int64))


# ------------------------------------------------------------------ data file

def _data_header(tf):
    """Header values -> (dict, line of first section)."""
    head, k = {}, 2                        # line 1 is the title
    while k <= len(tf):
        toks = tf.tokens(k)
        if toks and not _is_number(toks[0]):
            return head, k
        if toks:
            for keys, count in ((("xlo", "xhi"), 2), (("ylo", "yhi"), 2), (("zlo", "zhi"), 2),
                                (("xy", "xz", "yz"), 3)):
                if toks[count:count + len(keys)] == list(keys):
                    head[keys[0]] = (k, tf.floats(k, toks[:count], " ".join(keys)))
            if toks[1:] == ["atoms"]:
                head["atoms"] = (k, tf.ints(k, toks[:1], "atoms"))
        k += 1
    tf.fail(len(tf), "no Atoms section")


def _is_number(tok):
    try:
        float(tok)
    except ValueError:
        return False
    return True


def _sections(tf, k):
    """{name: (header line, [body line numbers])} of the sections from line ``k``."""
    out, name = {}, None
    for j in range(k, len(tf) + 1):
        toks = tf.tokens(j)
        if not toks:
            continue
        if not _is_number(toks[0]):
            name = " ".join(toks)
            if name in out:
                tf.fail(j, f"section {name} appears twice")
            out[name] = (j, [])
        else:
            out[name][1].append(j)
    return out


def _data_box(tf, head):
    for key in ("xlo", "ylo"):
        if key not in head:
            tf.fail(1, f"header has no '{key} {key[0]}hi' line")
    (kx, (xlo, xhi)), (ky, (ylo, yhi)) = head["xlo"], head["ylo"]
    for k, lo, hi, ax in ((kx, xlo, xhi, "x"), (ky, ylo, yhi, "y")):
        if not hi > lo:
            tf.fail(k, f"box {ax} from {lo} to {hi} has no size")
    kt, (xy, xz, yz) = head.get("xy", (None, (0.0, 0.0, 0.0)))
    if xz or yz:
        tf.fail(kt, f"tilts xz = {xz}, yz = {yz}: a 2D packing has only xy")
    return (xlo, ylo), (xhi - xlo, yhi - ylo), xy


def read_lammps_data(path, *, periodic=None, mass_rule="sphere", fixed_types=(), units=None):
    """Read a LAMMPS data file of ``atom_style sphere`` (see the module docstring).

    Parameters
    ----------
    path : str or Path
    periodic : bool or (bool, bool), optional
        Periodicity in x and y (default: both; a data file does not say).
    mass_rule : {"sphere", "disk"}
        ``density * 4/3 pi r^3`` (LAMMPS' rule) or ``density * pi r^2``.
    fixed_types : sequence of int
        Atom types that are walls (``fixed`` True).
    units : str or dict, optional
        The LAMMPS unit style of the run (``"si"``, ``"lj"``, ...) or a dict of names.

    Returns
    -------
    ImportedState
    """
    _check_mass_rule(mass_rule)
    tf = TextFile(path)
    head, k = _data_header(tf)
    ids, types, diam, dens, xy, lines = _data_atoms(tf, head, k)
    origin, box, tilt = _data_box(tf, head)
    radius = diam / 2.0
    mass = dens * np.array([_MASS_RULES[mass_rule](r) for r in radius])
    rule = "4/3 pi r^3" if mass_rule == "sphere" else "pi r^2"
    what = f"particles (Atoms # sphere), mass = density * {rule}"
    return ImportedState(pos=xy, radius=radius, ids=ids, mass=mass,
                         fixed=_fixed(types, fixed_types), box=box, origin=origin,
                         le_offset=tilt, periodic=_periodic(periodic, (True, True)),
                         units=unit_names(units), sources=[(tf.path, what)],
                         particle_lines=lines)


def _data_atoms(tf, head, k):
    secs = _sections(tf, k)
    if "Atoms" not in secs:
        tf.fail(k, "no Atoms section")
    hk, body = secs["Atoms"]
    style = tf.line(hk).partition("#")[2].split()
    if style and style[0] != "sphere":
        tf.fail(hk, f"Atoms section is '{style[0]}', need atom_style sphere "
                    "(id type diameter density x y z)")
    if "atoms" in head and head["atoms"][1][0] != len(body):
        tf.fail(hk, f"the header says {head['atoms'][1][0]} atoms, the section has {len(body)}")
    ints, reals = np.zeros((len(body), 2), np.int64), np.zeros((len(body), 4))
    for r, j in enumerate(body):
        toks = tf.tokens(j)
        if len(toks) not in (7, 10):
            tf.fail(j, f"expected 7 or 10 fields (id type diameter density x y z [ix iy iz]), "
                       f"found {len(toks)}")
        ints[r] = tf.ints(j, toks[:2], "id/type")
        tf.ints(j, toks[7:], "image flag")
        d, rho, x, y, _ = tf.floats(j, toks[2:7], "diameter/density/x/y/z")
        if d <= 0:
            tf.fail(j, f"diameter {toks[2]} is not positive (a point particle is not a disk)")
        reals[r] = d, rho, x, y
    lines = tuple((tf.path, j) for j in body)
    return ints[:, 0], ints[:, 1], reals[:, 0], reals[:, 1], reals[:, 2:4].copy(), lines


# ------------------------------------------------------------------ per-atom dump

def _col(tf, fr, *names, required=None):
    for name in names:
        if name in fr.columns:
            return fr.columns.index(name)
    if required:
        tf.fail(fr.header_line, f"no column {required} among {' '.join(fr.columns)}")
    return None


def _matrix(tf, fr, cols, what):
    out = np.empty((len(fr.rows), len(cols)))
    for r, (k, toks) in enumerate(fr.rows):
        out[r] = tf.floats(k, [toks[c] for c in cols], what)
    return out


def _positions(tf, fr):
    for cx, cy, scaled in (("x", "y", False), ("xu", "yu", False), ("xs", "ys", True),
                           ("xsu", "ysu", True)):
        if cx in fr.columns and cy in fr.columns:
            xy = _matrix(tf, fr, [fr.columns.index(cx), fr.columns.index(cy)], "position")
            if scaled:
                if fr.lo is None:
                    tf.fail(fr.header_line, "scaled coordinates need ITEM: BOX BOUNDS")
                (lx, ly), (xlo, ylo) = fr.box, fr.lo
                xy = np.column_stack([xlo + xy[:, 0] * lx + xy[:, 1] * fr.tilt,
                                      ylo + xy[:, 1] * ly])
            return xy
    tf.fail(fr.header_line, f"no position columns (x y, xu yu, xs ys or xsu ysu) among "
                            f"{' '.join(fr.columns)}")


def _dump_particles(path, frame, need_radius=True):
    tf, fr, _ = read_frame(path, frame, "ATOMS")
    cid = _col(tf, fr, "id", required="id")
    ids = np.array([tf.ints(k, [t[cid]], "id")[0] for k, t in fr.rows], np.int64)
    crad = _col(tf, fr, "radius", "diameter", required="radius (or diameter)" if need_radius
                else None)
    radius = None
    if crad is not None:
        radius = _matrix(tf, fr, [crad], "radius")[:, 0]
        radius = radius / 2.0 if fr.columns[crad] == "diameter" else radius
    optional = {}
    for key, names in (("mass", ("mass",)), ("theta", ("angle", "theta")), ("type", ("type",))):
        c = _col(tf, fr, *names)
        optional[key] = None if c is None else _matrix(tf, fr, [c], key)[:, 0]
    lines = tuple((tf.path, k) for k, _ in fr.rows)
    return tf, fr, ids, _positions(tf, fr), radius, optional, lines


def read_lammps_dump(path, *, frame=-1, periodic=None, fixed_types=(), units=None):
    """Read one frame of a LAMMPS per-atom text dump (see the module docstring).

    Parameters
    ----------
    path : str or Path
    frame : int
        Frame index (default -1, the last).
    periodic : bool or (bool, bool), optional
        Overrides the ``BOX BOUNDS`` flags.
    fixed_types : sequence of int
        Atom types that are walls (needs a ``type`` column).
    units : str or dict, optional
        LAMMPS unit style or names (``ITEM: UNITS`` in the dump is used otherwise).

    Returns
    -------
    ImportedState
    """
    return read_lammps(dump=path, frame=frame, periodic=periodic, fixed_types=fixed_types,
                       units=units)


# ------------------------------------------------------------------ pair dump

def _column_map(tf, fr, columns):
    """{our name: column index} from ``columns`` (sequence in order, or {file name: ours})."""
    if columns is None:
        raise ParameterError("columns: name the pair dump's columns, e.g. columns=('id1', "
                             "'id2', 'fx', 'fy', 'fz', 'p1', 'p2', 'p3'); LAMMPS writes c_ID[k]")
    if isinstance(columns, dict):
        missing = [c for c in columns if c not in fr.columns]
        if missing:
            tf.fail(fr.header_line, f"no column {missing[0]} among {' '.join(fr.columns)}")
        pairs = [(fr.columns.index(c), ours) for c, ours in columns.items()]
    else:
        columns = list(columns)
        if len(columns) != len(fr.columns):
            tf.fail(fr.header_line, f"{len(fr.columns)} columns, but columns= names "
                                    f"{len(columns)}")
        pairs = list(enumerate(columns))
    out = {}
    for c, ours in pairs:
        if ours is None:
            continue
        if ours not in PAIR_COLUMNS or ours in out:
            raise ParameterError(f"columns: {ours!r} is unknown or repeated; allowed: "
                                 f"{', '.join(PAIR_COLUMNS)} or None")
        out[ours] = c
    for need in (("id1", "id2"), ("fx", "fy"), ("p1", "p2"), ("hx", "hy")):
        if (need[0] in out) != (need[1] in out) or (need[0] == "id1" and "id1" not in out):
            raise ParameterError(f"columns: give both {need[0]} and {need[1]}"
                                 f"{' (the pair ids are required)' if need[0] == 'id1' else ''}")
    return out


def pair_frame(path, timestep, frame, box=None):
    """(TextFile, Frame) of a ``dump local`` at the atoms' ``timestep`` (else frame ``frame``);
    its box, where it states one, must be the particles' ``box`` (origin, size, tilt)."""
    tf, fr, starts = read_frame(path, frame, "ENTRIES")
    if timestep is not None and fr.timestep != timestep:
        frames = [dump_frame(tf, s, "ENTRIES") for s in starts]
        match = [f for f in frames if f.timestep == timestep]
        if not match:
            tf.fail(starts[-1], f"no frame at timestep {timestep} (the atoms' frame); "
                                f"timesteps here: {[f.timestep for f in frames][:8]}")
        fr = match[-1]
    why = None if box is None or fr.lo is None else _box_differs(_frame_box(fr), box)
    if why:
        tf.fail(fr.box_line, f"the pairs' box is not the particles' ({why}): not one frame")
    return tf, fr


def particle_box(fields):
    """(origin, size, tilt) of particle fields, or None without a box."""
    return None if fields["box"] is None else (fields["origin"], fields["box"],
                                               fields["le_offset"])


def _pairs(path, columns, timestep, frame, index, box=None):
    """(ci, cj, {field: (K, 2)}, lines) of the pair dump frame (:func:`pair_frame`)."""
    tf, fr = pair_frame(path, timestep, frame, box)
    cmap = _column_map(tf, fr, columns)
    ci, cj = [], []
    for k, toks in fr.rows:
        a, b = tf.ints(k, [toks[cmap["id1"]], toks[cmap["id2"]]], "pair ids")
        for pid in (a, b):
            if pid not in index:
                tf.fail(k, f"the pair names particle id {pid}, which the particle file lacks")
        ci.append(index[a])
        cj.append(index[b])
    fields = {}
    for name, (cx, cy) in (("force_n", ("fx", "fy")), ("force_t", ("p1", "p2")),
                           ("history", ("hx", "hy"))):
        if cx in cmap:
            fields[name] = _matrix(tf, fr, [cmap[cx], cmap[cy]], name)
    what = f"contacts ({', '.join(['ids'] + list(fields))}) at timestep {fr.timestep}"
    return (np.array(ci, np.int64), np.array(cj, np.int64), fields,
            tuple((tf.path, k) for k, _ in fr.rows), (tf.path, what))


#: Two files of one frame state its box to within this (relative to its size): LAMMPS
#: prints bounds with 17 digits; the tilted bounds' conversion rounds by an ulp or two.
BOX_AGREE = 1e-12


def _box_differs(a, b):
    """Why boxes ``a`` and ``b`` ((origin, size, tilt) each) differ, or None."""
    scale = max(max(a[1]), max(b[1]))
    for name, x, y in (("xlo", a[0][0], b[0][0]), ("ylo", a[0][1], b[0][1]),
                       ("lx", a[1][0], b[1][0]), ("ly", a[1][1], b[1][1]),
                       ("xy", a[2], b[2])):
        if abs(x - y) > BOX_AGREE * scale:
            return f"{name} {x:.17g} against {y:.17g}"
    return None


def _frame_box(fr):
    return None if fr.lo is None else (fr.lo, fr.box, fr.tilt)


# ------------------------------------------------------------------ combined

def _merge_data(state, ids, radius, tf, lines):
    """Masses (and radii, where the dump has none) from the data file, matched by id."""
    index = {int(i): r for r, i in enumerate(state.ids)}
    rows = []
    for r, pid in enumerate(ids):
        if int(pid) not in index:
            raise FileFormatError(*lines[r], f"particle id {pid} is not in the data file "
                                             f"{state.sources[0][0]}")
        rows.append(index[int(pid)])
    if len(ids) != state.n:
        raise FileFormatError(tf.path, None, f"{len(ids)} atoms, the data file has {state.n}")
    rows = np.array(rows)
    return state.mass[rows], (state.radius[rows] if radius is None else radius), \
        state.fixed[rows]


def read_lammps(*, data=None, dump=None, pairs=None, columns=None, frame=-1, periodic=None,
                mass_rule="sphere", fixed_types=(), units=None):
    """Combine a data file, a per-atom dump and a pair dump (see the module docstring).

    Particles come from ``dump`` (frame ``frame``) when given, else from
    ``data``; with both, ``data`` adds the masses (and radii a dump lacks),
    matched by id.  ``pairs`` adds the contacts of the frame at the same
    timestep as the dump's frame (else frame ``frame``).

    Parameters
    ----------
    data, dump, pairs : str or Path, optional
        Data file, per-atom dump, ``dump local`` of the pairs.
    columns : sequence or dict
        Names of the pair dump's columns (:data:`PAIR_COLUMNS`), in order
        (``None`` ignores one) or as ``{dump column: name}``.
    frame : int
        Frame index (default -1, the last).
    periodic, mass_rule, fixed_types, units
        As in :func:`read_lammps_data` and :func:`read_lammps_dump`.

    Returns
    -------
    ImportedState
    """
    fields, sources, timestep = particle_fields(data, dump, frame, periodic, mass_rule,
                                                fixed_types, units)
    if pairs is not None:
        index = id_index(fields["ids"], fields["particle_lines"])
        ci, cj, extra, clines, source = _pairs(pairs, columns, timestep, frame, index,
                                               particle_box(fields))
        fields.update(ci=ci, cj=cj, contact_lines=clines, **extra)
        sources.append(source)
    return ImportedState(sources=sources, **fields)


def particle_fields(data, dump, frame, periodic, mass_rule="sphere", fixed_types=(),
                    units=None):
    """(ImportedState keyword arguments, sources, dump timestep or None) of the particles."""
    if data is None and dump is None:
        raise ParameterError("read_lammps: give data= (a data file) or dump= (a per-atom dump)")
    state = None if data is None else read_lammps_data(
        data, periodic=periodic, mass_rule=mass_rule, fixed_types=fixed_types, units=units)
    if dump is None:
        return _fields_of(state), list(state.sources), None
    return _dump_fields(dump, frame, state, periodic, fixed_types, units)


def _fields_of(state):
    keys = ("pos", "radius", "ids", "mass", "theta", "fixed", "box", "origin", "le_offset",
            "periodic", "units", "particle_lines")
    return {k: getattr(state, k) for k in keys}


def _dump_fields(dump, frame, state, periodic, fixed_types, units):
    tf, fr, ids, pos, radius, opt, lines = _dump_particles(dump, frame, state is None)
    names = unit_names(units)
    if fr.units is not None:
        if fr.units not in LAMMPS_UNITS:
            tf.fail(fr.units_line, f"unit style {fr.units!r} is not one of "
                                   f"{', '.join(LAMMPS_UNITS)}")
        if names.get("style", fr.units) != fr.units:
            tf.fail(fr.units_line, f"the dump says units {fr.units}, the call says "
                                   f"{names['style']}")
        names = names or unit_names(fr.units)
    mass, fixed = opt["mass"], None
    if opt["type"] is not None:
        fixed = _fixed(opt["type"].astype(np.int64), fixed_types)
    sources = [(tf.path, f"particles at timestep {fr.timestep}")]
    if state is not None:
        _same_box(tf, fr, state)
        what = "masses" + (" and radii" if radius is None else "")
        dmass, radius, dfixed = _merge_data(state, ids, radius, tf, lines)
        mass = dmass if mass is None else mass
        fixed = dfixed if fixed is None else fixed
        sources.insert(0, (state.sources[0][0], what))
    box = fr.box
    per = _periodic(periodic, fr.periodic if box is not None else (False, False))
    return dict(pos=pos, radius=radius, ids=ids, mass=mass, theta=opt["theta"], fixed=fixed,
                box=box, origin=fr.lo or (0.0, 0.0), le_offset=fr.tilt, periodic=per,
                units=names, particle_lines=lines), sources, fr.timestep


def _same_box(tf, fr, data):
    """A data file written at the dump frame's timestep (``write_data`` names it in the
    header) has its box; one of another or no timestep (a start) only gives masses."""
    import re
    path = data.sources[0][0]
    head = TextFile(path).line(1) if Path(path).is_file() else ""
    m = re.search(r"timestep\s*=\s*(\d+)", head)
    if m is None or int(m.group(1)) != fr.timestep or fr.lo is None:
        return
    why = _box_differs(_frame_box(fr), (data.origin, data.box, data.le_offset))
    if why:
        tf.fail(fr.box_line, f"the box is not the one of {path} ({why}) at the same "
                             f"timestep {fr.timestep}: not one packing")
