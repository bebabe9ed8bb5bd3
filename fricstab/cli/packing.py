"""``fricstab packing make|rigidity|dos|jacobian``: disk packings of Ishima et al. from the command line.

Units: large diameter ``d = 1``, ``k_N = 1``, mass of a large disk ``m = 1``,
so ``t0 = 1``.  Every command takes a contact law (``--law
hertz|ishima|charan|lee_hurley``, default ishima, the paper's) and its
parameters (``--param KEY=VALUE``; defaults in Ishima's units:
``fricstab scene show packing``).  Friction is switched on at the
frictionless force balance with zero histories (App. A.2); a law whose normal
force is not Hertz's (lee_hurley) is relaxed under it first (Newton).  The
Jacobians are written in Ishima's convention: ``J = -dF/dq`` (Eq. 18) in
``(x, y, l = R theta)`` per particle, ``(x, y)`` for the frictionless hertz
(the 2N x 2N Hessian).

``--kt`` scans kT/kN of ishima or charan (scene key ``kt_scan``); ``0`` is
the frictionless limit (hertz with the law's kn).  Without ``--kt``, a
``kt`` given as ``--param kt=...`` or a scene key is the one run, else the
paper's scan of the command; hertz and lee_hurley run once (``--kt`` is
refused for them).  Each run has a folder ``kt_<value>`` (a scan) or
``<law>``.

``fricstab packing make [--n 256] [--phi 0.90] [--seed 0] [--dphi ...] --out DIR``
    A force-balanced bidisperse packing (:func:`fricstab.scenes.packing.make_packing`;
    make options ``--n --phi --seed --dphi --f-tol --f-tol-compress``), and
    friction switched on with the law.  Writes ``DIR/packing.npz``,
    ``DIR/packing.json`` (parameters, protocol info, contacts, rattlers at
    ``z_th``, mean contact number of the backbone, the law and how friction
    was switched on, versions, command, seconds) and ``DIR/packing.png``
    (disks to scale, rattlers in grey, contact forces as lines).
``fricstab packing rigidity [--packing DIR|FILE.npz | make options] [--kt 1e-4 1 10] --out DIR``
    For each run: G_A, G_NA by sparse solve, G_NA by the mode sum
    (``--modes``; default on when the backbone has <= 1100 particles), G by
    step strain ``--dgamma`` (default 1e-6) with its error estimate, and the
    relative disagreements.  Writes ``DIR/rigidity.json``,
    ``DIR/rigidity.png`` and per run a folder with ``jacobian_tilde.npz``
    (``scipy.sparse.save_npz`` of J~ = J), ``xi.npy``, ``theta.npy``,
    ``u.npy`` (nonaffine rate of the solve, flat, ``ndof`` per particle),
    ``nonaffine_step.npy`` ((n, ndof), step strain) and ``g.json`` (box, n,
    ndof, law, the G values and a recipe to recompute G_NA from these files).
    Exit status 3 when a theory value differs from step strain by more than
    1% of |G|; the files are written first.
``fricstab packing dos [--packing ... | make options] [--kt 1e-8 1e-4 1 10] [--bins 50] --out DIR``
    For each run the spectrum of the backbone's J (``--route``), omega =
    sqrt(lambda) with the two translations dropped, psi^T, psi^R, p, the DOS
    with N = all particles on ``--bins`` log bins spanning every run's
    nonzero frequencies, the peak and median frequency of rotation-dominated
    modes.  Writes ``dos.json``, ``dos.npz`` (per run index i:
    ``eigenvalues_<i>``, ``omega_<i>``, ``psi_t_<i>``, ``psi_r_<i>``,
    ``p_<i>``, ``dos_<i>``; and ``edges``, ``kt``) and ``dos.png``.
``fricstab packing jacobian [--packing ... | make options] [--law NAME] --out DIR``
    The backbone under the law, force-balanced, written by
    :func:`fricstab.io.jacobian_export.write_state_jacobian`: ``state.npz``,
    ``jacobian.npz`` (``K = dF/dq`` in the law's own coordinates),
    ``dofs.json``, ``mass.npy``; and ``jacobian.json`` (the record).

``fricstab packing jacobian|rigidity|dos|aqs --state DIR_OR_NPZ [--f-tol F] --out DIR``
    The same analyses of a written state (``state.npz`` of ``fricstab
    import``, ``packing jacobian``, an AQS event; or its directory), checked
    against the record beside it (``import.json`` or ``jacobian.json``; a
    changed file is refused, exit 2; none: a one-line warning).  The law, its
    parameters, the box and its Lees-Edwards offset, walls and fixed particles
    come from the file, in its units (``--packing``, make options, ``--kt``,
    ``--law``, ``--param``, ``--scene`` are refused); rattlers (``--z-th``) are
    removed from it; ``--f-tol`` defaults to 1e-12 x its mean contact force.
    ``rigidity`` and ``aqs`` need a periodic box without walls or fixed
    particles; ``jacobian`` also records the spectrum of ``M^-1 K``, its complex
    pairs and the largest growth rate.  Records name the state under
    ``"state"`` instead of ``"packing"`` (:mod:`fricstab.cli.packing_state`).

Common options: ``--z-th`` (rattlers: Z <= z_th, removed iteratively;
default 2), ``--route auto|symmetric|dense``, ``--scene FILE.toml`` (keys at
the top level or under ``[packing]``: ``fricstab scene show packing``; the
command line wins; keys a command does not use are ignored), ``--force``
(replace this command's result, and the packing of ``--out`` if it is
another), ``--no-progress``, ``--dry-run``.  ``rigidity``, ``dos`` and
``jacobian`` use the packing that ``--packing`` names, checked against its
record's manifest (a changed, missing or damaged file, or an interrupted
run, is refused); else the packing of ``--out`` if its make parameters are
the run's; else they make one and record it as a ``packing`` result of
``--out`` (``packing.npz``, ``packing.json``).  ``--packing`` cannot be
combined with make options on the command line.  A directory holds one
packing and only results made from it (:mod:`fricstab.cli.packing_source`).

Every command writes through :class:`fricstab.io.results.ResultDir`: one
writer per directory (a second is refused naming the first), a record with
the fingerprint of the parameters and the manifest of its files.

Exit status: 0 ok, 2 bad input (one line naming the parameter; nothing is
written), 3 theory and step strain disagree by more than 1%, 4 a relaxation
did not converge or the law refused a configuration.  Every file is written
atomically (a complete file or none).
"""

import argparse
import math
import sys
from pathlib import Path

from fricstab.cli.packing_common import DEFAULT_KT, DEFAULTS, MODES_MAX_PARTICLES, ROUTES
from fricstab.errors import ConvergenceError, ParameterError

__all__ = ["add_parser", "run"]


def _nonneg_float(text):
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
    from fricstab.io.scenes import add_law_options
    add_law_options(c, "packing")
    c.add_argument("--scene", type=Path, default=None, help="TOML scene file")
    c.add_argument("--z-th", type=int, default=None,
                   help="rattlers: Z <= z_th, removed iteratively (default 2)")
    c.add_argument("--out", type=Path, required=True, help="output directory")
    c.add_argument("--force", action="store_true",
                   help="replace this command's result in --out; a packing there made with "
                        "other parameters is replaced too, with the results made from it")
    c.add_argument("--no-progress", action="store_true", help="no progress bars")
    c.add_argument("--quiet", action="store_true",
                   help="print nothing on success (errors still go to stderr)")
    c.add_argument("--dry-run", action="store_true",
                   help="validate and resolve every parameter, print them as JSON, write nothing")


def _packing_option(c):
    c.add_argument("--packing", type=Path, default=None, metavar="DIR_OR_NPZ",
                   help="use this packing (a directory with packing.npz, or the .npz), "
                        "checked against its record, instead of making one; without it the "
                        "packing of --out is reused if made with the same make options, "
                        "else one is made (a different one there needs --force)")
    c.add_argument("--state", type=Path, default=None, metavar="DIR_OR_NPZ",
                   help="analyse this written state (a directory with state.npz, e.g. of "
                        "fricstab import, or the .npz), checked against its record; the law, "
                        "its parameters and the box come from it (--packing, make options, "
                        "--kt, --law, --param, --scene refused); --f-tol defaults to 1e-12 "
                        "x its mean contact force")


def add_parser(sub, parser_class, positive_float):
    """Register ``fricstab packing make|rigidity|dos|jacobian`` on the subparsers ``sub``."""
    p = sub.add_parser("packing", help="bidisperse disk packings: rigidity and DOS (Ishima et al.)",
                       description="Bidisperse disk packings (Ishima et al.) under any contact "
                       "law: make one, its shear rigidity from the Jacobian against step strain, "
                       "its density of states, its state and Jacobian.")
    psub = p.add_subparsers(dest="packing_command", metavar="PACKING_COMMAND",
                            parser_class=parser_class)
    psub.required = True
    m = psub.add_parser("make", help="a force-balanced frictionless packing")
    _make_options(m)
    _common_options(m)
    for name, helptext in (("rigidity", "G_A, G_NA (solve, modes) and G by step strain per kt"),
                           ("dos", "density of states and mode character per kt")):
        c = psub.add_parser(name, help=helptext)
        _packing_option(c)
        _make_options(c)
        default = " ".join(f"{k:g}" for k in DEFAULT_KT[name])
        c.add_argument("--kt", type=_nonneg_float, nargs="+", default=None, metavar="KT",
                       help=f"kT/kN values of ishima or charan, >= 0; 0 = frictionless "
                            f"(default {default}, or the law's kt when given)")
        c.add_argument("--route", choices=ROUTES, default=None,
                       help="eigen-solver of the %s: symmetric (eigh), dense (eig), auto "
                            "(symmetric when J = J^T to 1e-12; default)"
                            % ("mode sum" if name == "rigidity" else "spectrum"))
        if name == "rigidity":
            c.add_argument("--dgamma", type=positive_float(), default=None,
                           help="step strain, in (0, 0.1] (default 1e-6)")
            c.add_argument("--modes", action=argparse.BooleanOptionalAction, default=None,
                           help="G_NA also by the eigenmode sum (dense eigen-decomposition); "
                                f"default: on when the backbone has <= {MODES_MAX_PARTICLES} "
                                "particles, else off")
        else:
            c.add_argument("--bins", type=int, default=None,
                           help="logarithmic frequency bins of the DOS, >= 1 (default 50)")
        _common_options(c)
    j = psub.add_parser("jacobian", help="the force-balanced state under the law and its "
                        "Jacobian (state.npz, jacobian.npz, dofs.json, mass.npy)")
    _packing_option(j)
    _make_options(j)
    _common_options(j)
    from fricstab.cli.packing_aqs import add_parser as add_aqs
    add_aqs(psub, _packing_option, _make_options, _common_options)
    return p


# ------------------------------------------------------------------ the scene

def _schema():
    """The packing scene (``fricstab scene show packing``); one source of keys and ranges."""
    from fricstab.io.scenes import Field, Schema, in_scale_window
    from fricstab.scenes.packing import PHI_MAX, PHI_START_MAX
    from fricstab.scenes.packing_friction import LAWS
    return Schema("packing", "bidisperse frictional disk packings (Ishima et al.)", (
        Field("n", "int", DEFAULTS["n"], "-", "number of disks (half large d = 1, half small "
              "d = 1/1.4); cost of rigidity/dos grows as n^1.5 (sparse) to n^3 (dense modes)",
              low=4, high=200_000, check=lambda v: v % 2 == 0, check_doc="even"),
        Field("phi", "float", DEFAULTS["phi"], "-", "area fraction of the packing",
              low=PHI_START_MAX, high=PHI_MAX),
        Field("seed", "int", DEFAULTS["seed"], "-", "seed of the random placement",
              low=0, high=2 ** 63 - 1),
        Field("dphi", "float", DEFAULTS["dphi"], "-", "compression increment (paper 1e-4); "
              "smaller is slower, closer to the paper's protocol", low=1e-9, high=0.1,
              check_doc="below 1e-9 the compression takes more steps than any run"),
        Field("f_tol", "float", DEFAULTS["f_tol"], "k_N d", "force threshold at the target "
              "phi: max |F| below it", low=1e-16, high=1.0,
              check_doc="below 1e-16 the round-off of the forces never meets it"),
        Field("f_tol_compress", "float", DEFAULTS["f_tol_compress"], "k_N d",
              "force threshold of the intermediate compression steps (looser is faster)",
              low=1e-16, high=1.0,
              check_doc="below 1e-16 the round-off of the forces never meets it"),
        Field("kt_scan", "floats", None, "-", "kT/kN values scanned with ishima or charan "
              "(replace the law's kt); 0 = frictionless (hertz with the law's kn)", low=0.0,
              high=1e30, check=in_scale_window, check_doc="0 or >= 1e-30 (a sub-normal kT "
              "leaves float64 in its products)",
              cli="--kt", default_doc="the law's kt when given, else rigidity: 1e-4 1 10; "
              "dos: 1e-8 1e-4 1 10"),
        Field("dgamma", "float", DEFAULTS["dgamma"], "-", "step strain of the G check; "
              "smaller is closer to linear response until round-off dominates (below 1e-10 "
              "the stress round-off 2 eps_sigma/dgamma, with the relaxation's 1e-14 residual "
              "forces, exceeds 1 % of G)", low=1e-10, high=0.1),
        Field("z_th", "int", DEFAULTS["z_th"], "-", "rattlers: Z <= z_th, removed "
              "iteratively", low=0, high=1000),
        Field("route", "str", DEFAULTS["route"], "-", "eigen-solver: symmetric (eigh), dense "
              "(eig), auto (symmetric when J = J^T to 1e-12)", choices=ROUTES),
        Field("bins", "int", DEFAULTS["bins"], "-", "logarithmic frequency bins of the DOS",
              low=1, high=100_000),
    ), laws=LAWS)


# ------------------------------------------------------------------ entry

def run(ns, argv=None):
    """Run ``fricstab packing ...``; ``argv`` (the command's arguments) goes into the JSON."""
    argv = list(sys.argv[1:] if argv is None else argv)
    try:
        if getattr(ns, "state", None) is not None:
            from fricstab.cli.packing_state import run as run_state
            return run_state(ns, argv)
        if ns.packing_command == "make":
            from fricstab.cli.packing_make import make
            return make(ns, argv)
        if ns.packing_command == "jacobian":
            from fricstab.cli.packing_make import jacobian
            return jacobian(ns, argv)
        if ns.packing_command == "aqs":
            from fricstab.cli.packing_aqs import aqs
            return aqs(ns, argv)
        if ns.packing_command == "rigidity":
            from fricstab.cli.packing_rigidity import rigidity
            return rigidity(ns, argv)
        from fricstab.cli.packing_dos import dos
        return dos(ns, argv)
    except ConvergenceError as exc:
        print(f"fricstab: error: no convergence: {' '.join(str(exc).split())}", file=sys.stderr)
        return ConvergenceError.exit_code
    except ValueError as exc:
        if isinstance(exc, ParameterError):
            raise
        # a contact law refusing a configuration (e.g. beyond the turning point of lee_hurley)
        print(f"fricstab: error: numerical failure: {' '.join(str(exc).split())}",
              file=sys.stderr)
        return ConvergenceError.exit_code


def _register():
    from fricstab.io.scenes import register
    register(_schema())


_register()
