"""Registry of the generated contact laws and validation of their parameters.

Each law is a generated module of :mod:`fricstab.generated` (written by
``python -m symbolic.codegen`` from :mod:`symbolic.laws`); this module wraps
them in a :class:`LawInfo` and checks user input before it reaches a kernel.

Sign and coordinate conventions are those of the generated modules' docstrings:
Jacobian blocks are ``K = dF/dq`` (Charan's sign).  Ishima's Jacobian
(Ishima Eq. 18) is ``-K`` in the coordinates (x, y, l = d theta/2).

Sixteen laws, eight pair laws and their wall forms (the last three pairs the
frame-indifferent ``_fi`` forms, :data:`FRAME_INDIFFERENT`) (:data:`PAIR_LAW_NAMES`,
:data:`WALL_LAW_NAMES`; a pair law and its wall form share the integer id
:func:`law_id` of :mod:`fricstab.generated.dispatch`).  Every law has the
uniform kernels ``eval``, ``rate``, ``project``, ``advance`` (one calling
convention: geometry ``dx, dy, Ri, Rj`` or ``y, R``, the parameter array ``p``
in ``params`` order, the history row ``h``; a pair's ``advance`` also takes
``r, delta, lam`` from :func:`fricstab._numerics.pair_geometry`, see
:attr:`LawInfo.advance_geometry_args`; see :mod:`symbolic.codegen`) and
the scalar kernels the verification harnesses differentiate.
"""

import importlib
import math
from dataclasses import dataclass

from fricstab.errors import ParameterError
from fricstab.generated import dispatch
from fricstab.generated import (ALL_LAW_NAMES, CAPPED_LAW_NAMES, LAW_NAMES, PAIR_LAW_NAMES,
                                WALL_LAW_NAMES)

__all__ = ["ALL_LAW_NAMES", "CAPPED_LAW_NAMES", "FRAME_INDIFFERENT", "LAW_NAMES", "LawInfo",
           "PAIR_LAW_NAMES", "ParameterError", "WALL_LAW_NAMES", "check_parameters", "evaluate",
           "get_law", "law_id", "vector_form"]

#: The pair laws with a lab-frame vector history; each has a frame-indifferent
#: form ``<law>_fi`` (scalar history along the tangent, symbolic/frame.py) and
#: its wall partner ``<law>_fi_wall`` (the physics of ``<law>_wall``).
FRAME_INDIFFERENT = ("charan", "ishima", "linear")


def vector_form(name):
    """The law whose physics ``name`` has: ``ishima_fi`` -> ``ishima``, ``linear_fi_wall``
    -> ``linear_wall``; any other name unchanged."""
    for law in FRAME_INDIFFERENT:
        if name in (f"{law}_fi", f"{law}_fi_wall"):
            return law + name[len(law) + 3:]
    return name


@dataclass(frozen=True)
class LawInfo:
    """A generated contact law: metadata and its numba kernels.

    Metadata (the generated module's constants): ``params`` (PARAMS, kernel
    order), ``param_units``, ``param_docs``, ``n_dof`` (N_DOF, per particle),
    ``n_hist`` (N_HIST), ``rotation`` (ROTATION: "theta", "l" = R theta, or
    ""), ``capped`` (CAPPED: the history is projected onto a cap), ``wall``
    (the wall form of a pair law, "" for a wall law), ``pair`` (the pair form
    of a wall law, "" for a pair law), ``contact`` (CONTACT: the names of
    ``aux`` of ``advance``), ``law_id`` (the id of the dispatch module, shared
    by a pair law and its wall form), ``width`` (a pair law whose ``advance``
    reads ``lam``, the Hertz-cylinder width: dispatch's WIDTH).

    Kernels: the scalar ``force``, ``force_jacobian``, ``increment`` (None
    without history), ``contact_quantities`` (``<law>_contact`` of a capped
    law, else None), ``assemble`` (None except for the laws whose loops
    callers outside the laws still import), and the uniform ``eval``,
    ``rate``, ``project``, ``advance`` (``fricstab/generated/<law>.py``).
    """

    name: str
    kind: str  # "pair" or "wall"
    inputs: tuple
    coords: tuple
    outputs: tuple
    history: tuple
    coulomb: bool
    params: tuple
    param_units: tuple
    param_docs: tuple
    n_dof: int
    n_hist: int
    rotation: str
    capped: bool
    wall: str
    pair: str
    contact: tuple
    law_id: int
    width: bool
    force: object
    force_jacobian: object
    increment: object  # None for frictionless laws
    contact_quantities: object  # None except for capped laws
    assemble: object  # None except for LEGACY_ASSEMBLE laws (symbolic.codegen)
    eval: object
    rate: object
    project: object
    advance: object

    @property
    def geometry_args(self):
        """The geometry arguments of the uniform kernels."""
        return ("dx", "dy", "Ri", "Rj") if self.kind == "pair" else ("y", "R")

    @property
    def advance_geometry_args(self):
        """The geometry arguments of ``advance``: a pair's also ``r, delta, lam``.

        For a pair they are :func:`fricstab._numerics.pair_geometry` ``(dx, dy,
        Ri, Rj, law.width)``, which the engine computes for several contacts at
        once for a law with a width (:func:`fricstab._numerics.pair_geometry_lanes`)
        and contact by contact for the others
        (:func:`fricstab._numerics.pair_overlap`; ``lam`` 0.0).
        """
        return self.geometry_args + (("r", "delta", "lam") if self.kind == "pair" else ())

    def wall_form(self):
        """The :class:`LawInfo` of this pair law's wall form."""
        if not self.wall:
            raise ParameterError(f"{self.name} is a wall law; its pair form is {self.pair!r}")
        return get_law(self.wall)

    def pair_form(self):
        """The :class:`LawInfo` of this wall law's pair form."""
        if not self.pair:
            raise ParameterError(f"{self.name} is a pair law; its wall form is {self.wall!r}")
        return get_law(self.pair)


_CACHE = {}


def law_id(name):
    """The integer id of ``name`` in :mod:`fricstab.generated.dispatch` (pair or wall form)."""
    for names in (PAIR_LAW_NAMES, WALL_LAW_NAMES):
        if name in names:
            return names.index(name)
    raise ParameterError(f"unknown law {name!r}; known laws: {', '.join(ALL_LAW_NAMES)}")


def get_law(name):
    """The :class:`LawInfo` of a contact law: its metadata and numba kernels.

    Parameters
    ----------
    name : str
        One of :data:`ALL_LAW_NAMES`: the family :data:`LAW_NAMES` (``hertz``,
        ``charan``, ``ishima`` and their wall forms, verified by
        :mod:`fricstab.laws.verify`) or :data:`CAPPED_LAW_NAMES` (``lee_hurley``
        and its wall form, verified by :mod:`fricstab.laws.verify_lee_hurley`).

    Returns
    -------
    LawInfo
        Parameter names in kernel order with their units (``params``,
        ``param_units``, ``param_docs``: each names the paper's equation),
        coordinates and generalized forces, history, cap, wall or pair form, and
        the kernels ``force``, ``force_jacobian``, ``increment``, ``eval``,
        ``rate``, ``project``, ``advance`` (plain numba functions, unchecked;
        their arguments are listed by ``fricstab laws``).

    Raises
    ------
    ParameterError
        If ``name`` is not a known law.
    """
    if name not in ALL_LAW_NAMES:
        raise ParameterError(f"unknown law {name!r}; known laws: {', '.join(ALL_LAW_NAMES)}")
    if name not in _CACHE:
        mod = importlib.import_module(f"fricstab.generated.{name}")
        kernel = lambda suffix: getattr(mod, f"{name}{suffix}", None)  # noqa: E731
        _CACHE[name] = LawInfo(
            name=name, kind=mod.KIND, inputs=mod.INPUTS, coords=mod.COORDS,
            outputs=mod.OUTPUTS, history=mod.HISTORY, coulomb=mod.COULOMB,
            params=mod.PARAMS, param_units=mod.PARAM_UNITS, param_docs=mod.PARAM_DOCS,
            n_dof=mod.N_DOF, n_hist=mod.N_HIST, rotation=mod.ROTATION, capped=mod.CAPPED,
            wall=getattr(mod, "WALL", ""), pair=getattr(mod, "PAIR", ""),
            contact=mod.CONTACT, law_id=law_id(name),
            width=mod.KIND == "pair" and dispatch.WIDTH[law_id(name)],
            force=kernel("_force"), force_jacobian=kernel("_force_jacobian"),
            increment=kernel("_increment"), contact_quantities=kernel("_contact"),
            assemble=kernel("_assemble"), eval=kernel("_eval"), rate=kernel("_rate"),
            project=kernel("_project"), advance=kernel("_advance"))
    return _CACHE[name]


_POSITIVE = ("kn", "kt", "mu", "R", "Ri", "Rj", "radius", "E", "mus", "Rw")
#: Closed-open ranges ``[lo, hi)`` of bounded parameters (Poisson ratio: Lai's
#: k_t has nu/(2(1 - nu)); rolling friction may be 0: no rolling resistance).
_RANGES = {"nu": (0.0, 0.5), "mur": (0.0, float("inf"))}


def check_parameters(**values):
    """Raise ParameterError naming the first bad parameter.

    Radii (the wall's radius of curvature Rw too), stiffnesses, E* and the
    friction coefficients mu, mus must be finite and > 0; nu in [0, 0.5); mur >= 0; every other value finite.
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

    The law's scalar kernels (``force_jacobian``) evaluated once: the Hertz
    normal force ``kn delta^(3/2)`` (Charan Eq. 1, Ishima Eq. 7), the tangential
    force of the law (Charan Eq. 5, Ishima Eqs. 8-9, Lee & Hurley Eqs. A1-A23)
    and the block ``K = dF/dq`` with the history advanced by the increment rule
    (Charan Eq. 2, Ishima Eq. D4).  Units are those of the inputs (any
    consistent set; the scenes use Charan's, Ishima's or SI per unit thickness).

    Parameters
    ----------
    name : str
        The law (:data:`ALL_LAW_NAMES`).
    **inputs : float
        The law's kernel arguments by name (``fricstab laws`` and
        ``get_law(name).inputs`` list them), e.g. for ``charan``: ``dx, dy``
        (``r_i - r_j``, length), ``Ri, Rj`` (radii, length), ``kn, kt``
        (force/length^(3/2)), ``mu`` (-), ``tx, ty`` (tangential history, length).
        A wall law takes ``y`` (the disk's height above the wall) and ``R``.

    Returns
    -------
    f : ndarray, shape (n_out,)
        Generalized forces, e.g. ``(Fx_i, Fy_i, T_i, Fx_j, Fy_j, T_j)`` for a
        pair law with rotations (Ishima's law: ``F^l = 2T/d`` in place of ``T``).
    jac : ndarray, shape (n_out, n_coords)
        ``jac[a, b] = d f[a] / d q[b]``, ``q = (x_i, y_i, theta_i, x_j, y_j,
        theta_j)`` (Ishima's law: ``l = d theta/2``); Charan's sign
        (Ishima's Jacobian of Eq. 18 is ``-jac``).

    Raises
    ------
    ParameterError
        Naming a missing, unknown or bad argument (radii, stiffnesses and
        ``mu`` must be > 0, everything finite).
    NumericalError
        A force or Jacobian entry that is not finite (a separation whose
        square overflows or underflows).
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
    if not (np.isfinite(f).all() and np.isfinite(jac).all()):   # e.g. |d| overflows or underflows
        from fricstab.errors import NumericalError
        raise NumericalError(f"{name}: non-finite force or Jacobian at the inputs "
                             f"{', '.join(f'{k}={inputs[k]!r}' for k in law.inputs)} "
                             "(a separation beyond the range of doubles)", quantity="force")
    return f, jac
