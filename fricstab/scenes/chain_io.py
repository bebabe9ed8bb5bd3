"""Scene files (TOML), atomic result writing and the Jacobian export of the chain.

Scene file keys (all optional, defaults of :class:`fricstab.scenes.chain.ChainScene`):
``n, radius, mass, kn, kt, mu, fy, fx, inertia``, either at the top level or
under a ``[chain]`` table; the schema (types, units, ranges) is
:data:`CHAIN_SCHEMA` (``fricstab scene show chain``).  An unknown key, a
wrong type or a value out of range is an error naming it.

Results are written atomically: to a temporary file in the same directory,
then renamed, so an interrupted run leaves either no file or a complete one.
"""

from dataclasses import fields
from pathlib import Path

import numpy as np

from fricstab.io.files import atomic_write
from fricstab.scenes.chain import ChainScene, contacts
from fricstab.io.scenes import Field, Schema, register, resolve

__all__ = ["CHAIN_SCHEMA", "export_state", "load_scene", "scene_parameters"]

# Units: Charan's, length 2R = 1 (R = 0.5), m = 1; forces in kn (2R)^(3/2) units.
CHAIN_SCHEMA = register(Schema("chain", "chain of disks on a flat substrate (Charan et al.)", (
    Field("n", "int", 10, "-", "number of disks (periodic ring in x, period 2 N R)",
          low=2, high=2000),
    Field("radius", "float", 0.5, "length", "disk radius R (2R = 1 is Charan's length unit)",
          low=0.0, low_open=True, cli=""),
    Field("mass", "float", 1.0, "mass", "disk mass m", low=0.0, low_open=True, cli=""),
    Field("kn", "float", 2000.0, "force/length^(3/2)", "Hertz normal stiffness k_n (Eq. 1)",
          low=0.0, low_open=True, cli=""),
    Field("kt", "float", None, "force/length^(3/2)", "tangential stiffness k_t (Eq. 2)",
          low=0.0, low_open=True, default_doc="2 kn / 7", cli=""),
    Field("mu", "float", 10.0, "-", "friction coefficient of the smoothed Coulomb law (Eq. 5)",
          low=0.0, low_open=True),
    Field("fy", "float", 0.1, "force", "pressing force F_y on every disk", low=0.0,
          low_open=True),
    Field("fx", "float", 0.0, "force", "pushing force F_x on disk 0 (ramp, jacobian, dynamics set it: --fx)",
          cli=""),
    Field("inertia", "float", None, "mass length^2", "moment of inertia I",
          low=0.0, low_open=True, default_doc="m R^2 / 2 (uniform disk)"),
)))


def scene_parameters(path, **overrides):
    """Validated chain scene keys (defaults filled): TOML ``path``, then ``overrides``."""
    return resolve("chain", path, overrides)


def load_scene(path, **overrides):
    """A :class:`ChainScene` from a TOML file, then ``overrides`` (not None), validated."""
    values = scene_parameters(path, **overrides)
    return ChainScene(**{k: v for k, v in values.items() if v is not None})


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
