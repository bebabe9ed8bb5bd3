"""Jacobian of a sheared state from the engine and its spectrum (fricstab.analysis.shear_spectrum).

Tolerances: the blocks are exact to ~64 eps of their terms (test_lee_hurley);
assembled sums of a few blocks stay within 1e3 eps of the largest entry.
Eigenvalues of a symmetric K through the nonsymmetric dense route carry
round-off ~eps * spectral radius * (eigenvector condition ~1): imaginary
parts below 1e-10 of the radius.  The Jacobian itself is proven against a
complex step of an independent assembly in tests/test_shear_proof.py.
"""

import math
from pathlib import Path

import numpy as np
import pytest
import scipy.linalg
import scipy.sparse.linalg

from fricstab.analysis.shear_spectrum import (CAP_REL, IMAG_TOL, RADIUS_TOL, SOFT_TOL,
                                              clamped_system, recorded_state, soft_spectrum,
                                              softest, spectrum)
from fricstab.engine import jacobian
from fricstab.errors import ParameterError
from fricstab.generated.lee_hurley import lee_hurley_contact

EPS = np.finfo(float).eps
MAT = dict(E=1.0, nu=0.2, mus=0.5, mur=0.01)


def _cluster(ratio=0.0, kind=(0, 0, 0, 0), law="lee_hurley", params=MAT):
    """Four overlapping disks in a rhombus, box lx = 100; histories ``ratio`` x their caps."""
    radius = np.array([0.5, 0.55, 0.45, 0.5])
    pos = np.array([[0.0, 0.0], [1.04, 0.0], [0.46, 0.8], [0.5, -0.85]])
    contacts = np.array([[0, 1], [0, 2], [1, 2], [0, 3], [1, 3]])
    hist = np.zeros((5, 2))
    out = np.empty(9)
    for c, (i, j) in enumerate(contacts):
        d = pos[i] - pos[j]
        lee_hurley_contact(d[0], d[1], radius[i], radius[j], *MAT.values(), 0.0, 0.0, out)
        assert out[0] > 0
        rr = radius[i] * radius[j] / (radius[i] + radius[j])
        hist[c] = (ratio * MAT["mus"] * out[5] * (1 if c % 2 else -1),
                   ratio * MAT["mur"] * rr * out[5])
    mass = math.pi * radius ** 2
    system = clamped_system(law, params, radius, mass, mass * radius ** 2 / 2, kind, 100.0)
    n_hist = system.material.info.n_hist
    state = recorded_state(system, pos, np.zeros(4), contacts, hist[:, :n_hist])
    return system, state


def _k(system, state):
    return jacobian(system, state)[1].toarray()


def test_sticking_without_history_is_symmetric_with_real_spectrum():
    system, state = _cluster(0.0)
    kd = _k(system, state)
    assert np.abs(kd - kd.T).max() <= 1e3 * EPS * np.abs(kd).max()
    spec = spectrum(system, state)
    radius = np.abs(spec.eigenvalues).max()
    assert spec.symmetric and spec.n_complex_pairs == 0
    assert spec.n_sliding == spec.n_rolling == 0
    assert np.abs(spec.eigenvalues.imag).max() <= 1e-10 * radius


def test_sliding_contacts_make_k_nonsymmetric():
    system, state = _cluster(2.0)
    kd = _k(system, state)
    asym = np.abs(kd - kd.T).max() / np.abs(kd).max()
    # the slip rows mu_s dF_n/dq have no transpose partner: O(mu_s) asymmetry
    assert asym > 1e-3
    spec = spectrum(system, state)
    assert not spec.symmetric and spec.n_sliding == spec.n_rolling == 5


def test_free_cluster_translations_are_zero_modes():
    system, state = _cluster(0.5)
    kd = _k(system, state)
    spec = spectrum(system, state)
    radius = np.abs(spec.eigenvalues).max()
    for c in range(2):
        u = np.zeros(12)
        u[c::3] = 1.0
        assert np.abs(kd @ u).max() <= 1e3 * EPS * np.abs(kd).max()
    # two eigenvalues of D at round-off zero
    assert np.sum(np.abs(spec.eigenvalues) <= 1e-10 * radius) >= 2


@pytest.mark.parametrize("law, params", [("hertz", {"kn": 1.0}),
                                         ("charan", {"kn": 1.0, "kt": 0.7, "mu": 0.5}),
                                         ("ishima", {"kn": 1.0, "kt": 0.7})])
def test_every_law_gives_a_spectrum_with_its_generalized_masses(law, params):
    """D = -M^-1 K with M = gmass (m, m, I/s^2): the eigenvalues do not depend on s.

    For ishima (l = R theta) the same K in theta would be S K S with S =
    diag(1, 1, R): D is similar, so the spectra agree to round-off x condition.
    """
    system, state = _cluster(0.3, law=law, params=params)
    spec = spectrum(system, state)
    assert len(spec.eigenvalues) == system.dof * 4
    kd = _k(system, state)
    m = system.gmass[:, :system.dof].ravel()
    s = np.concatenate([[1.0, 1.0, r] for r in system.radius])[:len(m)] if system.dof == 3 \
        else np.ones(len(m))
    k_theta = s[:, None] * kd * s[None, :]
    m_theta = m * s * s
    lam = np.sort_complex(np.linalg.eigvals(-k_theta / m_theta[:, None]))
    radius = np.abs(lam).max()
    assert np.abs(np.sort_complex(spec.eigenvalues) - lam).max() <= 1e-9 * radius


def test_clamped_particles_and_periodic_image():
    system, state = _cluster(0.0, kind=(0, 0, 1, 0))
    k = _k(system, state)
    assert k.shape == (9, 9)
    # shifting a particle by the box length changes nothing (another image)
    pos = state.q[:, :2] + np.array([[0.0, 0.0], [100.0, 0.0], [0.0, 0.0], [-100.0, 0.0]])
    c = state.contacts
    s2 = recorded_state(system, pos, np.zeros(4), np.column_stack([c.i, c.j]), c.hist)
    # x + 100 - 100 moves x by up to ulp(100) ~ 1.4e-14: relative 1e-12 of an
    # overlap ~1e-2, amplified by the 1/delta of the block derivatives: 1e-9.
    assert np.allclose(_k(system, s2), k, rtol=0, atol=1e-9 * np.abs(k).max())


def test_recorded_flags_restore_the_branch_of_rounded_histories():
    """A history a few ulp inside its cap but recorded as sliding is put on the cap
    (slide branch), one a few ulp outside but recorded as sticking inside it, by
    CAP_REL; the forces move by CAP_REL of the cap at most."""
    system, state = _cluster(1.0 + 1e-9)         # projected onto the caps exactly
    c = state.contacts
    caps = np.abs(c.hist.copy())
    assert np.all(c.flag == 3)
    rounded = np.sign(c.hist) * caps * (1.0 - 4 * EPS)
    contacts = np.column_stack([c.i, c.j])
    pos, theta = state.q[:, :2], np.zeros(4)
    inside = recorded_state(system, pos, theta, contacts, rounded)
    assert np.all(inside.contacts.flag == 0)     # without flags: the stick branch
    back = recorded_state(system, pos, theta, contacts, rounded, flags=np.full(5, 3))
    assert np.all(back.contacts.flag == 3)
    assert np.array_equal(back.contacts.hist, c.hist)
    outside = np.sign(c.hist) * caps * (1.0 + 4 * EPS)
    stick = recorded_state(system, pos, theta, contacts, outside, flags=np.zeros(5, int))
    assert np.all(stick.contacts.flag == 0)
    assert np.allclose(np.abs(stick.contacts.hist), caps * (1 - CAP_REL), rtol=4 * EPS)


def test_growth_rate_definition():
    system, state = _cluster(0.0)
    spec = spectrum(system, state)
    lam = spec.eigenvalues
    assert math.isclose(spec.max_growth_rate, np.abs(np.sqrt(-lam.astype(complex)).real).max())


def test_bad_input_is_named():
    system, state = _cluster(0.0)
    contacts = np.column_stack([state.contacts.i, state.contacts.j])
    with pytest.raises(ParameterError, match="theta"):
        recorded_state(system, state.q[:, :2], np.zeros(3), contacts, state.contacts.hist)
    with pytest.raises(ParameterError, match="contacts"):
        recorded_state(system, state.q[:, :2], np.zeros(4), np.array([[0, 9]] * 5),
                       state.contacts.hist)
    with pytest.raises(ParameterError, match="not within reach"):
        recorded_state(system, state.q[:, :2], np.zeros(4), np.array([[2, 3]]), np.zeros((1, 2)))


# ------------------------------------------------------------------ the soft route

STORED = Path(__file__).resolve().parents[1] / "validation" / "regression" / "shear_state.npz"


def _stored(scale=1.0):
    """The stored stick state of a sheared 150-disk cell (450 dof); histories x ``scale``."""
    with np.load(STORED) as z:
        s = {key: z[key] for key in z.files}
    law = {key: float(s[key]) for key in ("E", "nu", "mus", "mur")}
    system = clamped_system("lee_hurley", law, s["radius"], s["mass"], s["inertia"], s["kind"],
                            float(s["lx"]))
    state = recorded_state(system, s["pos"], s["angle"], s["contacts"],
                           scale * np.column_stack([s["ft"], s["mr"]]))
    return system, state


def soft_error_bound(system, state, window, tol=SOFT_TOL):
    """Error model of the k softest against the dense route, per eigenvalue of ``window``.

    Both routes are backward stable on matrices similar to D: the dense QR on
    D (balanced by LAPACK), the sparse LU of shift-invert ARPACK on
    ``S = -M^-1/2 K M^-1/2``; a backward error ``n eps |S|`` (Wilkinson's
    worst case, ``|S|`` = the spectral radius here, S nearly normal) moves an
    eigenvalue by ``cond`` times it, and ARPACK's stopping test adds ``cond
    max(tol, eps) |lambda|``.  ``cond``: the eigenvalue condition number of
    S, from its dense left and right eigenvectors.
    """
    kk = _k(system, state)
    m = system.gmass[system.free, :system.dof].ravel()
    s = -kk / np.sqrt(m)[:, None] / np.sqrt(m)[None, :]
    w, vl, vr = scipy.linalg.eig(s, left=True, right=True)
    vl, vr = vl / np.linalg.norm(vl, axis=0), vr / np.linalg.norm(vr, axis=0)
    cond = 1.0 / np.abs(np.einsum("ij,ij->j", vl.conj(), vr))
    at = np.abs(window[:, None] - w[None, :]).argmin(axis=1)
    n, radius = len(w), np.abs(w).max()
    return cond[at] * (n * EPS * radius + max(tol, EPS) * np.abs(window))


def _nearest(a, b):
    return np.abs(a[:, None] - b[None, :]).min(axis=1)


@pytest.mark.parametrize("scale, k", [(1.0, 50), (0.5, 20), (0.0, 30)])
def test_soft_route_matches_the_dense_k_softest(scale, k):
    """Histories as stored (sliding contacts, complex pairs), halved, and none (K symmetric)."""
    system, state = _stored(scale)
    dense = spectrum(system, state, k)
    soft = soft_spectrum(system, state, k)
    assert soft.route == "soft" and dense.route == "dense" and soft.fallback == ""
    assert soft.n_null == dense.n_null > 0                # the cell has rattlers
    assert np.sum(dense.eigenvalues == 0) >= dense.n_null
    a, b = soft.softest, dense.softest
    assert len(a) == len(b) in (k, k + 1)
    bound = soft_error_bound(system, state, a)
    assert np.all(_nearest(a, b) <= bound)
    assert np.all(_nearest(b, a) <= soft_error_bound(system, state, b))
    # the window is the soft end: nothing of the dense spectrum (beside the
    # exact zeros of the null columns) is softer than its edge
    nonnull = np.sort(np.abs(dense.eigenvalues))[dense.n_null:]
    assert np.abs(b).max() <= nonnull[len(b) - 1] and len(b) <= len(nonnull)
    # the statistics of the soft route are those of the dense window
    radius = dense.spectral_radius
    assert abs(soft.spectral_radius / radius - 1) <= RADIUS_TOL
    assert soft.n_complex_pairs == np.sum(np.abs(b.imag) > IMAG_TOL * radius) // 2
    assert soft.n_complex_pairs <= dense.n_complex_pairs
    growth_b = np.abs(np.sqrt(-b).real).max()
    assert soft.max_growth_rate <= dense.max_growth_rate * (1 + 1e-9)
    # growth |Re sqrt(-lambda)| ~ |Im lambda| / (2 sqrt(Re lambda)): relative error of an
    # eigenvalue error e: e / |Im lambda| at most; bounded by the window's worst
    assert math.isclose(soft.max_growth_rate, growth_b, rel_tol=1e-6, abs_tol=1e-9 * math.sqrt(
        radius))
    if dense.lowest_real_eigenvalue < 0:
        assert soft.lowest_real_eigenvalue == pytest.approx(dense.lowest_real_eigenvalue,
                                                            abs=bound.max())
    else:
        assert soft.lowest_real_eigenvalue == dense.lowest_real_eigenvalue == 0.0
    if scale == 0.0:
        assert soft.symmetric and soft.n_complex_pairs == dense.n_complex_pairs == 0


def test_softest_keeps_a_conjugate_pair_whole():
    w = np.array([3.0, 1.0, 2.0 + 1j, 2.0 - 1j, 5.0])
    np.testing.assert_array_equal(softest(w, 2), [1.0, 2.0 + 1j, 2.0 - 1j])
    np.testing.assert_array_equal(softest(w, 3), [1.0, 2.0 + 1j, 2.0 - 1j])
    np.testing.assert_array_equal(softest(w, 4), [1.0, 2.0 + 1j, 2.0 - 1j, 3.0])
    assert len(softest(w, 9)) == 5


def test_arpack_failure_falls_back_to_dense_and_says_so(monkeypatch):
    def no_convergence(*args, **kw):
        raise scipy.sparse.linalg.ArpackNoConvergence("No convergence (1 iterations)", [], [])
    system, state = _stored()
    monkeypatch.setattr(scipy.sparse.linalg, "eigs", no_convergence)
    spec = soft_spectrum(system, state, 50)
    monkeypatch.undo()
    assert "ArpackNoConvergence" in spec.fallback
    dense = spectrum(system, state, 50)
    a, b = spec.softest, dense.softest     # dense on D without the null columns, and with
    assert len(a) == len(b) and np.all(_nearest(a, b) <= soft_error_bound(system, state, a))
    assert spec.n_complex_pairs == np.sum(np.abs(dense.softest.imag) > IMAG_TOL
                                          * dense.spectral_radius) // 2


def test_small_problem_takes_the_dense_window():
    system, state = _cluster(2.0)                  # 12 dof: ARPACK needs k < n - 1
    soft = soft_spectrum(system, state, 20)
    dense = spectrum(system, state, 20)
    assert soft.fallback == "" and len(soft.softest) == 12 - soft.n_null
    a, b = soft.softest, dense.softest            # two dense solves: round-off apart
    assert np.all(_nearest(a, b) <= soft_error_bound(system, state, a))


def test_bad_window_is_named():
    system, state = _cluster(0.0)
    for k in (0, -3, 2.5, True):
        with pytest.raises(ParameterError, match="k must be an integer"):
            soft_spectrum(system, state, k)
    with pytest.raises(ParameterError, match="tol"):
        soft_spectrum(system, state, 4, tol=-1.0)


def test_every_capped_law_has_its_cap_slots():
    """A recorded cap branch is restored for every pair law with a cap (CAP_SLOTS), on
    history slots the law has: a law added without its slots would lose its branches."""
    from fricstab.analysis.shear_spectrum import CAP_SLOTS
    from fricstab.laws import PAIR_LAW_NAMES, get_law
    for name in PAIR_LAW_NAMES:
        info = get_law(name)
        assert info.capped == (name in CAP_SLOTS), name
        for slots in CAP_SLOTS.get(name, {}).values():
            assert max(slots) < info.n_hist, name
