"""Which code a claim's values depend on, as hashes that change when that code changes.

A claim is recomputed in a process of its own (``reproduce.py`` starts one
per claim) that imports only the claim machinery and the claim's section
module.  After ``compute`` returns, the dependence is read off that process:

* every module of the checkout (``fricstab/``, ``validation/``, ``tests/``) in
  ``sys.modules``: Python runs no code of a module it has not imported, and
  numba compiles only functions of imported modules, so the set is a
  superset of the code that ran (sound, and coarse: a module imported but
  not used counts too).  The generated kernels are modules like any other;
  ``codegen --check`` ties them to ``symbolic/``.
* the claim's own ``compute`` and what it names in its section module
  (a static closure over the module's top-level definitions), so that
  adding a claim beside it does not mark it stale.
* the data files the claim declares (``inputs``), by their bytes.

A module's hash is that of its syntax tree with docstrings removed
(``ast.dump``): comments, docstrings and formatting do not change what
runs, so editing them does not make a claim stale.  Not covered, and said
so in the docs: versions of NumPy, SciPy and numba (recorded with each
value, not compared), and the machine.  Claims of the ``seconds`` tier are
recomputed in CI, which covers those too for them.
"""

import ast
import hashlib
import inspect
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
WATCHED = ("fricstab", "validation", "tests")
#: the claim machinery itself: not a dependence of any claim's values (section modules
#: of validation/claims/ enter by the claim's closure; helpers named _*.py whole)
MACHINERY = {f"validation/claims/{m}.py" for m in
             ("__init__", "core", "fingerprint", "records", "render", "runner")}
MACHINERY |= {"validation/reproduce.py"}


def _strip_docstrings(tree):
    for node in ast.walk(tree):
        if isinstance(node, (ast.Module, ast.ClassDef, ast.FunctionDef, ast.AsyncFunctionDef)):
            body = node.body
            if body and isinstance(body[0], ast.Expr) and isinstance(body[0].value, ast.Constant) \
                    and isinstance(body[0].value.value, str):
                node.body = body[1:] or [ast.Pass()]
    return tree


def source_hash(text):
    """Hash of Python source: its syntax tree without docstrings."""
    tree = _strip_docstrings(ast.parse(text))
    return hashlib.sha256(ast.dump(tree, include_attributes=False).encode()).hexdigest()[:16]


def module_hash(rel, root=ROOT):
    """Hash of the module at ``rel`` (relative to ``root``); 'missing' if it is gone."""
    path = Path(root) / rel
    if not path.exists():
        return "missing"
    return source_hash(path.read_text())


def file_hash(rel, root=ROOT):
    """Hash of a data file's bytes; 'missing' if it is gone."""
    path = Path(root) / rel
    if not path.exists():
        return "missing"
    return hashlib.sha256(path.read_bytes()).hexdigest()[:16]


def loaded_modules(root=ROOT):
    """Modules of the checkout in ``sys.modules`` (paths relative to ``root``)."""
    root = Path(root).resolve()
    out = set()
    for mod in list(sys.modules.values()):
        f = getattr(mod, "__file__", None)
        if not f or not f.endswith(".py"):
            continue
        try:
            rel = Path(f).resolve().relative_to(root).as_posix()
        except ValueError:
            continue
        if rel.split("/")[0] not in WATCHED or rel in MACHINERY:
            continue
        if rel.startswith("validation/claims/") and not Path(rel).name.startswith("_"):
            continue      # a section module: its claim's closure is hashed instead
        out.add(rel)
    return out


def closure_hash(func, root=ROOT):
    """Hash of ``func``'s definition and of every top-level definition of its module
    that it names, transitively (the claim's own code, not its neighbours')."""
    rel, names = closure(func, root)
    return unit_hash(rel, names, root)


def closure(func, root=ROOT):
    """(module path, sorted top-level names) reached from ``func`` by name."""
    path = Path(inspect.getsourcefile(func)).resolve()
    rel = path.relative_to(Path(root).resolve()).as_posix()
    defs = _top_level(path.read_text())
    if func.__name__ not in defs or getattr(defs[func.__name__], "name", None) != func.__name__:
        raise ValueError(f"{rel}: a claim's compute must be a top-level function "
                         f"(got {func.__qualname__}); its hash is that of its definition")
    seen, todo = set(), [func.__name__]
    while todo:
        n = todo.pop()
        if n in seen or n not in defs:
            continue
        seen.add(n)
        todo.extend(x.id for x in ast.walk(defs[n]) if isinstance(x, ast.Name))
        todo.extend(x.value.id for x in ast.walk(defs[n])
                    if isinstance(x, ast.Attribute) and isinstance(x.value, ast.Name))
    return rel, sorted(seen)


def unit_hash(rel, names, root=ROOT):
    """Hash of the named top-level definitions of module ``rel``; 'missing' if one is gone."""
    path = Path(root) / rel
    if not path.exists():
        return "missing"
    defs = _top_level(path.read_text())
    if any(n not in defs for n in names):
        return "missing"
    text = "\n".join(ast.dump(_strip_docstrings(ast.Module([defs[n]], [])),
                              include_attributes=False) for n in names)
    return hashlib.sha256(text.encode()).hexdigest()[:16]


def _top_level(text):
    """name -> node for the top-level functions, classes and assignments of a module."""
    defs = {}
    for node in ast.parse(text).body:
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)):
            defs[node.name] = node
        elif isinstance(node, (ast.Assign, ast.AnnAssign)):
            targets = node.targets if isinstance(node, ast.Assign) else [node.target]
            for t in targets:
                for x in ast.walk(t):
                    if isinstance(x, ast.Name):
                        defs[x.id] = node
        elif isinstance(node, (ast.Import, ast.ImportFrom)):
            for a in node.names:
                defs[(a.asname or a.name).split(".")[0]] = node
    return defs


def fingerprint(claim, root=ROOT):
    """The dependence of ``claim`` as recorded now (call after ``compute`` ran, in
    the claim's own process)."""
    rel, names = closure(claim.compute, root)
    return {
        "modules": {m: module_hash(m, root) for m in sorted(loaded_modules(root))},
        "claim": {"module": rel, "names": names, "hash": unit_hash(rel, names, root)},
        "inputs": {f: file_hash(f, root) for f in claim.inputs},
    }


def changes(fp, root=ROOT):
    """What changed since fingerprint ``fp`` was taken: a list of paths (empty: fresh)."""
    out = [m for m, h in fp["modules"].items() if module_hash(m, root) != h]
    c = fp["claim"]
    if unit_hash(c["module"], c["names"], root) != c["hash"]:
        out.append(f"{c['module']} ({', '.join(c['names'])})")
    out += [f for f, h in fp["inputs"].items() if file_hash(f, root) != h]
    return out
