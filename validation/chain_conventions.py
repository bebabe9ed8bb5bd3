"""Charan's numbers under each reading of "the eigenvalues of J" (issue 33).

The paper prints eigenvalues "of J" without saying which matrix, and never
states the moment of inertia of its LAMMPS dynamics; its supplementary
material states ``I_i = I_0 m_i R^2`` with ``m_i = I_0 = 1`` for its
Jacobian (around SM Eqs. 36-37).  Each *reading* fixes both: the matrix whose
spectrum is taken (:data:`fricstab.scenes.chain.CONVENTIONS`) and the inertia
of the dynamics (:func:`fricstab.scenes.chain.convention_scene`):

* ``physical``: M^-1 J and dynamics with I = m R^2 / 2 (a uniform disk; our default);
* ``lammps``: I = 2/5 m R^2 (LAMMPS' fix nve/sphere default) for both;
* ``sm``: I = m R^2 (the SM's statement) for both;
* ``bare``: J itself; its dynamics is I = m (2R)^2 = 1 (the inertia under which
  M^-1 J is J at m = 1, 2R = 1);
* ``bare+lammps``: the spectrum of J itself, dynamics with LAMMPS' 2/5 m R^2
  (a paper that took the eigenvalues of its Jacobian as printed and ran LAMMPS
  with its default).

For each reading, every Charan number that depends on it: pair events on the
default Newton ramp (step 1e-3, bisection 1e-6), pairs at the paper's six F_x,
the onset of "unstable for all F_x > 0.082", the largest Im lambda at 0.083,
0.087, 0.090, V1 (25 seeded realizations per F_x, 25,000 time units), V1 over
Im lambda (the paper's ratio, like for like), V2 measured, and the
y band's frequency at wavelength 2 and omega / pi (the paper's V2
prediction) at F_x = 0 and 0.083.  Each against the paper with a computed distance: a value the
paper prints without an error gets half a unit of its last printed digit;
agreement means within 2 combined standard errors.  Writes
``chain_conventions.md``; :func:`run` returns the numbers (claims
``chain.conv_*`` of ``validation/claims/chain_conventions.py``).

    python validation/chain_conventions.py [--realizations 25]
"""

import argparse
import math
import platform
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))
sys.path.insert(0, str(HERE))        # the claims registry (validation/claims)

import numpy as np  # noqa: E402

from claims.chain_conventions import row_word  # noqa: E402
from claims.core import half_unit, sigma_distance, sigma_verdict  # noqa: E402
from fricstab.analysis.spectrum import complex_pairs  # noqa: E402
from fricstab.protocols.ramp import ramped_equilibrium, run_ramp  # noqa: E402
from fricstab.protocols.waves import fit_waves, run_realization  # noqa: E402
from fricstab.scenes.chain import ChainScene, convention_scene, eigenvalue_unit  # noqa: E402

REPORT = HERE / "chain_conventions.md"
#: reading -> (spectrum convention, dynamics convention)
READINGS = {"physical": ("physical", "physical"), "lammps": ("lammps", "lammps"),
            "sm": ("sm", "sm"), "bare": ("bare", "bare"), "bare+lammps": ("bare", "lammps")}
PROBES = (0.03, 0.04, 0.062, 0.083, 0.087, 0.090)
PAPER_PAIRS = (True, True, False, True, True, True)
WAVE_FX = (0.083, 0.087, 0.090)
#: Charan p. 3: "0.00024, 0.00077 and 0.001"; V1 "0.0014 +- 0.00013, 0.0022 +- 0.00015 and
#: 0.0028 +- 8 x 10^-5"; the ratio "4.3 +- 1.5"; omega ~ 0.235, V2 ~ 0.075; SM: "unstable
#: for all force values F_x > 0.082".
PAPER_IM = ("0.00024", "0.00077", "0.001")
PAPER_V1 = ((0.0014, 0.00013), (0.0022, 0.00015), (0.0028, 8e-5))
PAPER_RATIO = (4.3, 1.5)
PAPER_ONSET = "0.082"
PAPER_OMEGA, PAPER_V2 = "0.235", "0.075"
K = 2.0   # agreement: within K combined standard errors


def sigma(ours, ours_err, paper, paper_err):
    """Combined-sigma distance (claims.core); no value of ours (no breach) is infinitely far."""
    return sigma_distance(ours, ours_err, paper, paper_err) if math.isfinite(ours) else math.inf


def paper_ratio_from_printed():
    """The paper's V1 / Im from its own printed values: mean and spread of the three."""
    r = np.array([v[0] / float(p) for v, p in zip(PAPER_V1, PAPER_IM)])
    return float(r.mean()), float(r.std(ddof=1)), [float(x) for x in r]


# ------------------------------------------------------------ spectra

def spectrum_numbers(convention, fx_max=0.1, step=1e-3, tol=1e-6):
    """The default Newton ramp's events and the paper's probes under ``convention``."""
    scene = ChainScene()
    res = run_ramp(scene, fx_max, step, tol=tol, convention=convention)
    unit = eigenvalue_unit(scene, convention)
    counts = [len(complex_pairs(w)) for w in res.eigenvalues]

    def at(fx):
        return int(np.argmin(np.abs(res.fx - fx)))

    births = [e.fx for e in res.events if e.kind == "birth"]
    onset = min(births, key=lambda b: abs(b - float(PAPER_ONSET)))
    above = [k for k, f in enumerate(res.fx) if 0.082 + 1e-12 < f <= 0.090 + 1e-12]
    count = counts[above[0] - 1]
    unbroken = all(counts[k] > 0 for k in above)
    for e in res.events:      # a death and birth between two steps leaves no pair there
        if res.fx[above[0] - 1] < e.fx <= 0.090:
            count += 1 if e.kind == "birth" else -1
            unbroken = unbroken and count > 0
    im = [float(np.abs(res.eigenvalues[at(f)].imag).max()) * unit for f in WAVE_FX]
    return {"onset_pair_im": _tracked_im(res, onset, unit), "convention": convention,
            "events": [{"kind": e.kind, "fx": e.fx, "width": e.fx_hi - e.fx_lo,
                        "located": e.located} for e in res.events],
            "births": births, "onset_nearest_0082": onset,
            "probes": [counts[at(p)] for p in PROBES],
            "pairs_above_0082": bool(unbroken),
            "im_lambda": im}


def _tracked_im(res, birth_fx, unit):
    """Im lambda (paper units) at :data:`WAVE_FX` of the pair born at ``birth_fx``: from the
    birth's centre, step by step, the conjugate pair nearest the previous real part (NaN
    where it has died).  The paper's "imaginary part of the associated eigenvalue"."""
    event = next(e for e in res.events if e.kind == "birth" and e.fx == birth_fx)
    center, out = event.pair_center, {}
    for k in np.nonzero(res.fx > event.fx_hi - 1e-12)[0]:
        upper = res.eigenvalues[k][res.eigenvalues[k].imag > 0]
        near = upper[np.argmin(np.abs(upper.real - center))] if upper.size else None
        if near is None or abs(near.real - center) > event.radius:
            center = None
            break
        center = near.real
        out[round(float(res.fx[k]), 9)] = float(near.imag) * unit
    return [out.get(round(f, 9), math.nan) for f in WAVE_FX]


def transverse_numbers(convention):
    """The y band's frequency at wavelength 2 (Charan Fig. 6), paper units, at F_x = 0 and 0.083.

    At F_x = 0 the ten y modes are degenerate (neighbours just touch) and every
    wavelength has omega = sqrt(k_wall / m); under load the band disperses.  The
    frequency of wavelength 2 is the band's y-power weighted omega in that Fourier
    family (:meth:`fricstab.analysis.modes.TransverseBand.frequency`).
    """
    from fricstab.analysis.modes import transverse_band
    out = {}
    for fx in (0.0, 0.083):
        scene = ChainScene().with_fx(fx)
        band = transverse_band(scene, ramped_equilibrium(scene, fx), convention=convention)
        out[f"omega_{fx:g}"] = float(band.frequency(2.0))
        out[f"v2_{fx:g}"] = float(band.speed(2.0))
    return out


# ------------------------------------------------------------ dynamics

def wave_numbers(convention, n_real=25):
    """V1, V2 and breached fraction from R realizations with the convention's inertia."""
    base = convention_scene(ChainScene(), convention)
    rows = []
    for fx in WAVE_FX:
        scene = base.with_fx(fx)
        eq = ramped_equilibrium(base, fx)
        fit = fit_waves([run_realization(scene, eq, seed) for seed in range(n_real)])
        rows.append({"fx": fx, "v1": fit.v1, "v1_err": fit.v1_err, "v2": fit.v2,
                     "v2_err": fit.v2_err, "breached": fit.breached_fraction,
                     "v_com": fit.v_com})
    return {"convention": convention, "inertia": base.inertia, "realizations": n_real,
            "rows": rows}


# ------------------------------------------------------------ the table

def _ratio_row(name, waves, ims):
    """V1 / Im lambda at the three F_x, their mean and its error against the paper's 4.3."""
    ratio = [r["v1"] / im for r, im in zip(waves["rows"], ims)]
    if not all(math.isfinite(x) for x in ratio):
        return (name, "no V1" if any(not math.isfinite(r["v1"]) for r in waves["rows"])
                else "no pair", "not comparable", False)
    mean = float(np.mean(ratio))
    err = float(math.sqrt(sum((r["v1_err"] / im) ** 2 for r, im in
                              zip(waves["rows"], ims))) / len(ratio))
    dr = sigma(mean, err, *PAPER_RATIO)
    return (name, f"{mean:.2f} +- {err:.2f} (" + ", ".join(f"{x:.2f}" for x in ratio) + ")",
            f"{dr:.1f} sigma", _label([(mean, err, *PAPER_RATIO)]))


def _label(items):
    """A statistical comparison's word (claims.core.sigma_verdict at K): agrees, disagrees,
    or undecided where a new set of realizations would flip it with probability >= 1/4."""
    return sigma_verdict(items, K).label


def judge(spec, waves, transverse):
    """Each comparison of a reading with the paper: (name, ours text, distance text, agrees:
    a bool, or for a statistical one the word of :func:`_label`)."""
    out = []
    flags = [n > 0 for n in spec["probes"]]
    same = sum(f == p for f, p in zip(flags, PAPER_PAIRS))
    out.append(("pairs_at_probes", "/".join(map(str, spec["probes"])), f"{same}/6 as the paper",
                same == 6))
    d = sigma(spec["onset_nearest_0082"], 0.0, float(PAPER_ONSET), half_unit(PAPER_ONSET))
    out.append(("onset", f"{spec['onset_nearest_0082']:.6f}", f"{d:.1f} sigma", d <= K))
    out.append(("pairs_above_0082", "yes" if spec["pairs_above_0082"] else "no",
                "exact", spec["pairs_above_0082"]))
    ds = [sigma(o, 0.0, float(p), half_unit(p)) for o, p in zip(spec["im_lambda"], PAPER_IM)]
    out.append(("im_lambda", " / ".join(f"{x:.2e}" for x in spec["im_lambda"]),
                " / ".join(f"{x:.1f}" for x in ds) + " sigma", max(ds) <= K))
    ds = [sigma(o, 0.0, float(p), half_unit(p)) for o, p in zip(spec["onset_pair_im"], PAPER_IM)]
    out.append(("onset_im", " / ".join("absent" if not math.isfinite(x) else f"{x:.2e}"
                                       for x in spec["onset_pair_im"]),
                " / ".join(f"{x:.1f}" for x in ds) + " sigma", max(ds) <= K))
    v1 = [r["v1"] for r in waves["rows"]]
    dv = [sigma(r["v1"], r["v1_err"], *p) for r, p in zip(waves["rows"], PAPER_V1)]
    out.append(("v1", " / ".join("no breach" if not math.isfinite(x) else f"{x:.2e}" for x in v1),
                " / ".join(f"{x:.1f}" for x in dv) + " sigma",
                _label([(r["v1"], r["v1_err"], *p) for r, p in zip(waves["rows"], PAPER_V1)])
                if all(map(math.isfinite, v1)) else False))
    out.append(_ratio_row("ratio", waves, spec["im_lambda"]))
    out.append(_ratio_row("ratio_onset", waves, spec["onset_pair_im"]))
    v2s = [(r["v2"], r["v2_err"]) for r in waves["rows"] if math.isfinite(r["v2"])
           and r["v2_err"] > 0]
    if v2s:
        w = np.array([1 / e ** 2 for _, e in v2s])
        v2 = float((w * [v for v, _ in v2s]).sum() / w.sum())
        e2 = float(1 / math.sqrt(w.sum()))
        d2 = sigma(v2, e2, float(PAPER_V2), half_unit(PAPER_V2))
        out.append(("v2", f"{v2:.3f} +- {e2:.3f}", f"{d2:.1f} sigma",
                    _label([(v2, e2, float(PAPER_V2), half_unit(PAPER_V2))])))
    else:
        out.append(("v2", "no sliding", "not comparable", False))
    if transverse is not None:
        dw = sigma(transverse["omega_0"], 0.0, float(PAPER_OMEGA), half_unit(PAPER_OMEGA))
        out.append(("omega_2", f"{transverse['omega_0']:.5f}", f"{dw:.1f} sigma", dw <= K))
        dp = sigma(transverse["v2_0"], 0.0, float(PAPER_V2), half_unit(PAPER_V2))
        out.append(("v2_predicted", f"{transverse['v2_0']:.4f}", f"{dp:.1f} sigma", dp <= K))
        if v2s:
            dm = sigma(transverse["v2_0.083"], 0.0, v2, e2)
            out.append(("v2_loaded", f"{transverse['v2_0.083']:.4f} against {v2:.3f} +- {e2:.3f}",
                        f"{dm:.1f} sigma", dm <= K))
        else:
            out.append(("v2_loaded", f"{transverse['v2_0.083']:.4f}; no sliding",
                        "not comparable", False))
    return out


def run(n_real=25):
    """Every reading: write ``chain_conventions.md``; returns the values."""
    t0 = time.perf_counter()
    convs = sorted({c for pair in READINGS.values() for c in pair}, key=list(READINGS).index)
    spectra = {c: spectrum_numbers(c) for c in convs}
    transverse = {}
    for c in convs:
        try:
            transverse[c] = transverse_numbers(c)
        except ImportError:         # the band analysis is not there: the rows say so
            transverse[c] = None
    waves = {}
    for c in convs:
        waves[c] = wave_numbers(c, n_real)
        print(f"{c}: V1 " + ", ".join(f"{r['v1']:.2e}" for r in waves[c]["rows"]), flush=True)
    readings = {}
    for name, (sc, dc) in READINGS.items():
        rows = judge(spectra[sc], waves[dc], transverse[sc])
        readings[name] = {"spectrum": sc, "dynamics": dc,
                          "rows": [{"what": w, "ours": o, "distance": d,
                                    "agrees": a == "agrees" if isinstance(a, str) else bool(a),
                                    "undecided": a == "undecided"} for w, o, d, a in rows],
                          "compared": len(rows)}
        readings[name]["agreements"] = sum(r["agrees"] for r in readings[name]["rows"])
        readings[name]["undecided"] = sum(r["undecided"] for r in readings[name]["rows"])
    best = max(readings.values(), key=lambda r: r["agreements"])["agreements"]
    printed = paper_ratio_from_printed()
    values = {"realizations": n_real, "spectra": spectra, "waves": waves,
              "transverse": transverse, "readings": readings,
              "best": [k for k, r in readings.items() if r["agreements"] == best],
              "paper_ratio_from_printed": {"mean": printed[0], "std": printed[1],
                                           "ratios": printed[2]}}
    REPORT.write_text(report(values, time.perf_counter() - t0))
    return values


WHAT = {"pairs_at_probes": "pairs at F_x = 0.03 / 0.04 / 0.062 / 0.083 / 0.087 / 0.090 "
                           "(paper: yes, yes, no, yes, yes, yes)",
        "onset": "the pair birth nearest 0.082 (paper: 'unstable for all F_x > 0.082')",
        "pairs_above_0082": "pairs at every F_x in (0.082, 0.090] (paper: yes)",
        "im_lambda": "largest Im lambda at 0.083 / 0.087 / 0.090, paper units "
                     "(paper: 0.00024 / 0.00077 / 0.001)",
        "onset_im": "Im lambda of the pair born nearest 0.082, tracked, at 0.083 / 0.087 / "
                    "0.090 (the paper's 'associated eigenvalue': 0.00024 / 0.00077 / 0.001)",
        "ratio_onset": "V1 / Im lambda of that pair, mean of the three (paper: 4.3 +- 1.5)",
        "v1": "V1 at 0.083 / 0.087 / 0.090 (paper: 0.0014 +- 0.00013 / 0.0022 +- 0.00015 / "
              "0.0028 +- 8e-5)",
        "ratio": "V1 / Im lambda, mean of the three (paper: 4.3 +- 1.5)",
        "v2": "V2 measured, weighted mean of the three F_x (paper: ~0.075)",
        "omega_2": "omega of the y band at wavelength 2, F_x = 0 (paper: ~0.235, 'a wavelength "
                   "of approximately 2')",
        "v2_predicted": "its omega / pi, the predicted V2 (paper: ~0.075)",
        "v2_loaded": "the same prediction at F_x = 0.083 against our V2 measured (same reading)"}


def report(values, seconds):
    """The text of ``chain_conventions.md``."""
    names = list(values["readings"])
    lines = [
        "# Chain: Charan's numbers under each reading of the eigenvalues and the inertia",
        "",
        f"`python validation/chain_conventions.py --realizations {values['realizations']}` "
        f"({seconds:.0f} s, {platform.machine()}, Python {platform.python_version()}, "
        f"{time.strftime('%Y-%m-%d')}). Paper units: length 2R, time sqrt(m 2R / kn); a bare-J "
        "eigenvalue per unit mass. Readings (spectrum / dynamics inertia): "
        + "; ".join(f"`{k}`: {r['spectrum']} / {r['dynamics']}" for k, r in
                    values["readings"].items())
        + " (`fricstab chain ramp --convention NAME`; dynamics inertia: physical m R^2 / 2, "
        "lammps 2/5 m R^2, sm m R^2, bare m (2R)^2). Each cell: ours, then the distance to "
        f"the paper in combined standard errors (agree within {K:g}; a printed value without "
        "an error gets half a unit of its last digit).",
        "",
        "| comparison | " + " | ".join(names) + " |",
        "|---|" + "---|" * len(names),
    ]
    for i, row in enumerate(values["readings"][names[0]]["rows"]):
        cells = []
        for n in names:
            r = values["readings"][n]["rows"][i]
            cells.append(f"{r['ours']}; {r['distance']} ({row_word(r)})")
        lines.append(f"| {WHAT.get(row['what'], row['what'])} | " + " | ".join(cells) + " |")
    lines.append("| **agreements** | " + " | ".join(
        f"**{values['readings'][n]['agreements']} of {values['readings'][n]['compared']}**"
        + (f" ({values['readings'][n]['undecided']} undecided)"
           if values["readings"][n].get("undecided") else "")
        for n in names) + " |")
    p = values["paper_ratio_from_printed"]
    lines += [
        "",
        f"* Most agreements: {', '.join(values['best'])}.",
        "* The paper's own printed V1 and Im values give V1 / Im = "
        + ", ".join(f"{x:.2f}" for x in p["ratios"])
        + f", mean {p['mean']:.2f} +- {p['std']:.2f} (spread), not the printed 4.3 +- 1.5.",
        "* Pair events on each ramp (b: birth, d: death), F_x:",
    ]
    for c, s in values["spectra"].items():
        lines.append(f"  - {c}: " + ", ".join(f"{e['kind'][0]} {e['fx']:.6f}" for e in s["events"]))
    lines.append("* Breached fraction of the disks within 25,000 time units "
                 f"({values['realizations']} realizations), "
                 "per dynamics inertia, at 0.083 / 0.087 / 0.090: "
                 + "; ".join(f"{c} (I = {w['inertia']:g}): " + " / ".join(
                     f"{r['breached']:.2f}" for r in w["rows"])
                     for c, w in values["waves"].items()))
    return "\n".join(lines) + "\n"


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--realizations", type=int, default=25)
    ns = p.parse_args(argv)
    run(ns.realizations)
    print(REPORT.read_text(), end="")


if __name__ == "__main__":
    main()
