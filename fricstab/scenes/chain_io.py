"""Scene files (TOML) and the state/Jacobian export of the chain.

Scene file keys (all optional, defaults of :class:`fricstab.scenes.chain.ChainScene`):
``n, radius, mass, fy, fx, inertia``, the contact law ``law`` (default
``charan``) and that law's parameters (``kn, kt, mu`` for charan; ``fricstab
laws``), either at the top level or under a ``[chain]`` table; the schema
(types, units, ranges, every law's defaults) is :data:`CHAIN_SCHEMA`
(``fricstab scene show chain``).  An unknown key, a parameter of another
law, a wrong type or a value out of range is an error naming it.

Export (:func:`export_state`): the common files of every scene
(:func:`fricstab.io.jacobian_export.write_state_jacobian`: ``state.npz``,
``jacobian.npz``, ``dofs.json``, ``mass.npy``) and, for compatibility with
the pre-engine chain export, ``jacobian.npy`` (the dense dF/dq) and the
legacy keys ``q`` and ``t`` of ``state.npz`` (:func:`legacy_arrays`).
Every file is written atomically.
"""

from pathlib import Path

import numpy as np

from fricstab.io.files import atomic_write
from fricstab.io.jacobian_export import write_state_jacobian
from fricstab.io.scenes import (SCALE_DOC, Derived, Field, LawChoice, Schema, in_scale_window,
                                register, resolve)
from fricstab.scenes.chain import (LAW_DEFAULTS, LAW_DOCS, LAW_UNITS, ChainScene, chain_system,
                                   legacy_order, refusal, time_unit)

__all__ = ["CHAIN_SCHEMA", "UNITS", "export_state", "legacy_arrays", "load_scene",
           "scene_from_values", "scene_parameters"]


def _law_choice():
    defaults = {law: {k: (Derived(v[1], v[0]) if isinstance(v, tuple) else v)
                      for k, v in table.items()} for law, table in LAW_DEFAULTS.items()}
    return LawChoice(default="charan", defaults=defaults, docs=LAW_DOCS, units=LAW_UNITS,
                     refuse=refusal)


# Units: Charan's, length 2R = 1 (R = 0.5), m = 1; forces in kn (2R)^(3/2) units.
_WHY = "in [1e-30, 1e30] (beyond it the products of the scene's scales leave float64)"
CHAIN_SCHEMA = register(Schema("chain", "chain of disks on a flat substrate (Charan et al.)", (
    Field("n", "int", 10, "-", "number of disks (periodic ring in x, period 2 N R)",
          low=2, high=2000),
    Field("radius", "float", 0.5, "length", "disk radius R (2R = 1 is Charan's length unit)",
          low=0.0, low_open=True, check=in_scale_window, check_doc=_WHY, cli=""),
    Field("mass", "float", 1.0, "mass", "disk mass m", low=0.0, low_open=True,
          check=in_scale_window, check_doc=_WHY, cli=""),
    Field("fy", "float", 0.1, "force", "pressing force F_y on every disk", low=0.0,
          low_open=True, check=in_scale_window, check_doc=_WHY),
    Field("fx", "float", 0.0, "force", "pushing force F_x on disk 0 (ramp, jacobian, dynamics set it: --fx)",
          check=in_scale_window, check_doc=SCALE_DOC, cli=""),
    Field("inertia", "float", None, "mass length^2", "moment of inertia I",
          low=0.0, low_open=True, check=in_scale_window, check_doc=_WHY,
          default_doc="m R^2 / 2 (uniform disk)"),
), laws=_law_choice()))

#: Unit names of the chain's files (dofs.json).
UNITS = {"length": "2R = 1 (Charan)", "mass": "m = 1", "force": "kn (2R)^(3/2) with kn = 2000",
         "time": "simulation units sqrt(m/kn) for kn = 1; Charan's unit is sqrt(m 2R/kn)"}


def scene_parameters(path, **overrides):
    """Validated chain scene keys (defaults filled): TOML ``path``, then ``overrides``.

    Returns the scene keys with ``law``, ``law_params`` and ``wall_params``
    (:func:`fricstab.io.scenes.validate`).
    """
    return resolve("chain", path, overrides)


def scene_from_values(values, **changes):
    """A :class:`ChainScene` from validated values (:func:`scene_parameters`)."""
    keys = {k: values[k] for k in ("n", "radius", "mass", "fy", "fx", "inertia")
            if values.get(k) is not None}
    keys.update(changes)
    return ChainScene(law=values["law"], params=dict(values["law_params"]),
                      wall_params=dict(values["wall_params"]), **keys)


def load_scene(path=None, **overrides):
    """A :class:`ChainScene` from a TOML file (or None), then ``overrides``, validated.

    ``overrides`` take scene keys, ``law`` and law parameters, e.g.
    ``load_scene(None, n=20, law="ishima", kt=500.0)``.
    """
    return scene_from_values(scene_parameters(path, **overrides))


def legacy_arrays(scene, state):
    """The pre-engine keys of ``state.npz``: ``q`` (N x 3) and ``t`` (2N x 2).

    ``q``: x, y, theta (radians, counter-clockwise; physical theta for every
    law).  ``t``: one row per contact in the pre-engine order (ring pairs
    (i, i+1 mod N), then the wall contacts of disks 0..N-1): for charan and
    ishima (and linear) the tangential displacement of i relative to i+1 in the lab frame
    (a wall row (t_x, 0)); for lee_hurley the stored (ft, mr); zeros for a
    frictionless law.
    """
    pos, theta = chain_system(scene).positions(state)
    rows, sign = legacy_order(state)
    h = state.contacts.hist[rows]
    t = np.zeros((len(rows), 2))
    t[:, :h.shape[1]] = h
    if scene.law in ("charan", "ishima", "linear"):
        t *= sign[:, None]
    return {"q": np.column_stack([pos, theta]), "t": t}


def export_state(scene, state, out_dir, extra=None):
    """Write the common files, ``jacobian.npy`` and the legacy keys into ``out_dir``.

    Returns the forces of the free dof (flat) and the sparse Jacobian.
    """
    system = chain_system(scene)
    info = {"scene": "chain", "law": scene.law, "law_params": scene.params,
            "wall_params": scene.wall_params, "fx": scene.fx, "fy": scene.fy,
            "time_unit_charan": time_unit(scene),
            "legacy": "state.npz keys q (N x 3: x, y, theta) and t (2N x 2, ring pairs "
                      "(i, i+1 mod N) then walls, i relative to i+1), jacobian.npy (dense "
                      "dF/dq in the order of rows_and_columns)", **(extra or {})}
    f, k = write_state_jacobian(out_dir, system, state, units=UNITS, extra=info,
                                extra_arrays=legacy_arrays(scene, state))
    dense = k.toarray()

    def write_npy(tmp):
        with open(tmp, "wb") as fh:
            np.save(fh, dense)

    atomic_write(Path(out_dir) / "jacobian.npy", write_npy)
    return f, k
