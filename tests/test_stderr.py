"""fricstab._stderr.drop_c_lines: BLAS's "illegal value" lines dropped, everything else kept."""

import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

SCRIPT = r'''
import ctypes, sys
sys.path.insert(0, sys.argv[1])
from fricstab._stderr import drop_c_lines
libc = ctypes.CDLL(None)
print("before", flush=True)
with drop_c_lines():
    libc.printf(b" ** On entry to DGEMV  parameter number  2 had an illegal value\n")
    libc.printf(b"kept C line\n")
    print("kept python line")
    print("kept stderr line", file=sys.stderr)
print("after")
'''


def test_the_blas_message_is_dropped_and_the_rest_kept_in_order():
    # a child process: the filter works on file descriptors, which pytest captures itself;
    # stdout a pipe, so C's printf is buffered (the filter flushes it)
    r = subprocess.run([sys.executable, "-c", SCRIPT, str(ROOT)], capture_output=True,
                       timeout=60)
    assert r.returncode == 0, r.stderr
    assert r.stdout == b"before\nkept C line\nkept python line\nafter\n"
    assert r.stderr == b"kept stderr line\n"
