"""Claims of section aqs (see claims/__init__.py): issue 17, complex pairs along
athermal quasistatic shear."""

import math

from .core import Claim, Result, Verdict, bound_verdict

HEADING = 'Complex pairs along quasistatic shear'
INTRO = ("`fricstab packing aqs`: athermal quasistatic shear with history, the dense spectrum "
         "of M^-1 K at every state, pair births bisected in strain; the checks of the protocol. "
         "Whether pairs precede the stress drops is the next section: the ranked test, with issue "
         "17's birth-window test (a pair born within one step before a drop's onset, against the "
         "same at every strain) and the power of each.")

AQS_ARGS = ["packing", "aqs", "--law", "charan", "--n", "64", "--strain", "0.015",
            "--dgamma", "1e-4", "--no-progress", "--quiet"]


def _checkout():
    from pathlib import Path
    return Path(__file__).resolve().parents[2]


def _aqs_study(name):
    import importlib
    import sys
    path = str(_checkout() / "validation")
    if path not in sys.path:
        sys.path.insert(0, path)
    return importlib.import_module(name)


# ------------------------------------------------------------ minutes: brackets, growth, resume

def aqs_checks():
    """Three checks of the protocol on N = 64, phi = 0.90, seed 0, charan:

    * ``fricstab packing aqs --law charan --n 64 --strain 0.015 --dgamma 1e-4``: every
      located birth's bracket, and the pair count re-evaluated from the exported
      ``jacobian.npz`` + ``mass.npy`` at both ends (``tests/test_aqs.py``'s recount);
    * the growth rate of Newtonian dynamics along the pair's mode against the
      Jacobian's, at the three fastest-growing states with a pair between strains 0.01
      and 0.013 (steps of 2.5e-4; ``tests/test_aqs_growth.py``);
    * a path interrupted at step 4 of 8 and resumed from its checkpoint against the
      uninterrupted one (``tests/test_aqs.py -k resume``).
    """
    import json
    import tempfile
    from pathlib import Path

    import numpy as np

    from fricstab.analysis.spectrum import growth_rate
    from fricstab.cli import main
    from fricstab.protocols import aqs as aqs_protocol
    from fricstab.protocols.aqs import pairs, relax_step, spectrum
    from fricstab.protocols.aqs_growth import measure_growth
    from fricstab.scenes.packing import make_packing
    from fricstab.scenes.packing_friction import backbone, frictional, material
    from tests.test_aqs import _pair_count

    out = Path(tempfile.mkdtemp()) / "aqs"
    status = main(AQS_ARGS + ["--out", str(out)])
    doc = json.loads((out / "aqs.json").read_text())
    births = [e for e in doc["events"] if e["kind"] == "birth"]
    located = [e for e in births if e["located"]]
    recounted = 0
    for e in located:
        lo, hi = (out / d for d in e["directories"])
        recounted += _pair_count(hi) == _pair_count(lo) + 1
    brackets = {"status": status, "births": len(births), "located": len(located),
                "recounted": recounted,
                "max_bracket": max((e["gamma_hi"] - e["gamma_lo"] for e in located), default=0.0)}

    bb = backbone(make_packing(64, 0.9, 0))
    fr = frictional(bb, material("charan"))
    system, state = fr.system, fr.state
    found = []
    for k in range(1, 53):
        state, _ = relax_step(system, state, 2.5e-4, 1e-13)
        if k >= 40:
            w, _ = spectrum(system, state)
            if len(pairs(w)) and growth_rate(w) > 1e-4:
                found.append((growth_rate(w), k * 2.5e-4, state.copy()))
    found.sort(key=lambda t: -t[0])
    growth = []
    for _, strain, s in found[:3]:
        g = measure_growth(system, s)
        growth.append({"strain": strain, "predicted": float(g.predicted),
                       "measured": float(g.measured),
                       "relative_difference": float(g.relative_difference)})
    growth.sort(key=lambda x: x["strain"])

    system, state = fr.system, fr.state
    saved = {}
    full = aqs_protocol.run_aqs(system, state, 2e-3, 2.5e-4, checkpoint=saved.__setitem__,
                                checkpoint_every=4)
    cont = aqs_protocol.run_aqs(system, state, 2e-3, 2.5e-4,
                                resume=dict(saved[4], step=np.int64(4)))
    resume = {"stress_identical": bool(np.array_equal(cont.stress, full.stress)),
              "events_identical": [e.row() for e in cont.events] == [e.row() for e in full.events],
              "steps": int(len(full.stress))}
    return Result({"brackets": brackets, "growth": growth, "states_with_pair": len(found),
                   "resume": resume}, seeds=(0,))


def _check_brackets(a, b):
    x, y = a["brackets"], b["brackets"]
    if y["max_bracket"] > 1e-6 or y["recounted"] != y["located"] or y["status"] != 0:
        return False, f"bracket {y['max_bracket']:.2g}, recounted {y['recounted']} of {y['located']}"
    if abs(x["births"] - y["births"]) > 2:
        return False, f"births {x['births']} -> {y['births']}"
    return True, f"births {x['births']} -> {y['births']}, every bracket <= 1e-6, recounted"


def _check_growth(a, b):
    if len(b["growth"]) < 3:
        return False, f"only {len(b['growth'])} states with a pair"
    worst = max(g["relative_difference"] for g in b["growth"])
    if worst > 2e-3:
        return False, f"relative difference {worst:.2g} > 2e-3 (the error model)"
    return True, f"largest relative difference {worst:.2g} <= 2e-3"


def _range(xs, fmt="{:.2g}"):
    lo, hi = min(xs), max(xs)
    return fmt.format(lo) if fmt.format(lo) == fmt.format(hi) else f"{fmt.format(lo)}-{fmt.format(hi)}"


def _claim(short, title, tier, command, compute, show, tolerance, check, **kw):
    return Claim(f"aqs.{short}", "aqs", title, tier, command, compute, show, tolerance,
                 check, **kw)


CLAIMS = [
    _claim("birth_brackets",
           "every birth bracket <= 1e-6 in strain; the pair count re-evaluated from the "
           "exported jacobian.npz + mass.npy is n at the lower end and n + 1 at the upper "
           "(charan N = 64, strain 0.015, dgamma 1e-4)",
           "minutes", "fricstab packing aqs --law charan --n 64 --strain 0.015 --dgamma 1e-4 "
           "--out DIR", aqs_checks,
           show=lambda v: f"{v['brackets']['recounted']} of {v['brackets']['located']} births "
           f"n / n + 1 ({v['brackets']['births']} births), largest bracket "
           f"{v['brackets']['max_bracket']:.2g}",
           tolerance="one deterministic path on one machine; another CPU's rounding may move "
                     "a birth across a step (births within 2); every bracket below the "
                     "bisection's --tol 1e-6 and every recount n / n + 1 in any case (the "
                     "pair's Im at 1e-6 from its exceptional point, ~1e-5, is far above eig's "
                     "round-off)",
           check=_check_brackets, job="aqs.checks",
           verdict=lambda v: bound_verdict(
               v["brackets"]["max_bracket"] if v["brackets"]["recounted"]
               == v["brackets"]["located"] > 0 else math.inf, 1e-6,
               "largest bracket (every recount n / n + 1)")),
    _claim("growth",
           "dynamic growth rate (velocity Verlet from a 1e-10 d perturbation along the "
           "pair's mode) against the Jacobian's, at the three fastest-growing states with a "
           "pair (charan N = 64, strains 0.01-0.013 in steps of 2.5e-4)",
           "minutes", "python -m pytest tests/test_aqs_growth.py", aqs_checks,
           show=lambda v: ", ".join(f"{g['relative_difference']:.2g}" for g in v["growth"])
           + " relative (strains " + ", ".join(f"{g['strain']:g}" for g in v["growth"])
           + "; rates " + _range([g["predicted"] for g in v["growth"]]) + " t0^-1)",
           tolerance="each relative difference below 2e-3, the error model: Verlet phase "
                     "error (omega dt)^2 ~ 1e-3 and the linear regime (amplitude <= 2e-6 d)",
           check=_check_growth, job="aqs.checks",
           verdict=lambda v: bound_verdict(max(g["relative_difference"] for g in v["growth"]),
                                           0.02, "largest relative difference (issue: 2 %)"),
           texts={"agreement": lambda v: f"{max(g['relative_difference'] for g in v['growth']):.0e}",
                  "strains": lambda v: ", ".join(f"{g['strain']:g}" for g in v["growth"]),
                  "measured": lambda v: ", ".join(f"{g['measured']:.7g}" for g in v["growth"]),
                  "predicted": lambda v: ", ".join(f"{g['predicted']:.7g}" for g in v["growth"]),
                  "differences": lambda v: ", ".join(f"{g['relative_difference']:.2g}"
                                                     for g in v["growth"])}),
    _claim("resume",
           "a path checkpointed at step 4 and resumed gives the uninterrupted result "
           "(stresses and events)",
           "minutes", "python -m pytest tests/test_aqs.py -k resume", aqs_checks,
           show=lambda v: ("identical" if v["resume"]["stress_identical"]
                           and v["resume"]["events_identical"] else "DIFFERENT")
           + f" over {v['resume']['steps']} states",
           tolerance="exact: the checkpoint holds the whole state and path",
           check=lambda a, b: (b["resume"]["stress_identical"] and b["resume"]["events_identical"],
                               "bit-identical" if b["resume"]["stress_identical"] else "differs"),
           job="aqs.checks",
           verdict=lambda v: Verdict("meets" if v["resume"]["stress_identical"]
                                     and v["resume"]["events_identical"] else "fails",
                                     "np.array_equal of the stresses, events equal")),
]
