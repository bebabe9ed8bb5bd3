"""Claims of section shear (see claims/__init__.py)."""

HEADING = 'Plane shear (Lee & Hurley)'
INTRO = ("The quick preset changes the paper's scene so that it runs in minutes (fewer disks, a larger inertial number, softer grains, a coarser output interval): its numbers compare with the paper in trend, not value.")

CLAIMS = []
