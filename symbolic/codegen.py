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
  - ``<law>_advance(G', p, h, D, f, aux, want_aux) -> flags``: one dynamics
    step of one contact with the geometry used once (``G' = G`` for a wall;
    ``dx, dy, Ri, Rj, r, delta, lam`` for a pair, the centre distance, accurate
    overlap and Hertz-cylinder width from
    ``fricstab._numerics.pair_geometry_lanes``, which the engine runs on several
    contacts at once): ``h += a @ du``
    (``D = du`` for a wall, ``dui, duj, dxj`` for a pair: the rows of i and j
    and the extra x of j's image, read in place),
    project, forces from the projected history into ``f``, and with
    ``want_aux`` ``aux[0:4] = CONTACT`` values (the dashpots' stiffnesses and
    the elastic normal force; the engine asks for them only when it uses them:
    four stores fewer per contact, ~6 % of the packing's pass);

  flags: bit 1 the tangential history is on its cap (sliding), bit 2 the
  rolling one; 0 without contact;

* module constants: ``NAME, KIND, INPUTS, COORDS, OUTPUTS, HISTORY, COULOMB``
  and the metadata ``PARAMS, PARAM_UNITS, PARAM_DOCS, N_DOF, N_HIST, ROTATION,
  CAPPED, WALL`` (pair laws) or ``PAIR`` (wall laws), ``CONTACT``;

* ``<law>_assemble(...)`` (a loop over an array of contacts) only for the
  laws in :data:`LEGACY_ASSEMBLE`, whose loops modules outside the laws still
  import until the engine replaces them.

The templates of the uniform kernels and of the dispatch module are in
:mod:`symbolic.uniform`, the expression printer in :mod:`symbolic.printing`.

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

from symbolic.laws import CAPPED_LAWS, CONTACT, LAWS, PAIR_LAWS, derive
from symbolic.printing import body as _body
from symbolic.printing import code as _code
from symbolic.uniform import (ON_CIRCLE, UNIFORM, capped_advance, capped_project, capped_rate,
                              eval_kernel, family_advance, family_project, family_rate,
                              generate_dispatch, normal_lines, uniform_doc, width_lines)

__all__ = ["LEGACY_ASSEMBLE", "clear_numba_cache", "generate_capped_law", "generate_dispatch",
           "generate_law", "main", "render_all"]

OUT_DIR = Path(__file__).resolve().parent.parent / "fricstab" / "generated"
COMMAND = "python -m symbolic.codegen"
TEMPLATE_VERSION = "9"
CAPPED_TEMPLATE_VERSION = "5"

#: Laws that keep their generated ``<law>_assemble`` loop: still imported by
#: fricstab/scenes/pack_system.py (hertz, ishima),
#: fricstab/analysis/shear_spectrum.py (lee_hurley) and
#: validation/benchmarks/bench_kernels.py (ishima) until the engine replaces
#: them.  Every other law has none (the engine assembles).
LEGACY_ASSEMBLE = ("hertz", "ishima", "lee_hurley")


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


def _legacy_assemble(law, args, nf, nq, nh):
    if law.name not in LEGACY_ASSEMBLE:
        return []
    return ["", ""] + _assemble(law, args, nf, nq, nh)


# ------------------------------------------------------------------ (kn, kt, mu, t) family

def _hard_cap(law):
    """True for a law whose Jacobian has the sliding flag (symbolic.linear.SLIDE)."""
    return "slide" in {str(s) for s in law.jacobian.free_symbols}


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
    if "sdelta" in used:
        lines.append("sdelta = np.sqrt(delta)")
    # |t| only where the Coulomb limit or the expressions need it (not Ishima's linear law)
    if law.history and (law.coulomb or used & {"tn", "inv_tn"}):
        t = [str(h) for h in law.history]
        lines.append(f"tn = np.sqrt({' + '.join(f'{c} * {c}' for c in t)})")
        if law.coulomb:
            lines.append("# Sliding: past t* = mu kn/kt delta the stored history is rescaled")
            if _hard_cap(law):
                lines.append("# onto the Coulomb circle |t| = t* (a hard cap: the sliding block")
                lines.append("# follows the projection, flag slide; symbolic/linear.py).")
            else:
                lines.append("# onto the Coulomb circle |t| = t*; at |t| = t* the smoothed law")
                lines.append("# has zero radial stiffness, so force and Jacobian are continuous.")
            lines.append("tstar = mu * kn / kt * delta")
            if "slip_scale" in used:
                lines.append("slip_scale = 1.0")
            if "slide" in used:
                lines.append("slide = 0.0")
            if _hard_cap(law):
                lines.append("# On the circle to rounding slides, as project flags it.")
                lines.append(f"if tn.real >= tstar.real * {ON_CIRCLE}:")
            else:
                lines.append("if tn.real > tstar.real:")
            lines.append("    scale = tstar / tn")
            for c in t:
                lines.append(f"    {c} = {c} * scale")
            lines.append("    tn = tstar")
            if "slip_scale" in used:
                lines.append("    slip_scale = scale  # d(t* t/|t|)/dt across the circle")
            if "slide" in used:
                lines.append("    slide = 1.0")
        if "inv_tn" in used:
            lines.append("# 1/|t| only multiplies products of t components: 0 is the limit at t = 0")
            lines.append("inv_tn = 1.0 / tn if tn.real > 0.0 else 0.0 * tn")
    return lines


def _function(name, args, doc, exprs, targets, law, zero_lines):
    body, used = _body(exprs, targets)
    pro = _prologue(law, used)
    out = ["@hot_jit", f"def {name}({', '.join(args)}):", f'    """{doc}"""']
    for line in pro:
        if line.strip() == "__ZERO__":
            out += ["    " * 2 + z for z in zero_lines]
        else:
            out.append("    " + line)
    out += ["    " + b for b in body]
    return out


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
        *uniform_doc(law),
        '"""',
        "",
        "import numpy as np",
        "",
        "from fricstab._numba import hot_inline_jit, hot_jit, kernel_jit",
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
        lines += ["", "", "@hot_jit", f"def {law.name}_increment({', '.join(inc_args)}, a):",
                  '    """Increment rule of the history: dt = a @ dq (a: n_history x n_coords)."""']
        if law.kind == "pair":
            lines += ["    r = np.sqrt(dx * dx + dy * dy)", "    nx = dx / r", "    ny = dy / r"]
        lines += ["    " + b for b in body]
    # The force body of the force kernel, verbatim: advance computes the same
    # forces from the same history.
    force_body, _ = _body(list(law.force), force_targets)
    for part in (eval_kernel(law), family_rate(law), family_project(law),
                 family_advance(law, force_body)):
        lines += ["", ""] + part
    lines += _legacy_assemble(law, args, nf, nq, nh)
    return "\n".join(lines) + "\n"


def _suffixes(law):
    s = ["_force", "_force_jacobian"]
    if law.history:
        s.append("_increment")
    s += list(UNIFORM)
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
    lines += normal_lines(law) + width_lines(law)
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
    out = ["@hot_jit", f"def {name}({', '.join(args)}):", f'    """{doc}"""']
    return out + ["    " + ln for ln in _drop_dead(law, code)]


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
        *uniform_doc(law),
        '"""',
        "",
        "import numpy as np",
        "",
        "from fricstab._numba import hot_inline_jit, hot_jit, kernel_jit",
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
    for part in (eval_kernel(law), capped_rate(law, inc_args), capped_project(law),
                 capped_advance(law, force_body)):
        lines += ["", ""] + part
    lines += _legacy_assemble(law, args, nf, nq, nh)
    return "\n".join(lines) + "\n"


def _capped_suffixes(law):
    s = ["_force", "_force_jacobian", "_increment", "_contact", *UNIFORM]
    return s + (["_assemble"] if law.name in LEGACY_ASSEMBLE else [])


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
