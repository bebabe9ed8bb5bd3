"""The Python front door validates its inputs (issue 39, "The Python front door").

Every public function of ``fricstab`` (the table ``fricstab._NAMES``) is called
with its valid arguments on tiny systems and then, one argument slot at a time,
with a wrong type, NaN, inf, a negative value, zero, a huge (1e300) and a
sub-normal (1e-320) value.  Each call must either return a result without NaN
or raise a documented :class:`ParameterError`, :class:`NumericalError` or
:class:`ConvergenceError`; never another exception type, never a hang (each
call runs under ``signal.alarm``).  The default run sweeps wrong types, NaN,
inf and negative values (refused up front) and the issue's cases; zero, huge
and sub-normal values, which may run a protocol to its end, and the slots of
the expensive protocols sweep under ``-m slow``.
"""

import dataclasses
import math
import signal
import types

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import fricstab as fs
from fricstab.errors import (ConvergenceError, NumericalError, ParameterError, check_finite_array,
                             check_int, check_real)

ALLOWED = (ParameterError, NumericalError, ConvergenceError)
NAN, INF = float("nan"), float("inf")
TYPES = ["x", None, [0.1]]
NUMS = [*TYPES, NAN, INF, -1.0, 0.0, 1e300, 1e-320]
INTS = ["x", None, 2.5, NAN, -1, 0, 10**30]
OBJS = ["chain", None, 1.0]
#: Results with a documented NaN: d2min of a particle without a neighbourhood.
NAN_OK = {"d2min"}
#: Result fields whose NaN is a documented "not computed" or "never": rigidity without
#: modes, the breach and slide times of a disk that never breached or slid.
NAN_FIELDS = {"g_na_modes", "tau", "x_tau", "tau_slide", "x_slide"}
TIMEOUT = 60   # seconds for one call with a bad argument
WARM_TIMEOUT = 900   # the first, valid call of each function: its numba compile included


class _Timeout(Exception):
    pass


def _alarm(signum, frame):
    raise _Timeout()


def _has_nan(value, depth=0):
    """True where a NaN hides in a result (arrays, numbers, dataclasses, containers)."""
    if depth > 4 or value is None:
        return False
    if isinstance(value, (float, complex, np.floating, np.complexfloating)):
        return bool(np.isnan(value))
    if isinstance(value, np.ndarray):
        return value.dtype.kind in "fc" and bool(np.isnan(value).any())
    if isinstance(value, (list, tuple)):
        return any(_has_nan(v, depth + 1) for v in value[:1000])
    if isinstance(value, dict):
        return any(_has_nan(v, depth + 1) for v in value.values())
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        return any(_has_nan(getattr(value, f.name), depth + 1) for f in dataclasses.fields(value)
                   if f.name not in NAN_FIELDS)
    return False


def call_checked(fn, *args, _nan_ok=False, _timeout=TIMEOUT, **kwargs):
    """``fn(*args, **kwargs)``: a NaN-free result, or None after a documented refusal."""
    old = signal.signal(signal.SIGALRM, _alarm)
    signal.alarm(_timeout)
    try:
        out = fn(*args, **kwargs)
    except ALLOWED as exc:
        msg = str(exc)
        assert msg and "\n" not in msg.strip(), f"not one line: {msg!r}"
        return None
    except _Timeout:
        pytest.fail(f"no answer within {_timeout} s")
    except Exception as exc:   # noqa: BLE001 - the point of the test
        pytest.fail(f"{type(exc).__name__}: {exc}")
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, old)
    assert _nan_ok or not _has_nan(out), f"silent NaN in the result {type(out).__name__}"
    return out


# ---------------------------------------------------------------- tiny valid objects

@pytest.fixture(scope="module")
def chain():
    from fricstab.scenes.chain import forces_and_jacobian, mass_vector
    scene = fs.ChainScene(n=4)
    state = fs.ramped_equilibrium(scene, 0.0)
    jac = forces_and_jacobian(scene, state)[1]
    return types.SimpleNamespace(scene=scene, state=state, jac=jac, mass=mass_vector(scene))


@pytest.fixture(scope="module")
def pack():
    packing = fs.make_packing(16, 0.86, seed=1)
    bb = fs.backbone(packing)
    mat = fs.packing_material("ishima")
    fr = fs.frictional(bb, mat)
    return types.SimpleNamespace(packing=packing, bb=bb, mat=mat, system=fr.system,
                                 state=fr.state, jac=fs.jacobian(fr.system, fr.state)[1])


@pytest.fixture(scope="module")
def cell():
    return fs.make_cell({"n": 40, "seed": 3})


def _nan_state(state):
    s = state.copy()
    s.q[0, 0] = NAN
    return s


def _ctx(request, needs):
    return types.SimpleNamespace(**{k: request.getfixturevalue(k) for k in needs})


# name -> (fixtures needed, (ctx -> (callable, kwargs)), {slot: bad values}, slow)
CASES = {
    "ChainScene": (
        (), lambda c: (fs.ChainScene, {"n": 4}),
        {"n": INTS, "radius": NUMS, "mass": NUMS, "fy": NUMS, "fx": NUMS, "inertia": NUMS,
         "law": OBJS, "params": ["x", [1], {"kn": NAN}, {"kn": -1.0}, {"mu": 1e-300}]},
        False),
    "run_ramp": (
        ("chain",), lambda c: (fs.run_ramp, {"scene": c.chain.scene, "fx_max": 0.01,
                                             "step": 5e-3}),
        {"scene": OBJS, "fx_max": NUMS, "step": NUMS, "tol": NUMS,
         "keep_states": ["x", None], "locate": ["x", None]},
        False),
    "relax_newton": (
        ("chain",), lambda c: (fs.relax_newton, {"scene": c.chain.scene, "state": c.chain.state}),
        {"scene": OBJS, "state": [*OBJS, "nan"], "tol": NUMS, "max_iter": INTS,
         "max_step": NUMS},
        False),
    "ramped_equilibrium": (
        ("chain",), lambda c: (fs.ramped_equilibrium, {"scene": c.chain.scene, "fx": 0.005,
                                                       "step": 5e-3}),
        {"scene": OBJS, "fx": NUMS, "step": NUMS},
        False),
    "run_dynamics": (
        ("chain",), lambda c: (fs.run_dynamics, {"scene": c.chain.scene, "state": c.chain.state,
                                                 "duration": 1.0, "frames": 10}),
        {"scene": OBJS, "state": [*OBJS, "nan"], "velocity": ["x", [1.0], "nan"],
         "dt": NUMS, "duration": NUMS, "frames": INTS, "nu": NUMS},
        False),
    "relax_damped": (
        ("chain",), lambda c: (fs.relax_damped, {"scene": c.chain.scene, "state": c.chain.state,
                                                 "max_steps": 1000}),
        {"scene": OBJS, "state": [*OBJS, "nan"], "nu": NUMS, "dt": NUMS, "tol": NUMS,
         "max_steps": INTS},
        False),
    "measure_growth": (
        ("chain",), lambda c: (fs.measure_growth, {"scene": c.chain.scene,
                                                   "state": c.chain.state}),
        {"scene": OBJS, "state": [*OBJS, "nan"], "amplitude": NUMS, "e_folds": NUMS,
         "dt": NUMS},
        False),
    "run_realization": (
        ("chain",), lambda c: (fs.run_realization, {"scene": c.chain.scene,
                                                    "equilibrium": c.chain.state, "seed": 1,
                                                    "duration": 2.0, "frames": 10}),
        {"scene": OBJS, "equilibrium": [*OBJS, "nan"], "seed": INTS, "duration": NUMS,
         "amplitude": NUMS, "slide_threshold": NUMS, "frames": INTS, "dt": NUMS},
        True),
    "transverse_mode": (
        ("chain",), lambda c: (fs.transverse_mode, {"scene": c.chain.scene,
                                                    "state": c.chain.state}),
        {"scene": OBJS, "state": [*OBJS, "nan"]},
        False),
    "decompose": (
        ("chain",), lambda c: (fs.decompose, {"jac": c.chain.jac, "mass": c.chain.mass}),
        {"jac": [*OBJS, "nan_array"], "mass": [*OBJS, "nan_array", "zeros"]},
        False),
    "complex_pairs": (
        (), lambda c: (fs.complex_pairs, {"eigenvalues": np.array([1 + 1j, 1 - 1j, -2.0])}),
        {"eigenvalues": [*OBJS, "nan_array"]},
        False),
    "growth_rate": (
        (), lambda c: (fs.growth_rate, {"eigenvalues": np.array([1 + 1j, 1 - 1j, -2.0])}),
        {"eigenvalues": [*OBJS, "nan_array"]},
        False),
    "pair_indicator": (
        (), lambda c: (fs.pair_indicator, {"eigenvalues": np.array([1 + 1j, 1 - 1j, -2.0]),
                                          "center": 1.0, "radius": 0.5}),
        {"eigenvalues": [*OBJS, "nan_array"], "center": NUMS, "radius": NUMS},
        False),
    "evaluate": (
        (), lambda c: (fs.evaluate, {"name": "hertz", "dx": 0.99, "dy": 0.0, "Ri": 0.5,
                                     "Rj": 0.5, "kn": 2000.0}),
        {"name": OBJS, "dx": NUMS, "kn": NUMS},
        False),
    "get_law": ((), lambda c: (fs.get_law, {"name": "charan"}), {"name": [*OBJS, [1]]}, False),
    "Material": (
        (), lambda c: (fs.Material, {"law": "hertz", "params": {"kn": 1.0}}),
        {"law": OBJS, "params": ["x", None, {"kn": NAN}, {"kn": "x"}, {"kn": -1.0}]},
        False),
    "packing_material": (
        (), lambda c: (fs.packing_material, {"law": "ishima"}),
        {"law": OBJS, "kt": NUMS},
        False),
    "make_packing": (
        (), lambda c: (fs.make_packing, {"n": 16, "phi": 0.86, "seed": 1}),
        {"n": INTS, "phi": NUMS, "seed": INTS, "dphi": NUMS, "phi_start": NUMS,
         "f_tol_compress": NUMS, "max_iter": INTS, "f_tol": NUMS},
        True),
    "backbone": (
        ("pack",), lambda c: (fs.backbone, {"packing": c.pack.packing}),
        {"packing": OBJS, "z_th": INTS, "f_tol": NUMS},
        False),
    "packing_system": (
        ("pack",), lambda c: (fs.packing_system, {"bb": c.pack.bb, "mat": c.pack.mat}),
        {"bb": OBJS, "mat": OBJS, "skin": NUMS},
        False),
    "frictional": (
        ("pack",), lambda c: (fs.frictional, {"bb": c.pack.bb, "mat": c.pack.mat}),
        {"bb": OBJS, "mat": OBJS, "f_tol": NUMS, "max_iter": INTS},
        False),
    "rigidity": (
        ("pack",), lambda c: (fs.rigidity, {"system": c.pack.system, "state": c.pack.state}),
        {"system": OBJS, "state": [*OBJS, "nan"], "modes": ["x", None], "route": OBJS},
        False),
    "linear_response": (
        ("pack",), lambda c: (fs.linear_response, {"system": c.pack.system,
                                                   "state": c.pack.state}),
        {"system": OBJS, "state": [*OBJS, "nan"]},
        False),
    "dos_spectrum": (
        ("pack",), lambda c: (fs.dos_spectrum, {"jac": c.pack.jac}),
        {"jac": [*OBJS, "nan_array"], "route": OBJS},
        False),
    "step_strain": (
        ("pack",), lambda c: (fs.step_strain, {"system": c.pack.system, "state": c.pack.state}),
        {"system": OBJS, "state": [*OBJS, "nan"], "dgamma": NUMS, "f_tol": NUMS},
        False),
    "strain": (
        ("pack",), lambda c: (fs.strain, {"system": c.pack.system, "state": c.pack.state,
                                          "dgamma": 1e-6}),
        {"system": OBJS, "state": [*OBJS, "nan"], "dgamma": NUMS, "f_tol": NUMS,
         "max_iter": INTS},
        False),
    "run_aqs": (
        ("pack",), lambda c: (fs.run_aqs, {"system": c.pack.system, "state": c.pack.state,
                                           "strain": 2e-3, "dgamma": 1e-3,
                                           "locate_events": False}),
        {"system": OBJS, "state": [*OBJS, "nan"], "strain": NUMS, "dgamma": NUMS,
         "f_tol": NUMS, "tol": NUMS},
        True),
    "make_cell": (
        (), lambda c: (fs.make_cell, {"params": {"n": 40, "seed": 3}}),
        {"params": ["x", None, {"n": NAN}, {"n": -4}, {"seed": "x"}, {"n": 10**30}]},
        False),
    "ShearRun": (("cell",), lambda c: (fs.ShearRun, {"cell": c.cell}), {"cell": OBJS}, False),
    "run_shear": (
        (), lambda c: (fs.run_shear, {"n": 20, "seed": 3, "strain": 5e-5, "dgamma": 1e-5,
                                      "kappa": 100.0, "prep_ke": 1e-3, "prep_tol": 0.1}),
        {"preset": OBJS, "progress": OBJS, "keep_frames": OBJS, "n": INTS, "strain": NUMS,
         "dgamma": NUMS},
        False),
    "d2min": (
        (), lambda c: (fs.d2min, {"pos_ref": _grid(), "pos_cur": _grid() * 1.001, "lx": 4.0,
                                  "radius_cut": 1.5}),
        {"pos_ref": [*OBJS, "nan_array"], "pos_cur": [*OBJS, "nan_array"], "lx": NUMS,
         "radius_cut": NUMS},
        False),
    "detect_drops": (
        (), lambda c: (fs.detect_drops, {"strain": np.arange(4.0), "stress": [1.0, 2, 1, 3]}),
        {"strain": [*OBJS, "nan_array"], "stress": [*OBJS, "nan_array"], "threshold": NUMS},
        False),
}


def _grid():
    x, y = np.meshgrid(np.arange(4.0), np.arange(4.0))
    return np.column_stack([x.ravel() + 0.5, y.ravel() + 0.5])


def _bad(value, good):
    """The bad value for a slot whose valid value is ``good`` (``"nan"``: a NaN copy)."""
    if value == "nan" and hasattr(good, "copy") and hasattr(good, "q"):
        return _nan_state(good)
    if value == "nan" and good is None:    # a velocity: NaN in the right shape
        return "nan"
    if value == "nan_array":
        a = np.array(good, dtype=np.result_type(np.asarray(good).dtype, float))
        if hasattr(good, "toarray"):
            a = good.toarray()
        a.ravel()[0] = NAN
        return a
    if value == "zeros":
        return np.zeros_like(good)
    return value


def _extreme(v):
    """Zero, huge and sub-normal values: they may run a protocol to its end (slow sweep)."""
    return (isinstance(v, (int, float)) and not isinstance(v, bool) and not math.isnan(v)
            and v in (0, 1e300, 1e-320, 10**30))


def _params():
    out = []
    for name, (needs, make, slots, slow) in CASES.items():
        for slot, values in slots.items():
            for k, v in enumerate(values):
                marks = [pytest.mark.slow] if slow or _extreme(v) else []
                out.append(pytest.param(name, slot, k, marks=marks, id=f"{name}-{slot}-{v!r}"[:80]))
    return out


@pytest.mark.parametrize("name", [n for n, c in CASES.items() if not c[3]])
def test_valid_call_returns_a_result(request, name):
    needs, make, slots, slow = CASES[name]
    fn, kwargs = make(_ctx(request, needs))
    out = call_checked(fn, **kwargs, _timeout=WARM_TIMEOUT)
    if name not in ("measure_growth",):   # a stable chain has no growing mode: refused
        assert out is not None


@pytest.mark.parametrize("name, slot, k", _params())
def test_bad_argument_is_refused_or_answered(request, name, slot, k):
    needs, make, slots, slow = CASES[name]
    fn, kwargs = make(_ctx(request, needs))
    value = slots[slot][k]
    if value == "nan" and slot == "velocity":
        value = np.full((4, 3), NAN)
    else:
        value = _bad(value, kwargs.get(slot))
    call_checked(fn, **{**kwargs, slot: value}, _nan_ok=name in NAN_OK)


# ---------------------------------------------------------------- the issue's cases


def test_issue_cases(request):
    chain = request.getfixturevalue("chain")
    for fn, args, kwargs in [
            (fs.run_ramp, (chain.scene, 0.1, 0), {}),
            (fs.run_ramp, ("chain", 0.1, 1e-3), {}),
            (fs.run_ramp, (chain.scene, 0.1, -1e-3), {}),
            (fs.make_packing, (16, 0.9), {"dphi": 1e-300}),
            (fs.relax_newton, (chain.scene, _nan_state(chain.state)), {}),
            (fs.d2min, (np.full((16, 2), NAN), _grid(), 4.0, 1.5), {})]:
        with pytest.raises(ParameterError):
            fn(*args, **kwargs)


def test_numpy_scalars_are_numbers():
    scene = fs.ChainScene(n=4, fy=np.float32(0.1), radius=np.float64(0.5))
    assert scene.fy == np.float32(0.1)
    assert fs.ChainScene(n=np.int64(4)).n == 4


def test_rigidity_of_nan_state_is_refused(request):
    pack = request.getfixturevalue("pack")
    with pytest.raises(ParameterError, match="state"):
        fs.rigidity(pack.system, _nan_state(pack.state))


def test_shear_advance_refuses_negative_steps(request):
    run = fs.ShearRun(request.getfixturevalue("cell"))
    for bad in (-5, 2.5, "x", None, NAN):
        with pytest.raises(ParameterError, match="nsteps"):
            run.advance(bad)
    run.advance(0)
    assert np.isfinite(run.state.q).all()


# ---------------------------------------------------------------- the helpers


_anything = st.one_of(st.floats(allow_nan=True, allow_infinity=True), st.integers(-10**30, 10**30),
                      st.text(max_size=3), st.none(), st.booleans(), st.complex_numbers(),
                      st.lists(st.floats(), max_size=2),
                      st.floats(width=32).map(np.float32), st.integers(-5, 5).map(np.int64))


@settings(max_examples=300, deadline=None)
@given(_anything, st.sampled_from([None, -1.0, 0.0]), st.booleans())
def test_check_real_accepts_exactly_finite_reals_in_range(value, low, low_open):
    real = isinstance(value, (int, float, np.integer, np.floating)) and not isinstance(value, bool)
    ok = real and math.isfinite(value) and (
        low is None or (value > low if low_open else value >= low))
    if ok:
        assert check_real("x", value, low, low_open=low_open) is value
    else:
        with pytest.raises(ParameterError, match=r"^x must be a finite number"):
            check_real("x", value, low, low_open=low_open)


@settings(max_examples=200, deadline=None)
@given(_anything)
def test_check_int_and_array(value):
    integer = isinstance(value, (int, np.integer)) and not isinstance(value, bool)
    if integer and value >= 0:
        assert check_int("n", value, 0) is value
    else:
        with pytest.raises(ParameterError, match=r"^n must be an integer"):
            check_int("n", value, 0)
    try:
        check_finite_array("a", value)
    except ParameterError as exc:
        assert str(exc).startswith("a must")
