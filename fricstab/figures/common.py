"""What every figure of the command line shares: the backend, saving, SI prefixes.

Label convention (docs/figures.md): every axis and colour bar label ends
with its unit in square brackets, ``quantity [unit]``; a reduced unit is
named by its symbol (``[t_0]``, ``[2R]``, ``[k_N d^{1/2}]``) and defined
in the figure's note; a pure number is ``[-]``.  Each figure function
builds and returns a :class:`matplotlib.figure.Figure`; with ``path`` it
also writes the PNG and closes the figure.
"""

import math

import numpy as np

__all__ = ["UNIT_PATTERN", "finish", "note", "pyplot", "si_scale"]

#: A label's unit: brackets at the end of the label (checked by tests/test_figures.py).
UNIT_PATTERN = r"\[[^\[\]]+\]\s*$"

_PREFIXES = {0: "", -1: "m", -2: "µ", -3: "n", -4: "p", -5: "f", -6: "a", 1: "k", 2: "M",
             3: "G"}


def pyplot():
    """matplotlib.pyplot on the Agg backend (no display needed)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt


def finish(fig, path=None, dpi=110):
    """Lay out ``fig``; with ``path`` write it as PNG and close it.  Returns ``fig``."""
    if path is not None:
        fig.savefig(path, format="png", dpi=dpi)  # atomic writers pass a .tmp name
        pyplot().close(fig)
    return fig


def note(fig, text):
    """A line of unit definitions under the axes (the figure's legend of units)."""
    fig.text(0.005, 0.005, text, fontsize=7, color="0.25", ha="left", va="bottom")


def si_scale(values, unit, power=1):
    """Factor and label that bring ``values`` (in ``unit**power``) to 1-1000 of a prefixed unit.

    ``si_scale(x_in_m, "m")`` gives ``(1e6, "µm")`` for micrometre values;
    ``si_scale(d2_in_m2, "m", 2)`` gives ``(1e12, "µm$^{2}$")``;
    ``si_scale(rate, "s", -1)`` gives ``(1e-6, "µs$^{-1}$")`` for 1e8 / s.
    No finite non-zero value: factor 1 and the bare unit.
    """
    v = np.abs(np.asarray(values, dtype=float))
    v = v[np.isfinite(v) & (v > 0)]
    suffix = "" if power == 1 else f"$^{{{power}}}$"
    if v.size == 0:
        return 1.0, unit + suffix
    k = math.floor(math.log10(v.max()) / (3 * abs(power))) * (1 if power > 0 else -1)
    k = min(max(k, min(_PREFIXES)), max(_PREFIXES))
    return 10.0 ** (-3 * k * power), _PREFIXES[k] + unit + suffix
