"""Random sequential addition of a bidisperse disk mixture (Ishima App. A.1, first stage).

Scene construction, not a contact search: the cell list here only finds the
already placed disks near a candidate point while the packing is built
(disks never move during the placement).  Every contact search of a
simulation is the engine's neighbour list (:mod:`fricstab.engine.contacts`).

Units of :mod:`fricstab.scenes.packing`: the large diameter ``d = 1``.  Disks
``0 .. N/2 - 1`` have diameter 1 and ``N/2 .. N - 1`` diameter ``1/1.4``;
large disks are placed first.  Candidate points are drawn in batches of
``RSA_BATCH`` from :func:`numpy.random.default_rng` (a fixed batch size, so a
seed fixes the stream); a disk still unplaced after ``RSA_BUDGET`` tries is
put at its last try, overlapping (random sequential addition of this mixture
saturates close to phi = 0.6).
"""

import math

import numpy as np

from fricstab._numba import kernel_jit

__all__ = ["RSA_BATCH", "RSA_BUDGET", "SIZE_RATIO", "diameters", "place"]

SIZE_RATIO = 1.4
RSA_BATCH = 4096         # candidates per draw; fixed, so a seed fixes the stream
RSA_BUDGET = 1_000_000   # tries per disk before it is placed overlapping


def diameters(n):
    """``n/2`` diameters 1, then ``n/2`` diameters ``1/1.4`` (Ishima Sec. II)."""
    return np.concatenate([np.ones(n // 2), np.full(n // 2, 1 / SIZE_RATIO)])


@kernel_jit
def _cell(x, w, nc):
    c = int(x / w)
    return min(max(c, 0), nc - 1)


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


def place(n, box, seed, budget=RSA_BUDGET):
    """Random sequential addition in a periodic square box of side ``box``.

    Returns ``(pos, attempts, forced)``: ``pos`` (n, 2) in ``[0, box)``; the
    number of candidate points tried; ``forced`` disks found no free spot in
    ``budget`` tries and overlap others.
    """
    radius = diameters(n) / 2
    nc = int(box / (2 * radius.max() * (1 + 1e-10)))
    head = np.full(nc * nc if nc >= 3 else 1, -1, np.int64)
    nxt = np.full(n, -1, np.int64)
    pos = np.zeros((n, 2))
    rng = np.random.default_rng(seed)
    placed = tries = attempts = forced = 0
    while placed < n:
        placed, used, tries, f = _rsa(pos, radius, box, placed, rng.random((RSA_BATCH, 2)) * box,
                                      head, nxt, tries, budget)
        attempts += used
        forced += f
    return pos, attempts, forced
