"""Contact sources and the per-contact history store.

A contact is a row ``(i, j, m, k)``:

* a pair of particles ``i < j``, the image of ``j`` displaced by
  ``m (lx, 0) + k (shift, ly)`` (``shift`` the Lees-Edwards offset of the
  image above), so that the separation is
  ``r_i - r_j = (q_i - q_j) - k (shift, ly) - m (lx, 0)`` (:func:`separation`);
* a particle ``i`` and the analytic wall ``w``: ``j = -1 - w``, ``m = k = 0``.

Positions are never folded into the box: the image of a contact is fixed while
it exists, so ``(i, j, m, k)`` names the same physical contact from one
neighbour-list build to the next, and its history is carried by that key
(:func:`carry`).  Contacts are kept sorted by key, so the order in which their
forces are summed is a function of the contact set alone.

Sources (combined by :func:`build`):

* the neighbour list: every pair with a gap below ``skin`` (cell list, or all
  pairs and every image in reach when a periodic direction has fewer than
  three cells), except pairs of two non-free particles (walls made of
  particles do not touch each other);
* static pairs given by the scene (the chain's ring), always listed;
* analytic walls ``y = y0`` with direction ``+1`` (floor: the particle lies
  above) or ``-1`` (ceiling): every free particle within ``skin`` of one.
"""

from dataclasses import dataclass

import numpy as np

from fricstab._numba import hot_inline_jit, kernel_jit
from fricstab.errors import ParameterError

__all__ = ["Contacts", "build", "carry", "contact_keys", "separation"]

#: Image offsets are stored in the key as ``m + IMAGE_RANGE`` in [0, 2 IMAGE_RANGE).
IMAGE_RANGE = 1024


@dataclass
class Contacts:
    """The contact list of a state and its histories (arrays of length K).

    ``i, j, m, k`` (int64) as in the module docstring; ``hist`` (K, H) the
    law's history (zero for a new contact); ``flag`` (K,) int8 the projection
    flags of the last update (1: tangential history at its cap, 2: rolling);
    ``out`` (K, 3): force on i from the contact (x, y) and the elastic normal
    force, written by the dynamics pass.
    """

    i: np.ndarray
    j: np.ndarray
    m: np.ndarray
    k: np.ndarray
    hist: np.ndarray
    flag: np.ndarray
    out: np.ndarray

    @property
    def n(self):
        return len(self.i)

    @property
    def pairs(self):
        """Mask of particle pairs (the others are wall contacts)."""
        return self.j >= 0

    def copy(self):
        return Contacts(*(np.array(a, copy=True) for a in
                          (self.i, self.j, self.m, self.k, self.hist, self.flag, self.out)))

    def arrays(self, prefix="contact_"):
        """The arrays by name (for checkpoints)."""
        return {prefix + name: getattr(self, name)
                for name in ("i", "j", "m", "k", "hist", "flag", "out")}

    @classmethod
    def from_arrays(cls, d, prefix="contact_"):
        return cls(*(np.array(d[prefix + name]) for name in
                     ("i", "j", "m", "k", "hist", "flag", "out")))

    @classmethod
    def empty(cls, n_hist):
        z = np.zeros(0, np.int64)
        return cls(z, z.copy(), z.copy(), z.copy(), np.zeros((0, n_hist)),
                   np.zeros(0, np.int8), np.zeros((0, 3)))


@hot_inline_jit
def separation(q, i, j, m, k, lx, ly, shift):
    """``r_i - r_j`` of a pair contact (module docstring)."""
    dx = ((q[i, 0] - q[j, 0]) - k * shift) - m * lx
    dy = (q[i, 1] - q[j, 1]) - k * ly
    return dx, dy


def contact_keys(i, j, m, k, n_particles, n_walls):
    """Sorting keys of contacts: ``(i, j or N + wall, m, k)`` packed into int64."""
    i, j, m, k = (np.asarray(a, dtype=np.int64) for a in (i, j, m, k))
    if np.any(np.abs(m) >= IMAGE_RANGE) or np.any(np.abs(k) >= IMAGE_RANGE):
        raise ParameterError(f"a contact's periodic image is more than {IMAGE_RANGE} box "
                             "lengths away: fold the positions into the box")
    jj = np.where(j >= 0, j, n_particles - 1 - j)
    width = n_particles + n_walls
    return ((i * width + jj) * (2 * IMAGE_RANGE) + (m + IMAGE_RANGE)) * (2 * IMAGE_RANGE) \
        + (k + IMAGE_RANGE)


@kernel_jit
def _cell_of(x, lo, w, nc):
    c = int((x - lo) / w)
    return min(max(c, 0), nc - 1)


@kernel_jit
def _emit(out, count, i, j, m, k):
    if count < out.shape[0]:
        out[count, 0] = i
        out[count, 1] = j
        out[count, 2] = m
        out[count, 3] = k
    return count + 1


@kernel_jit
def _near(q, radius, i, j, m, k, lx, ly, shift, skin):
    dx, dy = separation(q, i, j, m, k, lx, ly, shift)
    lim = radius[i] + radius[j] + skin
    return dx * dx + dy * dy < lim * lim


@kernel_jit
def _search_all(q, radius, free, lx, ly, shift, skin, out):
    """Every pair and every image in reach (small periodic boxes)."""
    n = q.shape[0]
    cut = 2.0 * radius.max() + skin
    ry = int(np.ceil(cut / ly)) + 1 if ly > 0.0 else 0
    rx = int(np.ceil(cut / lx)) + 1 if lx > 0.0 else 0
    count = 0
    for i in range(n):
        for j in range(i + 1, n):
            if not (free[i] or free[j]):
                continue
            kc = int(np.rint((q[i, 1] - q[j, 1]) / ly)) if ly > 0.0 else 0
            for k in range(kc - ry, kc + ry + 1):
                mc = int(np.rint(((q[i, 0] - q[j, 0]) - k * shift) / lx)) if lx > 0.0 else 0
                for m in range(mc - rx, mc + rx + 1):
                    if _near(q, radius, i, j, m, k, lx, ly, shift, skin):
                        count = _emit(out, count, i, j, m, k)
    return count


@kernel_jit
def _search_cells(q, radius, free, lx, ly, shift, skin, out):
    """Pairs with a gap below ``skin`` from a cell list (>= 3 cells per periodic direction).

    Periodic directions bin the positions folded into the box, Lees-Edwards
    consistently (a fold by ``a`` boxes in y moves x by ``a shift``); open
    directions bin between the extreme positions.  The image of a found pair
    is the minimum image of the raw positions.
    """
    n = q.shape[0]
    cut = 2.0 * radius.max() + skin
    xs = np.empty(n)
    ys = np.empty(n)
    for i in range(n):
        y = q[i, 1]
        x = q[i, 0]
        if ly > 0.0:
            a = np.floor(y / ly)
            y -= a * ly
            x -= a * shift
        if lx > 0.0:
            x -= lx * np.floor(x / lx)
        xs[i] = x
        ys[i] = y
    if lx > 0.0:
        x0, wx = 0.0, lx
    else:
        x0, wx = xs.min(), xs.max() - xs.min() + cut
    if ly > 0.0:
        y0, wy = 0.0, ly
    else:
        y0, wy = ys.min(), ys.max() - ys.min() + cut
    ncx = max(int(wx / (cut * (1.0 + 1e-10))), 1)
    ncy = max(int(wy / (cut * (1.0 + 1e-10))), 1)
    cw, ch = wx / ncx, wy / ncy
    cx = np.empty(n, np.int64)
    cy = np.empty(n, np.int64)
    start = np.zeros(ncx * ncy + 1, np.int64)
    for i in range(n):
        cx[i] = _cell_of(xs[i], x0, cw, ncx)
        cy[i] = _cell_of(ys[i], y0, ch, ncy)
        start[cy[i] * ncx + cx[i] + 1] += 1
    for c in range(ncx * ncy):
        start[c + 1] += start[c]
    fill = start[:-1].copy()
    order = np.empty(n, np.int64)
    for i in range(n):
        c = cy[i] * ncx + cx[i]
        order[fill[c]] = i
        fill[c] += 1
    count = 0
    for i in range(n):
        for oy in range(-1, 2):
            row = cy[i] + oy
            cross = 0
            if row < 0 or row >= ncy:
                if ly <= 0.0:
                    continue
                cross = -1 if row < 0 else 1
                row -= cross * ncy
            xc = xs[i] - cross * shift
            if lx > 0.0:
                xc -= lx * np.floor(xc / lx)
            col0 = _cell_of(xc, x0, cw, ncx)
            for ox in range(-1, 2):
                col = col0 + ox
                if col < 0 or col >= ncx:
                    if lx <= 0.0:
                        continue
                    col = col % ncx
                c = row * ncx + col
                for idx in range(start[c], start[c + 1]):
                    j = order[idx]
                    if j <= i or not (free[i] or free[j]):
                        continue
                    k = int(np.rint((q[i, 1] - q[j, 1]) / ly)) if ly > 0.0 else 0
                    m = int(np.rint(((q[i, 0] - q[j, 0]) - k * shift) / lx)) if lx > 0.0 else 0
                    if _near(q, radius, i, j, m, k, lx, ly, shift, skin):
                        count = _emit(out, count, i, j, m, k)
    return count


@kernel_jit
def _search(q, radius, free, lx, ly, shift, skin, out):
    cut = 2.0 * radius.max() + skin
    wide = 3.0 * cut * (1.0 + 1e-10)   # the cell list's width, so >= 3 cells where periodic
    small = (lx > 0.0 and lx < wide) or (ly > 0.0 and ly < wide)
    if small:
        return _search_all(q, radius, free, lx, ly, shift, skin, out)
    return _search_cells(q, radius, free, lx, ly, shift, skin, out)


@kernel_jit
def _neighbour_pairs(q, radius, free, lx, ly, shift, skin):
    out = np.empty((4 * q.shape[0] + 16, 4), np.int64)
    count = _search(q, radius, free, lx, ly, shift, skin, out)
    if count > out.shape[0]:
        out = np.empty((count, 4), np.int64)
        _search(q, radius, free, lx, ly, shift, skin, out)
    return out[:count]


def _wall_contacts(q, radius, free, walls, skin):
    rows = []
    for w, (y0, direction) in enumerate(walls):
        gap = (q[:, 1] - y0) * direction - radius
        idx = np.flatnonzero(free & (gap < skin))
        rows.append(np.column_stack([idx, np.full(len(idx), -1 - w), np.zeros((len(idx), 2),
                                                                              np.int64)]))
    return np.vstack(rows).astype(np.int64) if rows else np.zeros((0, 4), np.int64)


def build(q, radius, free, lx, ly, shift, skin, walls=(), static=None, neighbours=True):
    """Contact rows ``(i, j, m, k)`` of all sources, sorted by key (module docstring).

    ``free`` (N,) bool marks the particles that move under forces;
    ``walls`` is a sequence of ``(y0, direction)``; ``static`` an (S, 4) array
    of pairs listed whatever their distance (``i < j``).
    """
    parts = []
    if neighbours and len(q) > 1:
        parts.append(_neighbour_pairs(q, radius, free, float(lx), float(ly), float(shift),
                                      float(skin)))
    if static is not None and len(static):
        parts.append(np.asarray(static, dtype=np.int64))
    if len(walls):
        parts.append(_wall_contacts(q, radius, free, walls, skin))
    rows = np.vstack(parts) if parts else np.zeros((0, 4), np.int64)
    keys = contact_keys(rows[:, 0], rows[:, 1], rows[:, 2], rows[:, 3], len(q), len(walls))
    order = np.argsort(keys, kind="stable")
    keys, rows = keys[order], rows[order]
    if len(keys) > 1 and np.any(keys[1:] == keys[:-1]):
        raise ParameterError("a contact is listed twice (a static pair also found by the "
                             "neighbour list)")
    return np.ascontiguousarray(rows), keys


def carry(old, old_keys, rows, keys, n_hist):
    """A :class:`Contacts` for ``rows`` with the histories of ``old`` carried by key."""
    hist = np.zeros((len(rows), n_hist))
    flag = np.zeros(len(rows), np.int8)
    out = np.zeros((len(rows), 3))
    if old is not None and old.n and len(rows):
        pos = np.searchsorted(old_keys, keys)
        pos = np.minimum(pos, len(old_keys) - 1)
        found = old_keys[pos] == keys
        hist[found] = old.hist[pos[found]]
        flag[found] = old.flag[pos[found]]
        out[found] = old.out[pos[found]]
    return Contacts(rows[:, 0].copy(), rows[:, 1].copy(), rows[:, 2].copy(),
                    rows[:, 3].copy(), hist, flag, out)
