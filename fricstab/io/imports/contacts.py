"""From an imported packing to our engine: :func:`to_engine` (System, State and a Report).

An :class:`~fricstab.io.imports.ImportedState` (the file's units, the file's
contact list) becomes a :class:`~fricstab.engine.System` under one of our
laws and a :class:`~fricstab.engine.State` whose contacts carry the law's
histories:

* **units**: the caller states how large the file's length, mass and force
  units are in the law's units (``units={"length": L, "mass": M, "force":
  F}``, default 1 each); nothing is guessed, the mapping goes into the report;
* **particles**: radius, mass (the file's, or ``density * pi R^2``),
  inertia ``m R^2 / 2`` unless given, fixed particles as family 1
  (:data:`~fricstab.engine.FIXED`), the periodic box and its Lees-Edwards
  offset; positions are taken relative to the file's ``origin``;
* **contacts**: each listed pair at the image that makes it touch (the
  nearest); a listed pair that does not overlap, or joins two fixed
  particles, is dropped and counted; a touching pair the file did not list is
  added with zero history and counted;
* **histories** (our pair history is that of i relative to j, lab frame): the
  file's where it has one (``history`` columns, in the law's history units
  times ``units``: length for ``ishima``, ``linear``, ``charan``; force and
  moment ``(ft, mr)`` for ``lee_hurley``), else the law's inverse of the
  tangential force on i (:func:`history_from_force`).  A contact at the
  Coulomb limit (``|F_t| >= mu F_n (1 - 1e-9)``) is flagged: its history is
  not unique, the one on the cap is stored;
* **check**: the force of our law at the imported geometry and history
  against the file's (:func:`fricstab.io.imports.engine_check.force_mismatch`),
  and the equilibrium residual, into the :class:`Report`.

``hertz`` has no history: a file with a tangential force beyond round-off is
refused (:class:`~fricstab.errors.ParameterError` naming ``file:line``).
"""

from dataclasses import dataclass, field

import numpy as np

from fricstab.engine import FIXED, FREE, Material, System
from fricstab.engine.contacts import contact_keys
from fricstab.errors import ParameterError
from fricstab.io.imports.state import ImportedState, contact_where

__all__ = ["CAP", "Report", "charan_s", "history_from_force", "to_engine"]

#: A tangential force within this fraction of its Coulomb cap is "at the cap" (flagged).
CAP = 1e-9
#: Relative size of a tangential force that ``hertz`` still calls round-off (of |F_n|).
ROUND_OFF = 1e-9


@dataclass
class Report:
    """What :func:`to_engine` did and found (``as_dict`` is ``import.json``).

    ``units``: the mapping ``{quantity: {"file": name, "scale": factor}}``;
    ``counts``: contacts listed, kept, dropped (apart, fixed pairs), added;
    ``history_source``: ``"file"``, ``"force"`` or ``"none"``;
    ``flagged``: contacts whose history is not unique (at a cap), each
    ``{"contact", "where", "cap"}``; ``mismatch``: the worst relative force
    mismatch and its contact; ``residual``: the equilibrium residual;
    ``relax``: filled by :func:`~fricstab.io.imports.engine_check.relax`.
    """

    law: str
    units: dict
    counts: dict
    history_source: str
    flagged: list = field(default_factory=list)
    dropped: list = field(default_factory=list)
    mismatch: dict = field(default_factory=dict)
    residual: dict = field(default_factory=dict)
    relax: dict = field(default_factory=dict)
    origin: tuple = (0.0, 0.0)
    sources: list = field(default_factory=list)
    notes: list = field(default_factory=list)
    order: np.ndarray = None     # engine contact row of each listed contact (-1: dropped)
    swapped: np.ndarray = None   # listed contacts stored as (j, i)

    def as_dict(self):
        """The report as plain JSON-ready data."""
        return dict(law=self.law, units=self.units, counts=self.counts,
                    history_source=self.history_source, flagged=self.flagged,
                    dropped=self.dropped, mismatch=self.mismatch, residual=self.residual,
                    relax=self.relax, origin=list(self.origin),
                    sources=[list(map(str, s)) for s in self.sources], notes=self.notes)


def _scales(imported, units):
    units = {} if units is None else dict(units)
    unknown = set(units) - {"length", "mass", "force"}
    if unknown:
        raise ParameterError(f"units: unknown quantity {sorted(unknown)[0]!r} "
                             "(give length, mass, force multipliers)")
    out = {}
    for key in ("length", "mass", "force"):
        v = units.get(key, 1.0)
        if not (isinstance(v, (int, float, np.integer, np.floating)) and np.isfinite(v) and v > 0):
            raise ParameterError(f"units[{key!r}] must be a finite number > 0 (the size of "
                                 f"the file's {key} unit in the law's units), got {v!r}")
        out[key] = float(v)
    mapping = {k: {"file": imported.units.get(k, imported.units.get("style")), "scale": v,
                   "given": k in units} for k, v in out.items()}
    return out, mapping


def _particles(imported, sc, density, inertia):
    L = sc["length"]
    radius = imported.radius * L
    if imported.mass is not None:
        mass = imported.mass * sc["mass"]
    elif density is not None:
        if not (np.isfinite(density) and density > 0):
            raise ParameterError(f"density must be a finite number > 0, got {density!r}")
        mass = density * np.pi * radius ** 2
    else:
        raise ParameterError("the file gives no masses: pass density= (mass per area, the "
                             "law's units): m = density pi R^2")
    if inertia is None:
        inertia = mass * radius ** 2 / 2
    inertia = np.broadcast_to(np.asarray(inertia, float), radius.shape).copy()
    family = np.where(imported.fixed, FIXED, FREE)
    return radius, mass, inertia, family


def _box(imported, sc):
    if imported.box is None:
        return 0.0, 0.0, 0.0
    L = sc["length"]
    lx = imported.box[0] * L if imported.periodic[0] else 0.0
    ly = imported.box[1] * L if imported.periodic[1] else 0.0
    return lx, ly, (imported.le_offset * L if ly > 0 else 0.0)


def _images(pos, ci, cj, lx, ly, shift):
    """Image ``(m, k)`` of j nearest to i, the separation ``r_i - r_j`` and its length."""
    d = pos[ci] - pos[cj]
    k = np.rint(d[:, 1] / ly) if ly > 0 else np.zeros(len(ci))
    m = np.rint((d[:, 0] - k * shift) / lx) if lx > 0 else np.zeros(len(ci))
    dx = (d[:, 0] - k * shift) - m * lx
    dy = d[:, 1] - k * ly
    return m.astype(np.int64), k.astype(np.int64), np.column_stack([dx, dy])


def charan_s(y):
    """``s`` in [0, 1] with ``s + s^2 - s^3 = y`` (the charan law's |F_t| / (mu F_n) = y).

    ``phi(s) = s (1 + s - s^2)`` is increasing on [0, 1] (``phi' = (1 - s)(1 + 3 s)``)
    from 0 to 1.  Solved for ``u = 1 - s`` in ``u^2 (2 - u) = 1 - y`` by bisection
    (increasing in u on [0, 1]), so that ``s`` near 1, where ``phi'`` vanishes, keeps
    the digits that ``1 - y`` has.  ``y >= 1`` gives 1.
    """
    w = 1.0 - np.clip(np.asarray(y, float), 0.0, 1.0)
    lo, hi = np.zeros_like(w), np.ones_like(w)
    for _ in range(1100):    # halves to the last bit even for u ~ 1e-300
        mid = 0.5 * (lo + hi)
        done = (mid == lo) | (mid == hi)
        if done.all():
            break
        up = mid * mid * (2.0 - mid) < w
        lo = np.where(up & ~done, mid, lo)
        hi = np.where(~up & ~done, mid, hi)
    u = np.where(np.abs(lo * lo * (2 - lo) - w) <= np.abs(hi * hi * (2 - hi) - w), lo, hi)
    return 1.0 - u


def history_from_force(law, params, fn, ft, n, delta, radius_i, radius_j, torque=None):
    """The law's history of each contact from its tangential force on i (K, 2).

    ``fn`` (K,) the law's elastic normal force at the geometry, ``ft`` (K, 2) the
    tangential force on i, ``n`` (K, 2) the unit vector ``(r_i - r_j)/|r_i - r_j|``,
    ``delta`` the overlap, ``torque`` (K,) the z torque on i (``lee_hurley``'s
    rolling moment ``mr = T_i - R_i ft``; zero when not given).  Inverses:
    ``ishima`` ``xi = -F_t / (k_T delta^(1/2))``; ``linear`` ``t = -F_t / kt``;
    ``charan`` ``t = -(F_t/|F_t|) s t*`` with ``s`` from :func:`charan_s`,
    ``t* = mu kn delta / kt``; ``lee_hurley`` ``ft = F_t . (n_y, -n_x)``.

    Returns ``(history (K, 2), flags (K,) int: 1 tangential cap, 2 rolling cap)``.
    """
    p = params
    ok = (delta > 0) & (fn > 0)             # a dropped (apart) contact gets zero history
    delta, fn = np.where(ok, delta, 1.0), np.where(ok, fn, 1.0)
    ft = np.where(ok[:, None], ft, 0.0)
    mag = np.hypot(ft[:, 0], ft[:, 1])
    flags = np.zeros(len(fn), np.int64)
    hist = np.zeros((len(fn), 2))
    if law == "ishima":
        hist = -ft / (p["kt"] * np.sqrt(delta))[:, None]
    elif law == "linear":
        cap = p["mu"] * fn
        flags[mag >= cap * (1 - CAP)] = 1
        tstar = cap / p["kt"]
        scale = np.where(flags == 1, tstar / np.where(mag > 0, mag, 1.0), 1.0 / p["kt"])
        hist = -ft * scale[:, None]
    elif law == "charan":
        cap = p["mu"] * fn
        y = mag / cap
        flags[y >= 1 - CAP] = 1
        s = np.where(flags == 1, 1.0, charan_s(y))
        tstar = p["mu"] * p["kn"] * delta / p["kt"]
        unit = -ft / np.where(mag > 0, mag, 1.0)[:, None]
        hist = unit * (s * tstar)[:, None]
    elif law == "lee_hurley":
        f_t = ft[:, 0] * n[:, 1] - ft[:, 1] * n[:, 0]
        cap_t = p["mus"] * fn
        flags[np.abs(f_t) >= cap_t * (1 - CAP)] = 1
        f_t = np.where(flags == 1, np.sign(f_t) * cap_t, f_t)
        mr = np.zeros(len(fn)) if torque is None else torque - radius_i * f_t
        cap_r = p["mur"] * radius_i * radius_j / (radius_i + radius_j) * fn
        at_r = (np.abs(mr) >= cap_r * (1 - CAP)) & (np.abs(mr) > 0)
        flags[at_r] |= 2
        mr = np.where(at_r, np.sign(mr) * cap_r, mr)
        hist = np.column_stack([f_t, mr])
    else:
        raise ParameterError(f"law {law} has no tangential history to reconstruct")
    return hist, flags


def _law_normal(system, state, rows):
    """The law's elastic normal force |F| at zero history, per engine row."""
    st = state.copy()
    st.contacts.hist[:] = 0.0
    f = system.contact_forces(st)[rows]
    return np.hypot(f[:, 0], f[:, 1])


def _refuse_hertz(imported, ft, fn_file, sc):
    mag = np.hypot(ft[:, 0], ft[:, 1]) * sc["force"]
    ref = np.hypot(fn_file[:, 0], fn_file[:, 1]) * sc["force"] if fn_file is not None else 0
    bad = np.flatnonzero(mag > ROUND_OFF * np.maximum(ref, 1e-300))
    if bad.size:
        c = int(bad[0])
        raise ParameterError(f"{contact_where(imported, c)}: contact "
                             f"{imported.ids[imported.ci[c]]}-"
                             f"{imported.ids[imported.cj[c]]} has a tangential force "
                             f"|F_t| = {mag[c]:.6g}, but law hertz is frictionless (no "
                             "history can carry it): choose a law with friction")


def _history_transform(law, hist, swapped):
    """History of (j, i) from that of (i, j): lab-frame vectors flip; lee_hurley's mr flips."""
    out = hist.copy()
    if law == "lee_hurley":
        out[swapped, 1] *= -1
    else:
        out[swapped] *= -1
    return out


def _history_scale(law, sc):
    if law == "lee_hurley":
        return np.array([sc["force"], sc["force"] * sc["length"]])
    return np.full(2, sc["length"])


def to_engine(imported, law, params, units=None, wall_params=None, density=None, inertia=None,
              skin=None):
    """System, State and :class:`Report` of an imported packing under one of our laws.

    Parameters
    ----------
    imported : ImportedState
    law : str
        A pair law (``fricstab laws``).
    params : dict
        The law's parameters in the law's units.
    units : dict, optional
        ``{"length": L, "mass": M, "force": F}``: the size of the file's unit in
        the law's units (default 1 each; the mapping goes into the report).
    wall_params : dict, optional
        The wall form's extra parameters (unused without walls).
    density : float, optional
        Mass per area (law's units) when the file has no masses.
    inertia : array_like, optional
        Moments of inertia (law's units); default ``m R^2 / 2``.
    skin : float, optional
        Neighbour-list skin (law's length); default a tenth of the mean radius.

    Returns
    -------
    system, state, report
    """
    from fricstab.io.imports.engine_check import equilibrium, force_mismatch
    if not isinstance(imported, ImportedState):
        raise ParameterError(f"imported must be an ImportedState (fricstab.io.imports), got "
                             f"{type(imported).__name__}")
    material = Material(law, dict(params), dict(wall_params or {}))
    sc, mapping = _scales(imported, units)
    radius, mass, inert, family = _particles(imported, sc, density, inertia)
    lx, ly, shift = _box(imported, sc)
    pos = (imported.pos - np.asarray(imported.origin)) * sc["length"]
    skin = 0.1 * float(radius.mean()) if skin is None else float(skin)
    system = System(material, radius, mass, inert, family=family, lx=lx, ly=ly, skin=skin)
    theta = imported.theta
    state = system.state(pos, theta, shift=shift)
    report = Report(law, mapping, {}, "none", origin=imported.origin,
                    sources=imported.sources)
    _contacts(imported, system, state, sc, report)
    force_mismatch(imported, system, state, sc, report)
    report.residual = equilibrium(system, state)
    return system, state, report


def _contacts(imported, system, state, sc, report):
    """Match the file's contacts to the engine's, set the histories (module docstring)."""
    law, n_c = system.material.law, imported.n_contacts
    ci, cj = imported.ci, imported.cj
    m, k, sep = _images(state.q[:, :2], ci, cj, system.lx, system.ly, state.shift)
    dist = np.hypot(sep[:, 0], sep[:, 1])
    delta = system.radius[ci] + system.radius[cj] - dist
    apart = ~(delta > 0)
    both_fixed = (system.family[ci] != FREE) & (system.family[cj] != FREE)
    swapped = ci > cj
    i, j = np.where(swapped, cj, ci), np.where(swapped, ci, cj)
    mm, kk = np.where(swapped, -m, m), np.where(swapped, -k, k)
    keys = contact_keys(i, j, mm, kk, system.n, len(system.walls))
    rows = np.searchsorted(state.keys, keys)
    rows = np.minimum(rows, max(len(state.keys) - 1, 0))
    found = (state.keys[rows] == keys) if len(state.keys) else np.zeros(n_c, bool)
    keep = found & ~apart & ~both_fixed
    if len(np.unique(keys[keep])) != keep.sum():
        dup = np.flatnonzero(keep)[np.unique(keys[keep], return_index=True)[1]]
        c = int(np.setdiff1d(np.flatnonzero(keep), dup)[0])
        raise ParameterError(f"{contact_where(imported, c)}: contact {imported.ids[ci[c]]}-"
                             f"{imported.ids[cj[c]]} is listed twice")
    report.order = np.where(keep, rows, -1)
    report.swapped = swapped
    report.dropped = [{"contact": int(c), "where": contact_where(imported, int(c)),
                       "why": "both fixed" if both_fixed[c] else
                       f"apart (gap {-delta[c]:.6g})"} for c in np.flatnonzero(~keep)]
    from fricstab.engine.newton import touching
    touch = touching(system, state)
    added = np.setdiff1d(touch, keys[keep])
    report.counts = dict(listed=int(n_c), kept=int(keep.sum()),
                         dropped_apart=int((apart & ~both_fixed).sum()),
                         dropped_fixed=int(both_fixed.sum()), added=int(len(added)))
    hist = _histories(imported, system, state, sc, report, rows, keep, sep, dist, delta)
    if hist is not None:
        nh = system.material.info.n_hist
        if nh == 1:    # a frame-indifferent law: xi = t . t_hat, t_hat = (n_y, -n_x)
            n = sep / np.where(dist > 0, dist, 1.0)[:, None]
            hist = (hist[:, 0] * n[:, 1] - hist[:, 1] * n[:, 0])[:, None]
        else:
            hist = _history_transform(law, hist, swapped)
        state.contacts.hist[rows[keep], :nh] = hist[keep]
    system.project(state)


def _histories(imported, system, state, sc, report, rows, keep, sep, dist, delta):
    """Histories (K_file, 2) in the file's orientation, or None (zero); flags in report.

    A frame-indifferent law (``ishima_fi``, ...) gets its vector law's history here
    (the caller keeps its part along the tangent)."""
    from fricstab.laws import vector_form
    law = vector_form(system.material.law)
    info = system.material.info
    if imported.history is not None and not info.n_hist:
        report.notes.append(f"law {law} has no history: the file's history columns are unused")
    if imported.history is not None and info.n_hist:
        report.history_source = "file"
        hist = imported.history * _history_scale(law, sc)
        fn = _law_normal(system, state, np.where(keep, rows, 0))
        flags = _cap_flags(law, system.material.params, hist, fn, delta, system.radius,
                           imported.ci, imported.cj)
    elif imported.force_t is not None:
        if not info.n_hist:
            _refuse_hertz(imported, imported.force_t, imported.force_n, sc)
            report.notes.append("hertz: no tangential force beyond round-off")
            return None
        report.history_source = "force"
        n = sep / np.where(dist > 0, dist, 1.0)[:, None]
        fn = _law_normal(system, state, np.where(keep, rows, 0))
        tq = None if imported.torque is None else imported.torque * sc["force"] * sc["length"]
        hist, flags = history_from_force(law, system.material.params, fn,
                                         imported.force_t * sc["force"], n,
                                         np.maximum(delta, 0.0), system.radius[imported.ci],
                                         system.radius[imported.cj], tq)
        if law == "lee_hurley" and tq is None:
            report.notes.append("lee_hurley: no torques in the file, rolling histories mr = 0")
    else:
        report.notes.append("the file has no tangential state: every history is zero")
        return None
    report.flagged = [{"contact": int(c), "where": contact_where(imported, int(c)),
                       "cap": ["tangential", "rolling", "both"][int(flags[c]) - 1]}
                      for c in np.flatnonzero(keep & (flags > 0))]
    return hist


def _cap_flags(law, p, hist, fn, delta, radius, ci, cj):
    """Flags of file histories on (or past) their caps."""
    flags = np.zeros(len(hist), np.int64)
    if law in ("linear", "charan"):
        tstar = p["mu"] * p["kn"] * np.maximum(delta, 0) / p["kt"]
        flags[np.hypot(hist[:, 0], hist[:, 1]) >= tstar * (1 - CAP)] = 1
    elif law == "lee_hurley":
        flags[np.abs(hist[:, 0]) >= p["mus"] * fn * (1 - CAP)] |= 1
        cap_r = p["mur"] * radius[ci] * radius[cj] / (radius[ci] + radius[cj]) * fn
        flags[(np.abs(hist[:, 1]) >= cap_r * (1 - CAP)) & (hist[:, 1] != 0)] |= 2
    return flags
