"""System-level proof of the plane-shear cell's Jacobian, for each law.

Hypothesis builds small cells: a fixed bottom row of touching disks filling
the period (family 1), bulk disks (family 0) each placed on an earlier disk
at an overlap drawn log-uniformly down to 1e-12 R, and driven top-row disks
(family 2) placed on the bulk; the box is so short (three bottom disks) that
contacts cross the periodic boundary and the engine lists images.  Every
history is drawn at 0, inside its cap, exactly on it or past it (the law's
caps: lee_hurley's Coulomb and rolling caps, charan's and linear's circle
|t| = t*; ishima has none, hertz no history).  Then, with the walls clamped:

* the engine's assembled K = dF/dq against the complex step of the
  independent reference assembly of tests/system_proof.py (the verified
  scalar kernels, contact by contact): <= 1e-10 of max|K| (round-off of
  ~100-flop blocks, 64 eps each, summed over < 10 contacts per dof: 1e-13
  expected; through a cap both follow the slide branch);
* central differences of the engine's forces (histories advanced by the
  increment rule) within the error model of :func:`central_bound`;
* with every particle's dof (walls included, ``free_only=False``) uniform
  translations in x and y are zero modes to 32 eps of max|K| (each block's
  rows sum to zero up to the rounding of a few terms).
"""

import numpy as np
import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

from fricstab.engine import Material, System
from fricstab.generated.dispatch import N_HIST
from fricstab.laws import FRAME_INDIFFERENT, vector_form

from tests.system_proof import (
    WorstErrors, central_jacobian, complex_step_jacobian, engine_jacobian, translation_residual)

EPS = np.finfo(float).eps
#: Laws in the cell's reduced units (E* = 1, L0 = 1; kn, kt of the quick preset's order).
LAWS = {"lee_hurley": {"E": 1.0, "nu": 0.2, "mus": 0.7, "mur": 0.01},
        "hertz": {"kn": 5.0},
        "charan": {"kn": 5.0, "kt": 3.4, "mu": 0.7},
        "ishima": {"kn": 5.0, "kt": 3.4},
        "linear": {"kn": 1.0, "kt": 0.3, "mu": 0.7}}
LAWS.update({f"{law}_fi": LAWS[law] for law in FRAME_INDIFFERENT})  # issue 36
#: History modes: 0, inside the cap, exactly on it, past it.
MODES = ("zero", "inside", "at", "past")
H_FD = 1e-7
WORST = WorstErrors(sorted(LAWS))


def _disk_on(rng, parent, r, overlap, pos, radius, lx):
    """A disk of radius r above disk ``parent`` at ``overlap``, overlapping no other by > 5 %."""
    for _ in range(60):
        ang = rng.uniform(0.15, np.pi - 0.15)
        p = pos[parent] + (radius[parent] + r - overlap) * np.array([np.cos(ang), np.sin(ang)])
        d = pos - p
        d[:, 0] -= lx * np.round(d[:, 0] / lx)
        gap = np.hypot(d[:, 0], d[:, 1]) - radius - r
        gap[parent] = np.inf
        if gap.min() > -0.05 * r:
            return p
    return None


@st.composite
def cells(draw, law):
    """(system, state) of a small cell with drawn overlaps and histories (module doc)."""
    rng = np.random.default_rng(draw(st.integers(0, 2 ** 32 - 1)))
    r_bot = rng.uniform(0.8, 1.2, 3)
    lx = 2.0 * r_bot.sum()
    x = np.concatenate([[0.0], np.cumsum(r_bot[:-1] + r_bot[1:])]) + r_bot[0]
    pos = [np.array([xk, 0.0]) for xk in x]
    radius, family = list(r_bot), [1, 1, 1]
    n_bulk = draw(st.integers(2, 4))
    exponents = st.one_of(st.sampled_from([-12.0, -1.5]), st.floats(-12.0, -1.5))
    for k in range(n_bulk + 2):
        top = k >= n_bulk
        r = rng.uniform(0.8, 1.2)
        choices = [i for i, f in enumerate(family) if (f == 0 if top else True)]
        parent = choices[rng.integers(len(choices))]
        overlap = (radius[parent] + r) / 2 * 10.0 ** draw(exponents)
        p = _disk_on(rng, parent, r, overlap, np.array(pos), np.array(radius), lx)
        assume(p is not None)
        pos.append(p)
        radius.append(r)
        family.append(2 if top else 0)
    radius = np.array(radius)
    mass = np.pi * radius ** 2
    system = System(Material(law, LAWS[law]), radius, mass, mass * radius ** 2 / 2,
                    family=np.array(family), lx=lx, skin=0.3)
    state = system.state(np.array(pos), rng.uniform(-3, 3, len(radius)))
    _draw_histories(draw, rng, system, state)
    return system, state


def _caps(system, state):
    """The histories projected from far outside: each contact's cap, per slot."""
    s = state.copy()
    s.contacts.hist[:] = 1e100    # squares stay finite; far beyond any cap
    system.project(s)
    return np.abs(s.contacts.hist)


def _draw_histories(draw, rng, system, state):
    c = state.contacts
    nh = N_HIST[system.law_id]
    if nh == 0 or c.n == 0:
        return
    modes = draw(st.lists(st.sampled_from(MODES), min_size=c.n, max_size=c.n))
    capped = system.material.info.capped
    caps = _caps(system, state) if capped else None
    d = state.q[c.i, :2] - state.q[c.j, :2] - np.column_stack([c.m * system.lx, 0 * c.m])
    delta = system.radius[c.i] + system.radius[c.j] - np.hypot(d[:, 0], d[:, 1])
    for k, mode in enumerate(modes):
        if mode == "zero":
            continue
        if not capped:                       # ishima: no cap, a history of the overlap's size
            c.hist[k, :nh] = max(delta[k], 1e-12) * rng.uniform(-1, 1, nh)
            continue
        factor = {"inside": rng.uniform(0.0, 1.0), "at": 1.0,
                  "past": 1.0 + 10.0 ** rng.uniform(-9, 0)}[mode]
        if vector_form(system.material.law) in ("charan", "linear"):  # the circle |t| = t*
            ang = rng.uniform(0, 2 * np.pi)
            t = caps[k, :2]                  # the cap along a fixed direction: rescale
            unit = np.array([np.cos(ang), np.sin(ang)])[:len(t)]
            unit = np.sign(unit) if len(t) == 1 else unit  # a _fi law's scalar: a sign
            c.hist[k, :2] = _norm(t[None])[0] * factor * unit
        else:                                # lee_hurley: ft and mr, each its own cap
            sign = rng.choice([-1.0, 1.0], nh)
            each = factor if mode != "inside" else rng.uniform(0, 1, nh)
            c.hist[k, :nh] = sign * caps[k, :nh] * each


def _norm(hist):
    """|t| per row: a vector history's length, or a _fi law's scalar's magnitude."""
    return np.hypot(*hist.T) if hist.shape[1] == 2 else np.abs(hist[:, 0])


def _rates(system, state):
    """Largest history change per unit generalized displacement, per contact (the rule A)."""
    from tests.system_proof import _increments, free_dofs
    rate = np.zeros(state.contacts.n)
    for col in free_dofs(system, free_only=False):
        _, dh = _increments(system, state, col)
        rate = np.maximum(rate, np.abs(dh).max(axis=1) if dh.size else 0.0)
    return rate


def central_bound(system, state, h):
    """Error model of the central differences per entry of K (free dof), and where it holds.

    A contact whose branch may change within the +-h step is not differentiable
    there, so the entries it feeds are left to the complex step (the mask is
    False): an overlap within 4 h (1 + R) of zero (it may open or close), a
    capped history within 4 h |A| of its cap (the cap's kink), charan's
    tangential displacement within 4 h |A| of t = 0 (its |t| t term is C1, not
    C2, DESIGN.md); |A| the contact's largest history change per unit
    displacement.  Elsewhere, per contact with largest block entry |K_c|:
    truncation 10 |K_c| (h (1 + R) / delta_c)^2 (the law's derivatives grow like
    1/delta per order) and the step's own rounding 4 eps max|q| / h |K_c|; for charan + 2 kt^2 (1 + R)^4 h^2 / (mu kn sqrt(delta) |t|)
    (the curvature of kt^2 |t| t / (mu kn sqrt(delta))); plus the rounding of
    the force sums, 16 eps sum_c |f_c| / h per row.
    """
    c = state.contacts
    _, blocks = system.forces(state, want_blocks=True)
    dof = system.dof
    arm = 1.0 + system.radius.max()
    d = state.q[c.i, :2] - state.q[c.j, :2] - np.column_stack([c.m * system.lx, 0 * c.m])
    delta = system.radius[c.i] + system.radius[c.j] - np.hypot(d[:, 0], d[:, 1])
    size = np.abs(blocks).max(axis=(1, 2)) if c.n else np.zeros(0)
    touch = delta > 0
    safe = np.where(touch, delta, 1.0)
    # truncation, and the step actually taken: q +- h rounds to ulp(|q|) ~ eps |q|
    contrib = np.where(touch, size * (10.0 * (h * arm / safe) ** 2
                                      + 4 * EPS * np.abs(state.q).max() / h), 0.0)
    kink = np.abs(delta) < 4 * h * arm
    rate = _rates(system, state)
    law = vector_form(system.material.law)
    if system.material.info.capped:
        caps = _caps(system, state)
        hist = c.hist[:, :caps.shape[1]]
        if law == "charan":
            tn, cap = _norm(hist), _norm(caps)
            kink |= (np.abs(tn - cap) < 4 * h * rate) | (tn < 4 * h * rate)
            kn, kt, mu = system._p
            contrib += np.where(touch & (tn > 0), 2 * kt ** 2 * arm ** 4 * h ** 2
                                / (mu * kn * np.sqrt(safe) * np.where(tn > 0, tn, 1.0)), 0.0)
        elif law == "linear":  # the block jumps at the circle, which moves with delta
            tn, cap = _norm(hist), _norm(caps)
            kink |= np.abs(tn - cap) < 4 * h * (rate + arm * cap / safe)
        else:
            kink |= np.any(np.abs(np.abs(hist) - caps) < 4 * h * rate[:, None], axis=1)
    index = np.full(system.n, -1)
    free = np.flatnonzero(system.free)
    index[free] = np.arange(len(free))
    n = len(free) * dof
    bound = np.zeros((n, n))
    checked = np.ones((n, n), bool)
    fmag = np.abs(system.contact_forces(state))
    row_round = np.zeros(n)
    for k in range(c.n):
        parts = [(0, c.i[k]), (1, c.j[k])]
        for a, p in parts:
            if index[p] < 0:
                continue
            rows = slice(index[p] * dof, (index[p] + 1) * dof)
            row_round[rows] += fmag[k, a * dof:(a + 1) * dof].max()
            for b, q in parts:
                if index[q] >= 0:
                    cols = slice(index[q] * dof, (index[q] + 1) * dof)
                    bound[rows, cols] += contrib[k]
                    checked[rows, cols] &= not kink[k]
    return bound + 16 * EPS * row_round[:, None] / h, checked


@pytest.mark.parametrize("law", sorted(LAWS))
@settings(deadline=None, suppress_health_check=[HealthCheck.filter_too_much,
                                               HealthCheck.too_slow])
@given(data=st.data())
def test_cell_jacobian_is_proven_for_every_law(law, data):
    system, state = data.draw(cells(law))
    k = engine_jacobian(system, state)
    scale = np.abs(k).max()
    assume(scale > 0)
    err_cs = np.abs(k - complex_step_jacobian(system, state, 1.0)).max() / scale
    fd = central_jacobian(system, state, H_FD)
    bound, checked = central_bound(system, state, H_FD)
    err_fd = np.where(checked, np.abs(fd - k), 0.0)
    zero = translation_residual(system, state)   # in eps
    WORST.record(law, complex_step=err_cs, central=err_fd.max() / scale,
                 central_over_bound=(err_fd / (bound + 1e-14 * scale)).max(), zero_mode=zero)
    assert err_cs <= 1e-10
    assert np.all(err_fd <= bound + 1e-14 * scale)
    assert zero <= 32


def test_clean_states_are_checked_tightly_by_central_differences():
    """Where no branch can change within the step, central differences alone are a
    sharp check: overlaps >= 1e-2 R, histories >= 10 % off their caps give an
    error below 1e-6 of max|K| (truncation (h/delta)^2 = 1e-10, rounding
    eps |F| / h ~ 1e-11)."""
    rng = np.random.default_rng(5)
    radius = np.array([1.0, 1.1, 0.9, 1.0])
    pos = np.array([[0.0, 0.0], [2.07, 0.0], [1.0, 1.6], [1.0, -1.62]])
    for law in sorted(LAWS):
        mass = np.pi * radius ** 2
        system = System(Material(law, LAWS[law]), radius, mass, mass * radius ** 2 / 2,
                        family=np.array([0, 0, 0, 1]), lx=50.0, skin=0.3)
        state = system.state(pos)
        nh = N_HIST[system.law_id]
        if nh:
            caps = _caps(system, state) if system.material.info.capped else 1e-2
            state.contacts.hist[:, :nh] = 0.5 * caps * rng.uniform(-1, 1, (state.contacts.n, nh))
        k = engine_jacobian(system, state)
        assert np.abs(central_jacobian(system, state, H_FD) - k).max() <= 1e-6 * np.abs(k).max()


def test_worst_errors_per_law(capsys):
    """Prints the worst errors the proof met (run after the tests above)."""
    WORST.report("plane-shear cell", capsys)
