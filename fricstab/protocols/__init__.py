"""Protocols: what is done to a scene (ramps, relaxation, dynamics, strain, shear)."""
