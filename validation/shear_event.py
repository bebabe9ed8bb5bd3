"""Lee & Hurley's statements about the largest slip (Sec. 3.2, Figs. 3-8) judged on one run.

    fricstab shear run --out RUN [...]
    fricstab shear analyze --out RUN           # or --partial DIR2 while the run goes on
    python validation/shear_event.py RUN [--analysis DIR2] [--event K]

Reads the run's frames and its analysis (``analysis.json``, ``analysis.npz`` in RUN, or
in DIR2) and writes ``RUN/event.md`` and ``RUN/event.json``: per statement the paper's
words, our numbers, the rule and the verdict (agrees / disagrees / not comparable, and
why; :func:`fricstab.analysis.shear_event.judge_event`), and ``RUN/event.png``: per output
step across the window, tau, the GR cluster count, gD2min and g_t10%D2min, the Spearman
rho of Fig. 8a and the GR contact angles, with the stages shaded.  ``--event K`` judges
phase K of ``analysis.npz["phases"]`` (a slip) instead of the largest slip.
"""

import argparse
import json
import sys
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))  # run from anywhere without installing

from fricstab.analysis.shear_event import step_spans  # noqa: E402
from fricstab.errors import ParameterError  # noqa: E402


def _cell(text):
    return str(text).replace("|", "\\|").replace("\n", " ")


def markdown(doc):
    """The page: the event, then one row per statement."""
    w, p = doc["event"], doc["parameters"]
    strain = w["strain"] and f"{100 * w['strain'][0]:.5f}-{100 * w['strain'][1]:.5f} %"
    st = w["stage_steps"]

    lines = [
        "# The largest slip against Lee & Hurley Figs. 3-8 (Sec. 3.2)", "",
        f"Run `{doc['run']}`, analysis `{doc['analysis']}`. Command: `{doc['command']}`.", "",
        "| event | value |", "|---|---|",
        f"| phase (index in analysis.npz phases) | {w['event']} of {w['n_phases']}"
        f"{'' if doc.get('event_given') else ' (the largest slip)'} |",
        f"| Stage II: slip steps (tau decreasing) | {w['first']}-{w['last']} (t_p = {w['t_p']}"
        f" output steps), strain {strain}"
        f"{'; it reaches the last frame analysed and may go on' if w['at_end'] else ''} |",
        f"| Delta tau_p | {w['dtau_p']:+.4g} |",
        f"| Stage I / Stage III steps | {step_spans(st['I'])} / {step_spans(st['III'])} "
        f"(pad {w['pad']}) |",
        f"| onset of Stage II (the paper's Steps 4-5) | {step_spans(w['onset'])} |",
        f"| Stage II steps with a single GR cluster; their first run | "
        f"{step_spans(w['single_steps'])}; {step_spans(w['single_run'])} |",
        f"| r_p; D2min and DBSCAN radius; GR fraction | {p['r_p']:.4g} m; {p['radius_factor']:g}"
        f" r_p; {p['fraction']:g} |", "",
        "A statement of several parts agrees when all hold, disagrees when one fails, and is "
        "not comparable when none fails but one cannot be evaluated.", "",
        "| # | Fig. | the paper | ours | rule | verdict |", "|---|---|---|---|---|---|"]
    for s in doc["statements"]:
        lines.append(f"| {s['id']} | {s['figure']} | \"{_cell(s['paper'])}\" | "
                     f"{_cell(s['ours'])} | {_cell(s['rule'])} | **{s['verdict']}**: "
                     f"{_cell(s['why'])} |")
    lines += ["", "![per step across the window](event.png)"]
    return "\n".join(lines) + "\n"


def figure(doc, path):
    """Per output step across the window: tau, GR clusters, D2min, rho, angles; stages shaded."""
    from fricstab.figures.common import finish, pyplot, si_scale
    plt = pyplot()
    s, w = doc["series"], doc["event"]
    k = np.array(s["step"])

    def arr(name):
        return np.array([np.nan if v is None else v for v in s[name]], float)
    g, g10 = arr("g"), arr("g10")
    scale, unit = si_scale(np.concatenate([g, g10]), "m", 2)
    fig, ax = plt.subplots(5, 1, figsize=(7, 10), sharex=True)
    ax[0].plot(k, arr("tau"), "o-", ms=3, color="k")
    ax[0].set_ylabel(r"$\tau = S/N$ [-]")
    ax[1].plot(k, arr("n_clusters"), "o-", ms=3, color="C2")
    ax[1].set_ylabel("GR clusters [-]")
    ax[2].semilogy(k, g * scale, "o-", ms=3, color="C0", label=r"$gD^2_{min}$")
    ax[2].semilogy(k, g10 * scale, "s-", ms=3, color="C1", label=r"$g_{t10\%}D^2_{min}$")
    ax[2].set_ylabel(f"$D^2_{{min}}$ [{unit}]")
    ax[2].legend(fontsize=7)
    ax[3].plot(k, arr("rho_sigma_d2"), "o-", ms=3, color="C0")
    ax[3].axhline(0.4, color="0.5", lw=0.6, ls=":")
    ax[3].set_ylabel(r"$\rho(|\Delta\sigma_p|, D^2_{min})$ [-]")
    ax[4].plot(k, arr("angle_mean"), "o-", ms=3, color="C3", label=r"mean $|\theta|$")
    ax[4].plot(k, arr("angle_median"), "s--", ms=3, color="C4", label=r"median $|\theta|$")
    ax[4].set(ylabel=r"GR $|\theta|$ [rad]", xlabel="output step $k$ [-]")
    ax[4].legend(fontsize=7)
    one = np.isin(k, w["single_steps"])
    ax[1].plot(k[one], arr("n_clusters")[one], "o", ms=8, mfc="none", color="C3",
               label="one cluster in Stage II")
    ax[1].legend(fontsize=7)
    for a in ax:
        a.axvspan(w["first"] - 0.5, w["last"] + 0.5, color="C3", alpha=0.15, lw=0)
    for name, steps in w["stage_steps"].items():
        if steps:
            ax[0].text(np.mean(steps), 1.02, f"Stage {name}", transform=ax[0].get_xaxis_transform(),
                       ha="center", fontsize=8)
    ax[0].set_title(f"slip phase {w['event']}, Stage II shaded (cf. Lee & Hurley Figs. 2b, 8)",
                    fontsize=8, pad=14)
    fig.tight_layout()
    return finish(fig, path, dpi=120)


def report(run, an_dir=None, event=None, pad=10, onset=2, n_perm=2000, frames=None):
    """Judge the event of the run in ``run`` (analysis in ``an_dir``); write the three files.
    ``frames``: the run's frames where ``run`` holds none (a segmented run,
    ``shear_rolling.event_frames``)."""
    from fricstab.analysis.shear_event import judge_event
    from fricstab.cli.shear_analyze import frames_of
    run = Path(run)
    an_dir = Path(an_dir or run)
    try:
        rec = json.loads((an_dir / "analysis.json").read_text())
        with np.load(an_dir / "analysis.npz") as z:
            arrays = {k: z[k] for k in z.files}
    except (OSError, ValueError) as exc:
        raise ParameterError(f"{an_dir}: no readable analysis ({exc}); run `fricstab shear "
                             f"analyze --out {run}` first") from None
    s = rec.get("summary", {})
    complete = (run / "shear.json").exists()
    if complete:
        made = json.loads((run / "shear.json").read_text()).get("fingerprint", {}).get("sha256")
        of = rec.get("parameters", {}).get("run")
        if made and of and made != of:
            raise ParameterError(f"the analysis in {an_dir} is of another run than {run}")
    if frames is None:
        frames = frames_of(run, partial=not complete)
    factor = s["radius_cut"] / s["r_p"] if s.get("radius_cut") and s.get("r_p") else 5.0
    doc = judge_event(frames, arrays, event, pad=pad, onset=onset, n_perm=n_perm,
                      radius_factor=factor, fraction=s.get("fraction", 0.01))
    cmd = " ".join(["python validation/shear_event.py", str(run)]
                   + ([f"--analysis {an_dir}"] if an_dir != run else [])
                   + ([f"--event {event}"] if event is not None else [])
                   + [f"--{k} {v}" for k, v, d in (("pad", pad, 10), ("onset", onset, 2),
                                                   ("n-perm", n_perm, 2000)) if v != d])
    doc.update(run=str(run), analysis=str(an_dir), event_given=event is not None, command=cmd)
    (run / "event.md").write_text(markdown(doc))
    (run / "event.json").write_text(json.dumps(doc, indent=1))
    figure(doc, run / "event.png")
    return doc


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("run", type=Path, help="a `fricstab shear run` folder")
    ap.add_argument("--analysis", type=Path, default=None,
                    help="the analysis folder (default: RUN; a --partial DIR2)")
    ap.add_argument("--event", type=int, default=None,
                    help="phase index (analysis.npz phases) of the slip to judge (default: "
                         "the largest slip)")
    ap.add_argument("--pad", type=int, default=10, help="steps of Stages I and III (10)")
    ap.add_argument("--onset", type=int, default=2, help="steps of the onset of Stage II (2)")
    ap.add_argument("--n-perm", type=int, default=2000, help="random draws of statement 3")
    a = ap.parse_args(argv)
    try:
        doc = report(a.run, a.analysis, a.event, a.pad, a.onset, a.n_perm)
    except ParameterError as exc:
        print(f"shear_event: error: {exc}", file=sys.stderr)
        return 2
    for st in doc["statements"]:
        print(f"{st['id']:>3} ({st['figure']}): {st['verdict']}: {st['why']}")
    print(f"wrote {a.run / 'event.md'}, event.json, event.png")
    return 0


if __name__ == "__main__":
    sys.exit(main())
