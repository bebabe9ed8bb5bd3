"""Sphinx configuration of the fricstab documentation.

Build (warnings are errors): ``python -m sphinx -W -b html docs docs/_build/html``.
The tutorials are MyST-NB text notebooks, executed on every build (no cache),
so that they cannot rot.
"""

import os
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
# The tutorials' kernels import fricstab from this checkout too.
os.environ["PYTHONPATH"] = os.pathsep.join(
    [str(ROOT), *filter(None, [os.environ.get("PYTHONPATH")])])

import fricstab  # noqa: E402

project = "fricstab"
author = "the fricstab authors"
copyright = "2026, the fricstab authors"
release = version = fricstab.__version__

extensions = [
    "myst_nb",
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.mathjax",
    "numpydoc",
]
exclude_patterns = ["_build", "**.ipynb_checkpoints", "jupyter_execute"]
source_suffix = {".rst": "restructuredtext", ".md": "myst-nb"}

# The validation reports included as they stand skip heading levels
# (shear_sweep.md: H1 then H3).
suppress_warnings = ["myst.header"]

# MyST: $...$ maths, ::: fences, heading anchors for links within pages.
myst_enable_extensions = ["dollarmath", "colon_fence", "deflist"]
myst_heading_anchors = 3

# MyST-NB: execute every notebook on every build (no cache: they cannot rot),
# fail the build on any error in a cell.
nb_execution_mode = "force"
nb_execution_timeout = 300
nb_execution_raise_on_error = True
nb_execution_show_tb = True
nb_merge_streams = True

# API reference: autosummary pages from the numpydoc docstrings of the front door.
autosummary_generate = True
autodoc_default_options = {"members": False}
autodoc_typehints = "none"
numpydoc_show_class_members = False
numpydoc_class_members_toctree = False

html_theme = "furo"
html_title = f"fricstab {release}"


# Pages that other work adds (the figure list, figures.md) are named in the
# toctree of index.md; until such a page exists its entry is dropped, so the
# build stays warning-free either way.
OPTIONAL_PAGES = ("figures",)


def _drop_absent_pages(app, docname, source):
    if docname == "index":
        for page in OPTIONAL_PAGES:
            if not (Path(app.srcdir) / f"{page}.md").exists():
                source[0] = source[0].replace(f"\n{page}\n", "\n")


def setup(app):
    app.connect("source-read", _drop_absent_pages)
