"""System-level proof of the chain's assembled Jacobian, for each law.

Hypothesis generates chain states near equilibrium (:func:`chain_states`):
2 to 5 disks, wall overlaps from 1e-12 R to a few rest overlaps (the ends
drawn exactly), ring pairs overlapping down to 1e-12 R, just apart or apart,
and every contact's history at 0, inside, exactly at and past its cap (the
law's own projection puts it on the cap to the bit; a law without a cap gets
multiples of the overlap).  The engine's Jacobian ``K = dF/dq`` (with the
increment rule) is compared with

* the complex step of an independent reference assembly
  (:func:`tests.system_proof.complex_step_jacobian`): <= 1e-10 of max |K|;
* central differences of the engine's forces at a sweep of steps, each column
  at the step its error model (:func:`central_model`) predicts best: the
  error of every column below its model.

The worst errors per law are collected in :data:`WORST` and printed by
:func:`test_worst_errors_per_law` (and in every failure message).
"""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from fricstab._numerics import cylinder_lambda
from fricstab.laws import PAIR_LAW_NAMES, vector_form
from fricstab.scenes.chain import ChainScene, chain_system, rest_overlap

from tests.system_proof import (
    WorstErrors, central_jacobian, complex_step_jacobian, engine_jacobian)

EPS = float(np.finfo(float).eps)
R = 0.5
#: Central-difference steps (length), the model picks one per column.
STEPS = tuple(10.0 ** -k for k in range(4, 14))
#: Safety factor of the central model: the bounds of the three contacts of a
#: disk are added, but a column's rows can pick up the same contact's error
#: through both of its particles, and the truncation constants are those of
#: the leading term only.
KAPPA = 4.0
WORST = WorstErrors(PAIR_LAW_NAMES)


def _overlap_values():
    """Overlaps (over R) with the ends exactly, log-uniform in between."""
    return st.one_of(st.sampled_from([1e-12, 1e-9, 1e-6, 1e-3]),
                     st.floats(math.log(1e-12), math.log(1e-2)).map(math.exp))


@st.composite
def chain_states(draw, law):
    """(scene, state): a generated chain state of ``law`` (module docstring)."""
    n = draw(st.integers(2, 5))
    params = {}
    if law == "lee_hurley":
        params["mur"] = draw(st.sampled_from([0.0, 0.01, 0.1]))
    if vector_form(law) in ("charan", "linear"):
        params["mu"] = draw(st.sampled_from([0.1, 10.0]))
    fx = 0.0 if law == "hertz" else 0.01
    scene = ChainScene(n=n, law=law, fx=fx, params=params)
    system = chain_system(scene)
    dw = rest_overlap(scene)
    wall = []
    for _ in range(n):
        kind = draw(st.sampled_from(["tiny", "range", "range", "apart"]))
        if kind == "tiny":
            wall.append(draw(st.sampled_from([1e-12, 1e-10])) * R)
        elif kind == "range":
            wall.append(draw(st.floats(math.log(1e-12 * R), math.log(3 * dw))
                             .map(math.exp)))
        else:
            wall.append(-draw(st.floats(1e-12, 1e-4)))
    y = R - np.array(wall)
    x = np.empty(n)
    x[0] = R + draw(st.floats(-1e-3, 1e-3))
    for i in range(n - 1):
        kind = draw(st.sampled_from(["overlap", "overlap", "apart"]))
        if kind == "overlap":
            d = 2 * R - draw(_overlap_values()) * R
        else:
            d = 2 * R + draw(st.floats(1e-12, 1e-4))
        dy = y[i + 1] - y[i]
        x[i + 1] = x[i] + math.sqrt(d * d - dy * dy)
    theta = np.array(draw(st.lists(st.floats(-3.0, 3.0), min_size=n, max_size=n)))
    state = system.state(np.column_stack([x, y]), theta)
    c = state.contacts
    nh = c.hist.shape[1]
    directions = np.array(draw(st.lists(st.floats(0.0, 2 * math.pi), min_size=c.n,
                                        max_size=c.n)))
    if nh:
        big = 1e100 if get_capped(law) else 1.0  # squared, still finite
        c.hist[:, 0] = big * np.cos(directions)
        if nh > 1:                         # a _fi law's one slot: a scalar along the tangent
            c.hist[:, 1] = big * np.sin(directions)
        if law == "lee_hurley":
            c.hist[:, 1] = big * np.sign(np.sin(directions) + 0.5)
        if get_capped(law):
            system.project(state)          # every touching contact exactly on its caps
        else:
            c.hist *= np.maximum(_overlaps(system, state), 0.0)[:, None]
        regime = draw(st.lists(st.sampled_from([0.0, "inside", 1.0, "past"]),
                               min_size=c.n * nh, max_size=c.n * nh))
        factors = np.array([draw(st.floats(0.0, 1.0)) if r == "inside" else
                            draw(st.floats(1.0, 3.0)) if r == "past" else r for r in regime])
        c.hist *= factors.reshape(c.n, nh)
        if law in ("charan", "linear"):
            c.hist[c.j < 0, 1] = 0.0        # the wall form has one slot
    return scene, system, state


def get_capped(law):
    from fricstab.laws import get_law
    return get_law(law).capped


def _overlaps(system, state):
    """Overlap of every contact (length; negative: apart)."""
    q, c = state.q, state.contacts
    pair = c.j >= 0
    jj = np.where(pair, c.j, 0)
    dx = q[c.i, 0] - q[jj, 0] - c.m * system.lx
    dy = q[c.i, 1] - q[jj, 1]
    d_pair = system.radius[c.i] + system.radius[jj] - np.hypot(dx, dy)
    return np.where(pair, d_pair, system.radius[c.i] - q[c.i, 1])


def _stiffness_bound(scene, x):
    """Largest entry of a contact block at overlap ``x`` (any history in the drawn range).

    Hertz family: normal 1.5 kn x^(1/2), tangential 2 kt x^(1/2), the
    friction coupling |t| / x^(1/2) with |t| <= 3 t* (3 mu kn x) or, without a
    cap, 3 x; lever arms (1 + R) on both sides.  lee_hurley: the secant and
    tangent normal stiffness pi E*/(lam - 1), Lai's kt and mus times it, and
    the rolling stiffness pi E* R_r^2 / 4, which does not vanish with x.
    """
    p = scene.params
    arm = (1 + R) ** 2
    if vector_form(scene.law) == "linear":  # kn, kt, and sliding mu kn + kt (slip_scale <= 1)
        return arm * (p["kn"] * (1.0 + p["mu"]) + 2.0 * p["kt"])
    if scene.law == "lee_hurley":
        lam = cylinder_lambda(max(x, 1e-300), R, R)
        kn = math.pi * p["E"] / (lam - 1.0)
        return arm * (kn * (3.0 + p["mus"]) + math.pi * p["E"] * (R / 2) ** 2 / 4 * (1 + p["mur"]))
    kt = p.get("kt", 0.0)
    coupling = 3.0 * p.get("mu", 1.0) * p["kn"] if vector_form(scene.law) == "charan" else 3.0 * kt
    return arm * (1.5 * p["kn"] + 2.0 * kt + coupling) * math.sqrt(max(x, 0.0))


def central_model(scene, system, state, h):
    """Bound on the central-difference error of each Jacobian column at step ``h``.

    Per column (a dof of disk p), summed over the contacts c of p and
    multiplied by :data:`KAPPA` (following fricstab/laws/verify.py,
    ``central_error_model``):

    * rounding of the two force evaluations: ``4 eps F / h``, F the sum of the
      magnitudes in a force row (applied forces and contact forces), and of
      the positions: a coordinate near |q| (and a separation near the period)
      carries ``ulp`` of absolute rounding, ``4 |K_c| ulp / h``;
    * truncation where the contact stays on one smooth branch:
      ``|K_c| C (h/delta)^2`` (1/24 for Hertz, 1/8 for Ishima's
      delta^(1/2) t, 1 for the Hertz-cylinder logarithm; for the smoothed
      Coulomb law ``|K_c| h^2 (2/delta^2 + 1/t*^2 + 3/(t* |t|))``: the
      third derivative of its ``|t| t`` term along a pair's 2-vector history
      is 3/|t|, large near t = 0);
    * where a step of ``h`` (moving the overlap by <= h and the history by
      <= (1 + R) h) reaches a point at which the law is C1 but not C2, first
      order: ``|K_c| (1 + R) h / t*`` at t = 0 and ``|K_c| (1 + R) h (1/t* +
      1/delta)`` at the Coulomb circle (charan); where it reaches a cap of
      lee_hurley or the circle of linear (the block jumps there) or the
      contact's edge, the derivatives themselves: ``|K_c|`` and the stiffness
      bound :func:`_stiffness_bound` at overlap delta + 2h.
    """
    f, blocks = system.forces(state, want_blocks=True)
    fc = np.abs(system.contact_forces(state)).max(axis=1)
    kc = np.abs(blocks).max(axis=(1, 2))
    delta = _overlaps(system, state)
    c = state.contacts
    p = scene.params
    fscale = np.abs(system.external).max() + np.bincount(
        np.concatenate([c.i, c.j[c.j >= 0]]),
        np.concatenate([fc, fc[c.j >= 0]]), minlength=system.n).max()
    reach = 2 * h * (1 + R)
    ulp = math.ulp(max(np.abs(state.q).max(), system.lx))
    per_contact = 4 * kc * ulp / h
    nh = c.hist.shape[1]
    for k in range(c.n):
        d = delta[k]
        if d + 2 * h < 0:
            continue
        if d < 2 * h:
            per_contact[k] += _stiffness_bound(scene, d + 2 * h) * (1 + 4 * ulp / h)
            continue
        e = 0.0
        law = vector_form(scene.law)  # a _fi law: its vector law's error model, |t| = |xi|
        if law == "charan":
            tstar = p["mu"] * p["kn"] / p["kt"] * d
            tn = float(np.hypot(*c.hist[k, :2])) if c.j[k] >= 0 and nh > 1 else abs(c.hist[k, 0])
            # curvature 2/delta^2 + 1/t*^2, and near t = 0 the |t| t term of a
            # pair's 2-vector history bends on the scale of |t| itself
            e += kc[k] * h * h * (2 / d ** 2 + 1 / tstar ** 2 + 3 / (tstar * max(tn, h)))
            if tn <= reach:
                e += kc[k] * (1 + R) * h / tstar
            if abs(tn - tstar) <= reach * (1 + tstar / d):
                e += kc[k] * (1 + R) * h * (1 / tstar + 1 / d)
        elif law == "linear":
            # smooth on each side (n turns on the scale r > d, t_hat on |t| = t*);
            # a step that reaches the circle crosses the jump of the block
            tstar = p["mu"] * p["kn"] / p["kt"] * d
            tn = float(np.hypot(*c.hist[k, :2])) if c.j[k] >= 0 and nh > 1 else abs(c.hist[k, 0])
            e += kc[k] * h * h * (1 / d ** 2 + 1 / tstar ** 2)
            if abs(tn - tstar) <= reach * (1 + tstar / d):
                e += kc[k] + _stiffness_bound(scene, d + 2 * h)
        elif law == "lee_hurley":
            e += kc[k] * (h / d) ** 2
            lam = cylinder_lambda(d, R, R)
            fn = math.pi * p["E"] * d / lam
            rr = R / 2
            caps = (p["mus"] * fn, p["mur"] * rr * fn)
            moves = reach * (kc[k] * (1 + p["mus"] + p["mur"]) + _stiffness_bound(scene, d))
            if any(abs(abs(c.hist[k, a]) - caps[a]) <= moves for a in range(2)):
                e += kc[k] + _stiffness_bound(scene, d + 2 * h)
        else:
            e += kc[k] * (0.125 if law == "ishima" else 1 / 24) * (h / d) ** 2
        per_contact[k] += e
    cols = np.flatnonzero(system.family == 0)
    out = []
    for i in cols:
        mine = (c.i == i) | (c.j == i)
        # a pair's error reaches the column of its other particle too
        out += [KAPPA * (4 * EPS * fscale / h + per_contact[mine].sum())] * system.dof
    return np.array(out)


def _check(law, scene, system, state):
    k = engine_jacobian(system, state)
    scale = np.abs(k).max()
    scale = scale if scale > 0 else 1.0   # every contact open: K = 0, errors absolute
    err_cs = np.abs(k - complex_step_jacobian(system, state, R)).max() / scale
    models = np.array([central_model(scene, system, state, h) for h in STEPS])
    best = np.argmin(models, axis=0)
    fds = {int(b): central_jacobian(system, state, STEPS[b]) for b in np.unique(best)}
    err_col = np.array([np.abs(k[:, j] - fds[int(b)][:, j]).max() for j, b in enumerate(best)])
    bound = models[best, np.arange(len(best))]
    WORST.record(law, complex_step=err_cs, central=err_col.max() / scale,
                 central_over_bound=(err_col / bound).max())
    # Complex step of the reference assembly: each block rounds to ~64 eps of
    # its terms (fricstab verify, ROUNDING_ULPS) and a dof sums <= 3 blocks;
    # terms up to ~1e3 max|K| where an overlap of 1e-12 R meets a history on
    # its cap (delta^(-1/2) factors): 1e-10 of max|K| leaves >= 1e2 to spare.
    assert err_cs <= 1e-10, f"{law}: complex step {err_cs:.2e}; worst so far {WORST.lines()}"
    assert np.all(err_col <= bound), (
        f"{law}: central {err_col.max():.2e} > model at column "
        f"{int(np.argmax(err_col / bound))}; worst so far {WORST.lines()}")


@pytest.mark.parametrize("law", PAIR_LAW_NAMES)
def test_chain_jacobian_matches_complex_step_and_central(law):
    @settings(deadline=None)
    @given(chain_states(law))
    def check(case):
        _check(law, *case)

    check()


def test_worst_errors_per_law(capsys):
    """Prints the worst errors the proof met (run after the parametrized tests)."""
    WORST.report("chain", capsys)
