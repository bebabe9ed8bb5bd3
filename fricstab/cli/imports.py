"""``fricstab import FILE... --law NAME --param KEY=VALUE ... --out DIR``: a packing made elsewhere.

Reads a LAMMPS data file with a per-atom dump and a ``compute pair/local``
dump, a LIGGGHTS ``pair/gran/local`` dump with its atoms, an extended XYZ
file (ours, OVITO's) or the plain CSV format (:mod:`fricstab.io.imports`),
turns it into our engine's state under a contact law with each contact's
history (read, or reconstructed from the tangential force by the law's
inverse: :func:`fricstab.io.imports.contacts.to_engine`), checks every
contact against the law and the state's force balance, optionally relaxes
it (``--relax``: Newton, histories by the increment rule) and writes

* ``state.npz``, ``jacobian.npz``, ``dofs.json``, ``mass.npy``: the state and
  its Jacobian as ``fricstab packing jacobian`` writes them, which
  ``fricstab packing jacobian|rigidity|dos|aqs --state DIR`` analyse;
* ``import.json``: the record (the files it read with their SHA-256, the
  units mapping, contact counts, contacts at their Coulomb cap, the worst
  force mismatch against the file, the equilibrium residual, the relaxation).

The format of each file is recognised from its contents (``--format`` to
say it); LAMMPS pair dumps name their columns ``c_ID[k]``, so ``--columns``
names them in order (``-`` skips one).  Every parameter of the law is given
with ``--param`` in the law's units, and ``--units length=L,mass=M,force=F``
says how large the file's units are in them: nothing is guessed.

Exit 2 (one line ``fricstab: error: FILE:LINE: what``, nothing written): a
file that cannot be read or parsed (missing column, a contact between
absent particles, NaN, an inconsistent box), a law that cannot invert the
file's forces (``hertz`` with a tangential force), a missing parameter.
"""

import argparse
import hashlib
import json
import sys
from pathlib import Path

from fricstab.errors import ParameterError

__all__ = ["FORMATS", "add_parser", "detect", "run"]

FORMATS = ("auto", "lammps", "liggghts", "extxyz", "csv")
#: A force mismatch above this (relative) is worth a warning line: a law or units
#: mapping that does not match the file (round-off gives ~1e-14).
MISMATCH_WARN = 1e-6
_HEAD_LINES = 64
#: The units mapping and --density: a factor beyond these leaves float64 in the products
#: the law forms (k delta^(3/2) of a converted overlap, masses times lengths squared).
UNIT_RANGE = (1e-100, 1e100)
_FLOAT64 = " (beyond it the law's products leave float64)"


def _csv_list(text):
    return [t.strip() for t in text.split(",") if t.strip()]


def _types(text):
    """``2,3`` -> [2, 3] (LAMMPS atom types, integers >= 1)."""
    try:
        out = [int(t) for t in _csv_list(text)]
    except ValueError:
        out = []
    if not out or min(out) < 1:
        raise argparse.ArgumentTypeError(f"expected atom types as integers >= 1, e.g. 2,3; "
                                         f"got {text!r}")
    return out


def _file_units(text):
    """A LAMMPS unit style, or ``length=mm,...`` unit names -> str or dict."""
    if "=" not in text:
        return text
    out = {}
    for item in _csv_list(text):
        key, sep, value = item.partition("=")
        if not sep or not key.strip() or not value.strip():
            raise argparse.ArgumentTypeError(f"expected a unit style (si, lj, ...) or "
                                             f"quantity=name pairs, got {item!r}")
        out[key.strip()] = value.strip()
    return out


def _int_in(low, high, why=""):
    """An integer in [low, high]."""
    def parse(text):
        try:
            value = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"must be an integer, got {text!r}") from None
        if not low <= value <= high:
            raise argparse.ArgumentTypeError(f"must be in [{low}, {high}]{why}, got {text!r}")
        return value
    return parse


def _units(text):
    """``length=L,mass=M,force=F`` -> dict (each > 0)."""
    out = {}
    for item in _csv_list(text):
        key, sep, value = item.partition("=")
        try:
            number = float(value)
        except ValueError:
            number = None
        if not sep or key not in ("length", "mass", "force") or number is None \
                or not UNIT_RANGE[0] <= number <= UNIT_RANGE[1]:
            raise argparse.ArgumentTypeError(
                f"expected length=L,mass=M,force=F with numbers in [{UNIT_RANGE[0]:g}, "
                f"{UNIT_RANGE[1]:g}] (the size of the file's unit in the law's units; beyond, "
                f"products of three leave float64), got {item!r}")
        out[key] = number
    return out


def add_parser(sub, parser_class, positive_float):
    """Register ``fricstab import`` on the top-level subparsers ``sub``."""
    from fricstab.io.scenes import add_law_options
    p = sub.add_parser("import", help="a packing made elsewhere (LAMMPS, LIGGGHTS, extxyz, CSV) "
                       "as our state, checked against the law",
                       description=__doc__.split("\n\n")[1].replace("\n", " "))
    p.add_argument("files", nargs="+", type=Path, metavar="FILE",
                   help="the files of one packing: a LAMMPS data file, a per-atom dump, a pair "
                        "dump; or a LIGGGHTS atoms dump and pair/gran/local dump; or one "
                        "extxyz file; or a CSV file (or particles and contacts CSV files)")
    p.add_argument("--format", choices=FORMATS, default="auto",
                   help="the files' format (default: recognised from their contents)")
    add_law_options(p, "packing")
    p.add_argument("--units", type=_units, default={}, metavar="length=L,mass=M,force=F",
                   help="the size of the file's length, mass and force units in the law's "
                        "units (default 1 each)")
    p.add_argument("--file-units", type=_file_units, default=None, metavar="STYLE",
                   help="the units the LAMMPS, LIGGGHTS or extxyz files were written in, "
                        "recorded: a LAMMPS unit style (si, lj, ...) or names such as "
                        "length=mm,mass=g,force=N (a CSV file names its own)")
    p.add_argument("--columns", type=_csv_list, default=None, metavar="NAME,...",
                   help="LAMMPS pair dump: our name of each column in order (id1, id2, dist, "
                        "eng, force, fx, fy, fz, p1..p12, hx, hy; '-' skips one), e.g. "
                        "id1,id2,dist,fx,fy,fz,p1,p2,p3,p4")
    p.add_argument("--keywords", type=_csv_list, default=None, metavar="KW,...",
                   help="LIGGGHTS: the keywords given to compute pair/gran/local (default its "
                        "default: pos,vel,id,force,torque,history,contactArea)")
    p.add_argument("--n-history", type=_int_in(0, 64), default=3, metavar="K",
                   help="LIGGGHTS: history values per contact (default 3)")
    p.add_argument("--frame", type=_int_in(-10 ** 9, 10 ** 9), default=-1,
                   help="frame of a dump or extxyz file (default -1, the last)")
    p.add_argument("--periodic", choices=("xy", "x", "y", "none"), default=None,
                   help="LAMMPS/LIGGGHTS periodicity (default: the dump's box flags, else xy)")
    p.add_argument("--fixed-types", type=_types, default=[],
                   metavar="T,...", help="LAMMPS atom types that are walls (fixed particles)")
    p.add_argument("--mass-rule", choices=("sphere", "disk"), default="sphere",
                   help="LAMMPS data file masses: density 4/3 pi r^3 (sphere, LAMMPS' "
                        "default) or density pi r^2 (disk, after set density/disc)")
    p.add_argument("--density", type=positive_float(*UNIT_RANGE, _FLOAT64), default=None,
                   help="mass per area in the law's units, for files without masses")
    p.add_argument("--relax", action="store_true",
                   help="relax the state by Newton before writing (histories carried by the "
                        "increment rule); the record says how far it moved")
    p.add_argument("--out", type=Path, required=True, help="output directory")
    p.add_argument("--force", action="store_true", help="replace an import result in --out")
    p.add_argument("--quiet", action="store_true", help="print nothing on success")
    return p


# ------------------------------------------------------------------ formats

def _head(path):
    try:
        with open(path, encoding="utf-8", errors="replace") as fh:
            return [fh.readline() for _ in range(_HEAD_LINES)]
    except OSError as err:
        raise ParameterError(f"{path}: cannot read the file ({err.strerror or err})") from None


def detect(path):
    """What a file is: ``data``, ``atoms`` (per-atom dump), ``local`` (pair dump), ``extxyz``,
    ``csv``; a file of none of these is refused naming it."""
    path = Path(path)
    lines = [ln.strip() for ln in _head(path)]
    text = [ln for ln in lines if ln]
    if text and text[0].startswith("ITEM:"):
        for ln in text:
            if ln.startswith("ITEM: ATOMS"):
                return "atoms"
            if ln.startswith("ITEM: ENTRIES"):
                return "local"
        raise ParameterError(f"{path}: a LAMMPS dump without ITEM: ATOMS or ITEM: ENTRIES in "
                             f"its first {_HEAD_LINES} lines")
    if path.suffix.lower() in (".xyz", ".extxyz") or \
            (len(lines) > 1 and lines[0].isdigit() and "properties=" in lines[1].lower()):
        return "extxyz"
    if path.suffix.lower() == ".csv" or any(ln.lower().startswith(("# units:", "[particles]",
                                                                    "[contacts]"))
                                            for ln in text):
        return "csv"
    if any(ln.split()[1:] == ["atoms"] for ln in text if len(ln.split()) == 2):
        return "data"
    raise ParameterError(f"{path}: cannot tell its format (a LAMMPS data file, dump, extxyz "
                         "or CSV file); give --format")


def _one(kinds, kind, what):
    found = kinds.get(kind, [])
    if len(found) > 1:
        raise ParameterError(f"{found[1]}: a second {what}; give one packing's files")
    return found[0] if found else None


def read(ns):
    """The :class:`~fricstab.io.imports.ImportedState` of the command's files."""
    from fricstab.io.imports import read_csv, read_extxyz, read_lammps, read_liggghts
    kinds = {}
    for f in ns.files:
        if not f.is_file():
            raise ParameterError(f"{f}: no such file")
        kinds.setdefault(detect(f), []).append(f)
    fmt = ns.format
    if fmt == "auto":
        fmt = ("csv" if "csv" in kinds else "extxyz" if "extxyz" in kinds
               else "liggghts" if ns.keywords is not None else "lammps")
    allowed = {"csv": {"csv"}, "extxyz": {"extxyz"}, "lammps": {"data", "atoms", "local"},
               "liggghts": {"atoms", "local"}}[fmt]
    other = [f for k, fs in kinds.items() if k not in allowed for f in fs]
    if other:
        raise ParameterError(f"{other[0]}: a {detect(other[0])} file does not go with the "
                             f"{fmt} format of the others")
    periodic = None if ns.periodic is None else \
        {"xy": (True, True), "x": (True, False), "y": (False, True), "none": (False, False)}[
            ns.periodic]
    if fmt == "csv":
        files = kinds["csv"]
        if len(files) > 2:
            raise ParameterError(f"{files[2]}: the CSV format is one file, or particles and "
                                 "contacts files")
        return read_csv(*files)
    if fmt == "extxyz":
        from fricstab.io.imports.lammps_text import unit_names
        return read_extxyz(_one(kinds, "extxyz", "extxyz file"), frame=ns.frame,
                           units=unit_names(ns.file_units, "--file-units"))
    atoms, pairs = _one(kinds, "atoms", "per-atom dump"), _one(kinds, "local", "pair dump")
    if fmt == "liggghts":
        if atoms is None or pairs is None:
            raise ParameterError("LIGGGHTS: give the atoms dump and the pair/gran/local dump")
        keywords = ns.keywords or None
        kw = {} if keywords is None else {"keywords": tuple(keywords)}
        return read_liggghts(atoms=atoms, pairs=pairs, n_history=ns.n_history, frame=ns.frame,
                             periodic=periodic, fixed_types=tuple(ns.fixed_types),
                             units=ns.file_units, **kw)
    data = _one(kinds, "data", "data file")
    if data is None and atoms is None:
        raise ParameterError("LAMMPS: give a data file or a per-atom dump (the particles)")
    columns = None if ns.columns is None else [None if c == "-" else c for c in ns.columns]
    if pairs is not None and columns is None:
        raise ParameterError(f"--columns: name the columns of {pairs} in order, e.g. "
                             "id1,id2,dist,fx,fy,fz,p1,p2,p3,p4 (LAMMPS writes c_ID[k])")
    try:
        return read_lammps(data=data, dump=atoms, pairs=pairs, columns=columns, frame=ns.frame,
                           periodic=periodic, mass_rule=ns.mass_rule,
                           fixed_types=tuple(ns.fixed_types), units=ns.file_units)
    except ParameterError as exc:
        text = str(exc)
        raise ParameterError(f"--{text}" if text.startswith("columns:") else text) from None


# ------------------------------------------------------------------ the law

def law_params(ns):
    """(law, params): every parameter of the law given with --param (no defaults: the file's
    units are not the packing scene's)."""
    from fricstab.io.scenes import law_overrides
    from fricstab.laws import get_law
    over = law_overrides(ns)
    law = over.pop("law")
    if law is None:
        raise ParameterError("--law: name the contact law of the packing (fricstab laws)")
    info = get_law(law)
    unknown = [k for k in over if k not in info.params]
    if unknown:
        raise ParameterError(f"--param {unknown[0]}: {law} has no such parameter; its "
                             f"parameters: {', '.join(info.params)}")
    missing = [k for k in info.params if k not in over]
    if missing:
        docs = dict(zip(info.params, info.param_docs))
        units = dict(zip(info.params, info.param_units))
        raise ParameterError(
            f"--param {missing[0]}=VALUE is needed ({law} takes "
            f"{', '.join(f'{k} [{units[k]}]' for k in info.params)}, in the law's units; "
            f"{missing[0]}: {docs[missing[0]]})")
    return law, {k: over[k] for k in info.params}


def _sha256(path):
    return hashlib.sha256(Path(path).read_bytes()).hexdigest()


# ------------------------------------------------------------------ run

def run(ns, argv):
    """``fricstab import``: read, convert, check, optionally relax, then write (module doc)."""
    from fricstab.errors import check_finite
    from fricstab.io.imports.contacts import to_engine
    from fricstab.io.imports.engine_check import equilibrium, relax
    from fricstab.io.jacobian_export import FILES, write_state_jacobian
    from fricstab.io.results import ResultDir

    law, params = law_params(ns)
    imported = read(ns)
    system, state, report = to_engine(imported, law, params, units=ns.units,
                                      density=ns.density)
    if ns.relax:
        state, report.relax = relax(system, state)
        report.residual = equilibrium(system, state)
    from fricstab.engine import jacobian as engine_jacobian
    from fricstab.engine.newton import touching
    f, k = engine_jacobian(system, state)          # checked before anything is written
    check_finite("force", f.reshape(-1, system.dof), item="particle")
    check_finite("Jacobian entry", k.data, item="entry")
    inputs = {str(p): _sha256(p) for p in ns.files}
    fingerprint = {"files": inputs, "law": law, "params": params, "units": ns.units,
                   "format": ns.format, "columns": ns.columns, "keywords": ns.keywords,
                   "frame": ns.frame, "periodic": ns.periodic, "fixed_types": ns.fixed_types,
                   "mass_rule": ns.mass_rule, "density": ns.density, "relax": ns.relax}
    rd = ResultDir(ns.out, "import", force=ns.force, outputs=FILES, fingerprint=fingerprint,
                   resumable=False).create()
    for name in FILES:
        rd.register(name)
    names = {key: v["file"] for key, v in report.units.items()}
    with rd.stage("write"):
        write_state_jacobian(rd.path, system, state, units=names,
                             extra={"import": "import.json (units mapping, counts, flags, "
                                              "checks)"})
    doc = {"inputs": inputs, "law": law, "law_params": params, "n": int(system.n),
           "n_fixed": int((~system.free).sum()), "box": [system.lx, system.ly],
           "lees_edwards_offset": float(state.shift), "contacts": int(len(touching(system, state))),
           "next": f"fricstab packing jacobian|rigidity|dos|aqs --state {rd.path} --out ...",
           **report.as_dict()}
    doc = json.loads(json.dumps(doc, default=float))
    rd.finish(doc, parameters=fingerprint, argv=argv)
    if not ns.quiet:
        _print(doc, rd.path)
    return 0


def _print(doc, out):
    c, m, r = doc["counts"], doc["mismatch"], doc["residual"]
    print(f"imported {doc['n']} particles ({doc['n_fixed']} fixed), {doc['contacts']} contacts "
          f"under {doc['law']}: listed {c.get('listed', 0)}, kept {c.get('kept', 0)}, dropped "
          f"{c.get('dropped_apart', 0) + c.get('dropped_fixed', 0)}, added {c.get('added', 0)}; "
          f"histories from {doc['history_source']}, {len(doc['flagged'])} at their cap")
    worst = m.get("worst_relative") if m.get("checked") else None
    if worst is not None:
        torque = (f"; torque {m['torque_worst_relative']:.2e} at {m['torque_where']}"
                  if "torque_worst_relative" in m else "")
        print(f"forces against the file: worst {worst:.2e} (relative) at {m['where']}, "
              f"median {m['median_relative']:.2e}{torque}")
    elif m:
        print(f"forces against the file: not checked ({m.get('why')})")
    if r and r.get("mean_contact_force"):
        print(f"force balance: max |F| / mean contact force = {r['relative']:.2e}")
    elif r:
        print(f"force balance: no contact force; max |F| = {r.get('max_force', 0.0):.2e}")
    if doc["relax"]:
        x = doc["relax"]
        print(f"relaxed: moved {x['moved']:.2e} mean radii, residual {x['residual_before']:.2e}"
              f" -> {x['residual_after']:.2e} ({x['iterations']} Newton iterations"
              f"{'' if x['converged'] else ', NOT converged'})")
    if worst is not None and worst > MISMATCH_WARN:
        print(f"fricstab: warning: the law's forces differ from the file's by {worst:.1e} "
              "(relative): check the law, its parameters and --units", file=sys.stderr)
    print(f"wrote {out}/state.npz, jacobian.npz, dofs.json, mass.npy, import.json")
