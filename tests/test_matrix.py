"""The matrix: every pair law in every scene, from the command line with its defaults.

For each of the 15 cells, ``fricstab SCENE jacobian --law LAW --out DIR``
(small systems, the law's documented defaults otherwise) exits 0 and writes the
common files; the Jacobian recomputed from ``state.npz`` alone
(:func:`fricstab.io.jacobian_export.system_from_state`) equals ``jacobian.npz``
to the bit.  The system-level proof of each cell is in
``tests/test_{chain,packing,shear}_proof.py``; docs/reference/law_scene_matrix.md names both.
"""

import json

import numpy as np
import pytest
import scipy.sparse as sps

from fricstab.cli import main
from fricstab.engine import jacobian
from fricstab.io import rundir
from fricstab.io.jacobian_export import FILES, system_from_state
from fricstab.laws import PAIR_LAW_NAMES

SMALL = {"chain": ["--n", "6"], "packing": ["--n", "32", "--phi", "0.88"],
         "shear": ["--n", "20"]}


@pytest.mark.parametrize("law", PAIR_LAW_NAMES)
@pytest.mark.parametrize("scene", sorted(SMALL))
def test_every_law_runs_in_every_scene(scene, law, tmp_path, capsys):
    out = tmp_path / "o"
    rc = main([scene, "jacobian", "--law", law, *SMALL[scene], "--out", str(out),
               "--no-progress", "--quiet"])
    assert rc == 0, capsys.readouterr().err
    for name in FILES:
        assert (out / name).is_file(), name
    system, state = system_from_state(out / "state.npz")
    assert system.material.law == law
    f, k = jacobian(system, state)
    saved = sps.load_npz(out / "jacobian.npz")
    assert (abs(k - saved) != 0).nnz == 0
    doc = json.loads((out / "dofs.json").read_text())
    assert doc["n_dof"] == k.shape[0] == len(np.load(out / "mass.npy"))
    assert doc["dof_per_particle"] == (2 if law == "hertz" else 3)
    record = rundir.verify(out, "jacobian")     # every file in the manifest, unchanged
    assert set(FILES) <= set(record["files"])
    assert record["fingerprint"]["parameters"]["law"] == law


@pytest.mark.parametrize("scene", sorted(SMALL))
@pytest.mark.parametrize("bad, key", [(["--law", "coulomb"], "--law"),
                                      (["--param", "zeta=1"], "zeta"),
                                      (["--law", "hertz", "--param", "mu=0.5"], "mu"),
                                      (["--param", "kn=-1"], "kn")])
def test_bad_law_input_is_one_line_exit_2_nothing_written(scene, bad, key, tmp_path, capsys):
    """An unknown law, an unknown parameter, a parameter of another law, a value out
    of range: ``fricstab: error: ...`` naming it, exit 2, no output directory."""
    out = tmp_path / "o"
    argv = [scene, "jacobian", *SMALL[scene], *bad, "--out", str(out), "--no-progress"]
    if scene == "shear" and key == "kn":
        argv = [scene, "jacobian", *SMALL[scene], "--law", "hertz", "--param", "kn=-1",
                "--out", str(out)]
    rc = main(argv)
    err = capsys.readouterr().err
    assert rc == 2 and err.startswith("fricstab: error: ") and err.count("\n") == 1, err
    assert key in err
    assert not out.exists()
