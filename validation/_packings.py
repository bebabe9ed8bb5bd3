"""Seeded packings for the validation scripts, cached on disk between runs.

The cache lives in ``validation/.packings/`` (git-ignored; set
``FRICSTAB_PACKING_CACHE`` to move it).  A cached file is keyed by every
argument of :func:`fricstab.scenes.packing.make_packing`, so a stale packing cannot
be reused after a knob changes.
"""

import os
import time
from pathlib import Path

from fricstab.scenes.packing import Packing, make_packing

CACHE = Path(os.environ.get("FRICSTAB_PACKING_CACHE",
                            Path(__file__).resolve().parent / ".packings"))


def packing(n, phi, seed, **knobs):
    """``make_packing(n, phi, seed, **knobs)``, from the cache when present."""
    key = "_".join([f"n{n}", f"phi{phi:g}", f"s{seed}"]
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
