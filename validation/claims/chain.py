"""Claims of the chain of disks (Charan et al.): the ramp, its pairs, dynamics and waves.

Paper values are quoted from ``/work/shared/papers/charan-static-to-dynamic-friction.md``
as printed.  Where the paper prints a value without an error ("omega ~ 0.235",
"a wavelength of approximately 2", Eq. 10, the imaginary parts), its standard
error is taken as half a unit of its last printed digit (of the exponent for
"about 10^-5"), and ours agrees with it where the two lie within 2 combined
standard errors (:func:`claims.core.sigma_verdict`); our deterministic values
(eigenvalues of a Newton equilibrium) have no error of their own.

Computations are imported inside the compute functions (the fingerprint of a
record is what its process imported); the validation scripts' ``run``
functions write their reports, whose hashes the records keep.
"""

import math

from .core import (Claim, Result, Verdict, bound_verdict, exact_verdict, floor_verdict,
                   half_unit, same, sigma_distance, sigma_verdict, within_sigma)

HEADING = 'Chain of disks on a substrate (Charan et al.)'
INTRO = ("Charan's chain as `ChainScene()` builds it: N = 10 disks, R = 0.5 (2R = 1), m = 1, "
         "I = m R^2 / 2, the law `charan` with k_n = 2000, k_t = 2 k_n / 7, mu = 10, "
         "F_y = 0.1 on every disk, F_x on the first, periodic in x with period 2NR. The "
         "default ramp is Newton's from F_x = 0 in steps of 1e-3 with every pair event "
         "bisected to 1e-6; dynamics start from the ramped equilibrium with a seeded "
         "perturbation of 1e-9 of the wall overlap (undamped velocity Verlet, "
         "dt = 0.02 / omega_wall). Eigenvalues, frequencies and speeds are in the paper's "
         "units (length 2R, time sqrt(m 2R / k_n)) unless stated. The paper names neither the "
         "matrix whose eigenvalues it prints nor the inertia of its LAMMPS dynamics: the rows "
         "chain.conv_* and chain.fig* give each number under every reading (spectrum of M^-1 J "
         "with I = m R^2 / 2, 2/5 m R^2 or m R^2, or of J itself; dynamics with the matching "
         "inertia, I = m (2R)^2 for J itself); the conv rows judge under the reading with the most "
         "agreements, itself computed (validation/chain_conventions.md), the fig rows under "
         "every reading whose runs all reach the transition. A value the paper prints "
         "without an error is given half a unit of its last printed digit as its standard "
         "error; agreement means within 2 combined standard errors.")

#: the paper's F_x values: pairs at 0.03, 0.04 (Fig. 3), none at 0.062, pairs at 0.083,
#: 0.087, 0.090 (the second regime)
PROBES = (0.03, 0.04, 0.062, 0.083, 0.087, 0.090)
PAPER_PAIRS = (True, True, False, True, True, True)
WAVE_FX = (0.083, 0.087, 0.090)
PAPER_IM = (0.00024, 0.00077, 0.001)
PAPER_V1 = ((0.0014, 0.00013), (0.0022, 0.00015), (0.0028, 8e-5))


def _root():
    from pathlib import Path
    return Path(__file__).resolve().parents[2]


def _script(name):
    """A validation script as a module (imported here, so the fingerprint names it)."""
    import importlib
    import sys
    path = str(_root() / "validation")
    if path not in sys.path:
        sys.path.insert(0, path)
    return importlib.import_module(name)


def _yes(flags):
    return ", ".join("yes" if f else "no" for f in flags)


def _pairs_word(counts):
    """Pair counts at the probes as yes / no / 'no eq.' (no equilibrium reached)."""
    return ", ".join("no eq." if n is None else ("yes" if n > 0 else "no") for n in counts)


# ------------------------------------------------------------ seconds: the default ramp

def ramp():
    """The default Newton ramp to F_x = 0.1: events, pairs at the paper's F_x, Im lambda."""
    import numpy as np

    from fricstab.analysis.spectrum import complex_pairs
    from fricstab.protocols.ramp import run_ramp
    from fricstab.scenes.chain import ChainScene, time_unit
    scene = ChainScene()
    res = run_ramp(scene, 0.1, 1e-3, tol=1e-6)
    unit = time_unit(scene)
    counts = [len(complex_pairs(w)) for w in res.eigenvalues]

    def at(fx):
        return int(np.argmin(np.abs(res.fx - fx)))

    # pairs for all F_x in (0.082, 0.1]: at every step, and no located death between
    # steps that leaves none (walk the events from the last step <= 0.082)
    above = [k for k, f in enumerate(res.fx) if f > 0.082 + 1e-12]
    k0 = above[0] - 1
    count, ok = counts[k0], all(counts[k] > 0 for k in above)
    for e in res.events:
        if e.fx > res.fx[k0]:
            count += 1 if e.kind == "birth" else -1
            ok = ok and not (e.fx > 0.082 and count <= 0)
    return Result({
        "events": [{"kind": e.kind, "fx": e.fx, "width": e.fx_hi - e.fx_lo,
                    "located": e.located} for e in res.events],
        "first_birth": next(e.fx for e in res.events if e.kind == "birth"),
        "probes": [counts[at(p)] for p in PROBES],
        "nearest_event_to_probe": float(min(abs(e.fx - p) for e in res.events for p in PROBES)),
        "pairs_above_0082": bool(ok),
        "min_pairs_above_0082": int(min(counts[k] for k in above)),
        "im_lambda": [float(np.abs(res.eigenvalues[at(f)].imag).max()) * unit ** 2
                      for f in WAVE_FX],
        "im_lambda_condition": [float(res.condition[at(f)][np.argmax(
            np.abs(res.eigenvalues[at(f)].imag))]) for f in WAVE_FX]})


def _same_events(a, b):
    ea, eb = a["events"], b["events"]
    if [e["kind"] for e in ea] != [e["kind"] for e in eb]:
        return False, f"event sequence {len(ea)} -> {len(eb)} events"
    worst = max(abs(x["fx"] - y["fx"]) for x, y in zip(ea, eb))
    return bool(worst <= 2e-6), f"events as recorded; largest move {worst:.1e} (allowed 2e-6)"


def _show_events(v):
    births = sum(e["kind"] == "birth" for e in v["events"])
    return (f"first birth at F_x = {v['first_birth']:.7f}; {len(v['events'])} events in "
            f"[0, 0.1] ({births} births), "
            + ("every one" if all(e["located"] for e in v["events"]) else "NOT every one")
            + f" located (bracket <= {max(e['width'] for e in v['events']):.1e})")


def _sigma_items_im(v):
    return [(ours, 0.0, float(p), half_unit(p)) for ours, p in
            zip(v["im_lambda"], ("0.00024", "0.00077", "0.001"))]


# ------------------------------------------------------------ seconds: rest and export

def rest():
    """At F_x = 0: wall overlap against Hertz, transverse frequency; at 0.03 the exported
    Jacobian against central differences of the exported state."""
    import sys
    import tempfile
    from pathlib import Path

    import numpy as np

    from fricstab.analysis.modes import transverse_mode
    from fricstab.io.jacobian_export import read_state
    from fricstab.protocols.ramp import ramped_equilibrium, relax_newton
    from fricstab.scenes.chain import (ChainScene, chain_system, forces_and_jacobian,
                                       initial_state, time_unit)
    from fricstab.scenes.chain_io import export_state
    if str(_root()) not in sys.path:
        sys.path.insert(0, str(_root()))
    from tests.system_proof import central_jacobian
    scene = ChainScene()
    res = relax_newton(scene, initial_state(scene))
    hertz = (scene.fy / scene.params["kn"]) ** (2.0 / 3.0)
    delta = scene.radius - res.state.q[:, 1]
    mode = transverse_mode(scene, ramped_equilibrium(scene, 0.0))
    closed = math.sqrt(1.5 * scene.params["kn"] * math.sqrt(hertz) / scene.mass) * time_unit(scene)
    # export at 0.03 and differentiate the reloaded state (tests/test_chain.py)
    sc = scene.with_fx(0.03)
    loaded = relax_newton(sc, res.state).state
    out = Path(tempfile.mkdtemp(prefix="chain_export_"))
    export_state(sc, loaded, out)
    dense = np.load(out / "jacobian.npy")
    d = read_state(out / "state.npz")
    again = chain_system(sc).state(d["pos"], d["theta"])
    again.contacts.hist[np.searchsorted(again.keys, loaded.keys)] = d["history"]
    q, c = again.q, again.contacts
    pair = c.j >= 0
    jj = np.where(pair, c.j, 0)
    dx = q[c.i, 0] - q[jj, 0] - c.m * sc.period
    gap = np.where(pair, np.hypot(dx, q[c.i, 1] - q[jj, 1]) - 2 * sc.radius,
                   q[c.i, 1] - sc.radius)
    h = 1e-3 * float((-gap[gap < 0]).min())
    fd = central_jacobian(chain_system(sc), again, h)
    return Result({
        "overlap_rel_err": float(np.max(np.abs(delta / hertz - 1.0))), "hertz": hertz,
        "newton_residual": float(res.residual),
        "omega": mode.omega, "omega_closed_form": closed,
        "export_equal": bool(np.array_equal(forces_and_jacobian(sc, again)[1], dense)),
        "export_fd_err": float(np.abs(dense - fd).max() / np.abs(dense).max())})


# ------------------------------------------------------------ seconds: growth

def growth():
    """The unstable mode at F_x = 0.03 in Newtonian dynamics against the Jacobian."""
    from fricstab.protocols.growth import measure_growth
    from fricstab.protocols.ramp import ramped_equilibrium
    from fricstab.scenes.chain import ChainScene
    scene = ChainScene()
    g = measure_growth(scene.with_fx(0.03), ramped_equilibrium(scene, 0.03))
    return Result({"predicted": g.predicted, "measured": g.measured,
                   "relative_difference": g.relative_difference})


def _growth_check(a, b):
    p = same(rel=1e-8, keys=["predicted"])(a, b)
    if not p[0]:
        return p
    allowed = max(10 * abs(a["measured"] - a["predicted"]), 1e-6 * a["predicted"])
    d = abs(b["measured"] - a["measured"])
    return d <= allowed, f"measured moved {d:.1e} (allowed {allowed:.1e})"


# ------------------------------------------------------------ seconds: transverse mode

def transverse_band():
    """validation/chain_transverse.py: the y band by wavelength, four conventions, seven F_x."""
    mod = _script("chain_transverse")
    return Result(mod.run(), outputs=("validation/chain_transverse.md",
                                      "validation/chain_transverse.png",
                                      "docs/_static/figures/chain_transverse.png"))


def _band(v, fx, convention="physical"):
    return next(r for r in v["rows"] if r["convention"] == convention
                and abs(r["fx"] - fx) < 1e-12)


# ------------------------------------------------------------ seconds: Ishima's law

def ishima_birth():
    """The compose tutorial's chain: 20 disks with Ishima's law, ramp to 0.02, tol 1e-8."""
    from fricstab.protocols.ramp import run_ramp
    from fricstab.scenes.chain import ChainScene
    res = run_ramp(ChainScene(n=20, law="ishima"), 0.02, 1e-3, tol=1e-8)
    b = next(e for e in res.events if e.kind == "birth")
    return Result({"fx": b.fx, "bracket": b.fx_hi - b.fx_lo, "events": len(res.events)})


# ------------------------------------------------------------ minutes: waves

def waves():
    """validation/chain_waves.py: 25 realizations at F_x = 0.078, 0.083, 0.087, 0.090."""
    mod = _script("chain_waves")
    values = mod.run(25)
    return Result(values, seeds=tuple(range(25)),
                  outputs=("validation/chain_waves.md", "validation/chain_waves.png"))


def _row(v, fx):
    return next(r for r in v["rows"] if abs(r["fx"] - fx) < 1e-9)


def _wave_pairs(keys, fxs=(0.078, 0.083, 0.087, 0.090)):
    idx = {0.078: 0, 0.083: 1, 0.087: 2, 0.090: 3}
    return [(f"rows[{idx[f]}].{k}", f"rows[{idx[f]}].{k}_err") for f in fxs for k in keys]


def _span(xs, fmt):
    return f"{min(xs):{fmt}}-{max(xs):{fmt}}"


def _v2_err(r):
    s = r["v2_split_err"]
    return max(r["v2_err"], s) if s == s else r["v2_err"]


# ------------------------------------------------------------ minutes: dynamics (Fig. 3)

#: seeds of the Fig. 3 runs: after the first breach the chain is chaotic, so a count of
#: breached disks or a slide is a sample, not a number; each seed perturbs the ramped
#: equilibrium differently (``fricstab chain dynamics --seed``)
DYN_SEEDS = (0, 1, 2, 3)
#: (key, F_x, duration in paper time units) of the Fig. 3 runs
DYN_RUNS = (("breach", 0.083, 20000), ("f0.03", 0.03, 40000), ("f0.04", 0.04, 40000),
            ("f0.062", 0.062, 20000), ("f0.083", 0.083, 40000))


def _dyn_run(fx, duration, seed):
    """One `fricstab chain dynamics` run, summarised: disks breached, first breach and M
    there, M's range over the last half, the centre of mass's forward motion."""
    import tempfile
    from pathlib import Path

    import numpy as np

    from fricstab.cli import main as cli
    d = Path(tempfile.mkdtemp(prefix="chain_dynamics_")) / "run"
    rc = cli(["chain", "dynamics", "--fx", str(fx), "--duration", str(duration),
              "--seed", str(seed), "--out", str(d), "--quiet", "--no-progress"])
    if rc != 0:
        raise RuntimeError(f"fricstab chain dynamics --fx {fx} --seed {seed} exited {rc}")
    with np.load(d / "dynamics.npz") as z:
        t, m, tau, com = z["time"], z["msd"], z["first_breach_time"], z["centre_of_mass"]
    late = m[len(m) // 2:]
    first = float(np.nanmin(tau)) if np.isfinite(tau).any() else None
    k = int(np.searchsorted(t, first)) if first is not None else None
    return {"seed": seed, "breached": int(np.isfinite(tau).sum()),
            "first_breach": first, "m_at_first_breach": None if k is None else float(m[k]),
            "late_min": float(late.min()), "late_max": float(late.max()),
            "com_moved": float(com[-1, 0] - com[0, 0])}


def dynamics():
    """`fricstab chain dynamics` at the paper's Fig. 3 forces, one run per seed of
    DYN_SEEDS: per F_x the list of runs."""
    out = {name: {"fx": fx, "duration": duration,
                  "runs": [_dyn_run(fx, duration, s) for s in DYN_SEEDS]}
           for name, fx, duration in DYN_RUNS}
    return Result(out, seeds=DYN_SEEDS)


def _stable(r):
    """Stable, as Fig. 3 says of 0.062: M stays minute (< 1e-3) and no disk breaches."""
    return r["late_max"] < 1e-3 and r["breached"] == 0


def _slides(r):
    """The transition the paper reports at 0.083: the Coulomb law is breached and the
    chain slides (its centre of mass moves forward more than 0.1 diameters)."""
    return r["breached"] > 0 and r["com_moved"] > 0.1


def _count(v, key, test):
    """How many of a key's runs pass ``test``, and of how many: 'k of n seeds'."""
    runs = v[key]["runs"]
    return sum(bool(test(r)) for r in runs), len(runs)


def _seeds_verdict(v, keys, test, paper, what):
    """Exact verdict where every seed says the same; undecided where seeds differ (the
    chaotic runs split: more seeds, not one run, decide)."""
    said = [bool(test(r)) for key in keys for r in v[key]["runs"]]
    if len(set(said)) > 1:
        return Verdict("undecided", f"{what}: {sum(said)} of {len(said)} runs")
    return exact_verdict(said[0], paper, what + f" in all {len(said)} runs")


def _geo(xs):
    """Geometric mean and the standard error of its log10 (0 for one value)."""
    logs = [math.log10(x) for x in xs]
    n = len(logs)
    mean = sum(logs) / n
    sd = math.sqrt(sum((g - mean) ** 2 for g in logs) / (n - 1)) if n > 1 else 0.0
    return 10.0 ** mean, sd / math.sqrt(n)


def _at_breach(v, key="breach"):
    """M at the first breach over the runs that breach: geometric mean, log10 error, n."""
    ms = [r["m_at_first_breach"] for r in v[key]["runs"] if r["m_at_first_breach"]]
    return (*_geo(ms), len(ms)) if ms else (None, None, 0)


def _run_level(r):
    """One run's stationary level of M: the geometric mean of its last half's range."""
    return math.sqrt(r["late_min"] * r["late_max"])


def _level(v, key):
    """The stationary level of M over the runs: geometric mean and log10 error."""
    return _geo([_run_level(r) for r in v[key]["runs"]])


def _first_breach(v, key="breach"):
    """Mean first-breach time over the runs that breach, or None."""
    ts = [r["first_breach"] for r in v[key]["runs"] if r["first_breach"] is not None]
    return sum(ts) / len(ts) if ts else None


def _per_seed_level(v, key):
    """Each run's stationary level (geometric mean of its last half's range)."""
    return ", ".join(f"{_run_level(r):.1e}" for r in v[key]["runs"])


def _at_0062(v):
    """F_x = 0.062 over the seeds: how many stable, how far M goes, disks breached."""
    k, n = _count(v, "f0.062", _stable)
    return (f"stable in {k} of {n} seeds; M reaches up to "
            f"{max(r['late_max'] for r in v['f0.062']['runs']):.1e}; disks breached within "
            f"20,000 time units per seed {_per_seed(v, 'f0.062', 'breached')} of 10")


def _per_seed(v, key, field, spec="{}"):
    return ", ".join(spec.format(r[field]) for r in v[key]["runs"])


def _dyn_check(a, b):
    """Per seed: stable or not exact; the linear growth before the first breach (time within
    5 %, M there within a factor 2) and the saturated levels (a factor 2) as numbers; after
    the breach the runs are chaotic, so the count of runs that slide within one."""
    for key, _, _ in DYN_RUNS:
        for ra, rb in zip(a[key]["runs"], b[key]["runs"]):
            if _stable(ra) != _stable(rb):
                return False, f"{key} seed {ra['seed']}: stable {_stable(ra)} -> {_stable(rb)}"
    if abs(_count(a, "breach", _slides)[0] - _count(b, "breach", _slides)[0]) > 1:
        return False, (f"F_x = 0.083: {_count(a, 'breach', _slides)} -> "
                       f"{_count(b, 'breach', _slides)} runs slide")
    for key in ("f0.03", "f0.04"):
        for ra, rb in zip(a[key]["runs"], b[key]["runs"]):
            for k in ("late_min", "late_max"):
                if not 0.5 <= rb[k] / ra[k] <= 2.0:
                    return False, (f"{key}.{k} seed {ra['seed']}: {ra[k]:.2g} -> {rb[k]:.2g} "
                                   "(beyond a factor 2)")
    for ra, rb in zip(a["breach"]["runs"], b["breach"]["runs"]):
        if (ra["first_breach"] is None) != (rb["first_breach"] is None):
            return False, f"seed {ra['seed']}: a breach {ra['first_breach']} -> {rb['first_breach']}"
        if ra["first_breach"] is None:
            continue
        if abs(rb["first_breach"] / ra["first_breach"] - 1) > 0.05 or \
                not 0.5 <= rb["m_at_first_breach"] / ra["m_at_first_breach"] <= 2.0:
            return False, (f"seed {ra['seed']}: first breach {ra['first_breach']:.0f} -> "
                           f"{rb['first_breach']:.0f}, M there {ra['m_at_first_breach']:.2g} -> "
                           f"{rb['m_at_first_breach']:.2g}")
    return True, "within the bands"


_DYN_COMMAND = ("fricstab chain dynamics --fx {fx} --duration {duration} --seed S --out DIR "
                "(S = 0 1 2 3)")


def _decade_verdict(values, about, what):
    """'About ``about``': ours (geometric mean, standard error of its log10) against the
    paper's order of magnitude, given half a decade as its standard error, in combined
    standard errors of log10 (:func:`claims.core.sigma_verdict`)."""
    items = [(math.log10(g), e, math.log10(about), 0.5) for g, e in values]
    v = sigma_verdict(items)
    return Verdict(v.label, " / ".join(f"{math.log10(g / about):+.1f}" for g, _ in values)
                   + f" decades from {what} (half a decade its error); " + v.detail)


# ------------------------------------------------------------ minutes: protocols

def protocols():
    """validation/chain_protocols.py: the ramp under Newton and damped protocols."""
    mod = _script("chain_protocols")
    return Result(mod.run(), outputs=("validation/chain_protocols.md",
                                      "validation/chain_protocols.png"))


def _variant(v, key):
    return v["variants"][key]


def _probe_text(flags):
    return "/".join("-" if n is None else str(n) for n in flags)


def _damped_show(v):
    d = _variant(v, "damped0.447")
    near = d["nearest_to_0.062"]
    where = ""
    if near is not None:
        where = (f"; its 'no pair at 0.062' lies {abs(near['fx'] - 0.062):.1e} from a "
                 f"{near['kind']} at {near['fx']:.6f}" if near["located"] else
                 f"; nearest event to 0.062: a {near['kind']} in ({near['lo']:.3f}, "
                 f"{near['hi']:.3f}]")
    fine, coarse = _variant(v, "damped0.447-fine"), _variant(v, "damped0.447-coarse")
    return (f"damped nu = 0.447 (0.01 per paper time unit), step 1e-3: pairs "
            f"{_probe_text(d['probes'])} at the six F_x, {d['agreement']}/6 as the paper{where}; "
            f"pairs for all F_x > 0.082: {d['above_note']}. Step 5e-4: {fine['agreement']}/6, "
            f"pairs above 0.082: {fine['above_note']}; step 2e-3: {coarse['agreement']}/6, "
            f"pairs above 0.082: {coarse['above_note']}")


def _protocol_check(a, b):
    for key, va in a["variants"].items():
        vb = b["variants"][key]
        for k in ("probes", "agreement", "above", "stopped", "events"):
            if va[k] != vb[k]:
                return False, f"{key}.{k}: {va[k]!r} -> {vb[k]!r}"
    return True, "pair counts, agreements and stops as recorded"


# ------------------------------------------------------------ minutes: solvers, knobs

def solvers():
    """validation/chain_solvers.py: Newton against the damped protocol, ramp to 0.03."""
    mod = _script("chain_solvers")
    return Result(mod.run(), outputs=("validation/chain_solvers.md",))


def knobs():
    """validation/chain_tradeoffs.py: ramp step, tolerance and Verlet step, measured."""
    mod = _script("chain_tradeoffs")
    return Result(mod.run(), seeds=tuple(range(10)), outputs=("validation/chain_tradeoffs.md",))


def _knobs_check(a, b):
    if (a["worst_error_over_tol"] <= 1) != (b["worst_error_over_tol"] <= 1):
        return False, f"location error / tol {a['worst_error_over_tol']:.2f} -> " \
                      f"{b['worst_error_over_tol']:.2f}"
    if abs(a["growth_error_order"] - b["growth_error_order"]) > 0.3:
        return False, f"growth error order {a['growth_error_order']:.2f} -> " \
                      f"{b['growth_error_order']:.2f}"
    if a["events_per_step"] != b["events_per_step"]:
        return False, f"events per step {a['events_per_step']} -> {b['events_per_step']}"
    return True, "location within tol, Verlet order within 0.3, events per step as recorded"


# ------------------------------------------------------------ the claims

_W = "python validation/chain_waves.py"
_T = "python validation/chain_transverse.py"
_P = "python validation/chain_protocols.py"
_RAMP = "fricstab chain ramp --out DIR"

CLAIMS = [
    # ---- the default ramp (seconds)
    Claim("chain.first_birth", "chain",
          "first complex-pair birth on the default ramp; events in [0, 0.1]",
          "seconds", _RAMP, ramp, show=_show_events,
          tolerance="each event within 2e-6 (the bisection's final bracket is 1e-6; a sign "
                    "decided otherwise at round-off moves the midpoint by at most one "
                    "bracket); the event sequence exact",
          check=_same_events,
          paper="(none: Fig. 2 shows two births, no F_x printed)", job="chain.ramp",
          texts={"short": lambda v: (f"{len(v['events'])} events in [0, 0.1]; the first "
                                     f"birth is at F_x = {v['first_birth']:.7f}"),
                 "near": lambda v: f"{v['first_birth']:.3f}"}),
    Claim("chain.pairs_at_probes", "chain",
          "pair / no pair at F_x = 0.03, 0.04, 0.062, 0.083, 0.087, 0.090 (default ramp)",
          "seconds", _RAMP, ramp,
          show=lambda v: "pairs " + "/".join(map(str, v["probes"])) + ": "
          + _yes(n > 0 for n in v["probes"])
          + f" (nearest event {v['nearest_event_to_probe']:.1e} from a probe)",
          tolerance="exact: pair counts are integers, at equilibria farther from every event "
                    "than round-off can move one (the nearest distance is shown)",
          check=same(keys=["probes"]),
          paper="yes, yes, no, yes, yes, yes (Fig. 3; 'for F_x = 0.062 all the eigenvalues of "
                "J are real')",
          verdict=lambda v: exact_verdict(_yes(n > 0 for n in v["probes"]), _yes(PAPER_PAIRS),
                                          "pair at each F_x"),
          job="chain.ramp",
          texts={"doc": lambda v: (
              "agrees with the paper at "
              f"{sum((n > 0) == p for n, p in zip(v['probes'], PAPER_PAIRS))} of these six F_x"
              + "".join(f" (it has pairs at {f:g})" if n > 0 else f" (it has none at {f:g})"
                        for f, n, p in zip(PROBES, v["probes"], PAPER_PAIRS) if (n > 0) != p))}),
    Claim("chain.pairs_above_0082", "chain", "pairs for all F_x > 0.082 (to 0.1), default ramp",
          "seconds", _RAMP, ramp,
          show=lambda v: ("yes" if v["pairs_above_0082"] else "no")
          + f" (at least {v['min_pairs_above_0082']} at every step)",
          tolerance="exact", check=same(keys=["pairs_above_0082", "min_pairs_above_0082"]),
          paper="'unstable for all force values F_x > 0.082' (SM)",
          verdict=lambda v: exact_verdict(v["pairs_above_0082"], True, "pairs for all F_x"),
          job="chain.ramp"),
    Claim("chain.im_lambda", "chain",
          "largest Im lambda of M^-1 J at F_x = 0.083 / 0.087 / 0.090 (default ramp), paper units",
          "seconds", _RAMP + " (ramp.npz x eigenvalue_unit)", ramp,
          show=lambda v: " / ".join(f"{x:.2e}" for x in v["im_lambda"])
          + " (condition numbers " + " / ".join(f"{x:.1f}" for x in v["im_lambda_condition"])
          + ")",
          tolerance="1e-6 relative: eigenvalues of Newton equilibria (max|F| < 1e-12), well "
                    "conditioned (condition numbers shown)",
          check=same(rel=1e-6, keys=["im_lambda"]),
          paper="0.00024 / 0.00077 / 0.001 ('the imaginary part of the associated eigenvalue')",
          verdict=lambda v: sigma_verdict(_sigma_items_im(v)), job="chain.ramp"),
    # ---- rest, export, growth (seconds)
    Claim("chain.wall_overlap", "chain", "wall overlap at F_x = 0 against Hertz",
          "seconds", "pytest tests/test_chain.py -k wall_overlap", rest,
          show=lambda v: f"{v['overlap_rel_err']:.1e} relative (largest over the disks)",
          tolerance="<= 7e-12 relative: Newton stops at max|F| < 1e-12, over the wall stiffness "
                    "1.5 k_n delta^(1/2) ~ 110 and delta = 1.36e-3",
          check=lambda a, b: (b["overlap_rel_err"] <= 7e-12,
                              f"{a['overlap_rel_err']:.1e} -> {b['overlap_rel_err']:.1e}"),
          paper="(F_y / k_n)^(2/3) (Hertz, Eq. 1)",
          verdict=lambda v: Verdict("agrees" if v["overlap_rel_err"] <= 1e-10 else "disagrees",
                                    f"relative {v['overlap_rel_err']:.1e}; agree if <= 1e-10 "
                                    "(the issue's)"),
          job="chain.rest",
          texts={"doc": lambda v: f"{v['overlap_rel_err']:.0e}"}),
    Claim("chain.transverse_zero", "chain", "transverse (y) mode frequency at F_x = 0",
          "seconds", "pytest tests/test_chain.py -k transverse", rest,
          show=lambda v: f"{v['omega']:.5f} (closed form sqrt(1.5 k_n delta^(1/2) / m) "
          f"{v['omega_closed_form']:.6f})",
          tolerance="1e-10 absolute: an eigenvalue of a Newton equilibrium (round-off)",
          check=same(abs=1e-10, keys=["omega"]),
          paper="omega ~ 0.235",
          verdict=lambda v: sigma_verdict([(v["omega"], 0.0, 0.235, half_unit("0.235"))]),
          job="chain.rest",
          texts={"short": lambda v: f"{v['omega']:.5f} at F_x = 0; paper 0.235",
                 "doc": lambda v: f"{v['omega']:.5f}"}),
    Claim("chain.export_fd", "chain",
          "exported Jacobian against central differences of the exported state (F_x = 0.03)",
          "seconds", "pytest tests/test_chain.py -k exported", rest,
          show=lambda v: f"{v['export_fd_err']:.1e} (relative to max |J|); reloaded assembly "
          + ("identical" if v["export_equal"] else "DIFFERENT"),
          tolerance="1e-10 absolute: the difference is truncation (h/delta_min)^2/24 with "
                    "h = 1e-3 delta_min, deterministic; round-off eps|F|/(h max|K|) ~ 3e-12",
          check=same(abs=1e-10, keys=["export_fd_err", "export_equal"]),
          verdict=lambda v: bound_verdict(v["export_fd_err"] if v["export_equal"] else math.inf,
                                          1e-6, "relative difference (issue)"),
          job="chain.rest", texts={"doc": lambda v: f"{v['export_fd_err']:.0e}"}),
    Claim("chain.growth", "chain",
          "growth rate of the unstable mode at F_x = 0.03: Newtonian dynamics against the "
          "Jacobian (simulation units)",
          "seconds", "pytest tests/test_growth.py", growth,
          show=lambda v: f"{v['measured']:.7f} vs {v['predicted']:.7f} "
          f"({v['relative_difference']:.1e} relative)",
          tolerance="Jacobian's rate 1e-8 relative; the measured rate within 10x its recorded "
                    "difference from the Jacobian's (another LAPACK may pick another phase of "
                    "the complex eigenvector, so another start on the same mode)",
          check=_growth_check,
          verdict=lambda v: bound_verdict(v["relative_difference"], 0.02,
                                          "relative difference (issue)"),
          texts={"doc": lambda v: f"{v['relative_difference']:.1e}"}),
    # ---- the transverse band by wavelength (seconds; validation/chain_transverse.py)
    Claim("chain.band_zero", "chain",
          "the transverse (y) band at wavelength 2, F_x = 0: omega and the predicted V2 = "
          "omega / pi (every convention)", "seconds", _T, transverse_band,
          show=lambda v: f"omega {_band(v, 0.0)['band_omega2']:.5f}, V2 "
          f"{_band(v, 0.0)['band_v2']:.4f} (Fourier purity {_band(v, 0.0)['mode_purity']:.2f}; "
          "the ten y modes are degenerate: neighbours only touch); the most y-like "
          f"eigenvector alone has wavelength {_band(v, 0.0)['old_wavelength']:g}",
          tolerance="1e-8 relative (eigenvalues of a Newton equilibrium); wavelengths exact",
          check=same(rel=1e-8, abs=1e-10, keys=["rows"]),
          paper="omega ~ 0.235, 'a wavelength of approximately 2', V2 ~ 0.235 / pi ~ 0.075",
          verdict=lambda v: sigma_verdict([
              (_band(v, 0.0)["band_omega2"], 0.0, 0.235, half_unit("0.235")),
              (_band(v, 0.0)["band_v2"], 0.0, 0.075, half_unit("0.075"))]),
          job="chain.transverse_band",
          texts={"doc": lambda v: f"omega = {_band(v, 0.0)['band_omega2']:.5f}, V2 = "
                 f"{_band(v, 0.0)['band_v2']:.4f}"}),
    Claim("chain.band_loaded", "chain",
          "the band's wavelength-2 frequency and V2 = omega / pi at the paper's six F_x "
          "(physical); the most y-like single eigenvector's wavelength", "seconds", _T,
          transverse_band,
          show=lambda v: "V2 " + ", ".join(f"{f:g}: {_band(v, f)['band_v2']:.4f}"
                                           for f in PROBES)
          + f" (omega {min(_band(v, f)['band_omega2'] for f in PROBES):.3f}-"
            f"{max(_band(v, f)['band_omega2'] for f in PROBES):.3f}); single-eigenvector "
            "wavelengths " + ", ".join(f"{_band(v, f)['old_wavelength']:g}" for f in PROBES),
          tolerance="1e-8 relative (eigenvalues of Newton equilibria); wavelengths exact",
          check=same(rel=1e-8, abs=1e-10, keys=["rows"]),
          paper="V2 ~ 0.075, 'independent of F_x'",
          verdict=lambda v: sigma_verdict([(_band(v, f)["band_v2"], 0.0, 0.075,
                                            half_unit("0.075")) for f in PROBES]),
          job="chain.transverse_band",
          texts={"doc": lambda v: ", ".join(f"{_band(v, f)['band_v2']:.3f}" for f in PROBES)}),
    Claim("chain.ishima_first_birth", "chain",
          "the compose tutorial's chain (20 disks, Ishima's law): first birth, ramp to 0.02, "
          "tol 1e-8",
          "seconds", "python -m pytest validation/test_examples.py", ishima_birth,
          show=lambda v: f"F_x = {v['fx']:.8f}, bracket {v['bracket']:.1e}",
          tolerance="2e-8 (twice the bisection tolerance, as chain.first_birth)",
          check=lambda a, b: (bool(abs(a["fx"] - b["fx"]) <= 2e-8 and b["bracket"] <= 1e-8),
                              f"{a['fx']:.9f} -> {b['fx']:.9f}"),
          texts={"print": lambda v: f"`first pair birth at F_x = {v['fx']:.8f} (bracket "
                                    f"{v['bracket']:.1e})`"}),
    # ---- waves (minutes)
    Claim("chain.v1", "chain",
          "V1, forward wave of Coulomb breaching, F_x = 0.083 / 0.087 / 0.090 (25 realizations)",
          "minutes", _W, waves,
          show=lambda v: " / ".join(f"{_row(v, f)['v1']:.5f} +- {_row(v, f)['v1_err']:.5f}"
                                    for f in WAVE_FX),
          tolerance="3 combined bootstrap errors: the sliding dynamics is chaotic (bit-identical "
                    "with the same seeds on one machine, not across code changes)",
          check=within_sigma(3, _wave_pairs(["v1"], WAVE_FX)),
          paper="0.0014 +- 0.00013 / 0.0022 +- 0.00015 / 0.0028 +- 8e-5",
          verdict=lambda v: sigma_verdict([(_row(v, f)["v1"], _row(v, f)["v1_err"], *p)
                                           for f, p in zip(WAVE_FX, PAPER_V1)]),
          job="chain.waves",
          texts={"doc": lambda v: (
              "V1 = " + ", ".join(f"{_row(v, f)['v1']:.5f} +- {_row(v, f)['v1_err']:.5f}"
                                  for f in WAVE_FX)
              + " at F_x = 0.083, 0.087, 0.090 (paper 0.0014 +- 0.00013, 0.0022 +- 0.00015, "
              "0.0028 +- 8e-5: "
              + " / ".join(f"{sigma_distance(_row(v, f)['v1'], _row(v, f)['v1_err'], *p):.1f}"
                           for f, p in zip(WAVE_FX, PAPER_V1))
              + " combined standard errors, **"
              + sigma_verdict([(_row(v, f)["v1"], _row(v, f)["v1_err"], *p)
                               for f, p in zip(WAVE_FX, PAPER_V1)]).label + "** by the rule "
              "'within 2')")}),
    Claim("chain.v1_078", "chain",
          "V1 at F_x = 0.078 (just past the birth that opens the last unbroken stretch of "
          "pairs on the default ramp, 0.0772)",
          "minutes", _W, waves,
          show=lambda v: f"{_row(v, 0.078)['v1']:.5f} +- {_row(v, 0.078)['v1_err']:.5f}",
          tolerance="3 combined bootstrap errors (chaotic)",
          check=within_sigma(3, _wave_pairs(["v1"], (0.078,))),
          paper="(none: the paper gives V1 at 0.083, 0.087, 0.090 only)", job="chain.waves"),
    Claim("chain.v2", "chain",
          "V2, backward wave of sliding, F_x = 0.078 / 0.083 / 0.087 / 0.090",
          "minutes", _W, waves,
          show=lambda v: " / ".join(f"{r['v2']:.3f} +- {_v2_err(r):.3f}" for r in v["rows"])
          + f" (error: the larger of bootstrap and split); weighted mean {v['v2_mean']:.3f} +- "
          f"{v['v2_mean_err']:.3f}; sliding thresholds 0.01 / 0.05 (2R) at 0.087: "
          + " / ".join(f"{s['v2']:.3f}" for s in v["sensitivity"]),
          tolerance="3 combined bootstrap errors (chaotic)",
          check=within_sigma(3, _wave_pairs(["v2"])),
          paper="V2 ~ 0.235 / pi ~ 0.075, independent of F_x",
          verdict=lambda v: sigma_verdict([(r["v2"], _v2_err(r), 0.075, half_unit("0.075"))
                                           for r in v["rows"]]),
          job="chain.waves",
          texts={"doc": lambda v: (
              "V2 = " + ", ".join(f"{r['v2']:.3f}" for r in v["rows"])
              + f" at F_x = 0.078-0.090 (weighted mean {v['v2_mean']:.3f} +- "
              f"{v['v2_mean_err']:.3f}, each within {v['v2_max_sigma_from_mean']:.1f} of its "
              "errors of that mean; paper ~0.075, independent of F_x)"),
              "errors": lambda v: (
              "bootstrap errors " + _span([r["v2_err"] for r in v["rows"]], ".3f")
              + " and split errors " + _span([r["v2_split_err"] for r in v["rows"]], ".3f")
              + f" (from {5} disjoint sets of the 25 realizations); the sliding threshold "
              "(0.01 / 0.02 / 0.05 of 2R) moves V2 at 0.087 to "
              + " / ".join(f"{x:.3f}" for x in (v["sensitivity"][0]["v2"], _row(v, 0.087)["v2"],
                                                 v["sensitivity"][1]["v2"])))}),
    Claim("chain.vcm_slope", "chain",
          "centre-of-mass sliding velocity against F_x, linear fit over the four F_x (Eq. 10)",
          "minutes", _W, waves,
          show=lambda v: f"{v['intercept']:.1e} + {v['slope']:.2e} (+- {v['slope_err']:.1e}) "
          f"F_x; over the paper's three F_x: slope {v['slope_paper_fx']:.2e} (+- "
          f"{v['slope_paper_fx_err']:.1e}); at 0.083: {_row(v, 0.083)['v_com']:.2e}",
          tolerance="3 combined standard errors of the slope (realizations' errors propagated, "
                    "or the fit's scatter where larger)",
          check=within_sigma(3, [("slope", "slope_err")]),
          paper="V = -1.3e-3 + 4.5e-4 F_x (negative at these F_x as printed)",
          verdict=lambda v: sigma_verdict([(v["slope"], v["slope_err"], 4.5e-4,
                                            half_unit("4.5e-4"))]),
          job="chain.waves",
          texts={"doc": lambda v: f"{v['intercept']:.1e} + {v['slope']:.2e} F_x (+- "
                                  f"{v['slope_err']:.1e} on the slope)"}),
    # ---- dynamics, Fig. 3 (minutes; DYN_SEEDS runs per F_x)
    Claim("chain.breach_0083", "chain",
          "M(t) at the first Coulomb breach, F_x = 0.083 (20,000 time units, 4 seeds)",
          "minutes", _DYN_COMMAND.format(fx="0.083", duration=20000), dynamics,
          show=lambda v: (f"M = {_at_breach(v)[0]:.1e} (2R)^2 (geometric mean of "
                          f"{_at_breach(v)[2]} runs; per seed {_per_seed(v, 'breach', 'm_at_first_breach', '{:.1e}')}) "
                          f"at t = {_first_breach(v):.0f}; disks breached within 20,000 per seed: "
                          f"{_per_seed(v, 'breach', 'breached')} of 10"
                          if _at_breach(v)[2] else "no breach in any run"),
          tolerance="per seed: first breach time within 5 %, M there within a factor 2 (linear "
                    "growth before the breach; frames every 5 time units); after it the runs are "
                    "chaotic: the count of runs that slide within 1",
          check=_dyn_check,
          paper="'bringing M(t) to about 10^-2 R where for the first time the Coulomb law is "
                "breached' (R = 0.5 in 2R units; 'about' read as half a decade)",
          verdict=lambda v: (_decade_verdict([_at_breach(v)[:2]], 0.5e-2, "10^-2 R")
                             if _at_breach(v)[2] else Verdict("disagrees", "no run breaches")),
          job="chain.dynamics",
          texts={"doc": lambda v: "no run breaches within 20,000 time units" if not
                 _at_breach(v)[2] else (
              f"M(t) grows exponentially to {_at_breach(v)[0]:.1e} (geometric mean of "
              f"{len(v['breach']['runs'])} seeds) and the chain starts to move at t = "
              f"{_first_breach(v):.0f}, when the first disk's wall contact reaches the Coulomb "
              f"limit (disks that reach it within 20,000 time units, per seed: "
              f"{_per_seed(v, 'breach', 'breached')} of 10)")}),
    Claim("chain.fig3_saturation", "chain",
          "F_x = 0.03 and 0.04 (Fig. 3): M(t) stationary and minute, no Coulomb breach "
          "(40,000 time units, 4 seeds)",
          "minutes", _DYN_COMMAND.format(fx="0.03", duration=40000), dynamics,
          show=lambda v: "; ".join(
              f"{k[1:]}: M {min(r['late_min'] for r in v[k]['runs']):.1e}-"
              f"{max(r['late_max'] for r in v[k]['runs']):.1e} over the last half, "
              f"disks breached per seed {_per_seed(v, k, 'breached')}" for k in ("f0.03", "f0.04")),
          tolerance="per seed: M within a factor 2, stable or not exact",
          check=_dyn_check,
          paper="'the MSD becomes stationary at a minute fraction the disk radius (about 10^-5)'",
          verdict=lambda v: _seeds_verdict(
              v, ("f0.03", "f0.04"),
              lambda r: r["late_max"] < 2 * r["late_min"] and r["late_max"] < 1e-3
              and r["breached"] == 0, True,
              "stationary (factor < 2), minute (< 1e-3), no breach"),
          job="chain.dynamics"),
    Claim("chain.fig3_level", "chain",
          "the level of that stationary M(t), F_x = 0.03 / 0.04 (per run the geometric mean of "
          "the last half's range; over 4 seeds their geometric mean)", "minutes",
          _DYN_COMMAND.format(fx="0.03", duration=40000), dynamics,
          show=lambda v: " / ".join(f"{_level(v, k)[0]:.1e} (+- {_level(v, k)[1]:.2f} decades; "
                                    f"per seed {_per_seed_level(v, k)})"
                                    for k in ("f0.03", "f0.04")),
          tolerance="per seed a factor 2 (as chain.fig3_saturation)", check=_dyn_check,
          paper="about 10^-5 ('about' read as half a decade)",
          verdict=lambda v: _decade_verdict([_level(v, k) for k in ("f0.03", "f0.04")], 1e-5,
                                            "10^-5"),
          job="chain.dynamics",
          texts={"doc": lambda v: (
              "at F_x = 0.03 and 0.04 the instability saturates: M(t) stationary at "
              + " and ".join(f"{_level(v, k)[0]:.1e} ({k[1:]}; per seed "
                             + _per_seed_level(v, k) + ")" for k in ("f0.03", "f0.04"))
              + f" over the last half of 40,000 time units ({len(v['f0.03']['runs'])} seeds), "
              "with no Coulomb breach (paper: stationary at about 1e-5)")}),
    Claim("chain.fig3_0062", "chain",
          "F_x = 0.062 (Fig. 3): stable, or not (20,000 time units, 4 seeds)",
          "minutes", _DYN_COMMAND.format(fx="0.062", duration=20000), dynamics,
          show=lambda v: (_at_0062(v) + "; centre of mass moves "
                          f"{_per_seed(v, 'f0.062', 'com_moved', '{:.2f}')} (2R)"),
          tolerance="per seed stable or not exact (M below 1e-3 and no breach)", check=_dyn_check,
          paper="'the system is stable and M(t) remains minute'",
          verdict=lambda v: _seeds_verdict(v, ("f0.062",), _stable, True,
                                           "stable (M < 1e-3, no breach)"),
          job="chain.dynamics",
          texts={"doc": lambda v: f"at 0.062 our chain is {_at_0062(v)} (paper: stable)"}),
    Claim("chain.fig3_0083", "chain",
          "F_x = 0.083 (Figs. 3, 4, 7): Coulomb breach and transition to sliding (4 seeds)",
          "minutes", _DYN_COMMAND.format(fx="0.083", duration=20000), dynamics,
          show=lambda v: (f"the chain slides in {_count(v, 'breach', _slides)[0]} of "
                          f"{_count(v, 'breach', _slides)[1]} seeds within 20,000 time units: "
                          f"disks breached per seed {_per_seed(v, 'breach', 'breached')} of 10, "
                          "centre of mass moves "
                          f"{_per_seed(v, 'breach', 'com_moved', '{:.2f}')} (2R); over 40,000: "
                          f"{_per_seed(v, 'f0.083', 'breached')} of 10, "
                          f"{_per_seed(v, 'f0.083', 'com_moved', '{:.2f}')} (2R)"),
          tolerance="per seed breach or not exact; runs that slide within 1 (chaotic)",
          check=_dyn_check,
          paper="Coulomb law breached, transition to dynamical friction",
          verdict=lambda v: _seeds_verdict(v, ("breach",), _slides, True,
                                           "Coulomb breach and sliding (centre of mass moves "
                                           "> 0.1 (2R)) within 20,000"),
          job="chain.dynamics",
          texts={"doc": lambda v: (
              f"at 0.083 the chain slides in {_count(v, 'breach', _slides)[0]} of "
              f"{_count(v, 'breach', _slides)[1]} seeds within 20,000 time units (disks "
              f"breached per seed {_per_seed(v, 'breach', 'breached')} of 10; centre of mass "
              f"moves {_per_seed(v, 'breach', 'com_moved', '{:.2f}')} (2R) forward)")}),
    # ---- protocols (minutes)
    Claim("chain.protocol_damped", "chain",
          "the paper's damped protocol (nu = 0.01 per paper time unit = 0.447 per simulation "
          "unit): pairs at the six F_x, and for all F_x > 0.082",
          "minutes", _P, protocols, show=_damped_show,
          tolerance="exact (pair counts); near a birth the damped path chooses among equilibria, "
                    "so a code change that moves a bit may move them: the check reports it",
          check=_protocol_check,
          paper="yes, yes, no, yes, yes, yes; unstable for all F_x > 0.082",
          verdict=lambda v: exact_verdict(
              _pairs_word(_variant(v, "damped0.447")["probes"])
              + f"; above 0.082: {_variant(v, 'damped0.447')['above']}",
              _yes(PAPER_PAIRS) + "; above 0.082: True", "step 1e-3"),
          job="chain.protocols", texts={"doc": _damped_show}),
    Claim("chain.protocol_nu001", "chain",
          "damped protocol with nu = 0.01 per simulation unit, step 1e-3",
          "minutes", _P, protocols,
          show=lambda v: (lambda d: f"pairs {_probe_text(d['probes'])} at the six F_x "
                          f"('-': no equilibrium), {d['agreement']}/6 as the paper; "
                          + (f"ramp stopped at {d['stopped']:.3f} (no equilibrium from "
                             f"{d['no_equilibrium'][0]:.3f})" if d["stopped"] is not None
                             else "reached 0.1"))(_variant(v, "damped0.01")),
          tolerance="as chain.protocol_damped", check=_protocol_check,
          paper="yes, yes, no, yes, yes, yes",
          verdict=lambda v: exact_verdict(_pairs_word(_variant(v, "damped0.01")["probes"]),
                                          _yes(PAPER_PAIRS), "pair at each F_x"),
          job="chain.protocols",
          texts={"doc": lambda v: (lambda d: (
              f"agrees at {d['agreement']} of the six F_x and "
              + (f"finds no equilibrium from F_x = {d['no_equilibrium'][0]:.3f} (the ramp stops "
                 f"at {d['stopped']:.3f})" if d["no_equilibrium"] else "reaches 0.1")))(
              _variant(v, "damped0.01"))}),
    Claim("chain.protocol_newton", "chain",
          "Newton ramps at steps 5e-4 / 2e-3 / 5e-3 and from a damped F_x = 0 state: the "
          "default's events?", "minutes", _P, protocols,
          show=lambda v: "; ".join(
              f"{k}: {_variant(v, k)['events']} events, first birth "
              f"{_variant(v, k)['first_birth']}, {_variant(v, k)['agreement']}/6 as the paper"
              for k in ("default", "step5e-4", "step2e-3", "step5e-3", "damped-start")),
          tolerance="as chain.protocol_damped", check=_protocol_check, job="chain.protocols"),
    # ---- solvers, knobs (minutes)
    Claim("chain.newton_speedup", "chain",
          "Newton against the damped protocol (nu = 0.01), time to max|F| < 1e-12, ramp to "
          "0.03 in steps of 1e-3",
          "minutes", "python validation/chain_solvers.py", solvers,
          show=lambda v: f"{v['seconds_newton']:.3f} s vs {v['seconds_damped']:.1f} s "
          f"({v['speedup']:.0f}x); first pair at F_x = {v['first_pair_newton']} (Newton), "
          f"{v['first_pair_damped']} (damped)",
          tolerance="speed ratio within a factor 3 (one timing on a shared machine); first pairs "
                    "exact",
          check=lambda a, b: (1 / 3 <= b["speedup"] / a["speedup"] <= 3
                              and same(keys=["first_pair_newton", "first_pair_damped"])(a, b)[0],
                              f"{a['speedup']:.0f}x -> {b['speedup']:.0f}x"),
          verdict=lambda v: floor_verdict(v["speedup"], 100, "speed ratio (issue: >= 100x)"),
          job="chain.solvers", trace=False,
          texts={"doc": lambda v: (
              f"Newton was {v['speedup']:.0f}x faster in the recorded run "
              f"({v['seconds_newton']:.3f} s against {v['seconds_damped']:.1f} s). The two "
              "equilibria differ because the history follows different paths (ramping to "
              f"0.03 in steps of 1e-3 they end {v['max_dq_at_end']:.1e} apart in position; "
              "the first complex pair at the ramp's resolution is at F_x = "
              f"{v['first_pair_newton']} with Newton and {v['first_pair_damped']} with the "
              "damped protocol at nu = 0.01)")}),
    Claim("chain.knobs", "chain",
          "ramp step, bisection tolerance and Verlet step against accuracy "
          "(chain_tradeoffs.md)", "minutes", "python validation/chain_tradeoffs.py", knobs,
          show=lambda v: f"first-birth error / tol <= {v['worst_error_over_tol']:.2f}; "
          f"growth-rate error ~ dt^{v['growth_error_order']:.2f}; V1, V2 at other dt within "
          f"{v['v1_max_sigma']:.1f}, {v['v2_max_sigma']:.1f} combined errors of the finest",
          tolerance="error / tol on the same side of 1; the Verlet order within 0.3; events "
                    "per step exact", check=_knobs_check,
          verdict=lambda v: bound_verdict(v["worst_error_over_tol"], 1.0,
                                          "first-birth error / bisection tol"),
          job="chain.knobs"),
]

# the readings of the eigenvalues and the inertia (issue 33): one job, its own module
from .chain_conventions import CLAIMS as _CONVENTION_CLAIMS  # noqa: E402

CLAIMS += _CONVENTION_CLAIMS
