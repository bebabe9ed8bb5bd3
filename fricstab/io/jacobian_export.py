"""The state and the assembled Jacobian of any scene, as files anyone can re-check.

:func:`write_state_jacobian` writes, atomically, into a directory:

``state.npz``
    ``pos`` (N, 2), ``theta`` (N,) (radians, counter-clockwise), ``radius``,
    ``mass``, ``inertia`` (N,), ``family`` (N,) (0 free, 1 fixed, 2 driven),
    ``box`` (2,) ``(lx, ly)`` with 0 for an open direction, ``le_offset`` (the
    Lees-Edwards shift of the image above), ``contacts`` (K, 2) ``(i, j)``
    with ``j = -1`` for a wall, ``images`` (K, 2) ``(m, k)``: the separation
    of a pair is ``r_i - r_j - m (lx, 0) - k (le_offset, ly)``, ``walls``
    (W, 2) ``(y0, direction)``, ``wall_of`` (K,) (the wall of a wall contact,
    -1 for a pair), ``history`` (K, h), ``law`` (its name), ``param_names``
    and ``param_values`` (the pair law's, then the wall form's extra ones),
    ``external`` (N, 3) the applied generalized forces (``param_names`` has the
    wall form's own parameters, e.g. ``Rw``, only where the scene has a wall);
``jacobian.npz``
    ``K = dF/dq`` over the free particles' dof, with the histories advanced by
    the increment rule (``scipy.sparse.save_npz``, CSR);
``dofs.json``
    the order of the rows and columns (``[particle, coordinate]`` each), the
    sign convention, the coordinates and their units, so that the matrix can
    be recomputed from ``state.npz`` alone;
``mass.npy``
    the diagonal of the mass matrix in the dof order (``m, m, I/s^2``).
"""

import json

import numpy as np
import scipy.sparse as sps

from fricstab.engine.jacobian import dof_labels, jacobian
from fricstab.io.files import atomic_write

__all__ = ["FILES", "read_state", "system_from_state", "write_state_jacobian"]

FILES = ("state.npz", "jacobian.npz", "dofs.json", "mass.npy")

_ROTATION = {
    "theta": ("theta", "radian", "torque T"),
    "l": ("l = R theta", "length", "T / R (Ishima's F^l)"),
    "": (None, None, None),
}


def write_state_jacobian(out_dir, system, state, units=None, extra=None, extra_arrays=None):
    """Write a state and its Jacobian: ``state.npz``, ``jacobian.npz``, ``dofs.json``, ``mass.npy``.

    The files of ``fricstab SCENE jacobian``:
    ``state.npz`` holds everything :func:`system_from_state` needs to rebuild
    the System and State; ``jacobian.npz`` is ``K = dF/dq`` over the free dof
    (``scipy.sparse.save_npz``, histories advanced by the increment rule);
    ``dofs.json`` names each row and column (particle, coordinate), the sign
    convention and the units; ``mass.npy`` is the diagonal of the mass matrix
    in that order.  Files are written atomically.

    Parameters
    ----------
    out_dir : path-like
        Existing directory.
    system : System
    state : State
    units : dict, optional
        Maps ``length``, ``mass``, ``time``, ``force`` to the scene's unit names
        (written into ``dofs.json``).
    extra : dict, optional
        Keys added to ``dofs.json``.
    extra_arrays : dict, optional
        Arrays added to ``state.npz`` (a scene's own keys, e.g. the chain's
        legacy ``q`` and ``t``; they may not replace the common ones).

    Returns
    -------
    f : ndarray
        Generalized forces of the free dof.
    K : scipy.sparse.csr_matrix
        The Jacobian written.
    """
    from pathlib import Path
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    f, k = jacobian(system, state)
    pos, theta = system.positions(state)
    c = state.contacts
    mat = system.material
    names, values = list(mat.info.params), list(system._p)
    if len(system.walls):   # the wall form's own parameters (lee_hurley's Rw) where it is used
        names += list(mat.info.wall_form().params[len(names):])
        values += list(system._pw[len(system._p):])
    arrays = dict(pos=pos, theta=theta, radius=system.radius, mass=system.mass,
                  inertia=system.inertia, family=system.family,
                  box=np.array([system.lx, system.ly], float), le_offset=float(state.shift),
                  contacts=np.column_stack([c.i, np.where(c.j >= 0, c.j, -1)]),
                  images=np.column_stack([c.m, c.k]), walls=system.walls,
                  wall_of=np.where(c.j >= 0, -1, -1 - c.j), history=c.hist,
                  law=np.array(mat.law), param_names=np.array(names),
                  param_values=np.array(values, float), external=system.external)
    clash = set(extra_arrays or {}) & set(arrays)
    if clash:
        raise ValueError(f"extra_arrays may not replace the common keys {sorted(clash)}")
    arrays.update(extra_arrays or {})
    rot_name, rot_unit, rot_force = _ROTATION[mat.rotation]
    free = system.family == 0
    gm = system.gmass[free, :system.dof].ravel()
    doc = {
        "rows_and_columns": dof_labels(system),
        "n_dof": int(k.shape[0]),
        "sign": "K = dF/dq (Charan's sign); Ishima's Jacobian (Eq. 18) is -K",
        "history": "derivatives include the tangential history advanced by the law's "
                   "increment rule (and the caps of a sliding contact)",
        "coordinates": {"x": "length", "y": "length",
                        **({rot_name: rot_unit} if rot_name else {})},
        "forces": {"x": "F_x", "y": "F_y", **({rot_name: rot_force} if rot_name else {})},
        "law": mat.law, "dof_per_particle": system.dof,
        "clamped": "particles with family != 0 (fixed, driven) carry no dof",
        "mass_matrix": "diag(m, m, I / s^2) with s = 1 (theta) or R (l = R theta): mass.npy",
        "units": units or {},
        "max_abs_force_on_free_dof": float(np.abs(f).max()) if f.size else 0.0,
    }
    if extra:
        doc.update(extra)

    def npz(path):
        with open(path, "wb") as fh:
            np.savez(fh, **arrays)

    def jac(path):
        with open(path, "wb") as fh:
            sps.save_npz(fh, k.tocsr())

    def js(path):
        with open(path, "w") as fh:
            json.dump(doc, fh, indent=1)
            fh.write("\n")

    def mass(path):
        with open(path, "wb") as fh:
            np.save(fh, gm)

    atomic_write(out / "state.npz", npz)
    atomic_write(out / "jacobian.npz", jac)
    atomic_write(out / "dofs.json", js)
    atomic_write(out / "mass.npy", mass)
    return f, k


def read_state(path):
    """The arrays of a ``state.npz`` as a dict (strings as Python str)."""
    with np.load(path) as z:
        d = {key: z[key] for key in z.files}
    d["law"] = str(d["law"])
    d["param_names"] = [str(x) for x in d["param_names"]]
    return d


def system_from_state(path):
    """The System and State written in a ``state.npz``: recompute anything from the file alone.

    The contacts (with their images and histories) are those of the file, in
    its order, so ``fricstab.jacobian(*system_from_state(p))`` gives the saved
    ``jacobian.npz`` to the bit.

    Parameters
    ----------
    path : path-like
        A ``state.npz`` written by :func:`write_state_jacobian`.

    Returns
    -------
    system : System
    state : State
    """
    from fricstab.engine import Material, System
    from fricstab.engine.contacts import Contacts, contact_keys
    from fricstab.laws import get_law
    d = read_state(path)
    info = get_law(d["law"])
    n_pair = len(info.params)
    names, values = d["param_names"], [float(v) for v in d["param_values"]]
    material = Material(d["law"], dict(zip(names[:n_pair], values[:n_pair])),
                        dict(zip(names[n_pair:], values[n_pair:])))
    lx, ly = (float(v) for v in d["box"])
    system = System(material, d["radius"], d["mass"], d["inertia"], family=d["family"],
                    lx=lx, ly=ly, walls=[tuple(w) for w in d["walls"]], neighbours=False,
                    external=d["external"])
    state = system.state(d["pos"], d["theta"], shift=float(d["le_offset"]))
    ij, img = d["contacts"], d["images"]
    j = np.where(ij[:, 1] >= 0, ij[:, 1], -1 - d["wall_of"])
    hist = np.array(d["history"], float).reshape(len(ij), -1)
    state.contacts = Contacts(ij[:, 0].astype(np.int64), j.astype(np.int64),
                              img[:, 0].astype(np.int64), img[:, 1].astype(np.int64), hist,
                              np.zeros(len(ij), np.int8), np.zeros((len(ij), 3)))
    state.keys = contact_keys(state.contacts.i, state.contacts.j, state.contacts.m,
                              state.contacts.k, system.n, len(system.walls))
    return system, state
