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

from fricstab.io.files import json_clean
from fricstab.laws import ParameterError
from fricstab.scenes.packing import make_packing

__all__ = ["DEFAULTS", "DEFAULT_KT", "MAKE_KEYS", "UNITS_NOTE", "Run", "dry_run", "law_runs",
           "new_packing", "packing_source_checks", "public", "resolve", "save_packing",
           "summary"]

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
UNITS_NOTE = "d = 1 (large diameter), k_N = 1, m = 1, t0 = 1; kt = k_T / k_N"


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


# ------------------------------------------------------------------ packings and records

def packing_source_checks(ns):
    """--packing excludes make options given on the command line."""
    if getattr(ns, "packing", None) is None:
        return
    given = [f"--{k.replace('_', '-')}" for k in MAKE_KEYS if getattr(ns, k) is not None]
    if given:
        raise ParameterError(f"--packing cannot be combined with {', '.join(given)} "
                             "(those make a new packing)")


def show_progress(ns):
    """Progress (:mod:`fricstab.progress`: a bar on a terminal, a line every few seconds
    in a log): off with --no-progress and --quiet."""
    return not ns.no_progress


def new_packing(params, progress=False):
    """The packing of the make parameters of ``params`` (seeded, bit-reproducible)."""
    return make_packing(params["n"], params["phi"], params["seed"], dphi=params["dphi"],
                        f_tol=params["f_tol"], f_tol_compress=params["f_tol_compress"],
                        progress=progress)


def save_packing(packing):
    """A writer of ``packing`` for :meth:`fricstab.io.results.ResultDir.write_with`."""
    def write(tmp):
        with open(tmp, "wb") as fh:
            packing.save(fh)
    return write


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


# ------------------------------------------------------------------ output

def dry_run(params, runs=None, estimate=None):
    doc = public(params)
    if runs is not None:
        doc["runs"] = [r.record() for r in runs]
    if estimate is not None:
        doc["estimate"] = estimate
    print(json.dumps(json_clean(doc), indent=2, allow_nan=False))
    return 0


def rel(a, b):
    """|a - b| / |b|; None when either is missing."""
    if a is None or b is None or not (math.isfinite(a) and math.isfinite(b)):
        return None
    return abs(a - b) / abs(b) if b != 0 else (0.0 if a == b else math.inf)
