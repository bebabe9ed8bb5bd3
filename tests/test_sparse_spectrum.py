"""Sparse ends of the spectrum of M^-1 K against dense, on sheared packings and a chain (issue 36).

Error model (fricstab.analysis.sparse_spectrum): an eigenvalue with backward
error eta (ARPACK at tol = 0: a few eps) and condition number cond is off by
at most ~ cond (eta + n eps) |A|_inf, the dense one by cond n eps |A|_inf;
``bound_ratio`` is the largest difference over 10 times that, so <= 1.
"""

import numpy as np
import pytest
import scipy.sparse as sps

from fricstab.analysis.sparse_spectrum import (SHIFT, compare_with_dense, fastest_growth,
                                               growth_of, soft_end)
from fricstab.analysis.spectrum import decompose
from fricstab.engine import jacobian
from fricstab.errors import NumericalError, ParameterError
from fricstab.protocols.aqs import relax_step
from fricstab.protocols.ramp import ramped_equilibrium
from fricstab.scenes.chain import ChainScene, chain_system, mass_vector
from fricstab.scenes.packing import make_packing
from fricstab.scenes.packing_friction import backbone, frictional, material


@pytest.fixture(scope="module")
def packing():
    return backbone(make_packing(64, 0.9, 0))


def _sheared(packing, law, steps=12):
    """K and mass after ``steps`` AQS steps of 1e-3 (histories make K non-symmetric)."""
    fr = frictional(packing, material(law))
    system, state = fr.system, fr.state
    for _ in range(steps):
        state, _ = relax_step(system, state, 1e-3, 1e-13)
    _, k = jacobian(system, state)
    return k, system.gmass[system.free, :system.dof].ravel(), system.dof


@pytest.fixture(scope="module")
def charan(packing):
    return _sheared(packing, "charan")


@pytest.mark.parametrize("law", ["charan", "ishima"])
def test_soft_end_equals_dense_on_sheared_packing(packing, law):
    k, mass, dof = _sheared(packing, law)
    assert abs(k - k.T).max() > 1e-6   # the history makes K non-symmetric
    r = compare_with_dense(k, mass, 12, dof=dof)
    assert r["bound_ratio"] <= 1.0, r
    assert r["max_rel"] < 1e-10, r   # measured ~3e-14 (cond ~ 1 at the soft end)
    assert r["pairs_sparse"] == r["pairs_dense"]
    assert r["growth_sparse"] == pytest.approx(r["growth_dense_soft"], abs=1e-12)


def test_complex_pair_nearest_zero(charan):
    """A skew coupling of the two softest modes (M-normalized u, v) makes them a pair.

    ``dK = e M (u v^T - v u^T) M`` keeps ``K C = C^T K = 0`` (u, v are in the
    complement) and turns the 2x2 block [[l1, e], [-e, l2]] complex for
    ``e > |l1 - l2| / 2 ~ 2.3e-3``: a pair near -0.081 +- 0.0098 i.
    """
    k, mass, dof = charan
    spec = decompose(k.toarray(), mass)
    order = np.argsort(np.abs(spec.eigenvalues))[2:4]          # past the translations
    u, v = (spec.right[:, i].real / np.sqrt(spec.right[:, i].real ** 2 @ mass) for i in order)
    mu, mv = mass * u, mass * v
    k2 = sps.csr_matrix(k.toarray() + 0.01 * (np.outer(mu, mv) - np.outer(mv, mu)))
    soft = soft_end(k2, mass, 12, dof=dof)
    assert soft.eigenvalues[0].imag > 0 and soft.eigenvalues[1] == soft.eigenvalues[0].conj()
    r = compare_with_dense(k2, mass, 12, dof=dof)
    assert r["bound_ratio"] <= 1.0 and r["pairs_sparse"] == r["pairs_dense"] == 1, r
    # this pair (|b| / (2 sqrt|a|) ~ 0.017) outgrows the bulk pairs (~2e-3): the
    # soft-end growth is the whole spectrum's
    assert r["growth_sparse"] == pytest.approx(r["growth_dense"], rel=1e-9)
    assert r["growth_sparse"] > 0.01


def test_chain_state_without_translations():
    scene = ChainScene()
    state = ramped_equilibrium(scene, 0.02, step=5e-3)
    _, k = jacobian(chain_system(scene), state)
    mass = mass_vector(scene)
    r = compare_with_dense(k, mass, 26)      # n = 30: nearly the whole spectrum
    assert r["bound_ratio"] <= 1.0 and r["pairs_sparse"] == r["pairs_dense"] >= 1, r
    assert r["growth_sparse"] == pytest.approx(r["growth_dense"], rel=1e-9)
    with pytest.raises(ParameterError, match="not zero modes"):
        soft_end(k, mass, 4, dof=3)          # a wall: translations are not zero modes


def test_the_search_widens_past_a_zero_cluster_of_any_size():
    """A packing at jamming can hold hundreds of zero modes (N = 4,096, phi = 0.84: ~200 in
    its backbone); the search widens until it holds k live eigenvalues.  Here 60 exact zeros
    and k = 5: three widenings (6, 13, 27 wanted) see only zeros, the old search stopped there
    with none (an IndexError), the fourth and fifth find them.  Diagonal K: the eigenvalues
    are its entries.  Error model: Arnoldi resolves w = 1/(lambda - sigma) to ~eps of the
    largest |w|, the zero modes' 1/sigma (sigma = SHIFT |A| = 1e-7), so lambda is off by
    ~eps lambda^2 / sigma (1e-9 here; 5.6e-10 seen); asserted within 10 times that."""
    live = -np.linspace(0.5, 10.0, 240)
    k = sps.diags(np.concatenate([np.zeros(60), live])).tocsr()
    soft = soft_end(k, np.ones(300), 5)
    assert soft.zero_modes == 60
    bound = 10 * np.finfo(float).eps * live[4] ** 2 / (SHIFT * 10.0)
    assert np.allclose(np.sort(soft.eigenvalues.real)[::-1], live[:5], rtol=0, atol=bound)
    with pytest.raises(NumericalError, match="zero cluster"):   # the widest search (298): zeros
        soft_end(sps.diags(np.concatenate([np.zeros(299), [-1.0]])).tocsr(),
                 np.ones(300), 5)


def test_rattler_zero_modes_counted_and_left_out(charan):
    k, mass, dof = charan
    k2 = sps.block_diag([k, sps.csr_matrix((3, 3))])   # a disk without contacts
    soft = soft_end(k2, np.concatenate([mass, [1.0, 1.0, 0.1]]), 8, dof=dof)
    ref = soft_end(k, mass, 8, dof=dof)
    assert soft.zero_modes == 3
    # the same eigenvalues: both at backward error ~eps, cond ~1 (see module doc)
    assert np.allclose(soft.eigenvalues, ref.eigenvalues, rtol=1e-12, atol=0)


def test_fastest_growth_bound_holds_on_dense(charan):
    k, mass, dof = charan
    g = fastest_growth(k, mass, 12, dof=dof)
    w = decompose(k.toarray(), mass, vectors=False).eigenvalues
    outside = np.abs(w) > g.radius * (1 + 1e-9)
    assert growth_of(w[outside]).max() <= g.bound
    assert not g.certified or g.rate >= growth_of(w).max() - 1e-12


@pytest.mark.parametrize("bad", ["nan_k", "nan_mass", "mass_shape", "square", "k_big", "mass0"])
def test_bad_input_raises(charan, bad):
    k, mass, dof = charan
    args = {"K": k, "mass": mass, "k": 6, "dof": dof}
    if bad == "nan_k":
        args["K"] = k.copy()
        args["K"].data[0] = np.nan
    elif bad == "nan_mass":
        args["mass"] = np.where(np.arange(len(mass)) == 3, np.nan, mass)
    elif bad == "mass_shape":
        args["mass"] = mass[:-1]
    elif bad == "square":
        args["K"] = k.toarray()[:-1]
    elif bad == "k_big":
        args["k"] = len(mass)
    else:
        args["mass"] = np.where(np.arange(len(mass)) == 0, 0.0, mass)
    with pytest.raises(ParameterError):
        soft_end(**args)
