"""Loaded by pytest before any test module of ``validation/``: takes the fingerprint's
snapshot of the checkout's texts (:data:`claims.fingerprint.SNAPSHOT`) first, so a test module
imported after it, from a file written just before pytest started (a ``git clone`` or
``pull`` then ``pytest``), is known to have run the snapshot's text and not taken for one
edited while the session ran."""

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

from claims.fingerprint import SNAPSHOT  # noqa: E402

__all__ = ["SNAPSHOT"]
