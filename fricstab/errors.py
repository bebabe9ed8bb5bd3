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

import numpy as np

__all__ = ["EXIT_NUMERICAL", "ConvergenceError", "NumericalError", "ParameterError",
           "check_finite"]

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
