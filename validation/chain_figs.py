"""Charan Figs. 3, 4 and 7 from our dynamics, under four readings of the moment of inertia.

What the paper states (p. 2-4):

* Fig. 3, F_x = 0.083: the instability brings "M(t) to about 10^-2 R where for
  the first time the Coulomb law is breached at the contact with the
  substrate, and subsequently M(t) increases linearly in time with a fixed
  average velocity".
* Fig. 4: "The actual trajectory in the x-y plane (for t ~ 17500) that is
  induced by the instability. Here we show the fourth grain (i = 4)"; "A spiral
  in the x-y plane leads in time to an increase in y_i to the point that
  breaching the Coulomb law ... becomes inevitable".
* Fig. 7, F_x = 0.087: C^x_mass; "the upper inset shows the y component of the
  centre of mass that oscillates without growth"; the lower inset: a transition
  "like a simple first order transition from static to dynamics with a fixed
  velocity".

For F_x = 0.083 and 0.087, the inertia readings ``physical`` (I = m R^2/2),
``lammps`` (2/5 m R^2), ``sm`` (m R^2) and ``bare`` (m (2R)^2)
(:data:`fricstab.scenes.chain.CONVENTIONS`) and seeds 0..4: the Newton-ramped
equilibrium perturbed by 1e-9 of the rest wall overlap (as
``validation/chain_waves.py``), undamped Verlet for 25,000 paper time units,
a frame every paper time unit.  Measures (:mod:`fricstab.analysis.chain_orbits`;
rules in ``docs/reference/chain_figures.md``): M and the time at the first
breach; disk 4's orbit before it (turns, monotonic fraction, envelope rate
over the Jacobian's growth rate, aspect against the growing mode's); C_y's
growth in the linear stretch against the disks' and after the transition;
C_x's velocity after every disk breached.  Writes ``chain_figs.md`` and
``chain_figs.png``; :func:`run` returns the numbers.

    python validation/chain_figs.py [--seeds 5] [--duration 25000]
"""

import argparse
import math
import platform
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))

import numpy as np  # noqa: E402

from fricstab.analysis.chain_orbits import (amplitude, centre_growth, disk_orbit,  # noqa: E402
                                            mode_ellipse, sliding_velocity)
from fricstab.analysis.observables import first_breach, msd, paper_time  # noqa: E402
from fricstab.analysis.spectrum import decompose, growth_rate  # noqa: E402
from fricstab.errors import ParameterError  # noqa: E402
from fricstab.figures.common import finish, pyplot  # noqa: E402
from fricstab.protocols.dynamics import perturbed, run_dynamics  # noqa: E402
from fricstab.protocols.ramp import ramped_equilibrium  # noqa: E402
from fricstab.scenes.chain import (ChainScene, convention_scene, forces_and_jacobian,  # noqa: E402
                                   mass_vector, time_unit)

REPORT, FIGURE = HERE / "chain_figs.md", HERE / "chain_figs.png"
FXS = (0.083, 0.087)
READINGS = ("physical", "lammps", "sm", "bare")
DISK = 3                      # the paper's i = 4
AMPLITUDE = 1e-9              # of the rest wall overlap, as chain_waves.py
WINDOW = 300.0                # paper time units (~11 periods) for the C_y amplitudes
#: Fig. 3's "about 10^-2 R" with R = 0.5 (2R units), and read as 10^-2 R^2.
PAPER_M = {"1e-2 R": 0.01 * 0.5, "1e-2 R^2": 0.01 * 0.25}
PAPER_FIG4_T = 17500.0
#: Eq. 10 with the intercept read as -1.3e-5 (validation/chain_waves.md).
EQ10_READ = (-1.3e-5, 4.5e-4)


def mode(scene, eq):
    """Growth rate, frequency (paper units) of the fastest-growing mode, the runner-up's
    rate, and disk 4's predicted (aspect, sense) in it."""
    unit = time_unit(scene)
    _, jac = forces_and_jacobian(scene, eq)
    sp = decompose(jac, mass_vector(scene))
    s = np.sqrt(sp.eigenvalues.astype(complex))
    order = np.argsort(-np.abs(s.real))
    k = int(order[0])
    second = next((abs(s[j].real) for j in order[1:]
                   if not np.isclose(sp.eigenvalues[j], np.conj(sp.eigenvalues[k]))), 0.0)
    aspect, sense = mode_ellipse(sp.eigenvalues[k], sp.right[:, k], DISK)
    return {"growth": growth_rate(sp.eigenvalues) * unit, "omega": float(abs(s[k].imag)) * unit,
            "second_growth": float(second) * unit, "aspect_mode": aspect, "sense_mode": sense}


def _line_residual(t, y):
    """RMS residual of a straight line through (t, y) over the mean of |y|."""
    fit = np.polyval(np.polyfit(t, y, 1), t)
    return float(np.sqrt(((y - fit) ** 2).mean()) / np.abs(y).mean())


def measure(scene, t, pos, tau, eq, growth):
    """The numbers of one run (paper units: time sqrt(m 2R/kn), length 2R)."""
    length = 2 * scene.radius
    out = {"tau_first": None, "tau_last": None, "m_breach": None}
    m = msd(pos) / length ** 2
    breached = np.isfinite(tau).any()
    t_b = float(np.nanmin(tau)) if breached else None
    if breached:
        out.update(tau_first=t_b, m_breach=float(m[np.searchsorted(t, t_b)]))
    if np.isfinite(tau).all():
        out["tau_last"] = float(tau.max())
    try:
        o = disk_orbit(t, pos / length, eq.q / length, DISK, t_end=t_b)
    except ParameterError as exc:
        out["orbit_error"] = str(exc)
        return out
    out.update(turns=o.turns, monotonic=o.monotonic, rate=o.rate, rate_ratio=o.rate / growth,
               omega_orbit=o.omega, aspect=o.aspect, window=list(o.window),
               rate_residual=o.residual, spiral=bool(o.monotonic >= 0.95 and abs(o.turns) >= 5))
    w0, w1 = o.window
    cy, disks = centre_growth(t, pos, (w0, w0 + WINDOW), (w1 - WINDOW, w1))
    out.update(cy_growth=cy, disk_y_growth=float(np.median(disks)),
               cy_ratio=cy / float(np.median(disks)),
               cy_amp_late=amplitude(t, pos[:, :, 1].mean(axis=1) / length, (w1 - WINDOW, w1)))
    t_end = float(t[-1])
    if out["tau_last"] is not None and t_end - out["tau_last"] > 4 * WINDOW:
        t_from = max(0.7 * t_end, out["tau_last"])
        mid = 0.5 * (t_from + t_end)
        out["cy_post_growth"] = centre_growth(t, pos, (t_from, mid), (mid, t_end))[0]
        out["v_cm"] = sliding_velocity(t, pos, t_from) / length
        late = t >= t_from
        out["m_line_residual"] = _line_residual(t[late], m[late])
        out["sqrt_m_line_residual"] = _line_residual(t[late], np.sqrt(m[late]))
    return out


def study(seeds=5, duration=25000.0):
    """All runs: values per (F_x, reading) and seed, and the traces the figure draws."""
    base = ChainScene()
    rows, traces = [], {}
    for fx in FXS:
        eq = ramped_equilibrium(base, fx)
        for reading in READINGS:
            sc = convention_scene(base, reading).with_fx(fx)
            unit = time_unit(sc)
            row = {"fx": fx, "reading": reading, "inertia": sc.inertia, **mode(sc, eq),
                   "runs": []}
            for seed in range(seeds):
                start = perturbed(sc, eq, AMPLITUDE, np.random.default_rng(seed))
                res = run_dynamics(sc, start, duration=duration * unit, frames=int(duration))
                t = paper_time(sc, res.times)
                tau = paper_time(sc, first_breach(sc, res.times, res.positions, res.wall_hist)[0])
                pos = res.positions[:, :, :2]
                run_ = {"seed": seed, **measure(sc, t, pos, tau, eq, row["growth"])}
                row["runs"].append(run_)
                if seed == 0:
                    traces[(fx, reading)] = (t, pos, eq.q[:, :2].copy(), run_)
            rows.append(row)
            print(_line(row), flush=True)
    return rows, traces


def _stat(row, key):
    """(mean, std, count) of ``key`` over the runs that have it."""
    v = np.array([r[key] for r in row["runs"] if r.get(key) is not None], dtype=float)
    if v.size == 0:
        return math.nan, math.nan, 0
    return float(v.mean()), float(v.std(ddof=1)) if v.size > 1 else 0.0, int(v.size)


def _fmt(row, key, spec=".3g"):
    mean, std, n = _stat(row, key)
    if n == 0:
        return "-"
    return f"{mean:{spec}}" + (f" +- {std:{spec}}" if n > 1 else "")


def _median(row, key):
    v = [r[key] for r in row["runs"] if r.get(key) is not None]
    return f"{float(np.median(v)):.2e}" if v else "-"


def _count(row, key):
    """(true, known) counts of a boolean over the runs."""
    v = [bool(r[key]) for r in row["runs"] if r.get(key) is not None]
    return sum(v), len(v)


def _line(row):
    n = len(row["runs"])
    return (f"F_x {row['fx']} {row['reading']:8s} I {row['inertia']:.3f}: growth "
            f"{row['growth']:.2e}, breached {_stat(row, 'tau_first')[2]}/{n}, tau1 "
            f"{_fmt(row, 'tau_first', '.0f')}, M(tau1) {_fmt(row, 'm_breach', '.2e')}, turns "
            f"{_fmt(row, 'turns', '.0f')}, mono {_fmt(row, 'monotonic', '.2f')}, rate/growth "
            f"{_fmt(row, 'rate_ratio', '.3f')}, C_y growth {_fmt(row, 'cy_growth', '.2e')} "
            f"(disks {_fmt(row, 'disk_y_growth', '.2e')}), post "
            f"{_fmt(row, 'cy_post_growth', '.2f')}")


TABLE_HEAD = ("| F_x | reading (I / m R^2) | growth rate (Jacobian) | runner-up rate | omega |"
              " breached | first breach tau_1 | M(tau_1) (2R)^2 | turns | monotonic |"
              " envelope rate / growth | aspect x/y (mode) | C_y growth (median) |"
              " C_y / disks' y growth | C_y growth after | v_cm |")


def table(rows):
    """The markdown table of seed means +- standard deviations."""
    lines = [TABLE_HEAD, "|" + "---|" * (TABLE_HEAD.count("|") - 1)]
    for r in rows:
        n = len(r["runs"])
        lines.append(
            f"| {r['fx']} | {r['reading']} ({r['inertia'] / 0.25:.2f}) | {r['growth']:.2e} | "
            f"{r['second_growth']:.2e} | {r['omega']:.3f} | {_stat(r, 'tau_first')[2]}/{n} | "
            f"{_fmt(r, 'tau_first', '.0f')} | {_fmt(r, 'm_breach', '.2e')} | "
            f"{_fmt(r, 'turns', '.0f')} | {_fmt(r, 'monotonic', '.2f')} | "
            f"{_fmt(r, 'rate_ratio', '.3f')} | {_fmt(r, 'aspect', '.2f')} "
            f"({r['aspect_mode']:.2f}) | {_median(r, 'cy_growth')} | "
            f"{_fmt(r, 'cy_ratio', '.2f')} | {_fmt(r, 'cy_post_growth', '.2f')} | "
            f"{_fmt(r, 'v_cm', '.2e')} |")
    return lines


def _fig3(r, name):
    """Fig. 3: M at the first breach against the paper's two readings; M's shape after."""
    mb = _stat(r, "m_breach")[0]
    if math.isnan(mb):
        return f"* Fig. 3, {name}: no breach within the run (the paper: breach and sliding): " \
               "DISAGREES."
    near = min(PAPER_M.values(), key=lambda p: abs(math.log(mb / p)))
    fac = mb / near
    res_m, res_sqrt = _stat(r, "m_line_residual")[0], _stat(r, "sqrt_m_line_residual")[0]
    shape = "" if math.isnan(res_m) else (
        "; after the transition M(t) is "
        + ("closer to a line" if res_m < res_sqrt else
           "closer to a parabola (sqrt M linear: a fixed velocity)")
        + f" (relative line residuals: M {res_m:.3f}, sqrt M {res_sqrt:.3f})")
    return (f"* Fig. 3, {name}: M at the first breach {mb:.2e} (2R)^2, {fac:.2g}x the nearer "
            f"paper reading ({near:g}): {'AGREES' if 1 / 3 <= fac <= 3 else 'DISAGREES'} "
            f"(rule: within 3x){shape}.")


def _fig4(r, name):
    """Fig. 4: disk 4 winds one way (majority of seeds) at the Jacobian's rate."""
    mono, turns, ratio = (_stat(r, k) for k in ("monotonic", "turns", "rate_ratio"))
    k, n = _count(r, "spiral")
    sense = sum(1 for x in r["runs"] if "turns" in x and np.sign(x["turns"]) == r["sense_mode"])
    tb = _fmt(r, "tau_first", ".0f")
    return (f"* Fig. 4, {name}: disk 4 winds {turns[0]:.0f} turns with monotonic fraction "
            f"{mono[0]:.2f}; a one-way spiral in {k}/{n} seeds: "
            f"{'AGREES' if 2 * k > n else 'DISAGREES'} (rule: majority); sense as the growing "
            f"mode's in {sense}/{n}; envelope rate / Jacobian growth {ratio[0]:.3f} +- "
            f"{ratio[1]:.3f}; first breach " + (f"at {tb}" if tb != "-" else "none in the run")
            + f" (the paper shows a pre-breach orbit at t ~ {PAPER_FIG4_T:.0f}).")


def _fig7(r, name):
    """Fig. 7: C_y's growth in the linear stretch and after the transition; C_x's velocity."""
    cy = float(np.median([x["cy_growth"] for x in r["runs"] if "cy_growth" in x]))
    ratio, post, v = (_stat(r, k)[0] for k in ("cy_ratio", "cy_post_growth", "v_cm"))
    grows = cy > 10 and ratio >= 0.3
    post_txt = "no transition in the run" if math.isnan(post) else (
        f"after the transition x{post:.2f} "
        f"({'no growth: AGREES' if 0.5 <= post <= 2 else 'DISAGREES'})")
    eq10 = EQ10_READ[0] + EQ10_READ[1] * r["fx"]
    return (f"* Fig. 7, {name}: C_y grows x{cy:.2e} (median) over the linear stretch, to an "
            f"amplitude {_stat(r, 'cy_amp_late')[0]:.1e} (2R) at its end (invisible on a "
            f"linear axis), {ratio:.2f} x the disks' y growth: "
            + ("GROWS (DISAGREES with no growth there)" if grows else "no growth (AGREES)")
            + f"; {post_txt}; v_cm " + ("-" if math.isnan(v) else f"{v:.2e}")
            + f" (Eq. 10 read with -1.3e-5: {eq10:.2e}).")


def verdicts(rows):
    """One verdict line per figure and reading (rules: docs/reference/chain_figures.md)."""
    out = []
    for r in rows:
        name = f"{r['reading']} at F_x = {r['fx']}"
        out += [_fig3(r, name), _fig4(r, name)] if r["fx"] == FXS[0] else [_fig7(r, name)]
    return out


def figure(traces, path):
    """Three panels: M(t) at 0.083, disk 4's orbit before the breach, C_x and C_y at 0.087."""
    plt = pyplot()
    fig, ax = plt.subplots(1, 3, figsize=(15, 4.6))
    for reading in READINGS:
        t, pos, q0, r = traces[(FXS[0], reading)]
        m = msd(pos)
        line, = ax[0].loglog(t[1:], m[1:], lw=0.8, label=reading)
        if r["tau_first"] is not None:
            ax[0].plot(r["tau_first"], r["m_breach"], "o", color=line.get_color())
    for (label, level), va in zip(PAPER_M.items(), ("bottom", "top")):
        ax[0].axhline(level, ls="--", color="0.4", lw=0.8)
        ax[0].text(2, level * (1.5 if va == "bottom" else 0.7), f"paper {label}", fontsize=7,
                   va=va)
    ax[0].set(xlabel="t (sqrt(m 2R/kn))", ylabel="M(t) ((2R)^2)",
              title="Fig. 3: M(t), F_x = 0.083 (dots: first breach)")
    ax[0].legend(fontsize=7)
    t, pos, q0, r = traces[(FXS[0], "physical")]
    t_b = r["window"][1] if "window" in r else t[-1]      # end of the linear stretch
    sel = (t >= t_b - 300) & (t <= t_b)
    d = pos[sel, DISK] - q0[DISK]
    sc = ax[1].scatter(d[:, 0], d[:, 1], c=t[sel], s=2, cmap="viridis")
    ax[1].plot(d[:, 0], d[:, 1], lw=0.3, color="0.5")
    fig.colorbar(sc, ax=ax[1], label="t (sqrt(m 2R/kn))")
    ax[1].set(xlabel="x - x0 (2R)", ylabel="y - y0 (2R)",
              title=f"Fig. 4: disk 4, physical, F_x = 0.083, t in [{t_b - 300:.0f}, {t_b:.0f}]\n"
                    "(the end of the linear growth, before the first breach)")
    t, pos, q0, r = traces[(FXS[1], "physical")]
    cx, cy = pos[:, :, 0].mean(axis=1), pos[:, :, 1].mean(axis=1)
    ax[2].plot(t, cx - cx[0], color="C0", lw=0.8)
    ax[2].set(xlabel="t (sqrt(m 2R/kn))", ylabel="C_x - C_x(0) (2R)", title="Fig. 7: F_x = 0.087, physical")
    twin = ax[2].twinx()
    twin.plot(t, cy - cy[0], color="C3", lw=0.5)
    twin.set_ylabel("C_y - C_y(0) (2R)", color="C3")
    if r["tau_first"] is not None:
        ax[2].axvline(r["tau_first"], ls=":", color="k", lw=0.8)
    fig.tight_layout()
    finish(fig, path)


def report(rows, seconds, seeds, duration):
    """The text of ``chain_figs.md``."""
    lines = [
        "# Chain: Charan Figs. 3, 4 and 7 under four inertia readings",
        "",
        f"`python validation/chain_figs.py --seeds {seeds} --duration {duration:g}` "
        f"({seconds:.0f} s, {platform.machine()}, Python {platform.python_version()}, "
        f"{time.strftime('%Y-%m-%d')}). Paper units: length 2R, time sqrt(m 2R/kn).",
        f"Newton-ramped equilibrium, perturbation {AMPLITUDE:g} of the rest wall overlap per "
        f"seed (0..{seeds - 1}), undamped Verlet for {duration:g}, a frame per time unit.",
        "Mean +- standard deviation over the seeds that have the value; measures and verdict",
        "rules: `docs/reference/chain_figures.md`. Growth rates and omega: the fastest-",
        "growing mode of the reading's M^-1 J (runner-up: the next pair). Disk 4 = index 3.",
        "",
        *table(rows),
        "",
        "Verdicts:",
        "",
        *verdicts(rows),
        "",
        "![figures](chain_figs.png)",
    ]
    return "\n".join(lines) + "\n"


def run(seeds=5, duration=25000.0):
    """The study: write ``chain_figs.md`` and ``chain_figs.png``; returns the values."""
    t0 = time.perf_counter()
    rows, traces = study(seeds, duration)
    REPORT.write_text(report(rows, time.perf_counter() - t0, seeds, duration))
    figure(traces, FIGURE)
    return {"seeds": seeds, "duration": duration, "rows": rows}


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--seeds", type=int, default=5)
    p.add_argument("--duration", type=float, default=25000.0)
    ns = p.parse_args(argv)
    run(ns.seeds, ns.duration)
    print(REPORT.read_text(), end="")


if __name__ == "__main__":
    main()
