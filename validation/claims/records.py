"""Recorded results: ``validation/records/<job>.json``, one per computation.

A record holds the values, the seeds, the revision and date they were
computed at, the machine and library versions, the wall time, the hashes of
the files the computation wrote (reports, figures) and its fingerprint
(:mod:`claims.fingerprint`).  Its ``digest`` is the SHA-256 of everything
else: a value edited by hand no longer matches it, and the test of the
registry fails, naming the record.
"""

import hashlib
import json
import os
import platform
import subprocess
from datetime import datetime, timezone

from .fingerprint import ROOT, file_hash

RECORDS = ROOT / "validation" / "records"


def _canonical(rec):
    body = {k: v for k, v in rec.items() if k != "digest"}
    return json.dumps(body, sort_keys=True, separators=(",", ":"), allow_nan=True)


def digest(rec):
    """SHA-256 of the record without its digest."""
    return hashlib.sha256(_canonical(rec).encode()).hexdigest()


def path(job):
    """Where the record of ``job`` lives."""
    return RECORDS / f"{job}.json"


def load(job):
    """The record of ``job``, or None if it was never recorded."""
    p = path(job)
    if not p.exists():
        return None
    return json.loads(p.read_text())


def save(rec):
    """Write a record (digest added), atomically."""
    rec = dict(rec)
    rec["digest"] = digest(rec)
    p = path(rec["job"])
    p.parent.mkdir(parents=True, exist_ok=True)
    tmp = p.with_suffix(".json.tmp")
    tmp.write_text(json.dumps(rec, indent=1, sort_keys=True, allow_nan=True) + "\n")
    os.replace(tmp, p)
    return rec


def verify(rec):
    """Problems with a record as committed: a digest that does not match, an output
    file that is not the one the computation wrote.  Empty: sound."""
    out = []
    if rec.get("digest") != digest(rec):
        out.append(f"records/{rec.get('job')}.json: digest mismatch (edited by hand?)")
    for f, h in rec.get("outputs", {}).items():
        if file_hash(f) != h:
            out.append(f"{f}: not the file that job {rec['job']} wrote (edited, or written by "
                       "another command)")
    return out


def revision():
    """(HEAD, dirty): the commit the values were computed at, and whether the watched
    code had uncommitted changes (then the fingerprint, not the commit, names the code)."""
    def git(*a):
        r = subprocess.run(["git", *a], cwd=ROOT, capture_output=True, text=True)
        return r.stdout.strip() if r.returncode == 0 else ""
    head = git("rev-parse", "--short=10", "HEAD") or "unknown"
    dirty = bool(git("status", "--porcelain", "--", "fricstab", "validation", "symbolic"))
    return head, dirty


def environment():
    """Machine and versions, recorded beside the values."""
    import numpy
    import scipy
    try:
        import numba
        nb = numba.__version__
    except ImportError:      # pragma: no cover
        nb = None
    return {"machine": platform.processor() or platform.machine(), "cores": os.cpu_count(),
            "python": platform.python_version(), "numpy": numpy.__version__,
            "scipy": scipy.__version__, "numba": nb,
            "threads": os.environ.get("NUMBA_NUM_THREADS")}


def now():
    return datetime.now(timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
