"""fricstab: a verified test-bed for the stability of frictional granular matter.

The contact-law kernels in :mod:`fricstab.generated` are written by
``python -m symbolic.codegen`` from the SymPy derivations in ``symbolic/``;
:mod:`fricstab.laws` is their registry and :mod:`fricstab.laws.verify` proves them.
fricstab never imports SymPy at run time.
"""

__version__ = "0.1.0"

__all__ = ["__version__"]
