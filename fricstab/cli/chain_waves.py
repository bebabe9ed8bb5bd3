"""``fricstab chain waves``: wave speeds over seeded realizations (see :mod:`fricstab.cli.chain`)."""

import sys

import numpy as np

from fricstab.cli.chain_common import (PAPER_TIME_UNIT, _capped, _check_ramp_steps, _dry_run,
                                       _fingerprint, _finish, _meta, _ramped_equilibrium,
                                       _result_dir, _scene)
from fricstab.laws import ParameterError

__all__ = ["waves"]

#: The fit of a wave speed needs at least three disks with a time (protocols.waves._fit).
MIN_WAVE_DISKS = 3


def _check_duration(scene, duration):
    """Refuse a --duration whose Verlet steps per realization exceed MAX_VERLET_STEPS."""
    from fricstab.cli.chain_common import MAX_VERLET_STEPS
    from fricstab.protocols.dynamics import default_dt
    from fricstab.scenes.chain import time_unit
    n_steps = duration * time_unit(scene) / default_dt(scene, 0.02)
    if not n_steps <= MAX_VERLET_STEPS:
        raise ParameterError(f"--duration {duration:g} needs {n_steps:.3g} Verlet steps per "
                             f"realization for this scene; at most {MAX_VERLET_STEPS:.0e}")


#: Why V1 / V2 is not defined (NaN from the fit): in the record (``v1_note``) and the table.
NOT_DEFINED = {"v1": "not defined: fewer than 3 disks breached within --duration (raise "
                     "--duration or --fx)",
               "v2": "not defined: fewer than 3 disks slid within --duration (raise "
                     "--duration or --fx)"}


def _speed(key, value, err, fmt, fmt_err):
    """``x +- e`` for the table, or why the speed is not defined."""
    if np.isfinite(value) and np.isfinite(err):
        return f"{value:{fmt}} +- {err:{fmt_err}}"
    return NOT_DEFINED[key] if not np.isfinite(value) else f"{value:{fmt}} +- (not defined)"


def waves(ns, argv):
    from fricstab.analysis.modes import transverse_mode
    from fricstab.analysis.spectrum import decompose
    from fricstab.figures.chain import wave_figure
    from fricstab.io.ensemble import member_key, run_ensemble
    from fricstab.protocols.waves import fit_waves, realization_from_arrays, realization_member
    from fricstab.scenes.chain import forces_and_jacobian, mass_vector, time_unit

    if ns.realizations < 2:
        raise ParameterError(f"--realizations must be >= 2, got {ns.realizations}")
    if ns.realizations > 100_000:
        raise ParameterError(f"--realizations must be <= 100000, got {ns.realizations}")
    if ns.workers is not None and not 1 <= ns.workers <= 1024:
        raise ParameterError(f"--workers must be an integer in [1, 1024], got {ns.workers}")
    twice = sorted({fx for fx in ns.fx if ns.fx.count(fx) > 1})
    if twice:
        raise ParameterError(f"--fx {twice[0]!r} is given {ns.fx.count(twice[0])} times; "
                             "give each F_x once")
    scene = _scene(ns, fx=max(ns.fx, key=abs)).with_fx(0.0)
    _capped(scene, "waves")
    if scene.n < MIN_WAVE_DISKS:
        raise ParameterError(f"--n {scene.n}: a wave speed is fitted over the disks' breach "
                             f"times and needs a chain of at least {MIN_WAVE_DISKS} disks")
    for fx in ns.fx:
        _check_ramp_steps(fx, ns.step, "--fx")
    _check_duration(scene, ns.duration)
    fxs = list(dict.fromkeys(ns.fx))
    protocol = {"fx": fxs, "step": ns.step, "realizations": ns.realizations, "seed": ns.seed,
                "duration_paper_units": ns.duration, "slide_threshold_2R": ns.slide_threshold,
                "scheduler": ns.scheduler}
    rd = _result_dir(ns, "waves", ["waves.npz", "waves.png", "members"], scene, protocol)
    if ns.dry_run:
        return _dry_run(ns, scene, protocol)
    rd.create()
    rd.register("members", folder=True)
    unit = time_unit(scene)
    seeds = range(ns.seed, ns.seed + ns.realizations)
    keys = {(fx, seed): member_key(f"fx{fx:g}_seed{seed}", _fingerprint(
                scene, {"member": "realization_member", "fx": fx, "step": ns.step,
                        "seed": seed, "duration_paper_units": ns.duration,
                        "slide_threshold_2R": ns.slide_threshold}))
            for fx in fxs for seed in seeds}
    members, equilibria = {}, {}
    from fricstab import progress
    loud = not ns.no_progress
    progress.compile_note(["contact laws", "chain dynamics"], enabled=loud)
    with rd.stage("equilibria"), progress.heartbeat("equilibria", loud):
        for fx in fxs:
            eq = _ramped_equilibrium(scene, fx, ns.step)
            equilibria[fx] = eq
            for seed in seeds:
                members[keys[fx, seed][0]] = dict(
                    scene=scene.with_fx(fx), equilibrium=eq, seed=seed, duration=ns.duration,
                    slide_threshold=ns.slide_threshold)
    with rd.stage("realizations"), progress.heartbeat(   # tqdm's bar: on a terminal only
            "waves: realizations", loud and not sys.stderr.isatty()):
        stored = run_ensemble(realization_member, members, rd.path, scheduler=ns.scheduler,
                              workers=ns.workers, progress=not ns.no_progress, desc="waves",
                              fingerprints=dict(keys.values()))
    results, all_reals, arrays, fits = [], {}, {}, {}
    with rd.stage("fits"), progress.heartbeat("fits", loud):
        for fx in fxs:
            sc, eq = scene.with_fx(fx), equilibria[fx]
            reals = [realization_from_arrays(stored[keys[fx, seed][0]]) for seed in seeds]
            all_reals[fx] = reals
            fit = fits[fx] = fit_waves(reals)
            _, jac = forces_and_jacobian(sc, eq)
            w = decompose(jac, mass_vector(scene), vectors=False).eigenvalues
            growth = float(np.abs(np.sqrt(w.astype(complex)).real).max()) * unit
            mode = transverse_mode(sc, eq)
            results.append({"fx": fx, "v1": fit.v1, "v1_err": fit.v1_err, "v2": fit.v2,
                            "v2_err": fit.v2_err, "v_com": fit.v_com, "v_com_err": fit.v_com_err,
                            "growth_rate": growth,
                            "v1_over_growth": fit.v1 / growth if growth > 0 else None,
                            "v2_predicted_transverse": mode.speed,
                            "transverse_omega": mode.omega,
                            "transverse_wavelength": mode.wavelength,
                            "breached_fraction": fit.breached_fraction,
                            **{f"{k}_note": NOT_DEFINED[k] for k, v in (("v1", fit.v1),
                                                                         ("v2", fit.v2))
                               if not np.isfinite(v)}})
            for key in ("tau", "x_tau", "tau_slide", "x_slide"):
                arrays[f"{key}_fx{fx!r}"] = np.array([getattr(r, key) for r in reals])
    doc = {"realizations": ns.realizations,
           "seeds": f"{ns.seed}..{ns.seed + ns.realizations - 1}",
           "duration_paper_units": ns.duration, "slide_threshold_2R": ns.slide_threshold,
           "units": "length 2R, time " + PAPER_TIME_UNIT, "results": results,
           "members": "members/fx<F>_seed<S>_<12 hex of the member's fingerprint>.npz, "
                      "one per realization"}
    if len(fxs) >= 2:
        slope, intercept = np.polyfit(fxs, [r["v_com"] for r in results], 1)
        doc["v_com_fit"] = {"intercept": float(intercept), "slope": float(slope)}
    doc.update(_meta(scene, ns, 0.0))
    with rd.stage("write"):
        rd.write_npz("waves.npz", **arrays)
        rd.write_png("waves.png", lambda tmp: wave_figure(all_reals, tmp, fits))
    _finish(rd, doc, scene, ns, argv, protocol)
    for r in results:
        print(f"F_x = {r['fx']!r}: V1 = {_speed('v1', r['v1'], r['v1_err'], '.2e', '.1e')}, "
              f"V2 = {_speed('v2', r['v2'], r['v2_err'], '.3f', '.3f')}, "
              f"v_cm = {r['v_com']:.2e}")
    print(f"wrote {rd.path}/waves.json, waves.npz, waves.png, members/")
    return 0
