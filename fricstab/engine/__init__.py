"""The one DEM engine: space, particles, contacts and history, forces, integrators, Jacobian."""
