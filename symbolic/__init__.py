"""SymPy derivations of the contact laws and the generator of fricstab's kernels.

``symbolic.laws`` derives forces, torques, increment rules and Jacobian blocks
as pure functions returning SymPy expressions (``symbolic.geometry``: the chain
rule over geometric intermediates); ``symbolic.codegen`` prints them as numba
kernels into ``fricstab/generated`` (``python -m symbolic.codegen [--check]``),
with the uniform kernels and the dispatch module from ``symbolic.uniform`` and
the expression printer ``symbolic.printing``.  Nothing in ``fricstab`` imports
this package.
"""
