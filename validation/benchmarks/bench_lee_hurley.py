"""Per-contact cost of the Lee & Hurley law in the engine's contact pass (issue 16).

The plane-shear quick cell (``fricstab shear --preset quick``: N = 337, about
620 listed contacts of which about 70 % touch) is prepared once under the
servo and sheared from (``ShearRun.start_shear``); its state is cached in
``--state`` (default ``$TMPDIR/fricstab_bench_lee_hurley_quick.npz``), so the
60 s preparation runs once and every code version times the same contacts.
On that configuration, one thread:

* ``advance_range`` (fricstab.engine.passes): the engine's contact pass, the
  generated ``lee_hurley_advance`` / ``lee_hurley_wall_advance`` plus the
  separation and the dashpots, with ``dq = 0`` (the pass is then idempotent:
  the histories do not move), in ns per listed contact (median of
  ``--repeats`` blocks of ``--calls`` passes);
* ``cylinder_lambda`` (fricstab._numerics) alone over the touching contacts'
  overlaps, in ns per call;
* per touching contact, counted by running the Python source of the law's
  advance kernel (and of every jitted function it calls) on counting numbers:
  the calls of log, exp and sqrt, and the flops (+, -, *, / of floats, one
  each; LLVM may fuse or reorder a few); the achieved flop rate against the
  machine's peak, cores x GHz x flops per cycle (AMD Zen 2 / EPYC Rome, as
  ``lscpu`` reports it here: 2 x 256-bit FMA pipes, 16 double-precision flops
  per cycle and core with AVX2, 4 for scalar code, which is what these
  kernels are).

``--against REV`` times the code of git revision REV too (``git archive`` into
a temporary directory, run in a subprocess on the same cached state) and
writes both rows.

``python validation/benchmarks/bench_lee_hurley.py [--against REV]`` -> lee_hurley.md.
"""

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
import types
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import numba  # noqa: E402
import numpy as np  # noqa: E402
from _common import HERE, ROOT, cpu_model, write_table  # noqa: E402

TRANSCENDENTAL = ("log", "exp", "sqrt")


class _Num(float):
    """A float that counts its arithmetic in ``_Num.counts`` (one flop per + - * /)."""

    counts = {}

    @property
    def real(self):
        return self

    def _op(self, other, fn):
        _Num.counts["flops"] = _Num.counts.get("flops", 0) + 1
        return _Num(fn(float(self), float(other)))

    def __add__(self, o): return self._op(o, lambda a, b: a + b)  # noqa: E704
    def __radd__(self, o): return self._op(o, lambda a, b: b + a)  # noqa: E704
    def __sub__(self, o): return self._op(o, lambda a, b: a - b)  # noqa: E704
    def __rsub__(self, o): return self._op(o, lambda a, b: b - a)  # noqa: E704
    def __mul__(self, o): return self._op(o, lambda a, b: a * b)  # noqa: E704
    def __rmul__(self, o): return self._op(o, lambda a, b: b * a)  # noqa: E704
    def __truediv__(self, o): return self._op(o, lambda a, b: a / b)  # noqa: E704
    def __rtruediv__(self, o): return self._op(o, lambda a, b: b / a)  # noqa: E704
    def __neg__(self): return _Num(-float(self))  # noqa: E704
    def __abs__(self): return _Num(abs(float(self)))  # noqa: E704


def _counting(name):
    def fn(x):
        if not isinstance(x, _Num):  # a constant (np.log(2.0)): LLVM folds it
            return getattr(np, name)(x)
        _Num.counts[name] = _Num.counts.get(name, 0) + 1
        return _Num(getattr(np, name)(float(x)))
    return fn


_SHIM = types.SimpleNamespace(pi=_Num(np.pi), **{n: _counting(n) for n in TRANSCENDENTAL})


def _counted(fn, seen=None):
    """The Python source of jitted ``fn`` with ``np`` and every jitted callee counted."""
    seen = {} if seen is None else seen
    py = fn.py_func
    if py in seen:
        return seen[py]
    names = dict(py.__globals__)
    out = types.FunctionType(py.__code__, names, py.__name__)
    seen[py] = out
    names["np"] = _SHIM
    for k, v in list(names.items()):
        if hasattr(v, "py_func") and k in py.__code__.co_names:
            names[k] = _counted(v, seen)
    if "_complex_step" in names:  # compiled for real inputs (a numba overload): lam itself
        names["_complex_step"] = lambda lam, ri, rj, delta: lam
    if "_fma" in names:  # an LLVM intrinsic: one fused multiply-add, counted as 2 flops
        names["_fma"] = lambda a, b, c: a * b + c
    return out


def _cell(path):
    """The prepared quick cell, sheared from: (sim, seconds spent preparing or 0 if cached)."""
    from fricstab.cli.shear import resolve_params
    from fricstab.protocols.shear_run import ShearRun, prepare
    from fricstab.scenes.shear import make_cell

    p = resolve_params(None, "quick", {})
    sim = ShearRun(make_cell(p))
    if path.exists():
        with np.load(path) as d:
            sim.load_arrays(dict(d))
        return sim, 0.0
    t0 = time.perf_counter()
    prepare(sim)
    sim.start_shear()
    d = sim.arrays()
    if d["forces"].dtype == object:  # no step run yet: no forces (not used here)
        d["forces"] = np.zeros_like(d["q"])
    np.savez(path, **d)
    return sim, time.perf_counter() - t0


def measure(state_path, calls, repeats):
    """Timings and counts of the code on sys.path, as a dict."""
    import fricstab
    from fricstab import _numerics
    from fricstab.engine import parallel, passes
    from fricstab.engine.contacts import separation
    from fricstab.engine.parallel import set_threads
    from fricstab.generated import lee_hurley as gen
    from fricstab.generated import lee_hurley_wall as gen_wall

    set_threads(1)
    sim, prep_s = _cell(state_path)
    system, state = sim.system, sim.state
    c, n = state.contacts, len(system.radius)
    try:
        space = parallel.workspace(c, system, 1)
    except TypeError:   # --against a revision before the dashpots' masses per contact
        try:
            space = parallel.workspace(c, n, 1, system.family)
        except TypeError:   # or before the driven-contact list
            space = parallel.workspace(c, n, 1)
    fcon, live, work = space[0], space[1], space[-2]
    dq = np.zeros((n, 3))
    box = np.array([system.lx, system.ly, float(state.shift), 0.0, 0.0])
    code = passes.advance_range.py_func.__code__
    masses = ((system.damping_mass, system.damping_inertia)
              if "mdamp" in code.co_varnames[:code.co_argcount] else ())
    args = (system.law_id, system._p, system._pw, system.walls, state.q, dq, state.v,
            system.radius, system.rscale, *masses, box, system.damping, c.i, c.j, c.m, c.k,
            c.hist, c.flag, c.out, fcon, live, system.dof, work[0], False)
    if passes.advance_range.py_func.__code__.co_argcount > len(args) + 2:
        args += (fcon, False)   # (f, scatter) of the engine since d679a8f: no scatter here
    passes.advance_range(0, c.n, *args)  # compile / warm
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        for _ in range(calls):
            passes.advance_range(0, c.n, *args)
        times.append((time.perf_counter() - t0) / calls / c.n * 1e9)

    # the touching contacts, their overlap and radii, and the counts per kind
    adv, adv_w = _counted(gen.lee_hurley_advance), _counted(gen_wall.lee_hurley_wall_advance)
    lanes = _counted(_numerics.pair_geometry_lanes)   # the engine's geometry stage, one lane
    p, pw = [_Num(x) for x in system._p], [_Num(x) for x in system._pw]
    deltas, r1, r2, tally = [], [], [], {"pair": [], "wall": []}
    for k in range(c.n):
        i, j = int(c.i[k]), int(c.j[k])
        h = [_Num(x) for x in c.hist[k]]
        f, aux = [_Num(0.0)] * 6, [_Num(0.0)] * 4
        _Num.counts = {}
        if j >= 0:
            dx, dy = separation(state.q, i, j, c.m[k], c.k[k], system.lx, system.ly, box[2])
            ri, rj = float(system.radius[i]), float(system.radius[j])
            g = {(0, col): _Num(x) for col, x in enumerate((dx, dy, ri, rj, 0.0, 0.0, 0.0, 0.0))}
            lanes(g, 1, True)
            adv(_Num(dx), _Num(dy), _Num(ri), _Num(rj), g[0, 4], g[0, 5], g[0, 6], p, h,
                [_Num(0.0)] * 3, [_Num(0.0)] * 3, _Num(0.0), f, aux, True)
            kind, delta, rb = "pair", ri + rj - float(np.hypot(dx, dy)), rj
        else:
            w = -1 - j
            y = (state.q[i, 1] - system.walls[w, 0]) * system.walls[w, 1]
            ri = float(system.radius[i])
            adv_w(_Num(y), _Num(ri), pw, h, [_Num(0.0)] * 3, f, aux, True)
            kind, delta, rb = "wall", ri - y, float(system._pw[-1])
        if aux[3] > 0.0:
            tally[kind].append(dict(_Num.counts))
            deltas.append(delta)
            r1.append(ri)
            r2.append(rb)
    touching = tally["pair"] + tally["wall"]
    mean = {key: float(np.mean([t.get(key, 0) for t in touching]))
            for key in ("flops",) + TRANSCENDENTAL}

    @numba.njit(error_model="numpy")  # no cache: it would keep the callee of another tree
    def lam_loop(d, a, b, reps):
        s = 0.0
        for _ in range(reps):
            for m in range(d.shape[0]):
                s += _numerics.cylinder_lambda(d[m], a[m], b[m])
        return s

    d, a, b = np.array(deltas), np.array(r1), np.array(r2)
    lam_loop(d, a, b, 1)
    lam_times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        lam_loop(d, a, b, calls)
        lam_times.append((time.perf_counter() - t0) / calls / len(d) * 1e9)
    return {"listed": int(c.n), "touching": len(touching), "walls_touching": len(tally["wall"]),
            "ns_per_listed": float(np.median(times)), "ns_spread": float(np.std(times)),
            "ns_lambda": float(np.median(lam_times)), "counts": mean, "prep_s": prep_s,
            "code": str(Path(fricstab.__file__).resolve().parent.parent)}


def sample_inputs(n, seed):
    """Seeded kernel arguments: both forms over every regime, and overlaps up to the turning point.

    ``(pair (n, 10), wall (n, 9), width (n, 3))``: the proofs' sampler
    (fricstab.laws.verify_lee_hurley.sample_cases: delta/R 1e-12 .. 0.1, the
    end points with probability 0.15, stick and slide on both caps), and
    ``(delta, Ri, Rj)`` for the width alone with ``delta`` from 1e-15 R to
    within 1e-12 of the turning point ``4 (Ri + Rj)/e^2`` (past delta/R ~ 0.3
    Lai's k_t has no positive denominator, so the kernels stop short of it).
    """
    from fricstab._numerics import turning_overlap
    from fricstab.laws.verify_lee_hurley import case_inputs, sample_cases

    pair = [case_inputs(c) for c in sample_cases(n, seed)]
    wall = [case_inputs(c, law="lee_hurley_wall")
            for c in sample_cases(n, seed + 1, law="lee_hurley_wall")]
    rng = np.random.default_rng(seed)
    ri, rj = np.full(n, 0.5), 0.5 * np.exp(rng.uniform(np.log(0.2), np.log(5.0), n))
    near = turning_overlap(ri, rj) * (1.0 - 10.0 ** rng.uniform(-12.0, -0.3, n))
    small = np.minimum(ri, rj) * 10.0 ** rng.uniform(-15.0, -1.0, n)
    width = np.column_stack([np.where(np.arange(n) % 2 == 0, near, small), ri, rj])
    return np.array(pair), np.array(wall), width


def kernel_values(pair, wall, width):
    """Forces, blocks and lam of the code on sys.path at the given arguments."""
    from fricstab._numerics import cylinder_lambda
    from fricstab.generated import lee_hurley as gen
    from fricstab.generated import lee_hurley_wall as gen_wall

    out = {}
    for name, kernel, args, nq in (("pair", gen.lee_hurley_force_jacobian, pair, 6),
                                   ("wall", gen_wall.lee_hurley_wall_force_jacobian, wall, 3)):
        f, jac = np.empty((len(args), nq)), np.empty((len(args), nq, nq))
        for k, a in enumerate(args):
            kernel(*a, f[k], jac[k])
        out[name + "_f"], out[name + "_jac"] = f, jac
    out["lam"] = np.array([cylinder_lambda(*w) for w in width])
    return out


def _round_off(new, old, width):
    """Max relative changes: force (of the contact's largest component), block (row-relative), lam."""
    eps = np.finfo(float).eps
    rows = []
    for form in ("pair", "wall"):
        f, f0 = new[form + "_f"], old[form + "_f"]
        df = np.abs(f - f0).max(axis=1) / np.abs(f0).max(axis=1)
        j, j0 = new[form + "_jac"], old[form + "_jac"]
        scale = np.abs(j0).max(axis=2)
        dj = np.abs(j - j0).max(axis=2) / np.where(scale > 0, scale, 1.0)
        rows.append([f"`lee_hurley{'_wall' if form == 'wall' else ''}`", str(len(f)),
                     f"{df.max():.1e} ({df.max() / eps:.0f} eps)",
                     f"{dj.max():.1e} ({dj.max() / eps:.0f} eps)", ""])
    lam, lam0 = new["lam"], old["lam"]
    rel = np.abs(lam - lam0) / lam0
    cond = rel * (lam0 - 1.0)  # in units of the conditioning 1/(lam - 1)
    rows.append(["`cylinder_lambda`", str(len(lam)), "", "",
                 f"{rel.max():.1e} ({rel.max() / eps:.1f} eps); x (lam - 1): "
                 f"{cond.max() / eps:.1f} eps"])
    return rows


def _peak():
    """(GHz, cores, scalar and AVX2 peak GFLOP/s per core) of this machine (Zen 2 assumed)."""
    ghz = 0.0
    for line in Path("/proc/cpuinfo").read_text().splitlines():
        if line.startswith("cpu MHz"):
            ghz = float(line.split(":")[1]) / 1000.0
            break
    return ghz, os.cpu_count(), 4 * ghz, 16 * ghz


def _against(rev, state_path, calls, repeats, inputs):
    """:func:`measure` and :func:`kernel_values` (at ``inputs``, an npz) of revision ``rev``."""
    src = Path(tempfile.gettempdir()) / f"fricstab_bench_lee_hurley_{rev}"
    if not src.exists():
        src.mkdir()
        archive = subprocess.run(["git", "-C", str(ROOT), "archive", rev], check=True,
                                 capture_output=True).stdout
        subprocess.run(["tar", "-x", "-C", str(src)], input=archive, check=True)
    # this script from here, fricstab from the archive (_common put ROOT first on the path)
    code = (f"import sys, json; sys.path.insert(0, {str(HERE)!r}); "
            "import bench_lee_hurley as b; "
            f"sys.path[:] = [{str(src)!r}] + [p for p in sys.path if p != str(b.ROOT)]; "
            f"z = b.np.load({str(inputs)!r}); "
            f"b.np.savez({str(inputs) + '.old.npz'!r}, **b.kernel_values(z['pair'], z['wall'], "
            "z['width'])); "
            f"print(json.dumps(b.measure(b.Path({str(state_path)!r}), {calls}, {repeats})))")
    out = subprocess.run([sys.executable, "-c", code], check=True, cwd=str(src),
                         capture_output=True, text=True).stdout
    with np.load(str(inputs) + ".old.npz") as z:
        old = {k: z[k] for k in z.files}
    return json.loads(out.strip().splitlines()[-1]), old


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--against", help="also time the code of this git revision")
    ap.add_argument("--state", default=str(Path(tempfile.gettempdir())
                                           / "fricstab_bench_lee_hurley_quick.npz"))
    ap.add_argument("--calls", type=int, default=200)
    ap.add_argument("--repeats", type=int, default=7)
    ap.add_argument("--cases", type=int, default=2000,
                    help="seeded contacts per form for the round-off comparison (--against)")
    ns = ap.parse_args(argv)
    state_path = Path(ns.state)
    results, change = [], []
    now = measure(state_path, ns.calls, ns.repeats)
    if ns.against:
        with tempfile.TemporaryDirectory() as tmp:
            inputs = Path(tmp) / "inputs.npz"
            pair, wall, width = sample_inputs(ns.cases, 16)
            np.savez(inputs, pair=pair, wall=wall, width=width)
            timed, old = _against(ns.against, state_path, ns.calls, ns.repeats, inputs)
        results.append((ns.against, timed))
        change = _round_off(kernel_values(pair, wall, width), old, width)
    results.append(("this tree", now))
    for label, r in results:
        print(f"{label}: fricstab from {r['code']}", file=sys.stderr)
    ghz, cores, scalar, avx = _peak()
    rows = []
    for label, r in results:
        cnt = r["counts"]
        gflops = cnt["flops"] / (r["ns_per_listed"] * r["listed"] / r["touching"])
        rows.append([label, f"{r['ns_per_listed']:.1f} ± {r['ns_spread']:.1f}",
                     f"{r['ns_lambda']:.1f}", f"{cnt['log']:.2f}", f"{cnt['exp']:.2f}",
                     f"{cnt['sqrt']:.2f}", f"{cnt['flops']:.0f}",
                     f"{gflops:.2f} ({100 * gflops / scalar:.0f} % / {100 * gflops / avx:.1f} %)"])
    base = results[0][1]["ns_per_listed"] / now["ns_per_listed"] if ns.against else None
    write_table(
        "lee_hurley", "Per-contact cost of the Lee & Hurley law (issue 16)",
        [f"Plane-shear quick cell after preparation: {now['listed']} listed contacts, "
         f"{now['touching']} touching ({now['walls_touching']} of them on the walls); one thread; "
         f"`advance_range` repeated {ns.calls} times per block, median of {ns.repeats} blocks "
         "(± their standard deviation).  Counts per touching contact, from the Python source "
         "of the law's advance kernel run on counting numbers (the engine's own separation and "
         "dashpots not counted).  GFLOP/s = law flops per touching contact over the pass's ns "
         "per touching contact, against the peak of one core: "
         f"{ghz:.2f} GHz x 4 flops/cycle scalar = {scalar:.1f} GFLOP/s, x 16 with AVX2 FMA = "
         f"{avx:.1f} GFLOP/s ({cores} cores: {cores * avx:.0f} GFLOP/s); CPU {cpu_model()}.",
         "", f"Speed-up of `advance_range` against {ns.against}: {base:.2f}x." if base else "",
         "", "`python validation/benchmarks/bench_lee_hurley.py"
         + (f" --against {ns.against}`" if ns.against else "`")],
        ["code", "advance_range ns / listed contact", "cylinder_lambda ns / call",
         "log / touching contact", "exp", "sqrt", "flops", "GFLOP/s (of scalar / AVX2 peak)"],
        rows, notes=_change_table(ns, change))


def _change_table(ns, change):
    """Markdown lines of the round-off comparison (empty without --against)."""
    if not change:
        return []
    return [f"## Round-off change against {ns.against}", "",
            f"Seeded sample (seed 16, {ns.cases} contacts per form, `sample_inputs`): the "
            "largest change of the forces relative to the contact's largest component, of "
            "the Jacobian block relative to its row's largest entry, and of lam (relative; "
            "times lam - 1, the scale of the tests' tolerance 64 eps/(lam - 1)).", "",
            "| kernel | contacts | force | Jacobian | lam |", "|---|---|---|---|---|",
            *["| " + " | ".join(r) + " |" for r in change]]


if __name__ == "__main__":
    main()
