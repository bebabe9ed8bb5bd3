"""Throughput of our own kernels: contact evaluations, sparse Jacobian assembly, compile time.

1. Contact-kernel evaluations per second on the contacts of a packing (N =
   1024, phi = 0.9, histories random of size 1e-3): forces alone
   (``ishima_force`` in a numba loop), forces plus the 6 x 6 Jacobian blocks
   (the engine's contact pass, ``System.forces(want_blocks=True)``), and the
   same expressions through ``sympy.lambdify``
   (NumPy, vectorized over contacts, with common-subexpression elimination):
   the generated kernel against the plainest alternative.  The lambdified
   values are checked against the kernel's first (max relative difference
   reported) so the comparison is of equal results.
2. Sparse Jacobian assembly ``K = dF/dq`` on the engine (contact list
   ``System.state``, blocks and CSR :func:`fricstab.engine.jacobian`) for
   N = 1024 and 4096.
3. numba compile time of the packing kernels: cold (an empty cache directory,
   ``NUMBA_CACHE_DIR``) and cached (the same directory again), each in a fresh
   interpreter, timing the first call.

``python validation/benchmarks/bench_kernels.py [--quick]`` -> kernels.md.
"""

import argparse
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import numpy as np  # noqa: E402
from _common import ROOT, median_time, write_table  # noqa: E402

from fricstab._numba import kernel_jit  # noqa: E402
from fricstab.engine import jacobian  # noqa: E402
from fricstab.generated.ishima import ishima_force  # noqa: E402
from fricstab.scenes.packing_friction import material, packing_system  # noqa: E402
from fricstab.scenes.packing_relax import separations  # noqa: E402

KT = 1.0


@kernel_jit
def _force_loop(sep, radius, pairs, kn, kt, hist, out):
    f = np.empty(6)
    for c in range(pairs.shape[0]):
        ishima_force(sep[c, 0], sep[c, 1], radius[pairs[c, 0]], radius[pairs[c, 1]], kn, kt,
                     hist[c, 0], hist[c, 1], f)
        for a in range(6):
            out[c, a] = f[a]


def _lambdified():
    """NumPy lambdify of the Ishima force and Jacobian (intermediates substituted back)."""
    import sympy as sp

    from symbolic.geometry import expand_geometry
    from symbolic.laws import ishima_pair
    law = ishima_pair()
    force = [expand_geometry(e, law.geometry) for e in law.force]
    jac = [expand_geometry(e, law.geometry) for e in law.jacobian]
    return (sp.lambdify(law.inputs, force, "numpy", cse=True),
            sp.lambdify(law.inputs, force + jac, "numpy", cse=True))


class _Net:
    """Touching contacts of a packing as flat arrays: pairs (M, 2), sep (M, 2), hist (M, 2)."""

    def __init__(self, pairs, sep, hist):
        self.pairs, self.sep, self.hist = pairs, sep, hist
        self.m = len(pairs)


def _contacts(n):
    """Packing, its engine System and State (random histories 1e-3), and the touching contacts."""
    from _packings import packing
    p = packing(n, 0.9, 0)
    system = packing_system(p, material("ishima", kt=KT))
    state = system.state(p.pos)
    c = state.contacts
    sep = separations(system, state)
    r = system.radius
    touch = np.flatnonzero(np.hypot(sep[:, 0], sep[:, 1]) < r[c.i] + r[c.j])
    rng = np.random.default_rng(0)
    c.hist[touch] = rng.normal(size=(len(touch), 2)) * 1e-3
    net = _Net(np.ascontiguousarray(np.column_stack([c.i, c.j])[touch]),
               np.ascontiguousarray(sep[touch]), np.ascontiguousarray(c.hist[touch]))
    return p, system, state, net


COMPILE = """
import time, numpy as np
t0 = time.perf_counter()
from fricstab.engine import jacobian, run
from fricstab.scenes.packing import make_packing
from fricstab.scenes.packing_friction import material, packing_system
t1 = time.perf_counter()
p = make_packing(16, 0.85, 0)
system = packing_system(p, material("ishima", kt=1.0))
s = system.state(p.pos)
jacobian(system, s)
run(system, s, 0.01, 10)
print(t1 - t0, time.perf_counter() - t1)
"""


def compile_times():
    """(import s, first-call s) cold and cached, each in a fresh interpreter."""
    out = {}
    with tempfile.TemporaryDirectory() as cache:
        env = dict(os.environ, NUMBA_CACHE_DIR=cache, PYTHONPATH=str(ROOT))
        for label in ("cold", "cached"):
            res = subprocess.run([sys.executable, "-c", COMPILE], capture_output=True, text=True,
                                 env=env, cwd=str(ROOT), timeout=1200)
            if res.returncode:
                raise RuntimeError(res.stderr[-1000:])
            out[label] = tuple(float(x) for x in res.stdout.split()[-2:])
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true")
    ns = ap.parse_args(argv)
    repeats = 3 if ns.quick else 7
    t_all = time.perf_counter()
    rows = []
    p, system, state, net = _contacts(1024)
    r = p.radius
    m = net.m
    out = np.empty((m, 6))
    _force_loop(net.sep, r, net.pairs, 1.0, KT, net.hist, out)
    inner = 20 if ns.quick else 100
    t, _ = median_time(lambda: [_force_loop(net.sep, r, net.pairs, 1.0, KT, net.hist, out)
                                for _ in range(inner)], repeats)
    rows.append(("forces (generated, numba)", m, f"{m * inner / t:.3g}", "1", "-"))
    system.forces(state, want_blocks=True)
    t_fj, _ = median_time(lambda: [system.forces(state, want_blocks=True)
                                   for _ in range(inner)], repeats)
    rate_fj = m * inner / t_fj
    rows.append(("forces + Jacobian blocks (engine contact pass)", m, f"{rate_fj:.3g}", "1",
                 "-"))
    t0 = time.perf_counter()
    lam_f, lam_fj = _lambdified()
    t_lambdify = time.perf_counter() - t0
    args = (net.sep[:, 0], net.sep[:, 1], r[net.pairs[:, 0]], r[net.pairs[:, 1]], 1.0, KT,
            net.hist[:, 0], net.hist[:, 1])
    ref = np.column_stack([np.broadcast_to(v, m) for v in lam_f(*args)])
    err_f = np.abs(ref - out).max() / np.abs(out).max()
    refj = lam_fj(*args)
    jl = np.column_stack([np.broadcast_to(v, m) for v in refj[6:]]).reshape(m, 6, 6)
    _, blocks = system.forces(state, want_blocks=True)
    c = state.contacts
    key = {(int(i), int(j)): b for i, j, b in zip(c.i, c.j, blocks)}
    blocks1 = np.array([key[int(i), int(j)] for i, j in net.pairs])
    err_j = np.abs(jl - blocks1).max() / np.abs(blocks1).max()
    inner_l = max(1, inner // 10)
    t_lf, _ = median_time(lambda: [lam_f(*args) for _ in range(inner_l)], repeats)
    t_lfj, _ = median_time(lambda: [lam_fj(*args) for _ in range(inner_l)], repeats)
    rows.append(("forces (sympy.lambdify, NumPy vectorized)", m, f"{m * inner_l / t_lf:.3g}",
                 f"{(m * inner_l / t_lf) / (m * inner / t):.3f}", f"{err_f:.1e}"))
    rows.append(("forces + Jacobian (sympy.lambdify, NumPy vectorized)", m,
                 f"{m * inner_l / t_lfj:.3g}", f"{(m * inner_l / t_lfj) / rate_fj:.3f}",
                 f"{err_j:.1e}"))
    for n in (1024, 4096):
        p_n, system_n, _, net_n = _contacts(n)

        def build(p_n=p_n, system_n=system_n):
            return jacobian(system_n, system_n.state(p_n.pos))[1]

        build()
        t_b, _ = median_time(build, repeats)
        jac = build()
        rows.append((f"sparse K assembly, N = {n} (contacts + blocks + CSR)", net_n.m,
                     f"{net_n.m / t_b:.3g} contacts/s ({1e3 * t_b:.1f} ms, nnz {jac.nnz})", "-",
                     "-"))
    ct = compile_times()
    rows.append(("numba compile, cold cache (import s / first call s)", "-",
                 f"{ct['cold'][0]:.2f} / {ct['cold'][1]:.2f}", "-", "-"))
    rows.append(("numba compile, cached (import s / first call s)", "-",
                 f"{ct['cached'][0]:.2f} / {ct['cached'][1]:.2f}", "-", "-"))
    write_table(
        "kernels", "Our kernels: evaluations per second, assembly, compile time",
        [f"`python validation/benchmarks/bench_kernels.py{' --quick' if ns.quick else ''}`; "
         f"contacts of the N = 1024, phi = 0.9 packing (seed 0), k_T/k_N = {KT}, random "
         f"histories 1e-3; median of {repeats} runs; one core."],
        ["what", "contacts", "evaluations / s", "relative to generated", "max rel. diff"], rows,
        ["`relative to generated` < 1 means lambdify is slower; `max rel. diff` compares the "
         "lambdified values to the generated kernel's (same expressions, different operation "
         f"order: round-off). Building the lambdified functions took {t_lambdify:.1f} s. "
         "The engine's contact pass counts every listed pair (its skin pairs cost a distance "
         "check). Compile: a fresh interpreter imports fricstab and runs one packing, one "
         "assembly and ten DEM steps on the engine; `cold` with an empty NUMBA_CACHE_DIR, `cached` with the one the "
         "cold run filled.", f"Total {time.perf_counter() - t_all:.0f} s."])
    return 0


if __name__ == "__main__":
    sys.exit(main())
