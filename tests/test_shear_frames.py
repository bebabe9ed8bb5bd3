"""The plane-shear frames container: validation, atomic NPZ round trip, chunks."""

import json
import os

import numpy as np
import pytest

from fricstab.laws import ParameterError
from fricstab.io.frames import Frames, FrameWriter, synthetic_frames

_ARRAYS = ("radius", "mass", "inertia", "kind", "time", "strain", "normal_force",
           "shear_force", "tau", "height", "pos", "angle", "vel", "omega", "contact_ptr",
           "contact_ij", "contact_force", "contact_fn", "contact_hist", "contact_flag")


def _same(a, b):
    assert a.lx == b.lx and a.meta == b.meta
    for name in _ARRAYS:
        x, y = getattr(a, name), getattr(b, name)
        assert x.dtype == y.dtype and np.array_equal(x, y), name


@pytest.fixture(scope="module")
def frames():
    return synthetic_frames(n_frames=6, nx=8, ny=4, seed=3)


def test_shapes_dtypes_and_contacts(frames):
    T, N = frames.n_frames, frames.n_particles
    assert (T, N) == (6, 8 * 6)
    assert frames.pos.shape == (T, N, 2) and frames.contact_ptr.shape == (T + 1,)
    assert frames.contact_ij.dtype == np.int32 and frames.kind.dtype == np.int8
    ij, force, fn, hist, flag = frames.contacts(2)
    m = frames.contact_ptr[3] - frames.contact_ptr[2]
    assert len(ij) == len(force) == len(fn) == len(hist) == len(flag) == m > 0
    assert hist.shape == (m, 2) and flag.dtype == np.int8
    assert np.all(ij[:, 0] < ij[:, 1])
    # tau defaults to S / N in the writer.
    assert np.allclose(frames.tau, frames.shear_force / frames.normal_force, rtol=0, atol=0)
    with pytest.raises(ValueError):
        frames.pos[0, 0, 0] = 1.0  # read-only
    with pytest.raises(ParameterError, match="out of range"):
        frames.contacts(T)


def test_save_load_round_trip(frames, tmp_path):
    path = tmp_path / "run.npz"
    frames.save(path)
    back = Frames.load(path)
    _same(frames, back)
    assert json.loads(json.dumps(back.meta)) == back.meta
    # Atomic write leaves no temporary file behind.
    assert sorted(os.listdir(tmp_path)) == ["run.npz"]


def test_load_rejects_truncated_foreign_and_missing(frames, tmp_path):
    path = tmp_path / "run.npz"
    frames.save(path)
    data = path.read_bytes()
    cut = tmp_path / "cut.npz"
    cut.write_bytes(data[: len(data) // 2])
    with pytest.raises(ParameterError, match="cut.npz"):
        Frames.load(cut)
    foreign = tmp_path / "foreign.npz"
    np.savez(foreign, a=np.zeros(3))
    with pytest.raises(ParameterError, match="foreign.npz.*not a fricstab frames file"):
        Frames.load(foreign)
    with pytest.raises(ParameterError, match="no such file"):
        Frames.load(tmp_path / "absent.npz")
    # A well-formed NPZ with a wrong dtype names the array.
    with np.load(path) as z:
        arrays = dict(z)
    arrays["pos"] = arrays["pos"].astype(np.float32)
    bad = tmp_path / "bad.npz"
    np.savez(bad, **arrays)
    with pytest.raises(ParameterError, match="bad.npz: pos has dtype float32"):
        Frames.load(bad)


def test_concat_of_chunks_is_the_whole(frames):
    whole = Frames.concat([frames.subset([0, 1, 2]), frames.subset([3]), frames.subset([4, 5])])
    _same(frames, whole)
    with pytest.raises(ParameterError, match="time decreases"):
        Frames.concat([frames.subset([3, 4]), frames.subset([0, 1])])
    other = synthetic_frames(n_frames=2, nx=6, ny=4, seed=0)
    with pytest.raises(ParameterError, match="differ"):
        Frames.concat([frames, other])


def _kwargs(frames):
    out = {name: np.array(getattr(frames, name)) for name in _ARRAYS}
    return dict(lx=frames.lx, meta=frames.meta, **out)


@pytest.mark.parametrize("edit, match", [
    (lambda kw: kw.update(pos=kw["pos"][:, :-1]), "pos has shape"),
    (lambda kw: kw["pos"].__setitem__((1, 2, 0), np.nan), "pos contains non-finite"),
    (lambda kw: kw["contact_ptr"].__setitem__(2, kw["contact_ptr"][3] + 1), "contact_ptr"),
    (lambda kw: kw["contact_ij"].__setitem__((0, 0), kw["contact_ij"][0, 1]), "i < j"),
    (lambda kw: kw["kind"].__setitem__(0, 5), "kind"),
    (lambda kw: kw.update(radius=-kw["radius"]), "radius"),
    (lambda kw: kw.update(lx=0.0), "lx"),
    (lambda kw: kw.update(meta={"x": object()}), "JSON"),
    (lambda kw: kw.update(contact_ij=kw["contact_ij"].astype(float)), "integer"),
])
def test_validation_names_the_fault(frames, edit, match):
    kw = _kwargs(frames)
    edit(kw)
    with pytest.raises(ParameterError, match=match):
        Frames(**kw)


def test_writer_rejects_empty_and_zero_normal_force():
    w = FrameWriter(4.0, np.ones(2), np.ones(2), np.ones(2), [1, 2])
    with pytest.raises(ParameterError, match="no frames"):
        w.finish()
    with pytest.raises(ParameterError, match="normal_force = 0"):
        w.append(time=0, strain=0, normal_force=0.0, shear_force=1.0, height=1.0,
                 pos=np.zeros((2, 2)), angle=np.zeros(2), vel=np.zeros((2, 2)),
                 omega=np.zeros(2), contact_ij=np.zeros((0, 2)), contact_force=np.zeros((0, 2)),
                 contact_fn=[], contact_hist=[], contact_flag=[])


def test_frames_without_history_and_empty_frames():
    """A law without history (hertz) has H = 0; a frame without contacts keeps H."""
    w = FrameWriter(4.0, np.ones(2), np.ones(2), np.ones(2), [1, 2], meta={"law": "hertz"})
    base = dict(strain=0, normal_force=1.0, shear_force=0.5, height=1.0, pos=np.zeros((2, 2)),
                angle=np.zeros(2), vel=np.zeros((2, 2)), omega=np.zeros(2))
    w.append(time=0, contact_ij=[[0, 1]], contact_force=[[1.0, 0.0]], contact_fn=[1.0],
             contact_hist=np.zeros((1, 0)), contact_flag=[0], **base)
    w.append(time=1, contact_ij=np.zeros((0, 2)), contact_force=np.zeros((0, 2)),
             contact_fn=[], contact_hist=[], contact_flag=[], **base)
    f = w.finish()
    assert f.contact_hist.shape == (1, 0) and f.contacts(1)[3].shape == (0, 0)
