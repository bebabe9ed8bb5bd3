"""Run pytest in the job's own process and collect what each test showed.

A claim that a committed test shows runs that test here, in the process that
records it (never in a subprocess: the fingerprint of the record is the set
of modules this process imported, the test modules under ``tests/`` among
them).  :func:`run_tests` returns, per test id, the outcome and, for a
hypothesis test, how many generated examples passed, failed or were rejected
as invalid (hypothesis' own statistics).
"""

import os
import re

_COUNTS = re.compile(r"(\d+) passing, (\d+) failing, and (\d+) invalid")


class _Collector:
    """pytest plugin: outcome and hypothesis statistics per test id."""

    def __init__(self):
        self.tests = {}

    def pytest_runtest_logreport(self, report):
        rec = self.tests.setdefault(report.nodeid, {"outcome": "passed"})
        if report.outcome == "failed":
            rec["outcome"] = "failed"
        elif report.outcome == "skipped" and rec["outcome"] != "failed":
            rec["outcome"] = "skipped"

    def pytest_runtest_teardown(self, item):
        stats = getattr(item, "hypothesis_statistics", None)
        if stats:
            found = [tuple(int(x) for x in m.groups()) for m in _COUNTS.finditer(stats)]
            rec = self.tests.setdefault(item.nodeid, {"outcome": "passed"})
            rec["examples"] = {"passing": sum(f[0] for f in found),
                               "failing": sum(f[1] for f in found),
                               "invalid": sum(f[2] for f in found)}


def run_tests(args, env=None):
    """``pytest.main(args)`` in this process with ``env`` set for its duration; returns
    (exit status, {test id: {"outcome", "examples"?}}).  Paths are relative to the
    checkout; the cache provider is off so nothing is written beside the tests."""
    import pytest

    from .fingerprint import ROOT
    old = {k: os.environ.get(k) for k in (env or {})}
    os.environ.update(env or {})
    cwd = os.getcwd()
    collector = _Collector()
    try:
        os.chdir(ROOT)
        status = pytest.main(["-q", "-p", "no:cacheprovider", *args], plugins=[collector])
    finally:
        os.chdir(cwd)
        for k, v in old.items():
            if v is None:
                os.environ.pop(k, None)
            else:
                os.environ[k] = v
    return int(status), collector.tests


def summary(tests, select):
    """Counts of the tests whose id contains any of ``select``: passed, failed, skipped,
    and the ids that did not pass."""
    chosen = {k: v for k, v in tests.items() if any(s in k for s in select)}
    out = {"passed": 0, "failed": 0, "skipped": 0}
    for v in chosen.values():
        out[v["outcome"]] += 1
    out["not_passed"] = sorted(k for k, v in chosen.items() if v["outcome"] != "passed")
    return out


__all__ = ["run_tests", "summary"]
