"""``fricstab chain ramp|jacobian``: the chain protocol from the command line.

``fricstab chain ramp --fx-max 0.1 --step 1e-3 --out DIR [--scene FILE.toml]``
    Quasistatic F_x ramp (Newton, history carried), spectra of M^-1 J and the
    complex-pair events located by bisection; writes ``DIR/ramp.json``
    (parameters, versions, events, timings), ``DIR/ramp.npz`` (fx,
    eigenvalues, condition numbers, residuals, growth rates) and
    ``DIR/ramp.png`` (real and imaginary parts against F_x, as Charan Fig. 2).
``fricstab chain jacobian --fx F --out DIR``
    Equilibrium at F (ramped from 0 in steps of ``--step``) and its Jacobian:
    ``DIR/state.npz`` and ``DIR/jacobian.npy`` (see fricstab.chain_io).
``fricstab chain dynamics --fx F --duration T --seed S --out DIR``
    Newtonian dynamics from that equilibrium with a seeded perturbation:
    ``dynamics.json`` (first Coulomb breach per disk), ``dynamics.npz``
    (frames, M(t), centre of mass) and ``dynamics.png`` (Figs. 3, 4, 7).

Every file is written atomically (a complete file or none).
"""

import json
import platform
import sys
import time
from pathlib import Path

import numpy as np

from fricstab import __version__
from fricstab.chain import forces_and_jacobian, initial_state
from fricstab.chain_io import atomic_write, export_state, load_scene
from fricstab.laws import ParameterError
from fricstab.quasistatic import relax_newton

__all__ = ["add_parser", "run"]

PAPER_TIME_UNIT = "sqrt(m 2R / kn)"


def add_parser(sub, parser_class, positive_float):
    p = sub.add_parser("chain", help="chain of disks on a substrate (Charan et al.)")
    csub = p.add_subparsers(dest="chain_command", metavar="CHAIN_COMMAND",
                            parser_class=parser_class)
    csub.required = True
    for name, helptext in (("ramp", "quasistatic F_x ramp and complex-pair events"),
                           ("jacobian", "equilibrium at --fx and its Jacobian"),
                           ("dynamics", "Newtonian dynamics from the equilibrium at --fx"),
                           ("waves", "forward and backward waves over realizations")):
        c = csub.add_parser(name, help=helptext)
        c.add_argument("--scene", type=Path, default=None, help="TOML scene file")
        c.add_argument("--n", type=int, default=None, help="number of disks (default 10)")
        c.add_argument("--fy", type=float, default=None, help="pressing force F_y (default 0.1)")
        c.add_argument("--mu", type=float, default=None, help="friction coefficient (default 10)")
        c.add_argument("--inertia", type=float, default=None,
                       help="moment of inertia (default m R^2 / 2)")
        c.add_argument("--step", type=positive_float(), default=1e-3,
                       help="ramp step in F_x (default 1e-3)")
        c.add_argument("--out", type=Path, required=True, help="output directory")
        c.add_argument("--no-progress", action="store_true", help="no progress bar")
        if name == "ramp":
            c.add_argument("--fx-max", type=positive_float(), default=0.1,
                           help="largest F_x (default 0.1)")
            c.add_argument("--tol", type=positive_float(), default=1e-6,
                           help="bisection tolerance in F_x (default 1e-6)")
        elif name == "waves":
            c.add_argument("--fx", type=positive_float(), nargs="+", default=[0.083, 0.087, 0.090],
                           help="F_x values (default: the paper's 0.083 0.087 0.090)")
            c.add_argument("--realizations", type=int, default=25,
                           help="seeded realizations per F_x (default 25)")
            c.add_argument("--duration", type=positive_float(), default=25000.0,
                           help="duration in Charan's time unit (default 25000)")
            c.add_argument("--slide-threshold", type=positive_float(), default=0.02,
                           help="displacement (2R) that counts as sliding (default 0.02)")
        else:
            c.add_argument("--fx", type=float, required=True, help="F_x of the equilibrium")
        if name == "dynamics":
            c.add_argument("--duration", type=positive_float(), default=20000.0,
                           help="duration in Charan's time unit sqrt(m 2R/kn) (default 20000)")
            c.add_argument("--seed", type=int, default=0, help="seed of the perturbation")
            c.add_argument("--amplitude", type=positive_float(), default=1e-9,
                           help="perturbation, times the wall overlap (default 1e-9)")
            c.add_argument("--disk", type=int, default=3,
                           help="disk whose trajectory is drawn (default 3: the paper's 4th)")
    return p


def _scene(ns):
    return load_scene(ns.scene, n=ns.n, fy=ns.fy, mu=ns.mu, inertia=ns.inertia)


def _meta(scene, ns, seconds):
    import numba
    import scipy
    return {
        "scene": {k: getattr(scene, k) for k in ("n", "radius", "mass", "kn", "kt", "mu", "fy",
                                                  "inertia")},
        "paper_time_unit": PAPER_TIME_UNIT,
        "command": " ".join(sys.argv),
        "seconds": round(seconds, 3),
        "versions": {"fricstab": __version__, "numpy": np.__version__,
                     "scipy": scipy.__version__, "numba": numba.__version__,
                     "python": platform.python_version()},
    }


def _prepare_out(path):
    path = path.expanduser()
    if path.exists() and not path.is_dir():
        raise ParameterError(f"--out: {path} exists and is not a directory")
    path.mkdir(parents=True, exist_ok=True)
    return path


def _ramp(ns):
    from tqdm import tqdm

    from fricstab.ramp import run_ramp

    scene = _scene(ns)
    out = _prepare_out(ns.out)
    steps = int(round(ns.fx_max / ns.step)) + 1
    with tqdm(total=steps, desc="ramp", unit="step", disable=ns.no_progress or None,
              file=sys.stderr) as bar:
        res = run_ramp(scene, ns.fx_max, ns.step, tol=ns.tol, progress=bar)
    unit2 = scene.mass * 2 * scene.radius / scene.kn  # eigenvalues in paper units
    events = [{"kind": e.kind, "fx": e.fx, "fx_lo": e.fx_lo, "fx_hi": e.fx_hi,
               "located": e.located, "bisections": e.bisections,
               "pair_real_part_paper_units": e.pair_center * unit2} for e in res.events]
    doc = {"protocol": "quasistatic ramp, Newton relaxation from the previous step",
           "fx_max": ns.fx_max, "step": ns.step, "tol": ns.tol, "events": events,
           "max_residual": float(res.residual.max()), **_meta(scene, ns, res.seconds)}

    def npz(tmp):
        with open(tmp, "wb") as fh:
            np.savez(fh, fx=res.fx, eigenvalues=res.eigenvalues, condition=res.condition,
                     residual=res.residual, growth=res.growth, eigenvalue_unit=unit2)

    atomic_write(out / "ramp.npz", npz)
    atomic_write(out / "ramp.png", lambda tmp: _figure(res, events, unit2, tmp))
    atomic_write(out / "ramp.json",
                 lambda tmp: Path(tmp).write_text(json.dumps(doc, indent=2) + "\n"))
    print(f"{len(events)} complex-pair events in F_x in [0, {ns.fx_max:g}] "
          f"({res.seconds:.1f} s); max residual {res.residual.max():.1e}")
    for e in events:
        flag = "" if e["located"] else "  (not located: refine --step)"
        print(f"  {e['kind']:5s} at F_x = {e['fx']:.7f} +- {0.5 * (e['fx_hi'] - e['fx_lo']):.1e}{flag}")
    print(f"wrote {out}/ramp.json, ramp.npz, ramp.png")
    return 0


def _figure(res, events, unit2, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (top, bottom) = plt.subplots(2, 1, figsize=(8, 6.5), sharex=True)
    w = res.eigenvalues * unit2
    top.plot(res.fx, w.real, color="0.75", lw=0.6)
    cplx = np.where(np.abs(w.imag) > 0, w.real, np.nan)
    top.plot(res.fx, cplx, color="C3", lw=1.4)
    bottom.plot(res.fx, np.where(w.imag > 0, w.imag, np.nan), color="C3", lw=1.4)
    for e in events:
        for ax in (top, bottom):
            ax.axvline(e["fx"], color="C0" if e["kind"] == "birth" else "C2", lw=0.6, ls="--")
    top.set_ylabel("Re eigenvalue of $M^{-1}J$ (paper units)")
    bottom.set_ylabel("Im eigenvalue (paper units)")
    bottom.set_xlabel("$F_x$")
    top.set_title("Chain ramp: complex pairs (red); births blue, deaths green")
    fig.tight_layout()
    fig.savefig(path, dpi=120, format="png")
    plt.close(fig)


def _ramped_equilibrium(scene, fx, step):
    """Newton ramp from 0 to fx in steps <= step; None if a step fails."""
    state = relax_newton(scene, initial_state(scene)).state
    n_steps = max(1, int(np.ceil(abs(fx) / step)))
    for f in np.linspace(0.0, fx, n_steps + 1)[1:]:
        res = relax_newton(scene.with_fx(f), state)
        if not res.converged:
            print(f"fricstab: error: no equilibrium at F_x = {f:.6g} "
                  f"(residual {res.residual:.1e})", file=sys.stderr)
            return None
        state = res.state
    return state


def _jacobian(ns):
    scene = _scene(ns)
    out = _prepare_out(ns.out)
    t0 = time.perf_counter()
    state = _ramped_equilibrium(scene, ns.fx, ns.step)
    if state is None:
        return 4
    loaded = scene.with_fx(ns.fx)
    f, jac = forces_and_jacobian(loaded, state)
    export_state(loaded, state, jac, out)
    print(f"equilibrium at F_x = {ns.fx:g}: max |F| = {np.abs(f).max():.1e} "
          f"({time.perf_counter() - t0:.2f} s); wrote {out}/state.npz, jacobian.npy")
    return 0


def _dynamics(ns):
    from fricstab.dynamics import run_dynamics
    from fricstab.observables import centre_of_mass, first_breach, msd, paper_time

    scene = _scene(ns)
    if not 0 <= ns.disk < scene.n:
        raise ParameterError(f"--disk must be in [0, {scene.n - 1}], got {ns.disk}")
    out = _prepare_out(ns.out)
    state = _ramped_equilibrium(scene, ns.fx, ns.step)
    if state is None:
        return 4
    loaded = scene.with_fx(ns.fx)
    rng = np.random.default_rng(ns.seed)
    start = state.copy()
    start.q += ns.amplitude * (scene.fy / scene.kn) ** (2 / 3) * rng.standard_normal(state.q.shape)
    unit = np.sqrt(scene.mass * 2 * scene.radius / scene.kn)
    res = run_dynamics(loaded, start, duration=ns.duration * unit, frames=4000)
    t = paper_time(scene, res.times)
    m = msd(res.positions)
    com = centre_of_mass(res.positions)
    tau, x_tau = first_breach(loaded, res.times, res.positions, res.wall_t)
    from fricstab.waves import first_slide
    tau_s, x_s = first_slide(scene, t, res.positions, state.q)
    doc = {"protocol": "Newton ramp to F_x, seeded perturbation, undamped velocity Verlet",
           "fx": ns.fx, "seed": ns.seed, "amplitude": ns.amplitude,
           "duration_paper_units": ns.duration, "time_unit": PAPER_TIME_UNIT,
           "first_breach_paper_time": [None if np.isnan(v) else float(v)
                                       for v in paper_time(scene, tau)],
           "first_breach_x": [None if np.isnan(v) else float(v) for v in x_tau],
           "first_slide_paper_time": [None if np.isnan(v) else float(v) for v in tau_s],
           "slide_threshold_2R": 0.02,
           "final_msd": float(m[-1]), **_meta(scene, ns, res.seconds)}

    def npz(tmp):
        with open(tmp, "wb") as fh:
            np.savez(fh, time=t, positions=res.positions, wall_t=res.wall_t, msd=m,
                     centre_of_mass=com, first_breach_time=paper_time(scene, tau),
                     first_breach_x=x_tau)

    atomic_write(out / "dynamics.npz", npz)
    atomic_write(out / "dynamics.png",
                 lambda tmp: _dynamics_figure(t, m, com, res.positions, ns.disk, tmp))
    atomic_write(out / "dynamics.json",
                 lambda tmp: Path(tmp).write_text(json.dumps(doc, indent=2) + "\n"))
    print(f"dynamics at F_x = {ns.fx:g} for {ns.duration:g} time units ({res.seconds:.1f} s): "
          f"final M(t) = {m[-1]:.3e}; disks at the Coulomb limit: {int(np.sum(~np.isnan(tau)))}"
          f"/{scene.n}; wrote {out}/dynamics.json, dynamics.npz, dynamics.png")
    return 0


def _dynamics_figure(t, m, com, positions, disk, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 3, figsize=(14, 4))
    axes[0].semilogy(t[1:], m[1:])  # M(0) = 0
    axes[0].set_xlabel("t (paper units)")
    axes[0].set_ylabel("M(t)")
    axes[0].set_title("mean-square displacement (Fig. 3)")
    sc = axes[1].scatter(positions[:, disk, 0], positions[:, disk, 1], c=t, s=1, cmap="viridis")
    fig.colorbar(sc, ax=axes[1], label="t (paper units)")
    axes[1].set_xlabel("x")
    axes[1].set_ylabel("y")
    axes[1].set_title(f"trajectory of disk {disk} (Fig. 4)")
    axes[2].plot(t, com[:, 0] - com[0, 0], label="x")
    axes[2].plot(t, com[:, 1] - com[0, 1], label="y")
    axes[2].set_xlabel("t (paper units)")
    axes[2].set_ylabel("centre of mass - initial")
    axes[2].legend()
    axes[2].set_title("centre of mass (Fig. 7)")
    fig.tight_layout()
    fig.savefig(path, dpi=110, format="png")
    plt.close(fig)


def _waves(ns):
    from tqdm import tqdm

    from fricstab.modes import transverse_mode
    from fricstab.spectrum import decompose
    from fricstab.chain import mass_vector
    from fricstab.waves import fit_waves, run_realization, wave_figure

    if ns.realizations < 2:
        raise ParameterError(f"--realizations must be >= 2, got {ns.realizations}")
    scene = _scene(ns)
    out = _prepare_out(ns.out)
    t0 = time.perf_counter()
    unit = np.sqrt(scene.mass * 2 * scene.radius / scene.kn)
    results, all_reals, arrays = [], {}, {}
    with tqdm(total=len(ns.fx) * ns.realizations, desc="waves", unit="run",
              disable=ns.no_progress or None, file=sys.stderr) as bar:
        for fx in ns.fx:
            eq = _ramped_equilibrium(scene, fx, ns.step)
            if eq is None:
                return 4
            sc = scene.with_fx(fx)
            reals = []
            for seed in range(ns.realizations):
                reals.append(run_realization(sc, eq, seed, duration=ns.duration,
                                             slide_threshold=ns.slide_threshold))
                bar.update(1)
            all_reals[fx] = reals
            fit = fit_waves(reals)
            _, jac = forces_and_jacobian(sc, eq)
            w = decompose(jac, mass_vector(scene), vectors=False).eigenvalues
            growth = float(np.abs(np.sqrt(w.astype(complex)).real).max()) * unit
            mode = transverse_mode(sc, eq)
            results.append({"fx": fx, "v1": fit.v1, "v1_err": fit.v1_err, "v2": fit.v2,
                             "v2_err": fit.v2_err, "v_com": fit.v_com, "v_com_err": fit.v_com_err,
                             "growth_rate": growth, "v1_over_growth": fit.v1 / growth,
                             "v2_predicted_transverse": mode.speed,
                             "transverse_omega": mode.omega,
                             "transverse_wavelength": mode.wavelength,
                             "breached_fraction": fit.breached_fraction})
            for key in ("tau", "x_tau", "tau_slide", "x_slide"):
                arrays[f"{key}_fx{fx:g}"] = np.array([getattr(r, key) for r in reals])
    doc = {"realizations": ns.realizations, "seeds": f"0..{ns.realizations - 1}",
           "duration_paper_units": ns.duration, "slide_threshold_2R": ns.slide_threshold,
           "units": "length 2R, time " + PAPER_TIME_UNIT, "results": results}
    if len(ns.fx) >= 2:
        slope, intercept = np.polyfit(ns.fx, [r["v_com"] for r in results], 1)
        doc["v_com_fit"] = {"intercept": float(intercept), "slope": float(slope)}
    doc.update(_meta(scene, ns, time.perf_counter() - t0))

    def npz(tmp):
        with open(tmp, "wb") as fh:
            np.savez(fh, **arrays)

    atomic_write(out / "waves.npz", npz)
    atomic_write(out / "waves.png", lambda tmp: wave_figure(all_reals, tmp))
    atomic_write(out / "waves.json",
                 lambda tmp: Path(tmp).write_text(json.dumps(doc, indent=2) + "\n"))
    for r in results:
        print(f"F_x = {r['fx']:g}: V1 = {r['v1']:.2e} +- {r['v1_err']:.1e}, "
              f"V2 = {r['v2']:.3f} +- {r['v2_err']:.3f}, v_cm = {r['v_com']:.2e}")
    print(f"wrote {out}/waves.json, waves.npz, waves.png")
    return 0


def run(ns):
    if ns.chain_command == "waves":
        return _waves(ns)
    if ns.chain_command == "ramp":
        return _ramp(ns)
    if ns.chain_command == "dynamics":
        return _dynamics(ns)
    return _jacobian(ns)
