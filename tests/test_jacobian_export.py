"""The exported state holds all it takes to recompute the saved Jacobian, to the bit."""

import json

import numpy as np
import pytest
import scipy.sparse as sps

from fricstab.engine import Material, System, jacobian
from fricstab.io.jacobian_export import read_state, system_from_state, write_state_jacobian

CASES = {
    "lee_hurley": ({"E": 1.0, "nu": 0.2, "mus": 0.5, "mur": 0.01}, {"Rw": 0.6}, True),
    "ishima": ({"kn": 1.0, "kt": 0.5}, {}, False),
    "charan": ({"kn": 1.0, "kt": 0.5, "mu": 0.4}, {}, True),
    "hertz": ({"kn": 1.0}, {}, False),
    "linear": ({"kn": 1.0, "kt": 0.3, "mu": 0.4}, {}, True),
}


@pytest.mark.parametrize("law", sorted(CASES))
def test_recomputed_from_the_state_file_alone(law, tmp_path):
    """Jittered lattice (small overlaps), a wall or a Lees-Edwards box, random histories:
    the matrix rebuilt from state.npz equals jacobian.npz exactly (same contacts, same
    order, same arithmetic), and dofs.json, mass.npy describe its rows."""
    params, wall_params, wall = CASES[law]
    rng = np.random.default_rng(0)
    gx, gy = np.meshgrid(np.arange(6), np.arange(5))
    pos = np.column_stack([gx.ravel(), gy.ravel()]) * 0.9 + 0.45 \
        + rng.normal(scale=0.01, size=(30, 2))
    rad = 0.46 + rng.uniform(-0.01, 0.01, 30)
    family = np.zeros(30, int)
    family[:3] = 1
    system = System(Material(law, params, wall_params), rad, rad ** 2, rad ** 4 / 2,
                    family=family, lx=5.4, ly=0.0 if wall else 4.5, skin=0.2,
                    walls=[(0.0, 1.0)] if wall else ())
    state = system.state(pos, shift=0.0 if wall else 0.3)
    state.contacts.hist[:] = rng.normal(scale=1e-5, size=state.contacts.hist.shape)
    f, k = write_state_jacobian(tmp_path, system, state)
    again = jacobian(*system_from_state(tmp_path / "state.npz"))
    saved = sps.load_npz(tmp_path / "jacobian.npz")
    assert (abs(again[1] - saved) != 0).nnz == 0 and np.array_equal(again[0], f)
    doc = json.loads((tmp_path / "dofs.json").read_text())
    assert len(doc["rows_and_columns"]) == doc["n_dof"] == k.shape[0] == 27 * system.dof
    assert np.load(tmp_path / "mass.npy").shape == (k.shape[0],)
    d = read_state(tmp_path / "state.npz")
    assert d["law"] == law and d["contacts"].shape == (state.contacts.n, 2)
