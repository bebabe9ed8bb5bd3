"""Analyses of states and runs: spectra, rigidity, density of states, shear statistics."""
