"""Timing of the sparse soft end against the dense spectrum (issue 36; a script, not a test).

For each N: a packing (``make_packing(N, 0.9, 0)``, backbone, charan) sheared
by three AQS steps of 1e-3 (non-symmetric K); one run each of the dense
spectrum (:func:`fricstab.analysis.spectrum.decompose`, eigenvalues only, and
with vectors where the comparison needs them) and of :func:`soft_end` (k = 12)
and :func:`fastest_growth`; the ratio is of the same run.  Dense is skipped
above ``--dense-max`` dof.  Errors (:func:`compare_with_dense`) where dense ran.

    NUMBA_NUM_THREADS=1 python validation/benchmarks/sparse_spectrum.py --sizes 64 256 1024
"""

import argparse
import time

import numpy as np

from fricstab.analysis.sparse_spectrum import compare_with_dense, fastest_growth, soft_end
from fricstab.analysis.spectrum import decompose
from fricstab.engine import jacobian
from fricstab.protocols.aqs import relax_step
from fricstab.scenes.packing import make_packing
from fricstab.scenes.packing_friction import backbone, frictional, material


def state(n, law="charan", steps=3):
    """K, mass and dof of a sheared packing of ``n`` disks, and the seconds to make it."""
    t0 = time.perf_counter()
    fr = frictional(backbone(make_packing(n, 0.9, 0)), material(law))
    system, s = fr.system, fr.state
    for _ in range(steps):
        s, _ = relax_step(system, s, 1e-3, 1e-13)
    _, k = jacobian(system, s)
    return k, system.gmass[system.free, :system.dof].ravel(), system.dof, \
        time.perf_counter() - t0


def timed(f, *args, **kw):
    t0 = time.perf_counter()
    out = f(*args, **kw)
    return out, time.perf_counter() - t0


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sizes", type=int, nargs="+", default=[64, 256, 1024])
    ap.add_argument("--k", type=int, default=12)
    ap.add_argument("--dense-max", type=int, default=4000, help="largest n (dof) for dense")
    a = ap.parse_args()
    print(f"{'N':>6} {'n dof':>6} {'nnz':>8} {'dense s':>9} {'soft s':>8} {'growth s':>9} "
          f"{'ratio':>7} {'max abs':>9} {'max rel':>9} {'bnd ratio':>9} {'pairs s/d':>9} "
          f"{'growth s/d(all)':>20}")
    for n in a.sizes:
        k, mass, dof, t_make = state(n)
        nd = len(mass)
        _, t_soft = timed(soft_end, k, mass, a.k, dof=dof)
        g, t_grow = timed(fastest_growth, k, mass, a.k, dof=dof)
        if nd <= a.dense_max:
            _, t_dense = timed(decompose, k.toarray(), mass, vectors=False)
            r = compare_with_dense(k, mass, a.k, dof=dof)
            err = (f"{r['max_abs']:9.2e} {r['max_rel']:9.2e} {r['bound_ratio']:9.2e} "
                   f"{r['pairs_sparse']:>4}/{r['pairs_dense']:<4} "
                   f"{r['growth_sparse']:.2e}/{r['growth_dense']:.2e}")
            ratio = f"{t_dense / t_soft:7.1f}"
            dense = f"{t_dense:9.3f}"
        else:
            err, ratio, dense = f"{'-':>9} {'-':>9} {'-':>9} {'-':>9} {g.rate:.2e}/-", \
                f"{'-':>7}", f"{'-':>9}"
        print(f"{n:>6} {nd:>6} {k.nnz:>8} {dense} {t_soft:8.3f} {t_grow:9.3f} {ratio} {err}"
              f"   (state {t_make:.1f} s; growth bound {g.bound:.2e}, "
              f"certified {g.certified})", flush=True)


if __name__ == "__main__":
    np.seterr(all="ignore")
    main()
