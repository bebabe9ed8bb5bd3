"""Claims of section aqs (see claims/__init__.py)."""

HEADING = 'Complex pairs along quasistatic shear'
INTRO = ('`fricstab packing aqs`: athermal quasistatic shear with history, the dense spectrum of M^-1 K at every state, pair births bisected in strain.')

CLAIMS = []
