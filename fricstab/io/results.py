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
written as ``null`` (strict JSON).  Last comes ``record_sha256``, the digest
of the rest (:func:`fricstab.io.rundir.record_digest`): readers refuse a
record edited after its run (``record_version`` 2).
"""

import contextlib
import functools
import json
import os
import platform
import shlex
import shutil
import subprocess
import sys
import time
from datetime import datetime, timezone
from pathlib import Path

import numpy as np

from fricstab import __version__
from fricstab.io import rundir, undo
from fricstab.io.files import atomic_write, json_clean, write_json
from fricstab.io.undo import Before as _Before
from fricstab.io.undo import abandon_all, entries as _entries, forget_all, note_removed
from fricstab.laws import ParameterError

__all__ = ["INDEX", "ResultDir", "abandon_all", "add_run_options", "forget_all", "git_revision",
           "json_clean", "note_removed", "provenance", "release_all", "update_index", "versions",
           "write_json"]

#: 2: the record carries its digest ``record_sha256`` (:func:`fricstab.io.rundir.record_digest`).
RECORD_VERSION = rundir.DIGESTED_VERSION
INDEX_VERSION = 1
#: The directory's index of records (see :func:`_update_index`).
INDEX = "result.json"
_PACKAGES = ("numpy", "scipy", "numba", "sympy", "dask", "distributed", "matplotlib", "tqdm")


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
    """The output directory of one protocol run (lock, journal, manifest: :mod:`fricstab.io.rundir`).

    Parameters
    ----------
    path : path-like
        The ``--out`` directory (created by :meth:`create`, not by the constructor).
    name : str
        The protocol; the record is ``<name>.json``.
    force : bool
        Start afresh: :meth:`create` removes what the previous run of this
        protocol wrote (its record, journal, and the files and folders they
        list), and nothing else, and drops its record from ``result.json``, so
        that a forced run that then fails leaves no record of removed files.
    resume : bool
        Continue an interrupted run of this protocol (same fingerprint).
    resumable : bool
        Whether the command has ``--resume`` (named in the refusal of an
        interrupted run only if so).
    outputs : list of str, optional
        Further names that count as an existing result (records written
        before manifests existed list no files).
    fingerprint : dict, optional
        Every parameter that affects the output; stored in the journal and the
        record, compared on ``resume``.
    within : ResultDir, optional
        A created ResultDir of the same directory whose lock this run shares:
        a result written as part of another run (the packing that ``packing
        rigidity`` makes), with its own record, journal and manifest.
    free : tuple of str
        Parameters a resumed run may change: stop conditions (the total
        strain of a shear run) that extend the run without changing what it
        has computed.

    Raises
    ------
    ParameterError
        ``path`` is a file; or it holds a result (or an interrupted run) and
        neither ``force`` nor ``resume`` is set; or ``resume`` is set and the
        result is already complete, or was made with other parameters.
    """

    def __init__(self, path, name, *, force=False, resume=False, outputs=(), fingerprint=None,
                 resumable=True, within=None, free=()):
        self.path = Path(path).expanduser()
        self.name = name
        self.record = self.path / f"{name}.json"
        self.timings = {}
        self.force, self.resume, self.outputs = force, resume, tuple(outputs)
        self.fingerprint = None if fingerprint is None else rundir.fingerprint(fingerprint)
        self._names, self._folders, self._transient = set(), set(), set()
        self._kept = set()   # what the run's folders held before it took them: not its own
        self._lock, self._within, self._created = None, within, False
        self._t0 = time.perf_counter()
        self._started = datetime.now(timezone.utc)
        _check_out_path(self.path)
        if within is None:   # a run in progress there is not an interrupted one
            rundir.Lock(self.path, name).refuse_if_held()
        journal = rundir.journal_path(self.path, name)
        if force:
            return
        if resume:
            if self.record.exists():
                raise ParameterError(f"--resume: {self.path} already holds a complete "
                                     f"result ({self.record.name}); use --force to recompute")
            old = _read_json(journal)
            differs = None if old is None or self.fingerprint is None else \
                rundir.difference(old.get("fingerprint"), self.fingerprint, free)
            if differs:
                raise ParameterError(
                    f"--resume: the interrupted run in {self.path} was made with other "
                    f"parameters ({differs}); rerun with the same parameters, or use --force "
                    "to start afresh")
            return
        found = [n for n in (self.record.name, *self.outputs) if (self.path / n).exists()]
        if journal.exists():
            found.append(f"an interrupted {name} run")
        if found:
            raise ParameterError(f"--out: {self.path} already holds results "
                                 f"({', '.join(found)}); use --force to overwrite them"
                                 + (" (or --resume to continue an interrupted run)"
                                    if resumable else ""))

    def create(self):
        """Create the directory, take its lock, clear a previous run if ``force``; returns self.

        What the directory held before is noted (:class:`_Before`): a run refused
        later (exit 2) is undone by :func:`abandon_all`, so that it leaves nothing new.
        """
        made = [p for p in (self.path, *self.path.absolute().parents) if not p.exists()]
        self.path.mkdir(parents=True, exist_ok=True)
        before = _Before.of(self.path, made)
        if self._within is None:
            self._lock = rundir.Lock(self.path, self.name, " ".join(sys.argv[1:])).acquire()
            _HELD.append(self)
        elif self._within._lock is None or \
                self._within.path.resolve() != self.path.resolve():
            raise ValueError("within= needs a created ResultDir of the same directory")
        before.add(self)   # the lock is this run's: what it writes can be undone
        self._created = True
        if self.force:
            old = _read_json(self.record)
            legacy = isinstance(old, dict) and not isinstance(old.get("files"), dict)
            rundir.remove_run(self.path, self.name)
            for n in self.outputs if legacy else ():   # a run from before manifests existed
                q = self.path / n
                if q.is_dir():
                    shutil.rmtree(q, ignore_errors=True)
                elif q.exists():
                    q.unlink()
            self.record.unlink(missing_ok=True)
            update_index(self.path, self.name, None)
            _Before.of(self.path).removed()   # what it writes again is new
        elif self.resume:
            old = _read_json(rundir.journal_path(self.path, self.name)) or {}
            self._names.update(old.get("files", []))
            self._folders.update(old.get("folders", []))
            self._kept.update(old.get("kept", []))
        self._write_journal()
        return self

    def _write_journal(self):
        rundir.write_journal(self.path, self.name, self.fingerprint, self._names, self._folders,
                             self._kept)

    def register(self, relname, folder=False, transient=False):
        """Record that the run writes ``relname`` (a file, or a folder); returns its path.

        A ``transient`` folder (checkpoints) is removed when the run finishes.
        """
        rel = str(Path(relname))
        target = self._folders if folder else self._names
        if transient:   # also when a resumed run's journal already names it
            self._transient.add(rel)
        if rel not in target:
            target.add(rel)
            if folder and (self.path / rel).is_dir():   # another's files there stay its own
                self._kept.update(f"{rel}/{e}" for e in _entries(self.path / rel))
            if self._created:
                self._write_journal()
        return self.path / rel

    def checkpoints(self):
        """The checkpoint folder (transient: removed when the run completes)."""
        return self.register("checkpoints", folder=True, transient=True)

    def close(self):
        """Release the lock (the journal stays: the run is resumable or removable)."""
        if self._lock is not None:
            self._lock.release()
            self._lock = None
        self._created = False
        if self in _HELD:
            _HELD.remove(self)

    def __enter__(self):
        return self.create()

    def __exit__(self, *exc):
        self.close()

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
        """Path of ``relname`` inside the directory (registered; parent folders made)."""
        p = self.path / Path(relname)
        if p.is_dir() and not p.is_symlink():
            raise ParameterError(f"--out: {p} is a folder, not a file of this {self.name} run; "
                                 "move it away")
        p = self.register(relname)
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
        """Write the record ``<name>.json`` last: numbers, provenance, manifest, digest.

        Transient folders (checkpoints) are removed first; the journal after
        the record; the lock is released.  Returns the record.
        """
        for rel in self._transient:
            if any(k.startswith(rel + "/") for k in self._kept):
                rundir.remove_run_folder(self.path, rel, self._kept)
            else:
                shutil.rmtree(self.path / rel, ignore_errors=True)
        doc = dict(numbers)
        doc.update(provenance(self.name, parameters, seed, self.timings, argv, self._started))
        doc["seconds"] = round(time.perf_counter() - self._t0, 3)
        doc["fingerprint"] = self.fingerprint or rundir.fingerprint(parameters)
        doc["warnings"] = [dict(w) for w in WARNINGS]
        doc["files"] = {k: v for k, v in rundir.manifest(
            self.path, (self._names | self._folders) - self._transient).items()
            if k not in self._kept}
        doc["folders"] = sorted(self._folders - self._transient)   # --force: emptied of its files
        doc[rundir.DIGEST] = rundir.record_digest(doc)   # last: readers refuse an edited record
        write_json(self.record, doc)
        update_index(self.path, self.name, doc)
        rundir.journal_path(self.path, self.name).unlink(missing_ok=True)
        self.close()
        return doc


#: ResultDirs of this process whose lock is held (released by :func:`release_all`).
_HELD = []
#: Warnings raised during this command (the command line collects them), distinct
#: by (category, message, where), with counts; every record written lists them.
WARNINGS = []


def note_warning(category, message, where):
    """Count one warning (the command line's ``warnings.showwarning``)."""
    for w in WARNINGS:
        if (w["category"], w["message"], w["where"]) == (category, message, where):
            w["count"] += 1
            return
    WARNINGS.append({"category": category, "message": message, "where": where, "count": 1})


def release_all():
    """Release every lock this process holds (the command line calls it on any exit)."""
    for rd in list(_HELD):
        rd.close()


def _read_json(path):
    try:
        return json.loads(Path(path).read_text())
    except (OSError, ValueError):
        return None


def update_index(path, name=None, doc=None):
    """``result.json``: every protocol record of the directory, keyed by protocol.

    Written after the record ``doc`` of ``name``, atomically, from the records on
    disk, so it never loses a finished result nor keeps a removed one: ``doc``
    None drops ``name`` (its record was removed); ``name`` None rebuilds the
    index from the records alone; an index left without records is removed.
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
    if name is not None:
        records.pop(name, None)
        if doc is not None:
            records[name] = doc
    if not records:
        index_path.unlink(missing_ok=True)
        return
    write_json(index_path, {"index_version": INDEX_VERSION, "protocols": sorted(records),
                            "records": records})


undo.Before.index_name, undo.Before.rebuild_index = INDEX, staticmethod(update_index)


def _check_out_path(path):
    """``path`` is, or can be made, a writable directory; else ParameterError."""
    if "\x00" in str(path):
        raise ParameterError(f"--out: {str(path)!r} contains a NUL character")
    if str(path).strip() in ("", "."):
        raise ParameterError(f"--out: {str(path)!r} names no new directory; give a directory "
                             "name (the run writes several files into it)")
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
    """The options every protocol shares (see docs/howto/scene_files.md)."""
    from pathlib import Path as _P
    if scene:
        parser.add_argument("--scene", type=_P, default=None, metavar="FILE.toml",
                            help="TOML scene file (see `fricstab scene show NAME`); "
                                 "command-line options override its keys")
    parser.add_argument("--out", type=_P, required=True, metavar="DIR",
                        help="output directory (created; see docs/howto/result_layout.md)")
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
