"""fricstab.io.frame_store.FrameStore: a run's chunks read on demand give what the whole Frames gives."""

import numpy as np
import pytest

from fricstab.analysis.shear import analyze
from fricstab.io.frame_store import SERIES, FrameStore
from fricstab.io.frames import synthetic_frames
from fricstab.laws import ParameterError
from tests.test_shear_frames import _same


@pytest.fixture(scope="module")
def frames():
    return synthetic_frames(n_frames=9, nx=10, ny=6, seed=5)


def _chunks(frames, folder, cuts=((0, 3), (3, 4), (4, 9))):
    files = []
    for c, (a, b) in enumerate(cuts):
        files.append(folder / f"chunk_{c:06d}.npz")
        frames.subset(range(a, b)).save(files[-1])
    return files


def test_store_gives_every_frame_of_the_whole(frames, tmp_path):
    store = FrameStore(_chunks(frames, tmp_path))
    assert store.n_frames == frames.n_frames and store.n_particles == frames.n_particles
    assert store.lx == frames.lx and store.meta == frames.meta
    for name in SERIES + ("radius", "mass", "inertia", "kind"):
        assert np.array_equal(getattr(store, name), getattr(frames, name)), name
    for k in [0, 4, 3, 8, 1, -1]:      # out of order: chunks leave and re-enter the cache
        for name in ("pos", "angle", "vel", "omega"):
            assert np.array_equal(getattr(store, name)[k], getattr(frames, name)[k])
        for x, y in zip(store.contacts(k), frames.contacts(k)):
            assert np.array_equal(x, y)
    _same(store.subset(range(frames.n_frames)), frames)
    assert store.n_history == frames.contact_hist.shape[1]


def test_analysis_of_the_store_is_that_of_the_whole(frames, tmp_path):
    """Same frames, same arithmetic: the per-step arrays agree to the bit."""
    a = analyze(frames, 0.0, progress=False)
    b = analyze(FrameStore(_chunks(frames, tmp_path)), 0.0, progress=False)
    assert a.summary == b.summary and np.array_equal(a.phases, b.phases)
    for name, x in a.arrays.items():
        np.testing.assert_array_equal(x, b.arrays[name], err_msg=name)


def test_store_refuses_what_is_not_one_run(frames, tmp_path):
    files = _chunks(frames, tmp_path)
    with pytest.raises(ParameterError, match="time decreases"):
        FrameStore([files[2], files[0]])
    other = tmp_path / "other.npz"
    synthetic_frames(n_frames=2, nx=6, ny=4, seed=0).save(other)
    with pytest.raises(ParameterError, match="other.npz: differs"):
        FrameStore([files[0], other])
    with pytest.raises(ParameterError, match="no frame files"):
        FrameStore([])
    store = FrameStore(files)
    with pytest.raises(ParameterError, match="out of range"):
        store.pos[frames.n_frames]
    with pytest.raises(TypeError, match="subset"):
        store.pos[1:3]
    files[1].write_bytes(files[1].read_bytes()[:100])
    with pytest.raises(ParameterError, match="chunk_000001.npz: unreadable"):
        FrameStore(files)
