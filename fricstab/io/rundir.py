"""A result directory owns its run: lock, journal, manifest, fingerprint.

Every protocol run writes into its ``--out`` directory through
:class:`fricstab.io.results.ResultDir`, which keeps, besides the files:

``.fricstab.lock``
    who writes now (pid, host, process start time, protocol, command).  A
    second writer is refused with one line naming the holder; a lock whose
    process is gone (same host) is stale and taken over.
``.<protocol>.journal.json``
    the run in progress: its fingerprint and every file and folder it has
    written so far, rewritten atomically before each new one.  An interrupted
    run leaves it behind: ``--resume`` continues it (same fingerprint only),
    ``--force`` removes exactly what it lists.
``<protocol>.json``
    the record, written last and atomically: the numbers, the provenance, the
    fingerprint and the *manifest*: every file of the run with its size and
    SHA-256, and the folders the run owns (removed whole by ``--force``);
    last its own digest ``record_sha256`` (:func:`record_digest`).  Readers
    (:func:`verify`) refuse a directory whose record or files do not match,
    naming the file.

The fingerprint is the SHA-256 of the canonical JSON of every parameter that
affects the output (the validated scene, the protocol's options, the seed).
"""

import hashlib
import json
import os
import platform
import shutil
import time
from pathlib import Path

from fricstab.errors import ParameterError
from fricstab.io.files import json_clean, temporaries, write_json

__all__ = ["DIGEST", "LOCK", "Lock", "fingerprint", "journal_path", "manifest", "record_digest",
           "remove_run", "remove_run_folder", "verify"]

LOCK = ".fricstab.lock"
#: The record's key holding :func:`record_digest` (records of ``record_version`` >= 2).
DIGEST = "record_sha256"
#: The first ``record_version`` whose records carry a digest (and a manifest).
DIGESTED_VERSION = 2
_HASH_CHUNK = 1 << 20


def fingerprint(parameters):
    """``{"sha256": ..., "parameters": ...}`` of the canonical JSON of ``parameters``."""
    clean = json_clean(parameters)
    text = json.dumps(clean, sort_keys=True, allow_nan=False, separators=(",", ":"))
    return {"sha256": hashlib.sha256(text.encode()).hexdigest(), "parameters": clean}


def record_digest(record):
    """SHA-256 of the canonical JSON (sorted keys, no spaces) of ``record`` but :data:`DIGEST`.

    The same for the dict :meth:`ResultDir.finish` writes and for the one read back.
    """
    body = json_clean({k: v for k, v in record.items() if k != DIGEST})
    text = json.dumps(body, sort_keys=True, allow_nan=False, separators=(",", ":"))
    return hashlib.sha256(text.encode()).hexdigest()


def _check_record(record, record_path):
    """Refuse a record edited after its run: digest changed or removed, manifest removed.

    Returns whether the record has a manifest; a record of ``record_version``
    1 (or none) without a manifest, written before manifests, is legacy.
    """
    fix = "; rerun with --force"
    has_manifest = isinstance(record.get("files"), dict)
    version = record.get("record_version")
    modern = DIGEST in record or has_manifest or not (version is None or version == 1)
    if not modern:
        return False
    if DIGEST not in record:
        why = ("has no record digest (written before records carried one, or edited)"
               if has_manifest else f"has no manifest and no digest (record_version {version!r}"
               ", edited by hand?)")
        raise ParameterError(f"{record_path} {why}{fix}")
    if record[DIGEST] != record_digest(record):
        raise ParameterError(f"{record_path} does not match its digest {DIGEST} (the record "
                             f"was edited after the run){fix}")
    if not has_manifest:
        raise ParameterError(f"{record_path} has no manifest of its files{fix}")
    return True


def difference(old, new, free=()):
    """The first differing parameter of two fingerprints outside ``free``, in words, or None.

    Fingerprints without their parameters compare by hash.
    """
    a, b = (old or {}).get("parameters"), (new or {}).get("parameters")
    if isinstance(a, dict) and isinstance(b, dict):
        for key in sorted(set(a) | set(b)):
            if key not in free and a.get(key) != b.get(key):
                return f"{key}: {a.get(key)!r} there, {b.get(key)!r} now"
        return None
    return None if (old or {}).get("sha256") == (new or {}).get("sha256") else "other parameters"


def journal_path(folder, protocol):
    return Path(folder) / f".{protocol}.journal.json"


def _start_time(pid):
    """The process's start time in clock ticks (Linux /proc), or None."""
    try:
        stat = Path(f"/proc/{pid}/stat").read_text()
        return int(stat.rsplit(")", 1)[1].split()[19])
    except (OSError, ValueError, IndexError):
        return None


def _alive(pid, start):
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    if start is not None:
        now = _start_time(pid)
        return now is None or now == start   # another process took the pid: stale
    return True


class Lock:
    """The directory's writer lock (module docstring); a context manager."""

    def __init__(self, folder, protocol, command=""):
        self.path = Path(folder) / LOCK
        self.doc = {"pid": os.getpid(), "host": platform.node(),
                    "start": _start_time(os.getpid()), "protocol": protocol,
                    "command": command, "since": time.strftime("%Y-%m-%dT%H:%M:%S")}
        self.held = False

    def acquire(self):
        for _ in range(3):
            try:
                fd = os.open(self.path, os.O_CREAT | os.O_EXCL | os.O_WRONLY, 0o644)
            except FileExistsError:
                holder = self._holder()
                if holder is None or self._stale(holder):
                    self.path.unlink(missing_ok=True)
                    continue
                raise ParameterError(self._busy(holder))
            with os.fdopen(fd, "w") as fh:
                json.dump(self.doc, fh)
            self.held = True
            return self
        raise ParameterError(f"--out: cannot take the lock {self.path}")

    def _busy(self, holder):
        return (f"--out: {self.path.parent} is being written by another fricstab run "
                f"(pid {holder.get('pid')} on {holder.get('host')}, "
                f"`{holder.get('command') or holder.get('protocol')}`, since "
                f"{holder.get('since')}); wait for it to finish or stop it"
                + ("" if holder.get("host") == platform.node() else
                   f"; if that run is gone, remove {self.path}"))

    def refuse_if_held(self):
        """Raise the refusal naming the holder if a live writer holds the lock (else nothing).

        Checked before any other look at the directory: a run in progress there
        is not an interrupted one.
        """
        holder = self._holder() if self.path.exists() else None
        mine = holder is not None and (holder.get("pid"), holder.get("host")) == \
            (os.getpid(), platform.node())
        if holder is not None and not mine and not self._stale(holder):
            raise ParameterError(self._busy(holder))

    def _holder(self):
        try:
            holder = json.loads(self.path.read_text())
        except (OSError, ValueError):
            return None   # written by a killed writer mid-way: not a live one
        return holder if isinstance(holder, dict) else None

    def _stale(self, holder):
        if holder.get("host") != platform.node():
            return False
        pid = holder.get("pid")
        return not isinstance(pid, int) or not _alive(pid, holder.get("start"))

    def release(self):
        if self.held:
            try:
                if self._holder() == self.doc:
                    self.path.unlink(missing_ok=True)
            finally:
                self.held = False

    def __enter__(self):
        return self.acquire()

    def __exit__(self, *exc):
        self.release()


def sha256_file(path):
    h = hashlib.sha256()
    with open(path, "rb") as fh:
        for block in iter(lambda: fh.read(_HASH_CHUNK), b""):
            h.update(block)
    return h.hexdigest()


def _expand(folder, names):
    """Every file under the registered names (folders walked), relative, sorted."""
    folder = Path(folder)
    out = set()
    for name in names:
        p = folder / name
        if p.is_dir():
            out.update(str(q.relative_to(folder)) for q in p.rglob("*")
                       if q.is_file() and not q.name.endswith(".tmp"))
        elif p.is_file():
            out.add(str(Path(name)))
    return sorted(out)


def manifest(folder, names):
    """``{relative path: {"bytes", "sha256"}}`` of every file under ``names``."""
    folder = Path(folder)
    return {rel: {"bytes": (folder / rel).stat().st_size, "sha256": sha256_file(folder / rel)}
            for rel in _expand(folder, names)}


def verify(folder, protocol, files=None):
    """The record of ``protocol`` in ``folder``, after checking its digest and manifest.

    ``files`` restricts the check to those relative paths (a reader that needs
    only some).  Raises :class:`ParameterError` naming the missing or changed
    file, or saying that the run is incomplete.
    """
    folder = Path(folder)
    record_path = folder / f"{protocol}.json"
    try:
        record = json.loads(record_path.read_text())
    except FileNotFoundError:
        extra = (" (an interrupted run: rerun with --resume or --force)"
                 if journal_path(folder, protocol).exists() else "")
        raise ParameterError(f"{folder} holds no complete {protocol} result "
                             f"({record_path.name} missing){extra}") from None
    except (OSError, ValueError) as exc:
        raise ParameterError(f"{record_path} is not a readable record: {exc}") from None
    if not isinstance(record, dict):
        raise ParameterError(f"{record_path} is not a readable record: a JSON "
                             f"{type(record).__name__}, not an object; rerun with --force")
    if not _check_record(record, record_path):
        return record   # a record written before manifests existed: nothing to check
    listed = record["files"]
    for rel in (files if files is not None else sorted(listed)):
        if rel not in listed:
            raise ParameterError(f"{folder / rel} is not part of the {protocol} result")
        p = folder / rel
        want = listed[rel]
        if not p.is_file():
            raise ParameterError(f"{p} is missing: the {protocol} result in {folder} is "
                                 "incomplete; rerun with --force")
        size = p.stat().st_size
        if size != want.get("bytes") or sha256_file(p) != want.get("sha256"):
            raise ParameterError(f"{p} does not match the {protocol} record (changed or "
                                 "damaged after the run); rerun with --force")
    return record


def remove_run(folder, protocol):
    """Remove what the last run of ``protocol`` wrote (record, journal, their files); nothing else.

    A complete run's files are those of its manifest: its folders go only
    once empty, so a file put there by someone else stays.  An interrupted
    run (journal) lists its folders, not each file in them: what is in them
    goes, except what was there before the run took the folder (``kept``).
    Returns the removed relative paths.
    """
    folder = Path(folder)
    names, whole, kept, prune = set(), set(), set(), set()
    for path in (folder / f"{protocol}.json", journal_path(folder, protocol)):
        try:
            doc = json.loads(path.read_text())
        except (OSError, ValueError):
            continue
        if not isinstance(doc, dict):
            continue
        listed = doc.get("files")
        if isinstance(listed, dict):
            names.update(str(x) for x in listed)
        elif isinstance(listed, list):
            names.update(str(x) for x in listed)
        folders = [str(x) for x in doc.get("folders", []) if isinstance(x, str)] \
            if isinstance(doc.get("folders"), list) else []
        is_journal = path.name.startswith(".")
        (whole if is_journal or not isinstance(listed, dict) else prune).update(folders)
        if isinstance(doc.get("kept"), list):
            kept.update(str(x) for x in doc["kept"])
    removed = []
    for name in sorted(names, key=len, reverse=True):
        p = folder / name
        if not p.resolve().is_relative_to(folder.resolve()):
            continue   # a hand-edited list must not reach outside the directory
        if name in kept:
            continue
        if p.is_dir() and not p.is_symlink():
            if name not in whole:
                prune.add(name)   # a file's name that is now a folder: not ours
                continue
        elif p.exists() or p.is_symlink():
            p.unlink()
            removed.append(name)
        for tmp in temporaries(p.parent, p.name):
            tmp.unlink(missing_ok=True)
        _prune_empty(p.parent, folder)
    for name in sorted(whole, key=len, reverse=True):
        p = folder / name
        if not p.resolve().is_relative_to(folder.resolve()) or not p.is_dir():
            continue
        remove_run_folder(folder, name, kept)
        prune.add(name)
        removed.append(name)
    for name in sorted(prune, key=len, reverse=True):
        p = folder / name
        if p.resolve().is_relative_to(folder.resolve()) and p.is_dir():
            _prune_empty(p, folder)
    for path in (folder / f"{protocol}.json", journal_path(folder, protocol)):
        if path.exists():
            path.unlink()
            removed.append(path.name)
        for tmp in temporaries(folder, path.name):   # a killed writer's half record
            tmp.unlink(missing_ok=True)
    return removed


def remove_run_folder(folder, name, kept=()):
    """Empty the run's folder ``name`` of ``folder`` but for the relative paths ``kept``.

    The folder goes too once empty.
    """
    folder = Path(folder)
    p = folder / name
    if p.is_symlink() or not p.is_dir():
        return
    for q in sorted(p.rglob("*"), key=lambda q: len(q.parts), reverse=True):
        if str(q.relative_to(folder)) in kept:
            continue
        try:
            if q.is_dir() and not q.is_symlink():
                q.rmdir()   # emptied, unless something kept is in it
            else:
                q.unlink()
        except OSError:
            continue
    _prune_empty(p, folder)


def _prune_empty(path, top):
    """Remove ``path`` and its parents up to ``top`` (excluded) while they are empty."""
    path, top = Path(path).resolve(), Path(top).resolve()
    while path != top and path.is_relative_to(top):
        try:
            path.rmdir()
        except OSError:
            return
        path = path.parent


def write_journal(folder, protocol, fp, names, folders, kept=()):
    """The journal: the run's files and folders, and ``kept``: what its folders held before."""
    write_json(journal_path(folder, protocol),
               {"protocol": protocol, "fingerprint": fp, "files": sorted(names),
                "folders": sorted(folders), "kept": sorted(kept), "pid": os.getpid()})
