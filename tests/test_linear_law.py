"""The linear spring-Coulomb law (symbolic/linear.py) at hand-computed points.

Contact: dx, dy = 0.96, 0.28 (r = 1, n = (0.96, 0.28)), R_i = R_j = 0.52, so
delta = 0.04; kn = 3, kt = 2, mu = 1: F_n = kn delta = 0.12 and the Coulomb
radius t* = mu (kn/kt) delta = 0.06.  The decimal inputs carry a rounding of
eps r, i.e. eps r/delta = 25 eps relative in delta, and every output here is
a product of a few such numbers: bound 64 eps / delta relative.
"""

import math

import numpy as np
import pytest

from fricstab.laws import get_law

EPS = np.finfo(float).eps
TOL = 64 * EPS / 0.04
GEO = (0.96, 0.28, 0.52, 0.52)
P = np.array([3.0, 2.0, 1.0])        # kn, kt, mu
N = np.array([0.96, 0.28])
TANGENT = np.array([-0.28, 0.96])    # t_hat = (-n_y, n_x)


def _force(t, name="linear"):
    law = get_law(name)
    f = np.empty(len(law.outputs))
    geo = GEO if law.kind == "pair" else (0.48, 0.52)
    law.force(*geo, *P, *np.atleast_1d(t), f)
    return f


def test_normal_and_tangential_force_inside_the_cap():
    """|t| = 0.01 < t*: F_i = kn delta n - kt t = (0.1208, 0.0144) = -F_j;
    T_i = T_j = -R (n x F_t) = -0.52 (-0.02) = 0.0104."""
    f = _force(0.01 * TANGENT)
    expect = [0.1208, 0.0144, 0.0104, -0.1208, -0.0144, 0.0104]
    assert np.allclose(f, expect, rtol=TOL, atol=0)
    assert np.allclose(_force(np.zeros(2))[:2], 0.12 * N, rtol=TOL, atol=0)   # kn delta n


def test_on_and_past_the_cap_the_force_is_mu_kn_delta():
    """|t| = 0.1 > t*: the history is projected onto |t| = 0.06, |F_t| = mu kn delta."""
    for t in (0.1 * TANGENT, 0.06 * TANGENT, 5.0 * np.array([0.6, 0.8])):
        f = _force(t)
        ft = f[:2] - 0.12 * N
        assert abs(np.hypot(*ft) - 0.12) <= TOL * 0.12
        assert np.allclose(ft / np.hypot(*ft), -t / np.hypot(*t), rtol=0, atol=TOL)
    wall = _force(1.0, "linear_wall")            # wall: delta = 0.04, t* = 0.06
    assert np.allclose(wall, [-0.12, 0.12, -0.52 * 0.12], rtol=TOL, atol=0)


def test_projection_is_idempotent_and_flags_sliding():
    law = get_law("linear")
    h = np.array([0.3, -0.4])
    assert law.project(*GEO, P, h) == 1
    assert abs(np.hypot(*h) - 0.06) <= 4 * EPS * 0.06 + TOL * 0.06
    again = h.copy()
    assert law.project(*GEO, P, again) == 1
    # a second projection moves it by at most the rounding of one rescale
    assert np.allclose(again, h, rtol=4 * EPS, atol=0)
    wall = get_law("linear_wall")
    hw = np.array([-1.0])
    assert wall.project(0.48, 0.52, P, hw) == 1 and hw[0] == -(1.0 * 3.0 / 2.0 * (0.52 - 0.48))
    hw2 = hw.copy()
    assert wall.project(0.48, 0.52, P, hw2) == 1 and hw2[0] == hw[0]    # to the bit
    inside = np.array([0.01, 0.0])
    assert law.project(*GEO, P, inside) == 0 and inside[0] == 0.01


def _block(t):
    law = get_law("linear")
    f, jac = np.empty(6), np.empty((6, 6))
    law.force_jacobian(*GEO, *P, *t, f, jac)
    return jac


def _complex_step(t):
    """Im F(q + i h e_k, t + i h A e_k)/h: the history advanced by the increment rule."""
    law = get_law("linear")
    a = np.empty((2, 6))
    law.rate(*GEO, P, a)
    h = 1e-20
    out = np.empty((6, 6))
    for k in range(6):
        z = np.array(GEO + tuple(P) + tuple(t), complex)
        if k % 3 < 2:
            z[k % 3] += (1 if k < 3 else -1) * 1j * h
        z[7:9] += 1j * h * a[:, k]
        f = np.empty(6, complex)
        law.force(*z, f)
        out[:, k] = f.imag / h
    return out


@pytest.mark.parametrize("scale", [0.0, 0.5, 1.0, 1.5, 40.0])
def test_block_is_the_derivative_sticking_and_sliding(scale):
    """The block (with the sliding term of symbolic/linear.py) against complex step,
    inside, on and past the cap (complex step keeps the real part: same branch)."""
    t = scale * 0.06 * np.array([0.6, -0.8])
    jac, ref = _block(t), _complex_step(t)
    assert np.abs(jac - ref).max() <= 1e-13 * np.abs(ref).max()


def test_the_block_jumps_at_the_cap():
    """Sliding one-sided derivative on the circle = the limit from beyond it; the limit
    from inside is the sticking block; they differ by O(kt) (here the radial part)."""
    u = np.array([0.6, -0.8])
    on, past, inside = (_block(s * 0.06 * u) for s in (1.0, 1.0 + 1e-9, 1.0 - 1e-9))
    assert np.abs(on - past).max() <= 1e-8
    assert np.abs(on - inside).max() >= 0.1
    stick = _block(np.zeros(2))
    assert np.abs(inside - stick)[:, 2].max() <= 1e-12    # theta columns: kt R A, no t


def _lammps_hooke_history(xi, xj, ri, rj, kn, kt, xmu, shear):
    """LAMMPS pair gran/hooke/history (2D, gamman = gammat = 0, after its shear update):
    ccel = kn (radsum - r)/r on del = xi - xj; fs = -kt shear; if |fs| > xmu |F_n|
    the shear is rescaled by xmu |F_n|/|fs|; torque_i,j -= rad (del x fs)/r."""
    d = np.subtract(xi, xj)
    r = np.hypot(*d)
    fn = kn * (ri + rj - r) / r * d
    fs = -kt * np.asarray(shear, float)
    cap = xmu * np.hypot(*fn)
    if np.hypot(*fs) > cap:
        scale = cap / np.hypot(*fs)
        shear, fs = shear * scale, fs * scale
    tor = (d[0] * fs[1] - d[1] * fs[0]) / r
    return np.array([*(fn + fs), -ri * tor, *-(fn + fs), -rj * tor]), shear


@pytest.mark.parametrize("shear", [(0.0, 0.0), (-0.003, 0.01), (0.05, 0.2), (1.0, -3.0)])
def test_lammps_gran_hooke_history_convention(shear):
    """kn, kt, mu are LAMMPS's kn, kt, xmu; its shear history is t (the projected one
    after a slide); its increment vtr dt = (I - n n^T) dv + (n_y, -n_x)(R_i w_i + R_j w_j) dt
    is Charan's rule (rate), as the torques T = -R (n x F_t)."""
    ref, sheared = _lammps_hooke_history((0.96, 0.28), (0.0, 0.0), 0.52, 0.52, *P,
                                         np.array(shear))
    assert np.allclose(_force(np.array(shear)), ref, rtol=TOL, atol=TOL * np.abs(ref).max())
    h = np.array(shear, float)
    get_law("linear").project(*GEO, P, h)
    assert np.allclose(h, sheared, rtol=8 * EPS, atol=0)
    a = np.empty((2, 6))
    get_law("linear").rate(*GEO, P, a)
    dv_i, dv_j, w_i, w_j = np.array([0.3, -0.2]), np.array([0.1, 0.5]), 0.7, -1.1
    vr = dv_i - dv_j
    vtr = vr - (vr @ N) * N + np.array([N[1], -N[0]]) * (0.52 * w_i + 0.52 * w_j)
    du = np.array([*dv_i, w_i, *dv_j, w_j])
    assert np.allclose(a @ du, vtr, rtol=0, atol=8 * EPS * math.hypot(*vtr))
