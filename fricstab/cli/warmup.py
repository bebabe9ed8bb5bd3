"""``fricstab warmup``: compile every numba kernel the commands use, once.

numba compiles a kernel on its first call and keeps the machine code in its
on-disk cache (``__pycache__`` beside the sources, or ``NUMBA_CACHE_DIR``), so
the first run of each command pays the compilation (minutes on a loaded
2-core machine; measured costs in ``docs/concepts/performance.md``).
``warmup`` runs each command group on a tiny input in a temporary folder,
quietly (their stderr shown only if one fails), and prints one line per group with the time it took; a second
``warmup`` only loads the cache.  The cache is dropped when a source the
kernels depend on changes (:func:`fricstab._numba.purge_stale_cache`).
"""

import contextlib
import io
import sys
import tempfile
import time
from pathlib import Path

__all__ = ["GROUPS", "add_parser", "run"]

#: (group, command line on a tiny input); ``--out`` and ``--quiet`` are added.
GROUPS = (
    ("contact laws (chain ramp)", ["chain", "ramp", "--fx-max", "0.002", "--step", "1e-3"]),
    ("chain dynamics", ["chain", "dynamics", "--fx", "0.001", "--duration", "2"]),
    ("packing", ["packing", "make", "--n", "16", "--phi", "0.85"]),
    ("plane shear", ["shear", "run", "--n", "40", "--strain", "0.002", "--dgamma", "1e-4"]),
)


def add_parser(sub):
    """Register ``fricstab warmup`` on the subparsers ``sub``."""
    w = sub.add_parser("warmup", help="compile every numba kernel once (first-run cost; "
                                      "see docs/concepts/performance.md)")
    w.add_argument("--no-progress", action="store_true",
                   help="no heartbeat lines on stderr while a group compiles")
    w.add_argument("--quiet", action="store_true", help="print nothing on success")
    w.set_defaults(run=run)   # called by fricstab.cli._dispatch


def run(ns, main):
    """Run each group of :data:`GROUPS` through ``main`` (the CLI's ``_main``); 0 when all
    succeed, else the first failing group's exit status (its error line printed)."""
    from fricstab import progress
    from fricstab.cli import _shear_cli
    total = time.perf_counter()
    with tempfile.TemporaryDirectory(prefix="fricstab-warmup-") as tmp:
        for k, (name, argv) in enumerate(GROUPS):
            if argv[0] == "shear" and _shear_cli() is None:
                print(f"warmup: {name}: skipped (not installed)")
                continue
            t0 = time.perf_counter()
            said = io.StringIO()   # the tiny runs' warnings (a cell of 40 disks) are noise
            with progress.heartbeat(f"warmup: {name}", not ns.no_progress), \
                    contextlib.redirect_stderr(said):
                status = main([*argv, "--out", str(Path(tmp) / f"g{k}"), "--quiet"])
            if status != 0:
                sys.stderr.write(said.getvalue())
                print(f"fricstab: error: warmup: {name} failed (exit status {status})",
                      file=sys.stderr)
                return status
            print(f"warmup: {name}: {time.perf_counter() - t0:.1f} s", flush=True)
    print(f"warmup: done in {time.perf_counter() - total:.1f} s; numba's cache is warm")
    return 0
