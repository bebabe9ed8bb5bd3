"""Messages that C libraries print on the process's standard streams, filtered.

SuperLU (``scipy.sparse.linalg.spsolve``) on some singular matrices calls BLAS
with a degenerate argument, and the BLAS error handler prints
``** On entry to DGEMV parameter number 2 had an illegal value`` (through C's
``printf``: file descriptor 1, buffered) before SciPy reports the singularity
(``MatrixRankWarning``).  Where the caller handles that singularity (the AQS
relaxation falls back to least squares), the lines only alarm;
:func:`drop_c_lines` removes them and writes everything else back.
"""

import contextlib
import ctypes
import os
import sys
import tempfile

__all__ = ["drop_c_lines"]

try:
    _LIBC = ctypes.CDLL(None)
except OSError:          # no C library to flush (not on a POSIX system)
    _LIBC = None


def _flush():
    for stream in (sys.stdout, sys.stderr):
        if stream is not None:
            stream.flush()
    if _LIBC is not None:
        _LIBC.fflush(None)       # C stdio's buffers: printf output not yet written


@contextlib.contextmanager
def drop_c_lines(marker=b"had an illegal value"):
    """Within the block, drop the lines containing ``marker`` (bytes) that anything writes
    to file descriptors 1 and 2; the other lines are written back to their descriptor, in
    order, when the block ends.  A stream without a file descriptor (captured by a test)
    is left as it is."""
    fds = []
    for stream in (sys.stdout, sys.stderr):
        try:
            fds.append(stream.fileno())
        except (AttributeError, OSError, ValueError):
            pass
    _flush()
    saved = [(fd, os.dup(fd), tempfile.TemporaryFile()) for fd in fds]
    for fd, _, tmp in saved:
        os.dup2(tmp.fileno(), fd)
    try:
        yield
    finally:
        _flush()
        for fd, keep, tmp in saved:
            os.dup2(keep, fd)
            os.close(keep)
            tmp.seek(0)
            lines = [x for x in tmp.read().splitlines(keepends=True) if marker not in x]
            tmp.close()
            if lines:
                os.write(fd, b"".join(lines))
