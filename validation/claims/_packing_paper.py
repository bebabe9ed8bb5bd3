"""Claims of issue 35: Ishima's figures at the paper's scale (``validation/ishima_paper.py
--tier paper``), one job, ``hours`` (days on one core; resumable from its per-packing cache).

Each claim states the scale it reached (packings used per N and phi); its verdict is computed
from the values.  Regenerated on another CPU the seeded compressions may reach other
packings, so the check allows the sample spread: every mean root and every mean G within 3
combined standard errors of the recorded one.
"""

import math

from .core import Claim, Result, Verdict

JOB = "packing.ishima_paper"
COMMAND = ("python validation/ishima_paper.py --tier paper (N = 1,024 x 5 and 4,096 x 10 "
           "packings, phi = 0.83-0.90; resumable from the committed store validation/runs/ishima_paper/)")
G_KTS = (0.0, 1e-4, 1.0, 10.0)


JOB_1024 = "packing.ishima_paper_1024"
COMMAND_1024 = ("python validation/ishima_paper.py --tier paper1024 (N = 1,024 x 5 packings, "
                "phi = 0.83-0.90: the paper tier's N = 1,024 part; the same committed store)")


def _compute(tier, compute_missing=True):
    import sys
    from pathlib import Path
    here = Path(__file__).resolve().parents[1]
    sys.path.insert(0, str(here))
    import ishima_paper
    from fricstab.io.files import json_clean
    doc = ishima_paper.run(tier, out=here, compute_missing=compute_missing)
    out = tuple(f"validation/ishima_paper_{tier}{x}" for x in (".md", ".json", ".png"))
    return Result(json_clean(values_of(doc)), outputs=out, units=doc["units"])


def compute():
    """The paper tier (N = 1,024 and 4,096) as far as the committed store got: it computes
    nothing (days on one core, run over sittings by ``ishima_paper.py --tier paper``); every
    claim states the pieces done."""
    return _compute("paper", compute_missing=False)


def stored():
    """Every piece of the committed store now: the paper tier's inputs, so that a piece added
    makes its record stale (its numbers are no longer what the command gives) until it is
    regenerated."""
    from pathlib import Path
    root = Path(__file__).resolve().parents[2]
    return tuple(sorted(p.relative_to(root).as_posix() for p in
                        (root / "validation" / "runs" / "ishima_paper").glob("n*_phi*_s*_*.npz")))


def compute_1024():
    """Its N = 1,024 part (Figs. 4, 6 at the paper's N; the others at N = 1,024)."""
    return _compute("paper1024")


def values_of(doc):
    """The record's values from a report document (:func:`ishima_paper.analyse`)."""
    kts = doc["rig_kts"]
    return {
        "pieces": [doc["pieces_done"], doc["pieces_total"]], "sizes": doc["sizes"],
        "ensemble": {k: {"used": c["used"], "samples": c["samples"],
                         "excluded": [e["reason"] for e in c["excluded"]]}
                     for k, c in doc["ensemble"]["summary"].items()},
        "g": {phi: {f"{kt:g}": t["g"][kts.index(kt)] for kt in G_KTS}
              for phi, t in doc["fig4"].items()},
        "routes": {phi: {"modes": t["modes_vs_solve"], "step": t["step_vs_solve"],
                         "step_over_model": t["step_over_model"]}
                   for phi, t in doc["fig4"].items()},
        "sign_change": doc["sign_change"], "sign_figure": doc["sign_figure"],
        "linear": doc["linear"],
        "factorisation": doc["factorisation"], "limit": doc["limit"],
        "limit_readings": doc["limit_readings"],
        "bands": {k: {key: {f: r[f] for f in ("phi", "kt", "band", "dos_band", "classes",
                                              "paper", "samples")}
                      for key, r in b.items()} for k, b in doc["bands"].items()},
        "fig7_b2": doc["fig7_b2"], "fig10": doc["fig10"], "fig14": doc["fig14"],
        "fig16": {k: v for k, v in doc["fig16"].items() if k != "points"},
    }


def _scale(v):
    done, total = v["pieces"]
    used = sum(c["used"] for c in v["ensemble"].values())
    return (f"{done} of {total} pieces, {used} packings used (N = {v['sizes']['fig4']}: "
            f"Figs. 4, 6; N = {v['sizes']['dos']}: Figs. 5, 7-10, 14, 16)")


def _m(m, fmt=".3g"):
    return "-" if m.get("mean") is None else f"{format(m['mean'], fmt)} +- {m['sd']:.1g}"


def _check(old, new):
    from .core import judged_afresh
    grown = judged_afresh(old["pieces"], new["pieces"],
                          f"{old['pieces'][0]} -> {new['pieces'][0]} pieces")
    if grown:
        return grown
    for key, field in (("sign_change", None), ("g", "g")):
        for phi, a in old[key].items():
            pairs = [(a, new[key].get(phi, {}))] if field is None else \
                [(a[k], new[key].get(phi, {}).get(k, {})) for k in a]
            for x, y in pairs:
                if x.get("mean") is None or y.get("mean") is None:
                    if x.get("mean") != y.get("mean"):
                        return False, f"{key} phi = {phi}: defined in one run only"
                    continue
                s = math.hypot(x["se"], y["se"])
                if abs(x["mean"] - y["mean"]) > 3 * s + 1e-12:
                    return False, f"{key} phi = {phi}: {x['mean']:.4g} -> {y['mean']:.4g}"
    return True, "every mean root and mean G within 3 combined s.e."


TOL = ("every mean root of G_NA and mean G within 3 combined standard errors (another CPU "
       "may reach other packings: seeded FIRE is chaotic); the test labels follow")


def _sign_show(v):
    return "; ".join(f"phi = {phi}: {_m(r)} ({r['count']})" for phi, r in
                     v["sign_change"].items()) + f"; {_scale(v)}"


def _sign_verdict(v):
    rows = v["sign_change"]
    bad = [phi for phi, r in rows.items() if r["label"] == "disagrees"]
    na = [phi for phi, r in rows.items() if r["label"] == "not comparable"]
    if len(na) == len(rows):
        return Verdict("not comparable", "no phi with two roots")
    d = ", ".join(f"{phi}: {r['distance']:.1f}" for phi, r in rows.items()
                  if r["distance"] is not None)
    return Verdict("disagrees" if bad else "agrees",
                   f"distance of the mean root from 2.0 in combined s.e. ({d}); agree if every "
                   "phi <= 2" + (f"; not comparable at {', '.join(na)}" if na else ""))


def _figure_show(v):
    f = v["sign_figure"]
    rows = f["rows"]
    if not rows:
        return "no G_NA computed"
    opposite = sorted({k for r in rows.values() for k, x in r["signs"].items()
                       if x == "opposite"}, key=float)
    return ("G_NA(2.0) / range: " + ", ".join(
        f"{phi} {'-' if r['at_2_over_range'] is None else format(r['at_2_over_range'], '.1%')}"
        for phi, r in rows.items()) + f" (range {f['range']:.3g}); signs at kT/kN != 2 "
        + ("as the paper at every phi" if not opposite else
           f"opposite at kT/kN = {', '.join(opposite)}") + f"; {_scale(v)}")


def _figure_verdict(v):
    rows = v["sign_figure"]["rows"]
    made = {phi: r for phi, r in rows.items() if r["label"] != "not comparable"}
    if not made:
        return Verdict("not comparable", "no phi with two packings")
    worst = max(r["at_2_over_range"] for r in made.values())
    bad = [phi for phi, r in made.items() if r["label"] == "disagrees"]
    return Verdict("disagrees" if bad else "agrees",
                   f"largest |G_NA(2.0)| {worst:.1%} of the figure's range; agree if every phi "
                   f"<= {v['sign_figure']['tol']:.0%} (half a plotted marker) with no sign opposite "
                   "the paper's beyond 2 s.e." + (f"; disagrees at phi = {', '.join(bad)}"
                                                   if bad else ""))


def _g_show(v):
    return "; ".join(f"phi = {phi}: " + " / ".join(_m(g[f"{k:g}"]) for k in G_KTS)
                     for phi, g in v["g"].items()) + " (kT/kN = 0 / 1e-4 / 1 / 10)"


def _routes_verdict(v):
    worst = max(max(r["modes"] or 0.0, r["step"] or 0.0) for r in v["routes"].values())
    return Verdict("agrees" if worst <= 1e-2 else "disagrees",
                   f"largest |mode sum or step strain / solve - 1| {worst:.1e}; agree if "
                   "<= 1e-2 (the paper's 'quantitative agreement')")


def _limit_show(v):
    return "; ".join(f"phi = {phi}: {_m(r['0.0001'], '+.2g')} ({r['0.0001']['count']})"
                     for phi, r in v["limit"].items()) + f"; {_scale(v)}"


def _limit_verdict(reading, what):
    """Fig. 5 under one reading of 'only little' (:func:`ishima_paper.limit_readings`)."""
    def verdict(v):
        x = v["limit_readings"]["readings"][reading]
        bound = "-" if x["bound"] is None else f"{x['bound']:.1%}"
        per = ", ".join(f"{phi}: {said}" for phi, said in x["rows"].items())
        return Verdict(x["label"], f"per phi ({per}); at a phi, agree if |mean| + 2 s.e. <= "
                       f"{bound} ({what}), disagree if |mean| - 2 s.e. > it; one packing "
                       "unresolved; agree if every phi agrees")
    return verdict


def _test_show(key, cell):
    """The cells of a per-kT/kN test (``v[key]``), '-' where it could not be made."""
    return lambda v: "; ".join(f"kT/kN = {r['kt']:g}: " + ("-" if r["p"] is None else cell(r))
                               for r in v[key])


def _test_verdict(key, short, test, claim):
    """The paper's statement holds when the test at the largest kT/kN rejects (p < 0.05);
    of several sizes, the largest that could be tested."""
    def verdict(v):
        made = [r for r in v[key] if r["p"] is not None]
        r = made[-1] if made else v[key][-1]
        if r["p"] is None:
            return Verdict("not comparable", short)
        return Verdict("agrees" if r["p"] < 0.05 else "disagrees",
                       f"{test} at kT/kN = {r['kt']:g}: p {r['p']:.2g}; the paper's "
                       f"'{claim}' agrees if p < 0.05")
    return verdict


_fact_show = _test_show("factorisation", lambda r: f"N = {r['n']}: G/G_0 " + ", ".join(
    f"{x:.3g}" for x in r["ratios"]) + f" (Kruskal-Wallis p {r['p']:.2g})")
_fact_verdict = _test_verdict("factorisation", "fewer than 2 phi with 2 packings",
                              "Kruskal-Wallis test of G/G_0 across phi", "not factorised")
_linear_show = _test_show("linear", lambda r: f"chi^2/dof {r['chi2']:.2f}/{r['dof']} "
                          f"(p {r['p']:.2g})")
_linear_verdict = _test_verdict("linear", "fewer than 3 phi", "a straight line in phi",
                                "not proportional to phi - phi_c")


def _bands_show(v):
    out = []
    for key, name in (("backbone_fig", f"N = {v['sizes']['dos']}, phi = 0.90"),
                      ("rattlers_fig", f"N = {v['sizes']['dos']} with rattlers"),
                      ("backbone", f"N = {v['sizes']['fig4']}"),
                      ("rattlers", f"N = {v['sizes']['fig4']} with rattlers")):
        rows = v["bands"].get(key, {}).values()
        out.append(f"{name}: " + ", ".join(f"{r['phi']:g}/{r['kt']:g} {r['dos_band']}"
                                           + ("" if r["band"] == r["dos_band"]
                                              else f" (strict: {r['band']})")
                                           for r in rows))
    b2 = v["fig7_b2"]
    return "; ".join(out) + (f"; Fig. 7 b2: {b2.get('coupled', 0)} of {b2.get('near', 0)} modes "
                             f"near omega t0 = 1.3e-2 coupled; {_scale(v)}")


def _bands_verdict(v):
    """The paper's classes against the DOS read as a figure at its N and phi = 0.90, backbone
    and with rattlers (either reading may carry the paper's figure)."""
    out = {}
    for key in ("backbone_fig", "rattlers_fig"):
        rows = [r for r in v["bands"].get(key, {}).values() if r["paper"]]
        if rows:
            out[key] = sorted({f"{r['kt']:g}" for r in rows if r["dos_band"] != r["paper"]},
                              key=float)
    if not out:
        return Verdict("not comparable", "no spectrum at phi = 0.90")
    ok = [k for k, bad in out.items() if not bad]
    words = "; ".join(f"{'backbone' if k == 'backbone_fig' else 'with rattlers'}: "
                      + (f"differs at kT/kN = {', '.join(bad)}" if bad else "as the paper")
                      for k, bad in out.items())
    return Verdict("agrees" if ok else "disagrees",
                   words + "; rule: separated when an empty bin (10 per decade) lies between "
                   "the rotational peak and the translational median, merged when the N' "
                   "lowest modes have mean psi^R <= 1/2; agree if one reading matches every "
                   "kT/kN")


def _fig10_show(v):
    rows = v["fig10"]["rows"]
    nz = v["fig10"]["noise"]
    return "; ".join(f"{kt}: peak {_m(r['peak'])}, median {_m(r['median'])}"
                     + (f", collapse {r['collapse']:.3f}" if "collapse" in r else "")
                     for kt, r in rows.items()) + (f"; noise {nz:.3f}" if nz else "") \
        + f"; {_scale(v)}"


def _fig10_verdict(v):
    rows = v["fig10"]["rows"]
    pk = [r["peak"]["mean"] for kt, r in rows.items() if float(kt) <= 1e-4]
    if not pk:
        return Verdict("not comparable", "no rotational band computed")
    far = max(abs(math.log10(x)) for x in pk)
    return Verdict("agrees" if far <= math.log10(2) else "disagrees",
                   f"peak / sqrt(kT/kN) a factor {10 ** far:.2g} from 1; agree if within a "
                   "factor 2 (the paper's 'around')")


def _fig14_show(v):
    return "; ".join(f"kT/kN = {kt}: {r['rattlers']} rattlers in {r['samples']} packings, "
                     f"{r['zero_modes']} zero modes beyond the translations, "
                     f"{r['modes']} modes on rattlers, median p N "
                     f"{r['pN_median'] if r['pN_median'] is None else format(r['pN_median'], '.3g')}"
                     for kt, r in v["fig14"].items()) + f"; {_scale(v)}"


def _fig14_verdict(v):
    p = [r["pN_median"] for r in v["fig14"].values() if r["pN_median"] is not None]
    if not p:
        free = all(r["zero_modes"] == 3 * r["rattlers"] for r in v["fig14"].values())
        return Verdict("not comparable", "no mode carried by rattlers" + (
            ": every rattler is free (no contact; zero modes beyond the translations = 3 x "
            "the rattlers), so its three modes are exact zeros" if free else ""))
    return Verdict("agrees" if max(p) <= 3 else "disagrees",
                   f"largest median p N {max(p):.3g}; agree if <= 3 (a mode on at most ~3 "
                   "disks; the paper's p ~ 1/N)")


def _fig16_show(v):
    f = v["fig16"]
    if "rot_peak" not in f:
        return f"{f['why']}; {_scale(v)}"
    return (f"rotational peak vs phi: rho {f['rot_peak']['rho']:+.2f} (p {f['rot_peak']['p']:.2g}); "
            f"translational low end: rho {f['trans_low']['rho']:+.2f} "
            f"(p {f['trans_low']['p']:.2g}); {_scale(v)}")


def _fig16_verdict(v):
    f = v["fig16"]
    return Verdict(f["label"], "Spearman rho > 0 with one-sided p < 0.05 for both" if
                   "rot_peak" in f else f.get("why", ""))


def claims():
    store = stored()
    command = COMMAND[:-1] + "; the record reports the store as far as it got: --report-only)"

    def c(short, title, paper, show, verdict, n1024=False):
        said = lambda v: (lambda x: f"**{x.label}** ({x.detail})")(verdict(v))  # noqa: E731
        return Claim(f"packing.paper_{short}", "packing", title, "hours",
                     COMMAND_1024 if n1024 else command, compute_1024 if n1024 else compute,
                     show, TOL, _check, paper=paper, verdict=verdict,
                     job=JOB_1024 if n1024 else JOB, texts={"verdict": said},
                     inputs=() if n1024 else store)
    fig16 = ("\"the rotational band shifts to a lower frequency region and the plateau of the "
             "translational band becomes longer as the density approaches the jamming point\"")
    little = "\"G depends on k_T/k_N only little for k_T/k_N <= 1.0 x 10^-4\""
    bands = ("gap for 1e-10 <= kT/kN <= 1e-8, partial overlap for 1e-6..1e-2, merged for >= "
             "1; a coupled mode at kT/kN = 1e-4, omega t0 = 1.3e-2")
    return [
        c("sign_change", "Fig. 6 at the paper's scale: kT/kN where G_NA changes sign, per phi "
          "(N = 1,024, 5 packings per phi)", "\"G_NA is positive for k_T/k_N > 2.0, G_NA ~= 0 "
          "at k_T/k_N = 2.0, and G_NA is negative for k_T/k_N < 2.0\"", _sign_show,
          _sign_verdict, n1024=True),
        c("sign_figure", "Fig. 6 read as the figure shows it: the sign of G_NA at each "
          "kT/kN of the grid and G_NA(2.0) against the figure's range, per phi (N = 1,024, 5 "
          "packings per phi)", "\"G_NA is positive for k_T/k_N > 2.0, G_NA ~= 0 at k_T/k_N "
          "= 2.0, and G_NA is negative for k_T/k_N < 2.0\" (read off Fig. 6: G_NA against "
          "phi at fixed k_T/k_N)", _figure_show, _figure_verdict, n1024=True),
        c("g_phi", "Fig. 4 at the paper's scale: G against phi, and mode sum / step strain "
          "against the solve (N = 1,024)", "\"quantitative agreement between the theoretical "
          "and numerical values\" (Fig. 4)", _g_show, _routes_verdict, n1024=True),
        c("g_little", "Fig. 5 at the paper's scale: G(1e-4)/G(0) - 1 per phi (N = 4,096), "
          "read strictly", little, _limit_show,
          _limit_verdict("strict", "strict: a change of 1 %")),
        c("g_little_figure", "Fig. 5 read as the figure shows it: G(1e-4)/G(0) - 1 per phi "
          "against half a plotted marker on the figure's logarithmic G axis (N = 4,096)",
          little + " (see Fig. 5: G against k_T/k_N on logarithmic axes)", _limit_show,
          _limit_verdict("figure", "half a plotted marker: 2 % of the G axis's decades")),
        c("factorisation", "Footnote 2: G(phi, kT) = G_0(phi) G(kT)? Kruskal-Wallis test of "
          "G/G_0 across phi (N = 1,024; the paper names no N)", "\"the factorization "
          "G(phi, kT/kN) = G_0(phi) G(kT/kN) is not held\"", _fact_show, _fact_verdict,
          n1024=True),
        c("not_linear", "G against phi at large kT/kN: a straight line through the per-phi "
          "means (N = 1,024)", "\"G is not proportional to phi - phi_c for a large kT/kN\"",
          _linear_show, _linear_verdict, n1024=True),
        c("bands", "Figs. 7-9 at the paper's scale: the rotational and translational bands per "
          "kT/kN and phi, backbone and with rattlers; the coupled mode of Fig. 7 b2",
          bands, _bands_show, _bands_verdict),
        c("rot_prefactor", "Fig. 10 at the paper's scale: the rotational peak over "
          "sqrt(kT/kN) and the collapse of omega_R D (N = 4,096, phi = 0.90)",
          "\"a peak of D(omega) around omega t0 ~= (k_T/k_N)^(1/2)\"; omega_R D universal",
          _fig10_show, _fig10_verdict),
        c("rattlers", "Fig. 14 at the paper's scale: participation ratio of the modes carried "
          "by rattlers (N = 4,096, phi = 0.90)", "p ~ 1/N for the rattler modes",
          _fig14_show, _fig14_verdict),
        c("dos_phi", "Fig. 16 at the paper's scale: the rotational band and the translational "
          "plateau against phi (N = 4,096, kT/kN = 1e-8)", fig16, _fig16_show, _fig16_verdict),
        c("bands_n1024", "Figs. 7-9 at N = 1,024 (the paper's figures: N = 4,096): the bands "
          "per kT/kN and phi, backbone and with rattlers", bands, _bands_show, _bands_verdict,
          n1024=True),
        c("rot_prefactor_n1024", "Fig. 10 at N = 1,024 (the paper's: N = 4,096): the "
          "rotational peak over sqrt(kT/kN), phi = 0.90", "\"a peak of D(omega) around "
          "omega t0 ~= (k_T/k_N)^(1/2)\"", _fig10_show, _fig10_verdict, n1024=True),
        c("dos_phi_n1024", "Fig. 16 at N = 1,024 (the paper's: N = 4,096): the rotational band "
          "and the translational plateau against phi, kT/kN = 1e-8", fig16, _fig16_show,
          _fig16_verdict, n1024=True),
    ]
