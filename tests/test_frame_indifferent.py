"""The frame-indifferent laws (issue 36): a history kept on the tangent line (symbolic/frame.py).

(a) A loaded pair of disks rigidly rotated by 90 degrees in 100 steps of the
laws' own ``advance``: under ``ishima`` the lab-frame history ends up along
the normal, so the "tangential" force has a normal part of the order of F_n;
under ``ishima_fi`` (and ``charan_fi``, ``linear_fi``) it stays at rounding.
(b) At any one geometry a ``_fi`` law's forces are its vector law's at
``t = xi t_hat(n)``, and its increment row is ``t_hat^T A``.
"""

import math

import numpy as np
import pytest

from fricstab._numerics import pair_geometry
from fricstab.laws import FRAME_INDIFFERENT, get_law, vector_form

EPS = np.finfo(float).eps
PARAMS = {"kn": 1.0, "kt": 1.0, "mu": 0.5}
RI, RJ = 0.5, 0.4
DELTA = 0.02


def _p(info):
    return np.array([PARAMS[k] for k in info.params])


def _rotate(name, xi0, steps=100, angle=math.pi / 2):
    """Worst ``|F_i . n - F_n| / F_n`` over a rigid rotation of the pair, and the last F_n.

    The pair (overlap DELTA) turns about its midpoint by ``angle`` in ``steps``;
    each disk spins with it (``dtheta = dphi``; ``dl = R dphi`` in Ishima's
    coordinates).  Before turning, one step shears the contact by ``xi0``
    along the tangent, so the history starts at ``xi0 t_hat``.
    """
    info = get_law(name)
    p, arm = _p(info), (lambda r: r if info.rotation == "l" else 1.0)  # dq3 = arm dphi
    d = RI + RJ - DELTA
    h, f, aux = np.zeros(info.n_hist), np.zeros(6), np.zeros(4)

    def centres(phi):
        n = np.array([math.cos(phi), math.sin(phi)])
        return RJ / (RI + RJ) * d * n, -RI / (RI + RJ) * d * n  # ci - cj = d n

    worst, ci, cj = 0.0, *centres(0.0)
    tangent = np.array([0.0, -1.0])  # t_hat = (n_y, -n_x) at phi = 0
    moves = [(0.0, xi0 * tangent, 0.0)] + [(angle / steps, None, angle / steps)] * steps
    phi = 0.0
    for dphi, shear, spin in moves:
        phi += dphi
        ni, nj = centres(phi)
        if shear is not None:
            ni = ni + shear
        dui = np.array([*(ni - ci), arm(RI) * spin])
        duj = np.array([*(nj - cj), arm(RJ) * spin])
        ci, cj = ni, nj
        dx, dy = ci - cj
        r, delta, lam = pair_geometry(dx, dy, RI, RJ, info.width)
        info.advance(dx, dy, RI, RJ, r, delta, lam, p, h, dui, duj, 0.0, f, aux, True)
        n = np.array([dx, dy]) / r
        fn = aux[3]
        normal_part = f[0] * n[0] + f[1] * n[1] - fn
        # Error model: F_x, F_y are fn n + ft t_hat, each a few products (<= 4 eps of
        # |fn| + |ft|), then a two-term dot product with n (2 eps); fn as the kernel's.
        scale = fn + math.hypot(f[0] - fn * n[0], f[1] - fn * n[1])
        worst = max(worst, abs(normal_part) / scale)
    return worst, fn


@pytest.mark.parametrize("law", FRAME_INDIFFERENT)
def test_rotation_keeps_the_tangential_force_tangent(law):
    xi0 = 0.3 * DELTA  # below charan's and linear's t* = mu kn/kt delta = 0.5 delta
    lab, _ = _rotate(law, xi0)
    fi, _ = _rotate(f"{law}_fi", xi0)
    # The lab-frame history ends along the normal: |F_t . n| ~ kt |t| (delta^1/2),
    # 0.3 kt/kn of F_n for the Hertz laws' scale fn + |ft| ~ 0.2 of it at least.
    assert lab > 0.1, (law, lab)
    # Rounding: ~6 flops per component and the dot product: 16 eps of |fn| + |ft|.
    assert fi <= 16 * EPS, (law, fi)


def test_ishima_lab_history_normal_part_is_order_one():
    """The issue's numbers: xi = delta under ishima, 90 degrees: |F_t . n| ~ F_n."""
    lab, _ = _rotate("ishima", DELTA)
    fi, _ = _rotate("ishima_fi", DELTA)
    assert lab > 0.3 and fi <= 16 * EPS, (lab, fi)


def _cases(seed=3, n=200):
    rng = np.random.default_rng(seed)
    for _ in range(n):
        phi = rng.uniform(-math.pi, math.pi)
        delta = 10 ** rng.uniform(-8, -1) * RI
        r = RI + RJ - delta
        ratio = rng.choice([rng.uniform(-1.5, 1.5), 1.0, -1.0, 0.0])  # xi / t*, across the cap
        yield r * math.cos(phi), r * math.sin(phi), ratio * PARAMS["mu"] * delta


@pytest.mark.parametrize("law", FRAME_INDIFFERENT)
def test_forces_equal_the_vector_law_on_the_tangent(law):
    vec, fi = get_law(law), get_law(f"{law}_fi")
    assert vector_form(fi.name) == law and fi.n_hist == 1 and vec.n_hist == 2
    pv, pf = _p(vec), _p(fi)
    for dx, dy, xi in _cases():
        r = math.hypot(dx, dy)
        that = np.array([dy / r, -dx / r])
        fv, ff, jac = np.zeros(6), np.zeros(6), np.zeros((6, 6))
        hv, hf = that * xi, np.array([xi])
        fv_flags = vec.project(dx, dy, RI, RJ, pv, hv)
        ff_flags = fi.project(dx, dy, RI, RJ, pf, hf)
        vec.eval(dx, dy, RI, RJ, pv, hv, fv, jac, False)
        fi.eval(dx, dy, RI, RJ, pf, hf, ff, jac, False)
        # Rounding: t = xi t_hat costs one product per component, the kernels ~8 flops
        # each and the Coulomb factor (1 + s - s^2) a few more: 32 eps of the largest force.
        scale = np.abs(fv).max()
        assert np.abs(ff - fv).max() <= 32 * EPS * scale, (law, dx, dy, xi, ff - fv)
        # the same flag within rounding of the cap (|t| computed from two components)
        tstar = PARAMS["mu"] * (RI + RJ - r)
        if abs(abs(xi) - tstar) > 1e-12 * tstar:
            assert fv_flags == ff_flags
        a_v, a_f = np.zeros((2, 6)), np.zeros((1, 6))
        vec.rate(dx, dy, RI, RJ, pv, a_v)
        fi.rate(dx, dy, RI, RJ, pf, a_f)
        # t_hat^T A: two products and a sum per entry, entries O(arm): 4 eps
        np.testing.assert_allclose(a_f[0], that @ a_v, rtol=0, atol=4 * EPS * max(RI, 1.0))


@pytest.mark.parametrize("law", FRAME_INDIFFERENT)
def test_wall_partner_is_the_wall_law(law):
    wall, fi_wall = get_law(f"{law}_wall"), get_law(f"{law}_fi_wall")
    assert fi_wall.pair == f"{law}_fi" and fi_wall.law_id == get_law(f"{law}_fi").law_id
    assert vector_form(fi_wall.name) == wall.name and fi_wall.params == wall.params
    p = _p(wall)
    for t in (0.0, 0.003, -0.02, 0.2):
        fa, fb = np.zeros(3), np.zeros(3)
        ja, jb = np.zeros((3, 3)), np.zeros((3, 3))
        wall.eval(0.45, 0.5, p, np.array([t]), fa, ja, True)
        fi_wall.eval(0.45, 0.5, p, np.array([t]), fb, jb, True)
        assert np.array_equal(fa, fb) and np.array_equal(ja, jb)  # the same expressions


@pytest.mark.parametrize("law", list(FRAME_INDIFFERENT))
def test_import_into_a_fi_law_keeps_the_tangential_part(law):
    """A contact listed as (j, i) with a tangential force perpendicular to n: the _fi law's
    xi t_hat is the vector law's history (xi does not flip with the order: t and t_hat
    both do), so the contact forces agree to rounding (a few products: 8 eps)."""
    from fricstab.io.imports import ImportedState
    from fricstab.io.imports.contacts import to_engine
    state = ImportedState(pos=np.array([[0.0, 0.0], [0.9, 0.0]]), radius=np.array([0.5, 0.5]),
                          ids=np.array([1, 2]), mass=np.ones(2), ci=np.array([1]),
                          cj=np.array([0]), force_n=np.array([[0.1, 0.0]]),
                          force_t=np.array([[0.0, 0.01]]), units={"length": "m"},
                          sources=[("two.csv", "test")], contact_lines=(("two.csv", 7),))
    params = {k: PARAMS[k] for k in get_law(law).params}
    sv, stv, rv = to_engine(state, law, params)
    sf, stf, rf = to_engine(state, f"{law}_fi", params)
    fv, ff = sv.contact_forces(stv), sf.contact_forces(stf)
    assert np.abs(stf.contacts.hist[:, 0]).max() > 0 and rf.history_source == "force"
    assert np.abs(ff - fv).max() <= 8 * EPS * np.abs(fv).max()
    assert abs(rf.mismatch["worst_relative"] - rv.mismatch["worst_relative"]) <= 8 * EPS


@pytest.mark.parametrize("scene", ["packing", "chain", "shear"])
def test_every_scene_takes_the_fi_laws_with_their_vector_laws_defaults(scene):
    from fricstab.io import scenes
    laws = scenes.get(scene).laws
    for law in FRAME_INDIFFERENT:
        if law in laws.defaults:
            assert laws.defaults[f"{law}_fi"] == laws.defaults[law]
            assert f"{law}_fi" in laws.names() and laws.docs[f"{law}_fi"]
