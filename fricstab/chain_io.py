"""Scene files (TOML), atomic result writing and the Jacobian export of the chain.

Scene file keys (all optional, defaults of :class:`fricstab.chain.ChainScene`):
``n, radius, mass, kn, kt, mu, fy, fx, inertia``, either at the top level or
under a ``[chain]`` table.  An unknown key is an error naming it.

Results are written atomically: to a temporary file in the same directory,
then renamed, so an interrupted run leaves either no file or a complete one.
"""

import os
import tempfile
import tomllib
from dataclasses import fields
from pathlib import Path

import numpy as np

from fricstab.chain import ChainScene, contacts
from fricstab.laws import ParameterError

__all__ = ["atomic_write", "export_state", "load_scene"]

_KEYS = {f.name for f in fields(ChainScene)}


def load_scene(path, **overrides):
    """A :class:`ChainScene` from a TOML file, then ``overrides`` (not None)."""
    values = {}
    if path is not None:
        try:
            data = tomllib.loads(Path(path).read_text())
        except FileNotFoundError:
            raise ParameterError(f"scene file {path} does not exist") from None
        except tomllib.TOMLDecodeError as exc:
            raise ParameterError(f"scene file {path}: {exc}") from None
        data = data.get("chain", data)
        for key, value in data.items():
            if key not in _KEYS:
                raise ParameterError(f"scene file {path}: unknown key {key!r}; "
                                     f"known: {', '.join(sorted(_KEYS))}")
            values[key] = value
    values.update({k: v for k, v in overrides.items() if v is not None})
    return ChainScene(**values)


def atomic_write(path, write):
    """Call ``write(tmp_path)``, then rename onto ``path`` (same directory)."""
    path = Path(path)
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    os.close(fd)
    try:
        write(tmp)
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(tmp, 0o666 & ~umask)  # mkstemp creates 0600
        os.replace(tmp, path)
    finally:
        if os.path.exists(tmp):
            os.unlink(tmp)


def export_state(scene, state, jac, out_dir):
    """Write ``state.npz`` (q, contacts, t) and ``jacobian.npy`` into ``out_dir``.

    ``q`` (N x 3: x, y, theta), ``contacts`` (K x 2, second index -1 for the
    wall), ``t`` (K x 2: for a pair (i, j) the displacement of i relative to j
    in the lab frame; for the wall (t_x, 0)), ``jacobian.npy`` the 3N x 3N
    unscaled dF/dq, rows (F_x, F_y, T) and columns (x, y, theta) per disk.
    """
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    t = np.vstack([state.t_pair, np.column_stack([state.t_wall, np.zeros(scene.n)])])
    params = {f.name: getattr(scene, f.name) for f in fields(ChainScene)}

    def write_npz(tmp):
        with open(tmp, "wb") as fh:
            np.savez(fh, q=state.q, contacts=contacts(scene), t=t,
                     **{f"param_{k}": v for k, v in params.items()})

    def write_npy(tmp):
        with open(tmp, "wb") as fh:
            np.save(fh, jac)

    atomic_write(out / "state.npz", write_npz)
    atomic_write(out / "jacobian.npy", write_npy)
