"""Trajectory export for OVITO and LAMMPS tools: extended XYZ and LAMMPS text dumps.

Generic over any 2D disk system (plane shear, chain, packings).  Inputs are
positions ``pos (T, N, 2)`` or ``(N, 2)`` (one frame), ``radius (N,)`` and,
optionally, ``angle (T, N)``, ``vel (T, N, 2)``, ``omega (T, N)``,
``kind (N,)`` ints (written as particle types), ``box`` (lx, ly) or
(T, 2) per frame, and ``time (T,)``.  2D data get z = 0 (and v_z = 0).
Units are those of the inputs; nothing is converted.

Column names are those OVITO maps to its standard properties without a
column mapping:

* extxyz: ``species`` (Particle Type: ``K0``, ``K1``, ...), ``pos``
  (Position), ``radius`` (Radius), ``velo`` (Velocity), ``omega``
  (Angular Velocity), ``angle`` (user property); ``Lattice`` with the box
  and ``pbc="T F F"`` (periodic in x), ``Time`` per frame.
* LAMMPS dump: ``id type x y z radius vx vy vz omegaz angle``; ids start at
  1, types are ``kind + 1``; box bounds ``pp ff pp`` from ``box`` (or, when
  not given, the extent of the disks).

Files are written atomically (temporary file in the same directory, then
renamed).  fricstab does not import OVITO; tests load the files with it.
"""

import numpy as np

from fricstab.io.files import atomic_write
from fricstab.laws import ParameterError

__all__ = ["frames_to_ovito", "write_extxyz", "write_lammps_dump"]


def _prepare(pos, radius, angle, vel, omega, kind, box, time):
    pos = np.asarray(pos, dtype=np.float64)
    if pos.ndim == 2:
        pos = pos[None]
        angle = None if angle is None else np.asarray(angle, float)[None]
        vel = None if vel is None else np.asarray(vel, float)[None]
        omega = None if omega is None else np.asarray(omega, float)[None]
    if pos.ndim != 3 or pos.shape[2] != 2:
        raise ParameterError(f"export: pos must be (T, N, 2) or (N, 2), got {pos.shape}")
    T, N, _ = pos.shape
    radius = np.asarray(radius, dtype=np.float64)
    if radius.shape != (N,):
        raise ParameterError(f"export: radius has shape {radius.shape}, expected ({N},)")
    out = {"pos": pos, "radius": radius}
    for name, arr, shape in (("angle", angle, (T, N)), ("vel", vel, (T, N, 2)),
                             ("omega", omega, (T, N))):
        if arr is not None:
            arr = np.asarray(arr, dtype=np.float64)
            if arr.shape != shape:
                raise ParameterError(f"export: {name} has shape {arr.shape}, expected {shape}")
        out[name] = arr
    kind = np.zeros(N, np.int64) if kind is None else np.asarray(kind)
    if kind.shape != (N,) or kind.dtype.kind not in "iu" or np.any(kind < 0):
        raise ParameterError(f"export: kind must be (N,) = ({N},) non-negative ints")
    out["kind"] = kind.astype(np.int64)
    if box is not None:
        box = np.asarray(box, dtype=np.float64)
        box = np.broadcast_to(box, (T, 2)) if box.shape == (2,) else box
        if box.shape != (T, 2) or np.any(box <= 0):
            raise ParameterError(f"export: box must be (lx, ly) or (T, 2) positive, got "
                                 f"shape {box.shape}")
    out["box"] = box
    time = np.arange(T, dtype=np.float64) if time is None else np.asarray(time, float)
    if time.shape != (T,):
        raise ParameterError(f"export: time has shape {time.shape}, expected ({T},)")
    out["time"] = time
    for name, arr in out.items():
        if arr is not None and arr.dtype.kind == "f" and not np.all(np.isfinite(arr)):
            raise ParameterError(f"export: {name} contains non-finite values")
    return out


def _fmt(x):
    return np.char.mod("%.17g", x)


def write_extxyz(path, pos, radius, *, angle=None, vel=None, omega=None, kind=None,
                 box=None, time=None):
    """Write an extended-XYZ trajectory (one block per frame) that OVITO reads.

    Parameters
    ----------
    path : str or Path
    pos : array_like (T, N, 2) or (N, 2)
    radius : array_like (N,)
    angle, omega : array_like (T, N), optional
    vel : array_like (T, N, 2), optional
    kind : array_like (N,) int, optional
        Written as species ``K<kind>``.
    box : (lx, ly) or array_like (T, 2), optional
        The cell; the z extent is 1.
    time : array_like (T,), optional
    """
    d = _prepare(pos, radius, angle, vel, omega, kind, box, time)
    T, N, _ = d["pos"].shape
    props = ["species:S:1", "pos:R:3", "radius:R:1"]
    if d["vel"] is not None:
        props.append("velo:R:3")
    if d["omega"] is not None:
        props.append("omega:R:3")
    if d["angle"] is not None:
        props.append("angle:R:1")
    species = np.char.add("K", d["kind"].astype(str))
    zeros = np.zeros(N)

    def write(tmp):
        with open(tmp, "w") as fh:
            for k in range(T):
                cols = [species, _fmt(d["pos"][k, :, 0]), _fmt(d["pos"][k, :, 1]),
                        _fmt(zeros), _fmt(d["radius"])]
                if d["vel"] is not None:
                    cols += [_fmt(d["vel"][k, :, 0]), _fmt(d["vel"][k, :, 1]), _fmt(zeros)]
                if d["omega"] is not None:
                    cols += [_fmt(zeros), _fmt(zeros), _fmt(d["omega"][k])]
                if d["angle"] is not None:
                    cols.append(_fmt(d["angle"][k]))
                header = f'Properties={":".join(props)} Time={d["time"][k]:.17g}'
                if d["box"] is not None:
                    lx, ly = d["box"][k]
                    header = (f'Lattice="{lx:.17g} 0 0 0 {ly:.17g} 0 0 0 1" '
                              f'pbc="T F F" ' + header)
                fh.write(f"{N}\n{header}\n")
                fh.write("\n".join(" ".join(row) for row in zip(*cols)))
                fh.write("\n")

    atomic_write(path, write)


def write_lammps_dump(path, pos, radius, *, angle=None, vel=None, omega=None, kind=None,
                      box=None, time=None):
    """Write a LAMMPS text dump (``id type x y z radius vx vy vz omegaz angle``).

    Same arguments as :func:`write_extxyz`; the TIMESTEP of frame k is k (the
    physical time is not an integer), types are ``kind + 1``, the box is
    ``[0, lx] x [0, ly]`` when given, else the extent of the disks.  Missing
    velocities, spins and angles are written as 0.
    """
    d = _prepare(pos, radius, angle, vel, omega, kind, box, time)
    T, N, _ = d["pos"].shape
    ids = np.arange(1, N + 1).astype(str)
    types = (d["kind"] + 1).astype(str)
    zeros = np.zeros(N)

    def write(tmp):
        with open(tmp, "w") as fh:
            for k in range(T):
                p = d["pos"][k]
                if d["box"] is not None:
                    lo, hi = np.zeros(2), d["box"][k]
                else:
                    lo = (p - d["radius"][:, None]).min(axis=0)
                    hi = (p + d["radius"][:, None]).max(axis=0)
                vel = d["vel"][k] if d["vel"] is not None else np.zeros((N, 2))
                om = d["omega"][k] if d["omega"] is not None else zeros
                ang = d["angle"][k] if d["angle"] is not None else zeros
                fh.write(f"ITEM: TIMESTEP\n{k}\nITEM: NUMBER OF ATOMS\n{N}\n"
                         f"ITEM: BOX BOUNDS pp ff pp\n{lo[0]:.17g} {hi[0]:.17g}\n"
                         f"{lo[1]:.17g} {hi[1]:.17g}\n-0.5 0.5\n"
                         "ITEM: ATOMS id type x y z radius vx vy vz omegaz angle\n")
                cols = [ids, types, _fmt(p[:, 0]), _fmt(p[:, 1]), _fmt(zeros),
                        _fmt(d["radius"]), _fmt(vel[:, 0]), _fmt(vel[:, 1]), _fmt(zeros),
                        _fmt(om), _fmt(ang)]
                fh.write("\n".join(" ".join(row) for row in zip(*cols)))
                fh.write("\n")

    atomic_write(path, write)


def frames_to_ovito(frames, path, fmt="extxyz"):
    """Export a :class:`fricstab.io.frames.Frames` (box = (lx, height), time).

    ``fmt`` is ``"extxyz"`` or ``"lammps"``; the wall kinds become types.
    """
    writers = {"extxyz": write_extxyz, "lammps": write_lammps_dump}
    if fmt not in writers:
        raise ParameterError(f"frames_to_ovito: fmt = {fmt!r}; allowed: extxyz, lammps")
    box = np.column_stack([np.full(frames.n_frames, frames.lx), frames.height])
    writers[fmt](path, frames.pos, frames.radius, angle=frames.angle, vel=frames.vel,
                 omega=frames.omega, kind=frames.kind, box=box, time=frames.time)
