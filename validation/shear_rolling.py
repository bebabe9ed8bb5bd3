"""Issue 34, items 2-3: a paper-scale shear run that survives a change of machine.

A paper-preset run (1,000 disks, 7.2e-7 of strain per frame, ~160,000 frames) takes ~6 h on one
core and writes ~19 GB of frames: it outlives a sitting, and its frames cannot be committed.
Here the run goes in **segments** of ``--segment`` output frames (default 5,000, ~11 min at
the paper's scale).  Each segment is run from the previous segment's end state, its frames
are held in memory only, and :func:`fricstab.analysis.shear.analyze` computes their per-step
analyses (D2min, GR regions, contact angles, the stress-D2min correlation: every quantity
that needs two frames, :data:`fricstab.analysis.shear.PER_STEP`).  The segment file keeps the
series of its frames (time, strain, N, S, tau, height), those per-step arrays, the checkpoint
at its end (:meth:`fricstab.protocols.shear_run.ShearRun.arrays`) and its last frame (the
first segment also the preparation's record); the frames are dropped.  Every segment starts
from the stored state of the one before, in this process as on the next sitting's machine.
A segment of the paper preset is 0.69 MB (~22 MB a member), committed in
``validation/runs/shear_rolling/<mus..._seed...>/``, so the next sitting goes on where this
one stopped, on whatever machine it gets.  Measured (2-core AMD EPYC, the other core busy):
the preparation 391 s, a segment ~710 s (shearing and per-step analyses), ~6.3 h a member.

The phases, their metrics and the Spearman tables depend on the per-step arrays and the tau
series only, so :func:`analysis` assembles them with ``analyze(..., previous=...)`` from any
gamma0 (the steady start, :func:`fricstab.analysis.stationarity.steady_window`): the same
numbers, to the bit, as ``fricstab shear analyze`` on the frames of an uninterrupted run
(``validation/test_shear_rolling.py``).  ``export`` writes a member as a run folder
(``shear.npz``, ``shear.json``, ``analysis.npz``, ``analysis.json``) that
``validation/shear_sweep_paper.py`` and ``validation/shear_long_phases.py`` read as they read
a ``fricstab shear sweep`` member.  Not kept: the frames themselves, so the event maps of
Figs. 3-7 rerun the event's segment from the state stored before it (:func:`event_frames`,
checked to repeat the stored series to the bit; ~12 min), and the slip spectra (our
extension) are not computed.

Each segment is stamped with the functions of the checkout it executed
(:mod:`_stamped`): where one of them changed, the member is refused with the stale segment
named, never continued under other code (``--restart`` discards it).  Another machine
continues the same trajectory from the stored state; the machine of each segment is recorded.

Usage::

    python validation/shear_rolling.py run --mus 0.7 [0.5 ...] [--seed 0] [--preset paper] [--max-hours H]
    python validation/shear_rolling.py run --mus 0.7 --strain 0.16   # extend: tau not levelled
    python validation/shear_rolling.py status
    python validation/shear_rolling.py export --out DIR    # then shear_sweep_paper.py DIR
"""

import argparse
import dataclasses
import functools
import json
import platform
import shutil
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))
sys.path.insert(0, str(HERE))

import numpy as np  # noqa: E402

import _stamped  # noqa: E402
from fricstab.cli.shear import SERIES  # noqa: E402  (time, strain, N, S, tau, height)
from fricstab.io.frames import Frames  # noqa: E402
from fricstab.errors import ParameterError  # noqa: E402

STORE = HERE / "runs" / "shear_rolling"
SEGMENT = 5_000          # output frames per segment: ~12 min at the paper's scale on one core
_FRAME_FIELDS = tuple(f.name for f in dataclasses.fields(Frames) if f.name not in ("lx", "meta"))


def label(params, preset="paper"):
    """The member's folder name: ``mus<M>_seed<S>`` (as ``fricstab shear sweep``), led by
    the preset where it is not ``paper`` (``large-mus0.7_seed0``)."""
    name = f"mus{params['law_params']['mus']!r}_seed{params['seed']}"
    return name if preset == "paper" else f"{preset}-{name}"


def member_params(mus, seed=0, preset="paper", **overrides):
    """The parameters of a ``fricstab shear sweep --preset PRESET`` member (mu_s, seed)."""
    from fricstab.cli.shear import resolve_params
    return resolve_params(None, preset, {**overrides, "mus": mus, "seed": seed})


# ------------------------------------------------------------------ the store of a member

def _fingerprint(params):
    from fricstab.io import rundir
    return rundir.fingerprint({k: v for k, v in params.items() if k != "strain"})["sha256"]


def segments(folder):
    """The segment files of a member folder, in order (``seg_0000.npz`` onwards, no gap)."""
    files = sorted(Path(folder).glob("seg_*.npz"))
    for i, f in enumerate(files):
        if f.name != f"seg_{i:04d}.npz":
            raise SystemExit(f"{folder}: segment {f.name} out of sequence (expected "
                             f"seg_{i:04d}.npz); the store is damaged")
    return files


def _member_json(folder):
    path = Path(folder) / "member.json"
    return json.loads(path.read_text()) if path.exists() else None


def _last_frame(seg, meta):
    """The last frame of a segment, as a one-frame :class:`fricstab.io.frames.Frames`."""
    from fricstab.io.frames import Frames
    return Frames(lx=float(seg["last_lx"]), meta=meta,
                  **{n: seg[f"last_{n}"] for n in _FRAME_FIELDS})


def _checkpoint(seg):
    return {k[len("ck_"):]: v for k, v in seg.items() if k.startswith("ck_")}


def _fresh(folder, advice=""):
    """The stored segments of a member in order, each checked fresh: ``(file, contents)``;
    SystemExit naming the first stale or unreadable one (``advice`` ends the message)."""
    for f in segments(folder):
        got = _stamped.stored(f)
        if got is None:
            raise SystemExit(f"{f}: made by other code (a function it executed has changed "
                             f"since) or unreadable{advice}")
        yield f, got


def _load_all(folder):
    """The stored segments of a member, each checked fresh; SystemExit naming a stale one."""
    return [got for _, got in _fresh(folder, "; the member cannot go on under this code: "
                                             "rerun with --restart to discard it, or check "
                                             "out the revision that made it")]


# ------------------------------------------------------------------ running

def _frames(sim, cell, params, prev_last, k0, k1, meta):
    """Run frames k0..k1 from ``sim``'s state: their :class:`fricstab.io.frames.Frames`, led
    by ``prev_last`` (the frame before k0) or, for k0 = 0, by frame 0."""
    from fricstab.io.frames import FrameWriter
    from fricstab.protocols.shear_run import FRAME
    u = cell.units
    w = FrameWriter(cell.lx * u.length, cell.radius * u.length, cell.mass * u.mass,
                    cell.inertia * u.mass * u.length ** 2, cell.kind, meta=meta)
    w.append(**(sim.frame() if prev_last is None else prev_last._frame_kwargs(0)))
    spf = int(sim.scalars[3])
    for k in range(max(k0, 1), k1 + 1):
        sim.advance(spf)
        sim.scalars[FRAME] = k
        w.append(**sim.frame())
    return w.finish()


def _segment(sim, cell, params, prev_last, k0, k1, meta):
    """Run frames k0..k1 from ``sim``'s state; the segment's arrays (series, per-step
    analyses of steps k0..k1, the end checkpoint and the last frame)."""
    from fricstab.analysis.shear import PER_STEP, analyze
    frames = _frames(sim, cell, params, prev_last, k0, k1, meta)
    res = analyze(frames, params["gamma0"], progress=False)
    cut = 0 if prev_last is None else 1      # the frame carried over is the last segment's
    out = {"first": np.int64(k0), "last": np.int64(k1),
           "series": np.column_stack([getattr(frames, n) for n in SERIES])[cut:],
           **{f"step_{n}": res.arrays[n][cut:] for n in PER_STEP},
           **{f"ck_{k}": v for k, v in sim.arrays().items()},
           "last_lx": np.float64(frames.lx),
           **{f"last_{n}": v for n, v in dataclasses.asdict(
               frames.subset([frames.n_frames - 1]), dict_factory=dict).items()
              if n in _FRAME_FIELDS},
           "machine": np.str_(_machine())}
    return out


def _machine():
    """Host, architecture and CPU model (read from /proc: ``platform.processor()`` starts a
    process, which would leave the segment's stamp untraced)."""
    model = ""
    try:
        with open("/proc/cpuinfo") as f:
            model = next((line.split(":", 1)[1].strip() for line in f
                          if line.startswith("model name")), "")
    except OSError:
        pass
    return f"{platform.node()} {platform.machine()} {model}".strip()


def _start(params):
    from fricstab.protocols.shear_run import ShearRun
    from fricstab.scenes.shear import make_cell
    cell = make_cell(params)
    u = cell.units
    meta = {"units": "SI per unit thickness (N/m, N m/m, kg/m)", "scene": params,
            "reduced_units": u.to_json(), "lx_m": cell.lx * u.length, "law": params["law"]}
    return cell, ShearRun(cell), meta


def _resumed(params, prev):
    """(cell, sim, meta, the frame before, the preparation's record): prepared and started
    where ``prev`` is None (the seeded preparation), else at the end of segment ``prev``."""
    from fricstab.protocols.shear_run import prepare
    cell, sim, meta = _start(params)
    if prev is None:
        t0 = time.perf_counter()
        prep = prepare(sim)
        sim.start_shear()
        return cell, sim, meta, None, {**prep, "seconds_here": time.perf_counter() - t0}
    sim.load_arrays(_checkpoint(prev))
    return cell, sim, meta, _last_frame(prev, meta), None


def _compute(params, prev, k0, k1):
    """Segment k0..k1 after the stored segment ``prev`` (None: the first, with the
    preparation, whose record it keeps)."""
    cell, sim, meta, last, prep = _resumed(params, prev)
    out = _segment(sim, cell, params, last, k0, k1, meta)
    if prep is not None:
        out["prepare"] = np.str_(json.dumps(prep, default=float))
    return out


def frames_of_segment(folder, i):
    """The frames of stored segment ``i``, rerun from the state stored before it (for i = 0
    the seeded preparation is rerun): frames first-1..last (0..last for i = 0), for the event
    maps the store does not keep.  RuntimeError unless their series equals the stored one to
    the bit (a rerun on another kind of CPU can take another trajectory)."""
    rec = _member_json(folder)
    done = _load_all(folder)
    if rec is None or not 0 <= i < len(done):
        raise SystemExit(f"{folder}: no segment {i} stored ({len(done)} segments)")
    params = rec["parameters"]
    cell, sim, meta, last, _ = _resumed(params, done[i - 1] if i else None)
    frames = _frames(sim, cell, params, last, int(done[i]["first"]), int(done[i]["last"]), meta)
    got = np.column_stack([getattr(frames, n) for n in SERIES])[0 if i == 0 else 1:]
    if not np.array_equal(got, done[i]["series"]):
        raise RuntimeError(f"{folder}: segment {i} rerun here does not repeat the stored series "
                           f"(made on {done[i]['machine']}); the frames differ")
    return frames


def run(mus, seed=0, preset="paper", segment=SEGMENT, max_hours=None, restart=False,
        store=STORE, overrides=None, log=print):
    """Run (or go on with) the member (mu_s, seed) until its strain or ``max_hours``; returns
    the number of frames stored.  The strain (``overrides["strain"]``, default the preset's)
    only stops the run: a larger one extends a stored member, which then stays extended
    where a later call names no strain; one short of the frames stored is refused."""
    overrides = dict(overrides or {})
    params = member_params(mus, seed, preset, **overrides)
    folder = Path(store) / label(params, preset)
    rec = _member_json(folder)
    if restart and folder.exists():
        shutil.rmtree(folder)
        rec = None
    if rec is not None and "strain" not in overrides and \
            rec["parameters"]["strain"] > params["strain"]:     # extended: stays extended
        params = member_params(mus, seed, preset, **overrides, strain=rec["parameters"]["strain"])
    if rec is not None and rec["fingerprint"] != _fingerprint(params):
        raise SystemExit(f"{folder}: holds a member with other parameters (member.json); "
                         "rerun with --restart to discard it")
    if rec is not None and rec["segment"] != segment:
        raise SystemExit(f"{folder}: its segments have {rec['segment']} frames, not "
                         f"{segment}; give --segment {rec['segment']}")
    done = _load_all(folder) if rec is not None else []
    n_frames = int(round(params["strain"] / params["dgamma"]))
    if done and int(done[-1]["last"]) > n_frames:
        raise SystemExit(f"{folder}: holds frames to {int(done[-1]['last'])}, past strain "
                         f"{params['strain']:g} ({n_frames} frames); give --strain "
                         f"{rec['parameters']['strain']:g} or more")
    if rec is None or rec["parameters"]["strain"] != params["strain"]:
        folder.mkdir(parents=True, exist_ok=True)    # the strain only stops the run
        rec = {"parameters": params, "fingerprint": _fingerprint(params), "segment": segment}
        (folder / "member.json").write_text(json.dumps(rec, indent=1, default=float))
    prev = done[-1] if done else None
    k0 = int(prev["last"]) + 1 if prev is not None else 0
    if prev is not None:
        log(f"{folder.name}: {len(done)} segments stored, going on from frame {k0 - 1}")
    t_start = time.perf_counter()
    while k0 <= n_frames:
        if max_hours is not None and time.perf_counter() - t_start > 3600 * max_hours:
            log(f"{folder.name}: stopped after {max_hours:g} h at frame {k0 - 1} of {n_frames}")
            break
        k1 = min(k0 + segment - 1 if k0 else segment, n_frames)
        i = len(segments(folder))
        # each segment starts from the stored state, as on the next sitting's machine
        prev = _stamped.cached(folder / f"seg_{i:04d}.npz",
                               functools.partial(_compute, params, prev, k0, k1), log=log)
        k0 = k1 + 1
        log(f"{folder.name}: segment {i} (frames to {k1} of {n_frames}, strain "
            f"{prev['series'][-1, 1]:.5f}) in {float(prev['stamp_seconds']):.0f} s")
    return min(k0 - 1, n_frames)


# ------------------------------------------------------------------ reading

class _Window:
    """A run's frames as the analyses read them (``strain``, ``tau``, ``n_frames``, ``pos[k]``,
    ``contacts(k)``, ...) where only the frames ``offset``.. of ``part`` are kept: the whole
    series, the particles and contacts of the frames held.  Any other frame is refused.  With
    the last frame alone it is what ``analyze(frames, gamma0, previous=...)`` reads of a run
    whose every step is given (the rattlers and stresses it starts from)."""

    def __init__(self, series, part, offset):
        self.strain, self.tau = series[:, 1], series[:, 4]
        self.n_frames, self.n_particles = len(series), part.n_particles
        self.kind, self.radius, self.lx = part.kind, part.radius, part.lx
        self._part, self._offset = part, offset
        self.pos = self

    def _local(self, k):
        k = k + self.n_frames if k < 0 else k
        i = k - self._offset
        if not 0 <= i < self._part.n_frames:
            raise IndexError(f"frame {k}: only frames {self._offset}.."
                             f"{self._offset + self._part.n_frames - 1} of this segmented run "
                             "are held")
        return i

    def __getitem__(self, k):
        return self._part.pos[self._local(k)]

    def contacts(self, k):
        return self._part.contacts(self._local(k))


def event_frames(folder, lo, hi):
    """Frames ``lo``..``hi`` of a member (for the event maps), rerun from the stored states
    (:func:`frames_of_segment`), as a :class:`_Window` over the whole series."""
    from fricstab.io.frames import Frames
    done = _load_all(folder)
    series = np.concatenate([d["series"] for d in done])
    if not 0 <= lo <= hi < len(series):
        raise SystemExit(f"{folder}: frames {lo}..{hi} are not all stored ({len(series)})")
    parts, need = [], lo
    for i, d in enumerate(done):
        if int(d["last"]) < need:
            continue
        start = 0 if i == 0 else int(d["first"]) - 1   # segment i reruns from frame start
        end = min(hi, int(d["last"]))
        parts.append(frames_of_segment(folder, i).subset([k - start for k in range(need, end + 1)]))
        need = end + 1
        if need > hi:
            break
    return _Window(series, Frames.concat(parts) if len(parts) > 1 else parts[0], lo)


def _loaded(folder):
    """(member record, its stored segments, each checked fresh)."""
    rec = _member_json(folder)
    if rec is None:
        raise SystemExit(f"{folder}: no member.json (run it first: python "
                         "validation/shear_rolling.py run --mus M)")
    done = _load_all(folder)
    if not done:
        raise SystemExit(f"{folder}: no segment stored yet")
    return rec, done


def _arrays_of(rec, done):
    from fricstab.analysis.shear import PER_STEP
    series = np.concatenate([d["series"] for d in done])
    steps = {n: np.concatenate([d[f"step_{n}"] for d in done]) for n in PER_STEP}
    units = {}
    for d in done:
        units = _stamped.merge(units, _stamped.units_of(d))
    return series, steps, _last_frame(done[-1], {"scene": rec["parameters"]}), rec, units


def series_to(folder, strain):
    """The series (T, 6) of a member's frames up to ``strain`` (the first segments that reach
    it, each checked fresh, cut at the last frame at or below it), the merged code units of
    those segments and their files; SystemExit where the member has not reached ``strain``."""
    series, units, used = [], {}, []
    for f, got in _fresh(folder):
        series.append(got["series"])
        units = _stamped.merge(units, _stamped.units_of(got))
        used.append(f)
        if got["series"][-1, 1] >= strain - 1e-12:
            whole = np.concatenate(series)
            return whole[whole[:, 1] <= strain + 1e-12], units, used
    reached = series[-1][-1, 1] if series else 0.0
    raise SystemExit(f"{folder}: reaches strain {reached:.5f}, not {strain:g}; run it on: "
                     f"python validation/shear_rolling.py run --mus M --strain {strain:g}")


def arrays(folder):
    """(series (T, 6), per-step arrays, the last frame, member record, merged code units)."""
    return _arrays_of(*_loaded(folder))


def analysis(folder, gamma0=None, got=None):
    """The analysis of the stored frames of a member from ``gamma0`` (default: the run's),
    and its series: ``(ShearAnalysis, series, record)``; ``got``: :func:`arrays` of the
    member, where the caller has them already."""
    from fricstab.analysis.shear import analyze
    series, steps, last, rec, _ = got or arrays(folder)
    g0 = rec["parameters"]["gamma0"] if gamma0 is None else gamma0
    previous = {"strain": series[:, 1], "tau": series[:, 4], **steps}
    return analyze(_Window(series, last, len(series) - 1), g0, progress=False, previous=previous), series, rec


def _revision():
    import subprocess
    try:
        out = subprocess.run(["git", "-C", str(HERE), "rev-parse", "HEAD"], capture_output=True,
                             text=True, check=True).stdout.strip()
        dirty = bool(subprocess.run(["git", "-C", str(HERE), "status", "--porcelain"],
                                    capture_output=True, text=True, check=True).stdout.strip())
    except (OSError, subprocess.CalledProcessError):
        return {}
    return {"revision": out, "dirty": dirty}


def export(folder, dest, log=print):
    """Write the member as a run folder ``dest`` that ``shear_sweep_paper.py`` and
    ``shear_paper.py`` read: the series (``shear.npz``), the preparation (``prepare.json``),
    the analysis from the steady start (``analysis.npz``, ``analysis.json``; a partial one,
    with its frame count, while the member is not finished) and, once it is, the run's record
    (``shear.json``).  The records name this checkout's revision: every segment is checked
    fresh under its code (:func:`arrays`)."""
    from fricstab.analysis.stationarity import steady_window
    rec, segs = _loaded(folder)
    got = _arrays_of(rec, segs)
    series, _, last, _, _ = got
    params = rec["parameters"]
    n_frames = int(round(params["strain"] / params["dgamma"]))
    finished = len(series) == n_frames + 1
    start, info = steady_window(series[:, 1], series[:, 4], params["gamma0"])
    res, _, _ = analysis(folder, start, got)
    dest = Path(dest)
    dest.mkdir(parents=True, exist_ok=True)
    git = _revision()
    seconds = sum(float(g["stamp_seconds"]) for g in segs)
    prep = json.loads(segs[0]["prepare"])
    spf = int(segs[-1]["ck_run_scalars"][3])
    np.savez(dest / "shear.npz", **{n: series[:, i] for i, n in enumerate(SERIES)})
    np.savez(dest / "analysis.npz", **res.npz_arrays())
    (dest / "prepare.json").write_text(json.dumps(prep, default=float))
    setting = {"gamma0": start, **({} if finished else {"frames": len(series)})}
    (dest / "analysis.json").write_text(json.dumps(
        {"parameters": setting, "steady": info, "git": git, "segmented": str(folder),
         "run_parameters": params,
         **res.to_json()}, default=float))
    if finished:    # shear_sweep_paper.py takes a folder with shear.json as finished
        (dest / "shear.json").write_text(json.dumps(
            {"parameters": params, "segmented": str(folder), "frames": len(series), "git": git,
             "derived": {"n_particles": int(last.n_particles), "steps_per_frame": spf},
             "shear_seconds_this_process": seconds,
             "throughput_particle_steps_per_s": (len(series) - 1) * spf * last.n_particles
             / seconds, "machines": sorted({str(g["machine"]) for g in segs})},
            default=float))
    state = "finished" if finished else "not finished"
    log(f"{dest}: {len(series) - 1} of {n_frames} frames ({state}), analysed from strain "
        f"{start:.5f}: {res.summary['n_phases']} phases in {res.summary['n_steps']} steps")
    return dest


def status(store=STORE):
    """One line per member: frames stored of the total, strain, segments, machines."""
    lines = []
    for folder in sorted(Path(store).glob("*mus*_seed*")):
        rec = _member_json(folder)
        files = segments(folder)
        if rec is None or not files:
            lines.append(f"{folder.name}: nothing stored")
            continue
        p = rec["parameters"]
        n_frames = int(round(p["strain"] / p["dgamma"]))
        segs = [_stamped.load(f) for f in files]
        last = segs[-1]
        fresh = all(_stamped.stored(f) is not None for f in files)
        done = int(last["last"])
        per_frame = sum(float(g["stamp_seconds"]) for g in segs) / max(done, 1)
        lines.append(f"{folder.name}: frames to {done} of {n_frames} (strain "
                     f"{last['series'][-1, 1]:.5f} of {p['strain']:g}) in {len(files)} segments"
                     f" ({per_frame * done / 3600:.2f} h; ~{per_frame * (n_frames - done) / 3600:.1f}"
                     f" h to go at that pace)"
                     f"{'' if fresh else ' (STALE: made by other code)'}")
    return lines


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    sub = ap.add_subparsers(dest="cmd", required=True)
    r = sub.add_parser("run", help="run or go on with a member")
    r.add_argument("--mus", type=float, nargs="+", required=True,
                   help="mu_s of the members, run one after the other (--max-hours in all)")
    r.add_argument("--seed", type=int, default=0)
    r.add_argument("--preset", choices=("quick", "paper", "large"), default="paper")
    r.add_argument("--segment", type=int, default=SEGMENT)
    r.add_argument("--max-hours", type=float, default=None)
    r.add_argument("--strain", type=float, default=None,
                   help="run to this strain (default: the preset's, or the member's if it was "
                        "extended): a larger one extends a stored member where tau has not "
                        "levelled by the preset's")
    r.add_argument("--restart", action="store_true", help="discard the stored member first")
    r.add_argument("--store", type=Path, default=STORE)
    s = sub.add_parser("status", help="what is stored")
    s.add_argument("--store", type=Path, default=STORE)
    e = sub.add_parser("export", help="write every paper-preset member as a run folder under "
                       "DIR/runs/ (the sweep's)")
    e.add_argument("--out", type=Path, required=True)
    e.add_argument("--store", type=Path, default=STORE)
    a = ap.parse_args(argv)
    if a.cmd == "run":
        if a.segment < 2:
            ap.error("--segment must be >= 2")
        if a.max_hours is not None and not a.max_hours > 0:
            ap.error("--max-hours must be > 0")
        if a.strain is not None and not a.strain > 0:
            ap.error("--strain must be > 0")
        t0 = time.perf_counter()
        for mus in a.mus:
            left = None if a.max_hours is None else a.max_hours - (time.perf_counter() - t0) / 3600
            if left is not None and left <= 0:
                print(f"mus {mus:g}: not started (--max-hours spent)", flush=True)
                continue
            try:
                run(mus, a.seed, a.preset, a.segment, left, a.restart, a.store,
                    overrides=None if a.strain is None else {"strain": a.strain},
                    log=lambda m: print(m, flush=True))
            except ParameterError as exc:
                ap.error(str(exc))
    elif a.cmd == "status":
        print("\n".join(status(a.store)) or f"{a.store}: no member")
    else:
        for folder in sorted(Path(a.store).glob("mus*_seed*")):
            export(folder, a.out / "runs" / folder.name)
    return 0


if __name__ == "__main__":
    sys.exit(main())
