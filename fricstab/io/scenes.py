"""Scene schemas: every key of a scene file, with its type, default, unit and range.

A scene is a flat table of parameters, read from TOML (keys at the top level
or under a table named after the scene, e.g. ``[chain]``), then overridden by
command-line options, then validated against the scene's :class:`Schema`.
Validation happens before any work: an unknown key, a wrong type or a value
out of range raises :class:`fricstab.laws.ParameterError` with one line
naming the key, the value and what is allowed.

Types (``Field.type``)
----------------------
``int``     a TOML integer (never a boolean; ``32.0`` is not an integer).
``float``   a finite TOML number (integers accepted, returned as float).
``str``     a string, usually one of ``choices``.
``bool``    ``true`` or ``false``.
``floats``  a finite number or a non-empty list of them (returned as a list).

Registering a scene
-------------------
A protocol module registers its schema at import time::

    from fricstab.io.scenes import Field, Schema, register
    register(Schema("shear", "plane shear cell", (
        Field("mu_s", "float", 0.7, "-", "sliding friction coefficient", low=0.0),
    )))

``fricstab scene show NAME`` prints :func:`show` for it.

Contact laws
------------
A scene that runs any verified law declares a :class:`LawChoice`: its paper's
law and every law's default parameters in the scene's units.  Its files then
take ``law = "NAME"`` and that law's parameters as top-level keys (``kn``,
``kt``, ``mu``, ``E``, ``nu``, ``mus``, ``mur``, ``Rw``, as ``fricstab laws``
names them).  A parameter of another law is refused with the one line saying
what the chosen law takes; a missing one gets the scene's default (which may
depend on other keys, e.g. ``kt = 2 kn / 7``).  :func:`validate` returns them
as ``law``, ``law_params`` and ``wall_params`` (the wall form's extra ones).
"""

import math
import tomllib
from dataclasses import dataclass
from pathlib import Path

from fricstab.laws import ParameterError

__all__ = ["Derived", "Field", "LawChoice", "add_law_options", "law_overrides", "Schema", "register", "get", "names", "load_toml", "validate",
           "resolve", "show"]

TYPES = ("int", "float", "str", "bool", "floats")
_REGISTRY = {}

#: The window of a dimensional value (a length, mass, force, stiffness, modulus):
#: beyond it the products of a scene's scales (m R^2, k_n R^(3/2) delta^(3/2),
#: eigenvalues k/m) leave float64, sub-normal or infinite.
SCALE_LOW, SCALE_HIGH = 1e-30, 1e30
SCALE_DOC = ("0 or |value| in [1e-30, 1e30] (beyond it the products of the scene's scales "
             "leave float64)")


def in_scale_window(value):
    """True for 0 and for ``SCALE_LOW <= |value| <= SCALE_HIGH``."""
    return value == 0 or SCALE_LOW <= abs(value) <= SCALE_HIGH


def _short(value, limit=60):
    """``repr`` on one line, cut to ``limit`` characters (messages stay one line)."""
    text = " ".join(repr(value).split())
    return text if len(text) <= limit else text[:limit - 3] + "..."


@dataclass(frozen=True)
class Field:
    """One scene key.

    Parameters
    ----------
    key : str
        The key in the scene file; the command-line option is ``--key`` with
        ``_`` written ``-`` unless ``cli`` names another.
    type : {'int', 'float', 'str', 'bool', 'floats'}
    default : object
        Value when neither the scene file nor the command line gives one;
        ``None`` means derived from other keys (``default_doc`` says how).
    unit : str
        Physical unit, ``-`` when dimensionless.
    doc : str
        One line on what the key does (and what it trades, for numerical knobs).
    low, high : float, optional
        Range bounds; inclusive unless ``low_open`` / ``high_open``.
    choices : tuple of str, optional
        Allowed values of a ``str`` key.
    """

    key: str
    type: str
    default: object
    unit: str
    doc: str
    low: float = None
    high: float = None
    low_open: bool = False
    high_open: bool = False
    choices: tuple = None
    default_doc: str = None
    cli: str = None
    check: object = None      # extra predicate on the typed value (each item of ``floats``)
    check_doc: str = None     # its words, appended to :meth:`allowed`

    def __post_init__(self):
        if self.type not in TYPES:
            raise ValueError(f"Field {self.key}: type must be one of {TYPES}, got {self.type!r}")

    @property
    def option(self):
        return self.cli or "--" + self.key.replace("_", "-")

    def allowed(self):
        """The allowed values, in words (used in error messages and :func:`show`)."""
        base = self._allowed()
        return f"{base}, {self.check_doc}" if self.check_doc else base

    def _allowed(self):
        if self.type == "bool":
            return "true or false"
        if self.type == "str":
            return ("one of " + ", ".join(self.choices)) if self.choices else "a string"
        noun = {"int": "an integer", "float": "a finite number",
                "floats": "a finite number or a non-empty list of them"}[self.type]
        lo = None if self.low is None else ("> " if self.low_open else ">= ") + f"{self.low:g}"
        hi = None if self.high is None else ("< " if self.high_open else "<= ") + f"{self.high:g}"
        if lo and hi:
            if self.type == "floats":
                return f"{noun}, each in {'(' if self.low_open else '['}{self.low:g}, " \
                       f"{self.high:g}{')' if self.high_open else ']'}"
            return f"{noun} in {'(' if self.low_open else '['}{self.low:g}, " \
                   f"{self.high:g}{')' if self.high_open else ']'}"
        bound = lo or hi
        if bound is None:
            return noun
        return f"{noun}{', each' if self.type == 'floats' else ''} {bound}"

    def _in_range(self, v):
        if self.low is not None and (v < self.low or (self.low_open and v == self.low)):
            return False
        if self.high is not None and (v > self.high or (self.high_open and v == self.high)):
            return False
        return True

    def convert(self, value):
        """The typed value, or None when ``value`` is not allowed."""
        if self.type == "bool":
            return value if isinstance(value, bool) else None
        if self.type == "str":
            if not isinstance(value, str) or (self.choices and value not in self.choices):
                return None
            return value
        if self.type == "int":
            if isinstance(value, bool) or not isinstance(value, int) or not self._in_range(value):
                return None
            if self.check is not None and not self.check(value):
                return None
            return int(value)
        items = value if self.type == "floats" and isinstance(value, list) else [value]
        if self.type == "floats" and not items:
            return None
        out = []
        for v in items:
            if isinstance(v, bool) or not isinstance(v, (int, float)):
                return None
            try:
                x = float(v)
            except OverflowError:   # an integer beyond the float range
                return None
            if not math.isfinite(x) or not self._in_range(x):
                return None
            if self.check is not None and not self.check(x):
                return None
            out.append(x)
        return out if self.type == "floats" else out[0]


@dataclass(frozen=True)
class Derived:
    """A default computed from the other validated values: ``fn(values)``, shown as ``doc``."""

    fn: object
    doc: str

    def __call__(self, values):
        return self.fn(values)


@dataclass(frozen=True)
class LawChoice:
    """The contact laws a scene runs, with their defaults in the scene's units.

    Parameters
    ----------
    default : str
        The law of the scene's paper.
    defaults : dict
        ``law -> {parameter: value}``; a value may be a :class:`Derived` of the
        validated scene values (the law's earlier parameters included), e.g.
        ``Derived(lambda v: 2 * v["kn"] / 7, "2 kn / 7")``.
    docs : dict
        ``law -> one line``: why these defaults (units, what they match).
    units : dict
        ``parameter -> unit`` in this scene (for :func:`show`); a key
        ``"law.parameter"`` overrides it for that law (``linear``'s kn is a
        force/length, Hertz's a force/length^(3/2)).
    refuse : callable, optional
        ``refuse(law, values) -> str or None``: why a combination cannot make
        sense here (one line), checked after validation.
    """

    default: str
    defaults: dict
    docs: dict
    units: dict
    refuse: object = None

    def __post_init__(self):
        """Each law with a vector history brings its frame-indifferent form ``<law>_fi``."""
        from fricstab.laws import FRAME_INDIFFERENT
        defaults, docs, units = dict(self.defaults), dict(self.docs), dict(self.units)
        for law in (n for n in FRAME_INDIFFERENT if n in defaults):
            fi = f"{law}_fi"
            defaults.setdefault(fi, defaults[law])
            docs.setdefault(fi, f"{law} with its history kept on the tangent (a scalar, "
                                f"frame-indifferent); defaults as {law}: {docs.get(law, '')}")
            for key in [k for k in units if k.startswith(f"{law}.")]:
                units.setdefault(fi + key[len(law):], units[key])
        object.__setattr__(self, "defaults", defaults)
        object.__setattr__(self, "docs", docs)
        object.__setattr__(self, "units", units)

    @staticmethod
    def names():
        from fricstab.laws import PAIR_LAW_NAMES
        return PAIR_LAW_NAMES

    @staticmethod
    def params(law):
        """(pair-law parameters, wall-form extra parameters) of ``law``."""
        from fricstab.laws import get_law
        info = get_law(law)
        pair = tuple(info.params)
        return pair, tuple(info.wall_form().params[len(pair):])

    def all_params(self):
        keys = []
        for law in self.names():
            for k in sum(self.params(law), ()):
                if k not in keys:
                    keys.append(k)
        return tuple(keys)


@dataclass(frozen=True)
class Schema:
    """The keys of one scene: ``name`` (also the TOML table name), a title, the fields,
    and, where the scene runs any contact law, its :class:`LawChoice`."""

    name: str
    title: str
    fields: tuple
    laws: LawChoice = None

    def field(self, key):
        for f in self.fields:
            if f.key == key:
                return f
        if self.laws is not None:
            if key == "law":
                return Field("law", "str", self.laws.default, "-", "contact law (fricstab laws)",
                             choices=self.laws.names())
            if key in self.laws.all_params():
                return Field(key, "float", None, self.laws.units.get(key, "-"),
                             "parameter of the contact law (fricstab laws)",
                             check=in_scale_window, check_doc=SCALE_DOC)
        return None

    @property
    def keys(self):
        extra = ("law",) + self.laws.all_params() if self.laws is not None else ()
        return tuple(f.key for f in self.fields) + extra


def register(schema):
    """Make ``schema`` known to :func:`get`, :func:`validate` and ``fricstab scene show``."""
    _REGISTRY[schema.name] = schema
    return schema


def get(name):
    """The registered :class:`Schema` called ``name``."""
    _load_builtin()
    try:
        return _REGISTRY[name]
    except KeyError:
        raise ParameterError(f"unknown scene {_short(name)}; known scenes: "
                             f"{', '.join(names())}") from None


def names():
    """Names of the registered scenes, sorted."""
    _load_builtin()
    return sorted(_REGISTRY)


def _load_builtin():
    """Import the protocol modules that register their scenes (once)."""
    import importlib
    for mod in ("fricstab.scenes.chain_io", "fricstab.cli.packing", "fricstab.cli.shear"):
        try:
            importlib.import_module(mod)
        except ImportError:  # a protocol that is not installed has no scene
            pass


#: Largest scene file read (a scene is a few dozen keys; this refuses /dev/zero
#: or a data file passed by mistake before reading it into memory).
MAX_SCENE_BYTES = 1 << 20


def _read_scene_text(path):
    """The text of a scene file: a regular file of at most :data:`MAX_SCENE_BYTES`."""
    p = Path(path).expanduser()
    if p.exists() and not p.is_dir() and not p.is_file():
        raise ParameterError(f"--scene: {path} is not a regular file")
    with open(p, "rb") as fh:
        data = fh.read(MAX_SCENE_BYTES + 1)
    if len(data) > MAX_SCENE_BYTES:
        raise ParameterError(f"--scene: {path} is larger than {MAX_SCENE_BYTES} bytes: "
                             "not a scene file")
    return data.decode("utf-8")


def load_toml(name, path):
    """The key/value pairs of a TOML scene file (top level or under ``[name]``)."""
    schema = get(name)
    if path is None:
        return {}
    label = f"scene file {path}"
    try:
        data = tomllib.loads(_read_scene_text(path))
    except FileNotFoundError:
        raise ParameterError(f"--scene: scene file {path} does not exist") from None
    except IsADirectoryError:
        raise ParameterError(f"--scene: {path} is a directory, not a TOML file") from None
    except (tomllib.TOMLDecodeError, UnicodeDecodeError, ValueError) as exc:
        raise ParameterError(f"--scene: {path} is not valid TOML: "
                             f"{_short(str(exc), 120).strip(chr(39) + chr(34))}") from None
    except OSError as exc:
        raise ParameterError(f"--scene: cannot read {path}: {exc.strerror or exc}") from None
    values = {k: v for k, v in data.items() if k != schema.name}
    if schema.name in data:
        table = data[schema.name]
        if not isinstance(table, dict):
            raise ParameterError(f"{label}: key {schema.name!r} must be a table "
                                 f"([{schema.name}]), got {_short(table)}")
        both = sorted(set(values) & set(table))
        if both:
            raise ParameterError(f"{label}: key {_short(both[0])} is given both at the top "
                                 f"level and under [{schema.name}]; give it once")
        values.update(table)
    for key in values:
        if key not in schema.keys:
            raise ParameterError(f"{label}: unknown key {_short(key)}; known keys: "
                                 f"{', '.join(schema.keys)}")
    return {"__source__": label, **values}


def validate(name, mapping, *, source="scene"):
    """Every key of scene ``name``, typed and checked; defaults where ``mapping`` has none.

    ``mapping`` may hold ``"__labels__"``: key -> label used in messages
    (e.g. ``--mu`` for a command-line value); otherwise ``source`` names it.
    """
    schema = get(name)
    labels = dict(mapping.get("__labels__", {}))
    source = mapping.get("__source__", source)
    out = {}
    for key, value in mapping.items():
        if key in ("__labels__", "__source__"):
            continue
        f = schema.field(key)
        if f is None:
            raise ParameterError(f"{source}: unknown key {_short(key)}; known keys: "
                                 f"{', '.join(schema.keys)}")
        typed = f.convert(value)
        if typed is None and not (value is None and f.default is None):
            label = labels.get(key, f"{source}: key {key!r}")
            raise ParameterError(f"{label} = {_short(value)} is not allowed; allowed: "
                                 f"{f.allowed()}" + (f" [{f.unit}]" if f.unit != "-" else ""))
        out[key] = typed
    for f in schema.fields:
        out.setdefault(f.key, list(f.default) if isinstance(f.default, list) else f.default)
    if schema.laws is not None:
        _resolve_law(schema, out, labels, source)
    return out


def _resolve_law(schema, out, labels, source):
    """``law``, ``law_params``, ``wall_params`` of the validated ``out`` (module docstring)."""
    from fricstab.laws import check_parameters
    laws = schema.laws
    law = out.pop("law", None) or laws.default
    pair, wall = laws.params(law)
    given = {k: out.pop(k) for k in laws.all_params() if k in out}
    for key, value in given.items():
        if value is not None and key not in pair + wall:
            label = labels.get(key, f"{source}: key {key!r}")
            raise ParameterError(f"{label}: {key} is not a parameter of law {law} (it takes "
                                 f"{', '.join(pair + wall)}; see fricstab laws)")
    values = dict(out)
    values["law"] = law
    for key in pair + wall:
        if given.get(key) is None:
            d = laws.defaults[law][key]
            given[key] = float(d(values) if callable(d) else d)
        values[key] = given[key]
        try:
            check_parameters(**{key: given[key]})
        except ParameterError as exc:
            label = labels.get(key, f"{source}: key {key!r}")
            raise ParameterError(f"{label}: {exc}") from None
    out["law"] = law
    out["law_params"] = {k: given[k] for k in pair}
    out["wall_params"] = {k: given[k] for k in wall}
    if laws.refuse is not None:
        why = laws.refuse(law, {**out, **out["law_params"], **out["wall_params"]})
        if why:
            raise ParameterError(f"law {law}: {why}")


def resolve(name, path=None, overrides=None):
    """Scene file ``path`` (may be None), then ``overrides`` (None values ignored), validated."""
    mapping = load_toml(name, path)
    labels = {}
    schema = get(name)
    for key, value in (overrides or {}).items():
        if value is None:
            continue
        f = schema.field(key)
        labels[key] = f.option if f is not None else "--" + key.replace("_", "-")
        mapping[key] = value
    mapping["__labels__"] = labels
    return validate(name, mapping)


def show(name):
    """A text table of scene ``name``: key, type, default, unit, allowed values, doc."""
    schema = get(name)
    lines = [f"scene {schema.name!r}: {schema.title}",
             f"TOML keys at the top level or under [{schema.name}]; command-line options "
             "override them.", ""]
    for f in schema.fields:
        default = f.default_doc if f.default is None and f.default_doc else f.default
        option = "scene file only" if f.cli == "" else f"option {f.option}"
        lines.append(f"{f.key}  ({f.type}, default {default}, unit {f.unit}, {option})")
        lines.append(f"    allowed: {f.allowed()}")
        lines.append(f"    {f.doc}")
    if schema.laws is not None:
        lines += _show_laws(schema.laws)
    return "\n".join(lines)


def _show_laws(laws):
    from fricstab.laws import get_law
    lines = ["", f"law  (str, default {laws.default}, option --law)",
             f"    allowed: one of {', '.join(laws.names())}", "    the contact law; its "
             "parameters are top-level keys (defaults below, in this scene's units)"]
    for law in laws.names():
        pair, wall = laws.params(law)
        info = get_law(law)
        docs = dict(zip(info.wall_form().params, info.wall_form().param_docs))
        lines.append(f"  law {law}: {laws.docs.get(law, '')}")
        for key in pair + wall:
            d = laws.defaults[law][key]
            shown = d.doc if isinstance(d, Derived) else f"{d:g}"
            unit = laws.units.get(f"{law}.{key}", laws.units.get(key, "-"))
            lines.append(f"    {key} = {shown}  [{unit}]  {docs.get(key, '')}")
    return lines


def add_law_options(parser, schema_name):
    """``--law NAME`` and ``--param KEY=VALUE`` (repeatable) on a scene command.

    :func:`law_overrides` turns them into the overrides of :func:`resolve`;
    the values are validated with the scene file's (one line naming the key).
    """
    from fricstab.laws import PAIR_LAW_NAMES
    parser.add_argument("--law", choices=PAIR_LAW_NAMES, default=None,
                        help=f"contact law (default: the paper's; `fricstab scene show "
                             f"{schema_name}` lists each law's parameters and defaults)")
    parser.add_argument("--param", action="append", default=[], metavar="KEY=VALUE",
                        help="a parameter of the contact law, e.g. --param kn=1000 "
                             "(repeatable; overrides the scene file)")


def law_overrides(ns):
    """``{"law": ..., key: value}`` from :func:`add_law_options` options (None: not given)."""
    out = {"law": getattr(ns, "law", None)}
    for item in getattr(ns, "param", []) or []:
        key, sep, text = item.partition("=")
        key = key.strip()
        if not sep or not key:
            raise ParameterError(f"--param {_short(item)}: expected KEY=VALUE, e.g. kn=1000")
        try:
            value = float(text)
        except ValueError:
            raise ParameterError(f"--param {key}: {_short(text)} is not a number") from None
        if not math.isfinite(value):
            raise ParameterError(f"--param {key}: must be finite, got {_short(text)}")
        out[key] = value
    return out
