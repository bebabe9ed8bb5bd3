"""``fricstab packing make|rigidity|dos``: disk packings of Ishima et al. from the command line.

Units: large diameter ``d = 1``, ``k_N = 1``, mass of a large disk ``m = 1``,
so ``t0 = 1``; ``kt`` is ``k_T / k_N`` (``kt = 0``: frictionless, the
Jacobian is the 2N x 2N Hessian with coordinates (x, y) per particle; else
3N x 3N with (x, y, l = d theta / 2)).

``fricstab packing make [--n 256] [--phi 0.90] [--seed 0] [--dphi ...] --out DIR``
    A force-balanced bidisperse packing (:func:`fricstab.scenes.packing.make_packing`;
    make options ``--n --phi --seed --dphi --f-tol --f-tol-compress``).
    Writes ``DIR/packing.npz`` (:meth:`fricstab.scenes.packing.Packing.save`),
    ``DIR/packing.json`` (parameters, protocol info, number of contacts,
    rattlers at ``z_th``, mean contact number of the backbone, versions,
    command, seconds) and ``DIR/packing.png`` (disks to scale in the periodic
    box, rattlers in grey, contact forces as lines of width ~ force).
``fricstab packing rigidity [--packing DIR|FILE.npz | make options] [--kt 1e-4 1 10] --out DIR``
    For each ``kt``: G_A, G_NA by sparse solve, G_NA by the mode sum
    (``--modes``; default on when the backbone has <= 1100 particles), G by
    step strain ``--dgamma`` (default 1e-6) with its error estimate, and the
    relative disagreements.  Writes ``DIR/rigidity.json``,
    ``DIR/rigidity.png`` (G against kt; nonaffine rates of theory against
    step strain for the first kt, as Ishima Fig. 3c) and per kt a folder
    ``DIR/kt_<%g>/`` with ``jacobian_tilde.npz`` (``scipy.sparse.save_npz``
    of J~ = J), ``xi.npy``, ``theta.npy``, ``u.npy`` (nonaffine rate of the
    solve, flat, ``ndof`` per particle), ``nonaffine_step.npy`` ((n, ndof),
    step strain) and ``g.json`` (box, n, ndof, kt, the G values and a recipe
    to recompute G_NA from these files).  Exit status 3 when a theory value
    (solve or modes) differs from step strain by more than 1% of |G|; the
    files are written first.
``fricstab packing dos [--packing ... | make options] [--kt 1e-8 1e-4 1 10] [--bins 50] --out DIR``
    For each ``kt`` the spectrum of the backbone's J (``--route``), omega =
    sqrt(lambda) with the two translations (smallest |lambda|) dropped,
    psi^T, psi^R, p, the DOS with N = all particles (rattlers included) on
    ``--bins`` log bins spanning every kt's nonzero frequencies, and the peak
    and median frequency of rotation-dominated modes.  Writes ``dos.json``,
    ``dos.npz`` (per kt index i: ``eigenvalues_<i>`` (translations dropped,
    ascending real part), ``omega_<i>``, ``psi_t_<i>``, ``psi_r_<i>``,
    ``p_<i>``, ``dos_<i>``; and ``edges``, ``kt``) and ``dos.png`` (D(omega)
    as Ishima Fig. 9, psi^T and psi^R against omega as Fig. 8).

Common options: ``--z-th`` (rattlers: Z <= z_th, removed iteratively;
default 2), ``--route auto|symmetric|dense`` (eigen-solver of the mode sum or
the spectrum), ``--scene FILE.toml`` (keys at the top level or under
``[packing]``: ``n, phi, seed, dphi, f_tol, f_tol_compress, kt, dgamma, z_th,
route``; the command line wins; keys a command does not use are ignored),
``--force`` (overwrite result files that exist in ``--out``; without it an
existing result file is an error), ``--no-progress``.  ``rigidity`` and
``dos`` build the packing from the make options (and also save it as
``DIR/packing.npz``) unless ``--packing`` names one; ``--packing`` cannot be
combined with make options on the command line (scene packing keys are then
ignored).

Exit status: 0 ok, 2 bad input (one line naming the parameter), 3 theory
and step strain disagree by more than 1%, 4 a relaxation did not converge.
Every file is written atomically (a complete file or none).
"""

import inspect
import json
import math
import shlex
import sys
import time
from pathlib import Path

import numpy as np

from fricstab.io.files import atomic_write
from fricstab.io.results import json_clean, write_json
from fricstab.laws import ParameterError
from fricstab.figures.packing import dos_figure, packing_figure, rigidity_figure
from fricstab.scenes.packing import make_packing

__all__ = ["add_parser", "run"]

_MAKE = inspect.signature(make_packing).parameters  # one source for the packing defaults
DEFAULTS = {"n": 256, "phi": 0.90, "seed": 0, "dphi": _MAKE["dphi"].default,
            "f_tol": _MAKE["f_tol"].default, "f_tol_compress": _MAKE["f_tol_compress"].default,
            "dgamma": 1e-6, "z_th": 2, "route": "auto", "bins": 50}
DEFAULT_KT = {"rigidity": [1e-4, 1.0, 10.0], "dos": [1e-8, 1e-4, 1.0, 10.0]}
MAKE_KEYS = ("n", "phi", "seed", "dphi", "f_tol", "f_tol_compress")
SCENE_KEYS = MAKE_KEYS + ("kt", "dgamma", "z_th", "route")
ROUTES = ("auto", "symmetric", "dense")
MODES_MAX_PARTICLES = 1100   # --modes default: on up to this backbone size
_CPU0 = [0.0]                # process CPU time at the start of the command
TOLERANCE = 0.01             # theory vs step strain, relative to |G|
EXIT_DISAGREE = 3
EXIT_CONVERGENCE = 4


# ------------------------------------------------------------------ parser

def _nonneg_float(text):
    import argparse
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"must be a number, got {text!r}") from None
    if not math.isfinite(value) or value < 0:
        raise argparse.ArgumentTypeError(f"must be a finite number >= 0, got {text!r}")
    return value


def _make_options(c):
    c.add_argument("--n", type=int, default=None,
                   help=f"number of disks, even, >= 4 (default {DEFAULTS['n']})")
    c.add_argument("--phi", type=float, default=None,
                   help=f"area fraction in [0.6, 0.95] (default {DEFAULTS['phi']})")
    c.add_argument("--seed", type=int, default=None,
                   help=f"seed of the random placement (default {DEFAULTS['seed']})")
    c.add_argument("--dphi", type=float, default=None,
                   help=f"compression increment (default {DEFAULTS['dphi']:g}; paper 1e-4)")
    c.add_argument("--f-tol", type=float, default=None,
                   help=f"force threshold at the target phi (default {DEFAULTS['f_tol']:g})")
    c.add_argument("--f-tol-compress", type=float, default=None,
                   help="force threshold of the intermediate steps "
                        f"(default {DEFAULTS['f_tol_compress']:g})")


def _common_options(c):
    c.add_argument("--scene", type=Path, default=None, help="TOML scene file")
    c.add_argument("--z-th", type=int, default=None,
                   help="rattlers: Z <= z_th, removed iteratively (default 2)")
    c.add_argument("--out", type=Path, required=True, help="output directory")
    c.add_argument("--force", action="store_true",
                   help="overwrite result files that already exist in --out")
    c.add_argument("--no-progress", action="store_true", help="no progress bars")
    c.add_argument("--quiet", action="store_true",
                   help="print nothing on success (errors still go to stderr)")
    c.add_argument("--dry-run", action="store_true",
                   help="validate and resolve every parameter, print them as JSON, write nothing")


def add_parser(sub, parser_class, positive_float):
    """Register ``fricstab packing make|rigidity|dos`` on the subparsers ``sub``."""
    p = sub.add_parser("packing", help="bidisperse disk packings: rigidity and DOS (Ishima et al.)",
                       description="Bidisperse disk packings (Ishima et al.): make one, its shear "
                       "rigidity from the Jacobian against step strain, its density of states.")
    psub = p.add_subparsers(dest="packing_command", metavar="PACKING_COMMAND",
                            parser_class=parser_class)
    psub.required = True
    m = psub.add_parser("make", help="a force-balanced frictionless packing")
    _make_options(m)
    _common_options(m)
    for name, helptext in (("rigidity", "G_A, G_NA (solve, modes) and G by step strain per kt"),
                           ("dos", "density of states and mode character per kt")):
        c = psub.add_parser(name, help=helptext)
        c.add_argument("--packing", type=Path, default=None, metavar="DIR_OR_NPZ",
                       help="use this packing (a directory with packing.npz, or the .npz) "
                            "instead of making one")
        _make_options(c)
        default = " ".join(f"{k:g}" for k in DEFAULT_KT[name])
        c.add_argument("--kt", type=_nonneg_float, nargs="+", default=None, metavar="KT",
                       help=f"kT/kN values, >= 0; 0 = frictionless (default {default})")
        c.add_argument("--route", choices=ROUTES, default=None,
                       help="eigen-solver of the %s: symmetric (eigh), dense (eig), auto "
                            "(symmetric when J = J^T to 1e-12; default)"
                            % ("mode sum" if name == "rigidity" else "spectrum"))
        if name == "rigidity":
            c.add_argument("--dgamma", type=positive_float(), default=None,
                           help="step strain, in (0, 0.1] (default 1e-6)")
            import argparse
            c.add_argument("--modes", action=argparse.BooleanOptionalAction, default=None,
                           help="G_NA also by the eigenmode sum (dense eigen-decomposition); "
                                f"default: on when the backbone has <= {MODES_MAX_PARTICLES} "
                                "particles, else off")
        else:
            c.add_argument("--bins", type=int, default=None,
                           help="logarithmic frequency bins of the DOS, >= 1 (default 50)")
        _common_options(c)
    return p


# ------------------------------------------------------------------ parameters

def _schema():
    """The packing scene (``fricstab scene show packing``); one source of keys and ranges."""
    from fricstab.scenes.packing import PHI_MAX, PHI_START_MAX
    from fricstab.io.scenes import Field, Schema
    return Schema("packing", "bidisperse frictional disk packings (Ishima et al.)", (
        Field("n", "int", DEFAULTS["n"], "-", "number of disks (half large d = 1, half small "
              "d = 1/1.4); cost of rigidity/dos grows as n^1.5 (sparse) to n^3 (dense modes)",
              low=4, high=200_000, check=lambda v: v % 2 == 0, check_doc="even"),
        Field("phi", "float", DEFAULTS["phi"], "-", "area fraction of the packing",
              low=PHI_START_MAX, high=PHI_MAX),
        Field("seed", "int", DEFAULTS["seed"], "-", "seed of the random placement",
              low=0, high=2 ** 63 - 1),
        Field("dphi", "float", DEFAULTS["dphi"], "-", "compression increment (paper 1e-4); "
              "smaller is slower, closer to the paper's protocol", low=0.0, low_open=True),
        Field("f_tol", "float", DEFAULTS["f_tol"], "k_N d", "force threshold at the target "
              "phi: max |F| below it", low=0.0, low_open=True),
        Field("f_tol_compress", "float", DEFAULTS["f_tol_compress"], "k_N d",
              "force threshold of the intermediate compression steps (looser is faster)",
              low=0.0, low_open=True),
        Field("kt", "floats", None, "-", "k_T / k_N values; 0 = frictionless", low=0.0,
              default_doc="rigidity: 1e-4 1 10; dos: 1e-8 1e-4 1 10"),
        Field("dgamma", "float", DEFAULTS["dgamma"], "-", "step strain of the G check; "
              "smaller is closer to linear response until round-off dominates",
              low=0.0, high=0.1, low_open=True),
        Field("z_th", "int", DEFAULTS["z_th"], "-", "rattlers: Z <= z_th, removed "
              "iteratively", low=0, high=1000),
        Field("route", "str", DEFAULTS["route"], "-", "eigen-solver: symmetric (eigh), dense "
              "(eig), auto (symmetric when J = J^T to 1e-12)", choices=ROUTES),
        Field("bins", "int", DEFAULTS["bins"], "-", "logarithmic frequency bins of the DOS",
              low=1, high=100_000),
    ))


def _load_scene(path):
    from fricstab.io.scenes import load_toml
    values = load_toml("packing", path)
    values.pop("__source__", None)
    return values


def _resolve(ns, keys, kt_default=None):
    """Parameter values: the command line, else the scene, else the default; all checked."""
    from fricstab.io.scenes import resolve
    overrides = {k: getattr(ns, k, None) for k in SCENE_KEYS + ("bins",)}
    values = resolve("packing", ns.scene, overrides)
    out = {}
    for key in keys:
        out[key] = values[key]
    if "kt" in out:
        kts = out["kt"] if out["kt"] is not None else kt_default
        kts = [float(k) for k in kts]
        names = [_kt_name(k) for k in kts]
        if len(set(names)) != len(names):
            raise ParameterError(f"--kt: duplicate values {kts}")
        out["kt"] = kts
    return out


def _kt_name(kt):
    return f"kt_{kt:g}"


def _packing_file(path):
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


def _check_out(out, names, force):
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


def _prepare_out(out):
    out.mkdir(parents=True, exist_ok=True)
    return out


def _show_progress(ns):
    """tqdm bars as chain_cli: off with --no-progress, and when stderr is no terminal."""
    return not ns.no_progress and sys.stderr.isatty()


# ------------------------------------------------------------------ helpers

def _write_record(out, name, doc):
    """The record ``<name>.json`` (provenance included by :func:`_meta`), then ``result.json``."""
    from fricstab.io.results import update_index
    doc.setdefault("protocol", name)
    doc.setdefault("parameters", doc.get("resolved_parameters"))
    write_json(out / f"{name}.json", doc)
    update_index(out, name, json_clean(doc))


def _write_npy(path, array):
    def write(tmp):
        with open(tmp, "wb") as fh:
            np.save(fh, array)
    atomic_write(path, write)


def _meta(argv, seconds, seed=None, params=None):
    """Provenance of a record: command, versions, git revision, seed, timings."""
    from fricstab.io.results import git_revision, versions
    return {
        "units": "d = 1 (large diameter), k_N = 1, m = 1, t0 = 1; kt = k_T / k_N",
        "command": "fricstab " + shlex.join(argv),
        "seconds": round(seconds, 3),
        "seed": seed,
        "resolved_parameters": params,
        "timings": {"total": {"wall_s": round(seconds, 4),
                              "cpu_s": round(time.process_time() - _CPU0[0], 4)}},
        "versions": versions(),
        "git": git_revision(),
    }


def _dry_run(params):
    print(json.dumps(json_clean(params), indent=2, allow_nan=False))
    return 0


def _rel(a, b):
    """|a - b| / |b|; None when either is missing."""
    if a is None or b is None or not (math.isfinite(a) and math.isfinite(b)):
        return None
    return abs(a - b) / abs(b) if b != 0 else (0.0 if a == b else math.inf)


def _obtain_packing(ns, params, out):
    """The packing: loaded from --packing, or made (and saved to ``out/packing.npz``)."""
    from fricstab.scenes.packing import make_packing
    if getattr(ns, "packing", None) is not None:
        path = _packing_file(ns.packing)
        return _load_packing(path), str(path)
    packing = make_packing(params["n"], params["phi"], params["seed"], dphi=params["dphi"],
                           f_tol=params["f_tol"], f_tol_compress=params["f_tol_compress"],
                           progress=_show_progress(ns))
    if out is not None:
        _save_packing(out / "packing.npz", packing)
    return packing, None


def _save_packing(path, packing):
    def write(tmp):
        with open(tmp, "wb") as fh:
            packing.save(fh)
    atomic_write(path, write)


def _packing_source_checks(ns):
    """--packing excludes make options given on the command line; the file must exist."""
    if ns.packing is None:
        return
    given = [f"--{k.replace('_', '-')}" for k in MAKE_KEYS if getattr(ns, k) is not None]
    if given:
        raise ParameterError(f"--packing cannot be combined with {', '.join(given)} "
                             "(those make a new packing)")
    _packing_file(ns.packing)


def _summary(packing, bb):
    return {"n": packing.n, "phi": packing.phi, "seed": packing.seed, "box": packing.box,
            "n_backbone": bb.n, "rattlers": packing.n - bb.n,
            "backbone_rattler_force": bb.rattler_force}


# ------------------------------------------------------------------ make

def _make(ns, argv):
    from fricstab.scenes.pack_system import backbone, contact_forces, network

    t0 = time.perf_counter()
    params = _resolve(ns, MAKE_KEYS + ("z_th",))
    out = _check_out(ns.out, ["packing.npz", "packing.json", "packing.png"], ns.force)
    if ns.dry_run:
        return _dry_run(params)
    out = _prepare_out(out)
    packing, _ = _obtain_packing(ns, params, None)
    radius = packing.diameter / 2
    net = network(packing.pos, radius, packing.box)
    bb = backbone(packing, z_th=params["z_th"])
    m_bb = network(bb.pos, bb.radius, bb.box).m
    rattler = np.ones(packing.n, dtype=bool)
    rattler[bb.keep] = False
    force = np.linalg.norm(contact_forces(net, radius, 0.0), axis=1) if net.m else np.zeros(0)
    doc = {"parameters": params, "phi_start": packing.info.get("phi_start"),
           "info": packing.info, "box": packing.box,
           "contacts": net.m, "z_th": params["z_th"], "rattlers": int(rattler.sum()),
           "n_backbone": bb.n, "contacts_backbone": m_bb,
           "mean_contact_number_backbone": 2 * m_bb / bb.n if bb.n else None,
           "backbone_rattler_force": bb.rattler_force,
           "max_contact_force": float(force.max()) if force.size else 0.0}
    _save_packing(out / "packing.npz", packing)
    atomic_write(out / "packing.png",
                 lambda tmp: packing_figure(packing, net, force, rattler, tmp))
    doc.update(_meta(argv, time.perf_counter() - t0, params["seed"], params))
    _write_record(out, "packing", doc)
    print(f"packing N = {packing.n}, phi = {packing.phi:g}, seed = {packing.seed}: "
          f"L = {packing.box:.6g}, {net.m} contacts, {doc['rattlers']} rattlers (Z <= "
          f"{params['z_th']}), backbone Z = {doc['mean_contact_number_backbone']:.4f}, "
          f"max |F| = {packing.info.get('max_force', float('nan')):.1e} "
          f"({packing.info.get('seconds', float('nan')):.1f} s)")
    print(f"wrote {out}/packing.npz, packing.json, packing.png")
    return 0


def _setup(ns, keys, command, result_names):
    """Parameters, output folder, packing and backbone shared by rigidity and dos."""
    from fricstab.scenes.pack_system import backbone

    params = _resolve(ns, MAKE_KEYS + keys, DEFAULT_KT[command])
    _packing_source_checks(ns)
    kts = params["kt"]
    names = result_names(kts) + ([] if ns.packing else ["packing.npz"])
    out = _check_out(ns.out, names, ns.force)
    if ns.dry_run:
        return None
    out = _prepare_out(out)
    packing, source = _obtain_packing(ns, params, out)
    return params, kts, out, packing, source, backbone(packing, z_th=params["z_th"])


# ------------------------------------------------------------------ rigidity

def _rigidity(ns, argv):
    import scipy.sparse as sps
    from tqdm import tqdm

    from fricstab.scenes.pack_system import ndof
    from fricstab.analysis.rigidity import rigidity
    from fricstab.protocols.stepstrain import step_strain

    t0 = time.perf_counter()
    setup = _setup(ns, ("kt", "dgamma", "z_th", "route"), "rigidity",
                   lambda kts: ["rigidity.json", "rigidity.png"] + [_kt_name(k) for k in kts])
    if setup is None:
        return _dry_run(_resolve(ns, MAKE_KEYS + ("kt", "dgamma", "z_th", "route"),
                                 DEFAULT_KT["rigidity"]))
    params, kts, out, packing, source, bb = setup
    modes = ns.modes if ns.modes is not None else bb.n <= MODES_MAX_PARTICLES
    results, first = [], None
    with tqdm(kts, desc="rigidity", unit="kt", disable=ns.no_progress or None,
              file=sys.stderr) as bar:
        for kt in bar:
            bar.set_postfix_str(f"kt={kt:g}")
            r = rigidity(bb, kt, modes=modes, route=params["route"])
            s = step_strain(bb, kt, dgamma=params["dgamma"])
            g_modes = r.g_modes if modes else None
            g_na_modes = r.g_na_modes if modes else None
            rel = {"solve_vs_step": _rel(s.g, r.g), "modes_vs_step": _rel(s.g, g_modes),
                   "solve_vs_modes": _rel(g_modes, r.g)}
            k = ndof(kt)
            entry = {"kt": kt, "folder": _kt_name(kt), "ndof": k, "g_a": r.g_a,
                     "g_na_solve": r.g_na_solve, "g_na_modes": g_na_modes, "g": r.g,
                     "g_modes": g_modes, "g_step": s.g, "g_step_backward": s.g_backward,
                     "g_step_error": s.error, "sigma0": s.sigma0,
                     "relative_differences": rel,
                     "step_iterations": s.iterations, "contacts_changed": s.contacts_changed,
                     "checks": r.checks,
                     "seconds": {**r.seconds, "step_strain": s.seconds}}
            folder = out / _kt_name(kt)
            folder.mkdir(exist_ok=True)

            def jac_npz(tmp, jac=r.jacobian):
                with open(tmp, "wb") as fh:
                    sps.save_npz(fh, sps.csr_matrix(jac))

            atomic_write(folder / "jacobian_tilde.npz", jac_npz)
            _write_npy(folder / "xi.npy", r.xi)
            _write_npy(folder / "theta.npy", r.theta)
            _write_npy(folder / "u.npy", r.u)
            _write_npy(folder / "nonaffine_step.npy", s.nonaffine)
            write_json(folder / "g.json", {
                "box": bb.box, "n": bb.n, "ndof": k, "kt": kt,
                "ordering": "(x, y, l = d theta / 2) per particle" if k == 3
                            else "(x, y) per particle (frictionless Hessian)",
                "g_a": r.g_a, "g_na_solve": r.g_na_solve, "g_na_modes": g_na_modes,
                "g": r.g, "g_modes": g_modes, "g_step": s.g, "g_step_error": s.error,
                "recipe": [
                    ("J = scipy.sparse.load_npz('jacobian_tilde.npz'); xi = np.load('xi.npy'); "
                     "theta = np.load('theta.npy')"),
                    ("u = solve(J, xi) on the complement of the translations e_x, e_y: "
                     "[[J, C], [C^T, 0]] [u; mu] = [xi; 0], C = the unit columns e_x, e_y"),
                    "G_NA = -theta @ u / box**2; G = G_A + G_NA"]})
            results.append(entry)
            if first is None:
                first = (kt, r.u.reshape(bb.n, k), s.nonaffine)
    bad = [(e["kt"], key, v) for e in results
           for key, v in e["relative_differences"].items()
           if key != "solve_vs_modes" and v is not None and v > TOLERANCE]
    doc = {"parameters": {"kt": kts, "dgamma": params["dgamma"], "z_th": params["z_th"],
                          "route": params["route"], "modes": modes},
           "packing_source": source or "made by this command (packing.npz)",
           **_summary(packing, bb),
           "tolerance": TOLERANCE,
           "relative_difference": "|G_theory - G_step| / |G_theory|",
           "passed": not bad, "results": results}
    if source is None:
        doc["make"] = {k: params[k] for k in MAKE_KEYS}
    atomic_write(out / "rigidity.png", lambda tmp: rigidity_figure(results, first, tmp))
    doc.update(_meta(argv, time.perf_counter() - t0, params["seed"], params))
    _write_record(out, "rigidity", doc)
    print(f"packing N = {packing.n} (backbone {bb.n}), phi = {packing.phi:g}, "
          f"L = {packing.box:.6g}; dgamma = {params['dgamma']:g}")
    print(f"{'kt':>8s} {'G_A':>12s} {'G_NA':>12s} {'G solve':>12s} {'G modes':>12s} "
          f"{'G step':>12s} {'+-':>8s} {'rel.diff':>8s}")
    for e in results:
        gm = f"{e['g_modes']:12.5e}" if e["g_modes"] is not None else f"{'-':>12s}"
        worst = max((v for k, v in e["relative_differences"].items()
                     if k != "solve_vs_modes" and v is not None), default=float("nan"))
        print(f"{e['kt']:8g} {e['g_a']:12.5e} {e['g_na_solve']:12.5e} {e['g']:12.5e} {gm} "
              f"{e['g_step']:12.5e} {e['g_step_error']:8.1e} {worst:8.1e}")
    print(f"wrote {out}/rigidity.json, rigidity.png, "
          f"{', '.join(_kt_name(k) + '/' for k in kts)}")
    if bad:
        kt, key, v = max(bad, key=lambda b: b[2])
        print(f"fricstab: error: theory and step strain disagree by more than "
              f"{TOLERANCE:.0%}: {key.replace('_', ' ')} {v:.2%} at kt = {kt:g} "
              f"(results written)", file=sys.stderr)
        return EXIT_DISAGREE
    return 0


# ------------------------------------------------------------------ dos

def _dos(ns, argv):
    from tqdm import tqdm

    from fricstab.analysis import dos as dosmod
    from fricstab.scenes.pack_system import ndof
    from fricstab.analysis.rigidity import linear_response

    t0 = time.perf_counter()
    setup = _setup(ns, ("kt", "z_th", "route", "bins"), "dos",
                   lambda kts: ["dos.json", "dos.npz", "dos.png"])
    if setup is None:
        return _dry_run(_resolve(ns, MAKE_KEYS + ("kt", "z_th", "route", "bins"),
                                 DEFAULT_KT["dos"]))
    params, kts, out, packing, source, bb = setup
    spectra = []
    with tqdm(kts, desc="dos", unit="kt", disable=ns.no_progress or None,
              file=sys.stderr) as bar:
        for kt in bar:
            bar.set_postfix_str(f"kt={kt:g}")
            jac = linear_response(bb, kt)[0]
            sp = dosmod.spectrum(jac, route=params["route"], vectors=True)
            w = sp.eigenvalues
            order = np.argsort(np.abs(w), kind="stable")
            dropped = np.sort(order[:2])
            keep = np.sort(order[2:])   # ascending real part, as spectrum() returns them
            k = ndof(kt)
            psi_t, psi_r, p = dosmod.participation(sp.right[:, keep], k)
            omega = np.sqrt(np.clip(w[keep].real, 0.0, None))
            scale = np.abs(w).max()
            spectra.append({"kt": kt, "k": k, "sp": sp, "eig": w[keep], "omega": omega,
                            "psi_t": psi_t, "psi_r": psi_r, "p": p,
                            "dropped": w[dropped],
                            "negative": int(np.sum(w[keep].real < -1e-12 * scale))})
    positive = np.concatenate([s["omega"][s["omega"] > 0] for s in spectra])
    if positive.size == 0:
        raise ParameterError("the backbone has no mode with omega > 0: no DOS to bin")
    edges = dosmod.log_bins(positive.min() * (1 - 1e-9), positive.max() * (1 + 1e-9),
                            params["bins"])
    per_kt, arrays = [], {"edges": edges, "kt": np.array(kts)}
    for i, s in enumerate(spectra):
        d = dosmod.dos(s["omega"], packing.n, edges)
        peak, median = dosmod.rotational_peak(s["omega"], s["psi_r"])
        s["dos"] = d
        s["psi_t_mean"] = dosmod.binned_mean(s["omega"], s["psi_t"], edges)
        s["psi_r_mean"] = dosmod.binned_mean(s["omega"], s["psi_r"], edges)
        arrays.update({f"eigenvalues_{i}": s["eig"], f"omega_{i}": s["omega"],
                       f"psi_t_{i}": s["psi_t"], f"psi_r_{i}": s["psi_r"], f"p_{i}": s["p"],
                       f"dos_{i}": d, f"psi_t_mean_{i}": s["psi_t_mean"],
                       f"psi_r_mean_{i}": s["psi_r_mean"]})
        sp = s["sp"]
        per_kt.append({"kt": s["kt"], "index": i, "ndof": s["k"], "route": sp.route,
                       "seconds": sp.seconds, "modes": len(s["omega"]),
                       "dropped_translations": [complex(v) if np.iscomplexobj(v) else float(v)
                                                for v in s["dropped"]],
                       "negative_eigenvalues": s["negative"],
                       "negative_threshold": "lambda < -1e-12 max|lambda|",
                       "modes_outside_bins": int(np.sum((s["omega"] < edges[0])
                                                        | (s["omega"] > edges[-1]))),
                       "rotational_peak": peak, "rotational_median": median,
                       "rotation_dominated_modes": int(np.sum(s["psi_r"] > 0.5)),
                       "asymmetry": sp.asymmetry, "max_imag": sp.max_imag,
                       "omega_min": float(s["omega"].min()) if s["omega"].size else None,
                       "omega_max": float(s["omega"].max()) if s["omega"].size else None})
    doc = {"parameters": {"kt": kts, "z_th": params["z_th"], "route": params["route"],
                          "bins": params["bins"]},
           "packing_source": source or "made by this command (packing.npz)",
           **_summary(packing, bb),
           "normalization": "D(omega) = counts / (3 N width), N = all particles "
                            "(rattlers included); translations dropped",
           "edges": [float(edges[0]), float(edges[-1])], "results": per_kt}
    if source is None:
        doc["make"] = {k: params[k] for k in MAKE_KEYS}

    def npz(tmp):
        with open(tmp, "wb") as fh:
            np.savez(fh, **arrays)

    atomic_write(out / "dos.npz", npz)
    atomic_write(out / "dos.png", lambda tmp: dos_figure(spectra, edges, tmp))
    doc.update(_meta(argv, time.perf_counter() - t0, params["seed"], params))
    _write_record(out, "dos", doc)
    print(f"packing N = {packing.n} (backbone {bb.n}), phi = {packing.phi:g}; "
          f"{params['bins']} log bins in omega [{edges[0]:.3g}, {edges[-1]:.3g}]")
    for e in per_kt:
        print(f"  kt = {e['kt']:<8g} {e['route']:9s} {e['modes']:5d} modes, "
              f"{e['negative_eigenvalues']} negative, rotational peak "
              f"{e['rotational_peak']:.3g} (median {e['rotational_median']:.3g}), "
              f"{e['seconds']:.2f} s")
    print(f"wrote {out}/dos.json, dos.npz, dos.png")
    return 0


# ------------------------------------------------------------------ entry

def run(ns, argv=None):
    """Run ``fricstab packing ...``; ``argv`` (the command's arguments) goes into the JSON."""
    from fricstab.scenes.packing import ConvergenceError as PackingConvergence
    from fricstab.protocols.stepstrain import ConvergenceError as StepConvergence

    argv = list(sys.argv[1:] if argv is None else argv)
    _CPU0[0] = time.process_time()
    try:
        if ns.packing_command == "make":
            return _make(ns, argv)
        if ns.packing_command == "rigidity":
            return _rigidity(ns, argv)
        return _dos(ns, argv)
    except (PackingConvergence, StepConvergence) as exc:
        print(f"fricstab: error: no convergence: {' '.join(str(exc).split())}", file=sys.stderr)
        return EXIT_CONVERGENCE


def _register():
    from fricstab.io.scenes import register
    register(_schema())


_register()
