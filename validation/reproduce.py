"""Regenerate the claims of ``validation/RESULTS.md`` and check that they are fresh.

    python validation/reproduce.py --list                  # every claim: tier, record, fresh?
    python validation/reproduce.py --claim NAME [NAME ...] # regenerate claims (or jobs)
    python validation/reproduce.py --tier seconds|minutes|hours [--only-stale] [--resume]
    python validation/reproduce.py --stale                 # claims whose code changed (exit 1)
    python validation/reproduce.py --check                 # what CI checks (exit 1 on a problem)
    python validation/reproduce.py --write                 # render RESULTS.md and marked blocks

A tier includes the cheaper ones (``--tier minutes`` is every claim of the
seconds and minutes tiers: under an hour on two cores).  Each job runs in a
process of its own, so that its record names exactly the code it imported
(``validation/claims/fingerprint.py``); each record is written as soon as its
job ends, so an interrupted tier loses at most the job it was in, and
``--resume`` goes on with the jobs the interrupted run had not finished.
After regenerating, the summary names every claim whose value moved beyond
its stated tolerance, or whose verdict against the paper changed, and
RESULTS.md and the marked blocks are rewritten.
"""

import argparse
import json
import os
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
sys.path.insert(0, str(HERE.parent))

from claims import all_claims, jobs, records, render  # noqa: E402
from claims.core import TIERS  # noqa: E402
from claims.fingerprint import changes  # noqa: E402
from claims.runner import recompute, spawn, values_of, work  # noqa: E402

PROGRESS = records.RECORDS / ".progress.json"


def stale_jobs(root=None):
    """job -> the paths whose code changed since it was recorded (or 'never recorded');
    ``root``: the checkout to compare with (default this one)."""
    out = {}
    for job in jobs():
        rec = records.load(job)
        if rec is None:
            out[job] = ["never recorded"]
            continue
        ch = changes(rec["fingerprint"]) if root is None else changes(rec["fingerprint"], root)
        if ch:
            out[job] = ch
    return out


def stale_messages(root=None):
    """One line per stale claim past the seconds tier (CI fails on any): the claims, the
    changed code, and the command that regenerates them."""
    by_job, out = jobs(), []
    for job, ch in stale_jobs(root).items():
        c = by_job[job][0]
        if c.tier != "seconds" and ch != ["never recorded"]:
            out.append(f"stale: {', '.join(x.name for x in by_job[job])} (code changed: "
                       f"{', '.join(ch[:4])}); regenerate: python validation/reproduce.py "
                       f"--claim {c.name}")
    return out


def _select(ns):
    by_job = jobs(strict=not ns.claim)
    if ns.claim:
        names = {c.name: c.job_name for cs in by_job.values() for c in cs}
        sel = []
        for n in ns.claim:
            job = names.get(n, n if n in by_job else None)
            if job is None:
                sys.exit(f"reproduce: error: no claim or job named {n!r} (see --list)")
            if job not in sel:
                sel.append(job)
        return sel
    limit = TIERS.index(ns.tier)
    sel = [j for j, cs in by_job.items() if TIERS.index(cs[0].tier) <= limit]
    if ns.only_stale:
        st = stale_jobs()
        sel = [j for j in sel if j in st]
    return sel


THREAD_VARS = ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "NUMBA_NUM_THREADS")


def oversubscribed(load=None, cores=None, env=None):
    """A warning when other processes already load the machine and this one's BLAS and numba
    may start a thread per core: threads that wait on each other spin, and a job's measured
    cost is then several times its cost (precursors.dynamics: 6x, 400 s a run against 60 s
    with one thread each, on 2 cores beside two single-threaded runs).  None when fine."""
    load = os.getloadavg()[0] if load is None else load
    cores = (os.cpu_count() or 1) if cores is None else cores
    env = os.environ if env is None else env
    multi = [v for v in THREAD_VARS if env.get(v) != "1"]
    if load < 0.5 or not multi or cores == 1:
        return None
    return (f"the machine is busy (load {load:.1f} on {cores} cores) and {', '.join(multi)} "
            "not 1: oversubscribed threads spin; for a job beside other processes set "
            + " ".join(f"{v}=1" for v in THREAD_VARS))


def regenerate(selected, resume=False):
    """Run the jobs, one process each; returns (summary lines, failures)."""
    done = []
    if resume:
        if not PROGRESS.exists():
            sys.exit("reproduce: error: nothing to resume (no interrupted run recorded)")
        prog = json.loads(PROGRESS.read_text())
        selected, done = prog["jobs"], prog["done"]
    PROGRESS.write_text(json.dumps({"jobs": selected, "done": done}))
    by_job = jobs(strict=False)
    todo = [j for j in selected if j not in done]
    est = sum((records.load(j) or {}).get("wall_s", 0.0) for j in todo)
    print(f"reproduce: {len(todo)} job(s) to run ({len(done)} done before), last recorded "
          f"compute {est:.0f} s", file=sys.stderr)
    busy = oversubscribed()
    if busy:
        print(f"reproduce: warning: {busy}", file=sys.stderr)
    moved, failed, t_all = [], [], time.perf_counter()
    for k, job in enumerate(todo, 1):
        old = records.load(job)
        last = f", last time {old['wall_s']:.0f} s" if old else ""
        print(f"[{k}/{len(todo)}] {job} ({by_job[job][0].tier}{last}) ...", file=sys.stderr,
              flush=True)
        try:
            new, wall = spawn(job)
        except RuntimeError as exc:
            failed.append(str(exc))
            print(f"    FAILED: {exc}", file=sys.stderr)
            continue
        print(f"    done in {wall:.0f} s", file=sys.stderr, flush=True)
        done.append(job)
        PROGRESS.write_text(json.dumps({"jobs": selected, "done": done}))
        if old is None:
            moved.append(f"{job}: first record")
            continue
        ov, nv = values_of(old), values_of(new)
        for c in by_job[job]:
            try:      # an old record of another shape (a law added since) cannot be compared
                ok, text = c.check(ov, nv)
                va = c.judge(ov)
            except (KeyError, IndexError, TypeError) as exc:
                moved.append(f"{c.name}: the old record cannot be compared ({type(exc).__name__}: "
                             f"{exc}); new verdict {c.judge(nv).label}")
                continue
            if not ok:
                moved.append(f"{c.name}: moved beyond its tolerance: {text}")
            vb = c.judge(nv)
            if va.label != vb.label:
                moved.append(f"{c.name}: verdict {va.label} -> {vb.label} ({vb.detail})")
    if not failed:
        PROGRESS.unlink(missing_ok=True)
    print(f"reproduce: {len(done)} of {len(selected)} job(s) recorded in "
          f"{time.perf_counter() - t_all:.0f} s", file=sys.stderr)
    return moved, failed


def check():
    """What CI checks: records sound, pages as rendered, nothing stale past the seconds
    tier, and the seconds tier recomputed within its tolerances.  Returns problems."""
    problems = []
    for job, cs in jobs().items():
        rec = records.load(job)
        if rec is None:
            if cs[0].tier != "hours":      # an hours claim may wait for its run (shown so)
                problems.append(f"{job}: never recorded; run python validation/reproduce.py "
                                f"--claim {cs[0].name}")
            continue
        problems += records.verify(rec)
    problems += stale_messages()
    problems += [f"{p} differs from what the registry writes: python validation/reproduce.py "
                 "--write" for p in render.differences()]
    for job, cs in jobs().items():
        if cs[0].tier != "seconds" or records.load(job) is None:
            continue
        rec = records.load(job)
        old = values_of(rec)
        new = recompute(cs[0], keep=rec.get("outputs", {}))
        for c in cs:
            ok, text = c.check(old, new)
            if not ok:
                problems.append(f"{c.name}: recomputed value moved beyond its tolerance: {text}")
    return problems


def listing():
    st = stale_jobs()
    for c in all_claims():
        rec = records.load(c.job_name)
        state = ("never recorded" if rec is None else
                 f"recorded {rec['revision']}{'+' if rec['dirty'] else ''} {rec['date']}, "
                 f"{rec['wall_s']:.0f} s" + (", STALE" if c.job_name in st else ""))
        print(f"{c.name:36s} {c.tier:8s} {state}")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--claim", nargs="+", metavar="NAME")
    ap.add_argument("--tier", choices=TIERS + ("quick",),
                    help="a tier and the cheaper ones ('quick' is 'seconds')")
    ap.add_argument("--only-stale", action="store_true", help="with --tier: stale claims only")
    ap.add_argument("--resume", action="store_true", help="go on with an interrupted run")
    ap.add_argument("--stale", action="store_true", help="list stale claims; exit 1 if any")
    ap.add_argument("--check", action="store_true", help="what CI checks")
    ap.add_argument("--write", action="store_true", help="render RESULTS.md and blocks")
    ap.add_argument("--list", action="store_true")
    ap.add_argument("--worker", metavar="JOB", help=argparse.SUPPRESS)
    ns = ap.parse_args(argv)
    if ns.tier == "quick":
        ns.tier = "seconds"
    if ns.worker:
        work(ns.worker)
        return 0
    if ns.list:
        listing()
        return 0
    if ns.stale:
        st = stale_jobs()
        for job, ch in st.items():
            print(f"{job}: {', '.join(ch)}")
        return 1 if st else 0
    if ns.check:
        problems = check()
        for p in problems:
            print(p)
        return 1 if problems else 0
    if ns.claim or ns.tier or ns.resume:
        selected = [] if ns.resume else _select(ns)
        moved, failed = regenerate(selected, resume=ns.resume)
        # rendered in a fresh process: a long run must not write the pages with the
        # section modules it imported hours ago (claims since edited)
        import subprocess
        r = subprocess.run([sys.executable, str(Path(__file__).resolve()), "--write"],
                           capture_output=True, text=True)
        changed = [Path(x.split(" ", 1)[1]) for x in r.stdout.splitlines()
                   if x.startswith("wrote ")]
        if r.returncode != 0:
            print(f"reproduce: RESULTS.md not rewritten ({r.stderr.strip().splitlines()[-1:]}); "
                  "run --write when every section imports", file=sys.stderr)
        for m in moved:
            print(f"moved: {m}")
        for f in failed:
            print(f"failed: {f}")
        print(f"reproduce: rewrote {', '.join(p.name for p in changed) or 'nothing'}",
              file=sys.stderr)
        return 1 if failed else 0
    if ns.write:
        for p in render.write():
            print(f"wrote {p}")
        return 0
    ap.print_help()
    return 2


if __name__ == "__main__":
    sys.exit(main())
