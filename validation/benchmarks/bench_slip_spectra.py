"""Slip spectra of `fricstab shear analyze`: the soft route (ARPACK) against the dense one.

On a sample of the pre-slip frames of a shear run (``analysis.npz`` of
``fricstab shear analyze``: ``slip_frame``), each frame's Jacobian goes through
both routes of :mod:`fricstab.analysis.shear_spectrum`: ``dense``
(:func:`spectrum`, every eigenvalue, ``scipy.linalg.eigvals``) and ``soft``
(:func:`soft_spectrum`, the k eigenvalues of smallest modulus by shift-invert
ARPACK).  Printed: the time per frame of each, and the error of the soft
route: each of its k softest matched to the nearest of the dense route's k
softest (and back), ``|lambda_soft - lambda_dense|`` relative to
``|lambda_dense|`` (over the eigenvalues above round-off, ``|lambda| > n eps
radius``: below it a mode of a mechanism is zero to working precision, and
the two routes return different noise) and in units of ``eps * radius``;
whether the windows hold the same number of eigenvalues; the pair count among the k softest, the lowest real eigenvalue
and the largest growth rate of both; and, to show what the window cannot
report, the pair count and growth rate of the whole spectrum.

``python validation/benchmarks/bench_slip_spectra.py RUN_DIR [--sample 24] [--k 50]``
-> slip_spectra.md (a run of ``fricstab shear run`` analysed by ``fricstab shear analyze``).
"""

import argparse
import json
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import numpy as np  # noqa: E402
from _common import write_table  # noqa: E402

from fricstab.analysis.shear_spectrum import (IMAG_TOL, SOFT_K, SOFT_TOL,  # noqa: E402
                                              clamped_system, recorded_state, soft_spectrum,
                                              spectrum)
from fricstab.cli.shear_analyze import frames_of  # noqa: E402

EPS = np.finfo(float).eps


def _timed(fn):
    w, c = time.perf_counter(), time.process_time()
    out = fn()
    return out, time.perf_counter() - w, time.process_time() - c


def _match(a, b):
    """Largest distance from an entry of ``a`` to the nearest of ``b``, relative to that one."""
    d = np.abs(a[:, None] - b[None, :])
    j = d.argmin(axis=1)
    return d[np.arange(len(a)), j], np.abs(b[j])


def compare(run, sample, k):
    """Per sampled frame: times and the soft route's errors (a list of dicts)."""
    frames = frames_of(run)
    params = json.loads((run / "shear.json").read_text())["parameters"]
    with np.load(run / "analysis.npz") as z:
        slips = z["slip_frame"]
    pick = slips[np.unique(np.linspace(0, len(slips) - 1, sample).round().astype(int))]
    system = clamped_system(params["law"], params["law_params"], frames.radius, frames.mass,
                            frames.inertia, frames.kind, frames.lx)
    rows = []
    for f in pick:
        ij, _, _, hist, flag = frames.contacts(int(f))
        state = recorded_state(system, frames.pos[f], frames.angle[f], ij, hist, flag)
        soft_spectrum(system, state, k)       # warm (numba, first factorization)
        dense, td, cd = _timed(lambda: spectrum(system, state, k))
        soft, ts, cs = _timed(lambda: soft_spectrum(system, state, k))
        a, b = soft.softest, dense.softest
        e1, m1 = _match(a, b)
        e2, m2 = _match(b, a)
        err, mod = np.concatenate([e1, e2]), np.concatenate([m1, m2])
        n_dof = system.dof * int(system.free.sum())
        zero = n_dof * EPS * dense.spectral_radius        # round-off level of a zero mode
        rows.append({
            "frame": int(f), "t_dense": td, "t_soft": ts, "cpu_dense": cd, "cpu_soft": cs,
            "rel": float((err / mod)[mod > zero].max()),
            "eps_radius": float(err.max() / (EPS * dense.spectral_radius)),
            "n_zero": int((np.abs(b) <= zero).sum()), "zero": zero,
            "same_size": len(a) == len(b), "radius_rel": abs(soft.spectral_radius
                                                            / dense.spectral_radius - 1),
            "pairs_soft": soft.n_complex_pairs,
            "pairs_dense_window": int((np.abs(b.imag) > IMAG_TOL * dense.spectral_radius).sum()
                                      // 2),
            "pairs_dense_all": dense.n_complex_pairs,
            "lowest_soft": soft.lowest_real_eigenvalue,
            "lowest_dense": dense.lowest_real_eigenvalue,
            "growth_soft": soft.max_growth_rate, "growth_dense": dense.max_growth_rate,
            "growth_dense_window": float(np.abs(np.sqrt(-b).real).max()),
            "fallback": bool(soft.fallback), "n_dof": n_dof})
        print(f"frame {f}: dense {td:.2f} s, soft {ts:.3f} s, rel err {rows[-1]['rel']:.1e}",
              file=sys.stderr, flush=True)
    return rows


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("run", type=Path, help="a `fricstab shear run` directory, analysed")
    ap.add_argument("--sample", type=int, default=24, help="pre-slip frames (evenly spaced)")
    ap.add_argument("--k", type=int, default=SOFT_K, help="the soft window")
    args = ap.parse_args(argv)
    r = compare(args.run.expanduser(), args.sample, args.k)
    n = len(r)

    def agree(key_a, key_b, rel=0.0, zero=False):
        return sum(abs(x[key_a] - x[key_b]) <= max(rel * abs(x[key_b]), zero * x["zero"])
                   for x in r)

    med = {key: float(np.median([x[key] for x in r]))
           for key in ("t_dense", "t_soft", "cpu_dense", "cpu_soft")}
    low_neg = sum(x["lowest_dense"] < -x["zero"] for x in r)
    rows = [
        ("time per frame, dense / soft (median wall s)",
         f"{med['t_dense']:.3f} / {med['t_soft']:.4f} (x{med['t_dense'] / med['t_soft']:.0f})"),
        ("CPU per frame, dense / soft (median s)",
         f"{med['cpu_dense']:.3f} / {med['cpu_soft']:.4f}"),
        ("k softest above round-off: max abs(lambda_soft - lambda_dense) / abs(lambda_dense)",
         f"{max(x['rel'] for x in r):.1e}"),
        ("k softest, all: max abs(lambda_soft - lambda_dense) in units of eps x radius",
         f"{max(x['eps_radius'] for x in r):.0f} (n = {r[0]['n_dof']} dof)"),
        ("round-off zero modes in the window (abs(lambda) <= n eps radius), frames with / max",
         f"{sum(x['n_zero'] > 0 for x in r)} / {max(x['n_zero'] for x in r)}"),
        ("windows of equal size (a conjugate pair kept whole at the edge)",
         f"{sum(x['same_size'] for x in r)} of {n}"),
        ("spectral radius estimate: max relative error", f"{max(x['radius_rel'] for x in r):.1e}"),
        ("complex pairs among the k softest: soft = dense",
         f"{agree('pairs_soft', 'pairs_dense_window')} of {n}"),
        ("complex pairs, k softest / whole spectrum (dense; median)",
         f"{np.median([x['pairs_dense_window'] for x in r]):.0f} / "
         f"{np.median([x['pairs_dense_all'] for x in r]):.0f}"),
        ("lowest real eigenvalue: soft = dense (to 1e-6 relative or n eps radius)",
         f"{agree('lowest_soft', 'lowest_dense', 1e-6, True)} of {n} ({low_neg} below "
         "-n eps radius)"),
        ("largest growth rate over the k softest: soft = dense (to 1e-6 relative)",
         f"{agree('growth_soft', 'growth_dense_window', 1e-6)} of {n}"),
        ("largest growth rate: k softest / whole spectrum (median ratio)",
         f"{np.median([x['growth_soft'] / x['growth_dense'] for x in r]):.2f}"),
        ("ARPACK fallbacks to dense", f"{sum(x['fallback'] for x in r)} of {n}"),
    ]
    write_table("slip_spectra", "Slip spectra: soft route (ARPACK) against dense",
                [f"Run {args.run} ({r[0]['n_dof']} dof), {n} pre-slip frames evenly spaced "
                 f"over the slips, k = {args.k}, ARPACK tol = {SOFT_TOL} (0: machine "
                 "precision). Errors: each of the k softest matched to the nearest of the "
                 "other route's k softest, both ways. Timings: one call each after a warm-up "
                 "call; wall time depends on the machine's load."],
                ["quantity", "value"], rows)


if __name__ == "__main__":
    main()
