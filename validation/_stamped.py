"""A cache of computations stamped with the code that made them, for the validation scripts.

``cached(path, compute)`` runs ``compute()`` under the registry's tracer
(:class:`claims.fingerprint.Tracer`) and saves its arrays in ``path`` (``.npz``) with
``units``: the functions of the checkout it executed (:func:`claims.fingerprint.code_units`).
A later call reuses the file only while every one of those functions is unchanged
(:func:`fresh`); otherwise it recomputes, so a cached number is never older than its code.
Where the tracer could not see every call (a subprocess), the stamp is the hash of every
fricstab module (:func:`code_hash`), fresh only while none changed.  A claim that reads
cached results passes the merged units (:func:`merge`) as ``Result.units``, so its record
goes stale exactly when the code that made them changes.
"""

import functools
import hashlib
import json
import os
import sys
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
UNITS, CODE, SECONDS = "stamp_units", "stamp_code", "stamp_seconds"


def _fp():
    """:mod:`claims.fingerprint`, its pure functions of source text memoised in this process
    (a stamp hashes every loaded module; a script stamping hundreds of pieces would parse
    the same unchanged sources hundreds of times)."""
    sys.path.insert(0, str(HERE))
    import claims.fingerprint as fp
    for name in ("source_hash", "unit_hashes", "uses_numba"):
        f = getattr(fp, name)
        if not hasattr(f, "cache_info"):
            setattr(fp, name, functools.lru_cache(maxsize=1024)(f))
    return fp


def code_hash(root=HERE.parent):
    """The hash of every fricstab module but the CLI (syntax trees without docstrings)."""
    fp = _fp()
    digest = hashlib.sha256()
    for rel in fp.package_files(root=root):
        digest.update(f"{rel}:{fp.module_hash(rel, root)}\n".encode())
    return digest.hexdigest()[:16]


def fresh(units, code=""):
    """Whether a computation stamped ``units`` (JSON text, '' if untraced) and ``code``
    was made by the checkout's code."""
    if units:
        return not _fp().units_changed(json.loads(units))
    return bool(code) and code == code_hash()


def merge(a, b):
    """The union of two ``code_units`` dicts (None: untraced, stays None)."""
    if a is None or b is None:
        return None
    out = {m: dict(u) for m, u in a.items()}
    for m, u in b.items():
        out.setdefault(m, {}).update(u)
    return out


def units_of(stored):
    """The ``code_units`` of a loaded cache entry (None if it was untraced)."""
    text = str(stored.get(UNITS, ""))
    return json.loads(text) if text else None


def load(path):
    """The arrays of ``path`` (0-d string arrays as ``str``)."""
    with np.load(path, allow_pickle=False) as z:
        return {k: (str(z[k]) if z[k].dtype.kind == "U" else z[k]) for k in z.files}


def save(path, arrays):
    """Write ``arrays`` to ``path`` atomically (a killed process leaves no half file)."""
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(path.name + ".tmp")
    with open(tmp, "wb") as f:
        np.savez_compressed(f, **arrays)
    os.replace(tmp, path)


def stored(path):
    """The fresh cache entry at ``path``, or None (absent, unreadable or made by other code)."""
    path = Path(path)
    try:
        got = load(path)
    except (OSError, ValueError):
        return None
    return got if fresh(got.get(UNITS, ""), got.get(CODE, "")) else None


def cached(path, compute, log=print):
    """``compute()`` (a dict of arrays and numbers), from ``path`` while its stamp is fresh.

    Returns the dict with the stamp (``stamp_units``, ``stamp_code``) and the seconds the
    computation took (``stamp_seconds``, under the tracer) added."""
    path = Path(path)
    if path.exists():
        try:
            got = load(path)
        except (OSError, ValueError) as exc:        # a damaged file: recompute, say so
            log(f"    {path.name}: unreadable ({exc}); recomputed")
        else:
            if fresh(got.get(UNITS, ""), got.get(CODE, "")):
                return got
            log(f"    {path.name}: made by other code; recomputed")
    fp = _fp()
    t0 = time.perf_counter()
    with fp.Tracer() as tracer:
        out = dict(compute())
    out[SECONDS] = np.float64(time.perf_counter() - t0)
    units = fp.code_units(tracer)
    out[UNITS] = np.str_("" if units is None else json.dumps(units))
    out[CODE] = np.str_(code_hash())
    save(path, out)
    return load(path)
