"""Regenerate every benchmark and speed/accuracy table into validation/benchmarks/.

    python validation/benchmarks/run_all.py            # full: about 25 min on 2 quiet cores
    python validation/benchmarks/run_all.py --quick    # about 3 min; existing studies copied
    python validation/benchmarks/run_all.py --only lammps   # one entry (see --list)

Benchmarks of this folder (``bench_*.py``): LAMMPS comparison (skipped with a
note when the optional ``lammps[mpi]`` is not installed), our kernels, the
eigen-solvers, and the knobs no other study covers (DEM time step, system
size).  The knob studies that already exist in ``validation/`` are reused, not
duplicated: in the full run they are rerun (their own scripts, at the tier
whose table is committed) and their tables and figures copied here as
``study_<name>.md``; with ``--quick`` the committed tables are copied as they
are (rerunning a study in its quick tier would overwrite its committed
full-tier table).  ``index.md`` lists every knob and the table that holds its
trade, with the stamp and wall time of each entry.
"""

import argparse
import os
import shutil
import subprocess
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _common import HERE, ROOT, stamp  # noqa: E402

VAL = ROOT / "validation"

# name -> (script, full-run arguments, files it writes under validation/)
STUDIES = {
    "fd_tradeoff": ("fd_tradeoff.py", [], ["fd_tradeoff.md", "fd_tradeoff.png"]),
    "chain_tradeoffs": ("chain_tradeoffs.py", [], ["chain_tradeoffs.md"]),
    "packing_knobs": ("packing_knobs.py", [], ["packing_knobs.md"]),
    "packing_rigidity": ("packing_rigidity.py", ["--tier", "medium"],
                         ["packing_rigidity.md", "packing_rigidity.png"]),
    "packing_dos": ("packing_dos.py", ["--tier", "quick"],
                    ["packing_dos_quick.md", "packing_dos_quick.png"]),
}

BENCHES = {
    "lammps": "bench_lammps.py",
    "kernels": "bench_kernels.py",
    "eigen": "bench_eigen.py",
    "knobs": "bench_knobs.py",
    "meetings": "bench_meetings.py",
}

# knob -> where its trade table is (file under validation/benchmarks/, section)
KNOBS = [
    ("finite-difference scheme and step", "study_fd_tradeoff.md", "all sections"),
    ("DEM time step against energy drift", "knobs_dt.md", ""),
    ("time step against the growth rate of the unstable mode (chain)",
     "study_chain_tradeoffs.md", "Verlet time step against the growth rate"),
    ("time step against the wave speeds (chain)", "study_chain_tradeoffs.md",
     "Verlet time step against the wave speeds"),
    ("relaxation tolerance against G", "study_packing_knobs.md", "Force thresholds"),
    ("compression increment against G and cost", "study_packing_knobs.md",
     "Compression increment dphi"),
    ("strain step against G", "study_packing_rigidity.md", "dgamma independence"),
    ("ramp step and bisection tolerance against onset accuracy and cost",
     "study_chain_tradeoffs.md", "Ramp step and bisection tolerance"),
    ("DOS route against DOS accuracy", "study_packing_dos.md", "Spectrum routes"),
    ("eigen-solver route against time and error", "eigen.md", ""),
    ("system size against cost (scaling exponent)", "knobs_size.md", ""),
    ("kernel form (generated numba against lambdify), compile cache", "kernels.md", ""),
    ("code: fricstab DEM against LAMMPS", "lammps.md",
     "forces first: lammps_forces.md, lammps_forces_scenes.md"),
    ("threads: 1 against 2 per scene", "engine.md", ""),
    ("threads: a meeting as a parallel region against a barrier", "meetings.md", ""),
    ("Lee & Hurley width solve and logs: ns per contact", "lee_hurley.md", ""),
    ("slip spectra: soft end (k softest) against dense", "slip_spectra.md", ""),
]


def _run(cmd, log):
    t0 = time.perf_counter()
    with open(log, "w") as fh:
        rc = subprocess.run(cmd, cwd=str(ROOT), stdout=fh, stderr=subprocess.STDOUT,
                            env=dict(os.environ, PYTHONPATH=str(ROOT))).returncode
    return rc, time.perf_counter() - t0


def _copy_study(name, files):
    for f in files:
        src = VAL / f
        if not src.exists():
            continue
        ext = src.suffix
        dst = HERE / f"study_{name}{ext}"
        tmp = HERE / f".study_{name}.tmp{ext}"
        if ext == ".md":
            text = src.read_text()
            tmp.write_text(f"<!-- copied from validation/{f} by run_all.py -->\n{text}")
        else:
            shutil.copyfile(src, tmp)
        os.replace(tmp, dst)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--only", choices=sorted(BENCHES) + sorted(STUDIES), default=None)
    ap.add_argument("--list", action="store_true", help="list the entries and exit")
    ns = ap.parse_args(argv)
    if ns.list:
        print("benchmarks:", ", ".join(BENCHES))
        print("studies:", ", ".join(STUDIES))
        return 0
    quick = ["--quick"] if ns.quick else []
    logs = HERE / "logs"
    logs.mkdir(exist_ok=True)
    status, t_all = [], time.perf_counter()
    for name, script in BENCHES.items():
        if ns.only and ns.only != name:
            continue
        print(f"[run_all] {name} ...", flush=True)
        rc, sec = _run([sys.executable, str(HERE / script), *quick], logs / f"{name}.log")
        note = {0: "ok", 2: "skipped: optional dependency missing (see log)",
                3: "FAILED: disagreement (see log)"}.get(rc, f"FAILED rc {rc} (see log)")
        status.append((name, f"`validation/benchmarks/{script}{' --quick' if quick else ''}`",
                       note, f"{sec:.0f}"))
    for name, (script, args, files) in STUDIES.items():
        if ns.only and ns.only != name:
            continue
        if ns.quick:
            _copy_study(name, files)
            status.append((name, f"copied from `validation/{files[0]}` (not rerun)", "ok", "0"))
            continue
        print(f"[run_all] study {name} ...", flush=True)
        rc, sec = _run([sys.executable, str(VAL / script), *args], logs / f"study_{name}.log")
        if rc == 0:
            _copy_study(name, files)
        status.append((name, f"`validation/{script}{' ' + ' '.join(args) if args else ''}`",
                       "ok" if rc == 0 else f"FAILED rc {rc} (see log)", f"{sec:.0f}"))
    lines = ["# Benchmarks and the speed/accuracy trade of every knob", "",
             f"Regenerated by `python validation/benchmarks/run_all.py"
             f"{' --quick' if ns.quick else ''}{' --only ' + ns.only if ns.only else ''}` "
             f"in {time.perf_counter() - t_all:.0f} s; {stamp()}.", "",
             "## Knobs and where their trade is measured", "",
             "| knob | table | section |", "|---|---|---|"]
    lines += [f"| {k} | [{f}]({f}) | {s} |" for k, f, s in KNOBS]
    lines += ["", "## This run", "", "| entry | command | status | s |", "|---|---|---|---|"]
    lines += [f"| {a} | {b} | {c} | {d} |" for a, b, c, d in status]
    index = HERE / ("index.md" if not ns.only else f"index_{ns.only}.md")
    tmp = index.with_suffix(".md.tmp")
    tmp.write_text("\n".join(lines) + "\n")
    os.replace(tmp, index)
    print("\n".join(lines))
    return 0 if all(s[2].startswith(("ok", "skipped")) for s in status) else 3


if __name__ == "__main__":
    sys.exit(main())
