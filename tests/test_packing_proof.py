"""System-level proof of the packing's Jacobian for each law (hertz, ishima, charan, lee_hurley,
linear).

Hypothesis generates periodic packings with a Lees-Edwards offset: a chain of
contacts with overlaps from 1e-12 R to 3e-2 R, every disk then moved by a
random lattice vector ``a (shift, L) + b (L, 0)`` (the engine never folds
positions, so contacts cross the boundaries and the sheared image rows), and
histories at zero, inside, at and past the law's cap.  The engine's assembled
``K = dF/dq`` (with the increment rule) is compared with

* the complex step of an independent reference assembly through the verified
  scalar kernels (``tests/system_proof.py``): exact to round-off, so
  ``<= 1e-10 max|K|`` (blocks of ~100 flops, 64 eps each, summed over fewer
  than 10 contacts per dof: 1e-13 expected);
* central differences of the engine's force function with the histories
  advanced by the increment rule, step ``h = 1e-8``: truncation
  ``(h / delta_min)^2`` relative (``h^2 F''' / 6`` of a power-law force,
  ``F''' ~ F' / delta^2``; a factor 10 covers the constants and charan's cap
  term ``(h / t*)^2``), plus the rounding of the step itself, ``(q + h) - q``
  exact only to ``eps |q|`` (positions up to a few boxes away: ``4 eps
  max|q| / h`` relative), plus round-off ``eps sum|f| / h`` (64 eps for the
  sum of a dof's contact forces); for charan at zero history, whose ``|t| t``
  (Eq. 5) is C1 but not C2 there, the first-order term ``h / t*`` relative.
  Only where the finite difference does not cross a kink: overlaps >= 1e-3 R (h does not open a contact) and no history
  exactly on its cap;

and the uniform translations in x and y must be zero modes of the full
Jacobian to 32 eps (each entry of ``K e`` sums O(z) terms of size max|K|).
"""

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from fricstab._numerics import cylinder_lambda
from fricstab.laws import vector_form
from fricstab.scenes.packing_friction import Backbone, material, packing_system
from fricstab.scenes.packing_relax import separations

from tests.system_proof import (
    WorstErrors, central_jacobian, complex_step_jacobian, engine_jacobian, translation_residual)

EPS = np.finfo(float).eps
LAWS = ("hertz", "ishima", "charan", "lee_hurley", "linear", "ishima_fi", "charan_fi",
        "linear_fi")
CAPS = {"zero": 0.0, "inside": 0.5, "at": 1.0, "past": 1.5}
WORST = WorstErrors(LAWS)


class _Box(Backbone):
    """What :func:`packing_system` needs: radii and the box side (a Backbone, which the
    front door asks for, with only those two fields set)."""

    def __init__(self, radius, box):
        object.__setattr__(self, "radius", radius)
        object.__setattr__(self, "box", box)


def _overlaps(system, state):
    c, r = state.contacts, system.radius
    sep = separations(system, state)
    return r[c.i] + r[c.j] - np.hypot(sep[:, 0], sep[:, 1])


def _set_histories(system, state, regimes, rng):
    """Histories of the touching contacts at a fraction ``CAPS[regime]`` of the law's cap."""
    law, p = vector_form(system.material.law), system.material.params
    c, r = state.contacts, system.radius
    delta = _overlaps(system, state)
    for a in range(c.n):
        if delta[a] <= 0 or law == "hertz":
            continue
        s = CAPS[regimes[a % len(regimes)]]
        phi = rng.uniform(0, 2 * np.pi)
        # a direction: a unit vector, or a sign for a _fi law's scalar along the tangent
        unit = np.array([np.cos(phi), np.sin(phi)][:c.hist.shape[1]])
        unit = np.sign(unit) if len(unit) == 1 else unit
        if law == "ishima":        # no cap: a displacement of the overlap's size
            c.hist[a] = s * delta[a] * unit
        elif law in ("charan", "linear"):  # t* = mu (kn/kt) delta (Charan Eq. 5; linear's cap)
            tstar = p["mu"] * p["kn"] / p["kt"] * delta[a]
            c.hist[a] = s * tstar * unit
        else:                      # caps mus F_n and mur R_r F_n (Lee & Hurley A10, A18)
            ri, rj = r[c.i[a]], r[c.j[a]]
            fn = np.pi * p["E"] * delta[a] / float(cylinder_lambda(delta[a], ri, rj))
            sign = rng.choice([-1.0, 1.0], 2)
            c.hist[a] = [sign[0] * s * p["mus"] * fn,
                         sign[1] * s * p["mur"] * ri * rj / (ri + rj) * fn]
    return delta


def _place(n, box, shift, logs, rng):
    """A chain of contacts with overlaps ``10^logs R``, moved by random lattice vectors."""
    radius = rng.choice([0.5, 0.5 / 1.4], n)
    pos = np.zeros((n, 2))
    pos[0] = rng.uniform(0, box, 2)
    for k in range(1, n):
        parent = rng.integers(k)
        angle = rng.uniform(0, 2 * np.pi)
        dist = radius[k] + radius[parent] - 10.0 ** logs[k - 1] * radius[k]
        pos[k] = pos[parent] + dist * np.array([np.cos(angle), np.sin(angle)])
    a, b = rng.integers(-2, 3, (2, n))
    pos[:, 0] += a * shift + b * box
    pos[:, 1] += a * box
    return radius, pos


@st.composite
def packings(draw, law, min_log_overlap=-12.0, regimes=tuple(CAPS)):
    """A periodic state under ``law`` (module docstring) and its smallest touching overlap.

    Disks placed by chance on others (or on images) may overlap deeply: such
    a placement is redrawn (up to 100 times, from the same seed) so that every
    overlap stays below 0.2 R, the law's regime.
    """
    n = draw(st.integers(3, 8))
    box = draw(st.floats(2.6, 7.0))
    shift = draw(st.floats(-box, box))
    logs = draw(st.lists(st.floats(min_log_overlap, -1.5), min_size=n - 1, max_size=n - 1))
    which = draw(st.lists(st.sampled_from(regimes), min_size=1, max_size=6))
    rng = np.random.default_rng(draw(st.integers(0, 2**32 - 1)))
    for _ in range(100):
        radius, pos = _place(n, box, shift, logs, rng)
        system = packing_system(_Box(radius, box), material(law), skin=0.05)
        state = system.state(pos, shift=shift)
        delta = _overlaps(system, state)
        if delta.max() < 0.2 * radius.min():
            break
    assume(delta.max() < 0.2 * radius.min())
    _set_histories(system, state, which, rng)
    return system, state, float(delta[delta > 0].min())


def _zero_modes(system, state):
    """Translations: |K e| <= 32 eps max|K| (each entry sums O(Z) terms of size max|K|)."""
    worst = translation_residual(system, state)
    assert worst <= 32
    return worst


@pytest.mark.parametrize("law", LAWS)
@settings(max_examples=40, deadline=None)
@given(data=st.data())
def test_jacobian_matches_complex_step_of_the_reference(law, data):
    system, state, _ = data.draw(packings(law))
    k = engine_jacobian(system, state)
    scale = np.abs(k).max()
    assert scale > 0
    err = np.abs(k - complex_step_jacobian(system, state, 1.0)).max() / scale
    WORST.record(law, complex_step=err, zero_mode=_zero_modes(system, state))
    assert err <= 1e-10


@pytest.mark.parametrize("law", LAWS)
@settings(max_examples=25, deadline=None)
@given(data=st.data())
def test_jacobian_matches_central_differences(law, data):
    h = 1e-8
    system, state, delta_min = data.draw(packings(law, -3.0, ("zero", "inside", "past")))
    k = engine_jacobian(system, state)
    scale = np.abs(k).max()
    fsum = np.abs(system.contact_forces(state)).max() * 10    # <= 10 contacts per disk
    qmax = np.abs(state.q).max()
    bound = scale * (10 * (h / delta_min) ** 2 + 4 * EPS * qmax / h) + 64 * EPS * fsum / h
    if vector_form(law) == "charan":  # |t| t of Eq. 5 is C1 at t = 0: first order, h / t*
        p = system.material.params
        bound += scale * h / (p["mu"] * p["kn"] / p["kt"] * delta_min)
    err = np.abs(k - central_jacobian(system, state, h)).max()
    WORST.record(law, central=err / scale, central_over_bound=err / bound)
    assert err <= bound


def test_worst_errors_per_law(capsys):
    """Prints the worst errors the proof met (run after the tests above)."""
    WORST.report("periodic packing", capsys)
