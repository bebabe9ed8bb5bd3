"""Bidisperse frictionless packings in a periodic box (Ishima et al., App. A.1), on the engine.

Contract
--------
* Units: the large diameter ``d = 1``, ``k_N = 1`` and the mass of a large disk
  ``m = 1``, so ``t0 = sqrt(m / k_N) d^(1/4) = 1``, lengths are in ``d`` and
  forces in ``k_N d^(3/2)``.
* A packing holds ``N`` disks, ``N/2`` of diameter 1 (indices ``0 .. N/2-1``)
  and ``N/2`` of diameter ``1/1.4``; ``m_i = d_i^2`` and ``I_i = m_i d_i^2 / 8``
  (Ishima Sec. II).  ``pos`` is ``(N, 2)`` float64 folded into ``[0, L)``, ``L``
  the side of the square box; ``phi = sum(pi d_i^2 / 4) / L^2``.
* Periodic boundaries with a Lees-Edwards offset ``shift`` (``= gamma L``):
  the image above in ``y`` is displaced by ``+shift`` in ``x``
  (:mod:`fricstab.engine.contacts`: a pair's separation is
  ``r_i - r_j - m (L, 0) - k (shift, L)``).
* The pair force is the engine's ``hertz`` law, ``k_N xi^(3/2) n_ij`` with
  ``xi = (d_i + d_j)/2 - |r_ij|`` (Ishima Eq. A4), summed over the contacts in
  key order (:mod:`fricstab.engine.contacts`).

Protocol (Ishima App. A.1): random sequential addition without overlaps at
``phi_start = 0.6`` (:mod:`fricstab.scenes.packing_place`), then compression
in increments ``dphi`` (Eqs. A1-A2): at each increment the positions are
scaled with the box and a new frictionless System (``hertz``, 2 dof per disk)
is built for the new box; :func:`fricstab.engine.fire` (Eqs. A3, A5-A12, the
paper's FIRE parameters) relaxes until max |F| is below ``f_tol_compress``
(``f_tol`` at the target ``phi``).  The engine's neighbour list (skin
``SKIN``) makes a force evaluation O(N).  A disk that random sequential
addition could not place without overlap is relaxed by the FIRE run at
``phi_start`` (``info["rsa_forced"]`` counts them).

Reproducibility: a seed gives a bit-identical packing on one machine.  FIRE
near jamming is chaotic: a change of the summation order of the contact
forces (the engine sums in key order; the loop before the engine summed in
search order) leaves N = 256 at phi = 0.9 in the same minimum (positions to
3.1e-5, same 618 contacts; measured) but takes N >= 1024 to another one.
"""

import json
import math
import time
from dataclasses import dataclass, field

import numpy as np
from fricstab.engine import Material, System, fire
from fricstab.engine.contacts import build
from fricstab.errors import MAX_STEPS, ConvergenceError, ParameterError, check_steps
from fricstab.progress import bar as progress_bar
from fricstab.scenes.packing_place import diameters, place

__all__ = ["ConvergenceError", "KN", "Packing", "find_contacts", "fold", "frictionless_system",
           "hertz_forces", "make_packing"]

KN = 1.0                 # the unit of stiffness
PHI_MAX = 0.95
PHI_START_MIN = 1e-6     # below it the placement box overflows (front-door check)
PHI_START_MAX = 0.6      # random sequential addition saturates not far above
SKIN = 0.25              # neighbour-list skin of the compression, in d
MAX_COMPRESSIONS = 10**7  # compression steps of one make_packing ((phi - phi_start) / dphi)
MAX_N = 10**8            # disks of one make_packing
MAX_REFOLDS = 4          # FIRE reruns after folding the final positions into the box


@dataclass(frozen=True, eq=False)
class Packing:
    """A force-balanced frictionless packing (read-only arrays; Ishima App. A.1).

    Units: large diameter d = 1, k_N = 1, mass of a large disk m = 1.

    Parameters
    ----------
    pos : ndarray, shape (N, 2)
        Centres, folded into ``[0, box)`` (units of d).
    diameter : ndarray, shape (N,)
        1 for the first ``N/2`` disks, ``1/1.4`` for the others (units of d).
    box : float
        Side ``L`` of the square periodic box (units of d).
    phi : float
        Target area fraction, ``sum(pi d^2 / 4) / L^2``.
    seed : int
        Seed of :func:`numpy.random.default_rng` for the placement.
    info : dict
        Protocol knobs and costs: ``dphi``, ``f_tol``, ``f_tol_compress``,
        ``phi_start``, ``compression_steps``, ``fire_iterations``, ``max_force``
        (``max |F_i|`` at the end, in k_N d^(3/2)), ``seconds``.
    """

    pos: np.ndarray
    diameter: np.ndarray
    box: float
    phi: float
    seed: int
    info: dict = field(default_factory=dict)

    def __post_init__(self):
        for name in ("pos", "diameter"):
            a = np.array(getattr(self, name), dtype=np.float64)
            a.setflags(write=False)
            object.__setattr__(self, name, a)
        object.__setattr__(self, "box", float(self.box))
        object.__setattr__(self, "phi", float(self.phi))
        object.__setattr__(self, "seed", int(self.seed))

    @property
    def n(self):
        """Number of disks N."""
        return self.diameter.shape[0]

    @property
    def radius(self):
        """Radii ``d_i / 2``, shape (N,)."""
        return self.diameter / 2

    @property
    def mass(self):
        """Masses ``m_i = m (d_i / d)^2`` with ``m = d = 1`` (Sec. II)."""
        return self.diameter**2

    @property
    def inertia(self):
        """Moments of inertia ``I_i = m_i d_i^2 / 8`` (Sec. II, below Eq. 2)."""
        return self.mass * self.diameter**2 / 8

    def save(self, path):
        """Write to ``path`` with :func:`numpy.savez` (``.npz`` is appended if missing)."""
        np.savez(path, pos=self.pos, diameter=self.diameter, box=self.box, phi=self.phi,
                 seed=self.seed, info=json.dumps(self.info))

    @classmethod
    def load(cls, path):
        """Read a packing written by :meth:`save` (ValueError if ``path`` holds no NPZ archive)."""
        data = np.load(path, allow_pickle=False)
        if not isinstance(data, np.lib.npyio.NpzFile):
            raise ValueError("not an NPZ archive (a single .npy array)")
        with data:
            return cls(pos=data["pos"], diameter=data["diameter"], box=float(data["box"]),
                       phi=float(data["phi"]), seed=int(data["seed"]),
                       info=json.loads(str(data["info"])))


def _check_number(name, value, lo, hi, allowed):
    """``lo < value <= hi`` (``hi = None``: no upper bound), a real finite number."""
    ok = isinstance(value, (int, float, np.integer, np.floating)) and not isinstance(value, bool)
    ok = ok and math.isfinite(value) and value > lo and (hi is None or value <= hi)
    if not ok:
        raise ParameterError(f"{name} must be {allowed}, got {value!r}")


def _check_int(name, value, lo, allowed):
    if not (isinstance(value, (int, np.integer)) and not isinstance(value, bool) and value >= lo):
        raise ParameterError(f"{name} must be {allowed}, got {value!r}")


def fold(pos, box):
    """Positions folded into ``[0, box)`` (a ``-tiny`` coordinate goes to 0, not ``box``)."""
    out = pos - box * np.floor(pos / box)
    out[out >= box] = 0.0
    return out


def frictionless_system(radius, box, skin=SKIN):
    """The frictionless packing as an engine System: ``hertz`` (k_N = 1), 2 dof per disk.

    Masses ``m_i = (2 R_i)^2`` and inertias ``m_i (2 R_i)^2 / 8`` (Sec. II);
    periodic in x and y with period ``box``.
    """
    radius = np.asarray(radius, float)
    mass = (2 * radius) ** 2
    return System(Material("hertz", {"kn": KN}), radius, mass, mass * (2 * radius) ** 2 / 8,
                  lx=box, ly=box, skin=skin)


def _relax(pos, radius, box, tol, max_iter, phi):
    """FIRE at fixed box from ``pos`` (engine); returns (folded positions, iterations)."""
    system = frictionless_system(radius, box)
    state = system.state(pos)
    it, res = fire(system, state, tol, max_iter)
    if it > max_iter:
        raise ConvergenceError(
            f"FIRE did not converge at phi = {phi:.6g}: max |F| = {res:.3e} >= {tol:.1e} "
            f"after {max_iter} iterations")
    return fold(state.q[:, :2], box), it


def make_packing(n, phi, seed=0, *, dphi=1e-3, f_tol=1e-14, f_tol_compress=1e-6,
                 phi_start=0.6, max_iter=5_000_000, progress=False):
    """A force-balanced bidisperse frictionless packing (Ishima App. A.1).

    Parameters
    ----------
    n : int
        Number of disks, even and >= 4 (half of diameter 1, half 1/1.4).
    phi : float
        Target area fraction, ``phi_start <= phi <= 0.95``.
    seed : int
        Seed of :func:`numpy.random.default_rng`; the same seed gives a
        bit-identical packing on one machine.
    dphi : float
        Increment of phi per compression step (Eqs. A1-A2); the last one is
        clipped to land on ``phi``.  The paper uses 1e-4.
    f_tol : float
        FIRE stops at the target phi when ``max |F_i^zeta| < f_tol``
        (paper: F_Th = 1e-14 k_N d^(3/2)).
    f_tol_compress : float
        The same threshold on the intermediate steps.  Every step has overlaps,
        also below jamming (a relaxed state keeps overlaps of order
        ``f_tol_compress^(2/3)``), and a Hertz overlap relaxes ever more slowly
        as it shrinks, so this sets most of the cost; it is well below the
        force change of one increment,
        ``~1.5 sqrt(xi) dphi / (2 phi) ~ 5e-5`` at ``dphi = 1e-3``.
    phi_start : float
        Area fraction of the random placement, in [1e-6, 0.6] (paper: 0.6).
    max_iter : int
        Cap on the FIRE iterations of one relaxation (at most 1e10).
    progress : bool
        Show progress over the compression steps (:func:`fricstab.progress.bar`).

    Returns
    -------
    Packing

    Raises
    ------
    fricstab.laws.ParameterError
        On bad input; the message names the parameter.  Also more than 1e7
        compression steps (``(phi - phi_start) / dphi``) or more than 1e8 disks.
    ConvergenceError
        If a FIRE relaxation exceeds ``max_iter`` iterations; the message
        names phi, the residual and the iterations.

    Notes
    -----
    ``dphi`` and ``f_tol_compress`` trade speed for fidelity to the paper's
    protocol (``dphi = 1e-4``, F_Th at every step); their costs are measured
    in ``validation/packing_knobs.md``.  Each step sets
    ``L = sqrt(sum(pi d_i^2 / 4) / phi)`` and scales the positions by
    ``L_new / L_old`` (Eqs. A1-A2, exact in phi), then builds the System of
    the new box (:func:`frictionless_system`) and relaxes it with
    :func:`fricstab.engine.fire` from ``v = 0``.  The positions are folded
    into the box after each step; folding rounds a coordinate by up to
    ``ulp(L)/2``, so the final state is checked again and relaxed once more
    if that pushed ``max |F|`` to ``f_tol``.
    """
    t_start = time.perf_counter()
    _check_int("n", n, 4, "an even integer >= 4")
    if n % 2:
        raise ParameterError(f"n must be an even integer >= 4, got {n!r}")
    _check_number("phi_start", phi_start, 0.0, PHI_START_MAX, allowed=f"in (0, {PHI_START_MAX}]")
    _check_number("phi", phi, 0.0, PHI_MAX, allowed=f"in (0, {PHI_MAX}]")
    if phi < phi_start:
        raise ParameterError(f"phi must be >= phi_start = {phi_start}, got {phi!r}")
    _check_int("seed", seed, 0, "an integer >= 0")
    _check_number("dphi", dphi, 0.0, None, allowed="a finite number > 0")
    _check_number("f_tol", f_tol, 0.0, None, allowed="a finite number > 0")
    _check_number("f_tol_compress", f_tol_compress, 0.0, None, allowed="a finite number > 0")
    _check_int("max_iter", max_iter, 1, "an integer >= 1")
    if max_iter > MAX_STEPS or phi_start < PHI_START_MIN:
        raise ParameterError(f"max_iter must be <= {MAX_STEPS:.0e} and phi_start >= "
                             f"{PHI_START_MIN:g}, got {max_iter!r} and {phi_start!r}")
    phi, phi_start, dphi = float(phi), float(phi_start), float(dphi)
    check_steps("make_packing: (phi - phi_start) / dphi", (phi - phi_start) / dphi,
                MAX_COMPRESSIONS)
    if n > MAX_N:
        raise ParameterError(f"n must be an even integer in [4, {MAX_N:.0e}], got {n!r}")
    n, seed, max_iter = int(n), int(seed), int(max_iter)

    diameter = diameters(n)
    radius = diameter / 2
    area = float(np.sum(np.pi * diameter**2 / 4))
    box = math.sqrt(area / phi_start)
    pos, attempts, forced = place(n, box, seed)
    # The last increment is clipped to land on phi; 1e-9 keeps a rounding
    # remainder from adding a step of ~1e-16.  The first entry relaxes the
    # disks that random sequential addition had to place overlapping.
    steps = max(math.ceil((phi - phi_start) / dphi - 1e-9), 0)
    schedule = [phi_start] + [phi_start + k * dphi for k in range(1, steps)] + [phi] * (steps > 0)
    total = 0
    for k, phi_k in enumerate(progress_bar(schedule, desc="compress", unit="step",
                                           enabled=progress)):
        new_box = math.sqrt(area / phi_k)
        pos *= new_box / box
        box = new_box
        tol = f_tol if k == len(schedule) - 1 else f_tol_compress
        pos, it = _relax(pos, radius, box, tol, max_iter, phi_k)
        total += it
    for _ in range(MAX_REFOLDS):
        max_force = float(np.abs(hertz_forces(pos, radius, box)).max())
        if max_force < f_tol:
            break
        pos, it = _relax(pos, radius, box, f_tol, max_iter, phi)
        total += it
    info = {"dphi": dphi, "f_tol": f_tol, "f_tol_compress": f_tol_compress,
            "phi_start": phi_start, "compression_steps": steps, "fire_iterations": total,
            "max_force": max_force, "rsa_attempts": attempts, "rsa_forced": forced,
            "seconds": time.perf_counter() - t_start}
    return Packing(pos=pos, diameter=diameter, box=box, phi=phi, seed=seed, info=info)


def _geometry(pos, radius, box, shift):
    pos = np.array(pos, dtype=np.float64, order="C")
    radius = np.array(radius, dtype=np.float64, order="C")
    if pos.ndim != 2 or pos.shape[1] != 2:
        raise ParameterError(f"pos must have shape (N, 2), got {pos.shape}")
    if radius.shape != (pos.shape[0],):
        raise ParameterError(f"radius must have shape ({pos.shape[0]},), got {radius.shape}")
    if not (np.all(np.isfinite(pos)) and np.all(np.isfinite(radius)) and np.all(radius > 0)):
        raise ParameterError("pos and radius must be finite, radius > 0")
    _check_number("shift", shift, -np.inf, None, allowed="a finite number")
    _check_number("box", box, 0.0, None, allowed="a finite number > 0")
    return pos, radius, float(box), float(shift)


def find_contacts(pos, radius, box, shift=0.0):
    """All overlapping pairs, ``|r_ij| < R_i + R_j`` (Eq. 6), under Lees-Edwards periodicity.

    The engine's neighbour search (:func:`fricstab.engine.contacts.build`)
    with no skin.

    Parameters
    ----------
    pos : array_like, shape (N, 2)
        Centres (any image).
    radius : array_like, shape (N,)
    box : float
        Box side L; must exceed twice the largest diameter, so a pair touches
        through at most one image.
    shift : float
        Lees-Edwards offset ``gamma L``: the image above in y is displaced by
        ``+shift`` in x.

    Returns
    -------
    pairs : ndarray of int64, shape (M, 2)
        ``i < j``, sorted lexicographically.
    sep : ndarray of float64, shape (M, 2)
        ``r_i - r_j`` of the touching image.
    """
    pos, radius, box, shift = _geometry(pos, radius, box, shift)
    dmax = 2 * radius.max() if radius.size else 0.0
    _check_number("box", box, 2 * dmax, None, allowed=f"a number > 2 max diameter = {2 * dmax}")
    if len(pos) < 2:
        return np.empty((0, 2), np.int64), np.empty((0, 2))
    q = np.zeros((len(pos), 3))
    q[:, :2] = pos
    rows, _ = build(q, radius, np.ones(len(pos), bool), box, box, shift, 0.0)
    i, j, m, k = rows.T
    sep = np.empty((len(rows), 2))
    sep[:, 1] = (pos[i, 1] - pos[j, 1]) - k * box
    sep[:, 0] = ((pos[i, 0] - pos[j, 0]) - k * shift) - m * box
    return np.ascontiguousarray(rows[:, :2]), sep


def _find_contacts_brute(pos, radius, box, shift=0.0):
    """Reference for :func:`find_contacts`: every pair, NumPy minimum image."""
    pos = np.asarray(pos, dtype=np.float64)
    radius = np.asarray(radius, dtype=np.float64)
    i, j = np.triu_indices(len(pos), k=1)
    dx = pos[i, 0] - pos[j, 0]
    dy = pos[i, 1] - pos[j, 1]
    k = np.rint(dy / box)
    dy = dy - box * k
    dx = dx - shift * k
    dx = dx - box * np.rint(dx / box)
    hit = np.sqrt(dx * dx + dy * dy) < radius[i] + radius[j]
    return np.stack([i[hit], j[hit]], axis=1).astype(np.int64), np.stack([dx[hit], dy[hit]], axis=1)


def hertz_forces(pos, radius, box, shift=0.0):
    """Net frictionless Hertz forces ``F_i`` (Eq. A4, k_N = 1), shape (N, 2), by the engine.

    Every image within reach counts, so any ``box`` larger than the largest
    diameter (no disk touches its own image) is allowed.
    """
    pos, radius, box, shift = _geometry(pos, radius, box, shift)
    dmax = 2 * radius.max() if radius.size else 0.0
    _check_number("box", box, dmax, None, allowed=f"a number > max diameter = {dmax}")
    if len(pos) < 2:
        return np.zeros_like(pos)
    system = frictionless_system(radius, box, skin=0.0)
    return system.forces(system.state(pos, shift=shift))[:, :2]

