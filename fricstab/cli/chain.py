"""``fricstab chain ramp|jacobian|dynamics|waves``: the chain protocol from the command line.

Scene keys (``--scene FILE.toml``, overridden by ``--n --fy --mu --inertia``):
``fricstab scene show chain``.  Every command takes the contact law
``--law hertz|charan|ishima|lee_hurley|linear`` (default charan, the paper's) and its
parameters ``--param KEY=VALUE`` (repeatable; defaults in Charan's units,
``fricstab scene show chain``), ``--out DIR`` (required),
``--force``, ``--quiet``, ``--no-progress``, ``--dry-run`` (validate, print the
resolved parameters as JSON, write nothing); its record ``DIR/<command>.json``
carries the numbers, the resolved parameters, the seed, versions, git revision
and wall/CPU time per stage (:mod:`fricstab.io.results`).

``fricstab chain ramp --fx-max 0.1 --step 1e-3 --out DIR``
    Quasistatic F_x ramp (Newton, history carried), spectra of M^-1 J and the
    complex-pair events located by bisection; writes ``ramp.json``,
    ``ramp.npz`` (fx, eigenvalues, condition numbers, residuals, growth rates)
    and ``ramp.png`` (real and imaginary parts against F_x, as Charan Fig. 2).
``fricstab chain jacobian [--fx F] --out DIR``
    Equilibrium at F (default: the scene's fx, 0; ramped from 0 in steps of
    ``--step``) and its Jacobian: the common ``state.npz``, ``jacobian.npz``,
    ``dofs.json``, ``mass.npy`` of every scene, and for compatibility
    ``jacobian.npy`` (dense dF/dq) with the legacy keys ``q`` and ``t`` in
    ``state.npz`` (:mod:`fricstab.scenes.chain_io`); the record ``jacobian.json``.
``fricstab chain dynamics --fx F --duration T --seed S --out DIR [--checkpoint-every K] [--resume] [--export xyz|dump]``
    Newtonian dynamics from that equilibrium with a seeded perturbation:
    ``dynamics.json`` (first Coulomb breach per disk), ``dynamics.npz``
    (frames: positions, velocities, wall histories; M(t), centre of mass),
    ``dynamics.png`` (Figs. 3, 4, 7), optionally ``trajectory.xyz`` or
    ``trajectory.dump`` for OVITO.  Checkpoints every K Verlet steps in
    ``DIR/checkpoints/`` (removed when the run completes); ``--resume``
    continues bit-identically from the latest.
``fricstab chain waves --fx F... --realizations R --out DIR [--scheduler local|inline|ADDRESS] [--resume]``
    R seeded realizations per F_x through :func:`fricstab.io.ensemble.run_ensemble`,
    each stored when done as ``DIR/members/fx<F>_seed<S>_<hash>.npz``, ``<hash>``
    12 hex digits of the member's own fingerprint (scene and law, exact F_x,
    ``--step``, seed, ``--duration``, ``--slide-threshold``), which the file also
    holds; ``--resume`` keeps the sound members of an interrupted run and
    recomputes a missing, damaged or foreign one.  Wave fits in ``waves.json``,
    ``waves.npz`` (``tau_fx<F>`` ..., F as ``repr``), ``waves.png``.

Every record carries a ``fingerprint``: the validated scene (the law and its
parameters) and every option that changes the output (not ``--out``,
``--force``, ``--resume``, ``--quiet``, ``--no-progress``, ``--scheduler``,
``--workers``, ``--checkpoint-every``).  A result in ``--out`` is never
overwritten without ``--force``, which first removes everything the previous
run of that command wrote (members and checkpoints included); ``--resume`` of
a run made with other parameters is refused, naming the parameter.

A law that cannot make sense with the scene (a frictionless law under
F_x > 0; waves of a law without a Coulomb cap) is refused before any work.
Exit status: 0 ok, 2 bad input, 4 no equilibrium or a non-finite force.
Every file is written atomically (a complete file or none).  Figures:
:mod:`fricstab.figures.chain`.
"""

import sys

import numpy as np

from fricstab.cli.chain_common import (DEFAULT_CHECKPOINT_EVERY, MAX_VERLET_STEPS,
                                       PAPER_TIME_UNIT, _check_ramp_steps, _count, _dry_run,
                                       _fingerprint, _finish, _finite_float, _meta,
                                       _ramped_equilibrium, _result_dir, _scene)
from fricstab.cli.chain_waves import waves as _waves
from fricstab.errors import ConvergenceError
from fricstab.laws import ParameterError

__all__ = ["add_parser", "run"]

#: Why a first-breach / first-slide entry of dynamics.json is null (``<key>_note``).
NEVER = {"breach": "never: null for a disk that did not reach the Coulomb limit within "
                   "--duration (NaN in dynamics.npz)",
         "slide": "never: null for a disk that did not slide by slide_threshold_2R within "
                  "--duration"}

#: Why a command-line scale is kept in [1e-30, 1e30] (fricstab.io.scenes.SCALE_DOC).
_WHY = " (beyond it the products of the scene's scales leave float64)"

def _conventions():
    from fricstab.scenes.chain import CONVENTIONS
    return CONVENTIONS


def add_parser(sub, parser_class, positive_float):
    """Register ``fricstab chain ramp|jacobian|dynamics|waves`` on the subparsers ``sub``."""
    from fricstab.io.results import add_run_options
    from fricstab.io.scenes import add_law_options

    p = sub.add_parser("chain", help="chain of disks on a substrate (Charan et al.)",
                       description="Chain of disks pressed on a substrate (Charan et al.). "
                       "Scene keys: `fricstab scene show chain`.")
    csub = p.add_subparsers(dest="chain_command", metavar="CHAIN_COMMAND",
                            parser_class=parser_class)
    csub.required = True
    for name, helptext in (("ramp", "quasistatic F_x ramp and complex-pair events"),
                           ("jacobian", "equilibrium at --fx and its Jacobian"),
                           ("dynamics", "Newtonian dynamics from the equilibrium at --fx"),
                           ("waves", "forward and backward waves over realizations")):
        c = csub.add_parser(name, help=helptext, description=helptext)
        add_run_options(c, seed=name in ("dynamics", "waves"),
                        checkpoints=name == "dynamics")
        add_law_options(c, "chain")
        c.add_argument("--n", type=_count, default=None, help="number of disks (default 10)")
        c.add_argument("--fy", type=_finite_float, default=None,
                       help="pressing force F_y (default 0.1)")
        c.add_argument("--mu", type=_finite_float, default=None,
                       help="friction coefficient mu of charan (default 10; same as "
                            "--param mu=VALUE)")
        c.add_argument("--inertia", type=_finite_float, default=None,
                       help="moment of inertia (default m R^2 / 2)")
        c.add_argument("--step", type=positive_float(1e-30, 1e30, _WHY), default=1e-3,
                       help="ramp step in F_x (default 1e-3); smaller is slower and, for the "
                            "ramp, resolves closer events")
        if name in ("ramp", "jacobian"):
            c.add_argument("--convention", default="physical", metavar="NAME",
                           choices=tuple(_conventions()),
                           help="matrix whose spectrum is taken: " + "; ".join(
                               f"{k}: {v}" for k, v in _conventions().items())
                           + " (default physical)" + (
                               "; jacobian writes the convention's mass.npy" if name ==
                               "jacobian" else ""))
        if name == "ramp":
            c.add_argument("--fx-max", type=positive_float(1e-30, 1e30, _WHY), default=0.1,
                           help="largest F_x (default 0.1)")
            c.add_argument("--tol", type=positive_float(
                               1e-15, 1.0, " (below 1e-15 F_x is not resolved in float64)"),
                           default=1e-6,
                           help="bisection tolerance in F_x (default 1e-6); each halving "
                                "costs one more Newton solve and eigendecomposition per event")
        elif name == "waves":
            c.add_argument("--fx", type=positive_float(1e-30, 1e30, _WHY), nargs="+",
                           default=[0.083, 0.087, 0.090],
                           help="F_x values (default: the paper's 0.083 0.087 0.090)")
            c.add_argument("--realizations", type=_count, default=25,
                           help="seeded realizations per F_x, >= 2 (default 25); the "
                                "uncertainty of V1, V2 falls as 1/sqrt(realizations)")
            c.add_argument("--duration", type=positive_float(1e-30, 1e30, _WHY),
                           default=25000.0,
                           help="duration in Charan's time unit (default 25000)")
            c.add_argument("--slide-threshold", type=positive_float(1e-30, 1e30, _WHY),
                           default=0.02,
                           help="displacement (2R) that counts as sliding (default 0.02)")
            c.add_argument("--scheduler", default="local", metavar="ADDRESS",
                           help="dask scheduler: 'local' (a LocalCluster of processes, "
                                "default), 'inline' (no dask, in this process), or the "
                                "address of a running scheduler (tcp://host:8786)")
            c.add_argument("--workers", type=_count, default=None,
                           help="worker processes of the local cluster (default: CPU count)")
            c.add_argument("--resume", action="store_true",
                           help="continue an interrupted run in --out (same parameters): "
                                "its stored members are kept, a damaged one recomputed")
        elif name == "jacobian":
            c.add_argument("--fx", type=_finite_float, default=None,
                           help="F_x of the equilibrium (default: the scene's fx, 0)")
        else:
            c.add_argument("--fx", type=_finite_float, required=True,
                           help="F_x of the equilibrium")
        if name == "dynamics":
            c.add_argument("--duration", type=positive_float(1e-30, 1e30, _WHY),
                           default=20000.0,
                           help="duration in Charan's time unit sqrt(m 2R/kn) (default 20000)")
            c.add_argument("--amplitude", type=positive_float(
                               1e-30, 1.0, " (a perturbation beyond the overlap lifts the "
                               "disks off the wall)"), default=1e-9,
                           help="perturbation, times the wall overlap (default 1e-9)")
            c.add_argument("--disk", type=_count, default=4,
                           help="disk whose trajectory is drawn, counted from 1 as the paper "
                                "does (1 = the pushed disk; default 4)")
            c.add_argument("--export", choices=("xyz", "dump"), default=None,
                           help="also write the trajectory for OVITO: extended XYZ "
                                "(trajectory.xyz) or LAMMPS dump text (trajectory.dump)")
    return p


def _ramp(ns, argv):
    from fricstab import progress
    from fricstab.errors import check_finite
    from fricstab.figures.chain import ramp_figure
    from fricstab.protocols.ramp import run_ramp
    from fricstab.scenes.chain import CONVENTIONS, eigenvalue_unit

    scene = _scene(ns, fx=ns.fx_max).with_fx(0.0)
    _check_ramp_steps(ns.fx_max, ns.step, "--fx-max")
    protocol = {"fx_max": ns.fx_max, "step": ns.step, "tol": ns.tol,
                "convention": ns.convention}
    rd = _result_dir(ns, "ramp", ["ramp.npz", "ramp.png"], scene, protocol)
    steps = int(round(ns.fx_max / ns.step)) + 1
    from fricstab.cli import budget
    estimate = budget.chain("chain ramp", scene.n, steps, 3 * steps, dry_run=ns.dry_run)
    if ns.dry_run:
        return _dry_run(ns, scene, {**protocol, "estimate": estimate})
    rd.create()
    progress.compile_note(["contact laws"], enabled=not ns.no_progress)
    with rd.stage("ramp"), progress.bar(total=steps, desc="ramp", unit="step",
                                        enabled=not ns.no_progress) as bar:
        res = run_ramp(scene, ns.fx_max, ns.step, tol=ns.tol, progress=bar,
                       convention=ns.convention)
    check_finite("eigenvalue", res.eigenvalues, item="ramp step")
    check_finite("force residual", res.residual, item="ramp step")
    unit2 = eigenvalue_unit(scene, ns.convention)  # eigenvalues in paper units
    events = [{"kind": e.kind, "fx": e.fx, "fx_lo": e.fx_lo, "fx_hi": e.fx_hi,
               "located": e.located, "bisections": e.bisections,
               "pair_real_part_paper_units": e.pair_center * unit2} for e in res.events]
    doc = {"protocol_description": "quasistatic ramp, Newton relaxation from the previous step",
           **protocol, "convention_description": CONVENTIONS[ns.convention],
           "eigenvalue_unit_note": "eigenvalues in ramp.npz are in simulation units; times "
                                   "eigenvalue_unit they are in Charan's (t0 = sqrt(m 2R / kn)"
                                   "; bare: per unit mass)", "events": events,
           "max_residual": float(res.residual.max()), **_meta(scene, ns, res.seconds)}
    with rd.stage("write"):
        rd.write_npz("ramp.npz", fx=res.fx, eigenvalues=res.eigenvalues,
                     condition=res.condition, residual=res.residual, growth=res.growth,
                     eigenvalue_unit=unit2)
        rd.write_png("ramp.png", lambda tmp: ramp_figure(res, events, unit2, tmp, scene=scene,
                                                         convention=ns.convention))
    _finish(rd, doc, scene, ns, argv, protocol)
    out = rd.path
    print(f"{len(events)} complex-pair events in F_x in [0, {ns.fx_max:g}] "
          f"({res.seconds:.1f} s); max residual {res.residual.max():.1e}")
    for e in events:
        flag = "" if e["located"] else "  (not located: refine --step)"
        print(f"  {e['kind']:5s} at F_x = {e['fx']:.7f} +- {0.5 * (e['fx_hi'] - e['fx_lo']):.1e}{flag}")
    print(f"wrote {out}/ramp.json, ramp.npz, ramp.png")
    return 0


def _jacobian(ns, argv):
    from fricstab.errors import check_finite
    from fricstab.io.jacobian_export import FILES
    from fricstab.scenes.chain import CONVENTIONS, convention_scene, forces_and_jacobian
    from fricstab.scenes.chain_io import export_state

    # the convention's inertia (statics do not depend on it): mass.npy is its M
    loaded = convention_scene(_scene(ns, fx=ns.fx), ns.convention)
    fx = loaded.fx
    _check_ramp_steps(fx, ns.step, "--fx")
    protocol = {"fx": fx, "step": ns.step, "convention": ns.convention}
    rd = _result_dir(ns, "jacobian", [*FILES, "jacobian.npy"], loaded, protocol)
    from fricstab.cli import budget
    steps = max(1, int(np.ceil(abs(fx) / ns.step)))
    estimate = budget.chain("chain jacobian", loaded.n, 0, 3 * (steps + 1), dry_run=ns.dry_run)
    if ns.dry_run:
        return _dry_run(ns, loaded, {**protocol, "estimate": estimate})
    rd.create()
    from fricstab import progress
    progress.compile_note(["contact laws"], enabled=not ns.no_progress)
    with rd.stage("equilibrium"), progress.heartbeat("equilibrium", not ns.no_progress):
        state = _ramped_equilibrium(loaded.with_fx(0.0), fx, ns.step)
    with rd.stage("jacobian"):
        f, jac = forces_and_jacobian(loaded, state)
    check_finite("force", f[:, :loaded.dof], item="disk", components=("F_x", "F_y", "T"))
    check_finite("Jacobian entry", jac, item="row")
    with rd.stage("write"):
        for name in (*FILES, "jacobian.npy"):   # written by export_state: in the manifest
            rd.register(name)
        export_state(loaded, state, rd.path, extra={
            "convention": ns.convention, "convention_description": CONVENTIONS[ns.convention]})
    _finish(rd, {"max_force": float(np.abs(f[:, :loaded.dof]).max()),
                 "convention": ns.convention,
                 "convention_description": CONVENTIONS[ns.convention],
                 "shape": list(jac.shape), **_meta(loaded, ns, 0.0)}, loaded, ns, argv,
            protocol)
    print(f"equilibrium at F_x = {fx:g} ({loaded.law}): max |F| = "
          f"{np.abs(f[:, :loaded.dof]).max():.1e}; wrote {rd.path}/"
          f"{', '.join(FILES)}, jacobian.npy, jacobian.json")
    return 0


def _dynamics(ns, argv):
    from fricstab import progress
    from fricstab.analysis.observables import centre_of_mass, first_breach, msd, paper_time
    from fricstab.figures.chain import dynamics_figure
    from fricstab.io.checkpoint import Checkpointer
    from fricstab.protocols.dynamics import default_dt, perturbed, run_dynamics
    from fricstab.protocols.waves import first_slide
    from fricstab.scenes.chain import time_unit

    loaded = _scene(ns, fx=ns.fx)
    scene = loaded.with_fx(0.0)
    if not 1 <= ns.disk <= scene.n:
        raise ParameterError(f"--disk must be in [1, {scene.n}] (counted from 1), got {ns.disk}")
    _check_ramp_steps(ns.fx, ns.step, "--fx")
    unit = time_unit(scene)
    dt = default_dt(scene, 0.02)
    n_steps = ns.duration * unit / dt
    if not n_steps <= MAX_VERLET_STEPS:
        raise ParameterError(f"--duration {ns.duration:g} needs {n_steps:.3g} Verlet steps "
                             f"for this scene; at most {MAX_VERLET_STEPS:.0e}")
    every = ns.checkpoint_every or DEFAULT_CHECKPOINT_EVERY
    protocol = {"fx": ns.fx, "step": ns.step, "seed": ns.seed, "amplitude": ns.amplitude,
                "duration_paper_units": ns.duration, "dt": dt, "frames": 4000,
                "checkpoint_every": every, "export": ns.export, "disk": ns.disk}
    rd = _result_dir(ns, "dynamics", ["dynamics.npz", "dynamics.png"], scene, protocol)
    if ns.export is not None:
        _export_module()
    if ns.dry_run:
        return _dry_run(ns, scene, {**protocol, "verlet_steps": int(np.ceil(n_steps))})
    rd.create()
    ck = Checkpointer(rd.checkpoints(), _fingerprint(scene, protocol))
    resume = ck.latest() if ns.resume else None
    if resume is not None:   # saved between steps 1 and the last but one
        ck.check_step(resume, int(np.ceil(n_steps)) - 1, 1)
    if ns.resume and resume is None and not ns.quiet:
        print(f"no checkpoint in {rd.path}/checkpoints: starting from the beginning",
              file=sys.stderr)
    progress.compile_note(["contact laws", "chain dynamics"], enabled=not ns.no_progress)
    with rd.stage("equilibrium"), progress.heartbeat("equilibrium", not ns.no_progress):
        state = _ramped_equilibrium(scene, ns.fx, ns.step)
    start = perturbed(scene, state, ns.amplitude, np.random.default_rng(ns.seed))
    with rd.stage("dynamics"), progress.bar(total=int(np.ceil(n_steps)), desc="dynamics",
                                            unit="step", unit_scale=True,
                                            enabled=not ns.no_progress) as bar:
        res = run_dynamics(loaded, start, dt=dt, duration=ns.duration * unit, frames=4000,
                           checkpointer=ck, checkpoint_every=every, resume=resume,
                           progress=bar)
    t = paper_time(scene, res.times)
    m = msd(res.positions)
    com = centre_of_mass(res.positions)
    tau, x_tau = first_breach(loaded, res.times, res.positions, res.wall_hist)
    tau_s, x_s = first_slide(scene, t, res.positions, state.q)
    doc = {"protocol_description": "Newton ramp to F_x, seeded perturbation, undamped "
                                   "velocity Verlet (engine)",
           "fx": ns.fx, "seed": ns.seed, "amplitude": ns.amplitude,
           "duration_paper_units": ns.duration, "time_unit": PAPER_TIME_UNIT,
           "resumed_from_step": None if resume is None else int(resume["step"]),
           "first_breach_paper_time": [None if np.isnan(v) else float(v)
                                       for v in paper_time(scene, tau)],
           "first_breach_x": [None if np.isnan(v) else float(v) for v in x_tau],
           "first_slide_paper_time": [None if np.isnan(v) else float(v) for v in tau_s],
           "slide_threshold_2R": 0.02,
           "final_msd": float(m[-1]), **_meta(scene, ns, res.seconds)}
    for key, never in (("first_breach_paper_time", NEVER["breach"]),
                       ("first_breach_x", NEVER["breach"]),
                       ("first_slide_paper_time", NEVER["slide"])):
        if None in doc[key]:   # null: the event did not happen within the run
            doc[f"{key}_note"] = never
    wall_t = res.wall_hist[:, :, 0] if res.wall_hist.shape[2] else \
        np.zeros(res.wall_hist.shape[:2])
    with rd.stage("write"):
        rd.write_npz("dynamics.npz", time=t, positions=res.positions, velocities=res.velocities,
                     wall_t=wall_t, wall_hist=res.wall_hist, msd=m, centre_of_mass=com,
                     first_breach_time=paper_time(scene, tau), first_breach_x=x_tau)
        rd.write_png("dynamics.png",
                     lambda tmp: dynamics_figure(t, m, com, res.positions, ns.disk - 1, tmp))
        if ns.export is not None:
            _export_trajectory(rd, ns.export, scene, t, res.positions, res.velocities)
    _finish(rd, doc, scene, ns, argv, protocol)
    ck.clear()
    print(f"dynamics at F_x = {ns.fx:g} ({scene.law}) for {ns.duration:g} time units "
          f"({res.seconds:.1f} s): final M(t) = {m[-1]:.3e}; disks at the Coulomb limit: "
          f"{int(np.sum(~np.isnan(tau)))}/{scene.n}"
          + (f" (never: disk{'s' if np.isnan(tau).sum() > 1 else ''} "
             f"{', '.join(str(i + 1) for i in np.flatnonzero(np.isnan(tau)))})"
             if np.isnan(tau).any() else "")
          + f"; wrote {rd.path}/dynamics.json, dynamics.npz, dynamics.png")
    return 0


def _export_module():
    try:
        from fricstab.io import export
    except ImportError:
        raise ParameterError("--export: fricstab.io.export is not available in this "
                             "installation") from None
    return export


def _export_trajectory(rd, kind, scene, t, positions, velocities):
    """Trajectory for OVITO: x, y (z = 0), radius, angle theta, velocities, omega."""
    export = _export_module()
    pos = positions[:, :, :2]
    radius = np.full(scene.n, scene.radius)
    box = (scene.period, 4 * scene.radius)    # periodic in x; y spans the disks above the wall
    kw = dict(angle=positions[:, :, 2], vel=velocities[:, :, :2], omega=velocities[:, :, 2],
              kind=np.zeros(scene.n, dtype=int), box=box, time=t)
    if kind == "xyz":
        rd.write_with("trajectory.xyz", lambda tmp: export.write_extxyz(tmp, pos, radius, **kw))
    else:
        rd.write_with("trajectory.dump",
                      lambda tmp: export.write_lammps_dump(tmp, pos, radius, **kw))


def run(ns, argv=None):
    """Run ``fricstab chain ...``; ``argv`` (the command's arguments) goes into the record.

    No equilibrium (:class:`ConvergenceError`) is one line and exit status 4.
    """
    argv = list(sys.argv[1:] if argv is None else argv)
    command = {"waves": _waves, "ramp": _ramp, "dynamics": _dynamics,
               "jacobian": _jacobian}[ns.chain_command]
    try:
        return command(ns, argv)
    except ConvergenceError as exc:
        text = " ".join(str(exc).split())
        print(f"fricstab: error: {text}", file=sys.stderr)
        return 4
