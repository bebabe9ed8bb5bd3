"""Hypothesis profiles (numba compiles on first call, so no per-example deadline),
and the OVITO fixture of the tests that load exported frames in OVITO."""

import os

import pytest
from hypothesis import HealthCheck, settings

settings.register_profile(
    "default", deadline=None, max_examples=60,
    suppress_health_check=[HealthCheck.too_slow])
settings.register_profile(
    "thorough", deadline=None, max_examples=2000,
    suppress_health_check=[HealthCheck.too_slow])
settings.load_profile(os.environ.get("FRICSTAB_HYPOTHESIS_PROFILE", "default"))


@pytest.fixture(scope="session")
def ovito_io():
    """``ovito.io``; the test is skipped, saying why, where OVITO is not installed."""
    return pytest.importorskip(
        "ovito.io", reason="OVITO is not installed: it is the 'ovito' extra "
                           "(pip install -e '.[ovito]'), which .ci/run installs")
