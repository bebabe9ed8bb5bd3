"""Every protocol writes ``result.json`` with versions, seed, parameters and timings.

One tiny run of each protocol of each scene (chain ramp, jacobian, dynamics,
waves; packing make, rigidity, dos, jacobian; shear run, analyze, jacobian), all into
one output folder per scene, then the index ``result.json`` of each folder is read
back.
"""

import json

import pytest

from fricstab.cli import main

RUNS = {
    "chain": [["chain", "ramp", "--n", "4", "--fx-max", "0.01"],
              ["chain", "jacobian", "--n", "4", "--fx", "0.005"],
              ["chain", "dynamics", "--n", "4", "--fx", "0.005", "--duration", "5"],
              ["chain", "waves", "--n", "4", "--fx", "0.005", "--realizations", "2",
               "--duration", "5", "--scheduler", "inline"]],
    "packing": [["packing", "make", "--n", "32", "--phi", "0.88", "--seed", "1"],
                ["packing", "rigidity", "--packing", "{out}", "--kt", "1"],
                ["packing", "dos", "--packing", "{out}", "--kt", "1", "--bins", "10"],
                ["packing", "jacobian", "--packing", "{out}", "--law", "lee_hurley"]],
    "shear": [["shear", "run", "--n", "40", "--strain", "0.002", "--dgamma", "1e-4",
               "--gamma0", "0"],
              ["shear", "analyze", "--no-spectra"],
              ["shear", "jacobian", "--n", "20", "--law", "hertz"]],
}
PROTOCOLS = {"chain": ["dynamics", "jacobian", "ramp", "waves"],
             "packing": ["dos", "jacobian", "packing", "rigidity"],
             "shear": ["analysis", "jacobian", "shear"]}


@pytest.mark.parametrize("scene", sorted(RUNS))
def test_result_json_of_every_protocol_has_provenance(scene, tmp_path, capsys):
    out = tmp_path / scene
    for argv in RUNS[scene]:
        argv = [a.replace("{out}", str(out)) for a in argv]
        rc = main(argv + ["--out", str(out), "--no-progress"])
        assert rc in (0, 3), capsys.readouterr().err   # 3: packing theory vs step strain
    index = json.loads((out / "result.json").read_text())
    assert index["protocols"] == PROTOCOLS[scene]
    for name, rec in index["records"].items():
        assert rec["protocol"] == name
        assert rec["versions"]["numpy"] and rec["versions"]["fricstab"]
        assert "seed" in rec and rec["parameters"]
        assert rec["timings"] and all(t["wall_s"] >= 0 and t["cpu_s"] >= 0
                                      for t in rec["timings"].values())
