"""Claims of section chain (see claims/__init__.py)."""

HEADING = 'Chain of disks on a substrate (Charan et al.)'
INTRO = ("Charan's chain (`ChainScene()` defaults); time in the paper's unit unless stated.")

CLAIMS = []
