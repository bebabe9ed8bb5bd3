"""Load a written state (``state.npz``) for an analysis: record check, rattlers removed.

:func:`load_state` reads a directory holding ``state.npz`` (or the file),
checks it against the record beside it when there is one (``import.json`` of
``fricstab import``, ``jacobian.json`` of ``fricstab packing jacobian``:
:func:`fricstab.io.rundir.verify`; a changed file is refused naming it), and
rebuilds the System and State (:func:`fricstab.io.jacobian_export.system_from_state`)
with a neighbour list, so that a relaxation finds new contacts.  With
``z_th``, free particles with ``Z <= z_th`` touching contacts are removed
iteratively (:func:`remove_rattlers`; contacts among removed particles do not
count, as in :func:`fricstab.scenes.packing_friction.rattler_mask`; a fixed
particle or a wall is never removed and counts as a neighbour).

The same analyses then run from Python as from ``fricstab packing ... --state``::

    system, state = load_state("imported/", z_th=2)
    fricstab.analysis.rigidity.rigidity(system, state)
"""

import dataclasses
import hashlib
import io
import json
import sys
from pathlib import Path

import numpy as np

from fricstab.errors import ParameterError

__all__ = ["RECORDS", "Loaded", "load_state", "read_state_file", "remove_rattlers"]

NPZ = "state.npz"
#: Records that may list a ``state.npz`` (checked in this order).
RECORDS = ("import", "jacobian")
#: Neighbour-list skin of the rebuilt System, in units of the largest diameter
#: (the packing's :data:`~fricstab.scenes.packing_friction.SKIN` at d = 1).
SKIN_DIAMETERS = 0.1


@dataclasses.dataclass
class Loaded:
    """A loaded state: ``system``, ``state``, where it came from, and the rattlers removed."""

    system: object
    state: object
    source: str
    sha256: str
    record: str            # "import.json", "jacobian.json", or None (used unchecked)
    n_total: int           # particles in the file
    keep: np.ndarray       # file indices of the kept particles
    rattler_force: float   # largest |F| of a removed contact (0: rattlers were free)
    phi: float             # area fraction of every particle of the file (None: not periodic)

    @property
    def rattlers(self):
        return self.n_total - len(self.keep)


def _warn(text):
    print(f"fricstab: warning: {text}", file=sys.stderr)


def _record_of(folder, npz, flag):
    """The name of the record listing ``npz`` after :func:`rundir.verify`, or None (unchecked)."""
    from fricstab.io import rundir
    for name in RECORDS:
        if not (folder / f"{name}.json").exists():
            if rundir.journal_path(folder, name).exists():
                raise ParameterError(f"{flag}: {folder} holds an interrupted {name} run; "
                                     "rerun it")
            continue
        try:
            record = rundir.verify(folder, name)
        except ParameterError as exc:
            raise ParameterError(f"{flag}: {' '.join(str(exc).split())}") from None
        listed = record.get("files")
        if not isinstance(listed, dict):
            continue   # a report without a manifest (written before records): not a check
        if npz.name not in listed:
            raise ParameterError(f"{flag}: {npz} is not part of the {name} result in {folder}")
        return f"{name}.json", listed[npz.name].get("sha256")
    _warn(f"{npz} has no record listing it (import.json or jacobian.json with a manifest): "
          "used unchecked")
    return None, None


def read_state_file(path, flag="--state"):
    """``(npz path, bytes, sha256, record name)`` of a state, checked (module docstring)."""
    path = Path(path).expanduser()
    npz = path / NPZ if path.is_dir() else path
    if not npz.is_file():
        raise ParameterError(f"{flag}: no state file at {npz} (expected a directory with "
                             "state.npz, or a .npz file)")
    record, want = _record_of(npz.parent, npz, flag) if npz.name == NPZ else (None, None)
    data = npz.read_bytes()
    sha = hashlib.sha256(data).hexdigest()
    if want is not None and want != sha:
        raise ParameterError(f"{flag}: {npz} does not match {record} (changed while read); "
                             "rerun")
    return npz, data, sha, record


def _rebuild(path, data, flag):
    """System (with a neighbour list) and State of the bytes of a ``state.npz``."""
    import zipfile

    from fricstab.io.jacobian_export import system_from_state
    try:
        system, state = system_from_state(io.BytesIO(data))
    except (OSError, KeyError, ValueError, IndexError, zipfile.BadZipFile, EOFError) as exc:
        if isinstance(exc, ParameterError):
            raise ParameterError(f"{flag}: {path}: {' '.join(str(exc).split())}") from None
        raise ParameterError(f"{flag}: cannot read a state from {path}: "
                             f"{' '.join(str(exc).split()) or type(exc).__name__}") from None
    skin = SKIN_DIAMETERS * 2 * float(system.radius.max()) if system.n else 0.0
    return _with_neighbours(system, skin), state


def _with_neighbours(system, skin):
    from fricstab.engine import System
    return System(system.material, system.radius, system.mass, system.inertia,
                  family=system.family, lx=system.lx, ly=system.ly, walls=system.walls,
                  external=system.external, neighbours=True, skin=skin)


def touching(system, state):
    """Mask of the listed contacts that overlap (a wall contact counts as touching)."""
    from fricstab.scenes.packing_relax import separations
    c = state.contacts
    sep = separations(system, state)
    j = np.maximum(c.j, 0)
    reach = system.radius[c.i] + system.radius[j]
    return np.where(c.j >= 0, np.hypot(sep[:, 0], sep[:, 1]) < reach, True)


def rattler_mask(system, state, z_th):
    """Free particles with ``Z <= z_th`` touching contacts, removed iteratively."""
    c = state.contacts
    on = touching(system, state)
    n, nw = system.n, len(system.walls)
    i = c.i[on]
    j = np.where(c.j[on] >= 0, c.j[on], n - 1 - c.j[on])   # a wall: node n + w, never removed
    protected = np.concatenate([system.family != 0, np.ones(nw, bool)])
    rattler = np.zeros(n + nw, dtype=bool)
    while True:
        live = ~(rattler[i] | rattler[j])
        z = np.bincount(np.concatenate([i[live], j[live]]), minlength=n + nw)
        new = (z <= z_th) & ~rattler & ~protected
        if not new.any():
            return rattler[:n]
        rattler |= new


def remove_rattlers(system, state, z_th):
    """The sub-System and sub-State without rattlers; ``(system, state, keep, rattler_force)``.

    ``keep``: the indices of the kept particles; ``rattler_force``: the
    largest |F| a removed contact carried (the backbone is out of balance by
    it; the analyses check the balance).
    """
    from fricstab.engine import System
    from fricstab.engine.contacts import Contacts, contact_keys
    rattler = rattler_mask(system, state, z_th)
    keep = np.flatnonzero(~rattler)
    if len(keep) < 2:
        raise ParameterError(f"--z-th: every particle of the state is a rattler (Z <= {z_th})")
    c = state.contacts
    gone = rattler[c.i] | np.where(c.j >= 0, rattler[np.maximum(c.j, 0)], False)
    fc = system.contact_forces(state) if c.n else np.zeros((0, 2))
    force = float(np.hypot(fc[gone, 0], fc[gone, 1]).max()) if gone.any() else 0.0
    if not rattler.any():
        return system, state, keep, force
    new = np.full(system.n, -1, np.int64)
    new[keep] = np.arange(len(keep))
    sub = System(system.material, system.radius[keep], system.mass[keep],
                 system.inertia[keep], family=system.family[keep], lx=system.lx, ly=system.ly,
                 walls=system.walls, external=system.external[keep], neighbours=True,
                 skin=system.skin)
    pos, theta = system.positions(state)
    st = sub.state(pos[keep], theta[keep], shift=float(state.shift))
    k = ~gone
    j = np.where(c.j[k] >= 0, new[np.maximum(c.j[k], 0)], c.j[k])
    st.contacts = Contacts(new[c.i[k]], j.astype(np.int64), c.m[k].copy(), c.k[k].copy(),
                           c.hist[k].copy(), np.zeros(int(k.sum()), np.int8),
                           np.zeros((int(k.sum()), 3)))
    st.keys = contact_keys(st.contacts.i, st.contacts.j, st.contacts.m, st.contacts.k,
                           sub.n, len(sub.walls))
    return sub, st, keep, force


def load_state(path, z_th=None, flag="--state", details=False):
    """The System and State of a written state, checked; rattlers removed when ``z_th`` is given.

    Parameters
    ----------
    path : path-like
        A directory holding ``state.npz`` (with ``import.json`` or
        ``jacobian.json`` beside it: checked), or the ``.npz`` file.
    z_th : int, optional
        Remove free particles with at most ``z_th`` touching contacts, iteratively.
    details : bool
        Return a :class:`Loaded` (source, SHA-256, record, rattlers) instead.

    Returns
    -------
    (system, state), or Loaded
    """
    npz, data, sha, record = read_state_file(path, flag)
    system, state = _rebuild(npz, data, flag)
    n = system.n
    area = system.lx * system.ly
    phi = float(np.pi * np.sum(system.radius ** 2)) / area if area > 0 else None
    keep, force = np.arange(n), 0.0
    if z_th is not None:
        if isinstance(z_th, bool) or not isinstance(z_th, (int, np.integer)) or z_th < 0:
            raise ParameterError(f"z_th must be an integer >= 0, got {z_th!r}")
        system, state, keep, force = remove_rattlers(system, state, int(z_th))
    if not details:
        return system, state
    return Loaded(system, state, str(npz), sha, record, n, keep, force, phi)


def describe(loaded):
    """The ``"state"`` entry of a record made from ``loaded``."""
    mat = loaded.system.material
    return json.loads(json.dumps({
        "source": loaded.source, "sha256": loaded.sha256, "record": loaded.record,
        "law": mat.law, "law_params": {k: float(v) for k, v in dict(mat.params).items()},
        "n": loaded.n_total, "n_backbone": int(loaded.system.n),
        "rattlers": int(loaded.rattlers), "rattler_force": loaded.rattler_force}))
