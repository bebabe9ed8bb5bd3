"""One runner for ensembles: realizations, samples and parameter sweeps on dask.distributed.

An ensemble is a function ``func(**kwargs) -> dict`` of arrays and scalars and a
mapping ``key -> kwargs``, one entry per member.  Each member's result is
stored atomically as ``<out>/members/<key>.npz`` the moment it finishes (by
the worker that computed it), so:

* a rerun skips every stored member (a member never runs again once stored);
* a worker that dies loses only the member it was computing; the nanny
  restarts the worker and the scheduler reassigns that member (up to dask's
  ``distributed.scheduler.allowed-failures``, default 3 deaths per member);
  a member that *raises* is retried ``retries`` times;
* the results read back are the stored files, whichever process wrote them.

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
from pathlib import Path

import numpy as np

from fricstab.io.files import atomic_write
from fricstab.laws import ParameterError

__all__ = ["member_path", "load_member", "run_ensemble"]

_KEY = re.compile(r"^[A-Za-z0-9][A-Za-z0-9_.+=-]{0,120}$")


def member_path(out_dir, key):
    """``<out_dir>/members/<key>.npz``."""
    return Path(out_dir) / "members" / f"{key}.npz"


def load_member(path):
    """The stored dict of arrays of one member."""
    with np.load(path, allow_pickle=False) as z:
        return {k: z[k] for k in z.files}


def _store(path, result):
    if not isinstance(result, dict):
        raise TypeError(f"an ensemble member must return a dict, got {type(result).__name__}")
    arrays = {str(k): np.asarray(v) for k, v in result.items()}

    def write(tmp):
        with open(tmp, "wb") as fh:
            np.savez(fh, **arrays)

    Path(path).parent.mkdir(parents=True, exist_ok=True)
    atomic_write(path, write)


def _run_member(func, key, kwargs, path):
    """Worker side: compute one member unless stored, store it, return it."""
    path = Path(path)
    if path.is_file():
        return load_member(path)
    result = func(**kwargs)
    _store(path, result)
    return {str(k): np.asarray(v) for k, v in result.items()}


def _client(scheduler, workers, n_todo):
    from dask.distributed import Client, LocalCluster
    if scheduler == "local":
        n = workers or min(os.cpu_count() or 1, max(1, n_todo))
        cluster = LocalCluster(n_workers=n, threads_per_worker=1, processes=True,
                               dashboard_address=None, silence_logs=logging.ERROR)
        return Client(cluster), cluster
    try:
        return Client(scheduler, timeout="10s"), None
    except (OSError, ValueError, TypeError) as exc:
        raise ParameterError(f"--scheduler: cannot connect to {scheduler!r}: "
                             f"{' '.join(str(exc).split())[:120]}") from None


def run_ensemble(func, members, out_dir, *, scheduler="local", workers=None, retries=2,
                 progress=True, desc="ensemble"):
    """Run every member not yet stored; return ``{key: dict of arrays}`` for all members.

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
    paths = {k: member_path(out_dir, k) for k in members}
    todo = [k for k in members if not paths[k].is_file()]
    results, first_error = {}, None
    with tqdm(total=len(members), initial=len(members) - len(todo), desc=desc, unit="member",
              disable=(not progress) or None, file=sys.stderr) as bar:
        if todo and scheduler == "inline":
            for k in todo:
                try:
                    results[k] = _run_member(func, k, members[k], str(paths[k]))
                except Exception as exc:  # run the others, then raise the first
                    first_error = first_error or exc
                bar.update(1)
        elif todo:
            from dask.distributed import as_completed
            client, cluster = _client(scheduler, workers, len(todo))
            try:
                futures = {client.submit(_run_member, func, k, members[k], str(paths[k]),
                                         key=f"fricstab-member-{k}", retries=retries,
                                         pure=False): k for k in todo}
                for fut in as_completed(futures):
                    k = futures[fut]
                    try:
                        res = fut.result()
                    except Exception as exc:
                        first_error = first_error or exc
                    else:
                        if not paths[k].is_file():   # a remote worker without our filesystem
                            _store(paths[k], res)
                        results[k] = res
                    bar.update(1)
            finally:
                client.close()
                if cluster is not None:
                    cluster.close()
    if first_error is not None:
        raise first_error
    return {k: results[k] if k in results else load_member(paths[k]) for k in members}
