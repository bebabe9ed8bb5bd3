"""Claims of section packing (see claims/__init__.py)."""

HEADING = 'Frictional packings (Ishima et al.)'
INTRO = ('Units d = 1, k_N = 1, m = 1 (G in k_N d^(1/2), omega in 1/t0). Packings from `make_packing` defaults, rattlers (Z <= 2) removed.')

CLAIMS = []
