"""The packing of a ``fricstab packing`` command: read, reused or made, and one per directory.

A directory holds at most one packing, the ``packing`` record (``packing.json``
with ``packing.npz``, and ``packing.png`` from ``make``), and every
``rigidity``, ``dos`` and ``jacobian`` result in it was computed from that
packing: their records name it under ``"packing"`` (``source``, ``origin``
``read|reused|made``, the SHA-256 of ``packing.npz``, its make parameters).

Reading (``--packing DIR`` or ``DIR/packing.npz``): the packing record of
``DIR`` is checked against its manifest (:func:`fricstab.io.rundir.verify`): a
missing, changed or damaged file, or an interrupted run, is refused (exit 2,
naming the file).  A record written before manifests existed, or a
``packing.npz`` without a record, is used with a one-line warning; any other
``.npz`` file is the user's and is used as it is.

Making (no ``--packing``): a packing record already in ``--out`` whose make
parameters (:data:`MAKE_KEYS`) are the run's, and whose files are intact, is
reused; any other packing there is refused naming the first differing
parameter, or with ``--force`` replaced (record and files together, through
its own :class:`~fricstab.io.results.ResultDir` sharing the run's lock).

A result in ``--out`` made from another packing than the run's is refused, or
with ``--force`` removed (one line on stderr names it), so a directory never
mixes two packings.
"""

import hashlib
import io
import json
import shutil
import sys
from pathlib import Path

from fricstab.cli.packing_common import MAKE_KEYS, UNITS_NOTE, new_packing, public, save_packing
from fricstab.io import rundir
from fricstab.io.files import json_clean
from fricstab.laws import ParameterError

__all__ = ["DEPENDENTS", "NPZ", "Opened", "Source", "conflicts", "make_params", "open_run", "plan",
           "read", "refuse", "remove", "reuse"]

PACKING, NPZ = "packing", "packing.npz"
DEPENDENTS = ("rigidity", "dos", "jacobian", "aqs")
#: What a dependent wrote before records listed their files.
_LEGACY = {"rigidity": ("rigidity.png",), "dos": ("dos.npz", "dos.png"),
           "jacobian": ("state.npz", "jacobian.npz", "dofs.json", "mass.npy")}


class Source:
    """The packing a run uses: the object, where it came from, the SHA-256 of its file."""

    def __init__(self, packing, source, origin, sha256, params):
        self.packing, self.source, self.origin = packing, source, origin
        self.sha256, self.params = sha256, params

    def record(self):
        """The ``"packing"`` entry of a dependent record."""
        return {"source": self.source, "origin": self.origin, "sha256": self.sha256,
                "parameters": self.params}


def make_params(params):
    """The parameters that decide ``packing.npz`` (JSON-clean, comparable to a record's)."""
    return json_clean({k: params[k] for k in MAKE_KEYS})


def _record_params(record):
    """The make parameters of a packing record (its fingerprint's, else its parameters)."""
    fp = record.get("fingerprint")
    have = fp.get("parameters") if isinstance(fp, dict) else None
    have = have if isinstance(have, dict) else record.get("parameters")
    return {k: have.get(k) for k in MAKE_KEYS} if isinstance(have, dict) else None


def _warn(text):
    print(f"fricstab: warning: {text}", file=sys.stderr)


def _load(path, data, flag="--packing"):
    import zipfile

    from fricstab.scenes.packing import Packing
    try:
        return Packing.load(io.BytesIO(data))
    except (OSError, KeyError, ValueError, zipfile.BadZipFile, EOFError) as exc:
        why = ("not an NPZ archive" if "pickled" in str(exc) or "pickle" in str(exc)
               else " ".join(str(exc).split()))
        raise ParameterError(f"{flag}: cannot read a packing from {path}: {why}") from None


def _checked(folder, npz, flag):
    """The packing record of ``folder`` after checking every file it lists, or None (legacy)."""
    has_record = (folder / f"{PACKING}.json").exists()
    if not has_record and not rundir.journal_path(folder, PACKING).exists():
        if npz.is_file():
            _warn(f"{npz} has no packing record beside it (written before fricstab kept "
                  "one): used unchecked")
        return None
    try:
        record = rundir.verify(folder, PACKING)
    except ParameterError as exc:
        raise ParameterError(f"{flag}: {exc}") from None
    listed = record.get("files")
    if not isinstance(listed, dict):
        _warn(f"{folder / 'packing.json'} has no manifest (written before fricstab checked "
              "its files): packing.npz used unchecked")
    elif npz.name not in listed:
        raise ParameterError(f"{flag}: {npz} is not part of the packing result in {folder}")
    return record


def _read_bytes(npz, record, flag):
    """The file's bytes, checked once more against the manifest (what is loaded is what was checked)."""
    data = npz.read_bytes()
    sha = hashlib.sha256(data).hexdigest()
    want = ((record or {}).get("files") or {}).get(npz.name)
    if isinstance(want, dict) and want.get("sha256") != sha:
        raise ParameterError(f"{flag}: {npz} does not match the packing record (changed "
                             "while read); rerun")
    return data, sha


def read(path):
    """``--packing DIR|FILE.npz``: the checked packing (module docstring)."""
    path = Path(path).expanduser()
    npz = path / NPZ if path.is_dir() else path
    record = None
    if path.is_dir() or (npz.name == NPZ and npz.parent.is_dir()):
        record = _checked(npz.parent, npz, "--packing")   # a record or journal: checked first
    if not npz.is_file():
        raise ParameterError(f"--packing: no packing file at {npz} "
                             "(expected a directory with packing.npz, or a .npz file)")
    data, sha = _read_bytes(npz, record, "--packing")
    packing = _load(npz, data)
    params = _record_params(record) if record else None
    return Source(packing, str(npz), "read", sha,
                  params or {"n": packing.n, "phi": packing.phi, "seed": packing.seed})


def plan(out, want, force):
    """The packing record of ``--out`` for a run that makes its packing with ``want``.

    Returns the record to reuse, or None: make a packing (replacing what is there,
    which ``force`` allows).  Raises :class:`ParameterError` (one line) otherwise.
    """
    out = Path(out).expanduser()
    if (out / f"{PACKING}.json").exists():
        try:
            record = rundir.verify(out, PACKING)
        except ParameterError:
            if force:
                return None
            raise
        have = _record_params(record)
        if have == want:
            if not isinstance(record.get("files"), dict):
                _warn(f"{out / 'packing.json'} has no manifest (written before fricstab "
                      "checked its files): packing.npz reused unchecked")
            return record
        if force:
            return None
        diff = rundir.difference({"parameters": have}, {"parameters": want})
        raise ParameterError(f"--out: {out} holds a packing made with other parameters "
                             f"({diff}); use --force to replace it and the results made "
                             f"from it, --packing {out} to use it, or another --out")
    if rundir.journal_path(out, PACKING).exists() and not force:
        raise ParameterError(f"--out: {out} holds an interrupted packing run; use --force to "
                             "replace it")
    if (out / NPZ).exists() and not force:
        raise ParameterError(f"--out: {out} holds packing.npz without a packing record "
                             f"(written before fricstab kept one); use --packing {out} to "
                             "use it, or --force to replace it")
    return None


def reuse(out, record):
    """The packing of ``--out`` described by ``record`` (from :func:`plan`)."""
    npz = Path(out).expanduser() / NPZ
    data, sha = _read_bytes(npz, record, "--out")
    return Source(_load(npz, data, "--out"), NPZ, "reused", sha, _record_params(record))


def _dependent_sha(record, out):
    """The SHA-256 of the packing a dependent record was made from; None: not a packing result."""
    entry = record.get("packing") or record.get("state")   # "state": a --state run
    if isinstance(entry, dict) and entry.get("sha256"):
        return entry["sha256"]
    source = record.get("packing_source")   # a record from before "packing" was kept
    if not isinstance(source, str):
        return None
    p = out / NPZ if source.startswith("made by") else Path(source).expanduser()
    p = p / NPZ if p.is_dir() else p
    try:
        return rundir.sha256_file(p)
    except OSError:
        return "unknown (its packing is gone)"


def conflicts(out, protocol, sha=None, new=False):
    """The results of ``--out`` not made from the run's packing (``sha``; ``new``: a new one).

    ``protocol``'s own record is left to its ResultDir.  Returns the protocol
    names (with ``"packing"`` when the directory's packing is another).
    """
    out = Path(out).expanduser()
    found = []
    for name in (PACKING, *DEPENDENTS):
        if name == protocol or (name == PACKING and new):
            continue   # a new packing replaces the record through its own ResultDir
        try:
            record = json.loads((out / f"{name}.json").read_text())
        except (OSError, ValueError):
            continue
        if name == PACKING:
            entry = (record.get("files") or {}).get(NPZ) if isinstance(record.get("files"),
                                                                        dict) else None
            have = entry.get("sha256") if isinstance(entry, dict) else \
                _dependent_sha({"packing_source": "made by"}, out)
        else:
            have = _dependent_sha(record, out)
        if have is not None and (new or have != sha):
            found.append(name)
    return found


def refuse(out, found, detail=None):
    """Raise for results of ``--out`` made from another packing (without ``--force``)."""
    if found:
        names = ", ".join(f"{n}.json" for n in found)
        them = "them" if len(found) > 1 else "it"
        raise ParameterError(f"--out: {out} holds results of another packing ({names}"
                             f"{'; ' + detail if detail else ''}); use another --out, or "
                             f"--force to remove {them}")


def remove(out, found, why):
    """Remove the results ``found`` (record and files; a legacy one's usual files); one line."""
    from fricstab.io.results import note_removed, update_index
    out = Path(out)
    for name in found:
        try:
            record = json.loads((out / f"{name}.json").read_text())
        except (OSError, ValueError):
            record = {}
        if not isinstance(record.get("files"), dict):   # no manifest: its usual names
            legacy = list(_LEGACY.get(name, ()))
            if name == "rigidity":
                legacy += [r.get("folder") for r in record.get("results", [])
                           if isinstance(r, dict) and isinstance(r.get("folder"), str)]
            for rel in legacy:
                q = out / rel
                if not q.resolve().is_relative_to(out.resolve()):
                    continue
                if q.is_dir():
                    shutil.rmtree(q, ignore_errors=True)
                elif q.is_file():
                    q.unlink()
        rundir.remove_run(out, name)
    if found:
        update_index(out)
        note_removed(out)
        print(f"fricstab: note: removed {', '.join(n + '.json' for n in found)} and "
              f"{'their' if len(found) > 1 else 'its'} files from {out} ({why})",
              file=sys.stderr)


class Opened:
    """A rigidity, dos or jacobian run, checked (:func:`open_run`) and not yet started.

    ``rd`` is the run's :class:`~fricstab.io.results.ResultDir`; :meth:`start`
    takes the lock, removes the results made from another packing (``--force``),
    and returns the :class:`Source`, making and recording the packing if needed.
    """

    def __init__(self, rd, made, source, found, want):
        self.rd, self._made, self.source, self._found, self._want = rd, made, source, found, want

    def start(self, argv, progress=False):
        rd = self.rd.create()
        remove(rd.path, self._found, "made from another packing than this run's")
        if self._made is None:
            if self.source.origin == "reused" and \
                    rundir.sha256_file(rd.path / NPZ) != self.source.sha256:
                raise ParameterError(f"--out: {rd.path / NPZ} changed while this run started; "
                                     "rerun")
            return self.source
        prd = self._made.create()
        with prd.stage("make"):
            packing = new_packing(self._want, progress)
        prd.write_with(NPZ, save_packing(packing))
        doc = prd.finish({"n": packing.n, "phi": packing.phi, "box": packing.box,
                          "phi_start": packing.info.get("phi_start"), "info": packing.info,
                          "made_by": f"fricstab packing {self.rd.name}", "units": UNITS_NOTE},
                         parameters=self._want, seed=packing.seed, argv=argv)
        self.source = Source(packing, NPZ, "made", doc["files"][NPZ]["sha256"], self._want)
        return self.source


def open_run(ns, params, protocol, outputs, extra):
    """Every check of a run of ``protocol`` into ``--out`` before anything is written.

    The fingerprint is the resolved parameters with ``extra``; with
    ``--packing``, the SHA-256 of the packing read replaces the make parameters
    (``f_tol`` stays: the relaxations use it).  ``outputs``: the names of the
    protocol's files (a result from before manifests existed).
    """
    from fricstab.io.results import ResultDir
    given = getattr(ns, "packing", None)
    want = make_params(params)
    fp = {**public(params), **extra}
    source = read(given) if given is not None else None
    if source is not None:
        fp = {k: v for k, v in fp.items() if k not in MAKE_KEYS or k == "f_tol"}
        fp["packing_sha256"] = source.sha256
    rd = ResultDir(ns.out, protocol, force=ns.force, outputs=outputs, fingerprint=fp)
    if source is None:
        record = plan(rd.path, want, ns.force)
        source = reuse(rd.path, record) if record is not None else None
    found = conflicts(rd.path, protocol, sha=source and source.sha256, new=source is None)
    if not ns.force:
        refuse(rd.path, found, _detail(rd.path, source) if PACKING in found else None)
    made = None if source is not None else ResultDir(
        rd.path, PACKING, force=ns.force, within=rd, outputs=(NPZ, "packing.png"),
        fingerprint=want)
    return Opened(rd, made, source, found, want)


def _detail(out, source):
    """The first make parameter in which the packing of ``out`` differs from ``source``'s."""
    try:
        have = _record_params(json.loads((out / f"{PACKING}.json").read_text()))
    except (OSError, ValueError):
        return None
    if not have or not source.params or have == source.params:
        return None
    return rundir.difference({"parameters": have}, {"parameters": source.params})
