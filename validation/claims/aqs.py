"""Claims of section aqs (see claims/__init__.py): issue 17, complex pairs along
athermal quasistatic shear."""

import math

from .core import Claim, Result, Verdict, bound_verdict

HEADING = 'Complex pairs along quasistatic shear'
INTRO = ('`fricstab packing aqs`: athermal quasistatic shear with history, the dense spectrum of M^-1 K at every state, pair births bisected in strain. The study (`validation/aqs_study.py`, answer in `validation/aqs_study.md`): bidisperse packings at phi = 0.90, rattlers removed, strain 0.2 in steps of 5e-4; a drop is preceded when a pair is born within one step before its onset, against the null of the same statistic at uniform strains (exact), with 95 % Wilson intervals and a one-sided binomial test.')

STUDY_COMMAND = "python validation/aqs_study.py --cache DIR (N = 64 x 4 seeds, 128 x 2, strain 0.2)"
SIZE_COMMAND = ("python validation/aqs_study.py --sizes 256 --seeds 1 --laws 0 3 5 "
                "--no-dgamma-scan --prefix aqs_study_n256 --cache DIR")
AQS_ARGS = ["packing", "aqs", "--law", "charan", "--n", "64", "--strain", "0.015",
            "--dgamma", "1e-4", "--no-progress", "--quiet"]


def _checkout():
    from pathlib import Path
    return Path(__file__).resolve().parents[2]


def _aqs_study(name="aqs_study"):
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


# ------------------------------------------------------------ hours: the study

def _row_values(r):
    """The values of one law row of aqs_study (JSON-ready)."""
    out = {"law": r["law"], "runs": r["runs"],
           "births_per_strain": float(r["births_per_strain"]),
           "drops_per_strain": float(r["drops_per_strain"]),
           "growth_at_onset_median": float(r["growth_at_onset_median"]),
           "critical_rate_median": float(r["critical_rate_median"]),
           "pair_at_onset": [int(r["pair_at_onset"][0]), int(r["pair_at_onset"][1])],
           "pair_at_onset_ci": _interval(r["pair_at_onset"][2]),
           "states_with_pair": [int(r["pair_any_state"][0]), int(r["pair_any_state"][1])],
           "states_with_pair_ci": _interval(r["pair_any_state"][2])}
    for w in ("w1", "w4"):
        s = r[w]
        out[w] = {"drops": int(s["drops"]), "preceded": int(s["preceded"]),
                  "ci": _interval(s["fraction_ci95"]),
                  "null": float(s["null_fraction"]), "p": float(s["pvalue_greater"])}
    return out


def _study_values(doc):
    rows = {r["law"]: _row_values(r) for r in doc["rows"]}
    stopped = [{"law": label, "n": int(r["n"]), "seed": int(r["seed"]),
                "gamma_max": float(r["gamma_max"])}
               for label, runs in doc["runs"].items() for r in runs
               if r.get("failure")]
    dep = [{"law": d["law"], "dgamma": float(d["dgamma"]), "drops": int(d["drops"]),
            "total_drop": float(d["total_drop"])} for d in doc.get("dgamma_dependence", [])]
    return {"rows": rows, "stopped": stopped, "dgamma_dependence": dep,
            "strain": float(doc["strain"]), "dgamma": float(doc["dgamma"])}


def aqs_study_run():
    """``python validation/aqs_study.py`` (N = 64 x 4 seeds and 128 x 2, strain 0.2, six law
    rows, the dgamma scan), the runs cached in a fresh folder for this job only; writes
    validation/aqs_study.json, .png and aqs_study_tables.md."""
    import tempfile
    aqs_study = _aqs_study()
    doc = aqs_study.run(["--cache", tempfile.mkdtemp(), "--out", str(_checkout() / "validation")])
    return Result(_study_values(doc), seeds=(0, 1, 2, 3),
                  outputs=("validation/aqs_study.json", "validation/aqs_study.png",
                           "validation/aqs_study_tables.md"))


def aqs_size_run():
    """The size check: N = 256, one seed, charan mu = 0.1, ishima kT/kN = 1, hertz."""
    import tempfile
    aqs_study = _aqs_study()
    doc = aqs_study.run(["--sizes", "256", "--seeds", "1", "--laws", "0", "3", "5",
                         "--no-dgamma-scan", "--prefix", "aqs_study_n256",
                         "--cache", tempfile.mkdtemp(), "--out", str(_checkout() / "validation")])
    return Result(_study_values(doc), seeds=(0,),
                  outputs=("validation/aqs_study_n256.json", "validation/aqs_study_n256.png",
                           "validation/aqs_study_n256_tables.md"))


CHARAN = ("charan mu=0.1 kt=1", "charan mu=0.3 kt=1", "charan mu=0.1 kt=0.5")
ISHIMA = ("ishima kt=1", "ishima kt=0.5")


def _ci(ci):
    ok = ci[0] is not None and not isinstance(ci[0], str) and math.isfinite(ci[0])
    return f"[{ci[0]:.2f}, {ci[1]:.2f}]" if ok else "-"


def _interval(ci):
    """A Wilson interval for JSON: None where it is undefined (no trials)."""
    return [float(x) if math.isfinite(x) else None for x in ci]


def _preceded(r, w="w1"):
    s = r[w]
    return f"{s['preceded']}/{s['drops']} {_ci(s['ci'])} vs null {s['null']:.2f} (p {s['p']:.2g})"


def _rows_show(v, labels):
    return "; ".join(f"{label}: {_preceded(v['rows'][label])}" for label in labels
                     if label in v["rows"]) + "; pairs at " + _pct_range(v, labels) + " of all states"


def _pct_range(v, labels):
    fr = [r["states_with_pair"][0] / r["states_with_pair"][1] for k, r in v["rows"].items()
          if k in labels]
    lo, hi = min(fr), max(fr)
    return f"{100 * lo:.0f} %" if round(100 * lo) == round(100 * hi) else \
        f"{100 * lo:.0f}-{100 * hi:.0f} %"


def _fraction_sigma(s):
    n = max(s["drops"], 1)
    f = min(max(s["preceded"] / n, 0.5 / n), 1 - 0.5 / n)
    return f, math.sqrt(f * (1 - f) / n)


def _check_study(a, b):
    """Each law's preceded fraction (1 and 4 steps) and fraction of states with a pair
    within 3 combined binomial standard errors; hertz without a pair."""
    worst, where = 0.0, "identical"
    for label, x in a["rows"].items():
        y = b["rows"].get(label)
        if y is None:
            return False, f"{label} missing"
        for w in ("w1", "w4"):
            fa, sa = _fraction_sigma(x[w])
            fb, sb = _fraction_sigma(y[w])
            d = abs(fa - fb) / math.hypot(sa, sb)
            if d > 3:
                return False, f"{label} {w}: {fa:.2f} -> {fb:.2f} ({d:.1f} combined sigma)"
            if d > worst:
                worst, where = d, f"largest move {d:.2f} combined sigma ({label} {w})"
        if label == "hertz" and y["states_with_pair"][0] != 0:
            return False, f"hertz: {y['states_with_pair'][0]} states with a pair"
    return True, where


STUDY_TOLERANCE = ("each preceded fraction within 3 combined binomial standard errors: the "
                   "path is deterministic on one machine, but another CPU's rounding moves "
                   "events after the first drop; hertz's 0 pairs exact (symmetric Hessian)")


def _no_excess(v, labels):
    """No excess of births before drops: every law's one-sided p above 0.05."""
    ps = [v["rows"][k]["w1"]["p"] for k in labels if k in v["rows"]]
    return all(p > 0.05 for p in ps), ps


def _answer(v):
    out = []
    for name, labels in (("charan", CHARAN), ("ishima", ISHIMA)):
        no, ps = _no_excess(v, labels)
        out.append(f"{name}: {'no' if no else 'yes'} (p = "
                   + ", ".join(f"{p:.2g}" for p in ps) + ")")
    hz = v["rows"].get("hertz")
    if hz is not None:
        out.append(f"hertz drops without any pair ({hz['w1']['drops']} drops, "
                   f"{hz['states_with_pair'][0]} of {hz['states_with_pair'][1]:,} states with a pair)")
    return "; ".join(out)


def _range(xs, fmt="{:.2g}"):
    lo, hi = min(xs), max(xs)
    return fmt.format(lo) if fmt.format(lo) == fmt.format(hi) else f"{fmt.format(lo)}-{fmt.format(hi)}"


def _growth_show(v):
    parts = []
    for name, labels in (("charan", CHARAN), ("ishima", ISHIMA)):
        rows = [v["rows"][k] for k in labels if k in v["rows"]]
        parts.append(f"{name}: median growth at drop onsets "
                     f"{_range([r['growth_at_onset_median'] for r in rows])} t0^-1, critical "
                     f"shear rate {_range([r['critical_rate_median'] for r in rows])} t0^-1")
    return "; ".join(parts)


def study_table(v):
    """Table 1 of validation/aqs_study.md (the table aqs_study_tables.md holds)."""
    lines = ["| law | runs | drops | births / strain | preceded, 1 step (95 % CI) | null 1 step "
             "| p | preceded, 4 steps (95 % CI) | null 4 steps | p | pair at onset (CI) | "
             "states with a pair (CI) | median growth at onset (t0^-1) | median critical "
             "rate (t0^-1) |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in v["rows"].values():
        a, b = r["w1"], r["w4"]
        k, n = r["pair_at_onset"]
        ks, ns = r["states_with_pair"]
        lines.append(
            f"| {r['law']} | {r['runs']} | {a['drops']} | {r['births_per_strain']:.0f} | "
            f"{a['preceded']}/{a['drops']} {_ci(a['ci'])} | {a['null']:.2f} | {a['p']:.2g} | "
            f"{b['preceded']}/{b['drops']} {_ci(b['ci'])} | {b['null']:.2f} | {b['p']:.2g} | "
            f"{k}/{n} {_ci(r['pair_at_onset_ci'])} | {ks}/{ns} {_ci(r['states_with_pair_ci'])} | "
            f"{r['growth_at_onset_median']:.2g} | {r['critical_rate_median']:.2g} |")
    return "\n".join(lines)


def dgamma_table(v):
    """Table 2 of validation/aqs_study.md: drops against the strain step."""
    lines = ["| law | dgamma | drops | drops / strain | summed drop |", "|---|---|---|---|---|"]
    lines += [f"| {d['law']} | {d['dgamma']:g} | {d['drops']} | "
              f"{d['drops'] / v['strain']:.0f} | {d['total_drop']:.2e} |"
              for d in v["dgamma_dependence"]]
    return "\n".join(lines)


def _dgamma_sentence(v):
    out = []
    for law, name in (("charan mu=0.1 kt=1", "charan"), ("hertz", "hertz")):
        ds = [d for d in v["dgamma_dependence"] if d["law"] == law]
        if not ds:
            continue
        tot = [d["total_drop"] for d in ds]
        spread = (max(tot) - min(tot)) / max(tot) if max(tot) > 0 else 0.0
        out.append(f"{', '.join(str(d['drops']) for d in ds)} drops for {name} (summed drop "
                   f"within {100 * spread:.2g} %)")
    steps = ", ".join(f"{d['dgamma']:g}" for d in v["dgamma_dependence"]
                      if d["law"] == "hertz")
    return f"at dgamma = {steps} the same path has " + " and ".join(out)


def _stopped(v):
    if not v["stopped"]:
        return f"Every path reached strain {v['strain']:g}."
    items = [f"{s['law']} N = {s['n']} seed {s['seed']} at {s['gamma_max']:.3g}"
             for s in v["stopped"]]
    return (f"{len(items)} path{'s' if len(items) > 1 else ''} ended before strain "
            f"{v['strain']:g} on a step without equilibrium (FIRE then Newton did not reach "
            f"1e-13): {'; '.join(items)}; their statistics use the path up to there.")


def _answer_text(v, name):
    labels = CHARAN if name == "charan" else ISHIMA
    rows = [v["rows"][k] for k in labels if k in v["rows"]]
    k = sum(r["pair_at_onset"][0] for r in rows)
    n = sum(r["pair_at_onset"][1] for r in rows)
    no, _ = _no_excess(v, labels)
    verdict = "no" if no else "yes, for at least one parameter set (p <= 0.05)"
    return (f"**{verdict}.** Pairs exist at {_pct_range(v, labels)} of all relaxed states, "
            f"born at {_range([r['births_per_strain'] for r in rows], '{:,.0f}')} per unit "
            f"strain; {k}/{n} drops have a pair at their onset. A birth within one step "
            "before the onset: " + ", ".join(f"{r['w1']['preceded']}/{r['w1']['drops']}"
                                             for r in rows)
            + " drops against the null " + ", ".join(f"{r['w1']['null']:.2f}" for r in rows)
            + " (p = " + ", ".join(f"{r['w1']['p']:.2g}" for r in rows) + "). Median growth "
            f"rate at the onsets {_range([r['growth_at_onset_median'] for r in rows])} t0^-1; "
            "a pair grows by one e-fold between its birth and the drop only below shear rates "
            f"of {_range([r['critical_rate_median'] for r in rows])} t0^-1")


def _size_sentence(v):
    parts = []
    for label in ("charan mu=0.1 kt=1", "ishima kt=1"):
        r = v["rows"].get(label)
        if r is None:
            continue
        ks, ns = r["states_with_pair"]
        parts.append(f"{label}: {r['births_per_strain']:,.0f} births per strain, pairs at "
                     f"{ks} of {ns} states, drops preceded within one step {_preceded(r)}")
    hz = v["rows"].get("hertz")
    if hz is not None:
        parts.append(f"hertz: {hz['states_with_pair'][0]} pairs, {hz['w1']['drops']} drops")
    return "; ".join(parts)


def _readme(label, null_word="a null of "):
    return lambda v: (f"{v['rows'][label]['w1']['preceded']}/{v['rows'][label]['w1']['drops']} "
                      f"against {null_word}{v['rows'][label]['w1']['null']:.2f}, "
                      f"p = {v['rows'][label]['w1']['p']:.2g}")


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
    # --- the study (hours)
    _claim("charan_precursors",
           "charan (slip): drops preceded by a pair birth within one step (5e-4), against the "
           "null",
           "hours", STUDY_COMMAND, aqs_study_run,
           show=lambda v: _rows_show(v, CHARAN),
           tolerance=STUDY_TOLERANCE, check=_check_study, job="aqs.study",
           texts={"readme": _readme("charan mu=0.1 kt=1"),
                  "table": lambda v: f"\n\n{study_table(v)}\n\n",
                  "dgamma_table": lambda v: f"\n\n{dgamma_table(v)}\n\n",
                  "dgamma_sentence": _dgamma_sentence,
                  "stopped": _stopped, "answer": lambda v: _answer_text(v, "charan")}),
    _claim("ishima_precursors",
           "ishima (no slip): drops preceded by a pair birth within one step, against the null",
           "hours", STUDY_COMMAND, aqs_study_run,
           show=lambda v: _rows_show(v, ISHIMA),
           tolerance=STUDY_TOLERANCE, check=_check_study, job="aqs.study",
           texts={"readme": _readme("ishima kt=1", ""),
                  "answer": lambda v: _answer_text(v, "ishima")}),
    _claim("hertz_control",
           "hertz (frictionless control): complex pairs along the same paths",
           "hours", STUDY_COMMAND, aqs_study_run,
           show=lambda v: f"{v['rows']['hertz']['states_with_pair'][0]} pairs in "
           f"{v['rows']['hertz']['states_with_pair'][1]:,} states; "
           f"{v['rows']['hertz']['w1']['drops']} drops, "
           f"{v['rows']['hertz']['w1']['preceded']} preceded",
           tolerance=STUDY_TOLERANCE, check=_check_study, job="aqs.study",
           verdict=lambda v: bound_verdict(v["rows"]["hertz"]["states_with_pair"][0], 0,
                                           "states with a pair (symmetric Hessian: none)"),
           texts={"states": lambda v: f"{v['rows']['hertz']['states_with_pair'][1]:,}",
                  "drops": lambda v: f"{v['rows']['hertz']['w1']['drops']}"}),
    _claim("answer",
           "answer: do complex pairs precede stress drops? (no: no law's one-sided p <= 0.05 "
           "for births before drops against births at random strains)",
           "hours", STUDY_COMMAND, aqs_study_run,
           show=_answer, tolerance=STUDY_TOLERANCE, check=_check_study, job="aqs.study",
           texts={"pairs_charan": lambda v: _pct_range(v, CHARAN),
                  "pairs_ishima": lambda v: _pct_range(v, ISHIMA)}),
    _claim("growth_time",
           "growth time against the loading: median growth rate at drop onsets and the shear "
           "rate below which a pair grows by one e-fold between its birth and the drop",
           "hours", STUDY_COMMAND, aqs_study_run,
           show=_growth_show, tolerance=STUDY_TOLERANCE, check=_check_study, job="aqs.study"),
    _claim("size_check",
           "size check N = 256, one seed: charan mu = 0.1, ishima kT/kN = 1, hertz",
           "hours", SIZE_COMMAND, aqs_size_run,
           show=lambda v: "; ".join(
               f"{label}: {_preceded(v['rows'][label])}" for label in
               ("charan mu=0.1 kt=1", "ishima kt=1")) + f"; hertz "
           f"{v['rows']['hertz']['states_with_pair'][0]} pairs, "
           f"{v['rows']['hertz']['w1']['drops']} drops",
           tolerance=STUDY_TOLERANCE, check=_check_study,
           texts={"table": lambda v: f"\n\n{study_table(v)}\n\n",
                  "sentence": _size_sentence}),
]
