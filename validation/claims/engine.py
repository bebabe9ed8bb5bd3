"""Claims of section engine (see claims/__init__.py)."""

HEADING = 'The engine, the product surface and the tests'
INTRO = ("System-level proofs of every law in every scene, the pinned regression tier, and the product's promises (records, resume, bad input), each shown by a test.")

CLAIMS = []
