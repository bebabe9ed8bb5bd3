"""Which code a claim's values depend on, as hashes that change when that code changes.

A claim is recomputed in a process of its own (``reproduce.py`` starts one
per job) that imports only the claim machinery and the claim's section
module.  While ``compute`` runs, a :class:`Tracer` notes every Python
function of the checkout (``fricstab/``, ``validation/``, ``tests/``) that
starts running; after it returns, the dependence is read off that process:

* **functions**: for every module of the checkout in ``sys.modules``, the
  hash of each top-level function or method that ran, or that numba
  compiled (every live numba dispatcher's ``py_func``), and the hash of the
  module's *frame*: everything at top level except the bodies of its
  functions (imports, constants, class bodies, decorators, the names of
  methods and of functions that shadow another binding).  A function that
  did not run cannot have changed the values, so editing it, or adding a
  new one, leaves the claim fresh; editing one that ran, or any statement
  that runs at import, makes it stale.
* **whole modules** where a function-level record would not be sound, each
  hashed as a whole (as Python imported it):

  - modules that use numba (they import from ``numba`` or ``fricstab._numba``):
    a jitted function's Python body never runs, and numba inlines what it
    calls; the generated kernels are such modules, and ``codegen --check``
    ties them to ``symbolic/``;
  - test modules (``tests/``, ``validation/test_*.py``, ``conftest.py``):
    pytest finds tests by name, so a new test changes what runs;
  - every module, when the computation started another process (``fork``,
    ``subprocess``, ``multiprocessing``, dask workers): code run there is not
    traced here (``git``, with which a record names its revision, runs none of
    ours and does not count);
  - every module when another trace function was set while the claim ran (a
    debugger, coverage, hypothesis's explain phase): calls may have gone unseen;
  - every module, for a claim that asks for it (``Claim.trace = False``, for
    claims whose values are timings: tracing slows Python code down).
* the claim's own ``compute`` and what it names in its section module
  (a static closure over the module's top-level definitions), so that
  adding a claim beside it does not mark it stale.
* the data files the claim declares (``inputs``), by their bytes.

A module of the checkout whose file changes on disk while a computation runs (an edit
during a long run) is hashed as this process loaded it: the texts of the watched files
are read when this module is imported (:data:`SNAPSHOT`), at the start of the claim's or
script's process, and a file modified since the process started is hashed from that text,
so the stamp names the code that ran, and the result goes stale if the edit changed it.
A file already modified between the process's start and that snapshot is ambiguous when
its module was imported before the snapshot (:data:`PRELOADED`): its units are recorded as
:data:`EDITED`, which matches no hash (stale at once).  A module imported after the snapshot
from a file unchanged since (the same modification time) ran the snapshot's text (a file a
``git clone`` wrote just before ``pytest``: ``validation/conftest.py`` imports this module
before any test module).

Hashes are of syntax trees with docstrings removed (``ast.dump``): comments,
docstrings and formatting do not change what runs, so editing them does not
make a claim stale.  Not covered, and said so in the docs: versions of
NumPy, SciPy and numba (recorded with each value, not compared), the
machine, and code reached in ways Python does not show as a call (a
function looked up by a name built at run time, in a module whose frame did
not change, that did not exist when the claim ran).  Claims of the
``seconds`` tier are recomputed in CI, which covers those too for them.
"""

import ast
import gc
import hashlib
import inspect
import os
import sys
import threading
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
WATCHED = ("fricstab", "validation", "tests")
#: the claim machinery itself: not a dependence of any claim's values (section modules
#: of validation/claims/ enter by the claim's closure; helpers named _*.py whole)
MACHINERY = {f"validation/claims/{m}.py" for m in
             ("__init__", "core", "fingerprint", "records", "render", "runner")}
MACHINERY |= {"validation/reproduce.py"}
FRAME = "<frame>"      # the key of a module's frame among its units
#: the hash of a unit whose module's text as run is unknown: matches no hash
EDITED = "edited-while-running"


def _process_start():
    """Wall-clock time at which this process started, never later than it (Linux: its start
    in clock ticks since boot, from /proc/self/stat, on the boot clock of /proc/uptime, read
    with the wall clock: within a tick or two; elsewhere now, at the import of this module,
    which the validation scripts import before they compute).  /proc/stat's ``btime`` is
    whole seconds: a file written in the second or two before the process (a ``git clone``
    or ``pull`` just before ``pytest``) then looked edited while it ran."""
    now = time.time()
    try:
        tick = 1.0 / os.sysconf("SC_CLK_TCK")
        with open("/proc/self/stat") as f:
            ticks = float(f.read().rsplit(")", 1)[1].split()[19])
        with open("/proc/uptime") as f:
            up = float(f.read().split()[0])
        # uptime printed to 0.01 s and the start floored to a tick: two of each early
        return min(time.time() - up + ticks * tick - 2 * (tick + 0.01), now)
    except (OSError, ValueError, IndexError):
        return now


#: modification times after this are edits made while this process ran
STARTED = _process_start()


def _snapshot(root=ROOT):
    out = {}
    for top in WATCHED:
        for path in (root / top).rglob("*.py"):
            try:
                out[path.relative_to(root).as_posix()] = (path.read_text(),
                                                          path.stat().st_mtime)
            except (OSError, UnicodeDecodeError):
                pass
    return out


#: {path: (text, mtime)} of the watched files when this module was imported
SNAPSHOT = _snapshot()
_WARNED = set()


def _warn(m, what):
    if m not in _WARNED:
        _WARNED.add(m)
        print(f"warning: {m} changed on disk while this process ran: {what}",
              file=sys.stderr, flush=True)


def _source(m, root):
    """``(text, edited)``: module ``m``'s text as this process ran it; ``edited`` when that
    is unknown (module docstring)."""
    path = Path(root) / m
    text = path.read_text()
    if Path(root).resolve() != ROOT.resolve() or path.stat().st_mtime <= STARTED:
        return text, False
    snap = SNAPSHOT.get(m)
    if snap is not None and (snap[1] <= STARTED or (m not in PRELOADED
                                                   and path.stat().st_mtime == snap[1])):
        if snap[0] != text:
            _warn(m, "stamped with the text this process loaded")
        return snap[0], False
    _warn(m, "the text that ran is unknown; what it computed is recorded as stale")
    return text, True


def _strip_docstrings(tree):
    for node in ast.walk(tree):
        if isinstance(node, (ast.Module, ast.ClassDef, ast.FunctionDef, ast.AsyncFunctionDef)):
            body = node.body
            if body and isinstance(body[0], ast.Expr) and isinstance(body[0].value, ast.Constant) \
                    and isinstance(body[0].value.value, str):
                node.body = body[1:] or [ast.Pass()]
    return tree


def _digest(nodes):
    text = "\n".join(ast.dump(n, include_attributes=False) for n in nodes)
    return hashlib.sha256(text.encode()).hexdigest()[:16]


def source_hash(text):
    """Hash of Python source: its syntax tree without docstrings."""
    return _digest([_strip_docstrings(ast.parse(text))])


def module_hash(rel, root=ROOT):
    """Hash of the module at ``rel`` (relative to ``root``); 'missing' if it is gone."""
    path = Path(root) / rel
    if not path.exists():
        return "missing"
    return source_hash(path.read_text())


def package_files(package="fricstab", root=ROOT, exclude=("cli",)):
    """The Python files of ``package`` (relative paths, sorted), but those under a folder
    named in ``exclude``."""
    base = Path(root)
    return tuple(sorted(p.relative_to(base).as_posix() for p in (base / package).rglob("*.py")
                        if not set(p.relative_to(base).parts) & set(exclude)))


def file_hash(rel, root=ROOT):
    """Hash of a data file's bytes; 'missing' if it is gone."""
    path = Path(root) / rel
    if not path.exists():
        return "missing"
    return hashlib.sha256(path.read_bytes()).hexdigest()[:16]


# ------------------------------------------------------------------ function units

_FUNCS = (ast.FunctionDef, ast.AsyncFunctionDef)


def _bound_names(stmts):
    """Names bound at this scope by statements other than function definitions."""
    out = set()
    for s in stmts:
        if isinstance(s, _FUNCS):
            continue
        if isinstance(s, ast.ClassDef):
            out.add(s.name)
            continue
        if isinstance(s, (ast.Import, ast.ImportFrom)):
            out |= {(a.asname or a.name).split(".")[0] for a in s.names}
            continue
        for x in ast.walk(s):
            if isinstance(x, ast.Name) and isinstance(x.ctx, ast.Store):
                out.add(x.id)
            elif isinstance(x, _FUNCS + (ast.ClassDef,)):
                out.add(x.name)
    return out


def _stub(fn):
    """What a definition contributes to the frame: its name and decorators."""
    return ast.FunctionDef(name=fn.name, args=ast.arguments([], [], None, [], [], None, []),
                           body=[ast.Pass()], decorator_list=fn.decorator_list, returns=None,
                           type_comment=None)


def _split(body, prefix, units, in_class):
    """The frame of a scope (module or class body) and, into ``units``, its functions."""
    names = [s.name for s in body if isinstance(s, _FUNCS)]
    shadow = _bound_names(body) | {n for n in names if names.count(n) > 1}
    frame = []
    for s in body:
        if isinstance(s, _FUNCS):
            q = prefix + s.name
            units.setdefault(q, []).append(s)
            if in_class or s.decorator_list or s.name in shadow or s.name.startswith("__"):
                frame.append(_stub(s))
        elif isinstance(s, ast.ClassDef):
            inner = _split(s.body, f"{prefix}{s.name}.", units, True)
            frame.append(ast.ClassDef(name=s.name, bases=s.bases, keywords=s.keywords,
                                      body=inner or [ast.Pass()],
                                      decorator_list=s.decorator_list))
        else:
            frame.append(s)
    return frame


def unit_hashes(text):
    """{FRAME: hash of the module's frame, qualname: hash of that function} for source text."""
    tree = _strip_docstrings(ast.parse(text))
    units = {}
    frame = _split(tree.body, "", units, False)
    out = {k: _digest(v) for k, v in units.items()}
    out[FRAME] = _digest(frame)
    return out


def uses_numba(text):
    """True if the module imports numba or the package's numba helpers outside its
    functions (an import inside a function, to print numba's version say, compiles
    nothing; a dispatcher made inside a function is found alive by :func:`ran_units`)."""
    todo = list(ast.parse(text).body)
    while todo:
        node = todo.pop()
        if isinstance(node, _FUNCS):
            continue
        if isinstance(node, ast.Import) and any("numba" in a.name for a in node.names):
            return True
        if isinstance(node, ast.ImportFrom) and "numba" in (node.module or ""):
            return True
        todo.extend(ast.iter_child_nodes(node))
    return False


def whole_module(rel, text):
    """Modules hashed as a whole (see the module docstring): numba users and tests."""
    name = Path(rel).name
    return (rel.startswith("tests/") or name == "conftest.py"
            or (rel.startswith("validation/") and name.startswith("test_"))
            or uses_numba(text))


def unit_of(qualname):
    """The unit (top-level function or method qualname) a code object belongs to;
    FRAME for module and class bodies and what runs at import."""
    q = qualname.split(".<locals>")[0]
    parts = [p for p in q.split(".") if not p.startswith("<")]
    return ".".join(parts) if parts else FRAME


class Tracer:
    """Notes each Python code object that starts running (``sys.settrace`` and
    ``threading.settrace``, 'call' events only), and whether another process was
    started (``fork``, ``subprocess``, ``multiprocessing``, ``os.system``/``posix_spawn``)."""

    def __init__(self):
        self.codes = {}
        self.spawned = False
        self.lost = False       # someone else set a trace function: calls may be unseen
        self.active = False
        self._harmless = 0
        self._saved = []

    def _trace(self, frame, event, arg):
        code = frame.f_code
        self.codes[id(code)] = code
        return None

    def _flag(self, *a, **k):
        if self.active:
            self.spawned = True

    #: programs that run no Python of the checkout: starting them is not a spawn that
    #: hides code from the tracer (``git``: the revision a record names)
    HARMLESS = frozenset({"git"})

    def _wrap(self, owner, name):
        orig = getattr(owner, name, None)
        if orig is None:
            return
        tracer = self

        def wrapped(*a, **k):
            if not tracer._harmless:
                tracer._flag()
            return orig(*a, **k)
        self._saved.append((owner, name, orig))
        setattr(owner, name, wrapped)

    def _wrap_popen(self, popen):
        """``Popen._execute_child``: a harmless program (not a shell) is let through, and
        the ``os.posix_spawn`` or ``fork_exec`` it calls is not counted either."""
        orig = popen._execute_child
        tracer = self

        def wrapped(obj, args, executable, *a, **k):
            shell = k.get("shell", a[7] if len(a) > 7 else True)
            prog = executable or (args if isinstance(args, (str, bytes)) else args[0])
            harmless = not shell and Path(os.fsdecode(prog)).name in tracer.HARMLESS
            if not harmless:
                tracer._flag()
            tracer._harmless += harmless
            try:
                return orig(obj, args, executable, *a, **k)
            finally:
                tracer._harmless -= harmless
        self._saved.append((popen, "_execute_child", orig))
        popen._execute_child = wrapped

    def __enter__(self):
        import _posixsubprocess
        import subprocess
        self._wrap(_posixsubprocess, "fork_exec")          # multiprocessing's spawn
        self._wrap_popen(subprocess.Popen)                 # every subprocess but git
        for name in ("system", "posix_spawn", "posix_spawnp", "spawnv", "spawnve"):
            self._wrap(os, name)
        os.register_at_fork(before=self._flag)   # cannot be removed: inactive after exit
        self.active = True
        self._old = sys.gettrace()
        sys.settrace(self._trace)
        threading.settrace(self._trace)
        self._settrace = sys.settrace
        tracer = self

        def settrace(func):     # a debugger, coverage, hypothesis's explain phase
            # but not a new thread installing our own hook (threading.settrace above):
            # its calls are traced, so a thread keeps the record function-level
            if func != tracer._trace:
                tracer.lost = True
            return tracer._settrace(func)
        sys.settrace = settrace
        return self

    def __exit__(self, *exc):
        sys.settrace = self._settrace
        if sys.gettrace() != self._trace:
            self.lost = True
        sys.settrace(self._old)
        threading.settrace(None)
        for owner, name, orig in reversed(self._saved):
            setattr(owner, name, orig)
        self._saved.clear()
        self.active = False
        return False


def _rel(filename, root):
    try:
        return Path(filename).resolve().relative_to(root).as_posix()
    except (ValueError, OSError):
        return None


def _watched(rel):
    if rel is None or not rel.endswith(".py") or rel.split("/")[0] not in WATCHED \
            or rel in MACHINERY:
        return False
    # a section module: its claim's closure is hashed instead
    return not (rel.startswith("validation/claims/") and not Path(rel).name.startswith("_"))


def loaded_modules(root=ROOT):
    """Modules of the checkout in ``sys.modules`` (paths relative to ``root``)."""
    root = Path(root).resolve()
    out = set()
    for mod in list(sys.modules.values()):
        f = getattr(mod, "__file__", None)
        rel = _rel(f, root) if f else None
        if _watched(rel):
            out.add(rel)
    return out


#: checkout modules already imported when :data:`SNAPSHOT` was taken (they may have read a
#: text older than the snapshot's)
PRELOADED = frozenset(loaded_modules())


def ran_units(codes, root=ROOT):
    """{module path: set of units} for the code objects that ran or that numba compiled."""
    root = Path(root).resolve()
    found = list(codes)
    if "numba" in sys.modules:
        from numba.core.dispatcher import Dispatcher
        found += [o.py_func.__code__ for o in gc.get_objects()
                  if isinstance(o, Dispatcher) and hasattr(o.py_func, "__code__")]
    cache, out = {}, {}
    for code in found:
        f = code.co_filename
        if f not in cache:
            cache[f] = _rel(f, root)
        rel = cache[f]
        if _watched(rel):
            out.setdefault(rel, set()).add(unit_of(code.co_qualname))
    return out


# ------------------------------------------------------------------ the claim's closure

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


# ------------------------------------------------------------------ record and compare

def _hashes(m, root, whole=False):
    """``(hash, None)`` for module ``m`` hashed whole (``whole``, or a module
    :func:`whole_module` keeps whole), else ``(None, {unit: hash})``: of the text this process
    ran (:func:`_source`), :data:`EDITED` where that is unknown."""
    text, edited = _source(m, root)
    if whole or whole_module(m, text):
        return (EDITED if edited else source_hash(text)), None
    return None, ({u: EDITED for u in unit_hashes(text)} if edited else unit_hashes(text))


def fingerprint(claim, root=ROOT, tracer=None):
    """The dependence of ``claim`` as recorded now (call after ``compute`` ran, in
    the claim's own process; ``tracer`` is the :class:`Tracer` it ran under, None
    for a claim that is not traced: then every loaded module counts whole)."""
    rel, names = closure(claim.compute, root)
    whole, units = {}, {}
    ran = (ran_units(tracer.codes.values(), root)
           if tracer and not (tracer.spawned or tracer.lost) else None)
    for m in sorted(loaded_modules(root)):
        whole_hash, hashes = _hashes(m, root, whole=ran is None)
        if hashes is None:
            whole[m] = whole_hash
            continue
        # a unit that ran but is no top-level function (one defined inside an if, say):
        # the frame holds it
        units[m] = {u: hashes[u] for u in sorted(ran.get(m, set()) | {FRAME}) if u in hashes}
    fp = {"modules": whole}
    if ran is not None:
        fp["functions"] = units
    fp["claim"] = {"module": rel, "names": names, "hash": unit_hash(rel, names, root)}
    fp["inputs"] = {f: file_hash(f, root) for f in claim.inputs}
    return fp


def code_units(tracer, root=ROOT, skip=("fricstab/cli/",)):
    """The dependence of a cached computation that ran under ``tracer``: ``{module: {unit:
    hash}}`` of the checkout code it executed (a numba module whole, as ``"*"``), modules
    under a prefix in ``skip`` left out; None where the tracer could not see every call
    (then only a hash of whole modules is safe).  Compare later with :func:`units_changed`."""
    if tracer.spawned or tracer.lost:
        return None
    ran = ran_units(tracer.codes.values(), root)
    out = {}
    for m in sorted(loaded_modules(root) | set(ran)):
        if m.startswith(tuple(skip)) or not (Path(root) / m).exists():
            continue
        whole_hash, hashes = _hashes(m, root)
        if hashes is None:
            out[m] = {"*": whole_hash}
            continue
        # a validation script's own frame (its tables, constants) is not the computation's
        frame = set() if m.startswith("validation/") else {FRAME}
        out[m] = {u: hashes[u] for u in sorted(ran.get(m, set()) | frame) if u in hashes}
    return out


def add_units(fp, units):
    """``fp`` (:func:`fingerprint`) with the code ``units`` (:func:`code_units`) of cached
    computations merged in: a whole module (``"*"``) into its modules, functions into its
    functions.  ``units`` None: ``fp`` unchanged."""
    for m, u in (units or {}).items():
        if "*" in u:
            fp["modules"][m] = u["*"]
        else:
            fp.setdefault("functions", {}).setdefault(m, {}).update(u)
    return fp


def units_changed(units, root=ROOT):
    """The modules of ``units`` (from :func:`code_units`) whose executed code changed since."""
    out = []
    for m, old in units.items():
        path = Path(root) / m
        if not path.exists():
            out.append(m)
            continue
        text = path.read_text()
        new = {"*": source_hash(text)} if "*" in old else unit_hashes(text)
        if any(new.get(u, "missing") != h for u, h in old.items()):
            out.append(m)
    return out


def changes(fp, root=ROOT):
    """What changed since fingerprint ``fp`` was taken: a list of paths (empty: fresh);
    a function-level change names the module and the functions."""
    out = [m for m, h in fp["modules"].items() if module_hash(m, root) != h]
    for m, old in fp.get("functions", {}).items():
        path = Path(root) / m
        if not path.exists():
            out.append(m)
            continue
        new = unit_hashes(path.read_text())
        moved = [u for u, h in old.items() if new.get(u, "missing") != h]
        if moved:
            out.append(f"{m} ({', '.join(moved[:4])}{', ...' if len(moved) > 4 else ''})")
    c = fp["claim"]
    if unit_hash(c["module"], c["names"], root) != c["hash"]:
        out.append(f"{c['module']} ({', '.join(c['names'])})")
    out += [f for f, h in fp["inputs"].items() if file_hash(f, root) != h]
    return out
