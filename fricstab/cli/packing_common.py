"""Shared parts of ``fricstab packing ...``: parameters, laws and kT scans, packings, records.

Parameters come from the command line, else the scene file, else the
defaults (:func:`resolve`, through :func:`fricstab.io.scenes.validate` with the
packing schema of :mod:`fricstab.cli.packing`).  The contact law and its
parameters follow the packing's :class:`~fricstab.io.scenes.LawChoice`
(:data:`fricstab.scenes.packing_friction.LAWS`): ``--law``, ``--param
KEY=VALUE`` or the scene keys ``law``, ``kn``, ``kt``, ...

A kT/kN scan (``--kt``, scene key ``kt_scan``) runs the law once per value of
its ``kt`` (ishima and charan; ``0`` is the frictionless limit, ``hertz`` with
the law's ``kn``).  Without a scan, a ``kt`` given by ``--param`` or the scene
is the one run; without either, the paper's scan of the command
(:data:`DEFAULT_KT`).  A law without ``kt`` (hertz, lee_hurley) runs once.
"""

import inspect
import json
import math
import shlex
import sys
import time

import numpy as np

from fricstab.io.files import atomic_write
from fricstab.io.results import json_clean, write_json
from fricstab.laws import ParameterError
from fricstab.scenes.packing import make_packing

__all__ = ["DEFAULTS", "DEFAULT_KT", "MAKE_KEYS", "Run", "check_out", "law_runs", "meta",
           "obtain_packing", "resolve", "summary", "write_npy", "write_record"]

_MAKE = inspect.signature(make_packing).parameters  # one source for the packing defaults
DEFAULTS = {"n": 256, "phi": 0.90, "seed": 0, "dphi": _MAKE["dphi"].default,
            "f_tol": _MAKE["f_tol"].default, "f_tol_compress": _MAKE["f_tol_compress"].default,
            "dgamma": 1e-6, "z_th": 2, "route": "auto", "bins": 50}
DEFAULT_KT = {"rigidity": [1e-4, 1.0, 10.0], "dos": [1e-8, 1e-4, 1.0, 10.0]}
MAKE_KEYS = ("n", "phi", "seed", "dphi", "f_tol", "f_tol_compress")
OPTION_KEYS = MAKE_KEYS + ("dgamma", "z_th", "route", "bins")
ROUTES = ("auto", "symmetric", "dense")
MODES_MAX_PARTICLES = 1100   # rigidity --modes default: on up to this backbone size
UNITS = {"length": "d (large diameter) = 1", "mass": "m (large disk) = 1",
         "time": "t0 = sqrt(m/k_N) d^(1/4) = 1", "force": "k_N d^(3/2)"}
_CPU0 = [0.0]                # process CPU time at the start of the command


# ------------------------------------------------------------------ parameters

def resolve(ns, keys):
    """Validated parameters: ``keys`` of the schema, and ``law``, ``law_params``, ``wall_params``.

    Also ``explicit_kt``: whether ``kt`` came from ``--param`` or the scene
    file (it then replaces the default scan).
    """
    from fricstab.io.scenes import get, law_overrides, load_toml, validate
    mapping = load_toml("packing", ns.scene)
    schema = get("packing")
    labels = {}
    for key in OPTION_KEYS:
        value = getattr(ns, key, None)
        if value is not None:
            mapping[key], labels[key] = value, schema.field(key).option
    if getattr(ns, "kt", None) is not None:
        mapping["kt_scan"], labels["kt_scan"] = ns.kt, "--kt"
    explicit_kt = "kt" in mapping
    for key, value in law_overrides(ns).items():
        if value is not None:
            mapping[key] = value
            labels[key] = "--law" if key == "law" else f"--param {key}"
            explicit_kt |= key == "kt"
    mapping["__labels__"] = labels
    values = validate("packing", mapping)
    out = {key: values[key] for key in keys}
    out.update(law=values["law"], law_params=values["law_params"],
               wall_params=values["wall_params"], kt_scan=values["kt_scan"],
               explicit_kt=explicit_kt)
    return out


class Run:
    """One law of a command: its name (``kt_<value>`` of a scan, else the law), kT/kN, Material."""

    def __init__(self, name, kt, material):
        self.name, self.kt, self.material = name, kt, material

    @property
    def dof(self):
        return self.material.dof

    def label(self):
        return f"kT/kN = {self.kt:g}" if self.kt is not None else self.material.law

    def record(self):
        return {"folder": self.name, "kt": self.kt, "law": self.material.law,
                "law_params": dict(self.material.params), "ndof": self.dof}


def law_runs(params, command=None):
    """The runs of a command (module docstring); ``command=None``: exactly one (make, jacobian)."""
    from fricstab.scenes.packing_friction import material, with_kt
    base = material(params["law"], **params["law_params"], **params["wall_params"])
    scan = params["kt_scan"] if command is not None else None
    if "kt" not in base.params:
        return [Run(base.law, None, base)]
    if scan is not None and params["explicit_kt"]:
        raise ParameterError("--kt scans kT/kN and replaces the law's kt: give --kt or kt "
                             "(--param kt=... or the scene key kt), not both")
    if scan is None:
        scan = [base.params["kt"]] if params["explicit_kt"] or command is None \
            else DEFAULT_KT[command]
    kts = [float(k) for k in scan]
    names = [f"kt_{k:g}" for k in kts]
    if len(set(names)) != len(names):
        raise ParameterError(f"--kt: duplicate values {kts}")
    return [Run(name, kt, with_kt(base, kt)) for name, kt in zip(names, kts)]


def public(params):
    """The parameters for a record or ``--dry-run`` (no internal keys)."""
    return {k: v for k, v in params.items() if k not in ("explicit_kt", "kt_scan")}


# ------------------------------------------------------------------ packings and files

def packing_file(path):
    path = path.expanduser()
    if path.is_dir():
        path = path / "packing.npz"
    if not path.is_file():
        raise ParameterError(f"--packing: no packing file at {path} "
                             "(expected a directory with packing.npz, or a .npz file)")
    return path


def _load_packing(path):
    import zipfile

    from fricstab.scenes.packing import Packing
    try:
        return Packing.load(path)
    except (OSError, KeyError, ValueError, zipfile.BadZipFile) as exc:
        raise ParameterError(f"--packing: cannot read a packing from {path}: "
                             f"{' '.join(str(exc).split())}") from None


def packing_source_checks(ns):
    """--packing excludes make options given on the command line; the file must exist."""
    if getattr(ns, "packing", None) is None:
        return
    given = [f"--{k.replace('_', '-')}" for k in MAKE_KEYS if getattr(ns, k) is not None]
    if given:
        raise ParameterError(f"--packing cannot be combined with {', '.join(given)} "
                             "(those make a new packing)")
    packing_file(ns.packing)


def check_out(out, names, force):
    """Raise if ``out`` is not a directory or holds any of ``names`` (without ``force``)."""
    out = out.expanduser()
    if out.exists() and not out.is_dir():
        raise ParameterError(f"--out: {out} exists and is not a directory")
    if force:
        return out
    found = [n for n in names if (out / n).exists()]
    if found:
        raise ParameterError(f"--out: {out} already holds results ({', '.join(found)}); "
                             "use --force to overwrite them")
    return out


def show_progress(ns):
    """tqdm bars: off with --no-progress, and when stderr is no terminal."""
    return not ns.no_progress and sys.stderr.isatty()


def save_packing(path, packing):
    def write(tmp):
        with open(tmp, "wb") as fh:
            packing.save(fh)
    atomic_write(path, write)


def obtain_packing(ns, params, out):
    """The packing: loaded from --packing, or made (and saved to ``out/packing.npz``)."""
    if getattr(ns, "packing", None) is not None:
        path = packing_file(ns.packing)
        return _load_packing(path), str(path)
    packing = make_packing(params["n"], params["phi"], params["seed"], dphi=params["dphi"],
                           f_tol=params["f_tol"], f_tol_compress=params["f_tol_compress"],
                           progress=show_progress(ns))
    if out is not None:
        save_packing(out / "packing.npz", packing)
    return packing, None


def summary(packing, bb):
    return {"n": packing.n, "phi": packing.phi, "seed": packing.seed, "box": packing.box,
            "n_backbone": bb.n, "rattlers": packing.n - bb.n,
            "backbone_rattler_force": bb.rattler_force}


def friction_record(fr):
    """How friction was switched on (App. A.2): residuals and the normal-force relaxation."""
    return {"switch_residual": fr.switch_residual,
            "relaxed": fr.normal_iterations + fr.fire_iterations > 0,
            "normal_newton_iterations": fr.normal_iterations,
            "normal_fire_iterations": fr.fire_iterations, "max_force": fr.residual}


# ------------------------------------------------------------------ records

def write_record(out, name, doc):
    """The record ``<name>.json`` (provenance included by :func:`meta`), then ``result.json``."""
    from fricstab.io.results import update_index
    doc.setdefault("protocol", name)
    doc.setdefault("parameters", doc.get("resolved_parameters"))
    write_json(out / f"{name}.json", doc)
    update_index(out, name, json_clean(doc))


def write_npy(path, array):
    def write(tmp):
        with open(tmp, "wb") as fh:
            np.save(fh, array)
    atomic_write(path, write)


def start_clock():
    _CPU0[0] = time.process_time()


def meta(argv, seconds, seed=None, params=None):
    """Provenance of a record: command, versions, git revision, seed, timings."""
    from fricstab.io.results import git_revision, versions
    return {
        "units": "d = 1 (large diameter), k_N = 1, m = 1, t0 = 1; kt = k_T / k_N",
        "command": "fricstab " + shlex.join(argv),
        "seconds": round(seconds, 3),
        "seed": seed,
        "resolved_parameters": public(params) if params is not None else None,
        "timings": {"total": {"wall_s": round(seconds, 4),
                              "cpu_s": round(time.process_time() - _CPU0[0], 4)}},
        "versions": versions(),
        "git": git_revision(),
    }


def dry_run(params, runs=None):
    doc = public(params)
    if runs is not None:
        doc["runs"] = [r.record() for r in runs]
    print(json.dumps(json_clean(doc), indent=2, allow_nan=False))
    return 0


def rel(a, b):
    """|a - b| / |b|; None when either is missing."""
    if a is None or b is None or not (math.isfinite(a) and math.isfinite(b)):
        return None
    return abs(a - b) / abs(b) if b != 0 else (0.0 if a == b else math.inf)


def setup(ns, keys, command, result_names):
    """Parameters, runs, output folder, packing and backbone shared by rigidity and dos.

    Returns ``(params, runs, None)`` for ``--dry-run`` (nothing made), else
    ``(params, runs, (out, packing, source, backbone))``.
    """
    from fricstab.scenes.packing_friction import backbone

    params = resolve(ns, MAKE_KEYS + keys)
    runs = law_runs(params, command)
    packing_source_checks(ns)
    names = result_names(runs) + ([] if ns.packing else ["packing.npz"])
    out = check_out(ns.out, names, ns.force)
    if ns.dry_run:
        return params, runs, None
    out.mkdir(parents=True, exist_ok=True)
    packing, source = obtain_packing(ns, params, out)
    return params, runs, (out, packing, source, backbone(packing, z_th=params["z_th"]))

