"""The uniform kernels of every law (<law>_eval, _rate, _project, _advance) and dispatch.

Error models behind the tolerances
----------------------------------
* eval and rate call the scalar kernels (force, force_jacobian, increment):
  the same operations on the same numbers, equal to the bit.
* advance against rate + project + eval composed: advance computes the
  increment entries with the increment kernel's expressions and sums
  ``h[k] + (a[k, 0] du[0] + a[k, 1] du[1] + ...)`` left to right, as the test
  does, so the advanced and projected history is equal to the bit; the caps
  are computed by the force kernels' own expressions and the forces by the
  force kernel's own body, so the forces are equal to the bit too, except for
  ``charan``: its projected vector history has a recomputed norm within
  ~5 eps of t* (one square root and one division in the scale, two products,
  the norm again), which the force kernel may rescale once more, by a factor
  1 - O(5 eps): forces within 16 eps of the terms each row sums.
* aux against the contact expressions computed here (Hertz family: kn, kt
  times sqrt(delta); lee_hurley: its <law>_contact kernel, another CSE of the
  same expressions): a few roundings, 8 eps relative.
* project: the scalar caps are put at +-cap exactly (idempotent to the bit);
  charan's vector history is rescaled by t*/|t| (a second projection moves it
  by at most ~5 eps relative, bound 8 eps, and keeps flag 1 since
  |t| >= t* (1 - 8 eps) counts as on the circle).
"""

import inspect
import math
import re

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from fricstab._numerics import pair_geometry
from fricstab.generated import dispatch
from fricstab.laws import (ALL_LAW_NAMES, CAPPED_LAW_NAMES, LAW_NAMES, PAIR_LAW_NAMES,
                           WALL_LAW_NAMES, get_law, law_id, vector_form)
from fricstab.laws import verify_lee_hurley as lh
from fricstab.laws.verify import Case, case_inputs
from tests.strategies import cases, shear_cases

EPS = np.finfo(float).eps
PAD = 2  # history rows longer than N_HIST: the extra entries must stay untouched


def _inputs(law, args):
    """(geometry tuple, parameter array, history row padded with NaN) of scalar args."""
    a = dict(zip(law.inputs, args))
    geo = tuple(float(a[k]) for k in law.geometry_args)
    p = np.array([a[k] for k in law.params], dtype=float)
    h = np.full(law.n_hist + PAD, np.nan)
    h[:law.n_hist] = [a[k] for k in law.history]
    return geo, p, h


def _draw_args(data, name):
    law = get_law(name)
    if name in CAPPED_LAW_NAMES:
        return law, lh.case_inputs(data.draw(shear_cases(name)), law=name)
    return law, case_inputs(law, data.draw(cases()))


def _increment_args(law, args):
    a = dict(zip(law.inputs, args))
    if law.name in CAPPED_LAW_NAMES:
        names = [k for k in law.inputs if k not in law.history and k not in ("mus", "mur")]
    else:
        names = law.geometry_args
    return tuple(a[k] for k in names)


def _sizes(law):
    return len(law.outputs), len(law.coords), law.n_hist


def _ageo(law, geo):
    """The geometry arguments of ``law.advance``: a pair's with ``r, delta, lam`` as the engine has them."""
    return tuple(geo) + (pair_geometry(*geo, law.width) if law.kind == "pair" else ())


def _no_contact_geometry(law):
    return (1.3, 0.2, 0.5, 0.6) if law.kind == "pair" else (0.6, 0.5)


# ------------------------------------------------------------------ eval and rate

@pytest.mark.parametrize("name", ALL_LAW_NAMES)
@given(data=st.data())
def test_eval_is_the_scalar_kernels_to_the_bit(name, data):
    law, args = _draw_args(data, name)
    geo, p, h = _inputs(law, args)
    nf, nq, _ = _sizes(law)
    f0, j0 = np.empty(nf), np.empty((nf, nq))
    law.force_jacobian(*args, f0, j0)
    f1, j1 = np.full(nf, np.nan), np.full((nf, nq), np.nan)
    law.eval(*geo, p, h, f1, j1, True)
    assert np.array_equal(f1, f0) and np.array_equal(j1, j0)
    f2 = np.empty(nf)
    law.force(*args, f2)
    f3, j3 = np.full(nf, np.nan), np.full((nf, nq), 7.0)
    law.eval(*geo, p, h, f3, j3, False)
    assert np.array_equal(f3, f2) and np.all(j3 == 7.0)


def _geometry_names(law):
    return ("dx", "dy", "Ri", "Rj") if law.kind == "pair" else ("y", "R")


@pytest.mark.parametrize("name", ALL_LAW_NAMES)
@given(data=st.data())
def test_rate_is_the_increment_kernel_to_the_bit(name, data):
    law, args = _draw_args(data, name)
    geo, p, _ = _inputs(law, args)
    nf, nq, nh = _sizes(law)
    a1 = np.full((nh, nq), np.nan)
    law.rate(*geo, p, a1)
    if nh:
        a0 = np.full((nh, nq), np.nan)
        law.increment(*_increment_args(law, args), a0)
        assert np.array_equal(a1, a0)
    # Out of contact: a purely geometric rule (charan, ishima: the normal and the
    # radii) is still written, so a contact closing during a step counts the whole
    # step; Lee & Hurley's rule carries the contact stiffness, which has no value
    # without contact: zeros.
    a2 = np.full((nh, nq), np.nan)
    law.rate(*_no_contact_geometry(law), p, a2)
    assert not np.isnan(a2).any()
    if law.name.startswith("lee_hurley") or not nh:
        assert not a2.any()
    else:
        a3 = np.full((nh, nq), np.nan)
        far = dict(zip(law.inputs, args))
        far.update(dict(zip(_geometry_names(law), _no_contact_geometry(law))))
        law.increment(*_increment_args(law, [far[k] for k in law.inputs]), a3)
        assert np.array_equal(a2, a3)


# ------------------------------------------------------------------ advance

def _du(data, law, args):
    """A step du of size 1e-3 .. 10 overlaps (rotations over the radius)."""
    a = dict(zip(law.inputs, args))
    if law.kind == "pair":
        r = math.hypot(a["dx"], a["dy"])
        delta, radius = a["Ri"] + a["Rj"] - r, a["Ri"]
    else:
        delta, radius = a["R"] - a["y"], a["R"]
    scale = max(delta, 1e-300) * 10.0 ** data.draw(st.floats(-3.0, 1.0))
    u = data.draw(st.lists(st.floats(-1.0, 1.0), min_size=len(law.coords),
                           max_size=len(law.coords)))
    rot = [c.startswith("theta") for c in law.coords]
    return np.array([x * scale / (radius if t else 1.0) for x, t in zip(u, rot)])


def _composed(law, geo, p, h0, du):
    """rate, then h + a @ du summed left to right, project, eval: (h, flags, f)."""
    nf, nq, nh = _sizes(law)
    a = np.empty((nh, nq))
    law.rate(*geo, p, a)
    h = h0.copy()
    for k in range(nh):
        acc = 0.0
        for b in range(nq):
            acc = acc + a[k, b] * du[b]
        h[k] = h0[k] + acc
    flags = law.project(*geo, p, h)
    f = np.empty(nf)
    law.eval(*geo, p, h, f, np.empty((nf, nq)), False)
    return h, flags, f


def _charan_row_terms(args, name="charan"):
    """Terms a charan (linear) force row sums: F_n + |F_t| <= F_n (1 + mu), times the arm
    for a torque; F_n = kn delta^(3/2) (linear: kn delta)."""
    a = dict(zip(get_law(name).inputs, args))
    delta = a["Ri"] + a["Rj"] - math.hypot(a["dx"], a["dy"])
    power = 1.0 if name == "linear" else 1.5
    return a["kn"] * abs(delta) ** power * (1 + a["mu"]) * max(1.0, a["Ri"], a["Rj"])


def _contact_reference(law, args):
    """CONTACT values computed here (Hertz family) or by <law>_contact (capped)."""
    if law.name in CAPPED_LAW_NAMES:
        out = np.empty(9)
        law.contact_quantities(*args, out)
        return out[2:6]
    a = dict(zip(law.inputs, args))
    if law.kind == "pair":
        from fricstab._numerics import overlap_correction
        naive = a["Ri"] + a["Rj"] - math.hypot(a["dx"], a["dy"])
        delta = naive + overlap_correction(a["dx"], a["dy"], a["Ri"], a["Rj"], naive)
    else:
        delta = a["R"] - a["y"]
    if law.name.startswith("linear"):   # F_n = kn delta, F_t = -kt t
        return np.array([a["kn"], a["kt"], 0.0, a["kn"] * delta])
    sd = math.sqrt(delta)
    kt = a["kt"] * sd if law.n_hist else 0.0
    return np.array([a["kn"] * sd, kt, 0.0, a["kn"] * delta * sd])


def _disp(law, du, dxj=0.0):
    """``du`` as ``<law>_advance`` takes it: itself (wall), ``dui, duj, dxj`` (pair)."""
    du = np.asarray(du, float)
    if law.kind == "wall":
        return (du,)
    n = len(du) // 2
    return du[:n].copy(), du[n:].copy(), dxj


@pytest.mark.parametrize("name", ALL_LAW_NAMES)
@given(data=st.data())
def test_advance_is_rate_project_eval_composed(name, data):
    law, args = _draw_args(data, name)
    geo, p, h0 = _inputs(law, args)
    du = _du(data, law, args)
    nf, nq, nh = _sizes(law)
    h_c, flags_c, f_c = _composed(law, geo, p, h0, du)
    h, f, aux = h0.copy(), np.full(nf, np.nan), np.full(4, np.nan)
    flags = law.advance(*_ageo(law, geo), p, h, *_disp(law, du), f, aux, True)
    assert flags == flags_c
    assert np.array_equal(h[:nh], h_c[:nh]) and np.isnan(h[nh:]).all()
    if name in ("charan", "linear"):  # the force kernel may rescale a projected t once more
        assert np.all(np.abs(f - f_c) <= 16 * EPS * _charan_row_terms(args, name))
    else:
        assert np.array_equal(f, f_c)
    ref = _contact_reference(law, args)
    assert np.allclose(aux, ref, rtol=8 * EPS, atol=0)
    # without want_aux: the same step to the bit, aux untouched
    h2, f2, aux2 = h0.copy(), np.full(nf, np.nan), np.full(4, np.nan)
    assert law.advance(*_ageo(law, geo), p, h2, *_disp(law, du), f2, aux2, False) == flags
    assert np.array_equal(h2, h, equal_nan=True) and np.array_equal(f2, f)
    assert np.isnan(aux2).all()
    if law.kind == "pair":   # dxj is added to j's x displacement: duj[0] + dxj, to the bit
        dxj = data.draw(st.floats(-1e-3, 1e-3))
        dui, duj, _ = _disp(law, du)
        shifted = duj.copy()
        shifted[0] = duj[0] + dxj
        h3, h4, f3, f4 = h0.copy(), h0.copy(), np.empty(nf), np.empty(nf)
        assert law.advance(*_ageo(law, geo), p, h3, dui, duj, dxj, f3, aux2, False) == \
            law.advance(*_ageo(law, geo), p, h4, dui, shifted, 0.0, f4, aux2, False)
        assert np.array_equal(h3, h4, equal_nan=True) and np.array_equal(f3, f4)


@pytest.mark.parametrize("name", ALL_LAW_NAMES)
def test_without_contact_advance_and_project_forget_everything(name):
    law = get_law(name)
    nf, nq, nh = _sizes(law)
    p = np.array([{"kn": 1.0, "kt": 0.3, "mu": 0.5, "E": 1.0, "nu": 0.2, "mus": 0.5,
                   "mur": 0.01, "Rw": 2.0}[k] for k in law.params])
    for geo in (_no_contact_geometry(law),
                (1.1, 0.0, 0.5, 0.6) if law.kind == "pair" else (0.5, 0.5)):  # touching
        h = np.full(nh + PAD, np.nan)
        h[:nh] = 1e-3
        f, aux = np.full(nf, np.nan), np.full(4, np.nan)
        assert law.advance(*_ageo(law, geo), p, h, *_disp(law, np.full(nq, 1e-3)), f, aux, True) == 0
        assert not h[:nh].any() and np.isnan(h[nh:]).all()
        assert not f.any() and not aux.any() and not np.isnan(f).any() and not np.isnan(aux).any()
        h[:nh], f[:], aux[:] = 1e-3, np.nan, np.nan
        assert law.advance(*_ageo(law, geo), p, h, *_disp(law, np.full(nq, 1e-3)), f, aux, False) == 0
        assert not h[:nh].any() and not f.any() and np.isnan(aux).all()
        h[:nh] = 1e-3
        assert law.project(*geo, p, h) == 0
        assert not h[:nh].any() and np.isnan(h[nh:]).all()


def test_advance_contact_quantities_of_a_hand_computed_hertz_contact():
    """dx, dy = 0.96, 0.28 (r = 1), R = 0.52: delta = 0.04, sqrt = 0.2, kn = 3, kt = 2.

    CONTACT = (kn sqrt(delta), kt sqrt(delta) or 0, 0, kn delta^{3/2}) =
    (0.6, 0.4, 0, 0.024).  The decimal inputs carry a rounding of eps r, an
    error of eps r/delta = 25 eps relative in delta: bound 64 eps r/delta.
    """
    expect = {"hertz": (0.6, 0.0, 0.0, 0.024), "charan": (0.6, 0.4, 0.0, 0.024),
              "ishima": (0.6, 0.4, 0.0, 0.024)}
    tol = 64 * EPS / 0.04
    for name, values in expect.items():
        law = get_law(name)
        p = np.array([{"kn": 3.0, "kt": 2.0, "mu": 1.0}[k] for k in law.params])
        aux = np.empty(4)
        law.advance(*_ageo(law, (0.96, 0.28, 0.52, 0.52)), p, np.zeros(law.n_hist), *_disp(law, np.zeros(2 * law.n_dof)),
                    np.empty(len(law.outputs)), aux, True)
        assert np.allclose(aux, values, rtol=tol, atol=0), name
        wall = get_law(law.wall)
        aux = np.empty(4)
        wall.advance(0.48, 0.52, p, np.zeros(wall.n_hist), np.zeros(wall.n_dof),
                     np.empty(wall.n_dof), aux, True)
        assert np.allclose(aux, values, rtol=tol, atol=0), wall.name


# ------------------------------------------------------------------ project

def _capped_args(name, case, t_ratio, r_ratio=0.0):
    if name in CAPPED_LAW_NAMES:
        c = lh.ShearCase(**{**case.__dict__, "t_ratio": t_ratio, "r_ratio": r_ratio})
        return lh.case_inputs(c, law=name)
    return case_inputs(get_law(name), Case(**{**case.__dict__, "t_ratio": t_ratio}))


COULOMB = [n for n in LAW_NAMES if get_law(n).capped]


@pytest.mark.parametrize("name", COULOMB)
@given(case=cases(), ratio=st.sampled_from([0.0, 0.3, 1 - 1e-9, 1 + 1e-9, 2.0, 1e3]))
def test_coulomb_projection_flags_inside_at_and_beyond(name, case, ratio):
    """Inside the circle: a no-op, flag 0; beyond: onto |t| = t*, same direction, flag 1.

    A projected history is on the circle: projecting again keeps flag 1 and
    moves it by at most 8 eps (bit for bit at the wall, where it is +-t*).
    """
    law = get_law(name)
    args = _capped_args(name, case, ratio)
    geo, p, h0 = _inputs(law, args)
    if not np.linalg.norm(h0[:law.n_hist]) > 0:
        return
    h = h0.copy()
    flags = law.project(*geo, p, h)
    nh = law.n_hist
    assert np.isnan(h[nh:]).all()
    if ratio < 1:
        assert flags == 0 and np.array_equal(h[:nh], h0[:nh])
        return
    assert flags == 1
    a = dict(zip(law.inputs, args))
    delta = geo[2] + geo[3] - math.hypot(geo[0], geo[1]) if law.kind == "pair" else geo[1] - geo[0]
    tstar = a["mu"] * a["kn"] / a["kt"] * delta
    # delta here without the accurate correction: eps (R_i + R_j)/delta relative
    tol = 8 * EPS + 4 * EPS * (sum(geo[2:]) if law.kind == "pair" else geo[1]) / delta
    assert abs(np.linalg.norm(h[:nh]) / tstar - 1) <= tol
    unit0 = h0[:nh] / np.linalg.norm(h0[:nh])
    assert np.allclose(h[:nh] / np.linalg.norm(h[:nh]), unit0, rtol=0, atol=8 * EPS)
    h2 = h.copy()
    assert law.project(*geo, p, h2) == 1
    if nh == 1:
        assert np.array_equal(h2, h, equal_nan=True)
    else:
        assert np.all(np.abs(h2[:nh] - h[:nh]) <= 8 * EPS * np.abs(h[:nh]).max())


@pytest.mark.parametrize("name", [n for n in LAW_NAMES if not get_law(n).capped])
@given(case=cases(), ratio=st.sampled_from([0.0, 0.5, 1.0, 1e3]))
def test_projection_without_a_cap_is_a_no_op(name, case, ratio):
    law = get_law(name)
    args = _capped_args(name, case, ratio)
    geo, p, h0 = _inputs(law, args)
    h = h0.copy()
    assert law.project(*geo, p, h) == 0
    assert np.array_equal(h, h0, equal_nan=True)


@pytest.mark.parametrize("name", CAPPED_LAW_NAMES)
@given(data=st.data(), t=st.sampled_from([0.0, 0.5, 1 - 1e-9, 1 + 1e-9, 3.0]),
       r=st.sampled_from([0.0, -0.5, -(1 - 1e-9), -(1 + 1e-9), -3.0]))
def test_lee_hurley_projection_flags_and_idempotence(name, data, t, r):
    """Bit 1 iff |ft| >= mu_s F_n, bit 2 iff |mr| >= mu_r R_r F_n; caps put exactly.

    The flags of a projected history are those of the kernel's branch
    (<law>_contact's flag), and a second projection changes nothing, to the bit.
    """
    law = get_law(name)
    case = data.draw(shear_cases(name))
    args = _capped_args(name, case, t, r)
    geo, p, h0 = _inputs(law, args)
    h = h0.copy()
    flags = law.project(*geo, p, h)
    assert flags == (abs(t) > 1) + 2 * (abs(r) > 1)
    if abs(t) < 1:
        assert h[0] == h0[0]
    if abs(r) < 1:
        assert h[1] == h0[1]
    at = list(args)
    ih = law.inputs.index("ft")
    at[ih], at[ih + 1] = h[0], h[1]
    out = np.empty(9)
    law.contact_quantities(*at, out)
    assert int(out[8]) == flags
    if flags & 1:
        assert abs(h[0]) == out[6] == h[0] and np.sign(h[0]) == np.sign(h0[0])
    if flags & 2:
        assert h[1] == out[7]
    h2 = h.copy()
    assert law.project(*geo, p, h2) == flags
    assert np.array_equal(h2, h, equal_nan=True)


@pytest.mark.parametrize("name", CAPPED_LAW_NAMES)
@given(data=st.data())
def test_mur_zero_means_no_rolling_resistance(name, data):
    """mur = 0: every rolling history is on its cap 0: flag bit 2, torque R ft_c exactly."""
    law = get_law(name)
    case = data.draw(shear_cases(name))
    args = list(lh.case_inputs(case, law=name))
    args[law.inputs.index("mur")] = 0.0
    args[law.inputs.index("mr")] = data.draw(st.sampled_from([0.0, 1e-12, -2.0]))
    geo, p, h = _inputs(law, args)
    nf, nq, _ = _sizes(law)
    f, aux = np.empty(nf), np.empty(4)
    flags = law.advance(*_ageo(law, geo), p, h, *_disp(law, np.zeros(nq)), f, aux, True)
    assert flags & 2 and h[1] == 0.0
    r1 = geo[2] if law.kind == "pair" else geo[1]
    assert f[2] == r1 * h[0]
    if law.kind == "pair":
        assert f[5] == geo[3] * h[0]


# ------------------------------------------------------------------ dispatch

def _dispatch_case(kind, i, rng):
    name = (PAIR_LAW_NAMES if kind == "pair" else WALL_LAW_NAMES)[i]
    law = get_law(name)
    if name in CAPPED_LAW_NAMES:
        c = lh.sample_cases(4, int(rng.integers(1 << 30)), law=name)[int(rng.integers(4))]
        args = lh.case_inputs(c, law=name)
    else:
        c = Case(float(10 ** rng.uniform(-8, -1)), float(rng.uniform(0, 1.5)),
                 float(rng.uniform(0, 6.3)), float(rng.uniform(0, 6.3)),
                 float(10 ** rng.uniform(-3, 1)), float(10 ** rng.uniform(-1, 2)),
                 float(rng.uniform(1, 1.4)))
        args = case_inputs(law, c)
    return law, args


@pytest.mark.parametrize("kind", ["pair", "wall"])
@pytest.mark.parametrize("i", range(len(PAIR_LAW_NAMES)))
def test_dispatch_by_id_is_the_per_law_kernel(kind, i):
    rng = np.random.default_rng(11 + i)
    fns = {s: getattr(dispatch, f"{kind}_{s}") for s in ("eval", "rate", "project", "advance")}
    for _ in range(20):
        law, args = _dispatch_case(kind, i, rng)
        assert law_id(law.name) == i
        geo, p, h = _inputs(law, args)
        nf, nq, nh = _sizes(law)
        du = rng.uniform(-1, 1, nq) * 1e-3 * (geo[2] if kind == "pair" else geo[1])
        for want in (True, False):
            f0, j0, f1, j1 = np.zeros(nf), np.zeros((nf, nq)), np.zeros(nf), np.zeros((nf, nq))
            law.eval(*geo, p, h, f0, j0, want)
            fns["eval"](i, *geo, p, h, f1, j1, want)
            assert np.array_equal(f0, f1) and np.array_equal(j0, j1)
        a0, a1 = np.zeros((nh, nq)), np.zeros((nh, nq))
        law.rate(*geo, p, a0)
        fns["rate"](i, *geo, p, a1)
        assert np.array_equal(a0, a1)
        h0, h1 = h.copy(), h.copy()
        assert law.project(*geo, p, h0) == fns["project"](i, *geo, p, h1)
        assert np.array_equal(h0, h1, equal_nan=True)
        h0, h1, f0, f1, x0, x1 = h.copy(), h.copy(), np.zeros(nf), np.zeros(nf), np.zeros(4), np.zeros(4)
        assert law.advance(*_ageo(law, geo), p, h0, *_disp(law, du), f0, x0, True) == \
            fns["advance"](i, *_ageo(law, geo), p, h1, *_disp(law, du), f1, x1, True)
        assert np.array_equal(h0, h1, equal_nan=True)
        assert np.array_equal(f0, f1) and np.array_equal(x0, x1)


@pytest.mark.parametrize("kind", ["pair", "wall"])
@pytest.mark.parametrize("bad", [-1, len(PAIR_LAW_NAMES), 99])
def test_dispatch_refuses_an_unknown_id_loudly(kind, bad):
    geo = (0.99, 0.0, 0.5, 0.5) if kind == "pair" else (0.49, 0.5)
    p, h = np.ones(5), np.ones(3)
    f, jac, aux, a = np.ones(6), np.ones((6, 6)), np.ones(4), np.ones((2, 6))
    assert getattr(dispatch, f"{kind}_project")(bad, *geo, p, h) == dispatch.UNKNOWN_LAW == -1
    assert not h.any()
    h[:] = 1.0
    du = (np.ones(3),) if kind == "wall" else (np.ones(3), np.ones(3), 0.0)
    ageo = geo if kind == "wall" else geo + pair_geometry(*geo, False)
    assert getattr(dispatch, f"{kind}_advance")(bad, *ageo, p, h, *du, f, aux, True) == -1
    assert not h.any() and not f.any() and not aux.any()
    h[:], f[:], aux[:] = 1.0, 1.0, 1.0
    assert getattr(dispatch, f"{kind}_advance")(bad, *ageo, p, h, *du, f, aux, False) == -1
    assert not h.any() and not f.any() and (aux == 1.0).all()
    f[:], jac[:] = 1.0, 1.0
    with pytest.raises(ValueError, match="unknown contact law id"):
        getattr(dispatch, f"{kind}_eval")(bad, *geo, p, h, f, jac, True)
    assert not f.any() and not jac.any()
    with pytest.raises(ValueError, match="unknown contact law id"):
        getattr(dispatch, f"{kind}_rate")(bad, *geo, p, a)
    assert not a.any()


# ------------------------------------------------------------------ metadata

@pytest.mark.parametrize("name", ALL_LAW_NAMES)
def test_metadata_is_consistent_with_the_kernels(name):
    law = get_law(name)
    geometry = set(law.geometry_args)
    assert law.params == tuple(k for k in law.inputs if k not in geometry | set(law.history))
    assert len(law.param_units) == len(law.param_docs) == len(law.params)
    assert all(u and d for u, d in zip(law.param_units, law.param_docs))
    assert law.n_dof * (2 if law.kind == "pair" else 1) == len(law.coords) == len(law.outputs)
    assert law.n_hist == len(law.history)
    rot = {c.rstrip("_ij") for c in law.coords} - {"x", "y"}
    assert rot == ({law.rotation} if law.rotation else set())
    assert law.n_dof == (3 if law.rotation else 2)
    assert law.capped == (vector_form(name) in ("charan", "charan_wall", "lee_hurley",
                                                "lee_hurley_wall", "linear", "linear_wall"))
    assert law.contact == ("kn", "kt", "kr", "fn")
    other = get_law(law.wall or law.pair)
    assert (other.pair or other.wall) == name and other.law_id == law.law_id
    assert other.n_dof == law.n_dof and other.capped == law.capped
    assert other.rotation == law.rotation
    pair, wall = (law, other) if law.kind == "pair" else (other, law)
    assert wall.params == pair.params + (("Rw",) if name.startswith("lee_hurley") else ())
    assert law.wall_form() is get_law(pair.wall) if law.kind == "pair" else law.pair_form() is pair
    # the uniform kernels' arguments, and the p and h slots they read
    geo = list(law.geometry_args)
    signatures = {"eval": geo + ["p", "h", "f", "jac", "want_jac"], "rate": geo + ["p", "a"],
                  "project": geo + ["p", "h"],
                  "advance": list(law.advance_geometry_args) + ["p", "h", *(["du"] if law.kind == "wall" else ["dui", "duj", "dxj"]),
                              "f", "aux", "want_aux"]}
    p_read, h_read = set(), set()
    for kernel, expect in signatures.items():
        py = getattr(law, kernel).py_func
        assert list(inspect.signature(py).parameters) == expect
        src = inspect.getsource(py)
        p_read |= {int(k) for k in re.findall(r"\bp\[(\d+)\]", src)}
        h_read |= {int(k) for k in re.findall(r"\bh\[(\d+)\]", src)}
    assert p_read == set(range(len(law.params)))
    assert h_read == set(range(law.n_hist))
    # the dispatch tables
    i = law.law_id
    if law.kind == "pair":
        assert dispatch.PAIR_LAWS[i] == name and dispatch.N_HIST[i] == law.n_hist
        assert dispatch.N_PARAMS[i] == len(law.params) and dispatch.N_DOF[i] == law.n_dof
    else:
        assert dispatch.WALL_LAWS[i] == name and dispatch.N_HIST_WALL[i] == law.n_hist
        assert dispatch.N_PARAMS_WALL[i] == len(law.params) and dispatch.N_DOF[i] == law.n_dof


def test_law_ids_and_names():
    assert PAIR_LAW_NAMES == dispatch.PAIR_LAWS == ("hertz", "charan", "ishima", "lee_hurley",
                                                      "linear", "ishima_fi", "charan_fi",
                                                      "linear_fi")
    assert WALL_LAW_NAMES == dispatch.WALL_LAWS
    assert set(ALL_LAW_NAMES) == set(PAIR_LAW_NAMES) | set(WALL_LAW_NAMES)
    # eight pair laws and their wall forms (issue 37: linear; issue 36: the _fi forms)
    assert len(ALL_LAW_NAMES) == 16
    for i, (pair, wall) in enumerate(zip(PAIR_LAW_NAMES, WALL_LAW_NAMES)):
        assert law_id(pair) == law_id(wall) == i
    from fricstab.laws import ParameterError
    with pytest.raises(ParameterError, match="unknown law"):
        law_id("coulomb")
