"""Atomic NPZ checkpoints of long runs, and the lookup of the latest one.

A checkpoint is ``<dir>/ckpt_<step, 12 digits>.npz`` holding the arrays the
run needs to continue (all of its state: positions, velocities, histories,
the frames recorded so far, the step counter ``step``) and a fingerprint: the
JSON of the run's validated parameters, and a SHA-256 of all of it.  A stored
step counter that is not its name's step, or (:meth:`Checkpointer.check_step`)
outside the run's steps, is refused as edited.  Files are written to a temporary
name and renamed, so a run killed at any moment (even by SIGKILL) leaves
complete checkpoints only; the latest ``keep`` are kept.

Resuming a run with other parameters than those of its checkpoint is an
error (:class:`fricstab.laws.ParameterError` naming the first differing key):
the continued run would not be the run that was asked for.  Keys named
``free`` (a stop condition such as the total strain, which ends a run but
does not change its trajectory) may differ: a resumed run may be extended.
"""

import hashlib
import json
import re
import zipfile
from pathlib import Path

import numpy as np

from fricstab.io.files import atomic_write
from fricstab.laws import ParameterError

__all__ = ["Checkpointer"]

_NAME = re.compile(r"^ckpt_(\d{12})\.npz$")


def _digest(arrays):
    """SHA-256 over the names, dtypes, shapes and bytes of ``arrays`` (sorted by name)."""
    h = hashlib.sha256()
    for key in sorted(arrays):
        a = np.ascontiguousarray(arrays[key])
        h.update(f"{key}|{a.dtype.str}|{a.shape}|".encode())
        h.update(a.tobytes())
    return h.hexdigest()


def _check_step(path, step, named):
    """The stored step counter: an integer >= 0 equal to the one in the file's name."""
    a = np.asarray(step) if step is not None else None
    if a is None or a.shape != () or a.dtype.kind not in "iu" or int(a) < 0 or int(a) != named:
        raise ParameterError(f"--resume: the checkpoint {path} holds the step counter "
                             f"{None if a is None else a.tolist()!r}, not its name's step "
                             f"{named} (edited by hand?); rerun with --force")


def _fingerprint_text(fingerprint):
    from fricstab.io.results import json_clean
    return json.dumps(json_clean(fingerprint), sort_keys=True, allow_nan=False)


class Checkpointer:
    """Save and find checkpoints in ``directory``.

    Parameters
    ----------
    directory : path-like
        Folder of the checkpoints (created on the first save).
    fingerprint : dict
        JSON-able parameters of the run; stored with every checkpoint and
        compared on :meth:`latest`.
    keep : int
        Number of most recent checkpoints kept (>= 1).
    free : tuple of str
        Keys of ``fingerprint`` that may differ on :meth:`latest` (stop
        conditions that do not change the trajectory).
    """

    def __init__(self, directory, fingerprint, keep=2, free=()):
        self.directory = Path(directory)
        self.fingerprint = fingerprint
        self._text = _fingerprint_text(fingerprint)
        self.keep = max(1, int(keep))
        self.free = tuple(free)

    def _files(self):
        if not self.directory.is_dir():
            return []
        found = [(int(m.group(1)), p) for p in self.directory.iterdir()
                 if (m := _NAME.match(p.name))]
        return [p for _, p in sorted(found)]

    def save(self, step, **arrays):
        """Write checkpoint ``step`` with ``arrays`` atomically; prune old ones; its path."""
        self.directory.mkdir(parents=True, exist_ok=True)
        path = self.directory / f"ckpt_{int(step):012d}.npz"

        content = {"step": np.int64(step), "fingerprint": np.array(self._text),
                   **{k: np.asarray(v) for k, v in arrays.items()}}

        def write(tmp):
            with open(tmp, "wb") as fh:
                np.savez(fh, checksum=np.array(_digest(content)), **content)

        atomic_write(path, write)
        for old in self._files()[:-self.keep]:
            old.unlink(missing_ok=True)
        return path

    def latest(self, clean=True):
        """The latest readable checkpoint as a dict of arrays (with ``step``), or None.

        ``clean``: remove the temporary files of killed writes first (only
        under the directory's lock: a live writer's temporary file is not ours).
        """
        for p in self._leftovers() if clean else ():
            p.unlink(missing_ok=True)
        for path in reversed(self._files()):
            try:
                with np.load(path, allow_pickle=False) as z:
                    data = {k: z[k] for k in z.files}
            except (OSError, ValueError, KeyError, zipfile.BadZipFile, EOFError):
                continue   # cannot happen with atomic writes; a damaged file is skipped
            checksum = str(data.pop("checksum", ""))
            if checksum != _digest(data):
                raise ParameterError(f"--resume: the checkpoint {path} does not match its "
                                     "checksum (changed after it was written, or written by "
                                     "another version); rerun with --force")
            stored = str(data.pop("fingerprint", ""))
            if stored != self._text and self._difference(stored) is not None:
                raise ParameterError(f"--resume: the checkpoint {path} was made with other "
                                     f"parameters ({self._difference(stored)}); rerun with "
                                     "the same parameters, or use --force to start afresh")
            _check_step(path, data.get("step"), int(_NAME.match(path.name).group(1)))
            data["path"] = str(path)
            return data
        return None

    @staticmethod
    def check_step(data, last, first=0):
        """Refuse a checkpoint (from :meth:`latest`) whose step is outside ``[first, last]``.

        The protocol's own bound: a step counter edited past the end of the
        run (or before its start) would resume another run than the one asked for.
        """
        step = int(data["step"])
        if not first <= step <= last:
            raise ParameterError(f"--resume: the checkpoint {data.get('path')} is at step "
                                 f"{step}, outside this run's steps {first}..{last} (edited "
                                 "by hand?); rerun with --force")

    def _difference(self, stored):
        """The first differing key outside ``free`` in words, or None when there is none."""
        try:
            old = json.loads(stored)
        except ValueError:
            return "unreadable fingerprint"
        new = json.loads(self._text)
        if isinstance(old, dict) and isinstance(new, dict):
            for key in sorted(set(old) | set(new)):
                if key not in self.free and old.get(key) != new.get(key):
                    return f"{key}: {old.get(key)!r} there, {new.get(key)!r} now"
            return None
        return "different fingerprint"

    def _leftovers(self):
        """Temporary files of writes killed mid-way (SIGKILL); never complete checkpoints."""
        if not self.directory.is_dir():
            return []
        return [p for p in self.directory.glob(".ckpt_*.tmp")]

    def clear(self):
        """Remove every checkpoint (after the result is complete)."""
        for p in self._files() + self._leftovers():
            p.unlink(missing_ok=True)
        try:
            self.directory.rmdir()
        except OSError:
            pass
