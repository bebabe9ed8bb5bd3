"""The front door is documented: every public name has a numpydoc docstring
whose sections match its signature, and the API reference lists every name.

``fricstab._NAMES`` is the front door's table; ``docs/api.md`` is the
reference page Sphinx builds from these docstrings (numpydoc).  A name that
takes arguments must document them (a Parameters section naming each one); a
function must say what it returns (Returns), unless it returns nothing.
"""

import inspect
import re
from pathlib import Path

import pytest

import fricstab
from fricstab.cli import main
from fricstab.laws import ALL_LAW_NAMES

ROOT = Path(__file__).resolve().parent.parent
API = (ROOT / "docs" / "api.md").read_text()


def _sections(doc):
    """numpydoc section name -> body (the lines under a dashed underline)."""
    out, name, body = {}, None, []
    lines = doc.splitlines()
    for k, line in enumerate(lines):
        nxt = lines[k + 1] if k + 1 < len(lines) else ""
        if line.strip() and re.fullmatch(r"-{3,}", nxt.strip() or "x"):
            if name:
                out[name] = "\n".join(body)
            name, body = line.strip(), []
        elif name and not re.fullmatch(r"-{3,}", line.strip() or "x"):
            body.append(line)
    if name:
        out[name] = "\n".join(body)
    return out


def _arguments(obj):
    try:
        sig = inspect.signature(obj)
    except (TypeError, ValueError):
        return []
    return [p.name for p in sig.parameters.values() if p.name != "self"]


def _documented(body):
    """Parameter names of a Parameters section (``a, b : type`` and ``**kw``)."""
    names = set()
    for line in body.splitlines():
        if line and not line[0].isspace():
            head = line.split(":")[0]
            names.update(n.strip().lstrip("*") for n in head.split(","))
    return names


def _returns_nothing(func):
    src = inspect.getsource(func)
    return not re.search(r"^\s+return\s+\S", src, re.M)


CALLABLE = [n for n in fricstab._NAMES if callable(getattr(fricstab, n))]


@pytest.mark.parametrize("name", CALLABLE)
def test_every_argument_is_documented(name):
    obj = getattr(fricstab, name)
    doc = inspect.getdoc(obj) or ""
    summary = doc.splitlines()[0] if doc else ""
    assert summary and not summary.startswith(" "), f"{name}: no one-line summary"
    args = _arguments(obj)
    if isinstance(obj, type) and issubclass(obj, BaseException) and not args:
        return   # an exception class: its docstring says when it is raised
    sections = _sections(doc)
    if args:
        assert "Parameters" in sections, f"{name}: takes {args} but has no Parameters section"
        missing = set(args) - _documented(sections["Parameters"])
        assert not missing, f"{name}: arguments not documented: {sorted(missing)}"
    if inspect.isfunction(obj) and not _returns_nothing(obj):
        assert "Returns" in sections, f"{name}: returns a value but has no Returns section"


@pytest.mark.parametrize("name", [n for n in fricstab._NAMES if n not in CALLABLE])
def test_every_constant_is_described(name):
    # A constant has no docstring of its own: the API page describes it.
    assert re.search(rf"\.\. data:: {name}\n(\s+:.*\n)*\n\s+\S", API), \
        f"{name}: no '.. data::' entry with a description in docs/api.md"


@pytest.mark.parametrize("name", list(fricstab._NAMES))
def test_api_reference_lists_every_name(name):
    listed = re.findall(r"^   (\w+)$", API, re.M) + re.findall(r"\.\. data:: (\w+)", API)
    assert name in listed, f"{name} is not listed in docs/api.md"


def test_laws_lists_the_arguments_of_every_kernel(capsys):
    assert main(["laws"]) == 0
    out = capsys.readouterr().out
    for name in ALL_LAW_NAMES:
        law = fricstab.get_law(name)
        geo = ", ".join(law.geometry_args)
        assert f"{name}_force({', '.join(law.inputs)}, f)" in out
        for kernel in (f"{name}_eval({geo}, p, h, f, jac, want_jac)",
                       f"{name}_rate({geo}, p, a)", f"{name}_project({geo}, p, h)",
                       f"{name}_advance({', '.join(law.advance_geometry_args)}, p, h, "
                       f"{'du' if law.kind == 'wall' else 'dui, duj, dxj'}, f, aux, want_aux)"):
            assert kernel in out, f"`fricstab laws` does not list {kernel}"
        for p, unit in zip(law.params, law.param_units):
            assert f"{p} [{unit}]" in out
