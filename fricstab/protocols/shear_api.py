"""``fricstab.run_shear``: Lee & Hurley's plane-shear cell in one call (the front door).

The protocol of ``fricstab shear run`` without the result directory: the
parameters resolved as the command line resolves them (the preset, then the
scene file, then the keyword arguments; :func:`fricstab.cli.shear.resolve_params`),
the cell placed (:func:`fricstab.scenes.shear.make_cell`), compressed under
the servo (:func:`fricstab.protocols.shear_run.prepare`) and sheared frame by
frame (:class:`fricstab.protocols.shear_run.ShearRun`), in the same order of
operations, so that its series equal those of a :class:`ShearRun` driven by
hand to the bit.  The series come back as named arrays in SI per unit
thickness (:class:`ShearResult`); the run itself (``result.run``) can be
advanced further.
"""

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from fricstab.errors import ParameterError, check_bool, check_instance

__all__ = ["ShearResult", "run_shear"]


@dataclass(frozen=True)
class ShearResult:
    """The series of one shear run, one entry per output frame (frame 0: the sheared start).

    SI per unit thickness.  ``gamma`` [-] shear strain (top-wall x
    displacement / h0); ``shear_stress`` and ``normal_stress`` [Pa] the force
    on the top row S and N divided by the box length lx; ``tau`` [-] = S / N;
    ``time`` [s] since shearing started; ``servo_error`` [-] = N / N_target - 1;
    ``height`` [m] between the wall-row centre lines.  ``run`` is the
    :class:`~fricstab.protocols.shear_run.ShearRun` at the last frame (its
    ``state`` and ``system``, reduced units; ``run.advance`` continues);
    ``params`` the validated scene parameters; ``frames`` the
    :class:`~fricstab.io.frames.Frames` (positions, contacts) with
    ``keep_frames=True``, else None.
    """

    gamma: np.ndarray
    shear_stress: np.ndarray
    normal_stress: np.ndarray
    tau: np.ndarray
    time: np.ndarray
    servo_error: np.ndarray
    height: np.ndarray
    run: object
    params: dict
    steps_per_frame: int
    dt: float
    normal_force_target: float
    prepare: dict
    frames: object = None

    @property
    def state(self):
        """The final engine :class:`~fricstab.engine.State` (reduced units)."""
        return self.run.state


def _check_scene(scene):
    if scene is None:
        return None
    check_instance("scene", scene, (str, Path), "a path to a scene file (.toml) or None")
    if not Path(scene).is_file():
        raise ParameterError(f"scene: no scene file at {scene}")
    return scene


def run_shear(scene=None, *, preset="quick", progress=False, keep_frames=False, **params):
    """Prepare and shear Lee & Hurley's plane-shear cell; the series as named arrays.

    The protocol of ``fricstab shear run`` (Lee & Hurley Sec. 2-3): disks
    placed at random (seeded) between a fixed bottom row and a rigid top row,
    compressed under the servo until the normal force N and the kinetic energy
    settle, then sheared at V = I h0 sqrt(P/rho)/d with the servo holding N,
    one output frame every ``dgamma`` of strain up to ``strain``.  Nothing is
    written to disk.

    Parameters
    ----------
    scene : str or Path, optional
        A scene file (TOML, ``fricstab scene show shear``); its keys override
        the preset.
    preset : {"quick", "paper", "large"}
        Base parameters (``fricstab shear run --preset``): ``quick`` (300
        disks, strain 0.06: minutes), ``paper`` (Sec. 2: hours), ``large``
        (Sec. 5).
    progress : bool
        Show a progress bar of the frames on stderr.
    keep_frames : bool
        Also keep every frame (positions, velocities, contacts) as
        ``result.frames`` (:class:`fricstab.io.frames.Frames`, for
        :func:`fricstab.analyze_shear`); memory ~ frames x disks.
    **params
        Scene keys in SI per unit thickness, overriding the scene file: e.g.
        ``n`` (bulk disks), ``r_min``, ``r_max`` [m], ``modulus`` (E*) [Pa],
        ``inertial_number`` I [-], ``kappa`` = E*/P [-], ``strain`` and
        ``dgamma`` [-], ``seed``; ``law`` and the law's parameters
        (``lee_hurley``: ``E`` [Pa], ``nu``, ``mus``, ``mur``).

    Returns
    -------
    ShearResult
        ``gamma``, ``shear_stress`` and ``normal_stress`` [Pa], ``tau`` = S/N,
        ``time`` [s], ``servo_error`` = N/N_target - 1, ``height`` [m] per
        frame (``strain / dgamma + 1`` frames), the final ``run`` and
        ``state``, ``params``, ``steps_per_frame``, ``dt`` [s],
        ``normal_force_target`` [N/m], the ``prepare`` statistics and
        ``frames`` (with ``keep_frames``).

    Raises
    ------
    ParameterError
        An unknown key, a value out of range or of the wrong type, naming it.
    NumericalError
        A non-finite state or an overlap outside the law's domain (reduce
        ``dt_frac``).
    ConvergenceError
        The preparation did not settle within ``prep_max_steps``.
    """
    from fricstab.cli.shear import PRESETS, resolve_params
    if preset not in PRESETS:
        raise ParameterError(f"preset must be one of {', '.join(PRESETS)}, got {preset!r}")
    check_bool("progress", progress)
    check_bool("keep_frames", keep_frames)
    p = resolve_params(_check_scene(scene), preset, params)
    return _shear(p, progress, keep_frames)


def _shear(p, progress, keep_frames):
    """The loop of ``shear run`` on validated parameters ``p``."""
    from fricstab import progress as say
    from fricstab.cli.shear import SERIES
    from fricstab.protocols.shear_run import FRAME, SPF, ShearRun, prepare
    from fricstab.scenes.shear import make_cell

    cell = make_cell(p)
    sim = ShearRun(cell)
    prep = prepare(sim)
    sim.start_shear()
    spf = int(sim.scalars[SPF])
    n_frames = int(round(p["strain"] / p["dgamma"]))
    writer = _writer(cell) if keep_frames else None
    rows = []

    def take():
        fr = sim.frame()
        rows.append([fr[key] for key in SERIES])
        if writer is not None:
            writer.append(**fr)

    take()
    with say.bar(total=n_frames, enabled=progress, desc="shear", unit="frame") as bar:
        for k in range(1, n_frames + 1):
            sim.advance(spf)
            sim.scalars[FRAME] = k
            take()
            bar.update(1)
    t, gamma, nf, sf, tau, h = np.array(rows).T   # the order of SERIES
    u = cell.units
    lx, nt = cell.lx * u.length, cell.n_target * u.force
    return ShearResult(gamma=gamma, shear_stress=sf / lx, normal_stress=nf / lx, tau=tau,
                       time=t, servo_error=nf / nt - 1.0, height=h, run=sim, params=p,
                       steps_per_frame=spf, dt=sim.dt * u.time, normal_force_target=nt,
                       prepare=prep, frames=writer.finish() if writer is not None else None)


def _writer(cell):
    from fricstab.io.frames import FrameWriter
    u = cell.units
    return FrameWriter(cell.lx * u.length, cell.radius * u.length, cell.mass * u.mass,
                       cell.inertia * u.mass * u.length ** 2, cell.kind)
