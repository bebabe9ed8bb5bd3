"""``fricstab shear run|analyze``: the plane-shear cell of Lee & Hurley from the command line.

``fricstab shear run --out DIR [--scene FILE.toml] [--preset quick|paper] [options]``
    Place, compress (servo) and shear the cell (:mod:`fricstab.scenes.shear`).
    Parameters: the preset (``quick``, the default, or ``paper``), then the
    scene file, then the command line (``fricstab scene show shear`` lists
    every key).  Writes, under DIR: ``frames/chunk_<k>.npz`` (helper A's
    :class:`fricstab.io.frames.Frames`, SI, one chunk per checkpoint
    interval), ``prepare.json`` (compression statistics), ``shear.npz``
    (per frame: time, strain, normal_force, shear_force, tau, height),
    ``shear.png`` (tau = S/N against strain) and ``shear.json`` last (the
    record: parameters, derived V, N, dt, servo error, phases, throughput,
    timings, versions).  ``checkpoints/`` holds the last two checkpoints
    (every ``--checkpoint-every`` output frames); ``--resume`` continues an
    interrupted run bit-identically (same frames, same series).
``fricstab shear analyze --out DIR [--gamma0 G] [--force]``
    D2min, GR regions, phases and Spearman tables of the frames in DIR
    (:func:`fricstab.analysis.shear.analyze`); writes ``analysis.json`` and
    ``analysis.npz``.

Exit status: 0 ok, 2 bad input (one line naming the key), 4 a non-finite
state or an overlap outside the contact law (the message names the step and
the particle or pair; the last checkpoint is kept) or a preparation that did
not settle.
"""

import math
import sys
import time
from pathlib import Path

import numpy as np

from fricstab.laws import ParameterError
from fricstab.scenes.shear import SCHEMA  # registers the scene 'shear'; options come from it

__all__ = ["add_parser", "run", "run_shear", "QUICK", "PAPER", "frames_of"]

# The quick default: shows stick-slip within minutes on 2 cores.  Changes
# from the paper (PAPER = the schema defaults) and their effect: 300 instead
# of 1,000 disks (larger fluctuations, Sec. 5 shows the trend); I = 1e-4
# instead of 4e-6 (still quasi-static, I < 1e-3; 25x fewer steps per strain);
# kappa = 1e3 instead of 1e4 (overlaps 10x larger, still stiff; sqrt(10)x
# fewer steps per strain); strain 0.06 instead of 0.094; dgamma 1e-5 instead
# of 7.2e-7 (a step count per frame similar to the paper's).
QUICK = {"n": 300, "inertial_number": 1e-4, "kappa": 1e3, "strain": 0.06, "dgamma": 1e-5,
         "gamma0": 0.022, "checkpoint_every": 500}
PAPER = {}
#: The larger cell of Sec. 5: radius in [0.2, 0.4] um, about 5,000 disks,
#: output every 1.8e-6 of strain.  Steps per unit strain do not depend on the
#: radius at fixed I and kappa (dt ~ r and gamma_dot ~ 1/r), so the cost per
#: strain is about 5x that of ``paper`` (5x the disks).
LARGE = {"n": 5000, "r_min": 0.2e-6, "r_max": 0.4e-6, "dgamma": 1.8e-6, "gamma0": 0.054}
PRESETS = {"quick": QUICK, "paper": PAPER, "large": LARGE}
#: What each scene key trades, shown by ``fricstab shear run --help``.
TRADES = {
    "n": "cost ~ n per step; tau fluctuations shrink with n (Sec. 5)",
    "strain": "cost ~ strain; more phases for the statistics",
    "dgamma": "output interval: finer resolves short phases, costs disk and analysis time",
    "inertial_number": "steps per strain ~ 1/I; I << 1e-3 keeps the shear quasi-static",
    "kappa": "steps per strain ~ sqrt(kappa); larger is stiffer, closer to rigid grains",
    "dt_frac": "steps ~ 1/dt_frac; 0.3 already breaks the servo (README table)",
    "skin": "larger: fewer list rebuilds, more pairs per step",
    "servo_gain": "larger: N held tighter, until the servo oscillates",
    "prep_tol": "looser: shorter preparation, less settled start",
    "prep_ke": "looser: shorter preparation, less settled start",
}
_SKIP = ("seed", "checkpoint_every")   # options of add_run_options
_TYPES = {"int": int, "float": float, "str": str}
EXIT_NUMERICAL = 4


def add_parser(sub, parser_class, positive_float):
    """Register ``fricstab shear run|analyze`` on the subparsers ``sub``."""
    from fricstab.io.results import add_run_options
    p = sub.add_parser("shear", help="plane shear with constant normal force (Lee & Hurley)",
                       description="Plane-shear cell of Lee & Hurley: stick-slip, D2min, GR "
                       "regions.")
    s = p.add_subparsers(dest="shear_command", metavar="SHEAR_COMMAND",
                         parser_class=parser_class)
    s.required = True
    r = s.add_parser("run", help="prepare and shear the cell; frames, tau(strain)")
    add_run_options(r, seed=False, checkpoints=True, checkpoint_unit="frames")
    r.add_argument("--preset", choices=tuple(PRESETS), default="quick",
                   help="base parameters below the scene file: quick (default; minutes), "
                        "paper (Sec. 2; hours) or large (Sec. 5, 5,000 disks; ~5x paper)")
    r.add_argument("--seed", type=int, default=None, help="seed (default 0)")
    for f in SCHEMA.fields:
        if f.key in _SKIP:
            continue
        trade = f"; trade: {TRADES[f.key]}" if f.key in TRADES else ""
        r.add_argument(f.option, dest=f.key, type=_TYPES[f.type], default=None,
                       metavar=f.type.upper(),
                       help=f"{f.doc} [{f.unit}] (--preset paper: {f.default:g}){trade}")
    a = s.add_parser("analyze", help="D2min, GR regions, phases, Spearman tables of a run")
    a.add_argument("--out", type=Path, required=True, metavar="DIR", help="a `shear run` DIR")
    a.add_argument("--gamma0", type=float, default=None,
                   help="start of the analysed window (default: the run's gamma0)")
    a.add_argument("--force", action="store_true", help="overwrite analysis.json/.npz")
    a.add_argument("--no-progress", action="store_true", help="no progress bar")
    a.add_argument("--no-spectra", action="store_true",
                   help="skip the Jacobian spectrum before each slip (costs one dense "
                        "eigenvalue problem of 3 x bulk disks per slip)")
    e = s.add_parser("export", help="write the frames of a run for OVITO")
    e.add_argument("--out", type=Path, required=True, metavar="DIR", help="a `shear run` DIR")
    e.add_argument("--format", choices=("extxyz", "lammps"), default="extxyz",
                   help="extended XYZ (default) or LAMMPS dump text")
    e.add_argument("--every", type=int, default=1, help="every k-th frame (default 1)")
    e.add_argument("--force", action="store_true", help="overwrite an existing export")
    return p


def resolve_params(scene=None, preset="quick", overrides=None):
    """Validated parameters: preset, then the scene file, then ``overrides`` (None ignored)."""
    from fricstab.io.scenes import load_toml, validate
    merged = dict(PRESETS[preset])
    if scene is not None:
        merged.update(load_toml("shear", scene))
    merged.update({k: v for k, v in (overrides or {}).items() if v is not None})
    p = validate("shear", merged, source=f"scene file {scene}" if scene else "scene")
    if p["r_max"] < p["r_min"]:
        raise ParameterError(f"r_max = {p['r_max']:g} must be >= r_min = {p['r_min']:g}")
    if p["strain"] < p["dgamma"]:
        raise ParameterError(f"strain = {p['strain']:g} must be >= dgamma = {p['dgamma']:g}")
    return p


def frames_of(out):
    """All frames of a run directory, concatenated (:class:`Frames`)."""
    from fricstab.io.frames import Frames
    files = sorted((Path(out) / "frames").glob("chunk_*.npz"))
    if not files:
        raise ParameterError(f"--out: no frames in {out}/frames (run `fricstab shear run`)")
    return Frames.concat([Frames.load(f) for f in files])


def _figure(strain, tau, phases_from, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(7, 3.5), constrained_layout=True)
    ax.plot(100 * strain, tau, lw=0.6, color="k")
    ax.axvline(100 * phases_from, color="C1", lw=0.8, ls="--", label="stick-slip window")
    ax.set_xlabel("shear strain (%)")
    ax.set_ylabel(r"$\tau = S/N$")
    ax.legend(loc="lower right", frameon=False)
    fig.savefig(path, format="png", dpi=130)
    plt.close(fig)


def phase_count(strain, tau, gamma0):
    """Stick/slip phases of ``tau`` in the window strain >= gamma0 (helper A's rule)."""
    from fricstab.analysis.shear import find_phases
    ok = np.zeros(len(tau), bool)
    ok[1:] = strain[:-1] >= gamma0
    ph = find_phases(tau, ok)
    dt = tau[ph[:, 1]] - tau[ph[:, 0] - 1] if len(ph) else np.zeros(0)
    return {"n_phases": int(len(ph)), "n_stick": int((dt > 0).sum()),
            "n_slip": int((dt < 0).sum()), "window_steps": int(ok.sum()),
            "phases_per_step": len(ph) / ok.sum() if ok.sum() else None,
            "largest_drop": float(dt.min()) if len(dt) else None}


def run_shear(params, out, *, resume=False, force=False, progress=False, argv=None,
              log=print):
    """Run the protocol of ``shear run`` into ``out``; returns the record dict."""
    from tqdm import tqdm

    from fricstab.io.checkpoint import Checkpointer
    from fricstab.io.results import ResultDir
    from fricstab.scenes.shear import Shear, make_cell, prepare, restitution
    from fricstab.io.frames import FrameWriter

    rd = ResultDir(out, "shear", force=force, resume=resume,
                   outputs=("frames", "checkpoints", "shear.npz"))
    rd.create()
    (rd.path / "frames").mkdir(exist_ok=True)
    ck = Checkpointer(rd.path / "checkpoints", fingerprint=params)
    last = ck.latest() if resume else None
    cell = make_cell(params)
    sim = Shear(cell)
    u = cell.units
    if last is None:
        with rd.stage("prepare"):
            prep = prepare(sim)
        rd.write_json("prepare.json", prep)
        sim.start_shear()
        series = np.zeros((0, 6))
        chunk = 0
    else:
        sim.load_state(last)
        series = last["series"]
        chunk = int(last["chunk"])
        log(f"resumed from {last['path']} (frame {int(sim.scalars[1])})")
    spf = int(sim.scalars[3])
    n_frames = int(round(params["strain"] / params["dgamma"]))
    every = params["checkpoint_every"]
    meta = {"units": "SI per unit thickness (N/m, N m/m, kg/m)", "scene": params,
            "reduced_units": u.to_json(), "lx_m": cell.lx * u.length}
    radius, mass = cell.radius * u.length, cell.mass * u.mass
    inertia = cell.inertia * u.mass * u.length ** 2

    def writer():
        return FrameWriter(cell.lx * u.length, radius, mass, inertia, cell.kind, meta=meta)

    w = writer()
    k0 = int(sim.scalars[1])
    rows = [series]
    if k0 == 0:
        fr = sim.frame()
        w.append(**fr)
        rows.append([[fr["time"], fr["strain"], fr["normal_force"], fr["shear_force"],
                      fr["tau"], fr["height"]]])
    steps0, t_shear = int(sim.scalars[0]), time.perf_counter()
    with rd.stage("shear"), tqdm(total=n_frames, initial=k0, disable=not progress,
                                 desc="shear", unit="frame", file=sys.stderr) as bar:
        for k in range(k0 + 1, n_frames + 1):
            sim.advance(spf)
            sim.rebuild()
            sim.scalars[1] = k
            fr = sim.frame()
            w.append(**fr)
            rows.append([[fr["time"], fr["strain"], fr["normal_force"], fr["shear_force"],
                          fr["tau"], fr["height"]]])
            bar.update(1)
            if k % every == 0 or k == n_frames:
                w.finish().save(rd.path / "frames" / f"chunk_{chunk:06d}.npz")
                chunk += 1
                w = writer()
                series = np.concatenate(rows)
                rows = [series]
                ck.save(k, series=series, chunk=np.int64(chunk), **sim.state())
    seconds = time.perf_counter() - t_shear
    steps = int(sim.scalars[0]) - steps0
    series = np.concatenate(rows)
    names = ("time", "strain", "normal_force", "shear_force", "tau", "height")
    rd.write_npz("shear.npz", **{n: series[:, i] for i, n in enumerate(names)})
    strain, tau, nforce = series[:, 1], series[:, 4], series[:, 2]
    rd.write_png("shear.png", lambda path: _figure(strain, tau, params["gamma0"], path))
    prep = __import__("json").loads((rd.path / "prepare.json").read_text())
    nt = cell.n_target * u.force
    err = nforce[1:] / nt - 1.0
    phases = phase_count(strain, tau, params["gamma0"])
    h0 = sim.scalars[4]
    win = strain >= params["gamma0"]
    numbers = {
        "derived": {"lx_m": cell.lx * u.length, "h0_m": h0 * u.length,
                    "normal_force_N_per_m": nt, "pressure_Pa": nt / (cell.lx * u.length),
                    "V_m_per_s": sim.scalars[6] * u.velocity,
                    "shear_rate_per_s": sim.scalars[5] / u.time, "dt_s": sim.dt * u.time,
                    "dt_over_tc": sim.dt / cell.t_c, "t_c_s": cell.t_c * u.time,
                    "steps_per_frame": spf, "n_particles": len(cell.radius),
                    "n_bulk": int((cell.kind == 0).sum()),
                    "restitution_implied_by_alpha_n": restitution(params["alpha_n"]),
                    "restitution_paper": 0.9, "reduced_units": u.to_json()},
        "servo": {"kind": "velocity: v_y = -g (N_target - N), |v_y| <= prep_speed",
                  "gain_reduced": sim.ctrl[2],
                  "mean_rel_error": float(err.mean()) if err.size else None,
                  "rms_rel_error": float(np.sqrt(np.mean(err ** 2))) if err.size else None,
                  "max_abs_rel_error": float(np.abs(err).max()) if err.size else None},
        "prepare": prep,
        "frames": n_frames + 1, "chunks": chunk, "steps": int(sim.scalars[0]),
        "neighbour_rebuilds": int(sim.scalars[7]),
        "tau_mean_window": float(tau[win].mean()) if win.any() else None,
        "tau_std_window": float(tau[win].std()) if win.any() else None,
        "phases": phases,
        "throughput_particle_steps_per_s": steps * len(cell.radius) / seconds if steps else None,
        "shear_seconds_this_process": seconds,
    }
    doc = rd.finish(numbers, parameters=params, seed=params["seed"], argv=argv)
    log(f"shear: {len(cell.radius)} disks, strain {strain[-1]:.4g} in {n_frames} frames x "
        f"{spf} steps; tau mean {numbers['tau_mean_window'] or float('nan'):.3f}; "
        f"{phases['n_phases']} phases ({phases['n_stick']} stick, {phases['n_slip']} slip) "
        f"for strain >= {params['gamma0']:g}; N error mean "
        f"{numbers['servo']['mean_rel_error'] or 0:.2e} rms "
        f"{numbers['servo']['rms_rel_error'] or 0:.2e}; "
        f"{numbers['throughput_particle_steps_per_s'] or 0:.3g} particle-steps/s")
    return doc


def _run(ns, argv):
    import json
    overrides = {f.key: getattr(ns, f.key) for f in SCHEMA.fields if f.key not in _SKIP}
    overrides["seed"] = ns.seed
    params = resolve_params(ns.scene, ns.preset, overrides)
    if ns.checkpoint_every is not None:
        params["checkpoint_every"] = int(ns.checkpoint_every)
    if ns.dry_run:
        print(json.dumps(params, indent=2))
        return 0
    run_shear(params, ns.out, resume=ns.resume, force=ns.force,
              progress=not ns.no_progress and sys.stderr.isatty(), argv=argv,
              log=(lambda *a: None) if ns.quiet else print)
    print(f"wrote {ns.out}/shear.json, shear.npz, shear.png, frames/") if not ns.quiet else None
    return 0


def _analyze(ns, argv):
    import json

    from fricstab.io.results import ResultDir
    from fricstab.analysis.shear import analyze
    out = Path(ns.out).expanduser()
    rec = out / "shear.json"
    if not rec.is_file():
        raise ParameterError(f"--out: {out} holds no complete `shear run` result (shear.json)")
    params = json.loads(rec.read_text())["parameters"]
    gamma0 = params["gamma0"] if ns.gamma0 is None else ns.gamma0
    if not (math.isfinite(gamma0) and gamma0 >= 0):
        raise ParameterError(f"--gamma0 must be a finite number >= 0, got {gamma0!r}")
    rd = ResultDir(out, "analysis", force=ns.force, outputs=("analysis.npz",))
    frames = frames_of(out)
    with rd.stage("analyze"):
        res = analyze(frames, gamma0, progress=not ns.no_progress and sys.stderr.isatty())
    numbers, arrays = res.to_json(), res.npz_arrays()
    if not ns.no_spectra:
        from fricstab.analysis.shear_slips import slip_spectra
        with rd.stage("slip spectra"):
            spectra = slip_spectra(frames, res.phases, res.arrays["phase_dtau_p"], params,
                                   progress=not ns.no_progress and sys.stderr.isatty())
        numbers["slip_spectra"] = spectra.summary()
        arrays.update(spectra.arrays())
    rd.write_npz("analysis.npz", **arrays)
    _analysis_outputs(rd, frames, res, numbers, arrays)
    doc = rd.finish(numbers, parameters={"gamma0": gamma0, "run": str(out)}, argv=argv)
    s = doc.get("summary", {})
    sp = doc.get("slip_spectra")
    extra = (f"; {sp['slips_with_complex_pairs']} of {sp['n_slips']} slips follow a state "
             f"with complex pairs" if sp else "")
    print(f"analysis: {s.get('n_phases')} phases in {s.get('n_steps')} steps{extra}; wrote "
          f"{out}/analysis.json, analysis.npz, analysis.md, analysis_*.png")
    return 0


def _analysis_outputs(rd, frames, res, numbers, arrays):
    """analysis.md (Spearman tables) and the figures of Figs. 2, 8-10 and the slip spectra."""
    from fricstab.figures import shear as sf
    from fricstab.analysis.shear import tables_markdown
    t = res.tables
    text = [f"# Plane shear analysis of {rd.path}", "",
            "Spearman rho (p-value, n) of Delta tau / Delta tau_p per bin; struck through: "
            "p > 0.05 (omitted in the paper's figures).", "",
            tables_markdown({"Delta tau per step (Fig. 9a)": t["step_dtau"],
                             "all phases (Fig. 9b)": t["phase_all"],
                             "long phases, t_p > 3 dgamma (Fig. 10a)": t["phase_long"],
                             "short phases (Fig. 10b)": t["phase_short"],
                             "Delta tau_p - t_p (Fig. 10c)": t["phase_tp"]},
                            "Lee & Hurley correlations")]
    sp = numbers.get("slip_spectra")
    if sp:
        c = sp["correlations_with_following_dtau_p"]
        text += ["", tables_markdown({"all slips": {k: [{"lo": -1.0, "hi": 0.0, **v}]
                                                    for k, v in c["all"].items()},
                                      "binned by Delta tau_p": c["binned"]},
                                     "Jacobian before each slip against its Delta tau_p")]
    md = "\n".join(text) + "\n"
    rd.write_with("analysis.md", lambda tmp: Path(tmp).write_text(md))
    rd.write_png("analysis_stress_strain.png",
                 lambda path: sf.fig_stress_strain(frames, path, result=res))
    rd.write_png("analysis_steps.png", lambda path: sf.fig_step_panels(res, path))
    rd.write_png("analysis_spearman_phases.png",
                 lambda path: sf.fig_spearman_bins(t["phase_all"], path, "all phases"))
    steps = res.summary.get("largest_drop_steps")
    if steps:      # Figs. 3-7 at the first step of the largest slip
        k = int(steps[0])
        for name, draw in (("d2min", sf.fig_d2min_map), ("gr", sf.fig_gr_clusters),
                           ("forces", sf.fig_force_network),
                           ("dforces", sf.fig_differential_network),
                           ("nonaffine", sf.fig_nonaffine)):
            rd.write_png(f"analysis_map_{name}.png",
                         lambda path, draw=draw: draw(frames, k, path))
        rd.write_png("analysis_steps_largest_slip.png",
                     lambda path: sf.fig_step_panels(res, path,
                                                     (max(k - 20, 1), min(int(steps[1]) + 20,
                                                                          frames.n_frames))))
    if sp:
        rd.write_png("analysis_slip_spectra.png",
                     lambda path: _spectra_figure(arrays, path))


def _spectra_figure(a, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    d = np.asarray(a.get("slip_dtau_p", []))
    fig, ax = plt.subplots(1, 2, figsize=(8, 3.2), constrained_layout=True)
    ax[0].set_title("Jacobian before each slip")
    for axis, key, label in ((ax[0], "slip_n_complex_pairs", "complex pairs"),
                             (ax[1], "slip_max_growth_rate", "largest growth rate (1/s)")):
        if key in a and d.size:
            axis.scatter(-d, a[key], s=6)
        axis.set_xscale("log")
        axis.set_xlabel(r"$-\Delta\tau_p$ of the following slip")
        axis.set_ylabel(label)
    fig.savefig(path, format="png", dpi=120)
    plt.close(fig)


def _export(ns):
    from fricstab.io.export import frames_to_ovito
    out = Path(ns.out).expanduser()
    if ns.every < 1:
        raise ParameterError(f"--every must be >= 1, got {ns.every}")
    frames = frames_of(out)
    name = out / ("frames.xyz" if ns.format == "extxyz" else "frames.dump")
    if name.exists() and not ns.force:
        raise ParameterError(f"{name} exists; use --force to overwrite")
    frames_to_ovito(frames.subset(np.arange(0, frames.n_frames, ns.every)), name, ns.format)
    print(f"wrote {name} ({len(range(0, frames.n_frames, ns.every))} frames)")
    return 0


def run(ns, argv=None):
    """Run ``fricstab shear ...``; ``argv`` goes into the record."""
    from fricstab.errors import NumericalError
    from fricstab.scenes.packing import ConvergenceError
    argv = list(sys.argv[1:] if argv is None else argv)
    try:
        if ns.shear_command == "run":
            return _run(ns, argv)
        if ns.shear_command == "export":
            return _export(ns)
        return _analyze(ns, argv)
    except (NumericalError, ConvergenceError) as exc:
        print(f"fricstab: error: {' '.join(str(exc).split())} (last checkpoint kept in "
              f"{ns.out}/checkpoints; rerun with --resume)", file=sys.stderr)
        return EXIT_NUMERICAL
