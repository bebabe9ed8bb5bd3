"""Generate the numba contact kernels of :mod:`fricstab.generated`.

Usage::

    python -m symbolic.codegen          # (re)write fricstab/generated/*.py
    python -m symbolic.codegen --check  # exit 1 naming every stale file

For each law of :mod:`symbolic.laws` one module is written with

* ``<law>_force(inputs..., f)``: generalized forces of one contact into ``f``;
  valid for float64 and complex128 inputs (complex-step differentiation);
* ``<law>_force_jacobian(inputs..., f, jac)``: forces and the Jacobian block
  ``dF/dq`` with history, sharing common subexpressions;
* ``<law>_increment(inputs..., a)``: the increment rule ``dt = a dq``
  (frictional laws only);
* ``<law>_assemble(...)``: the loop over an array of contacts.

Laws with capped scalar histories (:data:`symbolic.laws.CAPPED_LAWS`, e.g.
``lee_hurley``) have their own template (:func:`generate_capped_law`): the
same four kernels plus ``<law>_contact`` (the contact quantities a DEM
stores), the implicit contact width from ``fricstab._numerics``, and the caps
applied in the prologue with branch flags in the Jacobian.

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

from symbolic.laws import CAPPED_LAWS, LAWS, derive

__all__ = ["generate_capped_law", "generate_law", "main", "render_all"]

OUT_DIR = Path(__file__).resolve().parent.parent / "fricstab" / "generated"
COMMAND = "python -m symbolic.codegen"
TEMPLATE_VERSION = "5"


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


def _law_hash(law):
    h = hashlib.sha256()
    h.update(TEMPLATE_VERSION.encode())
    for m in (law.force, law.increment, law.jacobian):
        h.update(sp.srepr(m).encode())
    h.update(repr((law.inputs, law.coords, law.outputs, law.coulomb)).encode())
    return h.hexdigest()


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


def _body(exprs, targets):
    """CSE the expressions and assign them to the target slots."""
    replacements, reduced = sp.cse(exprs, symbols=sp.numbered_symbols("c"), order="canonical")
    lines = [f"{s} = {_code(e)}" for s, e in replacements]
    lines += [f"{t} = {_code(e)}" for t, e in zip(targets, reduced)]
    used = set()
    for e in list(exprs):
        used |= {str(s) for s in e.free_symbols}
    return lines, used


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


def _metadata(law, args):
    """Module constants every generated law carries (read by fricstab.laws)."""
    return [f"NAME = {law.name!r}", f"KIND = {law.kind!r}", f"INPUTS = {tuple(args)!r}",
            f"COORDS = {law.coords!r}", f"OUTPUTS = {law.outputs!r}",
            f"HISTORY = {tuple(str(h) for h in law.history)!r}",
            f"COULOMB = {law.coulomb!r}"]


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
        '"""',
        "",
        "import numpy as np",
        "",
        "from fricstab._numba import kernel_jit",
        *(["from fricstab._numerics import overlap_correction"] if law.kind == "pair" else []),
        "",
        f"__all__ = [{', '.join(repr(law.name + s) for s in _suffixes(law))}]",
        "",
        *_metadata(law, args),
        "",
        "",
    ]
    fz = [f"for a in range({nf}):", "    f[a] = 0.0"]
    jz = [f"for a in range({nf}):", f"    for b in range({nq}):", "        jac[a, b] = 0.0"]
    lines += _function(
        f"{law.name}_force", args + ["f"],
        "Generalized forces of one contact into f (float64 or complex128).",
        list(law.force), [f"f[{a}]" for a in range(nf)], law, fz)
    lines += ["", ""]
    jac_exprs = list(law.force) + [law.jacobian[a, b] for a in range(nf) for b in range(nq)]
    jac_targets = [f"f[{a}]" for a in range(nf)] + [
        f"jac[{a}, {b}]" for a in range(nf) for b in range(nq)]
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
    lines += ["", ""] + _assemble(law, args, nf, nq, nh)
    return "\n".join(lines) + "\n"


def _suffixes(law):
    s = ["_force", "_force_jacobian"]
    if law.history:
        s.append("_increment")
    return s + ["_assemble"]


def _assemble(law, args, nf, nq, nh):
    """The array layer: loop over contacts, accumulate forces, store blocks."""
    dof = nq // (2 if law.kind == "pair" else 1)
    params = [a for a in args if a in law.params]
    hist_args = [f"hist[c, {k}]" for k in range(nh)]
    if law.kind == "pair":
        sig = ["sep", "radius", "contacts"] + params + (["hist"] if nh else []) + ["forces", "blocks"]
        call = ["sep[c, 0]", "sep[c, 1]", "radius[i]", "radius[j]"] + params + hist_args
        doc = ("Loop over pair contacts. sep[c] = r_i - r_j (minimum image), "
               "contacts[c] = (i, j); adds forces[i], forces[j] and writes blocks[c].")
        pre = ["        i = contacts[c, 0]", "        j = contacts[c, 1]"]
        scatter = [f"        forces[i, {k}] += f[{k}]" for k in range(dof)] + \
                  [f"        forces[j, {k}] += f[{dof + k}]" for k in range(dof)]
    else:
        sig = ["pos", "radius", "contacts"] + params + (["hist"] if nh else []) + ["forces", "blocks"]
        call = ["pos[i, 1]", "radius[i]"] + params + hist_args
        doc = ("Loop over wall contacts. contacts[c] = particle index; adds "
               "forces[i] and writes blocks[c].")
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


def _capped_hash(law):
    h = hashlib.sha256()
    h.update(CAPPED_TEMPLATE_VERSION.encode())
    for m in (law.force, law.increment, law.jacobian, sp.Matrix(law.caps),
              sp.Matrix([e for _, e in law.contact]), sp.Matrix([e for e, _ in law.domain])):
        h.update(sp.srepr(m).encode())
    h.update(repr((law.inputs, law.coords, law.outputs, law.capped, law.slides,
                   tuple(n for n, _ in law.contact), tuple(m for _, m in law.domain))).encode())
    return h.hexdigest()


def _capped_prologue(law, zero_lines, caps=True, domain=True):
    """Overlap, contact width, and (``caps``) the capped histories with flags."""
    g = law.geometry
    ft, mr = (str(h) for h in law.history)
    ftc, mrc = (str(c) for c in law.capped)
    st, sr = (str(c) for c in law.slides)
    lines = [
        "r = np.sqrt(dx * dx + dy * dy)",
        "delta = Ri + Rj - r",
        "# Recover the digits the subtraction cancels (fricstab/_numerics.py);",
        "# only the real part changes, so complex-step derivatives are kept.",
        "delta = delta + overlap_correction(dx.real, dy.real, Ri.real, Rj.real, delta.real)",
        "if delta.real <= 0.0:  # no contact: zero output",
        *["    " + z for z in zero_lines],
        "    return",
        f"nx = {_code(dict(g.intermediates())[g.nx])}",
        f"ny = {_code(dict(g.intermediates())[g.ny])}",
        "# Implicit Hertz-cylinder width: lam = ln(4Ri/a) + ln(4Rj/a) - 1 (Eq. A2),",
        "# raises ValueError beyond the turning point delta = 4 (Ri + Rj)/e^2.",
        "lam = cylinder_lambda(delta, Ri, Rj)",
        f"hw = {_code(dict(g.intermediates())[g.hw])}",
    ]
    if domain:
        for expr, message in law.domain:
            lines += [f"if not ({_code(expr)}).real > 0.0:", f"    raise ValueError({message!r})"]
    if caps:
        cap_t, cap_r = (_code(c) for c in law.caps)
        lines += [
            "# Caps with the elastic normal force (A10, A18); past a cap the",
            "# trial history is put back on it (A23) and its branch flag set.",
            f"cap_t = {cap_t}",
            f"{st} = 0.0",
            f"{ftc} = {ft}",
            f"if abs({ft}.real) > cap_t.real:",
            f"    {ftc} = cap_t if {ft}.real > 0.0 else -cap_t",
            f"    {st} = 1.0",
            f"cap_r = {cap_r}",
            f"{sr} = 0.0",
            f"{mrc} = {mr}",
            f"if abs({mr}.real) > cap_r.real:",
            f"    {mrc} = cap_r if {mr}.real > 0.0 else -cap_r",
            f"    {sr} = 1.0",
        ]
    return lines


def _capped_function(name, args, doc, exprs, targets, law, zero_lines, caps=True, extra=(),
                     domain=True):
    body, _ = _body(exprs, targets)
    code = _capped_prologue(law, zero_lines, caps, domain) + list(body) + list(extra)
    # Drop prologue names this function never reads (e.g. the branch flags in
    # the force kernel): dead assignments, and lint noise in generated code.
    for var in ("nx", "ny", "hw", *(str(c) for c in law.slides)):
        assign = re.compile(rf"^\s*{var} = ")
        read = re.compile(rf"\b{var}\b")
        if not any(read.search(ln) for ln in code if not assign.match(ln)):
            code = [ln for ln in code if not assign.match(ln)]
    out = ["@kernel_jit", f"def {name}({', '.join(args)}):", f'    """{doc}"""']
    return out + ["    " + ln for ln in code]


def generate_capped_law(law):
    """Source of the generated module for a :class:`symbolic.laws.CappedLaw`."""
    args = [str(s) for s in law.inputs]
    nf, nq = law.jacobian.shape
    nh = len(law.history)
    names = [n for n, _ in law.contact]
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
        "a sliding history follows its cap.  Conventions: symbolic/laws.py,",
        "lee_hurley_pair.  Contact quantities (<law>_contact, out[0:9]): delta, a,",
        f"{', '.join(names)}, {', '.join(str(c) for c in law.capped)}, sliding flag",
        "(0 none, 1 tangential, 2 rolling, 3 both).",
        '"""',
        "",
        "import numpy as np",
        "",
        "from fricstab._numba import kernel_jit",
        "from fricstab._numerics import cylinder_lambda, overlap_correction",
        "",
        f"__all__ = [{', '.join(repr(law.name + s) for s in _CAPPED_SUFFIXES)}]",
        "",
        *_metadata(law, args),
        f"CONTACT = {('delta', 'a', *names, *(str(c) for c in law.capped), 'sliding')!r}",
        "",
        "",
    ]
    fz = [f"for a in range({nf}):", "    f[a] = 0.0"]
    jz = [f"for a in range({nf}):", f"    for b in range({nq}):", "        jac[a, b] = 0.0"]
    lines += _capped_function(
        f"{law.name}_force", args + ["f"],
        "Generalized forces of one contact into f (float64 or complex128).",
        list(law.force), [f"f[{a}]" for a in range(nf)], law, fz, domain=False)
    lines += ["", ""]
    jac_exprs = list(law.force) + [law.jacobian[a, b] for a in range(nf) for b in range(nq)]
    jac_targets = [f"f[{a}]" for a in range(nf)] + [
        f"jac[{a}, {b}]" for a in range(nf) for b in range(nq)]
    lines += _capped_function(
        f"{law.name}_force_jacobian", args + ["f", "jac"],
        "Forces into f and the Jacobian block dF/dq (with history and caps) into jac.",
        jac_exprs, jac_targets, law, fz + jz)
    lines += ["", ""]
    inc_args = [a for a in args if a not in [str(h) for h in law.history]
                and a not in ("mus", "mur")]
    inc = [law.increment[a, b] for a in range(nh) for b in range(nq)]
    lines += _capped_function(
        f"{law.name}_increment", inc_args + ["rate"],
        "Increment rule of the trial histories: d(ft, mr) = rate @ dq (rate: 2 x 6).",
        inc, [f"rate[{a}, {b}]" for a in range(nh) for b in range(nq)], law,
        [f"for a in range({nh}):", f"    for b in range({nq}):", "        rate[a, b] = 0.0"],
        caps=False)
    lines += ["", ""]
    lines += _capped_function(
        f"{law.name}_contact", args + ["out"],
        "Contact quantities into out (9): delta, a, kn, kt, kr, Fn, ftc, mrc, sliding flag.",
        [e for _, e in law.contact], [f"out[{k}]" for k in range(2, 2 + len(names))], law,
        ["for a in range(9):", "    out[a] = 0.0"],
        extra=["out[0] = delta", "out[1] = hw", f"out[6] = {law.capped[0]}",
               f"out[7] = {law.capped[1]}", f"out[8] = {law.slides[0]} + 2.0 * {law.slides[1]}"])
    lines += ["", ""] + _assemble(law, args, nf, nq, nh)
    return "\n".join(lines) + "\n"


_CAPPED_SUFFIXES = ("_force", "_force_jacobian", "_increment", "_contact", "_assemble")
CAPPED_TEMPLATE_VERSION = "2"


def render_all():
    """``{path: source}`` for every generated file."""
    files = {}
    for name in LAWS:
        files[OUT_DIR / f"{name}.py"] = generate_law(derive(name))
    for name in CAPPED_LAWS:
        files[OUT_DIR / f"{name}.py"] = generate_capped_law(derive(name))
    init = ['# generated by `python -m symbolic.codegen`; do not edit.',
            '"""Generated contact-law kernels, one module per law (see symbolic/laws.py).',
            "",
            "LAW_NAMES: the (kn, kt, mu, vector history t) family that the shared",
            "verification harness and its tests sweep; CAPPED_LAW_NAMES: laws with",
            'capped scalar histories and their own verification (fricstab.laws.verify_lee_hurley)."""',
            "", f"LAW_NAMES = {tuple(LAWS)!r}",
            f"CAPPED_LAW_NAMES = {tuple(CAPPED_LAWS)!r}", ""]
    files[OUT_DIR / "__init__.py"] = "\n".join(init)
    return files


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
    return 0


if __name__ == "__main__":
    sys.exit(main())
