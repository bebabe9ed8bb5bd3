"""Shared helpers of the benchmark scripts: machine stamp, timing, tables.

Every table row carries the stamp of :func:`machine` (platform, CPU model,
cores, versions of Python, NumPy, SciPy, numba, the fricstab git revision,
LAMMPS where used, and the date), so a table read out of context still says
where and when its numbers were measured.
"""

import os
import platform
import statistics
import subprocess
import sys
import time
from functools import lru_cache
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent.parent
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))
if str(ROOT / "validation") not in sys.path:
    sys.path.insert(0, str(ROOT / "validation"))

import numba  # noqa: E402
import numpy as np  # noqa: E402
import scipy  # noqa: E402

__all__ = ["HERE", "ROOT", "cpu_model", "machine", "median_time", "save_figure", "stamp",
           "write_table"]


def cpu_model():
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or "unknown CPU"


@lru_cache(maxsize=1)
def machine():
    """Machine and software stamp (a dict of strings)."""
    try:
        rev = subprocess.run(["git", "-C", str(ROOT), "rev-parse", "--short", "HEAD"],
                             capture_output=True, text=True, timeout=10).stdout.strip()
        dirty = subprocess.run(["git", "-C", str(ROOT), "status", "--porcelain",
                                "--untracked-files=no"],
                               capture_output=True, text=True, timeout=10).stdout.strip()
        rev = (rev or "unknown") + ("+dirty" if dirty else "")
    except (OSError, subprocess.SubprocessError):
        rev = "unknown"
    return {"platform": f"{platform.system()} {platform.machine()}", "cpu": cpu_model(),
            "cores": str(os.cpu_count()), "python": platform.python_version(),
            "numpy": np.__version__, "scipy": scipy.__version__, "numba": numba.__version__,
            "fricstab": rev, "date": time.strftime("%Y-%m-%d")}


def stamp(extra=None):
    """One-line stamp for a table row: ``cpu/cores, versions, rev, date``."""
    m = dict(machine())
    if extra:
        m.update(extra)
    keys = ["cpu", "cores", "python", "numpy", "scipy", "numba", "fricstab", "date"]
    keys += [k for k in (extra or {}) if k not in keys]
    return "; ".join(f"{k} {m[k]}" for k in keys)


def median_time(fn, repeats):
    """Median wall time of ``repeats`` calls of ``fn()`` (seconds) and all times."""
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return statistics.median(times), times


def write_table(name, title, intro, header, rows, notes=(), extra_stamp=None):
    """Write ``HERE/name.md``: a markdown table whose rows end with the machine stamp."""
    s = stamp(extra_stamp)
    lines = [f"# {title}", "", *intro, "", "| " + " | ".join(header) + " | machine |",
             "|" + "---|" * (len(header) + 1)]
    for r in rows:
        lines.append("| " + " | ".join(str(c) for c in r) + f" | {s} |")
    if notes:
        lines += ["", *notes]
    path = HERE / f"{name}.md"
    tmp = path.with_suffix(".md.tmp")
    tmp.write_text("\n".join(lines) + "\n")
    os.replace(tmp, path)  # atomic: a reader never sees half a table
    print("\n".join(lines), flush=True)
    return path


def save_figure(fig, name):
    """Save ``fig`` as ``HERE/name.png`` atomically and close it."""
    import matplotlib.pyplot as plt

    path = HERE / f"{name}.png"
    tmp = HERE / f".{name}.tmp.png"
    fig.savefig(tmp, dpi=120, bbox_inches="tight")
    os.replace(tmp, path)
    plt.close(fig)
    return path
