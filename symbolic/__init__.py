"""SymPy derivations of the contact laws and the generator of fricstab's kernels.

``symbolic.laws`` derives forces, torques, increment rules and Jacobian blocks
as pure functions returning SymPy expressions; ``symbolic.codegen`` prints
them as numba kernels into ``fricstab/generated`` (``python -m
symbolic.codegen [--check]``).  Nothing in ``fricstab`` imports this package.
"""
