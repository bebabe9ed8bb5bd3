"""``fricstab packing rigidity`` (see :mod:`fricstab.cli.packing`): G by theory against step strain.

Per run (a kT/kN of a scan, or the law): friction switched on
(:func:`fricstab.scenes.packing_friction.frictional`), G_A and G_NA by the
sparse solve and the mode sum (:func:`fricstab.analysis.rigidity.rigidity`),
G by step strain (:func:`fricstab.protocols.stepstrain.step_strain`), and
the relative disagreements against the 1 % acceptance.
"""

import sys

from fricstab.cli.packing_common import (MAKE_KEYS, MODES_MAX_PARTICLES, UNITS_NOTE, dry_run,
                                         friction_record, law_runs, packing_source_checks, public,
                                         rel, resolve, show_progress, summary)
from fricstab.cli.packing_source import open_run

__all__ = ["TOLERANCE", "conclude", "measure", "rigidity"]

TOLERANCE = 0.01             # theory vs step strain, relative to |G|
EXIT_DISAGREE = 3

RECIPE = [
    "J = scipy.sparse.load_npz('jacobian_tilde.npz'); xi = np.load('xi.npy'); "
    "theta = np.load('theta.npy')",
    "u = solve(J, xi) on the complement of the translations e_x, e_y: "
    "[[J, C], [C^T, 0]] [u; mu] = [xi; 0], C = the unit columns e_x, e_y",
    "G_NA = -theta @ u / box**2; G = G_A + G_NA"]


def _save_run(rd, bb, run, r, s, g_na_modes, g_modes):
    """The per-run folder; ``bb``: anything with ``box`` and ``n`` (a backbone, a System view)."""
    import scipy.sparse as sps

    def jac_npz(tmp, jac=r.jacobian):
        with open(tmp, "wb") as fh:
            sps.save_npz(fh, sps.csr_matrix(jac))

    folder = run.name
    rd.write_with(f"{folder}/jacobian_tilde.npz", jac_npz)
    rd.write_npy(f"{folder}/xi.npy", r.xi)
    rd.write_npy(f"{folder}/theta.npy", r.theta)
    rd.write_npy(f"{folder}/u.npy", r.u)
    rd.write_npy(f"{folder}/nonaffine_step.npy", s.nonaffine)
    k = run.dof
    rd.write_json(f"{folder}/g.json", {
        "box": bb.box, "n": bb.n, "ndof": k, "kt": run.kt, "law": run.material.law,
        "law_params": dict(run.material.params),
        "ordering": "(x, y, l = R theta) per particle (Ishima's coordinates)" if k == 3
                    else "(x, y) per particle (frictionless Hessian)",
        "g_a": r.g_a, "g_na_solve": r.g_na_solve, "g_na_modes": g_na_modes,
        "g": r.g, "g_modes": g_modes, "g_step": s.g, "g_step_error": s.error,
        "recipe": RECIPE})


def rigidity(ns, argv):
    """``fricstab packing rigidity``: rigidity.json, rigidity.png, one folder per run."""
    from fricstab import progress
    from fricstab.scenes.packing_friction import backbone, frictional

    params = resolve(ns, MAKE_KEYS + ("dgamma", "z_th", "route"))
    runs = law_runs(params, "rigidity")
    packing_source_checks(ns)
    opened = open_run(ns, params, "rigidity", ["rigidity.png"] + [r.name for r in runs],
                      {"kt": [r.kt for r in runs], "modes": ns.modes})
    from fricstab.cli import budget
    src = opened.source
    n = src.packing.n if src is not None else params["n"]
    estimate = None
    if ns.modes or (ns.modes is None and n <= MODES_MAX_PARTICLES):
        estimate = budget.packing("packing rigidity --modes", opened, params, len(runs),
                                  route=params["route"], dry_run=ns.dry_run)
    if ns.dry_run:
        return dry_run(params, runs, estimate)
    source = opened.start(argv, show_progress(ns))
    rd, packing = opened.rd, source.packing
    bb = backbone(packing, z_th=params["z_th"])
    modes = ns.modes if ns.modes is not None else bb.n <= MODES_MAX_PARTICLES
    results, first = [], None
    with progress.bar(runs, desc="rigidity", unit="run", enabled=show_progress(ns)) as bar:
        for run in bar:
            bar.set_postfix_str(run.name)
            with rd.stage("theory"):
                fr = frictional(bb, run.material, f_tol=params["f_tol"])
            entry, shapes = measure(rd, bb, run, fr.system, fr.state, modes, params,
                                    friction_record(fr))
            results.append(entry)
            first = first or shapes
    doc = {"packing": source.record(), **summary(packing, bb)}
    if source.origin != "read":
        doc["make"] = {k: params[k] for k in MAKE_KEYS}
    head = (f"packing N = {packing.n} (backbone {bb.n}), phi = {packing.phi:g}, "
            f"L = {packing.box:.6g}")
    return conclude(rd, doc, results, first, {**public(params), "kt": [r.kt for r in runs],
                                              "modes": modes},
                    packing.seed, argv, head, params)


def measure(rd, bb, run, system, state, modes, params, friction):
    """One run on a force-balanced state: theory, step strain, its folder; (entry, shapes)."""
    from fricstab.analysis.rigidity import rigidity as linear_rigidity
    from fricstab.protocols import stepstrain
    with rd.stage("theory"):
        r = linear_rigidity(system, state, modes=modes, route=params["route"])
    with rd.stage("step_strain"):
        s = stepstrain.step_strain(system, state, dgamma=params["dgamma"],
                                   f_tol=params["f_tol"])
    g_modes = r.g_modes if modes else None
    g_na_modes = r.g_na_modes if modes else None
    diffs = {"solve_vs_step": rel(s.g, r.g), "modes_vs_step": rel(s.g, g_modes),
             "solve_vs_modes": rel(g_modes, r.g)}
    entry = {**run.record(), "g_a": r.g_a, "g_na_solve": r.g_na_solve,
             "g_na_modes": g_na_modes, "g": r.g, "g_modes": g_modes, "g_step": s.g,
             "g_step_backward": s.g_backward, "g_step_error": s.error,
             "sigma0": s.sigma0, "relative_differences": diffs,
             "step_iterations": s.iterations, "contacts_changed": s.contacts_changed,
             "friction": friction, "checks": r.checks,
             "seconds": {**r.seconds, "step_strain": s.seconds}}
    _save_run(rd, bb, run, r, s, g_na_modes, g_modes)
    return entry, (run.label(), r.u.reshape(system.n, run.dof), s.nonaffine)


def conclude(rd, doc, results, first, parameters, seed, argv, head, params):
    """rigidity.png, the record (``doc`` first), the table; the exit status."""
    from fricstab.figures.packing import rigidity_figure
    bad = [(e, key, v) for e in results for key, v in e["relative_differences"].items()
           if key != "solve_vs_modes" and v is not None and v > TOLERANCE]
    doc = {**doc, "tolerance": TOLERANCE,
           "relative_difference": "|G_theory - G_step| / |G_theory|",
           "passed": not bad, "results": results, "units": doc.get("units", UNITS_NOTE)}
    rd.write_png("rigidity.png", lambda tmp: rigidity_figure(results, first, tmp))
    rd.finish(doc, parameters=parameters, seed=seed, argv=argv)
    _print(head, params, results, rd.path)
    if bad:
        e, key, v = max(bad, key=lambda b: b[2])
        where = f"kt = {e['kt']:g}" if e["kt"] is not None else f"law {e['law']}"
        print(f"fricstab: error: theory and step strain disagree by more than "
              f"{TOLERANCE:.0%}: {key.replace('_', ' ')} {v:.2%} at {where} "
              f"(results written)", file=sys.stderr)
        return EXIT_DISAGREE
    return 0


def _print(head, params, results, out):
    print(f"{head}; law {params['law']}, dgamma = {params['dgamma']:g}")
    print(f"{'run':>12s} {'G_A':>12s} {'G_NA':>12s} {'G solve':>12s} {'G modes':>12s} "
          f"{'G step':>12s} {'+-':>8s} {'rel.diff':>8s}")
    for e in results:
        gm = f"{e['g_modes']:12.5e}" if e["g_modes"] is not None else f"{'-':>12s}"
        worst = max((v for k, v in e["relative_differences"].items()
                     if k != "solve_vs_modes" and v is not None), default=float("nan"))
        print(f"{e['folder']:>12s} {e['g_a']:12.5e} {e['g_na_solve']:12.5e} {e['g']:12.5e} "
              f"{gm} {e['g_step']:12.5e} {e['g_step_error']:8.1e} {worst:8.1e}")
    print(f"wrote {out}/rigidity.json, rigidity.png, "
          f"{', '.join(e['folder'] + '/' for e in results)}")
