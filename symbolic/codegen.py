"""Generate the numba contact kernels of :mod:`fricstab.generated`.

Usage::

    python -m symbolic.codegen          # (re)write fricstab/generated/*.py, clear numba caches
    python -m symbolic.codegen --check  # exit 1 naming every stale file

For each law of :mod:`symbolic.laws` one module is written with

* scalar kernels, valid for float64 and complex128 inputs (the verification
  harnesses differentiate them by complex step):

  - ``<law>_force(inputs..., f)``: generalized forces of one contact into ``f``;
  - ``<law>_force_jacobian(inputs..., f, jac)``: forces and the Jacobian block
    ``dF/dq`` with history, sharing common subexpressions;
  - ``<law>_increment(geometry..., a)``: the increment rule ``dh = a dq``
    (laws with history);
  - capped laws (:data:`symbolic.laws.CAPPED_LAWS`, e.g. ``lee_hurley``) also
    ``<law>_contact(inputs..., out)``, the contact quantities a DEM stores;

* the uniform kernels, float64, one calling convention for every law (what
  the engine calls; ``G`` is ``dx, dy, Ri, Rj`` for a pair and ``y, R`` for a
  wall, ``p`` the parameters in ``PARAMS`` order, ``h`` the contact's history
  row, of which the first ``N_HIST`` entries are used):

  - ``<law>_eval(G, p, h, f, jac, want_jac)``: forces from the stored
    history (``<law>_force``), and with ``want_jac`` the block
    (``<law>_force_jacobian``);
  - ``<law>_rate(G, p, a)``: the increment rule ``dh = a @ du`` at this
    geometry, zeros without contact;
  - ``<law>_project(G, p, h) -> flags``: ``h`` replaced in place by the
    admissible history (zero without contact, on the cap beyond it);
  - ``<law>_advance(G, p, h, du, f, aux) -> flags``: one dynamics step of one
    contact with the geometry computed once: ``h += a @ du``, project, forces
    from the projected history into ``f``, ``aux[0:4] = CONTACT`` values;

  flags: bit 1 the tangential history is on its cap (sliding), bit 2 the
  rolling one; 0 without contact;

* module constants: ``NAME, KIND, INPUTS, COORDS, OUTPUTS, HISTORY, COULOMB``
  and the metadata ``PARAMS, PARAM_UNITS, PARAM_DOCS, N_DOF, N_HIST, ROTATION,
  CAPPED, WALL`` (pair laws) or ``PAIR`` (wall laws), ``CONTACT``;

* ``<law>_assemble(...)`` (a loop over an array of contacts) only for the
  laws in :data:`LEGACY_ASSEMBLE`, whose loops modules outside the laws still
  import until the engine replaces them.

``fricstab/generated/dispatch.py`` switches on an integer law id
(``PAIR_LAWS``; a wall form has its pair law's id): ``pair_eval``,
``pair_rate``, ``pair_project``, ``pair_advance`` and the same four ``wall_*``.

**numba cache.**  A jitted function's on-disk cache is keyed on its own
source file; it does not see a callee in another file change (dispatch ->
per-law kernels -> ``fricstab._numerics``).  After writing the files this
command therefore deletes every numba cache file (``*.nbi``, ``*.nbc``) under
``fricstab/**/__pycache__`` and says how many; after editing
``fricstab/_numerics.py`` by hand, delete them the same way.

Output is deterministic for a given SymPy version (pinned in pyproject.toml);
each file starts with a "generated, do not edit" line naming this command and
the SHA-256 of the law's symbolic expressions.
"""

import argparse
import hashlib
import re
import sys
from pathlib import Path

import sympy as sp
from sympy.printing.pycode import PythonCodePrinter

from symbolic.laws import CAPPED_LAWS, CONTACT, LAWS, PAIR_LAWS, derive

__all__ = ["LEGACY_ASSEMBLE", "clear_numba_cache", "generate_capped_law", "generate_dispatch",
           "generate_law", "main", "render_all"]

OUT_DIR = Path(__file__).resolve().parent.parent / "fricstab" / "generated"
COMMAND = "python -m symbolic.codegen"
TEMPLATE_VERSION = "6"
CAPPED_TEMPLATE_VERSION = "3"
DISPATCH_TEMPLATE_VERSION = "1"

#: Laws that keep their generated ``<law>_assemble`` loop: still imported by
#: fricstab/scenes/pack_system.py (hertz, ishima),
#: fricstab/analysis/shear_spectrum.py (lee_hurley) and
#: validation/benchmarks/bench_kernels.py (ishima) until the engine replaces
#: them.  Every other law has none (the engine assembles).
LEGACY_ASSEMBLE = ("hertz", "ishima", "lee_hurley")

#: A rescaled vector history lies on the Coulomb circle to rounding: the
#: recomputed |t| is t* to within ~5 eps (one square root and one division
#: in the scale, two products, then the norm again).  |t| >= t* (1 - 8 eps)
#: counts as on the circle (flag bit 1), so a projected history keeps its flag.
ON_CIRCLE = repr(1.0 - 8.0 * 2.0 ** -52)


class _KernelPrinter(PythonCodePrinter):
    """Python source that numba compiles for float64 and complex128."""

    def _print_Pow(self, expr, rational=False):
        b, e = expr.base, expr.exp
        base = self.parenthesize(b, 100)  # atoms stay bare, sums get parentheses
        if e == sp.Rational(1, 2):
            return f"np.sqrt({self._print(b)})"
        if e == -sp.Rational(1, 2):
            return f"(1.0 / np.sqrt({self._print(b)}))"
        if e.is_Integer and 2 <= e <= 4:
            return "(" + " * ".join([base] * int(e)) + ")"
        if e.is_Integer and -4 <= e <= -1:
            return "(1.0 / (" + " * ".join([base] * int(-e)) + "))"
        return super()._print_Pow(expr, rational=rational)

    def _print_log(self, expr):
        return f"np.log({self._print(expr.args[0])})"

    def _print_exp(self, expr):
        return f"np.exp({self._print(expr.args[0])})"

    def _print_Pi(self, expr):
        return "np.pi"

    def _print_Rational(self, expr):
        return repr(float(expr))

    def _print_Integer(self, expr):
        return repr(float(expr))


_printer = _KernelPrinter({"fully_qualified_modules": False})


def _code(expr):
    return _printer.doprint(expr)


def _meta_hash(h, law):
    h.update(repr((law.params, law.param_units, law.param_docs, law.rotation, law.has_cap,
                   law.partner)).encode())
    h.update(sp.srepr(sp.Matrix(law.contact)).encode())


def _law_hash(law):
    h = hashlib.sha256()
    h.update(TEMPLATE_VERSION.encode())
    for m in (law.force, law.increment, law.jacobian):
        h.update(sp.srepr(m).encode())
    h.update(repr((law.inputs, law.coords, law.outputs, law.coulomb)).encode())
    _meta_hash(h, law)
    h.update(repr(law.name in LEGACY_ASSEMBLE).encode())
    return h.hexdigest()


# ------------------------------------------------------------------ shared pieces

def _body(exprs, targets, prefix="c"):
    """CSE the expressions and assign them to the target slots."""
    replacements, reduced = sp.cse(exprs, symbols=sp.numbered_symbols(prefix), order="canonical")
    lines = [f"{s} = {_code(e)}" for s, e in replacements]
    lines += [f"{t} = {_code(e)}" for t, e in zip(targets, reduced)]
    used = set()
    for e in list(exprs):
        used |= {str(s) for s in e.free_symbols}
    return lines, used


def _geometry_block(exprs):
    """CSE of geometry-only expressions (prefix g): (lines, reduced expressions)."""
    replacements, reduced = sp.cse(exprs, symbols=sp.numbered_symbols("g"), order="canonical")
    return [f"{s} = {_code(e)}" for s, e in replacements], reduced


def _geo_args(law):
    return ["dx", "dy", "Ri", "Rj"] if law.kind == "pair" else ["y", "R"]


def _scalar_call(law, names):
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


def _unpack(law, needed=None):
    return [f"{n} = p[{k}]" for k, n in enumerate(law.params) if needed is None or n in needed]


def _overlap_lines(law):
    """The overlap exactly as the force kernels compute it (one square root)."""
    if law.kind == "wall":
        return ["delta = R - y"]
    return ["r = np.sqrt(dx * dx + dy * dy)",
            "delta = Ri + Rj - r",
            "# the accurate overlap of the force kernels, reusing r (fricstab/_numerics.py)",
            "delta = delta + overlap_correction_at(dx, dy, Ri, Rj, delta, r)"]


def _zero_vec(arr, n):
    return [f"for k in range({n}):", f"    {arr}[k] = 0.0"] if n else []


def _zero_mat(arr, n, m):
    return [f"for k in range({n}):", f"    for b in range({m}):", f"        {arr}[k, b] = 0.0"] \
        if n * m else []


def _kernel(name, args, doc, body):
    return ["@kernel_jit", f"def {name}({', '.join(args)}):", f'    """{doc}"""'] + \
        ["    " + ln for ln in body]


def _increment_lines(law, reduced):
    """``h[k] = h[k] + sum_b a[k, b] du[b]``, terms in column order, zeros skipped."""
    nh, nq = law.increment.shape
    lines = []
    for k in range(nh):
        terms = []
        for b in range(nq):
            e = reduced[k * nq + b]
            if e == 0:
                continue
            if e == 1:
                terms.append(f"du[{b}]")
            elif e == -1:
                terms.append(f"-du[{b}]")
            else:
                terms.append(f"({_code(e)}) * du[{b}]")
        if terms:
            lines.append(f"h[{k}] = h[{k}] + ({' + '.join(terms)})")
    return lines


def _uniform_doc(law):
    g = "dx, dy, Ri, Rj" if law.kind == "pair" else "y, R"
    nf, nq = law.jacobian.shape
    nh = len(law.history)
    return [
        "Uniform kernels (float64; the engine's calling convention, dispatch.py):",
        f"``{law.name}_eval({g}, p, h, f, jac, want_jac)``,",
        f"``{law.name}_rate({g}, p, a)``, ``{law.name}_project({g}, p, h) -> flags``,",
        f"``{law.name}_advance({g}, p, h, du, f, aux) -> flags``; p = PARAMS values,",
        f"h the history row (first N_HIST = {nh} entries), f ({nf}), jac ({nf} x {nq}),",
        f"a ({nh} x {nq}), du ({nq}), aux ({len(CONTACT)}: {', '.join(CONTACT)});",
        "flags: bit 1 tangential history on its cap, bit 2 rolling; 0 without contact.",
    ]


def _metadata(law, args):
    """Module constants every generated law carries (read by fricstab.laws)."""
    partner = "WALL" if law.kind == "pair" else "PAIR"
    return [f"NAME = {law.name!r}", f"KIND = {law.kind!r}", f"INPUTS = {tuple(args)!r}",
            f"COORDS = {law.coords!r}", f"OUTPUTS = {law.outputs!r}",
            f"HISTORY = {tuple(str(h) for h in law.history)!r}",
            f"COULOMB = {law.coulomb!r}",
            "#: Material parameters in kernel order (the uniform kernels' p).",
            f"PARAMS = {tuple(law.params)!r}",
            f"PARAM_UNITS = {tuple(law.param_units)!r}",
            "PARAM_DOCS = (",
            *[f"    {d!r}," for d in law.param_docs],
            ")",
            f"N_DOF = {law.n_dof}",
            f"N_HIST = {len(law.history)}",
            "#: 'theta': generalized force T; 'l' = R theta: T/R; '': no rotation.",
            f"ROTATION = {law.rotation!r}",
            "#: True when the history is projected onto a cap.",
            f"CAPPED = {law.has_cap!r}",
            f"{partner} = {law.partner!r}",
            "#: aux of <law>_advance: secant normal stiffness F_n/delta, tangential",
            "#: stiffness at zero history, rolling stiffness, elastic normal force.",
            f"CONTACT = {CONTACT!r}"]


def _eval_kernel(law):
    args = [str(s) for s in law.inputs]
    call = _scalar_call(law, args)
    return _kernel(
        f"{law.name}_eval", _geo_args(law) + ["p", "h", "f", "jac", "want_jac"],
        f"Forces from the stored history into f; with want_jac the block dF/dq into jac "
        f"(= {law.name}_force, {law.name}_force_jacobian).",
        ["if want_jac:",
         f"    {law.name}_force_jacobian({call}, f, jac)",
         "else:",
         f"    {law.name}_force({call}, f)"])


def _legacy_assemble(law, args, nf, nq, nh):
    if law.name not in LEGACY_ASSEMBLE:
        return []
    return ["", ""] + _assemble(law, args, nf, nq, nh)


# ------------------------------------------------------------------ (kn, kt, mu, t) family

def _prologue(law, used):
    """Intermediates in order, the no-contact exit and the slip projection."""
    g = law.geometry
    lines = []
    defs = dict(g.intermediates())
    if law.kind == "pair":
        lines.append("r = np.sqrt(dx * dx + dy * dy)")
        lines.append("delta = Ri + Rj - r")
        lines.append("# Recover the digits the subtraction cancels (fricstab/_numerics.py);")
        lines.append("# only the real part changes, so complex-step derivatives are kept.")
        lines.append("delta = delta + overlap_correction(dx.real, dy.real, Ri.real, Rj.real, delta.real)")
    else:
        lines.append("delta = R - y")
    lines.append("if delta.real <= 0.0:  # no contact: zero force")
    lines.append("    __ZERO__")
    lines.append("    return")
    for sym in (getattr(g, "nx", None), getattr(g, "ny", None)):
        if sym is not None:
            lines.append(f"{sym} = {_code(defs[sym])}")
    lines.append("sdelta = np.sqrt(delta)")
    # |t| only where the Coulomb limit or the expressions need it (not Ishima's linear law)
    if law.history and (law.coulomb or used & {"tn", "inv_tn"}):
        t = [str(h) for h in law.history]
        lines.append(f"tn = np.sqrt({' + '.join(f'{c} * {c}' for c in t)})")
        if law.coulomb:
            lines.append("# Sliding: past t* = mu kn/kt delta the stored history is rescaled")
            lines.append("# onto the Coulomb circle |t| = t*; at |t| = t* the smoothed law")
            lines.append("# has zero radial stiffness, so force and Jacobian are continuous.")
            lines.append("tstar = mu * kn / kt * delta")
            if "slip_scale" in used:
                lines.append("slip_scale = 1.0")
            lines.append("if tn.real > tstar.real:")
            lines.append("    scale = tstar / tn")
            for c in t:
                lines.append(f"    {c} = {c} * scale")
            lines.append("    tn = tstar")
            if "slip_scale" in used:
                lines.append("    slip_scale = scale  # d(t* t/|t|)/dt across the circle")
        if "inv_tn" in used:
            lines.append("# 1/|t| only multiplies products of t components: 0 is the limit at t = 0")
            lines.append("inv_tn = 1.0 / tn if tn.real > 0.0 else 0.0 * tn")
    return lines


def _function(name, args, doc, exprs, targets, law, zero_lines):
    body, used = _body(exprs, targets)
    pro = _prologue(law, used)
    out = ["@kernel_jit", f"def {name}({', '.join(args)}):", f'    """{doc}"""']
    for line in pro:
        if line.strip() == "__ZERO__":
            out += ["    " * 2 + z for z in zero_lines]
        else:
            out.append("    " + line)
    out += ["    " + b for b in body]
    return out


def _family_rate(law):
    nh, nq = law.increment.shape
    name, geo = law.name, _geo_args(law)
    doc = "Increment rule at this geometry: dh = a @ du; zeros without contact."
    if not nh:
        return _kernel(f"{name}_rate", geo + ["p", "a"],
                       "Increment rule: no history (a has no rows), nothing to write.", ["return"])
    inc = ", ".join(a for a in geo)
    body = _overlap_lines(law) + ["if delta <= 0.0:", *["    " + z for z in _zero_mat("a", nh, nq)],
                                  "    return", f"{name}_increment({inc}, a)"]
    return _kernel(f"{name}_rate", geo + ["p", "a"], doc, body)


def _family_project(law):
    name, geo = law.name, _geo_args(law)
    nh = len(law.history)
    doc = ("History admissible at this geometry, in place: zero without contact"
           + (", rescaled onto |t| = t* beyond it; flags: 1 on the circle (sliding)."
              if law.coulomb else "; no cap, flags 0."))
    if not nh:
        return _kernel(f"{name}_project", geo + ["p", "h"],
                       "No history: nothing to project; flags 0.", ["return 0"])
    body = _overlap_lines(law) + ["if delta <= 0.0:  # a lost contact forgets its history",
                                  *["    " + z for z in _zero_vec("h", nh)], "    return 0"]
    if not law.coulomb:
        return _kernel(f"{name}_project", geo + ["p", "h"], doc, body + ["return 0"])
    body += _unpack(law)
    body.append("tstar = mu * kn / kt * delta")
    if nh == 1:
        body += ["t = h[0]",
                 "if abs(t) >= tstar:  # on the cap to the bit: +-t* exactly",
                 "    h[0] = tstar if t > 0.0 else -tstar",
                 "    return 1",
                 "return 0"]
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
    return _kernel(f"{name}_project", geo + ["p", "h"], doc, body)


def _family_advance(law, force_body):
    name, geo = law.name, _geo_args(law)
    nh, nq = law.increment.shape
    nf = len(law.outputs)
    g = law.geometry
    defs = dict(g.intermediates())
    zero = _zero_vec("h", nh) + _zero_vec("f", nf) + _zero_vec("aux", len(CONTACT))
    body = _overlap_lines(law) + ["if delta <= 0.0:  # no contact: forget the history",
                                  *["    " + z for z in zero], "    return 0"]
    body += _unpack(law)
    if law.kind == "pair":
        body += [f"nx = {_code(defs[g.nx])}", f"ny = {_code(defs[g.ny])}"]
    body.append("sdelta = np.sqrt(delta)")
    inc = [law.increment[a, b] for a in range(nh) for b in range(nq)]
    lines, reduced = _geometry_block(inc + list(law.contact))
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
    body += [f"aux[{k}] = {_code(e)}" for k, e in enumerate(reduced[len(inc):])]
    body.append(f"return {flags}")
    doc = ("One dynamics step at this geometry (computed once): h += a @ du, project, "
           "forces from the projected history into f, aux = CONTACT; returns the flags.")
    return _kernel(f"{name}_advance", geo + ["p", "h", "du", "f", "aux"], doc, body)


def generate_law(law):
    """Source text of the generated module for one :class:`symbolic.laws.Law`."""
    args = [str(s) for s in law.inputs]
    nf, nq = law.jacobian.shape
    nh = len(law.history)
    lines = [
        f"# generated by `{COMMAND}`; do not edit. "
        f"symbolic-inputs-sha256: {_law_hash(law)}",
        f'"""Generated contact kernels for the law ``{law.name}``.',
        "",
        f"{law.summary}.",
        "",
        f"Arguments: {', '.join(args)}.",
        f"Generalized forces f (rows): {', '.join(law.outputs)}.",
        f"Jacobian columns: {', '.join(law.coords)}; jac[a, b] = d f[a] / d q[b]",
        "with the tangential history advanced by the increment rule.",
        "",
        *_uniform_doc(law),
        '"""',
        "",
        "import numpy as np",
        "",
        "from fricstab._numba import kernel_jit",
        *(["from fricstab._numerics import overlap_correction, overlap_correction_at"]
          if law.kind == "pair" else []),
        "",
        f"__all__ = [{', '.join(repr(law.name + s) for s in _suffixes(law))}]",
        "",
        *_metadata(law, args),
        "",
        "",
    ]
    fz = [f"for a in range({nf}):", "    f[a] = 0.0"]
    jz = [f"for a in range({nf}):", f"    for b in range({nq}):", "        jac[a, b] = 0.0"]
    force_targets = [f"f[{a}]" for a in range(nf)]
    lines += _function(
        f"{law.name}_force", args + ["f"],
        "Generalized forces of one contact into f (float64 or complex128).",
        list(law.force), force_targets, law, fz)
    lines += ["", ""]
    jac_exprs = list(law.force) + [law.jacobian[a, b] for a in range(nf) for b in range(nq)]
    jac_targets = force_targets + [f"jac[{a}, {b}]" for a in range(nf) for b in range(nq)]
    lines += _function(
        f"{law.name}_force_jacobian", args + ["f", "jac"],
        "Forces into f and the Jacobian block dF/dq (with history) into jac.",
        jac_exprs, jac_targets, law, fz + jz)
    if nh:
        inc_args = [a for a in args if a in ("dx", "dy", "y", "Ri", "Rj", "R")]
        inc = [law.increment[a, b] for a in range(nh) for b in range(nq)]
        body, _ = _body(inc, [f"a[{a}, {b}]" for a in range(nh) for b in range(nq)])
        lines += ["", "", "@kernel_jit", f"def {law.name}_increment({', '.join(inc_args)}, a):",
                  '    """Increment rule of the history: dt = a @ dq (a: n_history x n_coords)."""']
        if law.kind == "pair":
            lines += ["    r = np.sqrt(dx * dx + dy * dy)", "    nx = dx / r", "    ny = dy / r"]
        lines += ["    " + b for b in body]
    # The force body of the force kernel, verbatim: advance computes the same
    # forces from the same history.
    force_body, _ = _body(list(law.force), force_targets)
    for part in (_eval_kernel(law), _family_rate(law), _family_project(law),
                 _family_advance(law, force_body)):
        lines += ["", ""] + part
    lines += _legacy_assemble(law, args, nf, nq, nh)
    return "\n".join(lines) + "\n"


_UNIFORM = ("_eval", "_rate", "_project", "_advance")


def _suffixes(law):
    s = ["_force", "_force_jacobian"]
    if law.history:
        s.append("_increment")
    s += list(_UNIFORM)
    return s + (["_assemble"] if law.name in LEGACY_ASSEMBLE else [])


def _assemble(law, args, nf, nq, nh):
    """The array layer: loop over contacts, accumulate forces, store blocks."""
    dof = nq // (2 if law.kind == "pair" else 1)
    params = [a for a in args if a in law.params]
    hist_args = [f"hist[c, {k}]" for k in range(nh)]
    legacy = ("  Kept for callers outside fricstab.laws until the engine assembles "
              "(symbolic.codegen.LEGACY_ASSEMBLE).")
    if law.kind == "pair":
        sig = ["sep", "radius", "contacts"] + params + (["hist"] if nh else []) + ["forces", "blocks"]
        call = ["sep[c, 0]", "sep[c, 1]", "radius[i]", "radius[j]"] + params + hist_args
        doc = ("Loop over pair contacts. sep[c] = r_i - r_j (minimum image), "
               "contacts[c] = (i, j); adds forces[i], forces[j] and writes blocks[c]." + legacy)
        pre = ["        i = contacts[c, 0]", "        j = contacts[c, 1]"]
        scatter = [f"        forces[i, {k}] += f[{k}]" for k in range(dof)] + \
                  [f"        forces[j, {k}] += f[{dof + k}]" for k in range(dof)]
    else:
        sig = ["pos", "radius", "contacts"] + params + (["hist"] if nh else []) + ["forces", "blocks"]
        call = ["pos[i, 1]", "radius[i]"] + params + hist_args
        doc = ("Loop over wall contacts. contacts[c] = particle index; adds "
               "forces[i] and writes blocks[c]." + legacy)
        pre = ["        i = contacts[c]"]
        scatter = [f"        forces[i, {k}] += f[{k}]" for k in range(dof)]
    return [
        "@kernel_jit",
        f"def {law.name}_assemble({', '.join(sig)}):",
        f'    """{doc}"""',
        f"    f = np.empty({nf})",
        "    for c in range(contacts.shape[0]):",
        *pre,
        f"        {law.name}_force_jacobian({', '.join(call)}, f, blocks[c])",
        *scatter,
    ]


# ------------------------------------------------------------------ capped laws

def _capped_hash(law):
    h = hashlib.sha256()
    h.update(CAPPED_TEMPLATE_VERSION.encode())
    for m in (law.force, law.increment, law.jacobian, sp.Matrix(law.caps),
              sp.Matrix([e for e, _ in law.domain])):
        h.update(sp.srepr(m).encode())
    h.update(repr((law.inputs, law.coords, law.outputs, law.capped, law.slides,
                   tuple(m for _, m in law.domain))).encode())
    _meta_hash(h, law)
    h.update(repr(law.name in LEGACY_ASSEMBLE).encode())
    return h.hexdigest()


def _width_lines(law):
    """Contact width: lam (the one solve) and the half-width hw."""
    g = law.geometry
    r1, r2 = ("Ri", "Rj") if law.kind == "pair" else ("R", "Rw")
    return [
        f"# Implicit Hertz-cylinder width: lam = ln(4{r1}/a) + ln(4{r2}/a) - 1 (Eq. A2),",
        f"# raises ValueError beyond the turning point delta = 4 ({r1} + {r2})/e^2.",
        f"lam = cylinder_lambda(delta, {r1}, {r2})",
        f"hw = {_code(dict(g.intermediates())[g.hw])}",
    ]


def _normal_lines(law):
    if law.kind != "pair":
        return []
    defs = dict(law.geometry.intermediates())
    return [f"nx = {_code(defs[law.geometry.nx])}", f"ny = {_code(defs[law.geometry.ny])}"]


def _capped_prologue(law, zero_lines, caps=True, domain=True):
    """Overlap, contact width, and (``caps``) the capped histories with flags.

    A history exactly on its cap takes the sliding branch (``>=``): after a
    projection |ft| equals the cap to the bit and the contact is sliding; with
    mur = 0 the capped torque and its derivative are then exactly 0.
    """
    ft, mr = (str(h) for h in law.history)
    ftc, mrc = (str(c) for c in law.capped)
    st, sr = (str(c) for c in law.slides)
    if law.kind == "pair":
        lines = [
            "r = np.sqrt(dx * dx + dy * dy)",
            "delta = Ri + Rj - r",
            "# Recover the digits the subtraction cancels (fricstab/_numerics.py);",
            "# only the real part changes, so complex-step derivatives are kept.",
            "delta = delta + overlap_correction(dx.real, dy.real, Ri.real, Rj.real, delta.real)",
        ]
    else:
        lines = ["delta = R - y"]
    lines += ["if delta.real <= 0.0:  # no contact: zero output",
              *["    " + z for z in zero_lines],
              "    return"]
    lines += _normal_lines(law) + _width_lines(law)
    if domain:
        for expr, message in law.domain:
            lines += [f"if not ({_code(expr)}).real > 0.0:", f"    raise ValueError({message!r})"]
    if caps:
        cap_t, cap_r = (_code(c) for c in law.caps)
        lines += [
            "# Caps with the elastic normal force (A10, A18); on or past a cap the",
            "# trial history is put on it (A23) and its branch flag set.",
            f"cap_t = {cap_t}",
            f"{st} = 0.0",
            f"{ftc} = {ft}",
            f"if abs({ft}.real) >= cap_t.real:",
            f"    {ftc} = cap_t if {ft}.real > 0.0 else -cap_t",
            f"    {st} = 1.0",
            f"cap_r = {cap_r}",
            f"{sr} = 0.0",
            f"{mrc} = {mr}",
            f"if abs({mr}.real) >= cap_r.real:",
            f"    {mrc} = cap_r if {mr}.real > 0.0 else -cap_r",
            f"    {sr} = 1.0",
        ]
    return lines


def _drop_dead(law, code):
    """Drop prologue names a function never reads (dead assignments, lint noise)."""
    for var in ("nx", "ny", "hw", *(str(c) for c in law.slides)):
        assign = re.compile(rf"^\s*{var} = ")
        read = re.compile(rf"\b{var}\b")
        if not any(read.search(ln) for ln in code if not assign.match(ln)):
            code = [ln for ln in code if not assign.match(ln)]
    return code


def _capped_function(name, args, doc, exprs, targets, law, zero_lines, caps=True, extra=(),
                     domain=True):
    body, _ = _body(exprs, targets)
    code = _capped_prologue(law, zero_lines, caps, domain) + list(body) + list(extra)
    out = ["@kernel_jit", f"def {name}({', '.join(args)}):", f'    """{doc}"""']
    return out + ["    " + ln for ln in _drop_dead(law, code)]


def _capped_project(law):
    name, geo = law.name, _geo_args(law)
    ft, mr = (str(h) for h in law.history)
    cap_t, cap_r = (_code(c) for c in law.caps)
    used = set().union(*(c.free_symbols for c in law.caps))
    r1, r2 = ("Ri", "Rj") if law.kind == "pair" else ("R", "Rw")
    body = _overlap_lines(law) + ["if delta <= 0.0:  # a lost contact forgets its history",
                                  "    h[0] = 0.0", "    h[1] = 0.0", "    return 0"]
    body += _unpack(law, {str(s) for s in used} | {r2})
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
    return _kernel(f"{name}_project", geo + ["p", "h"],
                   "Histories admissible at this geometry, in place: zero without contact, "
                   "on the cap at or beyond it (A10, A18, A23); flags: 1 tangential, "
                   "2 rolling on its cap.", body)


def _capped_advance(law, force_body):
    name, geo = law.name, _geo_args(law)
    nh, nq = law.increment.shape
    nf = len(law.outputs)
    ftc, mrc = (str(c) for c in law.capped)
    zero = _zero_vec("h", nh) + _zero_vec("f", nf) + _zero_vec("aux", len(CONTACT))
    body = _overlap_lines(law) + ["if delta <= 0.0:  # no contact: forget the history",
                                  *["    " + z for z in zero], "    return 0"]
    body += _unpack(law) + _normal_lines(law) + _width_lines(law)
    inc = [law.increment[a, b] for a in range(nh) for b in range(nq)]
    (denom, message), = law.domain
    lines, reduced = _geometry_block([denom] + inc + list(law.contact))
    body += lines
    body += [f"if not {_code(reduced[0])} > 0.0:", f"    raise ValueError({message!r})"]
    body += _increment_lines(law, reduced[1:1 + len(inc)])
    cap_t, cap_r = (_code(c) for c in law.caps)
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
    body += [f"aux[{k}] = {_code(e)}" for k, e in enumerate(reduced[1 + len(inc):])]
    body.append("return flags")
    doc = ("One dynamics step at this geometry (width solved once): h += a @ du, cap, "
           "forces from the capped history into f, aux = CONTACT; returns the flags.")
    return _kernel(f"{name}_advance", geo + ["p", "h", "du", "f", "aux"], doc, body)


def generate_capped_law(law):
    """Source of the generated module for a :class:`symbolic.laws.CappedLaw`."""
    args = [str(s) for s in law.inputs]
    nf, nq = law.jacobian.shape
    nh = len(law.history)
    convention = "lee_hurley_pair" if law.kind == "pair" else "lee_hurley_wall"
    lines = [
        f"# generated by `{COMMAND}`; do not edit. "
        f"symbolic-inputs-sha256: {_capped_hash(law)}",
        f'"""Generated contact kernels for the law ``{law.name}``.',
        "",
        f"{law.summary}.",
        "",
        f"Arguments: {', '.join(args)}; {', '.join(str(h) for h in law.history)} are the",
        "trial histories (after the DEM's increment), capped inside the kernels.",
        f"Generalized forces f (rows): {', '.join(law.outputs)}.",
        f"Jacobian columns: {', '.join(law.coords)}; jac[a, b] = d f[a] / d q[b]",
        "with the histories advanced by the increment rule (hypoelastic) and the caps:",
        "a sliding history follows its cap; a history exactly on its cap slides.",
        f"Conventions: symbolic/laws.py, {convention}.  Contact quantities",
        "(<law>_contact, out[0:9], names in CONTACT_OUT): delta, a,",
        f"{', '.join(CONTACT)}, {', '.join(str(c) for c in law.capped)}, sliding flag",
        "(0 none, 1 tangential, 2 rolling, 3 both).",
        "",
        *_uniform_doc(law),
        '"""',
        "",
        "import numpy as np",
        "",
        "from fricstab._numba import kernel_jit",
        "from fricstab._numerics import " + ("cylinder_lambda, overlap_correction, "
                                             "overlap_correction_at" if law.kind == "pair"
                                             else "cylinder_lambda"),
        "",
        f"__all__ = [{', '.join(repr(law.name + s) for s in _capped_suffixes(law))}]",
        "",
        *_metadata(law, args),
        f"CONTACT_OUT = {('delta', 'a', *CONTACT, *(str(c) for c in law.capped), 'sliding')!r}",
        "",
        "",
    ]
    fz = [f"for a in range({nf}):", "    f[a] = 0.0"]
    jz = [f"for a in range({nf}):", f"    for b in range({nq}):", "        jac[a, b] = 0.0"]
    force_targets = [f"f[{a}]" for a in range(nf)]
    lines += _capped_function(
        f"{law.name}_force", args + ["f"],
        "Generalized forces of one contact into f (float64 or complex128).",
        list(law.force), force_targets, law, fz, domain=False)
    lines += ["", ""]
    jac_exprs = list(law.force) + [law.jacobian[a, b] for a in range(nf) for b in range(nq)]
    jac_targets = force_targets + [f"jac[{a}, {b}]" for a in range(nf) for b in range(nq)]
    lines += _capped_function(
        f"{law.name}_force_jacobian", args + ["f", "jac"],
        "Forces into f and the Jacobian block dF/dq (with history and caps) into jac.",
        jac_exprs, jac_targets, law, fz + jz)
    lines += ["", ""]
    hist = [str(h) for h in law.history]
    inc_args = [a for a in args if a not in hist and a not in ("mus", "mur")]
    inc = [law.increment[a, b] for a in range(nh) for b in range(nq)]
    lines += _capped_function(
        f"{law.name}_increment", inc_args + ["rate"],
        f"Increment rule of the trial histories: d(ft, mr) = rate @ dq (rate: {nh} x {nq}).",
        inc, [f"rate[{a}, {b}]" for a in range(nh) for b in range(nq)], law,
        [f"for a in range({nh}):", f"    for b in range({nq}):", "        rate[a, b] = 0.0"],
        caps=False)
    lines += ["", ""]
    lines += _capped_function(
        f"{law.name}_contact", args + ["out"],
        "Contact quantities into out (9): delta, a, kn, kt, kr, Fn, ftc, mrc, sliding flag.",
        list(law.contact), [f"out[{k}]" for k in range(2, 2 + len(CONTACT))], law,
        ["for a in range(9):", "    out[a] = 0.0"],
        extra=["out[0] = delta", "out[1] = hw", f"out[6] = {law.capped[0]}",
               f"out[7] = {law.capped[1]}", f"out[8] = {law.slides[0]} + 2.0 * {law.slides[1]}"])
    force_body, _ = _body(list(law.force), force_targets)
    rate = _kernel(f"{law.name}_rate", _geo_args(law) + ["p", "a"],
                   f"Increment rule at this geometry: dh = a @ du (= {law.name}_increment); "
                   "zeros without contact.",
                   [f"{law.name}_increment({_scalar_call(law, inc_args)}, a)"])
    for part in (_eval_kernel(law), rate, _capped_project(law), _capped_advance(law, force_body)):
        lines += ["", ""] + part
    lines += _legacy_assemble(law, args, nf, nq, nh)
    return "\n".join(lines) + "\n"


def _capped_suffixes(law):
    s = ["_force", "_force_jacobian", "_increment", "_contact", *_UNIFORM]
    return s + (["_assemble"] if law.name in LEGACY_ASSEMBLE else [])


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
        "from fricstab._numba import kernel_jit",
    ]
    for n in pairs + walls:
        lines.append(f"from fricstab.generated.{n} import "
                     + ", ".join(f"{n}{s}" for s in _UNIFORM))
    tup = lambda xs: repr(tuple(xs))  # noqa: E731
    lines += [
        "",
        "__all__ = [" + ", ".join(repr(f"{k}{s}") for k in ("pair", "wall") for s in _UNIFORM)
        + ", 'PAIR_LAWS', 'WALL_LAWS', 'N_DOF', 'N_HIST', 'N_HIST_WALL', 'N_PARAMS',"
        " 'N_PARAMS_WALL', 'UNKNOWN_LAW']",
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
            ("_advance", "p, h, du, f, aux", True,
             ["for k in range(h.shape[0]):", "    h[k] = 0.0", "for k in range(f.shape[0]):",
              "    f[k] = 0.0", "for k in range(aux.shape[0]):", "    aux[k] = 0.0",
              "return UNKNOWN_LAW"]),
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
            lines += ["", ""] + _kernel(f"{kind}{suffix}", ["law", geo, rest], doc, body)
    return "\n".join(lines) + "\n"


# ------------------------------------------------------------------ files

def render_all():
    """``{path: source}`` for every generated file."""
    files = {}
    derived = {}
    for name in LAWS:
        derived[name] = law = derive(name)
        files[OUT_DIR / f"{name}.py"] = generate_law(law)
    for name in CAPPED_LAWS:
        derived[name] = law = derive(name)
        files[OUT_DIR / f"{name}.py"] = generate_capped_law(law)
    files[OUT_DIR / "dispatch.py"] = generate_dispatch(derived)
    walls = tuple(derived[n].partner for n in PAIR_LAWS)
    init = ['# generated by `python -m symbolic.codegen`; do not edit.',
            '"""Generated contact-law kernels, one module per law (see symbolic/laws.py).',
            "",
            "LAW_NAMES: the (kn, kt, [mu], vector history t) family that the shared",
            "verification harness and its tests sweep; CAPPED_LAW_NAMES: laws with",
            "capped scalar histories and their own verification (fricstab.laws.verify_lee_hurley);",
            "PAIR_LAW_NAMES: the pair laws in dispatch order (the id of a law is its index,",
            "its wall form, WALL_LAW_NAMES, has the same id; see dispatch.py)."
            '"""',
            "", f"LAW_NAMES = {tuple(LAWS)!r}",
            f"CAPPED_LAW_NAMES = {tuple(CAPPED_LAWS)!r}",
            f"ALL_LAW_NAMES = {tuple(LAWS) + tuple(CAPPED_LAWS)!r}",
            f"PAIR_LAW_NAMES = {tuple(PAIR_LAWS)!r}",
            f"WALL_LAW_NAMES = {walls!r}", ""]
    files[OUT_DIR / "__init__.py"] = "\n".join(init)
    return files


def clear_numba_cache(root=None):
    """Delete numba's cache files (``*.nbi``, ``*.nbc``) under ``root/**/__pycache__``.

    ``root`` defaults to the ``fricstab`` package (the parent of ``OUT_DIR``).
    A caller's cache entry does not see a callee in another file change (see
    the module docstring), so any regeneration invalidates them.  Returns the
    count.
    """
    root = OUT_DIR.parent if root is None else Path(root)
    removed = 0
    for pattern in ("*.nbi", "*.nbc"):
        for path in root.glob(f"**/__pycache__/{pattern}"):
            path.unlink(missing_ok=True)
            removed += 1
    return removed


def main(argv=None):
    parser = argparse.ArgumentParser(prog=COMMAND, description=__doc__.splitlines()[0])
    parser.add_argument("--check", action="store_true",
                        help="do not write; exit 1 naming each file that differs")
    ns = parser.parse_args(argv)
    files = render_all()
    if ns.check:
        stale = [p for p, src in files.items()
                 if not p.exists() or p.read_text() != src]
        for p in stale:
            print(f"stale generated file: {p.relative_to(OUT_DIR.parent.parent)} "
                  f"(run `{COMMAND}`)", file=sys.stderr)
        if not stale:
            print(f"{len(files)} generated files are up to date")
        return 1 if stale else 0
    OUT_DIR.mkdir(parents=True, exist_ok=True)
    for p, src in files.items():
        p.write_text(src)
        print(f"wrote {p.relative_to(OUT_DIR.parent.parent)}")
    removed = clear_numba_cache()
    print(f"removed {removed} numba cache files (*.nbi, *.nbc) under "
          f"{OUT_DIR.parent.name}/**/__pycache__: a caller's cache does not see a callee "
          "in another file change")
    return 0


if __name__ == "__main__":
    sys.exit(main())
