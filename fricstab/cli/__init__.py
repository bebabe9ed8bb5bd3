"""The ``fricstab`` command.

Subcommands
-----------
``fricstab laws``: the contact laws (kernel arguments, parameters with units, dof,
history, rotation coordinate, cap, wall/pair form).
``fricstab verify --law NAME|all --cases N --seed S --json PATH``: prove the generated
Jacobian blocks (:mod:`fricstab.laws.verify`); a table and a JSON list per law.
``fricstab chain ...``: Charan et al.'s chain (:mod:`fricstab.cli.chain`).
``fricstab packing ...``: Ishima et al.'s packings (:mod:`fricstab.cli.packing`).
``fricstab import FILE... --law NAME --param KEY=VALUE ... --out DIR``: a packing made
elsewhere as our state, checked against the law (:mod:`fricstab.cli.imports`).
``fricstab shear ...``: Lee & Hurley's plane shear (:mod:`fricstab.cli.shear`).
``fricstab warmup``: compile every numba kernel once (:mod:`fricstab.cli.warmup`).
``fricstab scene show NAME|list``: the keys of the scene files (:mod:`fricstab.io.scenes`).

Exit status
-----------
0 ok; 1 the operating system refused a file operation; 2 bad input (one
line naming the parameter, its value and what is allowed); 3 theory and
simulation (or a proof) disagree; 4 numerical failure (non-finite force,
energy or eigenvalue; no convergence; out of memory), the last checkpoint
kept; 70 internal error (a bug: one line, the traceback in
``<out>/fricstab-error.log`` or shown with ``--debug``); 130 SIGINT, 143
SIGTERM (:mod:`fricstab.signals`; checkpoints kept: rerun with ``--resume``).
No traceback reaches the user unless ``--debug`` is given.
"""

import argparse
import contextlib
import io
import math
import os
import platform
import sys
import tempfile
import time
import traceback
import warnings
from pathlib import Path

#: Most threads NUMBA_NUM_THREADS may ask for.
MAX_ENV_THREADS = 1024
#: numba's threading layers (NUMBA_THREADING_LAYER) -> the pools that can serve each.
_LAYERS = {"default": ("tbbpool", "omppool", "workqueue"), "safe": ("tbbpool",),
           "threadsafe": ("tbbpool", "omppool"), "forksafe": ("tbbpool", "workqueue"),
           "tbb": ("tbbpool",), "omp": ("omppool",), "workqueue": ("workqueue",)}


def _check_thread_count(environ):
    """Why ``NUMBA_NUM_THREADS`` cannot work (one line), or None.

    Read by numba when it is imported (a traceback for 0, -1; a warning for
    ``abc``): checked before.  A bad value is removed from ``environ`` so that
    numba still imports; :func:`main` then refuses with the line (exit 2).
    An empty value counts as unset.
    """
    text = environ.get("NUMBA_NUM_THREADS")
    if text is None:
        return None
    if not text.strip():
        environ.pop("NUMBA_NUM_THREADS")
        return None
    try:
        value = int(text)
    except ValueError:
        value = None
    if value is not None and 1 <= value <= MAX_ENV_THREADS:
        return None
    environ.pop("NUMBA_NUM_THREADS")
    return (f"environment variable NUMBA_NUM_THREADS = {text[:40]!r} must be an integer in "
            f"[1, {MAX_ENV_THREADS}] (unset it to use every core, or use --threads N)")


def _check_threading_layer(environ=os.environ):
    """Why ``NUMBA_THREADING_LAYER`` cannot work (one line), or None (numba is imported)."""
    import importlib
    text = environ.get("NUMBA_THREADING_LAYER")
    if text is None or not text.strip():
        return None
    pools = _LAYERS.get(text.strip().lower())
    if pools is None:
        return (f"environment variable NUMBA_THREADING_LAYER = {text[:40]!r} is not a "
                f"threading layer of numba; allowed: {', '.join(_LAYERS)} (or unset it)")
    for pool in pools:
        try:
            importlib.import_module(f"numba.np.ufunc.{pool}")
            return None
        except (ImportError, OSError):
            continue
    return (f"environment variable NUMBA_THREADING_LAYER = {text[:40]!r}: that threading "
            f"layer is not installed here (its library, e.g. TBB for 'tbb' and 'safe', is "
            f"missing); unset it or use workqueue")


#: A bad NUMBA_NUM_THREADS, found before numba is imported (below); main refuses it.
_THREAD_ENV_PROBLEM = _check_thread_count(os.environ)

from fricstab import __version__  # noqa: E402  (numba reads its environment when imported)
from fricstab.laws import ALL_LAW_NAMES, CAPPED_LAW_NAMES, ParameterError, get_law  # noqa: E402

ALL_LAWS = ALL_LAW_NAMES

__all__ = ["main", "EXIT_OK", "EXIT_OS", "EXIT_USAGE", "EXIT_DISAGREE", "EXIT_NUMERICAL",
           "EXIT_INTERNAL", "EXIT_INTERRUPTED"]

EXIT_OK, EXIT_OS, EXIT_USAGE, EXIT_DISAGREE, EXIT_NUMERICAL = 0, 1, 2, 3, 4
EXIT_INTERNAL, EXIT_INTERRUPTED = 70, 130


class UsageError(Exception):
    """Bad command-line input (exit status 2)."""


class _Parser(argparse.ArgumentParser):
    def error(self, message):
        raise UsageError(message)


def _int_at_least(minimum, maximum=None, why=""):
    def parse(text):
        try:
            value = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"must be an integer, got {text!r}") from None
        if value < minimum:
            raise argparse.ArgumentTypeError(f"must be >= {minimum}, got {text!r}")
        if maximum is not None and value > maximum:
            raise argparse.ArgumentTypeError(f"must be <= {maximum}{why}, got {text!r}")
        return value
    return parse


def _positive_float(low=0.0, high=math.inf, why=""):
    """A finite float in ``(0, inf)``, or in ``[low, high]`` when given (``why`` says why)."""
    def parse(text):
        try:
            value = float(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"must be a number, got {text!r}") from None
        if not math.isfinite(value) or value <= 0:
            raise argparse.ArgumentTypeError(f"must be a finite number > 0, got {text!r}")
        if not low <= value <= high:
            raise argparse.ArgumentTypeError(f"must be in [{low:g}, {high:g}]{why}, "
                                             f"got {text!r}")
        return value
    return parse


#: The verification's domain: its errors are relative, so scales far beyond
#: these only overflow (k_n R^(3/2) delta^(3/2)) or leave nothing to resolve.
_VERIFY_SCALE = " (the proofs are scale-free; beyond this float64 overflows)"


def _law_list(text):
    if text == "all":
        return list(ALL_LAWS)
    names = [t.strip() for t in text.split(",") if t.strip()]
    if not names:
        raise argparse.ArgumentTypeError("must name a law or 'all'")
    for n in names:
        if n not in ALL_LAWS:
            raise argparse.ArgumentTypeError(
                f"unknown law {n!r}; known laws: {', '.join(ALL_LAWS)}, all")
    return names


def _parser():
    p = _Parser(prog="fricstab", description="Verified contact laws of frictional disks, and "
                "the protocols of three studies of frictional granular matter.",
                epilog="exit status: 0 ok, 1 file system refused, 2 bad input, 3 theory and "
                "simulation disagree, 4 numerical failure or no convergence (last checkpoint "
                "kept), 70 internal error (a bug; log in the output folder), 130 SIGINT and "
                "143 SIGTERM (last checkpoint kept; resume with --resume)")
    p.add_argument("--version", action="version", version=f"fricstab {__version__}")
    p.add_argument("--debug", action="store_true",
                   help="show the traceback of an internal error (default: one line, the "
                        "traceback written to a log file)")
    p.add_argument("--threads", type=int, default=None, metavar="N",
                   help="threads of the DEM engine (default: all cores, or NUMBA_NUM_THREADS); "
                        "results are the same to the bit at every count")
    sub = p.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)
    sub.required = True
    sub.add_parser("laws", help="list the contact laws")
    v = sub.add_parser("verify", help="prove the generated Jacobians (see docs/reference/verification.md)")
    v.add_argument("--law", type=_law_list, default=list(ALL_LAWS),
                   help="law name, comma-separated names, or 'all' (default: all)")
    v.add_argument("--cases", type=_int_at_least(1, 1_000_000, " (about 1,000 cases per "
                                                   "law per minute)"), default=200,
                   help="configurations per law (default: 200)")
    v.add_argument("--seed", type=_int_at_least(0, 2 ** 63 - 1), default=0,
                   help="seed of the configuration sampler (default: 0)")
    v.add_argument("--json", type=Path, default=None, metavar="PATH",
                   help="write the JSON report here")
    v.add_argument("--radius", type=_positive_float(1e-6, 1e6, _VERIFY_SCALE), default=0.5,
                   help="radius R of particle i (default: 0.5)")
    v.add_argument("--kn", type=_positive_float(1e-6, 1e12, _VERIFY_SCALE), default=1.0,
                   help="normal stiffness k_n (default: 1)")
    v.add_argument("--mu-range", type=_positive_float(1e-8, 1e8, _VERIFY_SCALE), nargs=2,
                   metavar=("LO", "HI"), default=None, help="friction coefficient range "
                   "(default: 0.1 100)")
    v.add_argument("--kt-ratio-range", type=_positive_float(1e-14, 1e4, _VERIFY_SCALE),
                   nargs=2,
                   metavar=("LO", "HI"), default=None, help="k_t/k_n range (default: 1e-10 10)")
    v.add_argument("--delta-range", type=_positive_float(1e-15, 1.0), nargs=2,
                   metavar=("LO", "HI"), default=None, help="overlap/R range (default: 1e-12 0.1)")
    v.add_argument("--radius-ratio-range", type=_positive_float(1.0, 1e6, _VERIFY_SCALE),
                   nargs=2, metavar=("LO", "HI"), default=None,
                   help="R_j/R_i range (default: 1 1.4)")
    v.add_argument("--no-progress", action="store_true", help="no progress bar")
    from fricstab.cli import chain as chain_cli, imports as import_cli, packing as packing_cli
    from fricstab.cli import warmup as warmup_cli
    chain_cli.add_parser(sub, _Parser, _positive_float)
    packing_cli.add_parser(sub, _Parser, _positive_float)
    import_cli.add_parser(sub, _Parser, _positive_float)
    shear = _shear_cli()
    if shear is not None:
        shear.add_parser(sub, _Parser, _positive_float)
    warmup_cli.add_parser(sub)
    sc = sub.add_parser("scene", help="the keys of the scene files (show, list)")
    ssub = sc.add_subparsers(dest="scene_command", metavar="SCENE_COMMAND",
                             parser_class=_Parser)
    ssub.required = True
    show = ssub.add_parser("show", help="every key of a scene: type, default, unit, allowed, doc")
    show.add_argument("name", help="scene name (see `fricstab scene list`)")
    ssub.add_parser("list", help="the scene names")
    return p


def _shear_cli():
    """fricstab.cli.shear, or None where it is not installed."""
    try:
        from fricstab.cli import shear as shear_cli
    except ImportError:
        return None
    if not (hasattr(shear_cli, "add_parser") and hasattr(shear_cli, "run")):
        return None
    return shear_cli


def _cmd_scene(ns):
    from fricstab.io import scenes as scene
    if ns.scene_command == "list":
        for name in scene.names():
            print(f"{name:10s} {scene.get(name).title}")
        return 0
    print(scene.show(ns.name))
    return 0


def _ranges(ns):
    from fricstab.laws.verify import EXTREMES
    ranges = dict(EXTREMES)
    for key, opt, upper in (("mu", "mu_range", None), ("kt_over_kn", "kt_ratio_range", None),
                            ("delta_over_R", "delta_range", 1.0),
                            ("radius_ratio", "radius_ratio_range", None)):
        value = getattr(ns, opt)
        if value is None:
            continue
        lo, hi = value
        flag = "--" + opt.replace("_", "-")
        if lo > hi:
            raise UsageError(f"{flag}: LO must not exceed HI, got {lo:g} > {hi:g}")
        if upper is not None and hi >= upper:
            raise UsageError(f"{flag}: HI must be < {upper:g} (overlap below the radius), got {hi:g}")
        if key == "radius_ratio" and lo < 1.0:
            raise UsageError(f"{flag}: LO must be >= 1 (particle i is the smaller), got {lo:g}")
        ranges[key] = (lo, hi)
    return ranges


def _cmd_laws():
    for name in ALL_LAWS:
        law = get_law(name)
        geo = ", ".join(law.geometry_args)
        rot = {"theta": "theta (torque T)", "l": "l = R theta (force T/R)", "": "none"}
        other = f"wall form {law.wall}" if law.kind == "pair" else f"pair form {law.pair}"
        print(f"{name} ({law.kind}, id {law.law_id}): coords ({', '.join(law.coords)}), "
              f"forces ({', '.join(law.outputs)})")
        print("  kernel arguments:")
        print(f"    {name}_force({', '.join(law.inputs)}, f)")
        print(f"    {name}_eval({geo}, p, h, f, jac, want_jac)   forces f and K = dF/dq")
        print(f"    {name}_rate({geo}, p, a)   increment rule dh = a dq")
        print(f"    {name}_project({geo}, p, h) -> flags   history onto its admissible set")
        disp = "du" if law.kind == "wall" else "dui, duj, dxj"
        print(f"    {name}_advance({', '.join(law.advance_geometry_args)}, p, h, {disp}, f, aux, "
              f"want_aux) -> flags   one dynamics step; aux = ({', '.join(law.contact)}) if "
              "want_aux" + ("; r, delta, lam = fricstab._numerics.pair_geometry(dx, dy, Ri, Rj, "
                            f"{law.width})" if law.kind == "pair" else ""))
        print(f"    p = ({', '.join(law.params)}), h = ({', '.join(law.history) or '-'})")
        print("  parameters:")
        for p, u, d in zip(law.params, law.param_units, law.param_docs):
            print(f"    {p} [{u}]: {d}")
        print(f"  dof {law.n_dof}, history {law.n_hist} ({', '.join(law.history) or '-'}), "
              f"rotation {rot[law.rotation]}, cap {'yes' if law.capped else 'no'}, {other}")
    return 0


def _fmt(x):
    return "   null" if x is None else f"{x:8.1e}"


def _cmd_verify(ns):
    import numpy as np
    import numba
    import scipy
    from tqdm import tqdm

    from fricstab.laws.verify import sample_cases, verify_law

    ranges = _ranges(ns)
    if ns.json is not None:
        parent = ns.json.expanduser().resolve().parent
        if not parent.is_dir():
            raise UsageError(f"--json: directory {parent} does not exist")
    cases = sample_cases(ns.cases, ns.seed, ranges=ranges)
    results = []
    bar = tqdm(total=ns.cases * len(ns.law), desc="verify", unit="case",
               disable=ns.no_progress or None, file=sys.stderr)
    capped = [n for n in ns.law if n in CAPPED_LAW_NAMES]
    capped_ok = True
    for name in capped:   # own parameters and regimes: fricstab.laws.verify_lee_hurley
        from fricstab.laws import verify_lee_hurley as shear_verify
        bar.set_postfix_str(name)
        report = shear_verify.verify_cases(shear_verify.sample_cases(ns.cases, ns.seed, law=name),
                                           ns.seed, bar, law=name)
        results.append(report)
        capped_ok &= shear_verify.failures(report) == 0
    for name in (n for n in ns.law if n not in CAPPED_LAW_NAMES):
        t0 = time.perf_counter()
        bar.set_postfix_str(name)
        res = verify_law(name, cases, ns.seed, progress=bar, radius=ns.radius, kn=ns.kn)
        res["meta"] = {
            "elapsed_s": round(time.perf_counter() - t0, 3),
            "ranges": ranges, "radius": ns.radius, "kn": ns.kn,
            "fricstab": __version__, "numpy": np.__version__, "scipy": scipy.__version__,
            "numba": numba.__version__, "python": platform.python_version(),
        }
        results.append(res)
    bar.close()
    print(f"{'law':26s} {'cases':>6s} {'cplx-step':>9s} {'(unexpl.)':>9s} {'mp50':>9s} "
          f"{'(unexpl.)':>9s} {'central':>9s} {'>1e-6':>6s} {'(unexpl.)':>9s} "
          f"{'taylor':>13s} {'(failed)':>8s} {'nonfinite':>9s}")
    for r in results:
        if r["law"] in CAPPED_LAW_NAMES:
            for regime, g in r["regimes"].items():
                print(f"{r['law'] + ':' + regime:26s} {g['cases']:6d} "
                      f"{_fmt(g['max_rel_err_complex_step'])} {g['complex_step_above_bound']:9d} "
                      f"{_fmt(g['max_rel_err_central_mp50'])} {g['central_mp50_above_bound']:9d} "
                      f"{_fmt(g['max_rel_err_central'])} {g['central_above_1e-6']:6d} "
                      f"{'-':>9s} {g['taylor_slope_min']:13.3f} {'-':>8s} {g['nonfinite']:9d}")
            continue
        slope = (f"{r['taylor_slope_min']:.3f}-{r['taylor_slope_max']:.3f}"
                 if r["taylor_slope_min"] is not None else "n/a")
        print(f"{r['law']:26s} {r['cases']:6d} {_fmt(r['max_rel_err_complex_step'])} "
              f"{r['complex_step_unexplained_cases']:9d} {_fmt(r['max_rel_err_central_mp50'])} "
              f"{r['central_mp50_unexplained_cases']:9d} {_fmt(r['max_rel_err_central'])} "
              f"{r['central_cases_above_bound']:6d} {r['central_unexplained_cases']:9d} "
              f"{slope:>13s} {r['taylor_failed_cases']:8d} {r['nonfinite']:9d}")
    if ns.json is not None:
        from fricstab.io.files import write_json
        write_json(ns.json, results)   # atomically: a complete report or none
        print(f"wrote {ns.json}")
    ok = capped_ok and all(r["complex_step_unexplained_cases"] == 0 and r["central_unexplained_cases"] == 0
             and r["central_mp50_unexplained_cases"] == 0 and r["taylor_failed_cases"] == 0
             and r["nonfinite"] == 0 for r in results if r["law"] not in CAPPED_LAW_NAMES)
    if not ok:
        print("fricstab: verification FAILED (see the table)", file=sys.stderr)
    return 0 if ok else 3


def _dispatch(ns, argv):
    if ns.command == "laws":
        return _cmd_laws()
    if ns.command == "scene":
        return _cmd_scene(ns)
    if ns.command == "chain":
        from fricstab.cli import chain as chain_cli
        return chain_cli.run(ns, argv)
    if ns.command == "packing":
        from fricstab.cli import packing as packing_cli
        return packing_cli.run(ns, argv)
    if ns.command == "shear":
        return _shear_cli().run(ns, argv)
    if ns.command == "import":
        from fricstab.cli import imports as import_cli
        return import_cli.run(ns, argv)
    return _cmd_verify(ns) if ns.command == "verify" else ns.run(ns, _main)   # warmup


def _one_line(exc):
    text = " ".join(str(exc).split())
    return text if len(text) <= 500 else text[:497] + "..."


def _resume_hint(ns):
    out = getattr(ns, "out", None)
    if out is not None and getattr(ns, "checkpoint_every", "n/a") != "n/a":
        return f"; checkpoints kept in {out}: rerun the same command with --resume"
    if out is not None and hasattr(ns, "resume"):   # ensembles: chain waves
        return f"; stored members kept in {out}: rerun the same command with --resume"
    return ""


def _log_internal(ns, exc):
    """Write the traceback to ``<out>/fricstab-error.log`` (else a temporary file)."""
    text = "".join(traceback.format_exception(exc))
    out = getattr(ns, "out", None) if ns is not None else None
    candidates = ([Path(out).expanduser()] if out is not None else []) + \
        [Path(tempfile.gettempdir())]
    for folder in candidates:
        try:
            if folder.is_dir():
                path = folder / ("fricstab-error.log" if folder != candidates[-1]
                                 else f"fricstab-error-{os.getpid()}.log")
                path.write_text(text)
                return path
        except OSError:
            continue
    return None


def _stdout_closed():
    """True when stdout's reader is gone (``| head``); then fd 1 goes to /dev/null.

    So that neither this run nor the interpreter's last flush prints
    "Broken pipe": a closed pipe ends the output quietly, as in other Unix tools.
    """
    try:
        sys.stdout.flush()
        import select
        poll = select.poll()
        poll.register(sys.stdout.fileno(), select.POLLOUT)
        if not any(ev & select.POLLERR for _, ev in poll.poll(0)):
            return False
    except BrokenPipeError:
        pass
    except (OSError, ValueError, AttributeError):
        return False
    try:
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        os.close(devnull)
    except (OSError, ValueError):
        pass
    return True


def main(argv=None):
    """Entry point; returns the exit status (see the module docstring).

    Warnings (NumPy, SciPy, ours) do not reach stderr one by one: they are
    collected, stored in the record of the run (``warnings``) and summed up in
    one line at the end.
    """
    problem = _THREAD_ENV_PROBLEM or _check_threading_layer()
    if problem:   # before any work: numba's threads cannot start as asked
        print(f"fricstab: error: {problem}", file=sys.stderr)
        return EXIT_USAGE
    from fricstab import progress, signals
    from fricstab.io.results import WARNINGS, forget_all, release_all
    WARNINGS.clear()
    forget_all()
    try:
        with signals.interruptible(), warnings.catch_warnings(), progress.for_command(argv):
            warnings.simplefilter("always")
            warnings.showwarning = _collect_warning
            return _main(argv)
    finally:
        release_all()
        forget_all()
        _stdout_closed()   # a reader gone after the last line: quiet, the status kept
        if WARNINGS:
            first = WARNINGS[0]
            more = f" and {len(WARNINGS) - 1} more" if len(WARNINGS) > 1 else ""
            print(f"fricstab: note: {first['category']}: {_one_line(first['message'])}{more} "
                  "(listed under 'warnings' in the run's record)", file=sys.stderr)


def _collect_warning(message, category, filename, lineno, file=None, line=None):
    """``warnings.showwarning`` of the command line: into the records, not onto stderr."""
    from fricstab.io.results import note_warning
    note_warning(category.__name__, str(message), f"{Path(filename).name}:{lineno}")


def _main(argv):
    argv = list(sys.argv[1:] if argv is None else argv)
    ns = None
    debug = "--debug" in argv or os.environ.get("FRICSTAB_DEBUG") == "1"
    from fricstab.signals import Interrupted
    try:
        ns = _parser().parse_args(argv)
        if ns.threads is not None:
            from fricstab.engine.parallel import set_threads
            set_threads(ns.threads)
        quiet = getattr(ns, "quiet", False)
        if quiet:
            ns.no_progress = True
        with contextlib.redirect_stdout(io.StringIO()) if quiet else contextlib.nullcontext():
            return _dispatch(ns, argv)
    except SystemExit as exc:   # --help, --version
        return exc.code if isinstance(exc.code, int) else 0
    except (UsageError, ParameterError) as exc:
        from fricstab.io.results import abandon_all
        abandon_all()   # a refused run leaves nothing new in --out
        print(f"fricstab: error: {_one_line(exc)}", file=sys.stderr)
        return EXIT_USAGE
    except KeyboardInterrupt:
        print(f"fricstab: interrupted{_resume_hint(ns)}", file=sys.stderr)
        return EXIT_INTERRUPTED
    except Interrupted as exc:
        print(f"fricstab: {exc}{_resume_hint(ns)}", file=sys.stderr)
        return exc.exit_code
    except MemoryError:
        print("fricstab: error: out of memory; reduce the system size", file=sys.stderr)
        return EXIT_NUMERICAL
    except BrokenPipeError as exc:
        if _stdout_closed():   # `fricstab ... | head -1`: the reader has what it wanted
            return EXIT_OK
        print(f"fricstab: error: {_one_line(exc.strerror or exc)}", file=sys.stderr)
        return EXIT_OS
    except OSError as exc:
        name = f": {exc.filename}" if exc.filename else ""
        print(f"fricstab: error: {_one_line(exc.strerror or exc)}{name}", file=sys.stderr)
        return EXIT_OS
    except Exception as exc:
        from fricstab.errors import ConvergenceError, NumericalError
        if isinstance(exc, NumericalError):
            print(f"fricstab: error: numerical failure: {_one_line(exc)}{_resume_hint(ns)}",
                  file=sys.stderr)
            return EXIT_NUMERICAL
        if isinstance(exc, ConvergenceError):
            print(f"fricstab: error: no convergence: {_one_line(exc)}{_resume_hint(ns)}",
                  file=sys.stderr)
            return EXIT_NUMERICAL
        if debug:
            traceback.print_exception(exc, file=sys.stderr)
            return EXIT_INTERNAL
        log = _log_internal(ns, exc)
        where = f"traceback in {log}" if log else "rerun with --debug for the traceback"
        print(f"fricstab: internal error: {type(exc).__name__}: {_one_line(exc)[:200]} "
              f"({where}; please report it)", file=sys.stderr)
        return EXIT_INTERNAL


if __name__ == "__main__":
    sys.exit(main())
