"""SIGINT and SIGTERM as a flag that long runs check between chunks.

A signal that arrives while numba code runs cannot raise there: Python runs
its handler when the compiled call returns, and an exception raised by a
handler in the middle of it surfaces as ``SystemError``.  Inside
:func:`interruptible`, the handlers only record the signal; a protocol calls
:func:`check` between chunks (after saving its checkpoint, if any), which
raises :class:`Interrupted`.  The command line maps it to exit status 130
(SIGINT, Ctrl-C) or 143 (SIGTERM, what a batch system sends before SIGKILL),
the conventions of the shells (128 + signal number).

A second signal of the same kind while one is pending stops at once (the
user insists): the default action, with the last checkpoint on disk.
"""

import contextlib
import signal
import threading

__all__ = ["EXIT_SIGINT", "EXIT_SIGTERM", "Interrupted", "check", "interruptible", "pending"]

EXIT_SIGINT, EXIT_SIGTERM = 130, 143
_pending = []


class Interrupted(Exception):
    """A run stopped on SIGINT or SIGTERM at a safe point (``exit_code`` 130 or 143)."""

    def __init__(self, signum, where="", step=None):
        name = "SIGTERM" if signum == signal.SIGTERM else "SIGINT"
        super().__init__(f"interrupted by {name}{where}")
        self.signum = signum
        self.step = step   # the step of the interrupted call, where the caller counts steps
        self.exit_code = EXIT_SIGTERM if signum == signal.SIGTERM else EXIT_SIGINT


def pending():
    """The signal received and not yet acted upon, or None."""
    return _pending[0] if _pending else None


def check(where="", step=None):
    """Raise :class:`Interrupted` if a signal arrived (call between chunks of work)."""
    if _pending:
        raise Interrupted(_pending[0], where, step)


def _handler(signum, frame):
    if signum in _pending:  # the second one: stop now
        signal.signal(signum, signal.SIG_DFL)
        signal.raise_signal(signum)
    _pending.append(signum)


@contextlib.contextmanager
def interruptible():
    """Record SIGINT/SIGTERM instead of raising (main thread only; elsewhere a no-op)."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    old = {s: signal.getsignal(s) for s in (signal.SIGINT, signal.SIGTERM)}
    _pending.clear()
    try:
        for s in old:
            signal.signal(s, _handler)
        yield
    finally:
        for s, h in old.items():
            signal.signal(s, h)
        _pending.clear()
