"""Record the regression values (run once, with the code before the restructuring).

    python validation/regression/pin.py --data     # write the stored inputs
    python validation/regression/pin.py            # compute every case, write pinned.json

The stored inputs are a FIRE packing (N = 256, phi = 0.90, seed 0) and a stick
state of a sheared 150-disk plane-shear cell, written by the code that the
pinned values come from.
"""

import argparse
import json
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

from cases import CASES, PACKING, SHEAR_STATE  # noqa: E402


def write_data():
    from fricstab.scenes.packing import make_packing
    from fricstab.scenes.shear import Shear, make_cell, prepare
    from fricstab.cli.shear import resolve_params
    make_packing(256, 0.90, seed=0).save(PACKING)
    p = resolve_params(None, "quick", {"n": 150, "strain": 0.03, "gamma0": 0.01})
    sim = Shear(make_cell(p))
    prepare(sim)
    sim.start_shear()
    sim.advance(int(sim.scalars[3]) * 400)   # 400 frames of shear
    c = sim.cell
    on = sim.cfn > 0
    np.savez(SHEAR_STATE, pos=c.pos, angle=c.angle, radius=c.radius, mass=c.mass,
             inertia=c.inertia, kind=c.kind, lx=c.lx,
             contacts=np.column_stack([sim.pi[on], sim.pj[on]]),
             ft=sim.hist[on, 0], mr=sim.hist[on, 1], fn=sim.cfn[on],
             E=1.0, nu=p["nu"], mus=p["mu_s"], mur=p["mu_r"])


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--data", action="store_true", help="write the stored inputs first")
    ns = ap.parse_args()
    if ns.data:
        write_data()
    rev = subprocess.run(["git", "rev-parse", "HEAD"], capture_output=True, text=True,
                         cwd=HERE).stdout.strip()
    out = {"_revision": rev, "_date": time.strftime("%Y-%m-%d")}
    for name, fn in CASES.items():
        t0 = time.perf_counter()
        out[name] = fn()
        print(f"{name}: {time.perf_counter() - t0:.1f} s", flush=True)
    (HERE / "pinned.json").write_text(json.dumps(out, indent=1) + "\n")


if __name__ == "__main__":
    main()
