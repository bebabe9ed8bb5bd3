"""Result directories: atomic files and a JSON record with provenance.

A run writes into its ``--out`` directory: arrays as NPZ/NPY, figures as PNG,
and last the *record* ``<protocol>.json`` (e.g. ``dynamics.json``), whose
presence marks a complete result.  Several protocols may share one directory
(``packing make``, ``rigidity``, ``dos``), hence one record per protocol, and
``result.json``, rewritten after each record, holds them all:
``{"protocols": [...], "records": {protocol: record}}``.

Every file is written atomically: into a temporary file in the same
directory, then ``os.replace`` onto its name, so an interrupted run leaves a
complete file or none.  Existing results are not overwritten without
``force``.

The record holds the protocol's numbers at the top level and the provenance
keys ``protocol``, ``parameters`` (validated, fully resolved), ``seed``,
``versions`` (python, numpy, scipy, numba, sympy, dask, distributed,
matplotlib, tqdm, fricstab), ``git`` (revision and whether the tree was
dirty, or null), ``timings`` (per stage: ``wall_s`` and ``cpu_s``, the CPU
time of this process), ``seconds`` (total wall time), ``command``,
``started``/``finished`` (UTC, ISO 8601) and ``host``.  NaN and inf are
written as ``null`` (strict JSON).
"""

import contextlib
import functools
import json
import math
import os
import platform
import shlex
import subprocess
import sys
import time
from datetime import datetime, timezone
from pathlib import Path

import numpy as np

from fricstab import __version__
from fricstab.io.files import atomic_write
from fricstab.laws import ParameterError

__all__ = ["INDEX", "ResultDir", "add_run_options", "git_revision", "json_clean", "provenance",
           "update_index", "versions", "write_json"]

RECORD_VERSION = 1
#: The directory's index of records (see :func:`_update_index`).
INDEX = "result.json"
_PACKAGES = ("numpy", "scipy", "numba", "sympy", "dask", "distributed", "matplotlib", "tqdm")


def json_clean(obj):
    """A JSON-safe copy: numpy scalars and arrays to Python, nan/inf to None, paths to str."""
    if isinstance(obj, dict):
        return {str(k): json_clean(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [json_clean(v) for v in obj]
    if isinstance(obj, np.ndarray):
        return json_clean(obj.tolist())
    if isinstance(obj, (bool, np.bool_)):
        return bool(obj)
    if isinstance(obj, (int, np.integer)):
        return int(obj)
    if isinstance(obj, (float, np.floating)):
        return float(obj) if math.isfinite(obj) else None
    if isinstance(obj, (complex, np.complexfloating)):
        return [json_clean(obj.real), json_clean(obj.imag)]
    if isinstance(obj, Path):
        return str(obj)
    return obj


def write_json(path, doc):
    """Write ``doc`` (cleaned by :func:`json_clean`) atomically as indented JSON."""
    text = json.dumps(json_clean(doc), indent=2, allow_nan=False) + "\n"
    atomic_write(path, lambda tmp: Path(tmp).write_text(text))


@functools.lru_cache(maxsize=1)
def versions():
    """Versions of Python, fricstab and its dependencies (``None`` if not installed)."""
    from importlib import metadata
    out = {"python": platform.python_version(), "fricstab": __version__}
    for name in _PACKAGES:
        try:
            out[name] = metadata.version(name)
        except metadata.PackageNotFoundError:
            out[name] = None
    return out


@functools.lru_cache(maxsize=1)
def git_revision():
    """``{"revision", "dirty"}`` of the source tree of fricstab, or None (never raises)."""
    root = Path(__file__).resolve().parent.parent
    try:
        rev = subprocess.run(["git", "-C", str(root), "rev-parse", "HEAD"], capture_output=True,
                             text=True, timeout=5)
        if rev.returncode != 0:
            return None
        dirty = subprocess.run(["git", "-C", str(root), "status", "--porcelain",
                                "--untracked-files=no"], capture_output=True, text=True,
                               timeout=5)
        return {"revision": rev.stdout.strip(),
                "dirty": bool(dirty.stdout.strip()) if dirty.returncode == 0 else None}
    except (OSError, subprocess.SubprocessError):
        return None


def provenance(protocol, parameters, seed, timings, argv=None, started=None):
    """The provenance keys of a record (see the module docstring)."""
    now = datetime.now(timezone.utc)
    argv = list(sys.argv[1:] if argv is None else argv)
    return {"record_version": RECORD_VERSION, "protocol": protocol,
            "parameters": parameters, "seed": seed, "versions": versions(),
            "git": git_revision(), "timings": timings,
            "command": "fricstab " + shlex.join(str(a) for a in argv),
            "started": (started or now).isoformat(timespec="seconds"),
            "finished": now.isoformat(timespec="seconds"), "host": platform.node()}


class ResultDir:
    """The output directory of one protocol run.

    Parameters
    ----------
    path : path-like
        The ``--out`` directory (created by :meth:`create`, not by the constructor).
    name : str
        The protocol; the record is ``<name>.json``.
    force : bool
        Overwrite an existing result.
    resume : bool
        Accept a directory holding an unfinished run (checkpoints, no record).
    outputs : list of str, optional
        Further names (files or folders) that count as an existing result.

    Raises
    ------
    ParameterError
        ``path`` is a file; or it holds a result and ``force`` is not set; or
        ``resume`` is set and the result is already complete.
    """

    def __init__(self, path, name, *, force=False, resume=False, outputs=()):
        self.path = Path(path).expanduser()
        self.name = name
        self.record = self.path / f"{name}.json"
        self.timings = {}
        self._t0 = time.perf_counter()
        self._started = datetime.now(timezone.utc)
        _check_out_path(self.path)
        if force:
            return
        if resume:
            if self.record.exists():
                raise ParameterError(f"--resume: {self.path} already holds a complete "
                                     f"result ({self.record.name}); use --force to recompute")
            return
        found = [n for n in (self.record.name, *outputs) if (self.path / n).exists()]
        if found:
            raise ParameterError(f"--out: {self.path} already holds results "
                                 f"({', '.join(found)}); use --force to overwrite them "
                                 "(or --resume to continue an interrupted run)")

    def create(self):
        """Create the directory (and parents); returns self."""
        self.path.mkdir(parents=True, exist_ok=True)
        if self.record.exists():   # --force: a stale record must not outlive a failed rerun
            self.record.unlink()
        return self

    @contextlib.contextmanager
    def stage(self, name):
        """Time a stage: wall and CPU seconds, accumulated under ``timings[name]``."""
        w0, c0 = time.perf_counter(), time.process_time()
        try:
            yield
        finally:
            t = self.timings.setdefault(name, {"wall_s": 0.0, "cpu_s": 0.0})
            t["wall_s"] = round(t["wall_s"] + time.perf_counter() - w0, 4)
            t["cpu_s"] = round(t["cpu_s"] + time.process_time() - c0, 4)

    def file(self, relname):
        """Path of ``relname`` inside the directory; parent folders are created."""
        p = self.path / relname
        p.parent.mkdir(parents=True, exist_ok=True)
        return p

    def write_json(self, relname, doc):
        write_json(self.file(relname), doc)

    def write_npz(self, relname, **arrays):
        def write(tmp):
            with open(tmp, "wb") as fh:
                np.savez(fh, **arrays)
        atomic_write(self.file(relname), write)

    def write_npy(self, relname, array):
        def write(tmp):
            with open(tmp, "wb") as fh:
                np.save(fh, array)
        atomic_write(self.file(relname), write)

    def write_png(self, relname, draw):
        """``draw(path)`` saves a PNG figure to ``path`` (use ``format='png'``)."""
        atomic_write(self.file(relname), draw)

    def write_with(self, relname, write):
        """Any writer: ``write(tmp_path)``; renamed atomically onto ``relname``."""
        atomic_write(self.file(relname), write)

    def finish(self, numbers, *, parameters, seed=None, argv=None):
        """Write the record ``<name>.json`` last: ``numbers`` plus provenance; returns it."""
        doc = dict(numbers)
        doc.update(provenance(self.name, parameters, seed, self.timings, argv, self._started))
        doc["seconds"] = round(time.perf_counter() - self._t0, 3)
        write_json(self.record, doc)
        update_index(self.path, self.name, doc)
        return doc


def update_index(path, name, doc):
    """``result.json``: every protocol record of the directory, keyed by protocol.

    Written after the record, atomically; an unreadable old index is rebuilt
    from the records on disk, so it never loses a finished result.
    """
    index_path = Path(path) / INDEX
    records = {}
    for f in sorted(Path(path).glob("*.json")):
        if f.name == INDEX:
            continue
        try:
            rec = json.loads(f.read_text())
        except (OSError, ValueError):
            continue
        if isinstance(rec, dict) and rec.get("protocol") == f.stem:
            records[f.stem] = rec
    records[name] = doc
    write_json(index_path, {"index_version": RECORD_VERSION, "protocols": sorted(records),
                            "records": records})


def _check_out_path(path):
    """``path`` is, or can be made, a writable directory; else ParameterError."""
    if "\x00" in str(path):
        raise ParameterError(f"--out: {str(path)!r} contains a NUL character")
    if path.exists() and not path.is_dir():
        raise ParameterError(f"--out: {path} exists and is not a directory")
    for parent in (path, *path.absolute().parents):
        if parent.exists():
            if not parent.is_dir():
                raise ParameterError(f"--out: {parent} is not a directory, so {path} "
                                     "cannot be made")
            if not os.access(parent, os.W_OK | os.X_OK):
                raise ParameterError(f"--out: {parent} is not writable")
            return
    return


def add_run_options(parser, *, seed=True, checkpoints=False, scene=True, seed_default=0,
                    checkpoint_unit="steps"):
    """The options every protocol shares (see README, "Command line and scene files")."""
    from pathlib import Path as _P
    if scene:
        parser.add_argument("--scene", type=_P, default=None, metavar="FILE.toml",
                            help="TOML scene file (see `fricstab scene show NAME`); "
                                 "command-line options override its keys")
    parser.add_argument("--out", type=_P, required=True, metavar="DIR",
                        help="output directory (created; see README 'Result layout')")
    parser.add_argument("--force", action="store_true",
                        help="overwrite a result that already exists in --out")
    if seed:
        parser.add_argument("--seed", type=_seed, default=seed_default,
                            help=f"random seed, an integer >= 0 (default {seed_default})")
    parser.add_argument("--quiet", action="store_true",
                        help="print nothing on success (errors still go to stderr)")
    parser.add_argument("--no-progress", action="store_true", help="no progress bars")
    parser.add_argument("--dry-run", action="store_true",
                        help="validate and resolve every parameter, print them as JSON, "
                             "write nothing")
    if checkpoints:
        parser.add_argument("--checkpoint-every", type=_steps, default=None,
                            metavar=checkpoint_unit.upper(),
                            help=f"save a checkpoint every K {checkpoint_unit} (cost: one "
                                 "file write each time; a kill loses at most K "
                                 f"{checkpoint_unit}; default: see the command)")
        parser.add_argument("--resume", action="store_true",
                            help="continue from the last checkpoint in --out")
    return parser


def _seed(text):
    import argparse
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"must be an integer >= 0, got {text!r}") from None
    if not 0 <= value < 2 ** 63:
        raise argparse.ArgumentTypeError(f"must be an integer in [0, 2^63), got {text!r}")
    return value


def _steps(text):
    import argparse
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"must be an integer >= 1, got {text!r}") from None
    if not 1 <= value < 2 ** 62:
        raise argparse.ArgumentTypeError(f"must be an integer >= 1, got {text!r}")
    return value
