"""Checks of an imported packing against our law, relaxation, and its files.

* :func:`force_mismatch`: each listed contact's force from our law at the
  imported geometry and history against the file's (``force_n + force_t``,
  on i from j; the torque where the file gives one), the worst relative
  mismatch and its contact;
* :func:`equilibrium`: ``max |F_i|`` over the free particles (torques as
  ``T / R``) over the mean contact force;
* :func:`relax`: Newton (:func:`fricstab.engine.newton`, histories carried by
  the increment rule) from the imported state, how far it moved and the
  residual after;
* :func:`write_imported`: the common ``state.npz``, ``jacobian.npz``,
  ``dofs.json``, ``mass.npy`` (:func:`fricstab.io.jacobian_export.write_state_jacobian`,
  so :func:`~fricstab.io.jacobian_export.system_from_state` rebuilds the state)
  and ``import.json`` (the report), each written atomically.
"""

from pathlib import Path

import numpy as np

from fricstab.engine.newton import newton
from fricstab.io.files import write_json
from fricstab.io.imports.state import contact_where
from fricstab.io.jacobian_export import write_state_jacobian

__all__ = ["equilibrium", "force_mismatch", "relax", "write_imported"]


def _torque_scale(system):
    """Generalized rotational force -> torque: R for ``l = R theta``, 1 for theta."""
    return system.rscale


def force_mismatch(imported, system, state, sc, report):
    """Worst ``|F_ours - F_file| / |F_file|`` over the kept contacts (into ``report.mismatch``).

    Contacts with no force in the file (``|F_file| = 0``) are measured against
    the mean ``|F_file|``.  Torques (where given) are compared as
    ``|T_ours - T_file| / (R_i |F_file|)``.
    """
    if imported.force_n is None and imported.force_t is None:
        report.mismatch = {"checked": False, "why": "the file has no contact forces"}
        return
    zero = np.zeros((imported.n_contacts, 2))
    f_file = ((imported.force_n if imported.force_n is not None else zero)
              + (imported.force_t if imported.force_t is not None else zero)) * sc["force"]
    keep = report.order >= 0
    if not keep.any():
        report.mismatch = {"checked": False, "why": "no contact kept"}
        return
    cf = system.contact_forces(state)[report.order[keep]]
    dof = system.dof
    sw = report.swapped[keep]
    ours = np.where(sw[:, None], cf[:, dof:dof + 2], cf[:, :2])
    mag = np.hypot(f_file[keep, 0], f_file[keep, 1])
    denom = np.where(mag > 0, mag, mag.mean() if mag.mean() > 0 else 1.0)
    rel = np.hypot(*(ours - f_file[keep]).T) / denom
    idx = np.flatnonzero(keep)
    worst = int(np.argmax(rel))
    out = {"checked": True, "worst_relative": float(rel[worst]),
           "contact": int(idx[worst]), "where": contact_where(imported, int(idx[worst])),
           "median_relative": float(np.median(rel))}
    if imported.torque is not None and dof == 3:
        end = imported.ci[keep]                          # the file's i
        rot = np.where(sw, cf[:, dof + 2], cf[:, 2]) * _torque_scale(system)[end]
        t_file = imported.torque[keep] * sc["force"] * sc["length"]
        trel = np.abs(rot - t_file) / (system.radius[end] * denom)
        tw = int(np.argmax(trel))
        out.update(torque_worst_relative=float(trel[tw]), torque_contact=int(idx[tw]),
                   torque_where=contact_where(imported, int(idx[tw])))
    report.mismatch = out


def equilibrium(system, state):
    """``max |F_i|`` over free particles (x, y, T/R) over the mean contact force, and both."""
    f = system.forces(state)
    gen = f[:, :system.dof].copy()
    if system.dof == 3:
        gen[:, 2] *= system.rscale / system.radius     # generalized -> T, then T / R
    free = system.free
    fmax = float(np.abs(gen[free]).max()) if free.any() else 0.0
    cf = system.contact_forces(state)
    mags = np.hypot(cf[:, 0], cf[:, 1])
    mean = float(mags[mags > 0].mean()) if (mags > 0).any() else 0.0
    return {"max_force": fmax, "mean_contact_force": mean,
            "relative": fmax / mean if mean > 0 else float("inf")}


def relax(system, state, tol=1e-12, max_iter=60, max_step=None):
    """Relax a copy of ``state`` by Newton with the histories carried; what changed.

    Parameters
    ----------
    system, state
        From :func:`~fricstab.io.imports.contacts.to_engine` (``state`` is not modified).
    tol : float
        Threshold on ``max |F|`` over the free dof, relative to the mean contact force.
    max_iter : int
    max_step : float, optional
        Cap on one iteration's largest coordinate change (length); default a
        tenth of the mean radius.

    Returns
    -------
    relaxed : State
    info : dict
        ``moved`` (max |dq| of the positions over the mean radius),
        ``residual_before``, ``residual_after`` (relative, :func:`equilibrium`),
        ``iterations``, ``converged``, ``contacts_gained``, ``contacts_lost``.
    """
    before = equilibrium(system, state)
    st = state.copy()
    mean_r = float(system.radius.mean())
    scale = before["mean_contact_force"] or 1.0
    res = newton(system, st, tol * scale, max_iter=max_iter,
                 max_step=0.1 * mean_r if max_step is None else max_step,
                 raise_on_failure=False)
    after = equilibrium(system, st)
    moved = float(np.abs(st.q[:, :2] - state.q[:, :2]).max()) / mean_r if system.n else 0.0
    return st, {"moved": moved, "residual_before": before["relative"],
                "residual_after": after["relative"], "iterations": res.iterations,
                "converged": bool(res.converged), "contacts_gained": res.contacts_gained,
                "contacts_lost": res.contacts_lost}


def write_imported(out_dir, system, state, report):
    """Write the common state files and ``import.json`` (the report) into ``out_dir``.

    Returns the paths written.  ``system_from_state(out_dir / "state.npz")``
    rebuilds the System and State.
    """
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    names = {k: v["file"] for k, v in report.units.items()}
    write_state_jacobian(out, system, state, units=names,
                         extra={"import": "import.json (units mapping, counts, flags, checks)"})
    write_json(out / "import.json", report.as_dict())
    from fricstab.io.jacobian_export import FILES
    return [out / f for f in FILES + ("import.json",)]
