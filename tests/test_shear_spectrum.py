"""Jacobian of a sheared state and its spectrum (fricstab.analysis.shear_spectrum).

Tolerances: the blocks are exact to ~64 eps of their terms (test_lee_hurley);
assembled sums of a few blocks stay within 1e3 eps of the largest entry.
Eigenvalues of a symmetric K through the nonsymmetric dense route carry
round-off ~eps * spectral radius * (eigenvector condition ~1): imaginary
parts below 1e-10 of the radius.
"""

import math

import numpy as np
import pytest

from fricstab.generated.lee_hurley import lee_hurley_contact, lee_hurley_increment
from fricstab.laws import ParameterError
from fricstab.analysis.shear_spectrum import assemble_stiffness, shear_spectrum

EPS = np.finfo(float).eps
MAT = dict(E=1.0, nu=0.2, mus=0.5, mur=0.01)


def _cluster(ratio=0.0):
    """Four overlapping disks in a rhombus, free (no walls), box lx = 100.

    ``ratio`` sets every trial history to ``ratio`` times its cap (> 1: sliding).
    """
    radius = np.array([0.5, 0.55, 0.45, 0.5])
    pos = np.array([[0.0, 0.0], [1.04, 0.0], [0.46, 0.8], [0.5, -0.85]])
    contacts = np.array([[1, 0], [2, 0], [2, 1], [3, 0], [3, 1]])
    ft, mr = np.zeros(5), np.zeros(5)
    out = np.empty(9)
    for c, (i, j) in enumerate(contacts):
        d = pos[i] - pos[j]
        lee_hurley_contact(d[0], d[1], radius[i], radius[j], *MAT.values(), 0.0, 0.0, out)
        assert out[0] > 0
        rr = radius[i] * radius[j] / (radius[i] + radius[j])
        ft[c] = ratio * MAT["mus"] * out[5] * (1 if c % 2 else -1)
        mr[c] = ratio * MAT["mur"] * rr * out[5]
    mass = math.pi * radius ** 2
    return dict(pos=pos, theta=np.zeros(4), radius=radius, mass=mass, inertia=mass * radius ** 2 / 2,
                mobile=np.ones(4, bool), contacts=contacts, ft=ft, mr=mr, lx=100.0)


def _k(s):
    return assemble_stiffness(s["pos"], s["radius"], s["mobile"], s["contacts"], s["ft"],
                              s["mr"], s["lx"], **MAT)


def test_sticking_without_history_is_symmetric_with_real_spectrum():
    s = _cluster(0.0)
    k, _ = _k(s)
    kd = k.toarray()
    assert np.abs(kd - kd.T).max() <= 1e3 * EPS * np.abs(kd).max()
    spec = shear_spectrum(**s, **MAT)
    radius = np.abs(spec.eigenvalues).max()
    assert spec.symmetric and spec.n_complex_pairs == 0
    assert np.abs(spec.eigenvalues.imag).max() <= 1e-10 * radius


def test_sliding_contacts_make_k_nonsymmetric():
    s = _cluster(2.0)
    kd = _k(s)[0].toarray()
    asym = np.abs(kd - kd.T).max() / np.abs(kd).max()
    # the slip rows mu_s dF_n/dq have no transpose partner: O(mu_s) asymmetry
    assert asym > 1e-3
    assert not shear_spectrum(**s, **MAT).symmetric


def test_free_cluster_translations_are_zero_modes():
    s = _cluster(0.5)
    kd = _k(s)[0].toarray()
    spec = shear_spectrum(**s, **MAT)
    radius = np.abs(spec.eigenvalues).max()
    for c in range(2):
        u = np.zeros(12)
        u[c::3] = 1.0
        assert np.abs(kd @ u).max() <= 1e3 * EPS * np.abs(kd).max()
    # two eigenvalues of D at round-off zero
    assert np.sum(np.abs(spec.eigenvalues) <= 1e-10 * radius) >= 2


def test_k_column_is_the_derivative_of_the_assembled_forces_along_the_increment_rule():
    """Central difference with positions moved and histories advanced by the rule.

    Step h = 1e-7 (lengths ~1, overlaps ~1e-2): truncation (h/delta)^2 ~ 1e-10,
    rounding eps/h ~ 1e-9 of the force scale: bound 1e-6 of the column.
    """
    for ratio in (0.5, 2.0):
        s = _cluster(ratio)
        kd = _k(s)[0].toarray()
        rate = np.empty((2, 6))
        h = 1e-7
        for col in range(12):
            p, comp = divmod(col, 3)
            forces = []
            for sign in (1.0, -1.0):
                pos, ft, mr = s["pos"].copy(), s["ft"].copy(), s["mr"].copy()
                if comp < 2:
                    pos[p, comp] += sign * h
                for c, (i, j) in enumerate(s["contacts"]):
                    d = s["pos"][i] - s["pos"][j]
                    lee_hurley_increment(d[0], d[1], s["radius"][i], s["radius"][j],
                                         MAT["E"], MAT["nu"], rate)
                    dq = np.zeros(6)
                    if p == i:
                        dq[comp] = sign * h
                    if p == j:
                        dq[3 + comp] = sign * h
                    ft[c] += rate[0] @ dq
                    mr[c] += rate[1] @ dq
                forces.append(assemble_stiffness(pos, s["radius"], s["mobile"], s["contacts"],
                                                 ft, mr, s["lx"], **MAT)[1].ravel())
            fd = (forces[0] - forces[1]) / (2 * h)
            assert np.abs(fd - kd[:, col]).max() <= 1e-6 * max(np.abs(kd[:, col]).max(), 1e-3)


def test_clamped_particles_and_periodic_image():
    s = _cluster(0.0)
    s["mobile"] = np.array([True, True, False, True])
    k, _ = _k(s)
    assert k.shape == (9, 9)
    # shifting a particle by the box length changes nothing (minimum image)
    s2 = {**s, "pos": s["pos"] + np.array([[0.0, 0.0], [100.0, 0.0], [0.0, 0.0], [-100.0, 0.0]])}
    # x + 100 - 100 moves x by up to ulp(100) ~ 1.4e-14: relative 1e-12 of an
    # overlap ~1e-2, amplified by the 1/delta of the block derivatives: 1e-9.
    assert np.allclose(_k(s2)[0].toarray(), k.toarray(), rtol=0,
                       atol=1e-9 * np.abs(k.toarray()).max())


def test_growth_rate_definition():
    s = _cluster(0.0)
    spec = shear_spectrum(**s, **MAT)
    lam = spec.eigenvalues
    assert math.isclose(spec.max_growth_rate, np.abs(np.sqrt(-lam.astype(complex)).real).max())


def test_bad_input_is_named():
    s = _cluster(0.0)
    with pytest.raises(ParameterError, match="radius"):
        shear_spectrum(**{**s, "radius": s["radius"][:3]}, **MAT)
    with pytest.raises(ParameterError, match="contacts"):
        shear_spectrum(**{**s, "contacts": np.array([[0, 9]] * 5)}, **MAT)
