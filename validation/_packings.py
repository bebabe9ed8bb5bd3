"""Seeded packings for the validation scripts, cached on disk between runs.

The cache lives in ``validation/.packings/`` (git-ignored; set
``FRICSTAB_PACKING_CACHE`` to move it).  A cached file is keyed by every
argument of :func:`fricstab.scenes.packing.make_packing` and by the
protocol version ``PROTOCOL`` (2: FIRE on the engine, contacts summed in key
order; a packing of the loop before the engine differs at N >= 1024 and must
not be reused), so a stale packing cannot be reused after a knob changes.
"""

import os
import time
from pathlib import Path

from fricstab.scenes.packing import Packing, make_packing
from fricstab.scenes.packing_friction import frictional, material, with_kt

CACHE = Path(os.environ.get("FRICSTAB_PACKING_CACHE",
                            Path(__file__).resolve().parent / ".packings"))
PROTOCOL = 2


def packing(n, phi, seed, **knobs):
    """``make_packing(n, phi, seed, **knobs)``, from the cache when present."""
    key = "_".join([f"v{PROTOCOL}", f"n{n}", f"phi{phi:g}", f"s{seed}"]
                   + [f"{k}{v:g}" for k, v in sorted(knobs.items())])
    path = CACHE / f"{key}.npz"
    if path.exists():
        return Packing.load(path)
    CACHE.mkdir(parents=True, exist_ok=True)
    t0 = time.perf_counter()
    p = make_packing(n, phi, seed, **knobs)
    print(f"  made packing {key} in {time.perf_counter() - t0:.1f} s", flush=True)
    p.save(path)
    return p


def ishima(bb, kt):
    """``(system, state)``: Ishima's law at kT/kN = ``kt`` (0: frictionless hertz) on backbone
    ``bb``, friction switched on at the force balance (App. A.2)."""
    fr = frictional(bb, with_kt(material("ishima"), kt))
    return fr.system, fr.state
