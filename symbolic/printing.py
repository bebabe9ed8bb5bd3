"""Printing SymPy expressions as numba kernel source (shared by the code generators).

:class:`KernelPrinter` writes Python that numba compiles for float64 and
complex128 (``np.sqrt``, ``np.log``, small integer powers as products, floats
for rationals); :func:`body` eliminates common subexpressions and assigns the
results to target slots; :func:`kernel` wraps lines into a ``@kernel_jit``
function.
"""

import sympy as sp
from sympy.printing.pycode import PythonCodePrinter

__all__ = ["KernelPrinter", "body", "code", "geometry_block", "kernel", "zero_mat", "zero_vec"]


class KernelPrinter(PythonCodePrinter):
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


_printer = KernelPrinter({"fully_qualified_modules": False})


def code(expr):
    """Kernel source of one expression."""
    return _printer.doprint(expr)


def body(exprs, targets, prefix="c"):
    """CSE the expressions and assign them to the target slots."""
    replacements, reduced = sp.cse(exprs, symbols=sp.numbered_symbols(prefix), order="canonical")
    lines = [f"{s} = {code(e)}" for s, e in replacements]
    lines += [f"{t} = {code(e)}" for t, e in zip(targets, reduced)]
    used = set()
    for e in list(exprs):
        used |= {str(s) for s in e.free_symbols}
    return lines, used


def geometry_block(exprs):
    """CSE of geometry-only expressions (prefix g): (lines, reduced expressions)."""
    replacements, reduced = sp.cse(exprs, symbols=sp.numbered_symbols("g"), order="canonical")
    return [f"{s} = {code(e)}" for s, e in replacements], reduced


def kernel(name, args, doc, lines, decorator="hot_jit"):
    """A jitted function ``name(args)`` with docstring ``doc`` and body ``lines``.

    ``decorator``: ``hot_jit`` (no reference counting, no allocation: every
    kernel the engine calls per contact; :mod:`fricstab._numba`) or
    ``kernel_jit`` (a function that allocates).
    """
    return [f"@{decorator}", f"def {name}({', '.join(args)}):", f'    """{doc}"""'] + \
        ["    " + ln for ln in lines]


def zero_vec(arr, n):
    """Lines setting ``arr[0:n]`` to 0."""
    return [f"for k in range({n}):", f"    {arr}[k] = 0.0"] if n else []


def zero_mat(arr, n, m):
    """Lines setting ``arr[0:n, 0:m]`` to 0."""
    return [f"for k in range({n}):", f"    for b in range({m}):", f"        {arr}[k, b] = 0.0"] \
        if n * m else []
