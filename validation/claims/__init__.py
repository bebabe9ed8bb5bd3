"""The registry of claims: every number fricstab states about what it computed.

Sections are modules of this package (``chain``, ``packing``, ...), each with
a list ``CLAIMS`` of :class:`claims.core.Claim`.  ``validation/RESULTS.md``
and the marked blocks of the README and the docs are rendered from the
claims' recorded values (:mod:`claims.render`); ``validation/reproduce.py``
recomputes and records them.  See ``docs/howto/reproduce.md``.
"""

import importlib

#: the sections of RESULTS.md, in order: modules of this package, each with HEADING,
#: INTRO (the setting: units, parameters; numbers we computed belong in claims, never
#: there) and CLAIMS.
SECTION_KEYS = ["kernels", "chain", "packing", "shear", "aqs", "precursors", "engine"]


def section_module(key):
    """The module of section ``key``."""
    return importlib.import_module(f"{__name__}.{key}")


def sections():
    """(key, heading, introduction) of every section, in order."""
    return [(k, section_module(k).HEADING, section_module(k).INTRO) for k in SECTION_KEYS]


def all_claims(strict=True):
    """Every claim, in the order of the sections and of each section's list.  With
    ``strict=False`` a section module that fails to import is skipped with a warning
    (``reproduce.py --claim`` while another section is being edited)."""
    out = []
    for key in SECTION_KEYS:
        try:
            mod = section_module(key)
        except Exception as exc:       # noqa: BLE001 - named, and fatal when strict
            if strict:
                raise
            import warnings
            warnings.warn(f"claims.{key} skipped: {type(exc).__name__}: {exc}")
            continue
        for c in mod.CLAIMS:
            if c.section != key:
                raise ValueError(f"claim {c.name} is listed in {key} but says section {c.section}")
            out.append(c)
    names = [c.name for c in out]
    dup = {n for n in names if names.count(n) > 1}
    if dup:
        raise ValueError(f"claim names used twice: {sorted(dup)}")
    return out


def by_name():
    """name -> claim."""
    return {c.name: c for c in all_claims()}


def jobs(strict=True):
    """job -> its claims (claims that share one computation)."""
    out = {}
    for c in all_claims(strict):
        out.setdefault(c.job_name, []).append(c)
    for job, cs in out.items():
        if len({c.compute for c in cs}) != 1 or len({c.tier for c in cs}) != 1:
            raise ValueError(f"job {job}: its claims must share compute and tier")
    return out
