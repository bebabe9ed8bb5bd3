"""A relaxed state of the plane-shear cell with the walls clamped (for its Jacobian).

After the servo compression (:func:`fricstab.protocols.shear_run.prepare`)
the wall rows are held where they are (their rows and columns of the
Jacobian are dropped: clamped) and the bulk relaxes in two stages:

1. FIRE (:func:`fricstab.engine.fire`, Ishima App. A.1; the histories follow
   the increment rule) until the largest force on a bulk degree of freedom
   falls below ``fire_tol`` f_0, with f_0 = 2 E* L0 / kappa the typical
   contact force of the cell (:func:`fricstab.scenes.shear.typical_overlap`);
2. a Newton polish (:func:`fricstab.engine.newton`, least squares: rattlers
   and free rotations are zero modes) to ``newton_tol`` f_0.

Why FIRE and not damped dynamics: with ``charan``'s law the stored
tangential displacement is a vector in the global frame that the increment
rule (Charan Eq. 2) does not rotate with the contact, so in a packing whose
contacts have rotated (the compression) it carries a normal component; under
a global drag the cell then creeps at a steady rate (max|F| ~1e-2 f_0 after
10^6 steps) instead of settling, while FIRE's velocity mixing reaches
1e-8 f_0 in ~10^5 iterations.  Reduced units throughout.
"""

import time

from fricstab.engine import FireParameters, fire, newton
from fricstab.errors import ConvergenceError

__all__ = ["relax_clamped"]


def relax_clamped(sim, fire_tol=1e-8, newton_tol=1e-10, max_iter=1_000_000, newton_iter=60):
    """Relax the bulk of a prepared :class:`~fricstab.protocols.shear_run.ShearRun` in place.

    FIRE steps scale with the cell's contact time: ``dt_ini = 0.01 t_c``,
    ``dt_max = 0.1 t_c``... in t0 = the reduced time unit (t_c ~ 0.7 t0 for
    r_min = L0 / 2).  Returns a dict of statistics (iterations, residuals in
    units of f_0, seconds); ConvergenceError when a stage misses its tolerance.
    """
    c, system, state = sim.cell, sim.system, sim.state
    f0 = 2.0 / c.params["kappa"]
    t0 = time.perf_counter()
    state.v[:] = 0.0
    params = FireParameters(dt_ini=0.01 * c.t_c, dt_max=0.1 * c.t_c)
    iterations, residual = fire(system, state, fire_tol * f0, max_iter, params)
    if not residual < fire_tol * f0:
        raise ConvergenceError(f"clamped relaxation: FIRE reached max|F| = {residual / f0:.3g} "
                               f"f_0 in {iterations} iterations (tol {fire_tol:g} f_0)")
    t1 = time.perf_counter()
    state.v[:] = 0.0
    res = newton(system, state, newton_tol * f0, max_iter=newton_iter, solver="lstsq",
                 max_step=0.01)
    return {"fire_iterations": int(iterations), "fire_residual_f0": float(residual / f0),
            "fire_seconds": t1 - t0, "newton_iterations": int(res.iterations),
            "newton_residual_f0": float(res.residual / f0), "newton_seconds": res.seconds,
            "contacts_gained": res.contacts_gained, "contacts_lost": res.contacts_lost}
