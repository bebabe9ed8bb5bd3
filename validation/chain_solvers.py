"""Newton (verified Jacobian) against the damped protocol, side by side.

Both solvers ramp F_x from 0 in the same steps, each relaxing from its own
previous equilibrium (so each carries its own history), to the same residual
max |F|, |T| < 1e-12.  Reports the time per equilibrium of each, their ratio,
and the difference of the two equilibria (positions, pair and wall
histories) along the ramp, and the first complex-pair birth each finds at the
ramp's resolution.  Writes ``chain_solvers.md``; :func:`run` returns the
numbers (the claim ``chain.newton_speedup`` of ``validation/claims/chain.py``).

    python validation/chain_solvers.py [--fx-max 0.03] [--step 1e-3] [--nu 0.01]
"""

import argparse
import platform
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))

import numpy as np  # noqa: E402

from fricstab.analysis.spectrum import complex_pairs, decompose  # noqa: E402
from fricstab.protocols.dynamics import relax_damped  # noqa: E402
from fricstab.protocols.ramp import relax_newton  # noqa: E402
from fricstab.scenes.chain import (ChainScene, forces_and_jacobian, initial_state,  # noqa: E402
                                   mass_vector, pair_history, wall_history)

REPORT = HERE / "chain_solvers.md"


def compare(fx_max=0.03, step=1e-3, nu=0.01):
    """Ramp both solvers side by side; returns (summary dict, table rows)."""
    scene = ChainScene()
    # Warm up both (numba compilation is not part of the comparison).
    relax_newton(scene, initial_state(scene))
    relax_damped(scene, initial_state(scene), tol=1e-6)
    s_n = s_d = initial_state(scene)
    rows, t_newton, t_damped, first = [], 0.0, 0.0, {}
    mass = mass_vector(scene)
    worst = {"newton": 0.0, "damped": 0.0}
    for fx in np.round(np.arange(0.0, fx_max + step / 2, step), 12):
        sc = scene.with_fx(fx)
        rn = relax_newton(sc, s_n)
        rd = relax_damped(sc, s_d, nu=nu)
        s_n, s_d = rn.state, rd.state
        t_newton += rn.seconds
        t_damped += rd.seconds
        worst["newton"] = max(worst["newton"], float(rn.residual))
        worst["damped"] = max(worst["damped"], float(rd.residual))
        for name, st in (("newton", s_n), ("damped", s_d)):
            _, jac = forces_and_jacobian(sc, st)
            if name not in first and len(complex_pairs(decompose(jac, mass, False).eigenvalues)):
                first[name] = float(fx)
        rows.append((fx, rn.residual, rd.residual, rn.seconds, rd.seconds, rd.steps,
                     np.abs(s_n.q - s_d.q).max(),
                     np.abs(pair_history(sc, s_n) - pair_history(sc, s_d)).max(),
                     np.abs(wall_history(sc, s_n) - wall_history(sc, s_d)).max()))
    summary = {"fx_max": fx_max, "step": step, "nu": nu,
               "seconds_newton": t_newton, "seconds_damped": t_damped,
               "speedup": t_damped / t_newton,
               "first_pair_newton": first.get("newton"), "first_pair_damped": first.get("damped"),
               "max_residual_newton": worst["newton"], "max_residual_damped": worst["damped"],
               "max_dq_at_end": float(rows[-1][6])}
    return summary, rows


def report(summary, rows):
    """The text of ``chain_solvers.md``."""
    s = summary
    lines = [
        "# Chain: Newton against the damped protocol",
        "",
        f"`python validation/chain_solvers.py --fx-max {s['fx_max']} --step {s['step']} "
        f"--nu {s['nu']}`, {platform.machine()}, {platform.python_version()}, "
        f"{time.strftime('%Y-%m-%d')}.",
        "Both ramp F_x in the same steps from their own previous equilibria to",
        "max |F|, |T| < 1e-12 (numba compiled beforehand). Damped protocol: velocity",
        f"Verlet with drag m nu v, nu = {s['nu']} (simulation units), dt = 0.05 / omega_wall,",
        "history advanced every step.",
        "",
        f"* total time: Newton {s['seconds_newton']:.3f} s, damped {s['seconds_damped']:.1f} s: "
        f"Newton **{s['speedup']:.0f}x** faster (one run, on a machine shared with other jobs)",
        f"* first complex pair at the ramp resolution: Newton F_x = {s['first_pair_newton']}, "
        f"damped F_x = {s['first_pair_damped']}",
        "",
        "| F_x | residual Newton | residual damped | s Newton | s damped | Verlet steps |"
        " max |dq| | max |d t_pair| | max |d t_wall| |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        lines.append(f"| {r[0]:.3f} | {r[1]:.1e} | {r[2]:.1e} | {r[3]:.4f} | {r[4]:.3f} | {r[5]} |"
                     f" {r[6]:.1e} | {r[7]:.1e} | {r[8]:.1e} |")
    lines += ["", "The two protocols carry the history along different paths (Newton",
              "iterates against the damped trajectory), so their equilibria differ by",
              "the amounts above; the pair events inherit that difference."]
    return "\n".join(lines) + "\n"


def run(fx_max=0.03, step=1e-3, nu=0.01):
    """Compare, write ``chain_solvers.md``; returns the summary."""
    summary, rows = compare(fx_max, step, nu)
    REPORT.write_text(report(summary, rows))
    return summary


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--fx-max", type=float, default=0.03)
    p.add_argument("--step", type=float, default=1e-3)
    p.add_argument("--nu", type=float, default=0.01)
    ns = p.parse_args(argv)
    run(ns.fx_max, ns.step, ns.nu)
    print(REPORT.read_text(), end="")


if __name__ == "__main__":
    main()
