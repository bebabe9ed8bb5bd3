"""Packings of Ishima App. A.1: contact finder, force balance, determinism, I/O, bad input."""

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from fricstab.laws import ParameterError
from fricstab.scenes.packing import (
    ConvergenceError,
    Packing,
    _find_contacts_brute,
    find_contacts,
    hertz_forces,
    make_packing,
)

N, PHI, F_TOL = 64, 0.88, 1e-14


@pytest.fixture(scope="module")
def packing():
    return make_packing(N, PHI, seed=0, f_tol=F_TOL)


def _same_contacts(pos, radius, box, shift):
    pairs, sep = find_contacts(pos, radius, box, shift)
    ref_pairs, ref_sep = _find_contacts_brute(pos, radius, box, shift)
    assert pairs.dtype == np.int64 and pairs.shape == ref_pairs.shape
    np.testing.assert_array_equal(pairs, ref_pairs)
    np.testing.assert_allclose(sep, ref_sep, rtol=0, atol=1e-14)
    return pairs, sep


@st.composite
def scenes(draw):
    """Random disks, half of them overlapping something; boxes from just over 2 d_max
    (all-pairs path) to several cells; shifts anywhere, also beyond the box."""
    n = draw(st.integers(2, 60))
    rmax = draw(st.sampled_from([0.5, 0.3]))
    box = draw(st.floats(4 * rmax * 1.0001, 8.0))
    shift = draw(st.one_of(st.just(0.0), st.floats(-3 * box, 3 * box)))
    seed = draw(st.integers(0, 2**32 - 1))
    rng = np.random.default_rng(seed)
    radius = rng.choice([rmax, rmax / 1.4], size=n)
    pos = rng.uniform(-box, 2 * box, size=(n, 2)) if draw(st.booleans()) \
        else rng.uniform(0, box, size=(n, 2))
    return pos, radius, box, shift


@given(scenes())
def test_find_contacts_matches_brute_force(scene):
    _same_contacts(*scene)


@pytest.mark.parametrize("shift", [0.0, 0.37, 7.3, -12.1])
def test_contacts_across_the_boundaries(shift):
    box = 5.0
    radius = np.full(4, 0.5)
    # 0-1 touch across x = 0; 2 sits at the top, 3 under its Lees-Edwards image.
    pos = np.array([[0.1, 2.0], [4.8, 2.2], [1.0, 4.9], [1.0 - shift + 0.3, 0.2]])
    pos[3, 0] %= box
    pairs, sep = _same_contacts(pos, radius, box, shift)
    assert [tuple(p) for p in pairs] == [(0, 1), (2, 3)]
    np.testing.assert_allclose(sep, [[0.3, -0.2], [-0.3, -0.3]], atol=1e-12)


def test_hertz_forces_equal_sum_over_contacts():
    rng = np.random.default_rng(3)
    box, shift = 6.0, 2.345
    radius = rng.choice([0.5, 0.5 / 1.4], size=50)
    pos = rng.uniform(0, box, size=(50, 2))
    pairs, sep = find_contacts(pos, radius, box, shift)
    r = np.hypot(sep[:, 0], sep[:, 1])
    xi = radius[pairs[:, 0]] + radius[pairs[:, 1]] - r
    f = (xi**1.5 / r)[:, None] * sep  # Eq. A4 with k_N = 1
    expected = np.zeros_like(pos)
    np.add.at(expected, pairs[:, 0], f)
    np.add.at(expected, pairs[:, 1], -f)
    assert len(pairs) > 20
    np.testing.assert_allclose(hertz_forces(pos, radius, box, shift), expected,
                               rtol=1e-12, atol=1e-15)


def test_packing_is_force_balanced(packing):
    # Precondition first: the target was reached and every disk is balanced.
    assert np.abs(hertz_forces(packing.pos, packing.radius, packing.box)).max() < F_TOL
    assert packing.info["max_force"] < F_TOL
    phi = np.sum(np.pi * packing.diameter**2 / 4) / packing.box**2
    assert abs(phi - PHI) < 1e-12 and packing.phi == PHI
    assert np.all((packing.pos >= 0) & (packing.pos < packing.box))
    pairs, _ = _same_contacts(packing.pos, packing.radius, packing.box, 0.0)
    assert 2 * len(pairs) / N > 3  # phi = 0.88 is well above jamming


def test_packing_layout(packing):
    assert packing.n == N and packing.pos.shape == (N, 2)
    assert np.count_nonzero(packing.diameter == 1.0) == N // 2
    np.testing.assert_allclose(packing.diameter[N // 2:], 1 / 1.4, rtol=0, atol=0)
    np.testing.assert_allclose(packing.mass, packing.diameter**2)
    np.testing.assert_allclose(packing.inertia, packing.diameter**4 / 8)
    assert packing.info["compression_steps"] == math.ceil((PHI - 0.6) / 1e-3 - 1e-9)
    assert not packing.pos.flags.writeable


def test_small_box_counts_every_image():
    # N = 4: L < 2 d, a pair touches through several images.
    p = make_packing(4, 0.9, seed=1)
    assert p.box < 2.0
    assert p.info["max_force"] < 1e-14
    assert np.abs(hertz_forces(p.pos, p.radius, p.box)).max() < 1e-14


def test_no_compression_at_phi_start():
    p = make_packing(16, 0.6, seed=2)
    assert p.info["compression_steps"] == 0 and p.info["max_force"] < F_TOL
    assert abs(np.sum(np.pi * p.diameter**2 / 4) / p.box**2 - 0.6) < 1e-12


def test_progress_bar_counts_compression_steps(capsys):
    make_packing(8, 0.65, dphi=0.01, progress=True)
    err = capsys.readouterr().err
    assert "compress" in err and "6/6" in err  # the relaxation at phi_start + 5 steps


def test_same_seed_same_packing_other_seed_differs():
    a, b, c = (make_packing(16, 0.86, seed=s) for s in (5, 5, 6))
    for name in ("pos", "diameter"):
        np.testing.assert_array_equal(getattr(a, name), getattr(b, name))
    assert a.box == b.box and a.info["fire_iterations"] == b.info["fire_iterations"]
    assert not np.array_equal(a.pos, c.pos)


def test_save_load_round_trip(packing, tmp_path):
    path = tmp_path / "p.npz"
    packing.save(path)
    back = Packing.load(path)
    np.testing.assert_array_equal(back.pos, packing.pos)
    np.testing.assert_array_equal(back.diameter, packing.diameter)
    assert (back.box, back.phi, back.seed, back.info) == \
        (packing.box, packing.phi, packing.seed, packing.info)


def test_fire_cap_raises_convergence_error():
    message = r"phi = 0\.6\d*: max \|F\| = \S+ >= 1\.0e-06 after 3 iterations"
    with pytest.raises(ConvergenceError, match=message):
        make_packing(16, 0.9, max_iter=3)


@pytest.mark.parametrize("kwargs, name", [
    ({"n": 5}, "n"), ({"n": 2}, "n"), ({"n": 8.0}, "n"), ({"n": True}, "n"),
    ({"phi": 0.0}, "phi"), ({"phi": 0.96}, "phi"), ({"phi": float("nan")}, "phi"),
    ({"phi": 0.5}, "phi"), ({"phi_start": 0.0}, "phi_start"), ({"phi_start": 0.7}, "phi_start"),
    ({"dphi": 0.0}, "dphi"), ({"dphi": -1e-3}, "dphi"), ({"dphi": float("inf")}, "dphi"),
    ({"f_tol": 0.0}, "f_tol"), ({"f_tol_compress": -1.0}, "f_tol_compress"),
    ({"seed": -1}, "seed"), ({"seed": 1.5}, "seed"), ({"max_iter": 0}, "max_iter"),
])
def test_bad_input_names_the_parameter(kwargs, name):
    args = {"n": 16, "phi": 0.85} | kwargs
    with pytest.raises(ParameterError, match=rf"^{name} must be .*got"):
        make_packing(args.pop("n"), args.pop("phi"), **args)


def test_bad_geometry_names_the_parameter():
    pos, radius = np.zeros((3, 2)), np.full(3, 0.5)
    with pytest.raises(ParameterError, match="^box"):
        find_contacts(pos, radius, 1.9)
    with pytest.raises(ParameterError, match="^shift"):
        find_contacts(pos, radius, 5.0, float("nan"))
    with pytest.raises(ParameterError, match="^pos"):
        find_contacts(np.zeros((3, 3)), radius, 5.0)
    with pytest.raises(ParameterError, match="^radius"):
        hertz_forces(pos, radius[:2], 5.0)
    with pytest.raises(ParameterError, match="^box"):
        hertz_forces(pos, radius, 0.9)
    with pytest.raises(ParameterError, match="^box"):
        hertz_forces(pos, radius, "5")
