"""``fricstab packing jacobian|rigidity|dos|aqs --state DIR_OR_NPZ``: analyses of a state file.

The state is a ``state.npz`` (:func:`fricstab.io.jacobian_export.write_state_jacobian`:
``fricstab import``, ``fricstab packing jacobian``, an AQS event folder), or
the directory holding it.  A record beside it that lists it (``import.json``,
``jacobian.json``) is verified first (a changed file is refused, exit 2,
naming it); a ``state.npz`` without one is used with a one-line warning
(:func:`fricstab.io.imports.load.load_state`).  The law, its parameters, the
box (periodic, with its Lees-Edwards offset), walls and fixed particles come
from the file, in its units: ``--packing``, the make options, ``--kt``,
``--law``, ``--param`` and ``--scene`` are refused.  Rattlers (free particles
with ``Z <= --z-th`` touching contacts, iteratively; a fixed particle or a wall
counts as a neighbour and is never removed) are dropped first; the record says
how many.  Force tolerances (``--f-tol``) default to 1e-12 times the mean
contact force.

``rigidity`` and ``aqs`` need a periodic box without walls or fixed
particles (``rigidity`` a square one); ``dos`` and ``jacobian`` take any state
(fixed particles carry no dof; the two translations are dropped from the DOS
only where they are zero modes, a periodic box with every particle free).
Each writes what the packing route writes, the record's ``"packing"`` entry
replaced by ``"state"`` (source, sha256, record, law, law_params, n,
n_backbone, rattlers); ``jacobian`` also puts the spectrum of ``M^-1 K``
(:func:`fricstab.protocols.aqs.spectrum`; all of ``M^-1 K`` where the
translations are not zero modes), its complex pairs
(:func:`fricstab.protocols.aqs.pairs`) and the largest growth rate
(:func:`fricstab.analysis.spectrum.growth_rate`, ``max Im sqrt(-lambda)``)
into ``jacobian.json`` and prints them in one line.
"""

import math
from types import SimpleNamespace

import numpy as np

from fricstab.cli.packing_common import DEFAULTS, MODES_MAX_PARTICLES, Run, dry_run
from fricstab.errors import ParameterError

__all__ = ["REFUSED", "F_TOL_FACTOR", "run"]

#: Options that a --state run refuses: the state carries its packing, law and parameters.
REFUSED = (("packing", "--packing"), ("n", "--n"), ("phi", "--phi"), ("seed", "--seed"),
           ("dphi", "--dphi"), ("f_tol_compress", "--f-tol-compress"), ("kt", "--kt"),
           ("law", "--law"), ("param", "--param"), ("scene", "--scene"))
#: Default force tolerance of a --state run, times the state's mean contact force: the
#: relaxations' residual then shifts a stress by ~1e-12 relative, below the 1 % check and
#: above the round-off (~1e-16 x the contacts per particle) of a force sum.
F_TOL_FACTOR = 1e-12
UNITS_STATE = "the state file's units (law parameters as written in state.npz)"
_OUTPUTS = {"dos": ["dos.npz", "dos.png"], "aqs": ["aqs.png", "events"]}


def check_options(ns):
    """Refuse, in one line, an option that the state already decides."""
    for attr, flag in REFUSED:
        if getattr(ns, attr, None) not in (None, []):
            raise ParameterError(f"--state cannot be combined with {flag} (the state carries "
                                 "its packing, law and parameters)")


def _options(ns):
    """The run's own options, resolved against the packing defaults."""
    z_th = DEFAULTS["z_th"] if ns.z_th is None else ns.z_th
    if z_th < 0:
        raise ParameterError(f"--z-th must be an integer >= 0, got {z_th}")
    out = {"z_th": z_th, "route": getattr(ns, "route", None) or DEFAULTS["route"]}
    if getattr(ns, "bins", None) is not None and ns.bins < 1:
        raise ParameterError(f"--bins must be an integer >= 1, got {ns.bins}")
    out["bins"] = getattr(ns, "bins", None) or DEFAULTS["bins"]
    if ns.packing_command == "rigidity":
        out["dgamma"] = DEFAULTS["dgamma"] if ns.dgamma is None else ns.dgamma
    if ns.f_tol is not None and not (math.isfinite(ns.f_tol) and ns.f_tol > 0):
        raise ParameterError(f"--f-tol must be a finite number > 0, got {ns.f_tol!r}")
    return out


def _needs_bulk(system, command):
    """rigidity and aqs: a periodic box, no walls, every particle free (one line why not)."""
    why = None
    if not (system.lx > 0 and system.ly > 0):
        why = "the state's box is not periodic in x and y"
    elif len(system.walls):
        why = f"the state has {len(system.walls)} wall(s)"
    elif not np.all(system.free):
        why = f"the state has {int(np.sum(~system.free))} fixed or driven particle(s)"
    elif command == "rigidity" and system.lx != system.ly:
        why = f"the state's box is not square ({system.lx:g} x {system.ly:g})"
    if why:
        raise ParameterError(f"--state: packing {command} needs a periodic box without walls "
                             f"or fixed particles: {why}; use dos or jacobian")


def bulk(system):
    """Whether the two translations are zero modes: periodic in x and y, every particle free."""
    return bool(system.lx > 0 and system.ly > 0 and not len(system.walls)
                and np.all(system.free))


def default_f_tol(system, state):
    """``F_TOL_FACTOR`` x the mean magnitude of the contact forces that carry force."""
    from fricstab.io.imports.engine_check import equilibrium
    mean = equilibrium(system, state)["mean_contact_force"]
    if not mean > 0:
        raise ParameterError("--state: no contact carries force; give --f-tol")
    return F_TOL_FACTOR * mean


def _run_of(material):
    """The one run of a state: named ``kt_<kt>`` for a law with kt (as a scan's), else the law."""
    kt = material.params.get("kt")
    if kt is None:
        return Run(material.law, None, material)
    return Run(f"kt_{float(kt):g}", float(kt), material)


def _summary(loaded):
    s = loaded.system
    return {"n": loaded.n_total, "phi": loaded.phi, "seed": None,
            "box": float(s.lx) if s.lx == s.ly else [float(s.lx), float(s.ly)],
            "le_offset": float(loaded.state.shift), "n_backbone": int(s.n),
            "rattlers": int(loaded.rattlers), "backbone_rattler_force": loaded.rattler_force}


def _open(ns, command, fp_extra=None, resume=False):
    """Load and check the state and --out before anything is written.

    Returns ``(loaded, rd, found, params, fingerprint)``.
    """
    from fricstab.cli.packing_source import conflicts, refuse
    from fricstab.io.imports.load import describe, load_state
    from fricstab.io.results import ResultDir
    check_options(ns)
    opts = _options(ns)
    loaded = load_state(ns.state, z_th=opts["z_th"], details=True)
    if command in ("rigidity", "aqs"):
        _needs_bulk(loaded.system, command)
    mat = loaded.system.material
    f_tol = ns.f_tol if ns.f_tol is not None else default_f_tol(loaded.system, loaded.state)
    params = {**opts, "f_tol": f_tol, "law": mat.law,
              "law_params": {k: float(v) for k, v in dict(mat.params).items()}}
    fp = {**params, **(fp_extra or {}), "state_sha256": loaded.sha256}
    loaded.entry = describe(loaded)
    if resume:
        if ns.force:
            raise ParameterError("--resume and --force exclude each other")
        return loaded, ResultDir(ns.out, command, resume=True, fingerprint=fp), [], params, fp
    outputs = _OUTPUTS.get(command, [])
    if command == "rigidity":
        outputs = ["rigidity.png", _run_of(mat).name]
    elif command == "jacobian":
        from fricstab.io.jacobian_export import FILES
        outputs = list(FILES)
    rd = ResultDir(ns.out, command, force=ns.force, outputs=outputs, fingerprint=fp)
    found = conflicts(rd.path, command, sha=loaded.sha256)
    if not ns.force:
        refuse(rd.path, found, f"this run uses the state {loaded.source}")
    return loaded, rd, found, params, fp


def _start(rd, found):
    from fricstab.cli.packing_source import remove
    rd.create()
    remove(rd.path, found, "made from another packing or state than this run's")
    return rd


def _head(loaded):
    s = loaded.system
    return f"state N = {loaded.n_total} (backbone {s.n}), box {s.lx:.6g} x {s.ly:.6g}"


# ------------------------------------------------------------------ the commands

def rigidity(ns, argv):
    """``--state`` rigidity: rigidity.json, rigidity.png, the run's folder."""
    from fricstab.cli import budget
    from fricstab.cli.packing_rigidity import conclude, measure
    loaded, rd, found, params, _ = _open(ns, "rigidity", {"modes": ns.modes})
    system, state = loaded.system, loaded.state
    modes = ns.modes if ns.modes is not None else system.n <= MODES_MAX_PARTICLES
    run = _run_of(system.material)
    estimate = budget.packing("packing rigidity --modes", None, {"n": system.n}, 1,
                              route=params["route"], dry_run=ns.dry_run) if modes else None
    if ns.dry_run:
        return dry_run({**params, "state": loaded.entry}, [run], estimate)
    _start(rd, found)
    entry, first = measure(rd, SimpleNamespace(box=system.lx, n=system.n), run, system, state,
                           modes, params, None)
    doc = {"state": loaded.entry, **_summary(loaded), "units": UNITS_STATE}
    return conclude(rd, doc, [entry], first, {**params, "modes": modes}, None, argv,
                    _head(loaded), params)


def ishima_jacobian(system, state):
    """``J = -C K C`` over the free dof (Ishima's coordinates), as linear_response builds it."""
    import scipy.sparse as sps

    from fricstab.analysis.rigidity import ishima_scale
    from fricstab.engine import jacobian
    d = np.ones((system.n, system.dof))
    if system.dof == 3:
        d[:, 2] = 1.0 / ishima_scale(system)
    d = d[system.free].ravel()
    k = jacobian(system, state)[1]
    return -(sps.diags(d) @ k @ sps.diags(d)).tocsr()


def dos(ns, argv):
    """``--state`` dos: dos.json, dos.npz, dos.png."""
    from fricstab.cli import budget
    from fricstab.cli.packing_dos import conclude, spectrum_of
    loaded, rd, found, params, _ = _open(ns, "dos")
    system, state = loaded.system, loaded.state
    run = _run_of(system.material)
    estimate = budget.packing("packing dos", None, {"n": system.n}, 1, route=params["route"],
                              dry_run=ns.dry_run)
    if ns.dry_run:
        return dry_run({**params, "state": loaded.entry}, [run], estimate)
    _start(rd, found)
    with rd.stage("spectrum"):
        spectra = [spectrum_of(run, ishima_jacobian(system, state), params["route"], None,
                               n_drop=2 if bulk(system) else 0)]
    doc = {"state": loaded.entry, **_summary(loaded), "units": UNITS_STATE,
           "translations_dropped": 2 if bulk(system) else 0}
    return conclude(rd, doc, spectra, [run], loaded.n_total, params, params, None, argv,
                    f"{_head(loaded)}, law")


def mk_spectrum(system, state):
    """Eigenvalues of M^-1 K (translations deflated where they are zero modes), sorted; K."""
    import scipy.linalg

    from fricstab.engine import jacobian
    from fricstab.protocols.aqs import spectrum
    if bulk(system):
        return spectrum(system, state)
    _, k = jacobian(system, state)
    gm = system.gmass[system.free, :system.dof].ravel()
    w = scipy.linalg.eigvals(k.toarray() / gm[:, None])
    return w[np.argsort(w.real, kind="stable")], k


def jacobian(ns, argv):
    """``--state`` jacobian: state.npz, jacobian.npz, dofs.json, mass.npy, jacobian.json."""
    from fricstab.analysis.spectrum import growth_rate
    from fricstab.cli import budget
    from fricstab.cli.packing_make import write_jacobian
    from fricstab.protocols.aqs import pairs
    loaded, rd, found, params, _ = _open(ns, "jacobian")
    system, state = loaded.system, loaded.state
    estimate = budget.packing("packing jacobian --state (spectrum)", None, {"n": system.n}, 1,
                              vectors=False, dry_run=ns.dry_run)
    if ns.dry_run:
        return dry_run({**params, "state": loaded.entry}, [_run_of(system.material)], estimate)
    _start(rd, found)
    extra = {"scene": "a state read with --state (its box, walls and fixed particles)",
             "backbone": {"n_total": loaded.n_total, "n_backbone": system.n,
                          "z_th": params["z_th"],
                          "keep": "state.npz key 'keep': indices of the rows in the source"}}
    f, k = write_jacobian(rd, system, state, extra, {"keep": loaded.keep}, units={})
    with rd.stage("spectrum"):
        w, _ = mk_spectrum(system, state)
    p = pairs(w)
    g = growth_rate(w)
    doc = {"state": loaded.entry, **_summary(loaded), "law": system.material.law,
           "law_params": params["law_params"], "dof_per_particle": system.dof,
           "shape": list(k.shape), "nnz": int(k.nnz),
           "max_force": float(np.abs(f).max()) if f.size else 0.0,
           "spectrum": {"matrix": "M^-1 K, K = dF/dq (stable modes: lambda < 0)"
                        + (", the two translations deflated" if bulk(system) else ""),
                        "eigenvalues_real": w.real, "eigenvalues_imag": w.imag,
                        "complex_pairs": len(p), "pairs_real": p.real, "pairs_imag": p.imag,
                        "growth_rate": g, "growth_rate_rule": "max Im sqrt(-lambda)",
                        "largest_real": float(w.real.max()) if w.size else None},
           "units": UNITS_STATE}
    rd.finish(doc, parameters=params, argv=argv)
    print(f"{_head(loaded)}, law {system.material.law}: max |F| = {doc['max_force']:.1e}, "
          f"K {k.shape[0]} x {k.shape[1]} ({k.nnz} nonzeros); M^-1 K: {w.size} eigenvalues, "
          f"{len(p)} complex pairs, largest growth rate {g:.6g}")
    print(f"wrote {rd.path}/state.npz, jacobian.npz, dofs.json, mass.npy, jacobian.json")
    return 0


def aqs(ns, argv):
    """``--state`` aqs: aqs.json, aqs.png, events/birth_<k>_{lo,hi}/."""
    from fricstab.cli import budget
    from fricstab.cli.packing_aqs import _check_resumable, path_options, shear
    from fricstab.io import rundir
    from fricstab.io.checkpoint import Checkpointer
    window = path_options(ns)
    fp_extra = {"strain": ns.strain, "dgamma": ns.dgamma, "tol": ns.tol,
                "drop_threshold": ns.drop_threshold, "window": window}
    loaded, rd, found, params, fp = _open(ns, "aqs", fp_extra, resume=ns.resume)
    system, state = loaded.system, loaded.state
    n_steps = int(np.floor(ns.strain / ns.dgamma + 1e-9))
    estimate = budget.packing("packing aqs", None, {"n": system.n}, n_steps, vectors=False,
                              dry_run=ns.dry_run)
    if ns.dry_run:
        return dry_run({**params, **fp_extra, "state": loaded.entry},
                       [_run_of(system.material)], estimate)
    ck = Checkpointer(rd.path / "checkpoints", fp)
    last = None
    if ns.resume:
        if not rundir.journal_path(rd.path, "aqs").is_file():
            raise ParameterError(f"--resume: nothing to resume in {rd.path} (no interrupted "
                                 "aqs run there); rerun without --resume")
        last = ck.latest(clean=False)
        if last is not None:
            _check_resumable(rd.path, ck, last, n_steps)
    _start(rd, found)
    extra = {"scene": "a state read with --state, sheared (AQS)",
             "backbone": {"n_total": loaded.n_total, "n_backbone": system.n,
                          "z_th": params["z_th"]}}
    doc = {"state": loaded.entry, **_summary(loaded), "law": system.material.law,
           "law_params": params["law_params"], "dof_per_particle": system.dof,
           "friction": None, "units": UNITS_STATE}
    return shear(ns, rd, system, state, params["f_tol"], window, (ck, last), extra, doc,
                 ({**params, **fp_extra}, None, argv),
                 f"{_head(loaded)}, law {system.material.law}")


def run(ns, argv):
    """Dispatch ``fricstab packing COMMAND --state ...`` (make has no --state)."""
    commands = {"rigidity": rigidity, "dos": dos, "jacobian": jacobian, "aqs": aqs}
    return commands[ns.packing_command](ns, argv)
