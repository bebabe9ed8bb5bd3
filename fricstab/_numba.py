"""The one place that sets numba options for fricstab kernels.

``kernel_jit`` compiles lazily with ``cache=True`` (compiled machine code is
kept in ``__pycache__`` between runs) and NumPy's error model (no Python
exception checks on division in the hot loops; the kernels guard their own
divisions).  Scalar contact kernels are compiled for at most two signatures:
float64 and, for complex-step verification, complex128.
"""

import numba

__all__ = ["kernel_jit"]

kernel_jit = numba.njit(cache=True, error_model="numpy")
