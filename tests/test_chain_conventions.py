"""The chain's spectrum conventions (issue 33): physical, lammps, sm, bare.

Each convention's eigenvalues, as `fricstab chain ramp --convention` records
them, are recomputed from `fricstab chain jacobian --convention`'s exported
files with numpy alone: the mass diagonal rebuilt from state.npz's radius and
mass by the convention's stated formula (never read from our code), and
``numpy.linalg.eigvals(J / mass)``.  Error model: both sides are eigenvalues
of the same float64 matrix (the same Newton equilibrium, written and read
bit for bit) from two LAPACK drivers (numpy's geev against scipy's geev with
vectors); a simple eigenvalue's backward error is ~eps |A| times its
condition number (<= ~10 here, the ramp records them), so they agree to
1e-9 |A|: a wrong mass or a wrong matrix moves eigenvalues by O(|A|).
"""

import numpy as np
import pytest

from fricstab.cli import main as cli

#: I / (m R^2) of each convention, as the supplementary material and LAMMPS state it;
#: bare: no mass matrix (the identity)
FACTOR = {"physical": 0.5, "lammps": 0.4, "sm": 1.0, "bare": None}
FX = 0.083


def _mass_from_state(z, convention):
    m, r = z["mass"], z["radius"]
    if FACTOR[convention] is None:
        return np.ones(3 * len(m))
    return np.column_stack([m, m, FACTOR[convention] * m * r ** 2]).ravel()


@pytest.fixture(scope="module")
def exported(tmp_path_factory):
    out = {}
    for c in FACTOR:
        base = tmp_path_factory.mktemp(c)
        assert cli(["chain", "jacobian", "--fx", str(FX), "--convention", c, "--out",
                    str(base / "jac"), "--quiet", "--no-progress"]) == 0
        assert cli(["chain", "ramp", "--fx-max", str(FX), "--step", "1e-3", "--convention", c,
                    "--out", str(base / "ramp"), "--quiet", "--no-progress"]) == 0
        out[c] = base
    return out


@pytest.mark.parametrize("convention", list(FACTOR))
def test_exported_spectrum_equals_the_ramps(exported, convention):
    d = exported[convention]
    jac = np.load(d / "jac" / "jacobian.npy")
    with np.load(d / "jac" / "state.npz") as z:
        mass = _mass_from_state(z, convention)
    assert np.array_equal(np.load(d / "jac" / "mass.npy"), mass)
    ours = np.linalg.eigvals(jac / mass[:, None])
    with np.load(d / "ramp" / "ramp.npz") as z:
        k = int(np.argmin(np.abs(z["fx"] - FX)))
        assert abs(z["fx"][k] - FX) < 1e-12
        ramp = z["eigenvalues"][k]
    scale = np.abs(jac / mass[:, None]).max()
    # match each eigenvalue to its nearest (the spectra are sets)
    dist = np.abs(ours[:, None] - ramp[None, :]).min(axis=1)
    assert dist.max() <= 1e-9 * scale, (convention, dist.max() / scale)
    assert np.sum(ours.imag > 0) == np.sum(ramp.imag > 0)


def test_statics_do_not_depend_on_the_convention(exported):
    """The equilibrium (positions, rotations, histories) is the same under every reading."""
    ref = np.load(exported["physical"] / "jac" / "state.npz")
    for c in FACTOR:
        with np.load(exported[c] / "jac" / "state.npz") as z:
            for key in ("pos", "theta", "history"):
                assert np.array_equal(z[key], ref[key]), (c, key)


def test_sm_is_the_scaled_jacobian_at_unit_mass(exported):
    """SM Eq. 36: theta~ = R theta, T~ = T / R; with m = I_0 = 1 its J~ has the spectrum
    of M^-1 J with I = m R^2 (the similarity S J S^-1 / m with S = diag(1, 1, 1/R))."""
    d = exported["sm"] / "jac"
    jac = np.load(d / "jacobian.npy")
    with np.load(d / "state.npz") as z:
        r = z["radius"]
    s = np.column_stack([np.ones_like(r), np.ones_like(r), r]).ravel()
    scaled = jac / s[:, None] / s[None, :]
    a = np.sort_complex(np.linalg.eigvals(scaled))
    b = np.sort_complex(np.linalg.eigvals(jac / np.load(d / "mass.npy")[:, None]))
    assert np.abs(a - b).max() <= 1e-9 * np.abs(scaled).max()


def test_unknown_convention_is_refused(tmp_path, capsys):
    assert cli(["chain", "ramp", "--convention", "lab", "--out", str(tmp_path / "r")]) == 2
    err = capsys.readouterr().err
    assert err.startswith("fricstab: error:") and "--convention" in err
    assert not (tmp_path / "r").exists()
    from fricstab.laws import ParameterError
    from fricstab.scenes.chain import ChainScene, mass_vector
    with pytest.raises(ParameterError, match="convention"):
        mass_vector(ChainScene(), "Physical")
