"""``fricstab shear analyze|export``: analyses, slip spectra and OVITO export of a shear run.

``fricstab shear analyze --out DIR [--gamma0 G|steady] [--force] [--no-spectra] [--spectra R] [--partial DIR2] [--reuse DIR3]``
    D2min, GR regions, phases and Spearman tables of the frames in DIR
    (:func:`fricstab.analysis.shear.analyze`), then the spectrum of the
    Jacobian before each slip (:func:`fricstab.analysis.shear_slips.slip_spectra`)
    with the law and parameters the run recorded in ``shear.json`` (so no
    ``--law`` here: the histories of the frames belong to that law): by
    default its soft end (the k softest eigenvalues, shift-invert ARPACK;
    ``--spectra-k K``), ``--spectra dense`` the whole spectrum.  Writes ``analysis.json`` (its
    ``slip_spectra`` says which route and what the statistics run over),
    ``analysis.npz``, ``analysis.md`` and figures.  The frames are read a
    chunk at a time (:class:`fricstab.io.frame_store.FrameStore`), so a run
    larger than memory analyses in a few hundred MB.  ``--partial DIR2``
    analyses what an interrupted or still running run has written so far
    into DIR2, with the parameters its frames record; the record names the
    frames and strain it covers.  ``--reuse DIR3`` takes the per-step
    analyses and slip spectra of an earlier analysis of the run's first
    frames (a ``--partial`` one) and computes only the frames after them:
    the same result to the bit, checked by its strain and tau series.
    ``--gamma0 steady`` starts the window where tau is steady: the earliest
    strain from the run's gamma0 on from which the Mann-Kendall test on 20
    block means of tau does not reject at 0.05
    (:func:`fricstab.analysis.stationarity.steady_window`); where none does,
    the run's gamma0 with a warning to extend the run.  The test and the start
    are kept in ``analysis.json`` (``parameters.steady``).
``fricstab shear export --out DIR [--format extxyz|lammps] [--every K] [--force]``
    The frames for OVITO (:func:`fricstab.io.export.frames_to_ovito`).
"""

import math
import sys
from pathlib import Path

import numpy as np

from fricstab.errors import ParameterError

__all__ = ["add_analyze_parsers", "analyze", "export", "frames_of"]


def frames_of(out, partial=False):
    """The frames of a run directory, read a chunk at a time (:class:`fricstab.io.frame_store.FrameStore`).

    A complete run's record is checked first (:func:`fricstab.io.rundir.verify`):
    a missing, damaged or foreign frame chunk, or an interrupted run, is
    refused with one line naming it; the chunks read are those the record
    lists.  ``partial``: the chunks an interrupted (or still running) run has
    written so far, which must be ``chunk_000000`` onwards with no gap (each
    is written whole, by rename, so a running run adds chunks but never
    leaves half of one).
    """
    from fricstab.io import rundir
    from fricstab.io.frame_store import FrameStore
    out = Path(out).expanduser()
    if partial:
        if (out / "shear.json").exists():
            raise ParameterError(f"--partial: the run in {out} is complete; analyse it "
                                 "without --partial")
        files = sorted((out / "frames").glob("chunk_*.npz"))
        gap = [f.name for i, f in enumerate(files) if f.name != f"chunk_{i:06d}.npz"]
        if gap:
            raise ParameterError(f"--partial: {out}/frames has a gap before {gap[0]}")
    else:
        record = rundir.verify(out, "shear")
        listed = record.get("files")
        if isinstance(listed, dict):
            files = [out / rel for rel in sorted(listed) if rel.startswith("frames/")]
        else:   # a record from before manifests: the chunks on disk
            files = sorted((out / "frames").glob("chunk_*.npz"))
    if not files:
        raise ParameterError(f"--out: no frames in {out}/frames (run `fricstab shear run`)")
    return FrameStore(files)


#: Largest integer option (beyond it no frame or mode count exists).
MAX_INT = 2 ** 62


def _strain(text):
    """A strain of --gamma0: finite, 0 or in [1e-30, 10] (the shear scene's gamma0 range)."""
    import argparse
    import math
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"must be a number, got {text!r}") from None
    if not (math.isfinite(value) and (value == 0 or 1e-30 <= value <= 10.0)):
        raise argparse.ArgumentTypeError(f"must be 0 or a strain in [1e-30, 10] (a smaller "
                                         f"one is sub-normal), got {text!r}")
    return value


def _gamma0(text):
    """--gamma0: a strain (:func:`_strain`) or ``steady`` (the steady start)."""
    import argparse
    if text.strip().lower() == "steady":
        return "steady"
    try:
        return _strain(text)
    except argparse.ArgumentTypeError as exc:
        raise argparse.ArgumentTypeError(f"{exc}, or 'steady' (the start of the steady "
                                         "window)") from None


def add_analyze_parsers(s):
    """``analyze`` and ``export`` on the shear subparsers ``s``."""
    from fricstab.cli import _int_at_least
    a = s.add_parser("analyze", help="D2min, GR regions, phases, Spearman tables of a run")
    a.add_argument("--out", type=Path, required=True, metavar="DIR", help="a `shear run` DIR")
    a.add_argument("--gamma0", type=_gamma0, default=None, metavar="G|steady",
                   help="start of the analysed window (default: the run's gamma0); "
                        "'steady': the earliest strain from the run's gamma0 on from which "
                        "tau passes the Mann-Kendall trend test on 20 block means (alpha "
                        "0.05), the run's gamma0 with a warning where none does")
    a.add_argument("--force", action="store_true", help="overwrite analysis.json/.npz")
    a.add_argument("--partial", type=Path, default=None, metavar="DIR2",
                   help="analyse the frames an interrupted or still running run has written "
                        "so far, into DIR2 (the run's DIR is only read; its parameters come "
                        "from the frames)")
    a.add_argument("--no-progress", action="store_true", help="no progress bar")
    a.add_argument("--reuse", type=Path, default=None, metavar="DIR3",
                   help="take the per-step analyses and slip spectra of an earlier analysis "
                        "in DIR3 (e.g. a --partial one) of this run's first frames, and "
                        "compute only the frames after them (the same result to the bit)")
    a.add_argument("--no-spectra", action="store_true",
                   help="skip the Jacobian spectrum before each slip")
    a.add_argument("--spectra", choices=("soft", "dense"), default="soft",
                   help="soft (default): the k softest eigenvalues before each slip by "
                        "shift-invert ARPACK (pairs and growth rates among those k); dense: "
                        "the whole spectrum (pairs over all of it; one dense eigenvalue "
                        "problem of dof x bulk disks per slip, ~20x slower on the quick run)")
    a.add_argument("--spectra-k", type=_int_at_least(-MAX_INT, MAX_INT), default=None,
                   metavar="K",
                   help="the window of softest eigenvalues (default 50); trade: ARPACK cost "
                        "grows ~ K, the statistics see more of the spectrum")
    e = s.add_parser("export", help="write the frames of a run for OVITO")
    e.add_argument("--out", type=Path, required=True, metavar="DIR", help="a `shear run` DIR")
    e.add_argument("--format", choices=("extxyz", "lammps"), default="extxyz",
                   help="extended XYZ (default) or LAMMPS dump text")
    e.add_argument("--every", type=_int_at_least(1, MAX_INT), default=1,
                   help="every k-th frame (default 1)")
    e.add_argument("--force", action="store_true", help="overwrite an existing export")


def analyze(ns, argv):
    """``fricstab shear analyze``: the analyses and the slip spectra of a run (module doc)."""
    import json

    from fricstab.io.results import ResultDir
    from fricstab.analysis.shear import analyze as analyze_frames
    out = Path(ns.out).expanduser()
    partial = ns.partial is not None
    if partial and Path(ns.partial).expanduser().resolve() == out.resolve():
        raise ParameterError("--partial: DIR2 must differ from the run's DIR (the run "
                             "may still be writing there)")
    frames = frames_of(out, partial)    # checks the run's manifest first
    if partial:
        from fricstab.io import rundir
        params = frames.meta.get("scene")
        if not isinstance(params, dict) or "law" not in params:
            raise ParameterError(f"--partial: the frames in {out} do not record the run's "
                                 "parameters (written before fricstab.io.frames/2?)")
        run = {"fingerprint": rundir.fingerprint(params)}
        dest = Path(ns.partial).expanduser()
    else:
        run = json.loads((out / "shear.json").read_text())
        params, dest = _run_parameters(out, run, frames), out
    steady = None
    if ns.gamma0 is None or ns.gamma0 == "steady":
        gamma0 = _recorded_gamma0(params, out, partial)
        if ns.gamma0 == "steady":
            gamma0, steady = _steady(frames, gamma0)
    else:
        gamma0 = ns.gamma0
    if not (math.isfinite(gamma0) and gamma0 >= 0):
        raise ParameterError(f"--gamma0 must be a finite number >= 0, got {gamma0!r}")
    from fricstab.analysis.shear_spectrum import SOFT_K, check_window
    k = SOFT_K if ns.spectra_k is None else check_window(ns.spectra_k, "--spectra-k")
    setting = {"gamma0": gamma0, "spectra": None if ns.no_spectra else ns.spectra,
               "spectra_k": k, "run": run.get("fingerprint", {}).get("sha256")}
    if steady is not None:
        setting["steady"] = steady
    if partial:
        setting.update(frames=frames.n_frames, strain=float(frames.strain[-1]))
    previous = _previous(ns.reuse, setting, frames) if ns.reuse is not None else None
    if previous is not None:
        setting["reused"] = {"dir": str(ns.reuse), "frames": len(previous["tau"])}
    rd = ResultDir(dest, "analysis", force=ns.force, outputs=("analysis.npz",),
                   fingerprint=setting).create()
    from fricstab import progress
    bars = not ns.no_progress and sys.stderr.isatty()   # the analyses' tqdm bars
    log = not ns.no_progress and not bars                # else a line every few seconds
    with rd.stage("analyze"), progress.heartbeat("shear analysis", log):
        res = analyze_frames(frames, gamma0, progress=bars, previous=previous)
    numbers, arrays = res.to_json(), res.npz_arrays()
    if not ns.no_spectra:
        from fricstab.analysis.shear_slips import slip_spectra
        with rd.stage("slip spectra"), progress.heartbeat("slip spectra", log):
            spectra = slip_spectra(frames, res.phases, res.arrays["phase_dtau_p"], params,
                                   progress=bars,
                                   route=ns.spectra, k=k,
                                   previous=previous if previous and "slip_frame" in previous
                                   else None)
        numbers["slip_spectra"] = spectra.summary()
        arrays.update(spectra.arrays())
    rd.write_npz("analysis.npz", **arrays)
    with progress.heartbeat("figures", not ns.no_progress):
        _analysis_outputs(rd, frames, res, numbers, arrays)
    doc = rd.finish(numbers, parameters={**setting, "run_dir": str(out)}, argv=argv)
    if partial:
        print(f"partial: the first {frames.n_frames} frames, to strain "
              f"{frames.strain[-1]:.4g}")
    s = doc.get("summary", {})
    sp = doc.get("slip_spectra")
    among = f"among its {sp['k']} softest modes" if sp and sp["route"] == "soft" else ""
    extra = (f"; slip spectra ({sp['route']}): {sp['slips_with_complex_pairs']} of "
             f"{sp['n_slips']} slips follow a state with complex pairs {among}".rstrip()
             if sp else "")
    print(f"analysis: {s.get('n_phases')} phases in {s.get('n_steps')} steps{extra}; wrote "
          f"{dest}/analysis.json, analysis.npz, analysis.md, analysis_*.png")
    return 0


def _steady(frames, gamma0):
    """``--gamma0 steady``: the start of the steady window of the run's tau from ``gamma0``
    on (:func:`fricstab.analysis.stationarity.steady_window`) and the test's record; a
    warning on stderr where no start passes."""
    from fricstab.analysis.stationarity import steady_window
    start, info = steady_window(frames.strain, frames.tau, gamma0)
    if info["steady"]:
        print(f"steady start: strain {start:.6g} (Mann-Kendall on {info['n_blocks']} block "
              f"means of tau from there, each >= 2 of tau's integrated autocorrelation times "
              f"of {info['tau_int']:.0f} frames: p = {info['p']:.2g}, drift "
              f"{info['drift_over_std']:+.2g} std)")
    else:
        print(f"fricstab: warning: tau is not steady from strain {gamma0:g} on "
              f"({info['reason']}); analysed from gamma0 = {gamma0:g}, a drifting state",
              file=sys.stderr)
    return start, info


def _run_parameters(out, run, frames):
    """The parameters of the run's record, refused (one line, naming the key) if edited.

    They must be an object whose fingerprint is the record's (``shear.json``
    is not in its own manifest, so a hand edit shows only there) and, where the
    frames record the run's parameters, those of the frames (the total strain
    aside: a resumed run may extend it).
    """
    from fricstab.io import rundir
    path = out / "shear.json"
    params = run.get("parameters") if isinstance(run, dict) else None
    if not isinstance(params, dict):
        raise ParameterError(f"{path}: the key 'parameters' is missing or not an object "
                             "(edited by hand?); rerun the shear run with --force")
    _recorded_gamma0(params, out, False)
    recorded = run.get("fingerprint")
    if isinstance(recorded, dict) and "sha256" in recorded:
        try:
            now = rundir.fingerprint(params)
        except (TypeError, ValueError):
            now = {}
        if now.get("sha256") != recorded["sha256"]:
            differs = rundir.difference(recorded, now) or "other parameters"
            raise ParameterError(f"{path}: its 'parameters' do not match its fingerprint "
                                 f"({differs.replace(' there', ' in the fingerprint')}; edited "
                                 "by hand?); rerun the shear run with --force")
    scene = frames.meta.get("scene")
    if isinstance(scene, dict):
        differs = rundir.difference(rundir.fingerprint(scene), rundir.fingerprint(params),
                                    free=("strain",))
        if differs:
            raise ParameterError(f"{path}: its 'parameters' are not those of its frames "
                                 f"({differs.replace(' there', ' in the frames')}); rerun the "
                                 "shear run with --force")
    return params


def _recorded_gamma0(params, out, partial):
    """``gamma0`` of the run's parameters: a number (ParameterError naming the key)."""
    g = params.get("gamma0")
    if isinstance(g, bool) or not isinstance(g, (int, float)):
        where = f"the frames in {out}" if partial else f"{out / 'shear.json'}"
        raise ParameterError(f"{where}: the key 'parameters.gamma0' is missing or not a "
                             f"number (got {g!r}); give --gamma0, or rerun the shear run "
                             "with --force")
    return float(g)


def _previous(folder, setting, frames):
    """The arrays of the analysis in ``folder`` to reuse (its slip spectra if of the same route and k)."""
    import json

    from fricstab.analysis.shear import check_previous
    from fricstab.io import rundir
    folder = Path(folder).expanduser()
    rundir.verify(folder, "analysis")     # a complete analysis, its files as recorded
    done = json.loads((folder / "analysis.json").read_text()).get("parameters", {})
    with np.load(folder / "analysis.npz") as z:
        arrays = {name: z[name] for name in z.files}
    try:
        check_previous(frames, arrays)
    except ParameterError as exc:
        raise ParameterError(f"--reuse: {folder}: {exc}") from None
    if (done.get("spectra"), done.get("spectra_k")) != (setting["spectra"],
                                                        setting["spectra_k"]):
        arrays = {k: v for k, v in arrays.items() if not k.startswith("slip_")}
    return arrays

def _analysis_outputs(rd, frames, res, numbers, arrays):
    """analysis.md (Spearman tables) and the figures of Figs. 2, 8-10 and the slip spectra."""
    from fricstab.figures import shear as sf
    from fricstab.analysis.shear import paper_tables, tables_markdown
    t = res.tables
    text = [f"# Plane shear analysis of {rd.path}", "",
            "Spearman rho (p-value, n) of Delta tau / Delta tau_p per bin; struck through: "
            "p > 0.05 (omitted in the paper's figures).", "",
            paper_tables(t)]
    sp = numbers.get("slip_spectra")
    if sp:
        c = sp["correlations_with_following_dtau_p"]
        text += ["", f"Spectra ({sp['route']} route): statistics over {sp['statistics_over']}.",
                 "", tables_markdown({"all slips": {k: [{"lo": -1.0, "hi": 0.0, **v}]
                                                    for k, v in c["all"].items()},
                                      "binned by Delta tau_p": c["binned"]},
                                     "Jacobian before each slip against its Delta tau_p")]
    md = "\n".join(text) + "\n"
    rd.write_with("analysis.md", lambda tmp: Path(tmp).write_text(md))
    rd.write_png("analysis_stress_strain.png",
                 lambda path: sf.fig_stress_strain(frames, path, result=res))
    rd.write_png("analysis_steps.png", lambda path: sf.fig_step_panels(res, path))
    rd.write_png("analysis_spearman_phases.png",
                 lambda path: sf.fig_spearman_bins(t["phase_all"], path, "all phases"))
    steps = res.summary.get("largest_drop_steps")
    if steps:      # Figs. 3-7 at the first step of the largest slip
        k = int(steps[0])
        for name, draw in (("d2min", sf.fig_d2min_map), ("gr", sf.fig_gr_clusters),
                           ("forces", sf.fig_force_network),
                           ("dforces", sf.fig_differential_network),
                           ("nonaffine", sf.fig_nonaffine)):
            rd.write_png(f"analysis_map_{name}.png",
                         lambda path, draw=draw: draw(frames, k, path))
        rd.write_png("analysis_steps_largest_slip.png",
                     lambda path: sf.fig_step_panels(res, path,
                                                     (max(k - 20, 1), min(int(steps[1]) + 20,
                                                                          frames.n_frames))))
    if sp:
        rd.write_png("analysis_slip_spectra.png",
                     lambda path: sf.fig_slip_spectra(arrays, path, sp))


def export(ns):
    """``fricstab shear export``: the frames of a run for OVITO (record ``export.json``)."""
    from fricstab.io.export import frames_to_ovito
    from fricstab.io.results import ResultDir
    out = Path(ns.out).expanduser()
    if ns.every < 1:
        raise ParameterError(f"--every must be >= 1, got {ns.every}")
    frames = frames_of(out)
    name = "frames.xyz" if ns.format == "extxyz" else "frames.dump"
    setting = {"format": ns.format, "every": ns.every}
    if (out / name).is_dir():
        raise ParameterError(f"--out: {out / name} is a folder, not an export of this run; "
                             "move it away to export there")
    rd = ResultDir(out, "export", force=ns.force, outputs=("frames.xyz", "frames.dump"),
                   fingerprint=setting).create()
    keep = np.arange(0, frames.n_frames, ns.every)
    frames_to_ovito(frames.subset(keep), rd.file(name), ns.format)   # written atomically
    rd.finish({"frames": len(keep), "file": name}, parameters=setting)
    print(f"wrote {out / name} ({len(keep)} frames)")
    return 0
