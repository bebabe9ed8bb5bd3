"""System-level proof of the assembled Jacobian: a reference assembly in plain Python.

The engine assembles ``K = dF/dq`` of a whole scene from per-contact blocks
(each proven on its own by ``fricstab verify``).  What is left to prove is the
assembly: images and the Lees-Edwards offset, walls and their frames, the
generalized coordinates, clamped particles, the sign and the history carried
by the increment rule.  This module recomputes the force function of a whole
system independently of the engine's loops, by calling the verified scalar
kernels ``<law>_force`` contact by contact with complex128 arguments, and
differentiates it:

* complex step: ``K[:, k] = Im F(q + i h e_k, h_c + i h A_c e_k) / h`` with
  ``h = 1e-60 L``: exact to round-off (the kernels are analytic where they are
  evaluated; through a cap they follow the sliding branch, as the blocks do).
  Its truncation is ``O((h/delta)^2)`` relative for a Hertz ``delta^(3/2)``:
  with ``h = 1e-20 L`` an overlap at round-off level (``delta = 9e-17 R``, found
  by the thorough proof run of 2026-11-27, hertz chain) gave 5e-10 of max|K|;
  at ``1e-60 L`` it is below 1e-40 for any overlap above 1e-40 R, and nothing
  underflows (Im F is max|K| h, far above the smallest double, 2e-308);
* central differences of the engine's own force function, the histories
  advanced by ``A_c (+-h e_k)``: truncation ``O(h^2)`` plus round-off.

``A_c`` is the contact's increment rule at the base configuration (the
generated ``<law>_rate``, itself verified against hand-written rules).
"""


import numpy as np

from fricstab.engine.jacobian import jacobian
from fricstab.laws import get_law, vector_form

__all__ = ["WorstErrors", "complex_step_jacobian", "central_jacobian", "free_dofs",
           "reference_forces", "translation_residual"]

GEOMETRY = {"dx", "dy", "Ri", "Rj", "y", "R"}


def free_dofs(system, free_only=True):
    """(particle, component) of each Jacobian column, in the engine's order."""
    keep = np.flatnonzero(system.family == 0) if free_only else np.arange(system.n)
    return [(int(i), a) for i in keep for a in range(system.dof)]


def _call(law, geometry, params, hist, dtype):
    """One contact's generalized forces from the scalar kernel, args by name."""
    values = dict(geometry)
    values.update(params)
    values.update({name: hist[k] for k, name in enumerate(law.history)})
    f = np.zeros(len(law.outputs), dtype=dtype)
    law.force(*(dtype(values[name]) for name in law.inputs), f)
    return f


def _params(system, wall):
    info = get_law(system.material.law)
    names = list(info.params)
    values = dict(zip(names, system._p))
    if wall:
        wall_info = info.wall_form()
        values = dict(zip(wall_info.params, system._pw))
        return wall_info, values
    return info, values


def reference_forces(system, state, dq=None, dh=None, dtype=float):
    """Generalized forces (N, 3) of ``state`` moved by ``dq`` with histories ``+ dh``.

    ``dq`` (N, 3) and ``dh`` (K, H) may be complex.  Applied forces included.
    """
    c = state.contacts
    q = state.q.astype(dtype) + (0 if dq is None else dq)
    hist = c.hist.astype(dtype) + (0 if dh is None else dh)
    f = system.external.astype(dtype).copy()
    pair_law, pair_params = _params(system, wall=False)
    wall_law, wall_params = _params(system, wall=True) if len(system.walls) else (None, None)
    dof = system.dof
    for k in range(c.n):
        i, j = int(c.i[k]), int(c.j[k])
        if j >= 0:
            dx = ((q[i, 0] - q[j, 0]) - c.k[k] * state.shift) - c.m[k] * system.lx
            dy = (q[i, 1] - q[j, 1]) - c.k[k] * system.ly
            geo = {"dx": dx, "dy": dy, "Ri": system.radius[i], "Rj": system.radius[j]}
            fc = _call(pair_law, geo, pair_params, hist[k], dtype)
            f[i, :dof] += fc[:dof]
            f[j, :dof] += fc[dof:]
        else:
            y0, d = system.walls[-1 - j]
            geo = {"y": (q[i, 1] - y0) * d, "R": system.radius[i]}
            fc = _call(wall_law, geo, wall_params, hist[k], dtype)
            s = np.array([d, d, 1.0][:dof])
            f[i, :dof] += s * fc[:dof]
    return f


def _increments(system, state, column):
    """Per-contact history change for a unit generalized displacement of one dof."""
    from fricstab.engine import passes
    c = state.contacts
    dh = np.zeros_like(c.hist)
    dq = np.zeros((system.n, 3))
    i, a = column
    dq[i, a] = 1.0
    passes.increment_pass(system.law_id, system._p, system._pw, system.walls, state.q,
                          system.radius, float(system.lx), float(system.ly),
                          float(state.shift), c.i, c.j, c.m, c.k, dh, dq, system.dof,
                          np.zeros((6, 6)))
    return dq, dh


#: Relative move of a history towards the side of its cap the engine's kernel put
#: it on (see :func:`_on_engine_branch`).
BRANCH_NUDGE = 1e-12


def _on_engine_branch(system, state):
    """Histories moved by ``BRANCH_NUDGE`` (relative) to the engine's side of their caps.

    A history exactly on its cap (the engine's projection puts it there to the
    bit) takes the slide branch (``>=``), where the block jumps by design.  The
    reference's scalar kernel computes the cap along another path, which at
    overlaps near 1e-12 R can round the same cap an ulp or more apart, and
    then takes the other branch (found by hypothesis: lee_hurley in the shear
    cell, overlap 1.05e-12 R, ft on its cap).  So the reference histories are
    moved outwards by 1e-12 where the engine flags the contact as sliding and
    inwards elsewhere: within a branch the forces and the block depend on the
    history's size only through terms of relative size 1e-12, far below the
    1e-10 bound, and the reference is differentiated on the engine's branch.
    Flags (:func:`fricstab.engine.passes.project_pass`): bit 1 the tangential
    history, bit 2 the rolling history.  lee_hurley's block jumps at a cap, and
    linear's at its circle |t| = t* (its vector history moves as a whole).
    """
    hist = state.contacts.hist.copy()
    law = vector_form(system.material.law)  # a _fi law has its vector law's caps
    if law not in ("lee_hurley", "linear"):
        return hist   # charan's smoothed Coulomb law is C1 at t*, ishima and hertz have no cap
    s = state.copy()
    system.project(s)
    flag = s.contacts.flag.astype(int)
    if law == "linear":
        # project flags |t| >= t* (1 - 8 eps), where the kernels slide (symbolic/uniform.py
        # ON_CIRCLE; a wall history 1 - 1e-16 of t* at an overlap 5e-13 R, found by
        # hypothesis, slides): the vector history moves as a whole
        slide = (flag & 1) != 0
        return hist * np.where(slide, 1.0 + BRANCH_NUDGE, 1.0 - BRANCH_NUDGE)[:, None]
    for b, bit in enumerate((1, 2)):
        slide = (flag & bit) != 0
        hist[:, b] *= np.where(slide, 1.0 + BRANCH_NUDGE, 1.0 - BRANCH_NUDGE)
    return hist


def complex_step_jacobian(system, state, scale, free_only=True):
    """Dense ``dF/dq`` by complex step of :func:`reference_forces` (step 1e-60 scale),
    its histories on the engine's side of their caps (:func:`_on_engine_branch`)."""
    cols = free_dofs(system, free_only)
    rows = cols
    h = 1e-60 * scale   # module doc: an overlap at round-off level needs h << delta
    out = np.zeros((len(rows), len(cols)))
    nudged = state.copy()
    nudged.contacts.hist[:] = _on_engine_branch(system, state)
    for b, col in enumerate(cols):
        dq, dh = _increments(system, state, col)
        f = reference_forces(system, nudged, 1j * h * dq, 1j * h * dh, dtype=complex)
        out[:, b] = [f[i, a].imag / h for i, a in rows]
    return out


def central_jacobian(system, state, h, free_only=True):
    """Dense ``dF/dq`` by central differences of the engine's forces (step ``h``)."""
    cols = free_dofs(system, free_only)
    out = np.zeros((len(cols), len(cols)))
    for b, col in enumerate(cols):
        dq, dh = _increments(system, state, col)
        fs = []
        for sign in (1.0, -1.0):
            s = state.copy()
            s.q += sign * h * dq
            s.contacts.hist += sign * h * dh
            fs.append(system.forces(s))
        d = (fs[0] - fs[1]) / (2 * h)
        out[:, b] = [d[i, a] for i, a in cols]
    return out


def engine_jacobian(system, state, free_only=True):
    """The engine's assembled Jacobian, dense."""
    return jacobian(system, state, free_only)[1].toarray()


def translation_residual(system, state):
    """Largest ``|K e| / max|K|`` over the x and y translations ``e``, in eps (the
    full Jacobian, every particle free; a periodic scene has them as zero modes)."""
    full = engine_jacobian(system, state, free_only=False)
    worst = 0.0
    for axis in (0, 1):
        e = np.zeros(full.shape[0])
        e[axis::system.dof] = 1.0
        worst = max(worst, np.abs(full @ e).max() / np.abs(full).max())
    return worst / float(np.finfo(float).eps)


class WorstErrors:
    """The worst errors a proof module met, per law, for validation/RESULTS.md.

    ``record(law, complex_step=..., central=..., ...)`` keeps the maximum of
    each error (relative to max |K|; ``central_over_bound`` is the largest
    ratio of a central-difference error to its error model; ``zero_mode`` the
    largest ``|K e| / max|K|`` of a translation, in eps).  A module's last test
    calls :meth:`report`, which prints one line per law (``pytest -s``).
    """

    KEYS = ("complex_step", "central", "central_over_bound", "zero_mode")

    def __init__(self, laws):
        self.by_law = {law: dict.fromkeys(self.KEYS, 0.0) | {"cases": 0} for law in laws}

    def record(self, law, **errors):
        w = self.by_law[law]
        w["cases"] += 1
        for key, value in errors.items():
            w[key] = max(w[key], float(value))

    def lines(self):
        return [f"{law:10s} cases {w['cases']:4d}  complex step {w['complex_step']:.1e}  "
                f"central {w['central']:.1e} (error / model <= {w['central_over_bound']:.2f})"
                + (f"  translations {w['zero_mode']:.1f} eps" if w["zero_mode"] else "")
                for law, w in self.by_law.items()]

    def report(self, scene, capsys):
        with capsys.disabled():
            print(f"\n{scene}: worst errors relative to max|K|:\n  " + "\n  ".join(self.lines()))
        assert all(w["complex_step"] <= 1e-10 for w in self.by_law.values()), self.lines()
