"""Compute a job in a process of its own and record it; the worker side of reproduce.py."""

import importlib
import json
import math
import subprocess
import sys
import time

from . import records
from .fingerprint import ROOT, Tracer, add_units, file_hash, fingerprint

REPRODUCE = ROOT / "validation" / "reproduce.py"


def _finite_json(x):
    """Values as JSON allows: NaN and inf become strings ('nan', 'inf', '-inf')."""
    if isinstance(x, dict):
        return {str(k): _finite_json(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [_finite_json(v) for v in x]
    if hasattr(x, "item") and not isinstance(x, (str, bytes)):   # numpy scalars
        x = x.item()
    if isinstance(x, float) and not math.isfinite(x):
        return repr(x)
    return x


def job_claims(job):
    """The claims of ``job``, importing only its section module."""
    module = importlib.import_module(f"claims.{job.split('.')[0]}")
    claims = [c for c in module.CLAIMS if c.job_name == job]
    if not claims:
        raise KeyError(f"no claim has job {job!r}")
    return claims


def work(job):
    """Run in the job's own process: compute, fingerprint, write the record."""
    claims = job_claims(job)
    tracer = Tracer() if all(c.trace for c in claims) else None
    t0 = time.perf_counter()
    if tracer is None:
        res = claims[0].compute()
    else:
        with tracer:
            res = claims[0].compute()
    wall = time.perf_counter() - t0
    head, dirty = records.revision()
    rec = {
        "job": job, "claims": [c.name for c in claims], "tier": claims[0].tier,
        "values": _finite_json(res.values), "seeds": _finite_json(list(res.seeds)),
        "outputs": {str(f): file_hash(str(f)) for f in res.outputs},
        "revision": head, "dirty": dirty, "date": records.now(), "wall_s": round(wall, 1),
        "environment": records.environment(),
        "fingerprint": add_units(fingerprint(claims[0], tracer=tracer), res.units),
    }
    records.save(rec)
    return rec


def spawn(job, env=None):
    """Compute ``job`` in a fresh process (see :mod:`claims.fingerprint` for why);
    returns (the new record, wall seconds) or raises RuntimeError with its stderr tail."""
    t0 = time.perf_counter()
    r = subprocess.run([sys.executable, str(REPRODUCE), "--worker", job], cwd=ROOT, env=env,
                       stderr=subprocess.PIPE, text=True)
    if r.returncode != 0:
        tail = "\n".join(r.stderr.strip().splitlines()[-6:])
        raise RuntimeError(f"job {job} failed (exit {r.returncode}):\n{tail}")
    return records.load(job), time.perf_counter() - t0


def values_of(rec):
    """A record's values with the strings 'nan', 'inf' turned back into floats."""
    def back(x):
        if isinstance(x, dict):
            return {k: back(v) for k, v in x.items()}
        if isinstance(x, list):
            return [back(v) for v in x]
        if x in ("nan", "inf", "-inf"):
            return float(x)
        return x
    return back(json.loads(json.dumps(rec["values"])))


def recompute(claim, keep=()):
    """Compute a claim's job here, in this process, without recording (the CI check).

    ``keep``: files (paths from the checkout) the job writes and its record vouches for; they
    are put back as they were, so a check leaves the tree as it found it (another machine's
    rendering of a figure differs in bytes, and the next check would call it edited)."""
    saved = {}
    for rel in keep:
        path = ROOT / rel
        if path.is_file():
            saved[path] = path.read_bytes()
    try:
        return values_of({"values": _finite_json(claim.compute().values)})
    finally:
        for path, data in saved.items():
            if not path.is_file() or path.read_bytes() != data:
                path.write_bytes(data)


__all__ = ["work", "spawn", "recompute", "values_of", "job_claims"]
