"""Export a periodic state to LAMMPS: a data file and an input deck with the closest law.

:func:`write_lammps` writes, into a directory:

``data.lmp``
    ``atom_style sphere``, 2D, the periodic box ``[0, lx) x [0, ly)`` (a
    triclinic ``xy`` tilt for a Lees-Edwards offset: the image above is
    displaced by ``+xy`` in x, our ``state.shift`` folded into
    ``[-lx/2, lx/2)``), positions folded into the box, diameters, densities
    (LAMMPS turns ``atom_style sphere`` densities into masses with
    ``4/3 pi r^3`` even in 2D), velocities and angular velocities; atom types
    by radius where the law needs per-type-pair coefficients (ids 1..N in
    our particle order).
``in.lmp``
    ``units lj``, ``dimension 2``, the pair style with the mapped
    coefficients, ``fix nve/sphere disc`` (inertia ``m R^2 / 2``, our disks'),
    ``fix enforce2d``, ``compute pair/local`` + ``dump local`` of the contact
    forces (``contacts.dump``), ``run 0``.
``README.txt``
    The mapping, and what the export loses (below).

Laws (:data:`LAMMPS_LAWS`):

* ``ishima``: ``pair_style gran/hertz/history Kn Kt 0 0 1e4 0`` with
  ``Kn = kn / sqrt(R_eff)``, ``Kt = kt / sqrt(R_eff)``, ``R_eff = R_i R_j /
  (R_i + R_j)``; LAMMPS multiplies by ``sqrt(R_eff delta)``, so ``F_n = kn
  delta^(3/2)`` and ``F_t = -kt delta^(1/2) t``: exact, one sub-style per type
  pair through ``pair_style hybrid``.  ``xmu = 1e4`` (LAMMPS' maximum)
  stands for Ishima's missing Coulomb cap: exact while ``|F_t| < 1e4 F_n``.
* ``hertz``: the same with ``Kt = 0``, ``xmu = 0`` (frictionless).
* ``linear``: ``pair_style gran/hooke/history kn kt 0 0 mu 0``: ``F_n = kn
  delta``, ``F_t = -kt t`` capped at ``mu F_n`` by rescaling the history,
  no damping (``gamma_n = gamma_t = 0``, ``dampflag = 0``); one style for all
  pairs (Hooke has no radius factor).  Its shear history is our ``t`` (the
  tangential relative displacement, rotation included); LAMMPS also projects
  the stored shear onto the current tangent plane every step, ours keeps it
  as advanced, so the laws agree exactly in the normal force and at zero
  history, and differ by that projection once histories grow.
* ``charan`` with ``approximate=True``: ``gran/hertz/history Kn Kt 0 0 mu 0``
  as ``ishima`` with ``xmu = mu`` (:data:`APPROXIMATE`): the same normal force,
  the same tangential stiffness at zero history and the same cap ``mu F_n``,
  reached at the same ``|t| = t* = mu (kn/kt) delta``; in between charan's
  tangential force is larger by its factor ``1 + s - s^2`` (``s = |t|/t*``; at
  most 1.25, at ``s = 1/2``).  Step-0 forces are equal (zero history); a run
  differs once histories grow.  Without ``approximate`` it is refused, saying so.
* ``lee_hurley``: refused (:class:`~fricstab.errors.ParameterError` naming the
  closest LAMMPS law and why it differs: its 2D normal force has no LAMMPS form).

What is lost: contact histories.  A LAMMPS data file has no place for them
(LAMMPS keeps shear histories in binary restarts only), so a state with
nonzero histories exports its positions and velocities and LAMMPS starts
with zero shear history: its step-0 tangential forces are zero where ours
are not.  :func:`write_lammps` returns how many contacts carried history and
the largest generalized force they contribute (``README.txt`` says so too).
Angles are lost as well (``atom_style sphere`` stores none; no force
depends on them).  At zero history the step-0 forces and torques of the deck
equal ours to round-off (``tests/test_lammps_export.py``).
"""

from pathlib import Path

import numpy as np

from fricstab.errors import ParameterError

__all__ = ["APPROXIMATE", "LAMMPS_LAWS", "MAX_TYPES", "export_state_file", "write_lammps"]

#: Our law -> the LAMMPS pair style it is exported as (the module docstring has the mapping).
LAMMPS_LAWS = {"ishima": "gran/hertz/history", "hertz": "gran/hertz/history",
               "linear": "gran/hooke/history"}

#: Laws exported with ``approximate=True`` as the closest style (module docstring).
APPROXIMATE = {"charan": "gran/hertz/history"}

#: Most distinct radii of a per-type-pair export (MAX_TYPES (MAX_TYPES + 1) / 2 sub-styles).
MAX_TYPES = 8

XMU_MAX = 1.0e4     # LAMMPS' largest xmu: ishima's "no Coulomb cap"

_REFUSED = {
    "charan": "charan's smoothed Coulomb factor (1 + s - s^2) has no LAMMPS form; the closest "
              "is gran/hertz/history with xmu = mu (equal normal force, equal tangential "
              "force at zero history and at the cap, up to 25 % apart between): pass "
              "approximate=True to export it so",
    "lee_hurley": "lee_hurley's 2D Hertz-cylinder normal force pi E* delta / lam has no LAMMPS "
                  "form; the closest is pair_style granular hertz + tangential mindlin + "
                  "rolling sds (a 3D Hertz law, forces off by a per-contact factor)",
}

_FILES = ("data.lmp", "in.lmp", "README.txt")


def _style(law):
    """The LAMMPS pair style of ``law`` (exact or, for :data:`APPROXIMATE`, the closest)."""
    return LAMMPS_LAWS.get(law) or APPROXIMATE[law]


def _check(system, state, approximate=False):
    """ParameterError unless LAMMPS can take this system as exported here."""
    from fricstab.engine.system import check_system_state
    check_system_state(system, state)
    law = system.material.law
    if law in _REFUSED and not (approximate and law in APPROXIMATE):
        raise ParameterError(f"law {law} cannot be exported to LAMMPS: {_REFUSED[law]}")
    if law not in LAMMPS_LAWS and not (approximate and law in APPROXIMATE):
        raise ParameterError(f"law {law} cannot be exported to LAMMPS "
                             f"(exported: {', '.join(LAMMPS_LAWS)})")
    if not (system.lx > 0 and system.ly > 0):
        raise ParameterError("only a box periodic in x and y is exported to LAMMPS "
                             f"(lx = {system.lx:g}, ly = {system.ly:g})")
    if len(system.walls) or np.any(system.family != 0):
        raise ParameterError("walls and fixed or driven particles are not exported to LAMMPS")
    if np.any(system.external != 0) or np.any(system.damping != 0):
        raise ParameterError("applied forces and dashpots are not exported to LAMMPS")
    disc = 0.5 * system.mass * system.radius ** 2
    bad = np.flatnonzero(np.abs(system.inertia / disc - 1.0) > 1e-12)
    if bad.size:
        i = int(bad[0])
        raise ParameterError(f"particle {i} has inertia {system.inertia[i]:.17g}, LAMMPS' "
                             f"fix nve/sphere disc gives m R^2 / 2 = {disc[i]:.17g}")


def _types(system):
    """Atom types (N,) from 1 and the radius of each type; one type where Hooke needs none."""
    if system.material.law == "linear":
        return np.ones(system.n, int), np.array([system.radius.max()])
    radii, inverse = np.unique(system.radius, return_inverse=True)
    if len(radii) > MAX_TYPES:
        raise ParameterError(f"{len(radii)} distinct radii: law {system.material.law} needs "
                             f"one LAMMPS sub-style per pair of radii, at most {MAX_TYPES} "
                             "radii are exported")
    return inverse + 1, radii


def _folded(system, state):
    """Positions folded into the (tilted) box, and the tilt ``xy`` in ``[-lx/2, lx/2)``.

    Our image above is ``r + (shift, ly)``; shifting the offset by a multiple of
    ``lx`` changes no image, so ``xy = shift - lx round(shift/lx)``.
    """
    lx, ly = system.lx, system.ly
    xy = float(state.shift - lx * np.floor(state.shift / lx + 0.5))
    x, y = state.q[:, 0].copy(), state.q[:, 1].copy()
    k = np.floor(y / ly)
    y -= k * ly
    x -= k * xy
    x -= lx * np.floor(x / lx)
    x[x >= lx] -= lx        # a rounding to lx itself
    y[y >= ly] -= ly
    return np.column_stack([x, y]), xy


def _pair_lines(system, radii):
    """``pair_style`` and ``pair_coeff`` lines of the law (module docstring)."""
    law, p = system.material.law, system.material.params
    if law == "linear":
        return [f"pair_style gran/hooke/history {p['kn']:.17g} {p['kt']:.17g} 0.0 0.0 "
                f"{p['mu']:.17g} 0", "pair_coeff * *"]
    kt, xmu = {"ishima": (p.get("kt"), XMU_MAX), "charan": (p.get("kt"), p.get("mu"))}.get(
        law, (0.0, 0.0))
    pairs = [(a, b) for a in range(len(radii)) for b in range(a, len(radii))]
    styles, coeffs = [], []
    for m, (a, b) in enumerate(pairs, 1):
        s = 1.0 / np.sqrt(radii[a] * radii[b] / (radii[a] + radii[b]))
        styles.append(f"gran/hertz/history {p['kn'] * s:.17g} {kt * s:.17g} 0.0 0.0 "
                      f"{xmu:.17g} 0")
        tag = f" {m}" if len(pairs) > 1 else ""
        coeffs.append(f"pair_coeff {a + 1} {b + 1} gran/hertz/history{tag}")
    if len(pairs) == 1:
        return [f"pair_style {styles[0]}", "pair_coeff * *"]
    return ["pair_style hybrid " + " ".join(styles)] + coeffs


def _data(path, system, state, types, title):
    pos, xy = _folded(system, state)
    r = system.radius
    rho = system.mass / (4.0 / 3.0 * np.pi * r ** 3)
    omega = state.v[:, 2] / system.rscale
    lines = [title, "", f"{system.n} atoms", f"{types.max()} atom types",
             f"0.0 {system.lx:.17g} xlo xhi", f"0.0 {system.ly:.17g} ylo yhi",
             "-0.5 0.5 zlo zhi"]
    if xy != 0.0:
        lines.append(f"{xy:.17g} 0.0 0.0 xy xz yz")
    lines += ["", "Atoms # sphere", ""]
    lines += [f"{i + 1} {types[i]} {2 * r[i]:.17g} {rho[i]:.17g} {pos[i, 0]:.17g} "
              f"{pos[i, 1]:.17g} 0.0" for i in range(system.n)]
    lines += ["", "Velocities", ""]
    lines += [f"{i + 1} {state.v[i, 0]:.17g} {state.v[i, 1]:.17g} 0.0 0.0 0.0 {omega[i]:.17g}"
              for i in range(system.n)]
    Path(path).write_text("\n".join(lines) + "\n")
    return xy


def _deck(system, radii, dt, skin):
    law = system.material.law
    how = "" if law in LAMMPS_LAWS else " (the closest style, not the same law)"
    lines = [f"# fricstab state, law {law}: LAMMPS {_style(law)}{how} (README.txt)",
             "units lj", "dimension 2", "atom_style sphere", "boundary p p p", "newton on",
             "comm_modify vel yes", "read_data data.lmp"]
    lines += _pair_lines(system, radii)
    lines += [f"neighbor {skin:.17g} bin", "neigh_modify delay 0 every 1 check yes",
              "# disk inertia m R^2 / 2, as fricstab's", "fix nve all nve/sphere disc",
              "fix 2d all enforce2d"]
    lines += ([f"timestep {dt:.17g}"] if dt is not None
              else ["# timestep: LAMMPS' default (0.005); choose your own before a run"])
    lines += ["# touching pairs (sum of radii): ids, |F_n|, F_x F_y on i (normal part), "
              "tangential force on i (p1 p2)",
              "compute ids all property/local patom1 patom2 cutoff radius",
              "compute pf all pair/local force fx fy p1 p2 cutoff radius",
              "dump contacts all local 1 contacts.dump c_ids[1] c_ids[2] c_pf[1] c_pf[2] "
              "c_pf[3] c_pf[4] c_pf[5]", "dump_modify contacts format float %.17g",
              "thermo_style custom step atoms pe ke", "run 0"]
    return "\n".join(lines) + "\n"


def _history_loss(system, state):
    """Contacts with nonzero history, and max |F(history) - F(0)| over the generalized forces."""
    c = state.contacts
    carrying = int(np.count_nonzero(np.any(c.hist != 0, axis=1))) if c.hist.size else 0
    if not carrying:
        return 0, 0.0
    bare = state.copy()
    bare.contacts.hist[:] = 0.0
    diff = system.forces(state) - system.forces(bare)
    return carrying, float(np.abs(diff[:, :system.dof]).max())


def _readme(system, xy, carrying, lost):
    law = system.material.law
    text = [f"fricstab export of a {law} state to LAMMPS ({_style(law)}).",
            "Run: lmp -in in.lmp (from this directory); contacts.dump lists the touching "
            "pairs' forces at step 0.",
            "Mapping: see fricstab/io/lammps.py (docs/howto/lammps_export.md).",
            "Units: lj, i.e. the scene's own length, mass and time units.",
            "Inertia: fix nve/sphere disc, m R^2 / 2 (as fricstab's disks).",
            f"Lees-Edwards offset: triclinic tilt xy = {xy:.17g}.",
            "Contact histories are NOT exported: a LAMMPS data file has no place for them "
            "(LAMMPS keeps shear histories in restart files only), so LAMMPS starts with "
            "zero shear history."]
    if carrying:
        text.append(f"This state had {carrying} contacts with nonzero history; dropping them "
                    f"changes its generalized forces by up to {lost:.3e}.")
    else:
        text.append("This state had zero histories: LAMMPS' step-0 forces equal fricstab's.")
    if law == "linear":
        text.append("gran/hooke/history projects its shear history onto the tangent plane "
                    "every step; fricstab's linear law does not: trajectories differ once "
                    "histories grow.")
    if law == "charan":
        text.append("APPROXIMATE: charan has no LAMMPS form. gran/hertz/history with xmu = mu "
                    "has charan's normal force, its tangential stiffness at zero history and "
                    "its cap mu F_n, reached at the same |t| = t* = mu (kn/kt) delta; in "
                    "between charan's tangential force is larger by 1 + s - s^2 (s = |t|/t*), "
                    "up to 25 % at s = 1/2, and LAMMPS caps by rescaling its history. Step-0 "
                    "forces are equal (zero history); a run differs once histories grow.")
    if law == "ishima":
        text.append(f"xmu = {XMU_MAX:g} (LAMMPS' maximum) stands for Ishima's missing Coulomb "
                    "cap; LAMMPS also projects its shear history onto the tangent plane.")
    return "\n".join(text) + "\n"


def write_lammps(out_dir, system, state, dt=None, title=None, approximate=False):
    """Write ``data.lmp``, ``in.lmp`` and ``README.txt``: the state as a LAMMPS run.

    Histories are not exported (a data file cannot hold them): LAMMPS starts
    with zero shear history (module docstring); the return value says how much
    force that drops.

    Parameters
    ----------
    out_dir : path-like
        Directory (created if missing).
    system : System
        Periodic in x and y, free disks, law ``ishima``, ``hertz`` or ``linear``.
    state : State
        Positions (any images), velocities, Lees-Edwards offset.
    dt : float, optional
        Time step written into ``in.lmp`` (default: none, LAMMPS' own).
    title : str, optional
        First line of ``data.lmp``.
    approximate : bool
        Export a law without a LAMMPS form as the closest style
        (:data:`APPROXIMATE`: charan), saying how it differs in ``in.lmp`` and
        ``README.txt``; default False: refused.

    Returns
    -------
    dict
        ``files`` (paths), ``pair_style`` (the LAMMPS style), ``types`` (atom
        type per particle), ``tilt`` (the exported ``xy``), ``history_contacts``
        (contacts whose nonzero history was dropped) and ``history_force``
        (the largest generalized force they carried).

    Raises
    ------
    ParameterError
        A law LAMMPS has no form of (lee_hurley; charan without
        ``approximate``), walls, an open
        direction, fixed or driven particles, applied forces, dashpots, an
        inertia other than m R^2 / 2, more than :data:`MAX_TYPES` radii.
    """
    _check(system, state, approximate)
    if dt is not None and not (np.isfinite(dt) and dt > 0):
        raise ParameterError(f"dt must be a finite number > 0, got {dt!r}")
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    types, radii = _types(system)
    skin = system.skin if system.skin > 0 else 0.2 * float(system.radius.max())
    title = title or f"fricstab {system.material.law} state, N={system.n}"
    xy = _data(out / "data.lmp", system, state, types, title)
    (out / "in.lmp").write_text(_deck(system, radii, dt, skin))
    carrying, lost = _history_loss(system, state)
    (out / "README.txt").write_text(_readme(system, xy, carrying, lost))
    return {"files": [out / f for f in _FILES], "pair_style": _style(system.material.law),
            "approximate": system.material.law not in LAMMPS_LAWS,
            "types": types, "tilt": xy, "history_contacts": carrying, "history_force": lost}


def export_state_file(state_path, out_dir, dt=None, approximate=False):
    """:func:`write_lammps` of a ``state.npz`` (``fricstab SCENE jacobian``'s file).

    Parameters
    ----------
    state_path : path-like
        A ``state.npz`` of :func:`fricstab.io.jacobian_export.write_state_jacobian`.
    out_dir : path-like
        Directory for the LAMMPS files.
    dt : float, optional
        Time step written into ``in.lmp``.
    approximate : bool
        As :func:`write_lammps`.

    Returns
    -------
    dict
        As :func:`write_lammps`.
    """
    from fricstab.io.jacobian_export import system_from_state
    system, state = system_from_state(state_path)
    return write_lammps(out_dir, system, state, dt=dt, approximate=approximate)
