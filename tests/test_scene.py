"""Scene schemas: typed validation, one-line messages naming key/value/allowed, show."""

import math

import pytest

from fricstab.laws import ParameterError
from fricstab.io.scenes import Field, Schema, get, load_toml, register, resolve, show, validate


def test_defaults_are_filled_and_typed():
    p = validate("chain", {"n": 4, "fy": 1})
    assert p["n"] == 4 and p["fy"] == 1.0 and isinstance(p["fy"], float)
    assert p["inertia"] is None                          # derived default stays None
    assert p["law"] == "charan" and p["law_params"]["mu"] == 10.0
    assert p["law_params"]["kt"] == 2 * p["law_params"]["kn"] / 7   # derived law default
    assert set(p) == {f.key for f in get("chain").fields} | {"law", "law_params",
                                                               "wall_params"}


@pytest.mark.parametrize("key, value, allowed", [
    ("n", 1, "[2, 2000]"), ("n", 4.0, "an integer"), ("n", True, "an integer"),
    ("fy", 0.0, "> 0"), ("fy", math.nan, "finite"), ("fy", math.inf, "finite"),
    ("mu", "high", "a finite number"), ("mu", [1.0], "a finite number"),
    ("mu", {"a": 1}, "a finite number"), ("n", 10 ** 400, "[2, 2000]"),
])
def test_bad_values_name_key_value_and_range(key, value, allowed):
    with pytest.raises(ParameterError) as err:
        validate("chain", {key: value}, source="scene file s.toml")
    msg = str(err.value)
    assert "\n" not in msg and f"'{key}'" in msg and allowed in msg
    assert len(msg) < 400                              # absurd values are cut, not dumped


def test_unknown_key_and_scene():
    with pytest.raises(ParameterError, match="unknown key 'friction'.*known keys: n, radius"):
        validate("chain", {"friction": 1})
    with pytest.raises(ParameterError, match="unknown scene 'foam'"):
        validate("foam", {})


def test_floats_and_checks():
    p = validate("packing", {"kt_scan": [0, 1e-4], "n": 32})
    assert p["kt_scan"] == [0.0, 1e-4]
    assert validate("packing", {"kt_scan": 2})["kt_scan"] == [2.0]
    for bad in ([], [1, -2], [1, "x"], [[1]]):
        with pytest.raises(ParameterError, match="'kt_scan'"):
            validate("packing", {"kt_scan": bad})
    with pytest.raises(ParameterError, match="even"):
        validate("packing", {"n": 33})


def test_toml_loading(tmp_path):
    path = tmp_path / "s.toml"
    path.write_text("n = 6\n[chain]\nmu = 2.5\n")
    base = validate("chain", {})
    assert resolve("chain", path, {"mu": None, "fy": 0.5}) == \
        {**base, "n": 6, "fy": 0.5, "law_params": {**base["law_params"], "mu": 2.5}}
    path.write_text("chain = 3\n")
    with pytest.raises(ParameterError, match="must be a table"):
        load_toml("chain", path)
    path.write_text("[other]\nx = 1\n")
    with pytest.raises(ParameterError, match="unknown key 'other'"):
        load_toml("chain", path)
    path.write_bytes(b"\xff\xfe n = \x00")
    with pytest.raises(ParameterError, match="not valid TOML"):
        load_toml("chain", path)
    with pytest.raises(ParameterError, match="--fy = -1"):      # the command line is named
        resolve("chain", None, {"fy": -1.0})
    with pytest.raises(ParameterError, match="does not exist"):
        load_toml("chain", tmp_path / "missing.toml")


def test_show_lists_every_key_with_unit_and_range():
    text = show("chain")
    for f in get("chain").fields:
        assert f"\n{f.key}  (" in text
        assert f.allowed() in text and f.doc in text and f"unit {f.unit}" in text
    assert "2 kn / 7" in text                             # derived default explained


def test_register_a_new_scene():
    register(Schema("toy_F", "a test scene", (
        Field("r", "float", 1.0, "m", "radius", low=0.0, high=2.0, high_open=True),
        Field("mode", "str", "a", "-", "mode", choices=("a", "b")),
        Field("on", "bool", False, "-", "switch"),
    )))
    assert validate("toy_F", {"mode": "b", "on": True}) == {"r": 1.0, "mode": "b", "on": True}
    for key, bad, allowed in (("r", 2.0, "[0, 2)"), ("mode", "c", "one of a, b"),
                              ("on", 1, "true or false")):
        with pytest.raises(ParameterError, match=allowed.replace("[", r"\[").replace("(", r"\(")
                           .replace(")", r"\)")):
            validate("toy_F", {key: bad})
