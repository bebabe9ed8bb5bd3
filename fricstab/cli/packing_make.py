"""``fricstab packing make`` and ``fricstab packing jacobian`` (see :mod:`fricstab.cli.packing`).

``make``: a frictionless packing (Ishima App. A.1) with its record and
figure, and friction switched on with the chosen law (App. A.2) as a check
that the law holds it.  ``jacobian``: the force-balanced backbone under the
law, written by :func:`fricstab.io.jacobian_export.write_state_jacobian`.
"""

import numpy as np

from fricstab.cli.packing_common import (MAKE_KEYS, UNITS, UNITS_NOTE, dry_run, friction_record,
                                         law_runs, new_packing, packing_source_checks, public,
                                         resolve, save_packing, show_progress, summary)
from fricstab.cli.packing_source import NPZ, conflicts, open_run, refuse, remove

__all__ = ["jacobian", "make", "write_jacobian"]


def make(ns, argv):
    """``fricstab packing make``: packing.npz, packing.png, packing.json.

    A packing already in ``--out`` is replaced only with ``--force``, together
    with the results made from it (:mod:`fricstab.cli.packing_source`).
    """
    from fricstab.figures.packing import packing_figure
    from fricstab.io.results import ResultDir
    from fricstab.scenes.packing import find_contacts, hertz_forces
    from fricstab.scenes.packing_friction import backbone, frictional

    params = resolve(ns, MAKE_KEYS + ("z_th",))
    (run,) = law_runs(params)
    rd = ResultDir(ns.out, "packing", force=ns.force, outputs=(NPZ, "packing.png"),
                   fingerprint=public(params))
    found = conflicts(rd.path, "packing", new=True)
    if not ns.force:
        refuse(rd.path, found)
    if ns.dry_run:
        return dry_run(params, [run])
    rd.create()
    remove(rd.path, found, "made from the packing that --force replaced")
    from fricstab import progress
    progress.compile_note(["packing"], enabled=show_progress(ns))
    with rd.stage("make"):
        packing = new_packing(params, show_progress(ns))
    radius = packing.radius
    pairs, sep = find_contacts(packing.pos, radius, packing.box)
    bb = backbone(packing, z_th=params["z_th"])
    m_bb = len(find_contacts(bb.pos, bb.radius, bb.box)[0])
    with rd.stage("friction"), progress.heartbeat("friction", show_progress(ns)):
        fr = frictional(bb, run.material, f_tol=params["f_tol"])
    rattler = np.ones(packing.n, dtype=bool)
    rattler[bb.keep] = False
    xi = radius[pairs[:, 0]] + radius[pairs[:, 1]] - np.hypot(sep[:, 0], sep[:, 1])
    force = np.clip(xi, 0, None) ** 1.5          # Hertz, k_N = 1 (Eq. A4)
    doc = {"phi_start": packing.info.get("phi_start"), "info": packing.info,
           "n": packing.n, "phi": packing.phi, "box": packing.box,
           "contacts": len(pairs), "z_th": params["z_th"], "rattlers": int(rattler.sum()),
           "n_backbone": bb.n, "contacts_backbone": m_bb,
           "mean_contact_number_backbone": 2 * m_bb / bb.n if bb.n else None,
           "backbone_rattler_force": bb.rattler_force,
           "max_contact_force": float(force.max()) if force.size else 0.0,
           "max_force_hertz": float(np.abs(hertz_forces(packing.pos, radius,
                                                        packing.box)).max()),
           "law": run.material.law, "law_params": dict(run.material.params),
           "friction": friction_record(fr), "units": UNITS_NOTE}
    with rd.stage("write"):
        rd.write_with(NPZ, save_packing(packing))
        rd.write_png("packing.png",
                     lambda tmp: packing_figure(packing, pairs, sep, force, rattler, tmp))
    doc = rd.finish(doc, parameters=public(params), seed=packing.seed, argv=argv)
    print(f"packing N = {packing.n}, phi = {packing.phi:g}, seed = {packing.seed}: "
          f"L = {packing.box:.6g}, {len(pairs)} contacts, {doc['rattlers']} rattlers (Z <= "
          f"{params['z_th']}), backbone Z = {doc['mean_contact_number_backbone']:.4f}, "
          f"max |F| = {packing.info.get('max_force', float('nan')):.1e} "
          f"({packing.info.get('seconds', float('nan')):.1f} s)")
    f = doc["friction"]
    print(f"friction on ({run.material.law}): max |F| = {f['max_force']:.1e}"
          + (f" after relaxing under its normal force ({f['normal_fire_iterations']} FIRE, "
             f"{f['normal_newton_iterations']} Newton iterations)" if f["relaxed"] else ""))
    print(f"wrote {rd.path}/packing.npz, packing.png, packing.json")
    return 0


def jacobian(ns, argv):
    """``fricstab packing jacobian``: state.npz, jacobian.npz, dofs.json, mass.npy, jacobian.json."""
    from fricstab.io.jacobian_export import FILES
    from fricstab.scenes.packing_friction import backbone, frictional

    params = resolve(ns, MAKE_KEYS + ("z_th",))
    (run,) = law_runs(params)
    packing_source_checks(ns)
    opened = open_run(ns, params, "jacobian", FILES, {})
    if ns.dry_run:
        return dry_run(params, [run])
    source = opened.start(argv, show_progress(ns))
    rd, packing = opened.rd, source.packing
    bb = backbone(packing, z_th=params["z_th"])
    with rd.stage("friction"):
        fr = frictional(bb, run.material, f_tol=params["f_tol"])
    system, state = fr.system, fr.state
    extra = {"scene": "packing (Ishima et al.): the rattler-free backbone, periodic box",
             "ishima_convention": "Ishima's J (Eq. 18) is -K in (x, y, l = R theta); for a "
                                  "law in theta, J = -C^-1 K C^-1 with C = diag(1, 1, R_i)",
             "backbone": {"n_total": packing.n, "n_backbone": bb.n, "z_th": params["z_th"],
                          "keep": "state.npz key 'keep': packing indices of the rows"},
             "friction": friction_record(fr)}
    f, k = write_jacobian(rd, system, state, extra, {"keep": bb.keep,
                                                     "packing_phi": np.array(packing.phi)})
    doc = {"packing": source.record(), **summary(packing, bb), "law": run.material.law,
           "law_params": dict(run.material.params), "dof_per_particle": system.dof,
           "shape": list(k.shape), "nnz": int(k.nnz),
           "max_force": float(np.abs(f).max()) if f.size else 0.0,
           "friction": friction_record(fr), "units": UNITS_NOTE}
    rd.finish(doc, parameters=public(params), seed=packing.seed, argv=argv)
    print(f"packing N = {packing.n} (backbone {bb.n}), law {run.material.law}: max |F| = "
          f"{doc['max_force']:.1e}, K {k.shape[0]} x {k.shape[1]} ({k.nnz} nonzeros)")
    print(f"wrote {rd.path}/state.npz, jacobian.npz, dofs.json, mass.npy, jacobian.json")
    return 0


def write_jacobian(rd, system, state, extra, extra_arrays=None, units=UNITS):
    """state.npz, jacobian.npz, dofs.json, mass.npy into ``rd``, checked finite first; (f, K)."""
    from fricstab.engine import jacobian as engine_jacobian
    from fricstab.errors import check_finite
    from fricstab.io.jacobian_export import FILES, write_state_jacobian
    with rd.stage("jacobian"):
        f, k = engine_jacobian(system, state)   # checked before anything is written
    check_finite("force", f.reshape(-1, system.dof), item="particle")
    check_finite("Jacobian entry", k.data, item="entry")
    for name in FILES:
        rd.register(name)
    with rd.stage("write"):
        return write_state_jacobian(rd.path, system, state, units=units, extra=extra,
                                    extra_arrays=extra_arrays)
