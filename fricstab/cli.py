"""The ``fricstab`` command.

Subcommands
-----------
``fricstab laws``
    List the contact laws with their coordinates and forces.
``fricstab verify --law NAME|all --cases N --seed S --json PATH``
    Prove the generated Jacobian blocks against complex-step, central and
    50-digit differences and a Taylor test (:mod:`fricstab.verify`), print a
    table and write a JSON list with one object per law.
``fricstab chain ramp|jacobian ...``
    The chain of disks of Charan et al. (:mod:`fricstab.chain_cli`).
``fricstab packing make|rigidity|dos ...``
    Disk packings of Ishima et al.: rigidity and DOS (:mod:`fricstab.packing_cli`).

Bad input exits with status 2 and one line naming the parameter; no
traceback reaches the user.
"""

import argparse
import json
import math
import platform
import sys
import time
from pathlib import Path

from fricstab import __version__
from fricstab.laws import LAW_NAMES, ParameterError, get_law

__all__ = ["main"]


class UsageError(Exception):
    """Bad command-line input (exit status 2)."""


class _Parser(argparse.ArgumentParser):
    def error(self, message):
        raise UsageError(message)


def _int_at_least(minimum):
    def parse(text):
        try:
            value = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"must be an integer, got {text!r}") from None
        if value < minimum:
            raise argparse.ArgumentTypeError(f"must be >= {minimum}, got {text!r}")
        return value
    return parse


def _positive_float():
    def parse(text):
        try:
            value = float(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"must be a number, got {text!r}") from None
        if not math.isfinite(value) or value <= 0:
            raise argparse.ArgumentTypeError(f"must be a finite number > 0, got {text!r}")
        return value
    return parse


def _law_list(text):
    if text == "all":
        return list(LAW_NAMES)
    names = [t.strip() for t in text.split(",") if t.strip()]
    if not names:
        raise argparse.ArgumentTypeError("must name a law or 'all'")
    for n in names:
        if n not in LAW_NAMES:
            raise argparse.ArgumentTypeError(
                f"unknown law {n!r}; known laws: {', '.join(LAW_NAMES)}, all")
    return names


def _parser():
    p = _Parser(prog="fricstab", description="Verified contact laws of frictional disks.")
    p.add_argument("--version", action="version", version=f"fricstab {__version__}")
    sub = p.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)
    sub.required = True
    sub.add_parser("laws", help="list the contact laws")
    v = sub.add_parser("verify", help="prove the generated Jacobians (see README)")
    v.add_argument("--law", type=_law_list, default=list(LAW_NAMES),
                   help="law name, comma-separated names, or 'all' (default: all)")
    v.add_argument("--cases", type=_int_at_least(1), default=200,
                   help="configurations per law (default: 200)")
    v.add_argument("--seed", type=_int_at_least(0), default=0,
                   help="seed of the configuration sampler (default: 0)")
    v.add_argument("--json", type=Path, default=None, metavar="PATH",
                   help="write the JSON report here")
    v.add_argument("--radius", type=_positive_float(), default=0.5,
                   help="radius R of particle i (default: 0.5)")
    v.add_argument("--kn", type=_positive_float(), default=1.0,
                   help="normal stiffness k_n (default: 1)")
    v.add_argument("--mu-range", type=_positive_float(), nargs=2,
                   metavar=("LO", "HI"), default=None, help="friction coefficient range "
                   "(default: 0.1 100)")
    v.add_argument("--kt-ratio-range", type=_positive_float(), nargs=2,
                   metavar=("LO", "HI"), default=None, help="k_t/k_n range (default: 1e-10 10)")
    v.add_argument("--delta-range", type=_positive_float(), nargs=2,
                   metavar=("LO", "HI"), default=None, help="overlap/R range (default: 1e-12 0.1)")
    v.add_argument("--radius-ratio-range", type=_positive_float(),
                   nargs=2, metavar=("LO", "HI"), default=None,
                   help="R_j/R_i range (default: 1 1.4)")
    v.add_argument("--no-progress", action="store_true", help="no progress bar")
    from fricstab import chain_cli, packing_cli
    chain_cli.add_parser(sub, _Parser, _positive_float)
    packing_cli.add_parser(sub, _Parser, _positive_float)
    return p


def _ranges(ns):
    from fricstab.verify import EXTREMES
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
    for name in LAW_NAMES:
        law = get_law(name)
        print(f"{name:12s} {law.kind:4s}  coords ({', '.join(law.coords)})  "
              f"forces ({', '.join(law.outputs)})")
    return 0


def _fmt(x):
    return "   null" if x is None else f"{x:8.1e}"


def _cmd_verify(ns):
    import numpy as np
    import numba
    import scipy
    from tqdm import tqdm

    from fricstab.verify import sample_cases, verify_law

    ranges = _ranges(ns)
    if ns.json is not None:
        parent = ns.json.expanduser().resolve().parent
        if not parent.is_dir():
            raise UsageError(f"--json: directory {parent} does not exist")
    cases = sample_cases(ns.cases, ns.seed, ranges=ranges)
    results = []
    bar = tqdm(total=ns.cases * len(ns.law), desc="verify", unit="case",
               disable=ns.no_progress or None, file=sys.stderr)
    for name in ns.law:
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
    print(f"{'law':12s} {'cases':>6s} {'cplx-step':>9s} {'(unexpl.)':>9s} {'mp50':>9s} "
          f"{'(unexpl.)':>9s} {'central':>9s} {'>1e-6':>6s} {'(unexpl.)':>9s} "
          f"{'taylor':>13s} {'(failed)':>8s} {'nonfinite':>9s}")
    for r in results:
        slope = (f"{r['taylor_slope_min']:.3f}-{r['taylor_slope_max']:.3f}"
                 if r["taylor_slope_min"] is not None else "n/a")
        print(f"{r['law']:12s} {r['cases']:6d} {_fmt(r['max_rel_err_complex_step'])} "
              f"{r['complex_step_unexplained_cases']:9d} {_fmt(r['max_rel_err_central_mp50'])} "
              f"{r['central_mp50_unexplained_cases']:9d} {_fmt(r['max_rel_err_central'])} "
              f"{r['central_cases_above_bound']:6d} {r['central_unexplained_cases']:9d} "
              f"{slope:>13s} {r['taylor_failed_cases']:8d} {r['nonfinite']:9d}")
    if ns.json is not None:
        ns.json.write_text(json.dumps(results, indent=2) + "\n")
        print(f"wrote {ns.json}")
    ok = all(r["complex_step_unexplained_cases"] == 0 and r["central_unexplained_cases"] == 0
             and r["central_mp50_unexplained_cases"] == 0 and r["taylor_failed_cases"] == 0
             and r["nonfinite"] == 0 for r in results)
    if not ok:
        print("fricstab: verification FAILED (see the table)", file=sys.stderr)
    return 0 if ok else 3


def main(argv=None):
    """Entry point; returns the exit status (0 ok, 2 bad input, 3 failed proof)."""
    try:
        ns = _parser().parse_args(argv)
        if ns.command == "laws":
            return _cmd_laws()
        if ns.command == "chain":
            from fricstab import chain_cli
            return chain_cli.run(ns)
        if ns.command == "packing":
            from fricstab import packing_cli
            return packing_cli.run(ns, sys.argv[1:] if argv is None else argv)
        return _cmd_verify(ns)
    except (UsageError, ParameterError) as exc:
        print(f"fricstab: error: {exc}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("fricstab: interrupted", file=sys.stderr)
        return 130
    except OSError as exc:
        print(f"fricstab: error: {exc.strerror or exc}: {exc.filename or ''}".rstrip(": "),
              file=sys.stderr)
        return 1


if __name__ == "__main__":
    sys.exit(main())
