"""The errors fricstab raises, and the guard against silent NaN and inf.

* :class:`ParameterError`: bad user input; the message names the parameter
  (exit status 2 on the command line).
* :class:`ConvergenceError`: an iterative step did not reach its tolerance
  (exit status 4).
* :class:`NumericalError`: NaN or inf in a computed quantity (exit status 4).

:class:`NumericalError` carries the step, the item (a particle, a contact
or a mode) and the quantity; the command line prints its message, says where
the last checkpoint is, and exits with :data:`EXIT_NUMERICAL` (4, the code
of numerical failure and non-convergence).
"""

import math

import numpy as np

__all__ = ["EXIT_NUMERICAL", "ConvergenceError", "NumericalError", "ParameterError",
           "check_bool", "check_finite", "check_finite_array", "check_instance", "check_int",
           "check_real", "check_state", "check_steps"]

#: The most steps a front-door call takes (a ramp's F_x steps, a run's time steps):
#: more is refused up front as an input that cannot finish.
MAX_STEPS = 10**10

EXIT_NUMERICAL = 4


class ParameterError(ValueError):
    """Bad user input; the message names the parameter, the value and what is allowed.

    Raised before any work is done; the command line prints the message on one
    line (``fricstab: error: ...``) and exits with status 2.  A subclass of
    :class:`ValueError`.
    """


class ConvergenceError(RuntimeError):
    """An iterative step of a protocol did not reach its tolerance.

    Raised by Newton, FIRE and damped relaxations and by the ramp (a step
    without equilibrium); the message names the step (e.g. the F_x), the
    residual and the iterations.  The command line exits with status 4.  A
    subclass of :class:`RuntimeError`.
    """

    exit_code = EXIT_NUMERICAL


class NumericalError(ArithmeticError):
    """NaN or inf in a computed quantity (exit status 4).

    Parameters
    ----------
    message : str
        What became non-finite, and where.
    step : int, optional
        The step (Verlet step, Newton iteration, frame) at which it happened.
    item : int, optional
        The particle, contact or mode concerned.
    quantity : str, optional
        The quantity's name (e.g. ``"force"``, ``"position"``, ``"overlap"``).
    """

    exit_code = EXIT_NUMERICAL

    def __init__(self, message, *, step=None, item=None, quantity=None):
        super().__init__(message)
        self.step = step
        self.item = item
        self.quantity = quantity


def check_finite(quantity, array, *, step=None, item="particle", components=None,
                 labels=None):
    """Raise :class:`NumericalError` at the first non-finite entry of ``array``.

    Parameters
    ----------
    quantity : str
        What ``array`` holds, e.g. ``"force"``, ``"energy"``, ``"eigenvalue"``.
    array : array_like
        Shape (n,) or (n, k): row = item (particle, contact, mode), column = component.
    step : int, optional
        The step of the run, named in the message.
    item : str
        The word for a row (``"particle"``, ``"contact"``, ``"mode"``).
    components : sequence of str, optional
        Names of the columns (e.g. ``("F_x", "F_y", "T")``).
    labels : sequence, optional
        Names of the rows (e.g. the pair ``(i, j)`` of a contact); default the row index.
    """
    a = np.asarray(array)
    if a.size == 0:
        return
    bad = ~np.isfinite(a)
    if not bad.any():
        return
    flat = int(np.flatnonzero(bad.ravel())[0])
    idx = np.unravel_index(flat, a.shape) if a.ndim else ()
    row = int(idx[0]) if len(idx) else 0
    col = int(idx[1]) if len(idx) > 1 else None
    value = a.ravel()[flat]
    comp = f" {components[col]}" if components is not None and col is not None \
        else (f"[{', '.join(str(int(i)) for i in idx[1:])}]" if len(idx) > 1 else "")
    who = labels[row] if labels is not None else row
    where = f" at step {step}" if step is not None else ""
    count = int(bad.sum())
    more = f" ({count} non-finite entries)" if count > 1 else ""
    raise NumericalError(f"non-finite {quantity}{comp} = {value} of {item} {who}{where}{more}",
                         step=step, item=who, quantity=quantity)


# ---------------------------------------------------------------- input checks
# The front door's rule (docs/reference/engine.md, "Input checks"): every public
# function checks its arguments before any work and raises ParameterError with one
# line naming the parameter, its value and what is allowed.  Numbers are Python or
# numpy reals (np.float32, np.int64 are numbers; bool is not); the checks return
# the value unchanged, so a valid call computes exactly what it did before.

def _show(value):
    text = repr(value)
    return text if len(text) <= 60 else text[:57] + "..."


def _is_real(value):
    return isinstance(value, (int, float, np.integer, np.floating)) and not isinstance(value, bool)


def _range_text(low, high, low_open, high_open):
    parts = []
    if low is not None:
        parts.append(f"{'>' if low_open else '>='} {low:g}")
    if high is not None:
        parts.append(f"{'<' if high_open else '<='} {high:g}")
    return " and ".join(parts)


def check_real(name, value, low=None, high=None, *, low_open=False, high_open=False,
               allow_none=False):
    """Check that ``value`` is a finite real number in the range; return it unchanged.

    ``low``/``high`` are inclusive unless ``low_open``/``high_open``; ``None``
    passes only with ``allow_none``.  Raises :class:`ParameterError` naming
    ``name``, the value and the range.
    """
    if value is None and allow_none:
        return value
    ok = _is_real(value) and math.isfinite(value)
    if ok and low is not None:
        ok = value > low if low_open else value >= low
    if ok and high is not None:
        ok = value < high if high_open else value <= high
    if not ok:
        rng = _range_text(low, high, low_open, high_open)
        raise ParameterError(f"{name} must be a finite number{' ' + rng if rng else ''}"
                             f"{' (or None)' if allow_none else ''}, got {_show(value)}")
    return value


def check_int(name, value, low=None, high=None, *, allow_none=False):
    """Check that ``value`` is an integer (Python or numpy, not bool) in ``[low, high]``."""
    if value is None and allow_none:
        return value
    ok = isinstance(value, (int, np.integer)) and not isinstance(value, bool)
    ok = ok and (low is None or value >= low) and (high is None or value <= high)
    if not ok:
        rng = _range_text(low, high, False, False)
        raise ParameterError(f"{name} must be an integer{' ' + rng if rng else ''}"
                             f"{' (or None)' if allow_none else ''}, got {_show(value)}")
    return value


def check_bool(name, value):
    """Check that ``value`` is a bool (Python or numpy)."""
    if not isinstance(value, (bool, np.bool_)):
        raise ParameterError(f"{name} must be True or False, got {_show(value)}")
    return value


def check_instance(name, value, types, what=None):
    """Check ``isinstance(value, types)``; ``what`` names the allowed kind in the message."""
    if not isinstance(value, types):
        if what is None:
            tt = types if isinstance(types, tuple) else (types,)
            what = " or ".join(t.__name__ for t in tt)
        raise ParameterError(f"{name} must be {what}, got {type(value).__name__} "
                             f"{_show(value)}")
    return value


def check_finite_array(name, value, *, ndim=None, shape=None, allow_none=False,
                       complex_ok=False):
    """Check an array of finite real numbers (O(n)); return it unchanged.

    ``shape`` may hold ``None`` for a free axis.  Complex, object, string and
    bool arrays (complex ones unless ``complex_ok``), non-finite entries and a
    wrong shape raise :class:`ParameterError`.
    """
    if value is None and allow_none:
        return value
    try:
        a = np.asarray(value)
    except Exception:   # ragged lists and the like
        raise ParameterError(f"{name} must be an array of finite numbers, got "
                             f"{type(value).__name__}") from None
    if a.dtype.kind not in ("iufc" if complex_ok else "iuf"):
        raise ParameterError(f"{name} must be an array of finite {'' if complex_ok else 'real '}"
                             f"numbers, got "
                             f"{type(value).__name__} of dtype {a.dtype}")
    if ndim is not None and a.ndim != ndim:
        raise ParameterError(f"{name} must have {ndim} dimension(s), got shape {a.shape}")
    if shape is not None and (a.ndim != len(shape) or any(
            s is not None and s != t for s, t in zip(shape, a.shape))):
        want = "(" + ", ".join("n" if s is None else str(s) for s in shape) + ")"
        raise ParameterError(f"{name} must have shape {want}, got {a.shape}")
    if a.dtype.kind in "fc" and a.size and not np.isfinite(a).all():
        bad = int(np.flatnonzero(~np.isfinite(a.ravel()))[0])
        where = tuple(int(i) for i in np.unravel_index(bad, a.shape))
        raise ParameterError(f"{name} must be finite: entry {where} is {a.ravel()[bad]}")
    return value


def check_state(name, state, state_type, n=None):
    """Check an engine State (``state_type``): finite ``q`` and ``v``, ``n`` rows if given."""
    check_instance(name, state, state_type, f"a {state_type.__name__}")
    shape = None if n is None else (n, None)
    check_finite_array(f"{name}.q", state.q, ndim=2, shape=shape)
    check_finite_array(f"{name}.v", state.v, ndim=2, shape=shape)
    return state


def check_steps(name, count, limit=MAX_STEPS):
    """Refuse a call that would take ``count`` steps (a float, maybe inf) beyond ``limit``."""
    if not count <= limit:
        raise ParameterError(f"{name}: {count:.3g} steps, more than the {limit:.0e} a call "
                             "may take; use a larger step or a shorter range")
    return count

