"""Templates of the uniform kernels every law shares, and of the integer-switch dispatch.

One calling convention for every law (the engine's; see :mod:`symbolic.codegen`
for the list): ``<law>_eval(G, p, h, f, jac, want_jac)``, ``<law>_rate(G, p, a)``,
``<law>_project(G, p, h) -> flags``,
``<law>_advance(G', p, h, D, f, aux, want_aux) -> flags`` with ``G = dx, dy, Ri, Rj``
(pair) or ``y, R`` (wall), ``G'`` the same for a wall and ``dx, dy, Ri, Rj, r,
delta, lam`` for a pair (:func:`advance_geo_args`), ``p`` the parameters in
PARAMS order, ``h`` the history row and ``D`` the step's displacement
(:func:`advance_du_args`).

* ``eval`` and ``rate`` call the scalar kernels (``force``,
  ``force_jacobian``, ``increment``), so they agree with them to the bit.
* ``project`` zeroes the history without contact and puts it on its cap: a
  scalar cap at +-cap exactly (so a projected history is on its cap to the
  bit and reprojects to itself), Charan's vector history rescaled onto the
  circle as the force kernels do, flag 1 when ``|t| >= t* (1 - 8 eps)``
  (:data:`ON_CIRCLE`).
* ``advance`` uses the geometry once (a pair's centre distance, accurate
  overlap and contact-width solve come from the engine, which computes them
  for several contacts at once: ``fricstab._numerics.pair_geometry_lanes``;
  a wall's from its height; one ``sqrt(delta)``), the
  increment entries and the CONTACT values in one CSE block of geometry-only
  expressions (prefix ``g``), then ``h += a @ du`` summed left to right, the
  projection (the caps by the force kernels' own expressions) and the forces
  by the force kernel's own body (passed in), so that it equals rate, project
  and eval composed to the bit (Charan's vector history: to ~16 eps, as the
  force kernel may rescale a projected history once more).
"""

import hashlib

from symbolic.laws import CAPPED_LAWS, CONTACT, PAIR_LAWS
from symbolic.printing import code, geometry_block, kernel, zero_mat, zero_vec

__all__ = ["DISPATCH_TEMPLATE_VERSION", "ON_CIRCLE", "UNIFORM", "advance_du_args", "capped_advance",
           "advance_geo_args", "capped_project", "capped_rate", "eval_kernel", "family_advance",
           "family_project",
           "family_rate", "generate_dispatch", "geo_args", "normal_lines", "overlap_lines",
           "scalar_call", "uniform_doc", "unpack", "width_lines"]

COMMAND = "python -m symbolic.codegen"
DISPATCH_TEMPLATE_VERSION = "7"
#: Suffixes of the uniform kernels.
UNIFORM = ("_eval", "_rate", "_project", "_advance")

#: A rescaled vector history lies on the Coulomb circle to rounding: the
#: recomputed |t| is t* to within ~5 eps (one square root and one division
#: in the scale, two products, then the norm again).  |t| >= t* (1 - 8 eps)
#: counts as on the circle (flag bit 1), so a projected history keeps its flag; a
#: scalar history (a wall) uses the same threshold, as its force kernel does.
ON_CIRCLE = repr(1.0 - 8.0 * 2.0 ** -52)


# ------------------------------------------------------------------ all laws

def geo_args(law):
    return ["dx", "dy", "Ri", "Rj"] if law.kind == "pair" else ["y", "R"]


def scalar_call(law, names):
    """Arguments of a scalar kernel taking ``names``, from the uniform ones (p, h)."""
    hist = [str(s) for s in law.history]
    out = []
    for a in names:
        if a in law.params:
            out.append(f"p[{law.params.index(a)}]")
        elif a in hist:
            out.append(f"h[{hist.index(a)}]")
        else:
            out.append(a)
    return ", ".join(out)


def unpack(law, needed=None):
    return [f"{n} = p[{k}]" for k, n in enumerate(law.params) if needed is None or n in needed]


def overlap_lines(law):
    """The overlap exactly as the force kernels compute it (one square root)."""
    if law.kind == "wall":
        return ["delta = R - y"]
    return ["r = np.sqrt(dx * dx + dy * dy)",
            "delta = Ri + Rj - r",
            "# the accurate overlap of the force kernels, reusing r (fricstab/_numerics.py)",
            "delta = delta + overlap_correction_at(dx, dy, Ri, Rj, delta, r)"]


#: The displacement arguments of ``<law>_advance`` by kind of law.
_DU_ARGS = {"wall": ["du"], "pair": ["dui", "duj", "dxj"]}


#: A pair's geometry as ``<law>_advance`` takes it: what the force kernels compute
#: first (centre distance, accurate overlap, Hertz-cylinder ``lam``; the last is
#: read only by the laws with a contact width, ``WIDTH`` in dispatch.py).
_PAIR_GEOMETRY = ["r", "delta", "lam"]


def advance_geo_args(law):
    """The geometry arguments of ``<law>_advance``: ``y, R`` (wall), ``dx, dy, Ri, Rj, r, delta, lam`` (pair).

    A pair's ``r``, ``delta`` (and ``lam``) must be what
    ``fricstab._numerics.pair_geometry_lanes`` gives (the force kernels'
    values to the bit): the engine computes them for several contacts at
    once, which overlaps their square roots and logarithms.
    """
    return geo_args(law) + (_PAIR_GEOMETRY if law.kind == "pair" else [])


def _advance_overlap_lines(law):
    """The overlap lines of ``<law>_advance``: a wall's own; none for a pair (an argument)."""
    return overlap_lines(law) if law.kind == "wall" else []


def advance_du_args(law):
    """The displacement arguments of ``<law>_advance``: ``du`` (wall), ``dui, duj, dxj`` (pair).

    A pair reads the displacements of i and j over the step straight from the
    engine's rows (``dui``, ``duj``: no copy into a scratch vector, ~3 % of the
    packing's pass) and ``dxj``, the extra x displacement of j's periodic
    image (Lees-Edwards: ``k dshift``).
    """
    return _DU_ARGS[law.kind]


def _advance_kernel(law, doc, body):
    """``<law>_advance`` from its body (the calling convention of the module docstring)."""
    args = advance_geo_args(law) + ["p", "h", *advance_du_args(law), "f", "aux", "want_aux"]
    return kernel(f"{law.name}_advance", args, doc, body, decorator="hot_inline_jit")


def _no_contact_lines(nh, nf):
    """``h``, ``f`` (and ``aux`` if wanted) zeroed, return 0: an advance without contact."""
    zero = zero_vec("h", nh) + zero_vec("f", nf) + ["if want_aux:"] \
        + ["    " + z for z in zero_vec("aux", len(CONTACT))]
    return ["if delta <= 0.0:  # no contact: forget the history",
            *["    " + z for z in zero], "    return 0"]


def _aux_lines(exprs):
    """``aux[k] = CONTACT value k``, written only if wanted."""
    return ["if want_aux:"] + [f"    aux[{k}] = {code(e)}" for k, e in enumerate(exprs)]


def _du(law, b):
    """Entry ``b`` of the step's displacement ``du`` in the arguments of :func:`advance_du_args`."""
    if law.kind == "wall":
        return f"du[{b}]"
    dof = law.increment.shape[1] // 2
    if b < dof:
        return f"dui[{b}]"
    return "(duj[0] + dxj)" if b == dof else f"duj[{b - dof}]"


def _increment_lines(law, reduced):
    """``h[k] = h[k] + sum_b a[k, b] du[b]``, terms in column order, zeros skipped."""
    nh, nq = law.increment.shape
    lines = []
    for k in range(nh):
        terms = []
        for b in range(nq):
            e = reduced[k * nq + b]
            du = _du(law, b)
            if e == 0:
                continue
            if e == 1:
                terms.append(du)
            elif e == -1:
                terms.append(f"-{du}")
            else:
                terms.append(f"({code(e)}) * {du}")
        if terms:
            lines.append(f"h[{k}] = h[{k}] + ({' + '.join(terms)})")
    return lines


def uniform_doc(law):
    g = "dx, dy, Ri, Rj" if law.kind == "pair" else "y, R"
    nf, nq = law.jacobian.shape
    nh = len(law.history)
    return [
        "Uniform kernels (float64; the engine's calling convention, dispatch.py):",
        f"``{law.name}_eval({g}, p, h, f, jac, want_jac)``,",
        f"``{law.name}_rate({g}, p, a)``, ``{law.name}_project({g}, p, h) -> flags``,",
        f"``{law.name}_advance({', '.join(advance_geo_args(law))}, p, h, "
        f"{', '.join(advance_du_args(law))}, f, aux, want_aux) -> "
        "flags``; p = PARAMS values,",
        f"h the history row (first N_HIST = {nh} entries), f ({nf}), jac ({nf} x {nq}),",
        f"a ({nh} x {nq}), "
        + (f"du ({nq})" if law.kind == "wall" else
           f"dui, duj ({nq // 2}: the step's displacements of i and j), dxj (j's image's extra x)")
        + f", aux ({len(CONTACT)}: {', '.join(CONTACT)}; written "
        "only with want_aux);"
        + ("" if law.kind == "wall" else
           " r, delta, lam: the pair's geometry (fricstab._numerics.pair_geometry_lanes);"),
        "flags: bit 1 tangential history on its cap, bit 2 rolling; 0 without contact.",
    ]


def eval_kernel(law):
    args = [str(s) for s in law.inputs]
    call = scalar_call(law, args)
    return kernel(
        f"{law.name}_eval", geo_args(law) + ["p", "h", "f", "jac", "want_jac"],
        f"Forces from the stored history into f; with want_jac the block dF/dq into jac "
        f"(= {law.name}_force, {law.name}_force_jacobian).",
        ["if want_jac:",
         f"    {law.name}_force_jacobian({call}, f, jac)",
         "else:",
         f"    {law.name}_force({call}, f)"])


# ------------------------------------------------------------------ (kn, kt, mu, t) family

def family_rate(law):
    nh, nq = law.increment.shape
    name, geo = law.name, geo_args(law)
    doc = ("Increment rule at this geometry: dh = a @ du.  Purely geometric (the normal, the "
           "radii), so written in or out of contact: a contact that closes during a step counts "
           "the whole step, and the projection zeroes the history of one that is open; zeros "
           "only for coincident centres (no normal).")
    if not nh:
        return kernel(f"{name}_rate", geo + ["p", "a"],
                       "Increment rule: no history (a has no rows), nothing to write.", ["return"])
    inc = ", ".join(a for a in geo)
    if law.kind == "pair":
        body = ["if dx == 0.0 and dy == 0.0:", *["    " + z for z in zero_mat("a", nh, nq)],
                "    return", f"{name}_increment({inc}, a)"]
    else:
        body = [f"{name}_increment({inc}, a)"]
    return kernel(f"{name}_rate", geo + ["p", "a"], doc, body)


def family_project(law):
    name, geo = law.name, geo_args(law)
    nh = len(law.history)
    doc = ("History admissible at this geometry, in place: zero without contact"
           + (", rescaled onto |t| = t* beyond it; flags: 1 on the circle (sliding)."
              if law.coulomb else "; no cap, flags 0."))
    if not nh:
        return kernel(f"{name}_project", geo + ["p", "h"],
                       "No history: nothing to project; flags 0.", ["return 0"])
    body = overlap_lines(law) + ["if delta <= 0.0:  # a lost contact forgets its history",
                                  *["    " + z for z in zero_vec("h", nh)], "    return 0"]
    if not law.coulomb:
        return kernel(f"{name}_project", geo + ["p", "h"], doc, body + ["return 0"])
    body += unpack(law)
    body.append("tstar = mu * kn / kt * delta")
    if nh == 1:
        body += ["t = h[0]",
                 "if abs(t) >= tstar:  # on the cap to the bit: +-t* exactly",
                 "    h[0] = tstar if t > 0.0 else -tstar",
                 "    return 1",
                 f"return 1 if abs(t) >= tstar * {ON_CIRCLE} else 0"]
    else:
        body += ["tx = h[0]",
                 "ty = h[1]",
                 "tn = np.sqrt(tx * tx + ty * ty)",
                 "if tn > tstar:  # the rescaling of the force kernels",
                 "    scale = tstar / tn",
                 "    h[0] = tx * scale",
                 "    h[1] = ty * scale",
                 "    return 1",
                 f"return 1 if tn >= tstar * {ON_CIRCLE} else 0"]
    return kernel(f"{name}_project", geo + ["p", "h"], doc, body)


def family_advance(law, force_body):
    nh, nq = law.increment.shape
    nf = len(law.outputs)
    g = law.geometry
    defs = dict(g.intermediates())
    body = _advance_overlap_lines(law) + _no_contact_lines(nh, nf)
    body += unpack(law)
    if law.kind == "pair":
        body += [f"nx = {code(defs[g.nx])}", f"ny = {code(defs[g.ny])}"]
    body.append("sdelta = np.sqrt(delta)")
    inc = [law.increment[a, b] for a in range(nh) for b in range(nq)]
    lines, reduced = geometry_block(inc + list(law.contact))
    body += lines
    body += _increment_lines(law, reduced[:len(inc)])
    hist = [str(h) for h in law.history]
    body += [f"{c} = h[{k}]" for k, c in enumerate(hist)]
    flags = "0"
    if law.coulomb and nh == 1:
        body += ["tn = abs(t)  # = np.sqrt(t * t) of the force kernel, to the bit",
                 "tstar = mu * kn / kt * delta",
                 "flags = 0",
                 "if tn >= tstar:",
                 "    t = tstar if t > 0.0 else -tstar",
                 "    h[0] = t",
                 "    tn = tstar",
                 f"if tn >= tstar * {ON_CIRCLE}:",
                 "    flags = 1"]
        flags = "flags"
    elif law.coulomb:
        body += ["tn = np.sqrt(tx * tx + ty * ty)",
                 "tstar = mu * kn / kt * delta",
                 "flags = 0",
                 "if tn > tstar:",
                 "    scale = tstar / tn",
                 "    tx = tx * scale",
                 "    ty = ty * scale",
                 "    h[0] = tx",
                 "    h[1] = ty",
                 "    tn = tstar",
                 f"if tn >= tstar * {ON_CIRCLE}:",
                 "    flags = 1"]
        flags = "flags"
    body += force_body
    body += _aux_lines(reduced[len(inc):])
    body.append(f"return {flags}")
    doc = ("One dynamics step at this geometry (computed once): h += a @ du, project, "
           "forces from the projected history into f, aux = CONTACT if want_aux; returns the "
           "flags.")
    return _advance_kernel(law, doc, body)


# ------------------------------------------------------------------ capped laws

def width_lines(law, solve=True):
    """Contact width: lam (the one solve; an argument if not ``solve``) and the half-width hw."""
    g = law.geometry
    r1, r2 = ("Ri", "Rj") if law.kind == "pair" else ("R", "Rw")
    lines = [f"# Implicit Hertz-cylinder width: lam = ln(4{r1}/a) + ln(4{r2}/a) - 1 (Eq. A2),"]
    if solve:
        lines += [f"# raises ValueError beyond the turning point delta = 4 ({r1} + {r2})/e^2.",
                  f"lam = cylinder_lambda(delta, {r1}, {r2})"]
    else:
        lines += ["# solved by the engine (fricstab._numerics.pair_geometry_lanes)."]
    return lines + [f"hw = {code(dict(g.intermediates())[g.hw])}"]


def normal_lines(law):
    if law.kind != "pair":
        return []
    defs = dict(law.geometry.intermediates())
    return [f"nx = {code(defs[law.geometry.nx])}", f"ny = {code(defs[law.geometry.ny])}"]


def capped_rate(law, inc_args):
    """``<law>_rate``: the increment kernel (which zeroes ``a`` without contact)."""
    return kernel(f"{law.name}_rate", geo_args(law) + ["p", "a"],
                  f"Increment rule at this geometry: dh = a @ du (= {law.name}_increment); "
                  "zeros without contact.",
                  [f"{law.name}_increment({scalar_call(law, inc_args)}, a)"])


def capped_project(law):
    name, geo = law.name, geo_args(law)
    ft, mr = (str(h) for h in law.history)
    cap_t, cap_r = (code(c) for c in law.caps)
    used = set().union(*(c.free_symbols for c in law.caps))
    r1, r2 = ("Ri", "Rj") if law.kind == "pair" else ("R", "Rw")
    body = overlap_lines(law) + ["if delta <= 0.0:  # a lost contact forgets its history",
                                  "    h[0] = 0.0", "    h[1] = 0.0", "    return 0"]
    body += unpack(law, {str(s) for s in used} | {r2})
    body += [f"lam = cylinder_lambda(delta, {r1}, {r2})",
             "# the caps exactly as the force kernels compute them (A10, A18)",
             f"cap_t = {cap_t}", f"cap_r = {cap_r}",
             "flags = 0",
             f"{ft} = h[0]",
             f"if abs({ft}) >= cap_t:",
             f"    h[0] = cap_t if {ft} > 0.0 else -cap_t",
             "    flags = 1",
             f"{mr} = h[1]",
             f"if abs({mr}) >= cap_r:",
             f"    h[1] = cap_r if {mr} > 0.0 else -cap_r",
             "    flags += 2",
             "return flags"]
    return kernel(f"{name}_project", geo + ["p", "h"],
                   "Histories admissible at this geometry, in place: zero without contact, "
                   "on the cap at or beyond it (A10, A18, A23); flags: 1 tangential, "
                   "2 rolling on its cap.", body)


def capped_advance(law, force_body):
    nh, nq = law.increment.shape
    nf = len(law.outputs)
    ftc, mrc = (str(c) for c in law.capped)
    body = _advance_overlap_lines(law) + _no_contact_lines(nh, nf)
    body += unpack(law) + normal_lines(law) + width_lines(law, solve=law.kind == "wall")
    inc = [law.increment[a, b] for a in range(nh) for b in range(nq)]
    (denom, message), = law.domain
    lines, reduced = geometry_block([denom] + inc + list(law.contact))
    body += lines
    body += [f"if not {code(reduced[0])} > 0.0:", f"    raise ValueError({message!r})"]
    body += _increment_lines(law, reduced[1:1 + len(inc)])
    cap_t, cap_r = (code(c) for c in law.caps)
    body += ["# the caps exactly as the force kernels compute them (A10, A18)",
             f"cap_t = {cap_t}",
             f"cap_r = {cap_r}",
             "flags = 0",
             f"{ftc} = h[0]",
             f"if abs({ftc}) >= cap_t:",
             f"    {ftc} = cap_t if {ftc} > 0.0 else -cap_t",
             f"    h[0] = {ftc}",
             "    flags = 1",
             f"{mrc} = h[1]",
             f"if abs({mrc}) >= cap_r:",
             f"    {mrc} = cap_r if {mrc} > 0.0 else -cap_r",
             f"    h[1] = {mrc}",
             "    flags += 2"]
    body += force_body
    body += _aux_lines(reduced[1 + len(inc):])
    body.append("return flags")
    doc = ("One dynamics step at this geometry (width solved once"
           + (", by the engine" if law.kind == "pair" else "") + "): h += a @ du, cap, "
           "forces from the capped history into f, aux = CONTACT if want_aux; returns the "
           "flags.")
    return _advance_kernel(law, doc, body)


# ------------------------------------------------------------------ dispatch

def generate_dispatch(laws):
    """Source of ``fricstab/generated/dispatch.py`` from ``{name: Law}`` of every law."""
    pairs = list(PAIR_LAWS)
    walls = [laws[n].partner for n in pairs]
    for n, w in zip(pairs, walls):
        assert laws[w].partner == n and laws[w].n_dof == laws[n].n_dof, (n, w)
    h = hashlib.sha256(DISPATCH_TEMPLATE_VERSION.encode())
    h.update(repr([(n, laws[n].params, len(laws[n].history), laws[n].n_dof)
                   for n in pairs + walls]).encode())
    lines = [
        f"# generated by `{COMMAND}`; do not edit. symbolic-inputs-sha256: {h.hexdigest()}",
        '"""Integer-switch dispatch over the uniform kernels of every contact law.',
        "",
        "The id of a law is its index in PAIR_LAWS; its wall form (WALL_LAWS, same",
        "index) has the same id.  pair_eval, pair_rate, pair_project and pair_advance",
        "take (law, dx, dy, Ri, Rj, ...), the wall_* functions (law, y, R, ...), then",
        "the arguments of the per-law kernels (fricstab.generated.<law>: <law>_eval,",
        "_rate, _project, _advance) and return what they return.  Module-level",
        "functions calling module-level functions by name keep numba's on-disk cache",
        "effective; `python -m symbolic.codegen` clears it when any kernel changes.",
        "",
        "An unknown id never does nothing silently: project and advance zero their",
        "outputs (the whole h, f and aux rows) and return UNKNOWN_LAW (-1); eval and",
        "rate zero their outputs (f, and jac when want_jac; a) and raise ValueError.",
        '"""',
        "",
        "from fricstab._numba import hot_inline_jit",
    ]
    for n in pairs + walls:
        lines.append(f"from fricstab.generated.{n} import "
                     + ", ".join(f"{n}{s}" for s in UNIFORM))
    tup = lambda xs: repr(tuple(xs))  # noqa: E731
    lines += [
        "",
        "__all__ = [" + ", ".join(repr(f"{k}{s}") for k in ("pair", "wall") for s in UNIFORM)
        + ", 'PAIR_LAWS', 'WALL_LAWS', 'N_DOF', 'N_HIST', 'N_HIST_WALL', 'N_PARAMS',"
        " 'N_PARAMS_WALL', 'UNKNOWN_LAW', 'WIDTH']",
        "",
        "#: Pair laws; the id of a law is its index.",
        f"PAIR_LAWS = {tup(pairs)}",
        "#: Their wall forms, same ids.",
        f"WALL_LAWS = {tup(walls)}",
        "#: Degrees of freedom per particle (the same for a law's wall form).",
        f"N_DOF = {tup(laws[n].n_dof for n in pairs)}",
        f"N_HIST = {tup(len(laws[n].history) for n in pairs)}",
        f"N_HIST_WALL = {tup(len(laws[n].history) for n in walls)}",
        f"N_PARAMS = {tup(len(laws[n].params) for n in pairs)}",
        f"N_PARAMS_WALL = {tup(len(laws[n].params) for n in walls)}",
        "#: Whether a pair law's <law>_advance reads lam, the Hertz-cylinder width",
        "#: (fricstab._numerics.cylinder_lambda); the engine solves it only for these.",
        f"WIDTH = {tup(n in CAPPED_LAWS for n in pairs)}",
        "#: What project and advance return for an unknown law id.",
        "UNKNOWN_LAW = -1",
    ]
    for kind, names, geo in (("pair", pairs, "dx, dy, Ri, Rj"), ("wall", walls, "y, R")):
        specs = [
            ("_eval", "p, h, f, jac, want_jac", False,
             ["for k in range(f.shape[0]):", "    f[k] = 0.0", "if want_jac:",
              "    for k in range(jac.shape[0]):", "        for b in range(jac.shape[1]):",
              "            jac[k, b] = 0.0",
              f"raise ValueError('{kind}_eval: unknown contact law id')"]),
            ("_rate", "p, a", False,
             ["for k in range(a.shape[0]):", "    for b in range(a.shape[1]):",
              "        a[k, b] = 0.0", f"raise ValueError('{kind}_rate: unknown contact law id')"]),
            ("_project", "p, h", True,
             ["for k in range(h.shape[0]):", "    h[k] = 0.0", "return UNKNOWN_LAW"]),
            ("_advance", "".join(f"{g}, " for g in _PAIR_GEOMETRY if kind == "pair")
             + f"p, h, {', '.join(_DU_ARGS[kind])}, f, aux, want_aux", True,
             ["for k in range(h.shape[0]):", "    h[k] = 0.0", "for k in range(f.shape[0]):",
              "    f[k] = 0.0", "if want_aux:", "    for k in range(aux.shape[0]):",
              "        aux[k] = 0.0", "return UNKNOWN_LAW"]),
        ]
        for suffix, rest, returns, unknown in specs:
            doc = (f"{names[0]}{suffix} ... {names[-1]}{suffix} by law id "
                   f"({', '.join(f'{i}: {n}' for i, n in enumerate(names))}).")
            body = []
            for i, n in enumerate(names):
                kw = "if" if i == 0 else "elif"
                call = f"{n}{suffix}({geo}, {rest})"
                body += [f"{kw} law == {i}:", f"    {'return ' if returns else ''}{call}"]
                if not returns:
                    body.append("    return")
            body += unknown
            lines += ["", ""] + kernel(f"{kind}{suffix}", ["law", geo, rest], doc, body,
                                       decorator="hot_inline_jit")
    return "\n".join(lines) + "\n"
