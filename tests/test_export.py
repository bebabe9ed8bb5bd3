"""Exported trajectories load in OVITO with the same particles, positions, radii
and number of frames (OVITO is the 'ovito' extra; those tests skip, saying why,
without it)."""

import numpy as np
import pytest

from fricstab.io.export import frames_to_ovito, write_extxyz, write_lammps_dump
from fricstab.laws import ParameterError
from fricstab.io.frames import synthetic_frames


@pytest.fixture(scope="module")
def frames():
    return synthetic_frames(n_frames=4, nx=6, ny=3, seed=2)


@pytest.mark.parametrize("fmt, suffix", [("extxyz", "xyz"), ("lammps", "dump")])
def test_frames_round_trip_through_ovito(frames, tmp_path, fmt, suffix, ovito_io):
    path = tmp_path / f"run.{suffix}"
    frames_to_ovito(frames, path, fmt)
    pipeline = ovito_io.import_file(str(path), multiple_frames=True)
    assert pipeline.source.num_frames == frames.n_frames
    for k in range(frames.n_frames):
        data = pipeline.compute(k)
        assert data.particles.count == frames.n_particles
        pos = np.asarray(data.particles.positions)
        # Positions are float64 in OVITO and written with 17 digits.
        assert np.allclose(pos[:, :2], frames.pos[k], rtol=0, atol=1e-12)
        assert np.all(pos[:, 2] == 0.0)
        # OVITO keeps radii in float32: relative rounding 2^-24 ~ 6e-8.
        assert np.allclose(data.particles["Radius"], frames.radius, rtol=1.2e-7, atol=0)
        types = np.asarray(data.particles.particle_types)
        # Types follow kind: the same partition of the particles.
        for a in range(3):
            assert len(np.unique(types[frames.kind == a])) == 1
        assert np.isclose(data.cell[0, 0], frames.lx) and np.isclose(data.cell[1, 1], frames.height[k])


def test_single_frame_and_optional_columns(tmp_path, ovito_io):
    pos = np.array([[0.0, 0.0], [1.5, 0.25], [3.0, -1.0]])
    radius = np.array([0.5, 0.6, 0.7])
    for writer, name in ((write_extxyz, "one.xyz"), (write_lammps_dump, "one.dump")):
        writer(tmp_path / name, pos, radius)
        data = ovito_io.import_file(str(tmp_path / name)).compute(0)
        assert data.particles.count == 3
        assert np.allclose(np.asarray(data.particles.positions)[:, :2], pos, atol=1e-12)


def test_bad_input_names_the_array(tmp_path):
    pos = np.zeros((2, 3, 2))
    with pytest.raises(ParameterError, match="radius"):
        write_extxyz(tmp_path / "x.xyz", pos, np.ones(4))
    with pytest.raises(ParameterError, match="vel"):
        write_lammps_dump(tmp_path / "x.dump", pos, np.ones(3), vel=np.zeros((2, 3)))
    with pytest.raises(ParameterError, match="pos contains non-finite"):
        write_extxyz(tmp_path / "x.xyz", np.full((3, 2), np.nan), np.ones(3))
    with pytest.raises(ParameterError, match="fmt"):
        frames_to_ovito(synthetic_frames(n_frames=1, nx=4, ny=2), tmp_path / "x", "pdb")
    assert not list(tmp_path.iterdir())  # nothing half-written
