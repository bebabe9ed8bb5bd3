"""Registry of the generated contact laws and validation of their parameters.

Each law is a generated module of :mod:`fricstab.generated` (written by
``python -m symbolic.codegen`` from :mod:`symbolic.laws`); this module wraps
them in a :class:`LawInfo` and checks user input before it reaches a kernel.

Sign and coordinate conventions are those of the generated modules' docstrings:
Jacobian blocks are ``K = dF/dq`` (Charan's sign).  Ishima's Jacobian
(Ishima Eq. 18) is ``-K`` in the coordinates (x, y, l = d theta/2).
"""

import importlib
import math
from dataclasses import dataclass

from fricstab.generated import CAPPED_LAW_NAMES, LAW_NAMES

__all__ = ["CAPPED_LAW_NAMES", "LAW_NAMES", "LawInfo", "ParameterError", "check_parameters", "evaluate", "get_law"]


class ParameterError(ValueError):
    """Bad user input; the message names the parameter."""


@dataclass(frozen=True)
class LawInfo:
    """A generated contact law: metadata and its numba kernels."""

    name: str
    kind: str  # "pair" or "wall"
    inputs: tuple
    coords: tuple
    outputs: tuple
    history: tuple
    coulomb: bool
    force: object
    force_jacobian: object
    increment: object  # None for frictionless laws
    assemble: object

    @property
    def n_dof(self):
        """Degrees of freedom per particle (2 frictionless, 3 frictional)."""
        return len(self.coords) // (2 if self.kind == "pair" else 1)

    @property
    def params(self):
        """Material parameters among the inputs, in kernel order."""
        return tuple(a for a in self.inputs if a in ("kn", "kt", "mu", "E", "nu", "mus", "mur"))


_CACHE = {}


def get_law(name):
    """The :class:`LawInfo` of law ``name``; ParameterError if unknown.

    ``name`` is one of :data:`LAW_NAMES` or :data:`CAPPED_LAW_NAMES`
    (``lee_hurley``, verified by :mod:`fricstab.laws.verify_lee_hurley`).
    """
    if name not in LAW_NAMES + CAPPED_LAW_NAMES:
        raise ParameterError(f"unknown law {name!r}; known laws: "
                             f"{', '.join(LAW_NAMES + CAPPED_LAW_NAMES)}")
    if name not in _CACHE:
        mod = importlib.import_module(f"fricstab.generated.{name}")
        _CACHE[name] = LawInfo(
            name=name, kind=mod.KIND, inputs=mod.INPUTS, coords=mod.COORDS,
            outputs=mod.OUTPUTS, history=mod.HISTORY, coulomb=mod.COULOMB,
            force=getattr(mod, f"{name}_force"),
            force_jacobian=getattr(mod, f"{name}_force_jacobian"),
            increment=getattr(mod, f"{name}_increment", None),
            assemble=getattr(mod, f"{name}_assemble"))
    return _CACHE[name]


_POSITIVE = ("kn", "kt", "mu", "R", "Ri", "Rj", "radius", "E", "mus")
#: Closed-open ranges ``[lo, hi)`` of bounded parameters (Poisson ratio: Lai's
#: k_t has nu/(2(1 - nu)); rolling friction may be 0: no rolling resistance).
_RANGES = {"nu": (0.0, 0.5), "mur": (0.0, float("inf"))}


def check_parameters(**values):
    """Raise ParameterError naming the first bad parameter.

    Radii, stiffnesses, E* and the friction coefficients mu, mus must be
    finite and > 0; nu in [0, 0.5); mur >= 0; every other value finite.
    """
    for key, v in values.items():
        try:
            x = float(v)
        except (TypeError, ValueError):
            raise ParameterError(f"{key} must be a number, got {v!r}") from None
        if not math.isfinite(x):
            raise ParameterError(f"{key} must be finite, got {v!r}")
        if key in _POSITIVE and x <= 0.0:
            raise ParameterError(f"{key} must be > 0, got {v!r}")
        if key in _RANGES and not _RANGES[key][0] <= x < _RANGES[key][1]:
            lo, hi = _RANGES[key]
            raise ParameterError(f"{key} must be in [{lo:g}, {hi:g}), got {v!r}")


def evaluate(name, **inputs):
    """Forces and Jacobian block of one contact, with the inputs checked.

    ``inputs`` are the law's kernel arguments by name (``fricstab laws`` and
    ``get_law(name).inputs`` list them), e.g. for ``charan``:
    ``dx, dy, Ri, Rj, kn, kt, mu, tx, ty``.  Returns ``(f, jac)`` as float64
    arrays; raises :class:`ParameterError` naming a missing, unknown or bad
    argument (radii, stiffnesses and mu must be > 0, everything finite).
    """
    import numpy as np

    law = get_law(name)
    missing = [k for k in law.inputs if k not in inputs]
    unknown = [k for k in inputs if k not in law.inputs]
    if missing:
        raise ParameterError(f"{name}: missing argument {missing[0]!r}; needs {', '.join(law.inputs)}")
    if unknown:
        raise ParameterError(f"{name}: unknown argument {unknown[0]!r}; takes {', '.join(law.inputs)}")
    check_parameters(**inputs)
    if law.kind == "pair" and inputs["dx"] == 0 and inputs["dy"] == 0:
        raise ParameterError("dx, dy: coincident centres have no contact normal")
    f = np.empty(len(law.outputs))
    jac = np.empty((len(law.outputs), len(law.coords)))
    law.force_jacobian(*(float(inputs[k]) for k in law.inputs), f, jac)
    return f, jac
