"""``fricstab packing dos`` (see :mod:`fricstab.cli.packing`): DOS and mode character per run.

Per run: friction switched on, the spectrum of J in Ishima's convention
(:func:`fricstab.analysis.rigidity.linear_response`, Eq. 21), the two
translations (smallest |lambda|) dropped, participation fractions
(Eqs. 49-50, E1), the DOS (Eq. 23, N = all particles) on log bins common
to every run, and the rotational band.
"""


import numpy as np

from fricstab.cli.packing_common import (MAKE_KEYS, UNITS_NOTE, dry_run, friction_record,
                                         law_runs, packing_source_checks, public, resolve,
                                         show_progress, summary)
from fricstab.cli.packing_source import open_run
from fricstab.laws import ParameterError

__all__ = ["conclude", "dos", "spectrum_of"]


def _spectrum(bb, run, route, f_tol):
    from fricstab.analysis.rigidity import linear_response
    from fricstab.scenes.packing_friction import frictional

    fr = frictional(bb, run.material, f_tol=f_tol)
    jac = linear_response(fr.system, fr.state).jacobian
    return spectrum_of(run, jac, route, friction_record(fr))


def spectrum_of(run, jac, route, friction, n_drop=2):
    """The spectrum of one run's J (Ishima's convention), ``n_drop`` translations dropped."""
    from fricstab.analysis import dos as dosmod
    sp = dosmod.spectrum(jac, route=route, vectors=True)
    w = sp.eigenvalues
    order = np.argsort(np.abs(w), kind="stable")
    dropped = np.sort(order[:n_drop])
    keep = np.sort(order[n_drop:])   # ascending real part, as spectrum() returns them
    psi_t, psi_r, p = dosmod.participation(sp.right[:, keep], run.dof)
    omega = np.sqrt(np.clip(w[keep].real, 0.0, None))
    scale = np.abs(w).max()
    return {"run": run, "kt": run.kt, "label": run.label(), "k": run.dof, "sp": sp,
            "eig": w[keep], "omega": omega, "psi_t": psi_t, "psi_r": psi_r, "p": p,
            "dropped": w[dropped], "negative": int(np.sum(w[keep].real < -1e-12 * scale)),
            "friction": friction}


#: Why an entry of a dos.json result is null (``<key>_note``).
NOT_DEFINED = {"kt": "not defined: the law has no kT/kN parameter (hertz, lee_hurley); NaN "
                     "in dos.npz 'kt'",
               "rotational_peak": "not defined: no rotation-dominated mode (psi_r > 0.5), "
                                  "e.g. a law without rotations",
               "rotational_median": "not defined: no rotation-dominated mode (psi_r > 0.5), "
                                    "e.g. a law without rotations"}


def _notes(entry):
    """``entry`` with a ``<key>_note`` for each of its keys that is null (NaN or undefined)."""
    for key, why in NOT_DEFINED.items():
        v = entry.get(key)
        if v is None or (isinstance(v, float) and not np.isfinite(v)):
            entry[f"{key}_note"] = why
    return entry


def _number(v, fmt):
    """``v`` formatted, or "not defined" for None / NaN (the table's word for a null)."""
    return "not defined" if v is None or not np.isfinite(v) else format(v, fmt)


def _entry(i, s, edges):
    sp = s["sp"]
    return {**s["run"].record(), "index": i, "route": sp.route, "seconds": sp.seconds,
            "modes": len(s["omega"]),
            "dropped_translations": [complex(v) if np.iscomplexobj(v) else float(v)
                                     for v in s["dropped"]],
            "negative_eigenvalues": s["negative"],
            "negative_threshold": "lambda < -1e-12 max|lambda|",
            "modes_outside_bins": int(np.sum((s["omega"] < edges[0])
                                             | (s["omega"] > edges[-1]))),
            "rotational_peak": s["peak"], "rotational_median": s["median"],
            "rotation_dominated_modes": int(np.sum(s["psi_r"] > 0.5)),
            "asymmetry": sp.asymmetry, "max_imag": sp.max_imag,
            "omega_min": float(s["omega"].min()) if s["omega"].size else None,
            "omega_max": float(s["omega"].max()) if s["omega"].size else None,
            "friction": s["friction"]}


def dos(ns, argv):
    """``fricstab packing dos``: dos.json, dos.npz, dos.png."""
    from fricstab import progress
    from fricstab.scenes.packing_friction import backbone

    params = resolve(ns, MAKE_KEYS + ("z_th", "route", "bins"))
    runs = law_runs(params, "dos")
    packing_source_checks(ns)
    opened = open_run(ns, params, "dos", ["dos.npz", "dos.png"],
                      {"kt": [r.kt for r in runs]})
    from fricstab.cli import budget
    estimate = budget.packing("packing dos", opened, params, len(runs), route=params["route"],
                              dry_run=ns.dry_run)
    if ns.dry_run:
        return dry_run(params, runs, estimate)
    source = opened.start(argv, show_progress(ns))
    rd, packing = opened.rd, source.packing
    bb = backbone(packing, z_th=params["z_th"])
    spectra = []
    with progress.bar(runs, desc="dos", unit="run", enabled=show_progress(ns)) as bar, \
            rd.stage("spectrum"):
        for run in bar:
            bar.set_postfix_str(run.name)
            spectra.append(_spectrum(bb, run, params["route"], params["f_tol"]))
    doc = {"packing": source.record(), **summary(packing, bb)}
    if source.origin != "read":
        doc["make"] = {k: params[k] for k in MAKE_KEYS}
    head = f"packing N = {packing.n} (backbone {bb.n}), phi = {packing.phi:g}, law"
    return conclude(rd, doc, spectra, runs, packing.n, params,
                    {**public(params), "kt": [r.kt for r in runs]}, packing.seed, argv, head)


def conclude(rd, doc, spectra, runs, n_total, params, parameters, seed, argv, head):
    """The DOS on common bins: dos.npz, dos.png, the record (``doc`` first), the table."""
    from fricstab.analysis import dos as dosmod
    from fricstab.figures.packing import dos_figure
    positive = np.concatenate([s["omega"][s["omega"] > 0] for s in spectra])
    if positive.size == 0:
        raise ParameterError("the backbone has no mode with omega > 0: no DOS to bin")
    edges = dosmod.log_bins(positive.min() * (1 - 1e-9), positive.max() * (1 + 1e-9),
                            params["bins"])
    kts = np.array([np.nan if r.kt is None else r.kt for r in runs])
    per_run, arrays = [], {"edges": edges, "kt": kts}
    for i, s in enumerate(spectra):
        d = dosmod.dos(s["omega"], n_total, edges)
        s["peak"], s["median"] = dosmod.rotational_peak(s["omega"], s["psi_r"])
        s["dos"] = d
        s["psi_t_mean"] = dosmod.binned_mean(s["omega"], s["psi_t"], edges)
        s["psi_r_mean"] = dosmod.binned_mean(s["omega"], s["psi_r"], edges)
        arrays.update({f"eigenvalues_{i}": s["eig"], f"omega_{i}": s["omega"],
                       f"psi_t_{i}": s["psi_t"], f"psi_r_{i}": s["psi_r"], f"p_{i}": s["p"],
                       f"dos_{i}": d, f"psi_t_mean_{i}": s["psi_t_mean"],
                       f"psi_r_mean_{i}": s["psi_r_mean"]})
        per_run.append(_notes(_entry(i, s, edges)))
    doc = {**doc,
           "normalization": "D(omega) = counts / (3 N width), N = all particles "
                            "(rattlers included); translations dropped",
           "kt_array": "dos.npz 'kt': kT/kN of each run, NaN for a law without kt",
           "edges": [float(edges[0]), float(edges[-1])], "results": per_run,
           "units": doc.get("units", UNITS_NOTE)}
    rd.write_npz("dos.npz", **arrays)
    rd.write_png("dos.png", lambda tmp: dos_figure(spectra, edges, tmp))
    rd.finish(doc, parameters=parameters, seed=seed, argv=argv)
    print(f"{head} {params['law']}; {params['bins']} log bins in omega [{edges[0]:.3g}, "
          f"{edges[-1]:.3g}]")
    for e in per_run:
        print(f"  {e['folder']:<12s} {e['route']:9s} {e['modes']:5d} modes, "
              f"{e['negative_eigenvalues']} negative, rotational peak "
              f"{_number(e['rotational_peak'], '.3g')} (median "
              f"{_number(e['rotational_median'], '.3g')}), "
              f"{e['seconds']:.2f} s")
    print(f"wrote {rd.path}/dos.json, dos.npz, dos.png")
    return 0
