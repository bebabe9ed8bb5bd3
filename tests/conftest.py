"""Hypothesis profiles: numba compiles on first call, so no per-example deadline."""

import os

from hypothesis import HealthCheck, settings

settings.register_profile(
    "default", deadline=None, max_examples=60,
    suppress_health_check=[HealthCheck.too_slow])
settings.register_profile(
    "thorough", deadline=None, max_examples=2000,
    suppress_health_check=[HealthCheck.too_slow])
settings.load_profile(os.environ.get("FRICSTAB_HYPOTHESIS_PROFILE", "default"))
