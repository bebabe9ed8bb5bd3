"""One runner for ensembles: realizations, samples and parameter sweeps on dask.distributed.

An ensemble is a function ``func(**kwargs) -> dict`` of arrays and scalars and a
mapping ``key -> kwargs``, one entry per member.  Each member's result is
stored atomically as ``<out>/members/<key>.npz`` the moment it finishes (by
the worker that computed it), so:

* a rerun skips every stored member that is *sound*: it loads, and, where the
  caller gives member fingerprints, its stored ``fingerprint`` array is that
  of the member asked for.  A damaged member (unreadable, truncated) or one
  made with other parameters is computed again and its file replaced; it is
  never reused, and never fatal.  Callers whose member parameters can change
  between runs build keys with :func:`member_key`: a readable label plus a
  short hash of the member's full fingerprint, so members of other parameters
  never share a file name;
* a worker that dies loses only the member it was computing; the nanny
  restarts the worker and the scheduler reassigns that member (up to dask's
  ``distributed.scheduler.allowed-failures``, default 3 deaths per member);
  a member that *raises* is retried ``retries`` times;
* the results read back are the stored files, whichever process wrote them;
* SIGINT/SIGTERM (:mod:`fricstab.signals`, inside the command line) stop the
  ensemble between members: the workers are stopped, the members stored so
  far kept, and :class:`fricstab.signals.Interrupted` raised (exit 130/143); a
  rerun (``--resume``) computes only the members not stored.

Schedulers: ``"local"`` (default): a ``LocalCluster`` of ``workers`` worker
processes, one thread each, started and stopped here; an address
(``tcp://host:8786``): a running cluster, whose workers must see ``out`` at
the same path (a shared filesystem; the client also stores what comes back);
``"inline"``: no dask, members run one after the other in this process.

Stored arrays: every value of the member's dict goes through
``numpy.asarray`` (scalars become 0-d arrays); ``func`` must be importable
by the workers (a module-level function).
"""

import logging
import os
import re
import sys
import time
import zipfile
from pathlib import Path

import numpy as np

from fricstab import signals
from fricstab.io.files import atomic_write
from fricstab.laws import ParameterError

__all__ = ["FINGERPRINT", "member_key", "member_path", "load_member", "run_ensemble"]

_KEY = re.compile(r"^[A-Za-z0-9][A-Za-z0-9_.+=-]{0,120}$")
#: The array of a stored member that holds its fingerprint (SHA-256, hex).
FINGERPRINT = "fingerprint"
#: A damaged member file raises one of these on loading (cf. :mod:`fricstab.io.checkpoint`).
_DAMAGED = (OSError, ValueError, KeyError, EOFError, zipfile.BadZipFile)
#: Seconds between looks for finished members and for SIGINT/SIGTERM (fricstab.signals).
_POLL_S = 0.1


def member_key(label, parameters):
    """``(key, sha256)`` of a member: ``<label>_<12 hex>`` and its full fingerprint hash.

    ``parameters`` are every parameter that fixes the member's result (JSON-able;
    floats are hashed exactly, by their ``repr``): see :func:`fricstab.io.rundir.fingerprint`.
    """
    from fricstab.io.rundir import fingerprint
    sha = fingerprint(parameters)["sha256"]
    return f"{label}_{sha[:12]}", sha


def member_path(out_dir, key):
    """``<out_dir>/members/<key>.npz``."""
    return Path(out_dir) / "members" / f"{key}.npz"


def load_member(path):
    """The stored dict of arrays of one member (ValueError if the file is no NPZ archive)."""
    with open(path, "rb") as fh:   # ours to close, also when the archive is damaged
        z = np.load(fh, allow_pickle=False)
        if not isinstance(z, np.lib.npyio.NpzFile):
            raise ValueError(f"{path} is not an NPZ archive")
        with z:
            return {k: z[k] for k in z.files}


def _sound(path, fingerprint):
    """The member stored at ``path`` if it loads and has ``fingerprint`` (if given), or None."""
    path = Path(path)
    if not path.is_file():
        return None
    try:
        data = load_member(path)
    except _DAMAGED:
        return None
    if fingerprint is not None and str(data.get(FINGERPRINT, "")) != fingerprint:
        return None
    return data


def _arrays(result, fingerprint):
    if not isinstance(result, dict):
        raise TypeError(f"an ensemble member must return a dict, got {type(result).__name__}")
    arrays = {str(k): np.asarray(v) for k, v in result.items()}
    if fingerprint is not None:
        if FINGERPRINT in arrays:
            raise TypeError(f"an ensemble member with a fingerprint must not return the key "
                            f"{FINGERPRINT!r}")
        arrays[FINGERPRINT] = np.asarray(fingerprint)
    return arrays


def _store(path, arrays):
    def write(tmp):
        with open(tmp, "wb") as fh:
            np.savez(fh, **arrays)

    Path(path).parent.mkdir(parents=True, exist_ok=True)
    atomic_write(path, write)


def _run_member(func, key, kwargs, path, fingerprint=None):
    """Worker side: compute one member unless soundly stored, store it, return its arrays."""
    stored = _sound(path, fingerprint)
    if stored is not None:
        return stored
    arrays = _arrays(func(**kwargs), fingerprint)
    _store(path, arrays)
    return arrays


def _client(scheduler, workers, n_todo):
    from dask.distributed import Client, LocalCluster
    if scheduler == "local":
        n = workers or min(os.cpu_count() or 1, max(1, n_todo))
        # the scheduler's HTTP server on a free local port: dask's default, 8787, is
        # taken by any other cluster on the machine (a warning, then a failure); the
        # workers' logs silenced: a member's error reaches the caller as its exception,
        # and a cluster closed under busy workers (SIGINT) would log tracebacks
        cluster = LocalCluster(n_workers=n, threads_per_worker=1, processes=True,
                               dashboard_address="127.0.0.1:0",
                               silence_logs=logging.CRITICAL)
        return Client(cluster), cluster
    try:
        return Client(scheduler, timeout="10s"), None
    except (OSError, ValueError, TypeError) as exc:
        raise ParameterError(f"--scheduler: cannot connect to {scheduler!r}: "
                             f"{' '.join(str(exc).split())[:120]}") from None


def run_ensemble(func, members, out_dir, *, scheduler="local", workers=None, retries=2,
                 progress=True, desc="ensemble", fingerprints=None):
    """Run every member not soundly stored; return ``{key: dict of arrays}`` for all members.

    Parameters
    ----------
    func : callable
        ``func(**kwargs) -> dict`` (module level, picklable).
    members : dict
        ``key -> kwargs``; keys are file names: letters, digits, ``_ . + = -``.
    out_dir : path-like
        Members go to ``out_dir/members/<key>.npz``.
    scheduler : str
        ``"local"``, ``"inline"`` or a scheduler address (see module docstring).
    workers : int, optional
        Worker processes of the local cluster (default: CPU count, at most the
        number of members to run).
    retries : int
        Retries of a member that raises (worker deaths are handled by dask).
    progress : bool
        Show a tqdm bar on stderr.
    fingerprints : dict, optional
        ``key -> str``, the fingerprint of each member (e.g. the hash of
        :func:`member_key`): stored with the member as the array
        ``fingerprint`` and compared on a rerun; a stored member whose
        fingerprint differs is computed again.  The returned dicts do not
        hold it.  Without it, a stored member is reused if it loads.

    Raises
    ------
    ParameterError
        A bad key, ``workers`` < 1, or an unreachable scheduler.
    Exception
        The first exception of a member that failed after its retries; the
        other members are run and stored first.
    """
    from tqdm import tqdm

    for key in members:
        if not isinstance(key, str) or not _KEY.match(key):
            raise ParameterError(f"ensemble member key {key!r} is not a file name "
                                 "(letters, digits, _ . + = -)")
    if workers is not None and workers < 1:
        raise ParameterError(f"--workers must be an integer >= 1, got {workers}")
    fps = {k: None if fingerprints is None else str(fingerprints[k]) for k in members}
    paths = {k: member_path(out_dir, k) for k in members}
    results = {k: d for k in members if (d := _sound(paths[k], fps[k])) is not None}
    todo = [k for k in members if k not in results]
    first_error = None
    with tqdm(total=len(members), initial=len(members) - len(todo), desc=desc, unit="member",
              disable=(not progress) or None, file=sys.stderr) as bar:
        if todo and scheduler == "inline":
            for k in todo:
                signals.check(" in the ensemble")
                try:
                    results[k] = _run_member(func, k, members[k], str(paths[k]), fps[k])
                except Exception as exc:  # run the others, then raise the first
                    first_error = first_error or exc
                bar.update(1)
        elif todo:
            from dask.distributed import as_completed
            client, cluster = _client(scheduler, workers, len(todo))
            try:
                futures = {client.submit(_run_member, func, k, members[k], str(paths[k]),
                                         fps[k], key=f"fricstab-member-{k}",
                                         retries=retries, pure=False): k for k in todo}
                done = as_completed(futures)
                while not done.is_empty():
                    # SIGINT/SIGTERM (fricstab.signals): stop here, the stored members kept
                    signals.check(" in the ensemble")
                    batch = done.next_batch(block=False)
                    if not batch:
                        time.sleep(_POLL_S)
                        continue
                    for fut in batch:
                        k = futures[fut]
                        try:
                            res = fut.result()
                        except Exception as exc:
                            first_error = first_error or exc
                        else:
                            if _sound(paths[k], fps[k]) is None:   # a remote worker's disk
                                _store(paths[k], res)
                            results[k] = res
                        bar.update(1)
                # a signal that also reached the workers (Ctrl-C to the process group)
                # may have failed their members: it is the interruption, not their error
                signals.check(" in the ensemble")
            finally:
                client.close()
                if cluster is not None:
                    cluster.close()
    if first_error is not None:
        raise first_error
    return {k: {a: v for a, v in results[k].items() if fps[k] is None or a != FINGERPRINT}
            for k in members}
