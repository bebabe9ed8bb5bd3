"""Cold and warm start of ``fricstab chain ramp``: is numba's on-disk cache effective?

Cold: every numba cache file of the package removed first (a fresh install);
warm: the same command again (the cache written by the cold run).  Wall time
of the whole command, ``--repeats`` times each, as subprocesses.

``python validation/benchmarks/bench_startup.py [--label TEXT]`` appends a row
to startup.md (the label says which code: before/after a change).
"""

import argparse
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _common import ROOT, stamp  # noqa: E402

HERE = Path(__file__).resolve().parent


def clear_cache():
    n = 0
    for p in (ROOT / "fricstab").rglob("__pycache__/*"):
        if p.suffix in (".nbi", ".nbc"):
            p.unlink()
            n += 1
    return n


def timed(args):
    with tempfile.TemporaryDirectory() as d:
        t = time.perf_counter()
        subprocess.run([sys.executable, "-m", "fricstab", *args, "--out", str(Path(d) / "o")],
                       check=True, capture_output=True)
        return time.perf_counter() - t


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--label", default="")
    ns = ap.parse_args()
    args = ["chain", "ramp", "--no-progress"]
    cold, warm = [], []
    for _ in range(ns.repeats):
        clear_cache()
        cold.append(timed(args))
        warm.append(timed(args))
    row = (f"| {ns.label} | {statistics.median(cold):.1f} | {statistics.median(warm):.2f} | "
           f"{stamp()} |")
    path = HERE / "startup.md"
    if not path.exists():
        path.write_text("# Cold and warm start of `fricstab chain ramp`\n\n"
                        "Wall time of the whole command (s), median of "
                        f"{ns.repeats}; cold: numba cache cleared first.\n\n"
                        "| code | cold (s) | warm (s) | machine |\n|---|---|---|---|\n")
    with open(path, "a") as fh:
        fh.write(row + "\n")
    print(row)


if __name__ == "__main__":
    main()
