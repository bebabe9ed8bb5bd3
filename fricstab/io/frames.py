"""Output frames of the 2D plane-shear cell (Lee & Hurley), as one container.

A :class:`Frames` holds T output frames of N disks in a cell periodic in x
(box length ``lx``) between two walls made of rows of disks.  It is the
contract between the run that writes frames (:mod:`fricstab.protocols.shear_run`)
and the analyses (:mod:`fricstab.analysis.shear`), figures and export.

Shapes and conventions (units are those of the scene, recorded in ``meta``)
--------------------------------------------------------------------------
Per particle, constant over frames:
    ``radius (N,)``, ``mass (N,)``, ``inertia (N,)`` float64;
    ``kind (N,)`` int8: 0 bulk, 1 bottom wall (fixed), 2 top wall (rigid,
    servo-controlled normal force).
Per frame:
    ``time (T,)``, ``strain (T,)`` (shear strain gamma), ``normal_force (T,)``
    N and ``shear_force (T,)`` S on the top wall, ``tau (T,)`` = S / N,
    ``height (T,)`` of the cell; ``pos (T, N, 2)`` with x *unwrapped*
    (continuous trajectories: a displacement is ``pos[k] - pos[j]`` with no
    image bookkeeping; a neighbour vector at one frame uses the minimum image
    in x, ``d - lx * round(d / lx)``), ``angle (T, N)``, ``vel (T, N, 2)``,
    ``omega (T, N)`` (counter-clockwise positive).
Contacts, ragged over frames (CSR layout), frame k owns rows
``contact_ptr[k]:contact_ptr[k + 1]``:
    ``contact_ptr (T + 1,)`` int64, ``contact_ij (M, 2)`` int32 with i < j,
    ``contact_force (M, 2)`` total contact force on i from j (elastic +
    damping; the force on j is minus it), ``contact_fn (M,)`` elastic normal
    force (>= 0 compressive), ``contact_hist (M, H)`` the contact law's
    stored (projected) history, H = 0 for a law without one (``meta["law"]``
    names the law, ``meta["history"]`` the slots and their units: for
    ``lee_hurley`` the tangential force ft and the rolling torque mr, for
    ``charan`` and ``ishima`` the tangential displacement (tx, ty)),
    ``contact_flag (M,)`` int8: bit 1 the tangential history sits on its cap
    (sliding), bit 2 the rolling one (the engine's projection flags).
``meta``: a JSON-serialisable dict (units, scene parameters, law, version);
kept in the NPZ as a JSON string.

Files are NPZ written atomically (temporary file in the same directory, then
``os.replace``); :meth:`Frames.load` validates shapes and dtypes and raises
:class:`fricstab.laws.ParameterError` naming the file for a truncated or
foreign file.
"""

import json
import os
import tempfile
import zipfile
from dataclasses import dataclass, field, fields
from pathlib import Path

import numpy as np

from fricstab.laws import ParameterError

__all__ = ["FORMAT", "FrameWriter", "Frames", "frame_index", "read_arrays", "subset_of",
           "synthetic_frames"]

FORMAT = "fricstab.io.frames/2"  # /2: contact_hist (M, H), contact_flag

# name -> (dtype, shape template); "T", "N", "M", "T+1" are symbolic sizes.
_SPEC = {
    "radius": (np.float64, ("N",)),
    "mass": (np.float64, ("N",)),
    "inertia": (np.float64, ("N",)),
    "kind": (np.int8, ("N",)),
    "time": (np.float64, ("T",)),
    "strain": (np.float64, ("T",)),
    "normal_force": (np.float64, ("T",)),
    "shear_force": (np.float64, ("T",)),
    "tau": (np.float64, ("T",)),
    "height": (np.float64, ("T",)),
    "pos": (np.float64, ("T", "N", 2)),
    "angle": (np.float64, ("T", "N")),
    "vel": (np.float64, ("T", "N", 2)),
    "omega": (np.float64, ("T", "N")),
    "contact_ptr": (np.int64, ("T+1",)),
    "contact_ij": (np.int32, ("M", 2)),
    "contact_force": (np.float64, ("M", 2)),
    "contact_fn": (np.float64, ("M",)),
    "contact_hist": (np.float64, ("M", "H")),
    "contact_flag": (np.int8, ("M",)),
}
_PER_PARTICLE = ("radius", "mass", "inertia", "kind")
_PER_FRAME = ("time", "strain", "normal_force", "shear_force", "tau", "height",
              "pos", "angle", "vel", "omega")
_PER_CONTACT = ("contact_ij", "contact_force", "contact_fn", "contact_hist",
                "contact_flag")


def _readonly(a):
    a.setflags(write=False)
    return a


@dataclass(frozen=True, eq=False)
class Frames:
    """T output frames of the plane-shear cell (see the module docstring).

    Arrays are converted to the dtypes of the contract and made read-only;
    ``__post_init__`` checks shapes, finiteness, ``kind`` values, the
    monotone ``contact_ptr`` and ``i < j < N`` for contacts.
    """

    lx: float
    radius: np.ndarray
    mass: np.ndarray
    inertia: np.ndarray
    kind: np.ndarray
    time: np.ndarray
    strain: np.ndarray
    normal_force: np.ndarray
    shear_force: np.ndarray
    tau: np.ndarray
    height: np.ndarray
    pos: np.ndarray
    angle: np.ndarray
    vel: np.ndarray
    omega: np.ndarray
    contact_ptr: np.ndarray
    contact_ij: np.ndarray
    contact_force: np.ndarray
    contact_fn: np.ndarray
    contact_hist: np.ndarray
    contact_flag: np.ndarray
    meta: dict = field(default_factory=dict)

    def __post_init__(self):
        lx = float(self.lx)
        if not (np.isfinite(lx) and lx > 0):
            raise ParameterError(f"Frames: lx = {self.lx!r} must be finite and > 0")
        object.__setattr__(self, "lx", lx)
        for name, (dtype, _) in _SPEC.items():
            arr = np.asarray(getattr(self, name))
            if np.issubdtype(dtype, np.integer) and arr.size and arr.dtype.kind not in "iub":
                raise ParameterError(f"Frames: {name} must be integer, got {arr.dtype}")
            arr = np.array(arr, dtype=dtype, copy=True)
            object.__setattr__(self, name, _readonly(arr))
        n = self.radius.shape[0] if self.radius.ndim == 1 else -1
        t = self.time.shape[0] if self.time.ndim == 1 else -1
        m = self.contact_ij.shape[0] if self.contact_ij.ndim == 2 else -1
        h = self.contact_hist.shape[1] if self.contact_hist.ndim == 2 else -1
        sizes = {"N": n, "T": t, "M": m, "T+1": t + 1, "H": h}
        for name, (_, shape) in _SPEC.items():
            want = tuple(sizes[s] if isinstance(s, str) else s for s in shape)
            got = getattr(self, name).shape
            if got != want:
                raise ParameterError(f"Frames: {name} has shape {got}, expected {want} "
                                     f"(N={n}, T={t}, M={m})")
            arr = getattr(self, name)
            if arr.dtype.kind == "f" and not np.all(np.isfinite(arr)):
                raise ParameterError(f"Frames: {name} contains non-finite values")
        if n < 1 or t < 1:
            raise ParameterError(f"Frames: need N >= 1 and T >= 1, got N={n}, T={t}")
        if np.any(self.radius <= 0):
            raise ParameterError("Frames: radius must be > 0")
        if np.any((self.kind < 0) | (self.kind > 2)):
            raise ParameterError("Frames: kind must be 0 (bulk), 1 (bottom), 2 (top)")
        ptr = self.contact_ptr
        if ptr[0] != 0 or ptr[-1] != m or np.any(np.diff(ptr) < 0):
            raise ParameterError(f"Frames: contact_ptr must rise from 0 to M={m} "
                                 f"monotonically, got [{ptr[0]} .. {ptr[-1]}]")
        ij = self.contact_ij
        if m and (np.any(ij[:, 0] < 0) or np.any(ij[:, 0] >= ij[:, 1]) or np.any(ij[:, 1] >= n)):
            raise ParameterError(f"Frames: contact_ij must satisfy 0 <= i < j < N={n}")
        try:
            json.dumps(self.meta)
        except (TypeError, ValueError) as exc:
            raise ParameterError(f"Frames: meta is not JSON-serialisable: {exc}") from None

    @property
    def n_frames(self):
        """Number of frames T."""
        return self.time.shape[0]

    @property
    def n_particles(self):
        """Number of particles N (walls included)."""
        return self.radius.shape[0]

    def contacts(self, k):
        """Contacts of frame ``k``: ``(ij, force, fn, hist, flag)`` (views)."""
        k = frame_index(k, self.n_frames)
        s = slice(self.contact_ptr[k], self.contact_ptr[k + 1])
        return tuple(getattr(self, name)[s] for name in _PER_CONTACT)

    def subset(self, frames):
        """A new :class:`Frames` with the frames ``frames`` (sorted int indices)."""
        return subset_of(self, frames)

    def _frame_kwargs(self, k):
        ij, force, fn, hist, flag = self.contacts(k)
        out = {name: getattr(self, name)[k] for name in _PER_FRAME}
        out.update(contact_ij=ij, contact_force=force, contact_fn=fn, contact_hist=hist,
                   contact_flag=flag)
        return out

    def save(self, path):
        """Write an NPZ atomically (temporary file in the same directory, then rename)."""
        path = Path(path)
        arrays = {name: getattr(self, name) for name in _SPEC}
        header = json.dumps({"format": FORMAT, "lx": self.lx, "meta": self.meta})
        fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
        try:
            with os.fdopen(fd, "wb") as fh:
                np.savez(fh, header=np.array(header), **arrays)
            umask = os.umask(0)
            os.umask(umask)
            os.chmod(tmp, 0o666 & ~umask)
            os.replace(tmp, path)
        finally:
            if os.path.exists(tmp):
                os.unlink(tmp)

    @classmethod
    def load(cls, path):
        """Read a file written by :meth:`save`; ParameterError names the file and the fault."""
        header, arrays = read_arrays(path, _SPEC)
        try:
            return cls(lx=header["lx"], meta=header.get("meta", {}), **arrays)
        except ParameterError as exc:
            raise ParameterError(f"{path}: {exc}") from None

    @classmethod
    def concat(cls, chunks):
        """Join chunks of one run (same particles and lx) in order; time must not decrease."""
        chunks = list(chunks)
        if not chunks:
            raise ParameterError("concat: no chunks given")
        first = chunks[0]
        for c in chunks[1:]:
            if c.lx != first.lx or c.n_particles != first.n_particles or \
                    c.contact_hist.shape[1] != first.contact_hist.shape[1] or not (
                    np.array_equal(c.radius, first.radius) and np.array_equal(c.kind, first.kind)):
                raise ParameterError("concat: chunks differ in lx, particles or histories")
        out = {name: np.concatenate([getattr(c, name) for c in chunks])
               for name in _PER_FRAME + _PER_CONTACT}
        if np.any(np.diff(out["time"]) < 0):
            raise ParameterError("concat: time decreases across chunks (wrong order?)")
        offsets = np.cumsum([0] + [c.contact_ij.shape[0] for c in chunks[:-1]])
        out["contact_ptr"] = np.concatenate(
            [[0]] + [c.contact_ptr[1:] + o for c, o in zip(chunks, offsets)])
        return cls(lx=first.lx, radius=first.radius, mass=first.mass, inertia=first.inertia,
                   kind=first.kind, meta=first.meta, **out)



def read_arrays(path, names):
    """``(header, {name: array})`` of the arrays ``names`` of a frames file.

    Reads only those arrays (an NPZ member is read on access), so the
    per-frame series of a chunk cost a few kB, not its positions and
    contacts; dtypes are checked against the contract.  ParameterError names
    the file for a missing, truncated or foreign one.
    """
    path = Path(path)
    try:
        # Open the file ourselves: np.load leaks the handle of a truncated zip.
        with open(path, "rb") as fh, np.load(fh, allow_pickle=False) as z:
            if "header" not in z.files:
                raise ParameterError(f"{path}: not a fricstab frames file (no header)")
            header = json.loads(str(z["header"]))
            if header.get("format") != FORMAT:
                raise ParameterError(f"{path}: format {header.get('format')!r}, "
                                     f"expected {FORMAT!r}")
            missing = [name for name in names if name not in z.files]
            if missing:
                raise ParameterError(f"{path}: missing arrays {', '.join(missing)}")
            arrays = {name: z[name] for name in names}
    except FileNotFoundError:
        raise ParameterError(f"{path}: no such file") from None
    except (zipfile.BadZipFile, EOFError, OSError, ValueError, KeyError) as exc:
        if isinstance(exc, ParameterError):
            raise
        raise ParameterError(f"{path}: unreadable frames file ({type(exc).__name__}: "
                             f"{exc})") from None
    for name in names:
        if arrays[name].dtype != _SPEC[name][0]:
            raise ParameterError(f"{path}: {name} has dtype {arrays[name].dtype}, "
                                 f"expected {np.dtype(_SPEC[name][0])}")
    return header, arrays


class FrameWriter:
    """Build a :class:`Frames` one frame at a time (lists, converted in :meth:`finish`).

    Parameters
    ----------
    lx : float
        Box length in x.
    radius, mass, inertia : array_like (N,)
    kind : array_like (N,) int
        0 bulk, 1 bottom wall, 2 top wall.
    meta : dict, optional
        JSON-serialisable metadata.
    """

    def __init__(self, lx, radius, mass, inertia, kind, meta=None):
        self._const = {"lx": lx, "radius": np.asarray(radius), "mass": np.asarray(mass),
                           "inertia": np.asarray(inertia), "kind": np.asarray(kind)}
        self.meta = dict(meta or {})
        self._frames = {name: [] for name in _PER_FRAME + _PER_CONTACT}
        self._counts = []

    def __len__(self):
        return len(self._counts)

    def append(self, *, time, strain, normal_force, shear_force, height, pos, angle, vel,
               omega, contact_ij, contact_force, contact_fn, contact_hist, contact_flag,
               tau=None):
        """Add one frame; ``tau`` defaults to ``shear_force / normal_force``.

        ``contact_hist`` (M, H) has the same H in every frame.  Arrays are
        copied, so the caller may reuse its buffers.
        """
        if tau is None:
            if normal_force == 0:
                raise ParameterError("FrameWriter.append: normal_force = 0, tau undefined")
            tau = shear_force / normal_force
        scal = {"time": time, "strain": strain, "normal_force": normal_force,
                    "shear_force": shear_force, "tau": tau, "height": height}
        for name, v in scal.items():
            self._frames[name].append(float(v))
        for name, v in {"pos": pos, "angle": angle, "vel": vel, "omega": omega}.items():
            self._frames[name].append(np.array(v, dtype=np.float64))
        ij = np.array(contact_ij, dtype=np.int64).reshape(-1, 2)
        m = ij.shape[0]
        self._frames["contact_ij"].append(ij)
        self._frames["contact_force"].append(np.array(contact_force, np.float64).reshape(m, 2))
        self._frames["contact_fn"].append(np.array(contact_fn, np.float64).reshape(m))
        flag = np.array(contact_flag).reshape(m)
        if flag.size and flag.dtype.kind not in "iub":
            raise ParameterError(f"FrameWriter.append: contact_flag must be integer, got "
                                 f"{flag.dtype}")
        self._frames["contact_flag"].append(flag.astype(np.int8))
        hist = np.array(contact_hist, np.float64)
        if hist.ndim != 2:
            hist = hist.reshape(m, -1) if m else hist.reshape(0, 0)
        self._frames["contact_hist"].append(hist)
        self._counts.append(m)

    def finish(self):
        """The :class:`Frames` of all appended frames (validated)."""
        if not self._counts:
            raise ParameterError("FrameWriter.finish: no frames appended")
        f = self._frames
        arrays = {name: np.array(f[name]) for name in _PER_FRAME}
        width = max(h.shape[1] for h in f["contact_hist"])
        f["contact_hist"] = [h if len(h) else h.reshape(0, width) for h in f["contact_hist"]]
        for name in _PER_CONTACT:
            arrays[name] = np.concatenate(f[name])
        arrays["contact_ptr"] = np.concatenate([[0], np.cumsum(self._counts)])
        return Frames(meta=self.meta, **self._const, **arrays)


def frame_index(k, n_frames):
    """Frame ``k`` in [0, n_frames) (negative counts from the end); ParameterError if out of range."""
    k = int(k)
    if not -n_frames <= k < n_frames:
        raise ParameterError(f"frame k={k} out of range [0, {n_frames})")
    return k % n_frames


def subset_of(source, frames):
    """A :class:`Frames` of the frames ``frames`` of ``source`` (a Frames or a FrameStore).

    ``source`` gives ``lx``, the per-particle arrays, ``meta``, ``n_frames``
    and ``_frame_kwargs(k)`` (the arrays of frame k as :meth:`FrameWriter.append` takes them).
    """
    idx = np.asarray(frames, dtype=np.int64).ravel()
    if idx.size == 0 or np.any(idx < 0) or np.any(idx >= source.n_frames):
        raise ParameterError(f"subset: indices must lie in [0, {source.n_frames})")
    w = FrameWriter(source.lx, source.radius, source.mass, source.inertia, source.kind,
                    source.meta)
    for k in idx:
        w.append(**source._frame_kwargs(int(k)))
    return w.finish()


def synthetic_frames(n_frames=12, nx=12, ny=8, seed=0, dgamma=1e-3, noise=0.02):
    """A seeded synthetic :class:`Frames` for tests and examples (not a DEM run).

    A jittered triangular lattice of ``nx * ny`` disks of radius 0.5-0.6
    (spacing 1, so neighbours overlap) between a bottom and a top row of wall
    disks (kind 1 and 2), periodic in x with ``lx = nx``.  Each frame applies
    simple shear ``dgamma`` (x += dgamma * y) plus Gaussian noise of
    ``noise * dgamma`` per particle; contacts are overlapping pairs with a
    linear normal force (k = 1) and a random tangential part; tau follows a
    seeded stick-slip saw-tooth.  Positions are unwrapped in x.
    """
    rng = np.random.default_rng(seed)
    rows = ny + 2
    x = (np.arange(nx)[None, :] + 0.5 * (np.arange(rows)[:, None] % 2)).astype(float)
    y = np.broadcast_to(np.arange(rows)[:, None] * np.sqrt(3) / 2, x.shape)
    pos0 = np.column_stack([x.ravel(), y.ravel()])
    n = len(pos0)
    kind = np.zeros(n, np.int8)
    kind[:nx], kind[-nx:] = 1, 2
    pos0[kind == 0] += rng.normal(0.0, 0.03, size=((kind == 0).sum(), 2))
    radius = rng.uniform(0.5, 0.6, n)
    mass = np.pi * radius**2
    lx = float(nx)
    w = FrameWriter(lx, radius, mass, 0.5 * mass * radius**2, kind,
                    meta={"synthetic": True, "seed": seed, "dgamma": dgamma,
                          "law": "lee_hurley", "history": ["ft", "mr"]})
    pos, tau = pos0.copy(), 0.3
    h = pos0[:, 1].max() - pos0[:, 1].min()
    for k in range(n_frames):
        if k:
            step = np.zeros_like(pos)
            step[:, 0] = dgamma * (pos[:, 1] - pos0[:, 1].min())
            step[kind == 0] += rng.normal(0.0, noise * dgamma, size=((kind == 0).sum(), 2))
            step[kind == 1] = 0.0
            pos = pos + step
            tau += 2e-3 if rng.random() < 0.7 else -rng.uniform(1e-4, 5e-3)
        d = pos[None, :, :] - pos[:, None, :]
        d[..., 0] -= lx * np.round(d[..., 0] / lx)
        dist = np.hypot(d[..., 0], d[..., 1])
        ii, jj = np.nonzero(np.triu(dist < radius[:, None] + radius[None, :], 1))
        nrm = d[ii, jj] / dist[ii, jj, None]
        fn = radius[ii] + radius[jj] - dist[ii, jj]
        ft = rng.normal(0.0, 0.2, len(ii)) * fn
        tan = np.column_stack([-nrm[:, 1], nrm[:, 0]])
        w.append(time=float(k), strain=k * dgamma, normal_force=1.0, shear_force=tau,
                 height=h, pos=pos, angle=np.zeros(n), vel=np.zeros((n, 2)),
                 omega=np.zeros(n), contact_ij=np.column_stack([ii, jj]),
                 contact_force=-fn[:, None] * nrm + ft[:, None] * tan, contact_fn=fn,
                 contact_hist=np.column_stack([ft, np.zeros(len(ii))]),
                 contact_flag=np.zeros(len(ii), np.int8))
    return w.finish()


# Keep the documented field order and the spec in step.
assert [f.name for f in fields(Frames)] == ["lx", *_SPEC, "meta"]
