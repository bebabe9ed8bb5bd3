"""Bidisperse frictionless packings in a periodic box (Ishima et al., App. A.1).

Contract
--------
* Units: the large diameter ``d = 1``, ``k_N = 1`` and the mass of a large disk
  ``m = 1``, so ``t0 = sqrt(m / k_N) d^(1/4) = 1``, lengths are in ``d`` and
  forces in ``k_N d^(3/2)``.
* A packing holds ``N`` disks, ``N/2`` of diameter 1 (indices ``0 .. N/2-1``)
  and ``N/2`` of diameter ``1/1.4``; ``m_i = d_i^2`` and ``I_i = m_i d_i^2 / 8``
  (Ishima Sec. II).  ``pos`` is ``(N, 2)`` float64 wrapped into ``[0, L)``, ``L``
  the side of the square box; ``phi = sum(pi d_i^2 / 4) / L^2``.
* Periodic boundaries with a Lees-Edwards offset ``shift`` (``= gamma L``): the
  image above in ``y`` is displaced by ``+shift`` in ``x``.  Separations are
  ``r_i - r_j`` of the minimum image, ``k = round(dy / L)``, ``dy -= k L``,
  ``dx -= k shift``, then ``dx -= L round(dx / L)`` (round half to even).
* The pair force is the verified generated kernel
  :func:`fricstab.generated.hertz.hertz_force`, ``k_N xi^(3/2) n_ij`` with
  ``xi = (d_i + d_j)/2 - |r_ij|`` (Ishima Eq. A4).

Protocol (Ishima App. A.1): random sequential addition without overlaps at
``phi_start = 0.6``, then compression in increments ``dphi`` (Eqs. A1-A2); after
each increment with overlaps, FIRE on the Hertz energy (Eq. A3) with velocity
Verlet (Eqs. A5-A6) and the paper's FIRE parameters, until max |F| is below
``f_tol_compress`` (``f_tol`` at the target ``phi``).  Neighbours come from a
Verlet list with skin built on a cell list, so a force evaluation is O(N).

Random sequential addition of this mixture (large disks first) saturates close
to phi = 0.6: the last disks may need 1e6 tries or find no room at all.  A
disk still unplaced after ``RSA_BUDGET`` tries is put at its last try
(overlapping), and a FIRE relaxation at ``phi_start`` removes those overlaps
before the compression; ``info["rsa_forced"]`` counts them (0 to a few per
thousand disks).
"""

import json
import math
import time
from dataclasses import dataclass, field

import numpy as np
from tqdm import tqdm

from fricstab._numba import kernel_jit
from fricstab.generated.hertz import hertz_force
from fricstab.errors import ConvergenceError, ParameterError

__all__ = ["ConvergenceError", "Packing", "find_contacts", "hertz_forces", "make_packing"]

SIZE_RATIO = 1.4
PHI_MAX = 0.95
PHI_START_MAX = 0.6      # random sequential addition saturates not far above
# FIRE, Ishima App. A.1 (the values of Bitzek et al. 2006), in t0.
DT_INI = 1e-2
DT_MAX = 10 * DT_INI
F_INC = 1.1
F_DEC = 0.5
F_ALPHA = 0.99
ALPHA_START = 0.1
N_MIN = 5
SKIN = 0.25              # Verlet-list skin, in d
RSA_BATCH = 4096         # candidates per draw; fixed, so a seed fixes the stream
RSA_BUDGET = 1_000_000   # tries per disk before it is placed overlapping


# ---------------------------------------------------------------- numba kernels

@kernel_jit
def _wrap(x, box):
    """``x`` into ``[0, box)``; ``-tiny`` goes to 0 rather than rounding up to ``box``."""
    if 0.0 <= x < box:
        return x
    x = x - box * np.floor(x / box)
    if x < 0.0:
        x += box
    if x >= box:
        x = 0.0
    return x


@kernel_jit
def _cell(x, w, nc):
    c = int(x / w)
    return min(max(c, 0), nc - 1)


@kernel_jit
def _search(pos, radius, box, shift, skin, out):
    """Pairs ``i < j`` with an image of ``j`` closer than ``R_i + R_j + skin``.

    Row ``p`` of ``out`` gets ``(i, j, m, k)``: the image of ``j`` is displaced by
    ``(m box + k shift, k box)``.  Returns the number found; only the first
    ``len(out)`` are written, so the caller retries with a larger ``out``.
    """
    n = pos.shape[0]
    rmax = 0.0
    for i in range(n):
        rmax = max(rmax, radius[i])
    cut = 2.0 * rmax + skin
    nc = int(box / (cut * (1.0 + 1e-10)))  # the margin covers rounding in the wrap
    cap = out.shape[0]
    count = 0
    if nc < 3:  # small box: all pairs and every image in reach
        reach = int(np.ceil(cut / box)) + 1
        for i in range(n):
            for j in range(i + 1, n):
                lim = radius[i] + radius[j] + skin
                dy0 = pos[i, 1] - pos[j, 1]
                kc = int(np.rint(dy0 / box))
                for k in range(kc - reach, kc + reach + 1):
                    dy = dy0 - k * box
                    if abs(dy) >= lim:
                        continue
                    dx0 = (pos[i, 0] - pos[j, 0]) - k * shift
                    mc = int(np.rint(dx0 / box))
                    for m in range(mc - reach, mc + reach + 1):
                        dx = dx0 - m * box
                        if math.sqrt(dx * dx + dy * dy) < lim:
                            if count < cap:
                                out[count, 0], out[count, 1] = i, j
                                out[count, 2], out[count, 3] = m, k
                            count += 1
        return count
    # Cell list in Lees-Edwards-consistent wrapped coordinates (a wrap by a
    # boxes in y moves x by a shift), only to find candidates; the separation
    # itself is the minimum image of the raw positions.
    w = box / nc
    xw = np.empty(n)
    cx = np.empty(n, np.int64)
    cy = np.empty(n, np.int64)
    start = np.zeros(nc * nc + 1, np.int64)
    for i in range(n):
        a = np.floor(pos[i, 1] / box)
        cy[i] = _cell(pos[i, 1] - a * box, w, nc)
        x = pos[i, 0] - a * shift
        xw[i] = x - box * np.floor(x / box)
        cx[i] = _cell(xw[i], w, nc)
        start[cy[i] * nc + cx[i] + 1] += 1
    for c in range(nc * nc):
        start[c + 1] += start[c]
    fill = start[:-1].copy()
    order = np.empty(n, np.int64)
    for i in range(n):
        c = cy[i] * nc + cx[i]
        order[fill[c]] = i
        fill[c] += 1
    for i in range(n):
        for oy in range(-1, 2):
            row = cy[i] + oy
            q = 0
            if row < 0:
                row += nc
                q = -1
            elif row >= nc:
                row -= nc
                q = 1
            xc = xw[i] - q * shift
            col0 = _cell(xc - box * np.floor(xc / box), w, nc)
            for ox in range(-1, 2):
                col = col0 + ox
                if col < 0:
                    col += nc
                elif col >= nc:
                    col -= nc
                c = row * nc + col
                for idx in range(start[c], start[c + 1]):
                    j = order[idx]
                    if j <= i:
                        continue
                    lim = radius[i] + radius[j] + skin
                    dy0 = pos[i, 1] - pos[j, 1]
                    k = np.rint(dy0 / box)
                    dy = dy0 - k * box
                    if abs(dy) >= lim:
                        continue
                    dx0 = (pos[i, 0] - pos[j, 0]) - k * shift
                    m = np.rint(dx0 / box)
                    dx = dx0 - m * box
                    if math.sqrt(dx * dx + dy * dy) < lim:
                        if count < cap:
                            out[count, 0], out[count, 1] = i, j
                            out[count, 2], out[count, 3] = int(m), int(k)
                        count += 1
    return count


@kernel_jit
def _pair_list(pos, radius, box, shift, skin):
    out = np.empty((4 * pos.shape[0] + 16, 4), np.int64)
    count = _search(pos, radius, box, shift, skin, out)
    if count > out.shape[0]:
        out = np.empty((count, 4), np.int64)
        _search(pos, radius, box, shift, skin, out)
    return out[:count]


@kernel_jit
def _accumulate(pos, radius, box, shift, pairs, force):
    """Net Hertz forces (Eq. A4) over the listed pairs into ``force``; returns max |F|."""
    force[:] = 0.0
    f = np.empty(4)
    for p in range(pairs.shape[0]):
        i, j, m, k = pairs[p, 0], pairs[p, 1], pairs[p, 2], pairs[p, 3]
        dy = (pos[i, 1] - pos[j, 1]) - k * box
        dx = ((pos[i, 0] - pos[j, 0]) - k * shift) - m * box
        s = radius[i] + radius[j]
        if dx * dx + dy * dy >= s * s:
            continue
        hertz_force(dx, dy, radius[i], radius[j], 1.0, f)
        force[i, 0] += f[0]
        force[i, 1] += f[1]
        force[j, 0] += f[2]
        force[j, 1] += f[3]
    res = 0.0
    for i in range(force.shape[0]):
        res = max(res, abs(force[i, 0]), abs(force[i, 1]))
    return res


@kernel_jit
def _wrap_all(pos, box):
    """Wrap positions into ``[0, box)``; returns whether any moved."""
    moved = False
    for i in range(pos.shape[0]):
        for a in range(2):
            x = _wrap(pos[i, a], box)
            if x != pos[i, a]:
                pos[i, a] = x
                moved = True
    return moved


@kernel_jit
def _fire(pos, radius, mass, box, tol, max_iter, skin):
    """FIRE (App. A.1) in place on ``pos`` until max |F| < ``tol``.

    Returns ``(iterations, max |F|)``; ``iterations > max_iter`` means not
    converged.  Starts from v = 0, dt = dt_ini, chi = chi_start.
    """
    n = pos.shape[0]
    _wrap_all(pos, box)
    pairs = _pair_list(pos, radius, box, 0.0, skin)
    ref = pos.copy()
    force = np.empty((n, 2))
    new = np.empty((n, 2))
    res = _accumulate(pos, radius, box, 0.0, pairs, force)
    if res < tol:
        return 0, res
    v = np.zeros((n, 2))
    dt, chi, n_pos = DT_INI, ALPHA_START, 0
    for it in range(1, max_iter + 1):
        disp2 = 0.0
        for i in range(n):  # Eq. A5
            for a in range(2):
                pos[i, a] += dt * v[i, a] + 0.5 * dt * dt * force[i, a] / mass[i]
                disp2 = max(disp2, (pos[i, a] - ref[i, a]) ** 2)
        if 8.0 * disp2 > skin * skin:  # some displacement may exceed skin / 2
            _wrap_all(pos, box)
            pairs = _pair_list(pos, radius, box, 0.0, skin)
            ref[:] = pos
        res = _accumulate(pos, radius, box, 0.0, pairs, new)
        for i in range(n):  # Eq. A6
            for a in range(2):
                v[i, a] += 0.5 * dt * (force[i, a] + new[i, a]) / mass[i]
        force[:] = new
        if res < tol:
            if not _wrap_all(pos, box):
                return it, res
            # Wrapping rounds positions by up to ulp(box) / 2: check again.
            pairs = _pair_list(pos, radius, box, 0.0, skin)
            ref[:] = pos
            res = _accumulate(pos, radius, box, 0.0, pairs, force)
            if res < tol:
                return it, res
        power = 0.0
        vv = 0.0
        ff = 0.0
        for i in range(n):
            for a in range(2):
                power += force[i, a] * v[i, a]
                vv += v[i, a] * v[i, a]
                ff += force[i, a] * force[i, a]
        # Ishima's Eq. A7 is garbled; this is the mixing of Bitzek et al.
        # (2006), v -> (1 - chi) v + chi |v| F / |F| with norms over all disks.
        scale = chi * math.sqrt(vv / ff) if ff > 0.0 else 0.0
        for i in range(n):
            for a in range(2):
                v[i, a] = (1.0 - chi) * v[i, a] + scale * force[i, a]
        if power > 0.0:  # Eqs. A8-A9
            n_pos += 1
            if n_pos > N_MIN:
                dt = min(dt * F_INC, DT_MAX)
                chi *= F_ALPHA
        else:  # Eqs. A10-A12
            v[:] = 0.0
            chi = ALPHA_START
            dt *= F_DEC
            n_pos = 0
    return max_iter + 1, res


@kernel_jit
def _rsa(pos, radius, box, placed, cand, head, nxt, tries, budget):
    """Random sequential addition of disks ``placed, placed + 1, ...``.

    Candidate points of ``cand`` are tried in order; a disk is kept at the
    first one where it overlaps no placed disk (any image), or at its
    ``budget``-th try whatever it overlaps.  ``head``/``nxt`` are linked cell
    lists (``len(head) = nc^2``, ``nc >= 3``; ``len(head) = 1``: all pairs and
    images); they and ``tries`` (of the current disk) carry over between
    calls.  Returns ``(placed, used, tries, forced)``.
    """
    n = pos.shape[0]
    nc = int(math.sqrt(head.shape[0]) + 0.5)
    w = box / nc
    reach = int(np.ceil(2.0 * radius.max() / box)) + 1
    used = 0
    forced = 0
    while placed < n and used < cand.shape[0]:
        x, y = cand[used, 0], cand[used, 1]
        used += 1
        tries += 1
        ok = True
        if nc < 3:
            for j in range(placed):
                for k in range(-reach, reach + 1):
                    for m in range(-reach, reach + 1):
                        dy = (y - pos[j, 1]) - k * box
                        dx = (x - pos[j, 0]) - m * box
                        if math.sqrt(dx * dx + dy * dy) < radius[placed] + radius[j]:
                            ok = False
        else:
            cx, cy = _cell(x, w, nc), _cell(y, w, nc)
            for oy in range(-1, 2):
                for ox in range(-1, 2):
                    j = head[((cy + oy) % nc) * nc + (cx + ox) % nc]
                    while j >= 0 and ok:
                        dy = y - pos[j, 1]
                        dx = x - pos[j, 0]
                        dy -= box * np.rint(dy / box)
                        dx -= box * np.rint(dx / box)
                        ok = math.sqrt(dx * dx + dy * dy) >= radius[placed] + radius[j]
                        j = nxt[j]
        if not ok and tries >= budget:
            ok = True
            forced += 1
        if ok:
            pos[placed, 0], pos[placed, 1] = x, y
            if nc >= 3:
                c = _cell(y, w, nc) * nc + _cell(x, w, nc)
                nxt[placed] = head[c]
                head[c] = placed
            placed += 1
            tries = 0
    return placed, used, tries, forced


# ---------------------------------------------------------------- public API

@dataclass(frozen=True, eq=False)
class Packing:
    """A force-balanced frictionless packing (read-only arrays).

    Attributes
    ----------
    pos : ndarray, shape (N, 2)
        Centres, wrapped into ``[0, box)``.
    diameter : ndarray, shape (N,)
        1 for the first ``N/2`` disks, ``1/1.4`` for the others.
    box : float
        Side ``L`` of the square periodic box.
    phi : float
        Target area fraction, ``sum(pi d^2 / 4) / L^2``.
    seed : int
        Seed of :func:`numpy.random.default_rng` for the placement.
    info : dict
        Protocol knobs and costs: ``dphi``, ``f_tol``, ``f_tol_compress``,
        ``phi_start``, ``compression_steps``, ``fire_iterations``, ``max_force``
        (max |F_i^zeta| at the end), ``seconds``.
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
        """Read a packing written by :meth:`save`."""
        with np.load(path) as data:
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


def _diameters(n):
    return np.concatenate([np.ones(n // 2), np.full(n // 2, 1 / SIZE_RATIO)])


def _place(n, box, seed):
    """Random sequential addition, large disks first (they are first in the arrays).

    Returns ``(pos, attempts, forced)``: ``forced`` disks found no free spot
    in ``RSA_BUDGET`` tries and overlap others (module docstring).
    """
    radius = _diameters(n) / 2
    nc = int(box / (2 * radius.max() * (1 + 1e-10)))
    head = np.full(nc * nc if nc >= 3 else 1, -1, np.int64)
    nxt = np.full(n, -1, np.int64)
    pos = np.zeros((n, 2))
    rng = np.random.default_rng(seed)
    placed = tries = attempts = forced = 0
    while placed < n:
        placed, used, tries, f = _rsa(pos, radius, box, placed, rng.random((RSA_BATCH, 2)) * box,
                                      head, nxt, tries, RSA_BUDGET)
        attempts += used
        forced += f
    return pos, attempts, forced


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
        bit-identical packing.
    dphi : float
        Increment of phi per compression step (Eqs. A1-A2); the last one is
        clipped to land on ``phi``.  The paper uses 1e-4.
    f_tol : float
        FIRE stops at the target phi when max |F_i^zeta| < f_tol
        (paper: F_Th = 1e-14 k_N d^(3/2)).
    f_tol_compress : float
        The same threshold on the intermediate steps.  Every step has overlaps,
        also below jamming (a relaxed state keeps overlaps of order
        ``f_tol_compress^(2/3)``), and a Hertz overlap relaxes ever more slowly
        as it shrinks, so this sets most of the cost; it is well below the
        force change of one increment,
        ``~1.5 sqrt(xi) dphi / (2 phi) ~ 5e-5`` at ``dphi = 1e-3``.
    phi_start : float
        Area fraction of the random placement, in (0, 0.6] (paper: 0.6).
        Disks that find no room are placed overlapping and relaxed (module
        docstring).
    max_iter : int
        Cap on the FIRE iterations of one relaxation.
    progress : bool
        Show a tqdm bar over the compression steps.

    Returns
    -------
    Packing

    Raises
    ------
    fricstab.laws.ParameterError
        On bad input; the message names the parameter.
    ConvergenceError
        If a FIRE relaxation exceeds ``max_iter`` iterations; the message
        names phi, the residual and the iterations.

    Notes
    -----
    ``dphi`` and ``f_tol_compress`` trade speed for fidelity to the paper's
    protocol (``dphi = 1e-4``, F_Th at every step).  FIRE iterations at N =
    1024, phi = 0.9 (about 45 ns per disk and iteration on one core):
    ``(dphi, f_tol_compress) = (1e-3, 1e-6)``, the defaults: 0.47e6;
    ``(1e-4, 1e-6)``: 1.1e6; ``(1e-3, 1e-8)``: 2.5e6; ``(1e-2, 1e-6)``: 0.14e6.
    Most of them are spent between phi = 0.83 and 0.87, near jamming.

    Each step sets ``L = sqrt(sum(pi d_i^2 / 4) / phi)`` and scales the
    positions by ``L_new / L_old`` (Eqs. A1-A2, exact in phi).  FIRE (Eqs.
    A5-A12): velocity Verlet with masses ``m_i``, ``f_inc = 1.1``,
    ``f_chi = 0.99``, ``N_min = 5``, ``dt_max = 10 dt_ini``, ``dt_ini = 1e-2 t0``,
    ``f_dec = 0.5``, ``chi_start = 0.1``; each relaxation starts from v = 0.
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
    phi, phi_start, dphi = float(phi), float(phi_start), float(dphi)
    n, seed, max_iter = int(n), int(seed), int(max_iter)

    diameter = _diameters(n)
    radius, mass = diameter / 2, diameter**2
    area = float(np.sum(np.pi * diameter**2 / 4))
    box = math.sqrt(area / phi_start)
    pos, attempts, forced = _place(n, box, seed)
    # The last increment is clipped to land on phi; 1e-9 keeps a rounding
    # remainder from adding a step of ~1e-16.  The first entry relaxes the
    # disks that random sequential addition had to place overlapping.
    steps = max(math.ceil((phi - phi_start) / dphi - 1e-9), 0)
    schedule = [phi_start] + [phi_start + k * dphi for k in range(1, steps)] + [phi] * (steps > 0)
    total = 0
    for k, phi_k in enumerate(tqdm(schedule, disable=not progress, desc="compress", unit="step")):
        new_box = math.sqrt(area / phi_k)
        pos *= new_box / box
        box = new_box
        tol = f_tol if k == len(schedule) - 1 else f_tol_compress
        it, res = _fire(pos, radius, mass, box, tol, max_iter, SKIN)
        if it > max_iter:
            raise ConvergenceError(
                f"FIRE did not converge at phi = {phi_k:.6g}: max |F| = {res:.3e} >= {tol:.1e} "
                f"after {max_iter} iterations")
        total += it
    info = {"dphi": dphi, "f_tol": f_tol, "f_tol_compress": f_tol_compress,
            "phi_start": phi_start, "compression_steps": steps, "fire_iterations": total,
            "max_force": float(np.abs(hertz_forces(pos, radius, box)).max()),
            "rsa_attempts": attempts, "rsa_forced": forced,
            "seconds": time.perf_counter() - t_start}
    return Packing(pos=pos, diameter=diameter, box=box, phi=phi, seed=seed, info=info)


def _geometry(pos, radius, box, shift):
    # Writeable C-contiguous float64 copies: one compiled signature per kernel.
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
        ``r_i - r_j`` of the minimum image (module docstring).
    """
    pos, radius, box, shift = _geometry(pos, radius, box, shift)
    dmax = 2 * radius.max() if radius.size else 0.0
    _check_number("box", box, 2 * dmax, None, allowed=f"a number > 2 max diameter = {2 * dmax}")
    if len(pos) < 2:
        return np.empty((0, 2), np.int64), np.empty((0, 2))
    found = _pair_list(pos, radius, box, shift, 0.0)
    order = np.lexsort((found[:, 1], found[:, 0]))
    found = found[order]
    i, j, m, k = found.T
    sep = np.empty((len(found), 2))
    sep[:, 1] = (pos[i, 1] - pos[j, 1]) - k * box
    sep[:, 0] = ((pos[i, 0] - pos[j, 0]) - k * shift) - m * box
    return np.ascontiguousarray(found[:, :2]), sep


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
    """Net frictionless Hertz forces ``F_i`` (Eq. A4, k_N = 1), shape (N, 2).

    Every image within reach counts, so any ``box`` larger than the largest
    diameter (no disk touches its own image) is allowed.
    """
    pos, radius, box, shift = _geometry(pos, radius, box, shift)
    dmax = 2 * radius.max() if radius.size else 0.0
    _check_number("box", box, dmax, None, allowed=f"a number > max diameter = {dmax}")
    force = np.zeros_like(pos)
    if len(pos) >= 2:
        _accumulate(pos, radius, box, shift, _pair_list(pos, radius, box, shift, 0.0), force)
    return force
