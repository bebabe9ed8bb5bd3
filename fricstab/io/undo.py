"""The undo of a refused run: what an ``--out`` directory held before this command wrote.

:class:`Before` is taken by :meth:`fricstab.io.results.ResultDir.create`;
:func:`abandon_all` (the command line calls it before reporting a refusal,
exit 2) removes what the command's result directories added since, so that a
refused run leaves nothing new (see ``docs/howto/result_layout.md``).
"""

import contextlib
import os
from pathlib import Path

from fricstab.io import rundir

__all__ = ["Before", "abandon_all", "entries", "forget_all", "note_removed"]

def entries(folder):
    """Every file and folder under ``folder``, relative, as strings (the folder excluded)."""
    out = set()
    for root, dirs, files in os.walk(folder):
        rel = Path(root).relative_to(folder)
        out.update(str(rel / n) for n in (*dirs, *files))
    return out


def _read_bytes(path):
    try:
        return Path(path).read_bytes()
    except OSError:
        return None


class Before:
    """What an ``--out`` directory held before this command first wrote into it.

    Taken by :meth:`ResultDir.create`; :meth:`undo` removes what the command's
    ResultDirs of the directory added since (their journals, records, the files
    and folders they registered, the index), restores a journal or index they
    changed, releases their lock and removes the directories the command made:
    a refused run leaves nothing new (the files a ``--force`` run removed stay
    removed).
    """

    _all = {}

    @classmethod
    def of(cls, path, made=()):
        key = Path(path).absolute()
        if key not in cls._all:
            cls._all[key] = cls(key, made)
        return cls._all[key]

    #: the index file of a result directory and the function that rebuilds it
    #: (:mod:`fricstab.io.results` sets both: this module does not import it)
    index_name, rebuild_index = "result.json", None

    def __init__(self, path, made):
        self.path, self.made = path, list(made)
        self.tree = set() if made else entries(path)
        self.index = _read_bytes(path / self.index_name)
        self.journals, self.rds = {}, []

    def add(self, rd):
        if rd not in self.rds:
            self.rds.append(rd)
        jp = rundir.journal_path(self.path, rd.name)
        self.journals.setdefault(jp.name, _read_bytes(jp))

    def removed(self):
        """Forget what ``--force`` removed: written again, it is new."""
        if self.tree:
            self.tree &= entries(self.path)

    def _remove_new(self, p):
        """Remove ``p`` and what lies under it, except the paths that were there before."""
        found = [p, *p.rglob("*")] if p.is_dir() and not p.is_symlink() else [p]
        for q in sorted(found, key=lambda q: len(q.parts), reverse=True):
            if str(q.relative_to(self.path)) in self.tree:
                continue
            try:
                if q.is_dir() and not q.is_symlink():
                    q.rmdir()   # emptied: only new entries were under it
                elif q.exists() or q.is_symlink():
                    q.unlink()
            except OSError:
                pass

    def undo(self):
        from fricstab.io.files import temporaries
        if self.path.is_dir():
            names = {rd.record.name for rd in self.rds}
            for rd in self.rds:
                names |= rd._names | rd._folders
            if self.made:   # the directory is this command's: all of it is new
                names |= entries(self.path) - {rundir.LOCK}
            for rel in sorted(names, key=lambda r: len(Path(r).parts), reverse=True):
                p = self.path / rel
                if not p.absolute().is_relative_to(self.path):
                    continue
                for tmp in temporaries(p.parent, p.name) if p.parent.is_dir() else ():
                    tmp.unlink(missing_ok=True)
                self._remove_new(p)
            force = any(rd.force for rd in self.rds)
            for name, old in self.journals.items():
                jp = self.path / name
                if old is None or force:
                    jp.unlink(missing_ok=True)
                elif _read_bytes(jp) != old:
                    jp.write_bytes(old)
            if _read_bytes(self.path / self.index_name) != self.index:
                if force or self.index is None:
                    self.rebuild_index(self.path)
                else:
                    (self.path / self.index_name).write_bytes(self.index)
            for root, dirs, _ in os.walk(self.path, topdown=False):   # new folders left empty
                for d in dirs:
                    q = Path(root) / d
                    if str(q.relative_to(self.path)) not in self.tree:
                        with contextlib.suppress(OSError):
                            q.rmdir()
        for rd in self.rds:
            rd.close()
        for p in self.made:   # deepest first: the directories this command made
            with contextlib.suppress(OSError):
                p.rmdir()


def abandon_all():
    """Undo what this command wrote into its ``--out`` directories (a refused run: exit 2).

    See :class:`Before`; the command line calls it before reporting a refusal.
    """
    for before in list(Before._all.values()):
        before.undo()
    Before._all.clear()


def note_removed(path):
    """``--force`` removed results of ``path``: a refused run need not restore them (and
    what it wrote again under their names is new)."""
    key = Path(path).absolute()
    if key in Before._all:
        Before._all[key].removed()


def forget_all():
    """Drop the notes of :class:`Before` (the command line calls it when a command ends)."""
    Before._all.clear()
