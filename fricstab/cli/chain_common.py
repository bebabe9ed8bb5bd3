"""Helpers shared by the chain commands (:mod:`fricstab.cli.chain`, :mod:`fricstab.cli.chain_waves`):
the scene from the command line, refusals, the fingerprint, the result directory, the record."""

import json

from fricstab.laws import ParameterError, get_law

PAPER_TIME_UNIT = "sqrt(m 2R / kn)"


MAX_RAMP_STEPS = 1_000_000        # ramp/equilibrium steps of F_x: beyond this, refuse
MAX_VERLET_STEPS = 2_000_000_000  # dynamics: beyond this (hours), refuse
DEFAULT_CHECKPOINT_EVERY = 50_000  # Verlet steps between checkpoints of `chain dynamics`


def _finite_float(text):
    import argparse
    import math
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"must be a number, got {text!r}") from None
    if not math.isfinite(value):
        raise argparse.ArgumentTypeError(f"must be a finite number, got {text!r}")
    return value


def _count(text):
    import argparse
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"must be an integer, got {text!r}") from None
    return value


def _scene(ns, fx=None):
    """The scene (F_x = ``fx``, or the file's) from the scene file, then the command line.

    Validated before any work, the law's refusals included (with ``fx``).
    """
    from fricstab.io.scenes import law_overrides
    from fricstab.scenes.chain_io import scene_from_values, scene_parameters
    overrides = {"n": ns.n, "fy": ns.fy, "mu": ns.mu, "inertia": ns.inertia, "fx": fx}
    overrides.update({k: v for k, v in law_overrides(ns).items() if v is not None})
    return scene_from_values(scene_parameters(ns.scene, **overrides))


def _scene_dict(scene):
    return {**{k: getattr(scene, k) for k in ("n", "radius", "mass", "fy", "inertia", "law")},
            **scene.params, **scene.wall_params}


def _capped(scene, command):
    if not get_law(scene.law).capped:
        raise ParameterError(f"law {scene.law}: {command} measures Coulomb breaching and "
                             "sliding, but this law has no Coulomb cap (use charan or "
                             "lee_hurley)")


def _check_ramp_steps(value, step, flag):
    steps = abs(value) / step
    if steps > MAX_RAMP_STEPS:
        raise ParameterError(f"{flag} / --step = {steps:.3g} ramp steps; at most "
                             f"{MAX_RAMP_STEPS:.0e} (raise --step)")


def _dry_run(ns, scene, extra):
    """--dry-run: print the resolved parameters as JSON and stop."""
    from fricstab.io.results import json_clean
    doc = {"scene": _scene_dict(scene), **extra}
    print(json.dumps(json_clean(doc), indent=2, allow_nan=False))
    return 0


#: Protocol options that change how a run is computed, never its output: not fingerprinted.
_NOT_FINGERPRINTED = ("scheduler", "workers", "checkpoint_every")


def _fingerprint(scene, protocol):
    """Every parameter that fixes a command's output, flat (a refusal names the parameter).

    The validated scene (its law and the law's parameters included) and the
    protocol options, less :data:`_NOT_FINGERPRINTED`.
    """
    return {**_scene_dict(scene),
            **{k: v for k, v in protocol.items() if k not in _NOT_FINGERPRINTED}}


def _result_dir(ns, name, outputs, scene, protocol):
    """The command's :class:`ResultDir`, fingerprinted by :func:`_fingerprint`."""
    from fricstab.io.results import ResultDir
    return ResultDir(ns.out, name, force=ns.force, resume=getattr(ns, "resume", False),
                     resumable=hasattr(ns, "resume"), outputs=outputs,
                     fingerprint=_fingerprint(scene, protocol))


def _meta(scene, ns, seconds):
    """Keys of the record common to the chain commands (before the provenance)."""
    from fricstab.scenes.chain import time_unit
    return {"scene": _scene_dict(scene), "paper_time_unit": PAPER_TIME_UNIT,
            "paper_time_unit_sim": time_unit(scene)}


def _finish(rd, doc, scene, ns, argv, extra_params):
    params = {**_scene_dict(scene), **extra_params}
    return rd.finish(doc, parameters=params, seed=getattr(ns, "seed", None), argv=argv)


def _ramped_equilibrium(scene, fx, step):
    """Newton ramp from 0 to ``fx`` in steps <= ``step`` (ConvergenceError: exit 4)."""
    from fricstab.errors import check_finite
    from fricstab.protocols.ramp import ramped_equilibrium
    state = ramped_equilibrium(scene, fx, step)
    check_finite("equilibrium position", state.q, item="disk", components=("x", "y", "theta"))
    return state
