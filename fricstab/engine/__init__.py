"""The one DEM engine: space, particles, contacts and history, forces, integrators, Jacobian.

* :mod:`~fricstab.engine.system`: :class:`System` (particles, box, walls, the
  law and its parameters, applied forces, dashpots) and :class:`State`;
* :mod:`~fricstab.engine.contacts`: neighbour list, static pairs, analytic
  walls, the per-contact history store carried across rebuilds by key;
* :mod:`~fricstab.engine.passes`: the loops over contacts (forces, blocks,
  history increment and projection, the fused dynamics pass);
* :mod:`~fricstab.engine.jacobian`: the sparse system Jacobian ``dF/dq``;
* :mod:`~fricstab.engine.parallel`: the dynamics pass on threads, the same to
  the bit at every thread count (``set_threads``, ``fricstab --threads``);
* :mod:`~fricstab.engine.verlet`: velocity Verlet with drag and controllers;
* :mod:`~fricstab.engine.fire`: FIRE;
* :mod:`~fricstab.engine.newton`: Newton relaxation with the Jacobian.

Imports point one way: laws <- engine <- scenes <- protocols <- cli.
"""

from fricstab.engine.fire import FireParameters, fire
from fricstab.engine.jacobian import dof_labels, jacobian
from fricstab.engine.newton import NewtonResult, newton
from fricstab.engine.system import DRIVEN, FIXED, FREE, Material, State, System
from fricstab.engine.verlet import Controls, Run, run

__all__ = ["DRIVEN", "FIXED", "FREE", "Controls", "FireParameters", "Material", "NewtonResult",
           "Run", "State", "System", "dof_labels", "fire", "jacobian", "newton", "run"]
