"""``fricstab packing aqs``: athermal quasistatic shear with history, spectrum along the path.

``fricstab packing aqs [--packing ... | make options] --law NAME --strain S --dgamma D --out DIR``
    The backbone under the law, force-balanced (App. A.2), sheared in steps
    ``D`` to strain ``S`` (:func:`fricstab.protocols.aqs.run_aqs`): Newton
    relaxation with the history's increment rule, the spectrum of M^-1 K at
    every relaxed state, complex-pair births and deaths located by bisection
    in strain to ``--tol`` (default 1e-6), stress drops above
    ``--drop-threshold``.  Writes ``aqs.json`` (strains, stresses, pair counts,
    growth rates, drops, events with their brackets), ``aqs.png`` and, for
    every located birth ``k``, ``events/birth_<k>_lo/`` and
    ``events/birth_<k>_hi/`` with ``state.npz``, ``jacobian.npz``,
    ``dofs.json`` and ``mass.npy`` as ``fricstab packing jacobian`` writes them.
    ``--checkpoint-every K`` saves the path every K steps (default 50);
    ``--resume`` continues an interrupted run.

The law must be one of the packing's (hertz, ishima, charan, lee_hurley): a
law whose pair dof the periodic packing cannot carry (a wall form, an unknown
name) is refused with exit 2.  hertz (2 dof, no history) is the frictionless
control: its Jacobian is symmetric, so it has no complex pairs.
Exit 2: bad input (``--dgamma <= 0``, ``--strain < --dgamma``); 4: a step
without equilibrium (the message names the step and its strain).
"""


import numpy as np

from fricstab.cli.packing_common import (MAKE_KEYS, UNITS, UNITS_NOTE, dry_run, friction_record,
                                         law_runs, packing_source_checks, public, resolve,
                                         show_progress, summary)
from fricstab.errors import ParameterError

__all__ = ["add_parser", "aqs", "path_options", "shear"]

DEFAULT_CHECKPOINT_EVERY = 50
DEFAULT_WINDOW_STEPS = 10
_WHY = " (beyond it the stresses' products leave float64)"


def _fraction(x):
    """A fraction for the summary line; ``n/a`` where it is undefined (no drops)."""
    return f"{x:.3f}" if np.isfinite(x) else "n/a"


def _at_most(high, why):
    """A float <= ``high`` (the lower end is checked with the run's strain)."""
    def parse(text):
        import argparse
        try:
            value = float(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"must be a number, got {text!r}") from None
        if value > high:
            raise argparse.ArgumentTypeError(f"must be <= {high:g}{why}, got {text!r}")
        return value
    return parse


def add_parser(psub, packing_option, make_options, common_options):
    """Register ``fricstab packing aqs`` on the packing subparsers."""
    from fricstab.analysis.aqs import DROP_THRESHOLD
    from fricstab.cli import _int_at_least, _positive_float
    a = psub.add_parser("aqs", help="athermal quasistatic shear with history: stress drops "
                        "and complex-pair births along the path")
    packing_option(a)
    make_options(a)
    a.add_argument("--strain", type=float, required=True, help="final strain, >= --dgamma")
    a.add_argument("--dgamma", type=float, required=True, help="strain step, > 0")
    a.add_argument("--tol", type=_at_most(10.0, " (a strain)"), default=1e-6,
                   help="bisection bracket of a pair event in strain (default 1e-6)")
    a.add_argument("--drop-threshold", type=_positive_float(1e-30, 1e30, _WHY),
                   default=DROP_THRESHOLD,
                   help=f"a stress decrease above this is a drop (default {DROP_THRESHOLD:g} "
                        "k_N d^-1/2)")
    a.add_argument("--window", type=_positive_float(1e-30, 10.0, " (a strain)"), default=None,
                   help=f"precursor window in strain (default {DEFAULT_WINDOW_STEPS} dgamma)")
    a.add_argument("--checkpoint-every", type=_int_at_least(1, 2 ** 62),
                   default=DEFAULT_CHECKPOINT_EVERY,
                   metavar="STEPS", help=f"checkpoint every K strain steps (default "
                   f"{DEFAULT_CHECKPOINT_EVERY})")
    a.add_argument("--resume", action="store_true",
                   help="continue an interrupted run in --out from its last checkpoint")
    common_options(a)
    return a


def _open(ns, params, fp):
    """The run's ResultDir and packing source; ``--resume`` reuses the packing of --out."""
    from fricstab.cli.packing_source import Opened, open_run, plan, read, reuse
    from fricstab.io import rundir
    from fricstab.io.results import ResultDir
    if not ns.resume:
        return open_run(ns, params, "aqs", ["aqs.png", "events"], fp)
    if ns.force:
        raise ParameterError("--resume and --force exclude each other")
    want = {k: params[k] for k in MAKE_KEYS}
    source = read(ns.packing) if ns.packing is not None else None
    full = {**public(params), **fp}
    if source is not None:
        full = {k: v for k, v in full.items() if k not in MAKE_KEYS or k == "f_tol"}
        full["packing_sha256"] = source.sha256
    rd = ResultDir(ns.out, "aqs", resume=True, fingerprint=full)
    if not rundir.journal_path(rd.path, "aqs").is_file():
        raise ParameterError(f"--resume: nothing to resume in {rd.path} (no interrupted aqs "
                             "run there); rerun without --resume")
    if source is None:
        record = plan(rd.path, want, False)
        if record is None:
            raise ParameterError(f"--resume: {rd.path} holds no packing of this run")
        source = reuse(rd.path, record)
    return Opened(rd, None, source, [], want)


def _check_resumable(out, ck, last, n_steps):
    """Refuse a checkpoint outside the run, or one whose births' event folders are gone.

    Births before the checkpoint are not located again on resume, so their
    ``events/birth_<k>_{lo,hi}`` folders (numbered over all births) must be there.
    """
    ck.check_step(last, n_steps, 1)
    step = int(last["step"])
    if len(last["stress"]) != step + 1:
        raise ParameterError(f"--resume: the checkpoint {last['path']} is at step {step} but "
                             f"holds {len(last['stress'])} states (edited by hand?); rerun "
                             "with --force")
    rows = np.asarray(last["events"]).reshape(-1, 9)
    births = rows[rows[:, 0] == 0]
    for k, row in enumerate(births):
        for end in ("lo", "hi"):
            folder = out / "events" / f"birth_{k}_{end}"
            if row[7] and not (folder / "state.npz").is_file():
                what = "events/ missing" if not (out / "events").is_dir() else \
                    f"{folder.relative_to(out)} missing"
                raise ParameterError(f"--resume: {what} in {out} (birth {k}, before the "
                                     f"checkpoint at step {step}, is not located again): "
                                     "rerun with --force")


def path_options(ns):
    """Check --strain, --dgamma, --tol, --drop-threshold, --window, --checkpoint-every; window."""
    from fricstab.protocols.aqs import check_strain, check_tol
    check_strain(ns.strain, ns.dgamma)
    for name in ("tol", "drop_threshold"):
        v = getattr(ns, name)
        if not (np.isfinite(v) and v > 0):
            raise ParameterError(f"--{name.replace('_', '-')} must be a finite number > 0, "
                                 f"got {v!r}")
    check_tol(ns.tol, ns.strain)
    window = ns.window if ns.window is not None else DEFAULT_WINDOW_STEPS * ns.dgamma
    if not (np.isfinite(window) and window > 0):
        raise ParameterError(f"--window must be a finite number > 0, got {window!r}")
    if ns.checkpoint_every < 1:
        raise ParameterError(f"--checkpoint-every must be >= 1, got {ns.checkpoint_every}")
    return window


def aqs(ns, argv):
    """``fricstab packing aqs``: aqs.json, aqs.png, events/birth_<k>_{lo,hi}/."""
    from fricstab import progress
    from fricstab.io.checkpoint import Checkpointer
    from fricstab.scenes.packing_friction import backbone, frictional

    window = path_options(ns)
    params = resolve(ns, MAKE_KEYS + ("z_th",))
    if params["kt_scan"] is not None:
        raise ParameterError("aqs runs one law: give kt with --param kt=..., not a scan")
    (run,) = law_runs(params)
    packing_source_checks(ns)
    fp = {"strain": ns.strain, "dgamma": ns.dgamma, "tol": ns.tol,
          "drop_threshold": ns.drop_threshold, "window": window}
    opened = _open(ns, params, fp)
    n_steps = int(np.floor(ns.strain / ns.dgamma + 1e-9))
    from fricstab.cli import budget
    # a dense spectrum (values only) of M^-1 K per relaxed state, at least one per step
    estimate = budget.packing("packing aqs", opened, params, n_steps, vectors=False,
                              dry_run=ns.dry_run)
    if ns.dry_run:
        return dry_run({**params, **fp}, [run], estimate)
    # --resume: the checkpoint and the event folders are checked before anything is written
    ck = Checkpointer(opened.rd.path / "checkpoints", {**public(params), **fp})
    last = ck.latest(clean=False) if ns.resume else None
    if last is not None:
        _check_resumable(opened.rd.path, ck, last, n_steps)
    source = opened.start(argv, show_progress(ns))
    rd, packing = opened.rd, source.packing
    bb = backbone(packing, z_th=params["z_th"])
    with rd.stage("friction"), progress.heartbeat("friction", show_progress(ns)):
        fr = frictional(bb, run.material, f_tol=params["f_tol"])
    extra = {"scene": "packing (Ishima et al.): the rattler-free backbone, sheared (AQS)",
             "backbone": {"n_total": packing.n, "n_backbone": bb.n, "z_th": params["z_th"]}}
    doc = {"packing": source.record(), **summary(packing, bb), "law": run.material.law,
           "law_params": dict(run.material.params), "dof_per_particle": fr.system.dof,
           "friction": friction_record(fr)}
    if source.origin != "read":
        doc["make"] = {k: params[k] for k in MAKE_KEYS}
    head = f"packing N = {packing.n} (backbone {bb.n}), law {run.material.law}"
    return shear(ns, rd, fr.system, fr.state, params["f_tol"], window, (ck, last), extra, doc,
                 ({**public(params), **fp}, packing.seed, argv), head)


def shear(ns, rd, system, state, f_tol, window, resume, extra, doc, finish, head):
    """The path from ``state`` (run_aqs), event folders, aqs.json (``doc`` first), aqs.png.

    ``resume``: ``(Checkpointer, its latest checkpoint or None)``; ``finish``:
    ``(parameters, seed, argv)`` of the record.
    """
    from fricstab import progress
    from fricstab.analysis.aqs import compare, detect_drops
    from fricstab.io.jacobian_export import write_state_jacobian
    from fricstab.protocols.aqs import ZERO_CLUSTER, run_aqs
    ck, last = resume
    n_steps = int(np.floor(ns.strain / ns.dgamma + 1e-9))
    rd.checkpoints()
    rd.register("events", folder=True)

    def on_birth(k, ev, s_lo, s_hi):
        for end, s, g in (("lo", s_lo, ev.gamma_lo), ("hi", s_hi, ev.gamma_hi)):
            write_state_jacobian(rd.path / "events" / f"birth_{k}_{end}", system, s,
                                 units=UNITS, extra={**extra, "strain": g, "birth": k,
                                                     "bracket_end": end})

    done = 0 if last is None else int(last["step"])
    with rd.stage("aqs"), progress.bar(total=n_steps, initial=done, desc="aqs", unit="step",
                                       enabled=show_progress(ns)) as bar:
        res = run_aqs(system, state, ns.strain, ns.dgamma, f_tol=f_tol,
                      tol=ns.tol, progress=bar, resume=last,
                      checkpoint=lambda k, arrays: ck.save(k, **arrays),
                      checkpoint_every=ns.checkpoint_every, on_birth=on_birth)
    drops = detect_drops(res.strain, res.stress, ns.drop_threshold)
    births = [e for e in res.events if e.kind == "birth"]
    stats = compare([{"drops": [d.gamma for d in drops], "births": [e.gamma for e in births],
                      "gamma_max": float(res.strain[-1])}], window)
    located = [e for e in births if e.located]
    # run_aqs numbers the births it passes to on_birth over all births, located or not:
    # the record names the folders by the same number
    birth_number = {id(e): k for k, e in enumerate(births)}
    events = []
    for e in res.events:
        rec = {"kind": e.kind, "step": e.step, "gamma": e.gamma, "gamma_lo": e.gamma_lo,
               "gamma_hi": e.gamma_hi, "bracket": e.gamma_hi - e.gamma_lo,
               "pair_real_part": e.center, "radius": e.radius, "bisections": e.bisections,
               "located": e.located, "growth_rate": e.growth_hi}
        if e.kind == "birth" and e.located:
            k = birth_number[id(e)]
            rec["directories"] = [f"events/birth_{k}_lo", f"events/birth_{k}_hi"]
        events.append(rec)
    doc = {**doc, "strain_max": ns.strain, "dgamma": ns.dgamma,
           "tol": ns.tol, "drop_threshold": ns.drop_threshold, "window": window,
           "pair_rule": "conjugate pairs of eig(B^T diag(mass)^-1 K B), B an orthonormal "
                        "basis of {x: sum_i m_i x_i = 0 in x and y}, with |lambda| > "
                        f"{ZERO_CLUSTER:g} max|lambda|",
           "strains": res.strain, "stresses": res.stress, "n_pairs": res.n_pairs,
           "growth_rates": res.growth, "largest_real_eigenvalue": res.min_real,
           "contacts": res.contacts, "fire_steps": np.flatnonzero(res.fire),
           "drops": [d.record() for d in drops], "events": events,
           "births": len(births), "births_located": len(located),
           "max_bracket": max((e.gamma_hi - e.gamma_lo for e in located), default=None),
           "precursors": stats, "resumed_from_step": None if last is None else done,
           "units": doc.get("units", UNITS_NOTE)}
    from fricstab.figures.aqs import aqs_figure
    rd.write_png("aqs.png", lambda tmp: aqs_figure(res, drops, tmp))
    parameters, seed, argv = finish
    rd.finish(doc, parameters=parameters, seed=seed, argv=argv)
    ck.clear()
    print(f"{head}: "
          f"{n_steps} steps of {ns.dgamma:g} to strain {res.strain[-1]:.6g}, "
          f"{len(drops)} drops, {len(births)} births ({len(located)} located), "
          f"{sum(e.kind == 'death' for e in res.events)} deaths; "
          f"{stats['preceded']} of {stats['drops']} drops preceded within {window:g} "
          f"(null {_fraction(stats['null_fraction'])})")
    print(f"wrote {rd.path}/aqs.json, aqs.png, events/ ({2 * len(located)} directories)")
    return 0
