"""The frames of a run read a chunk at a time: runs larger than memory.

A paper-size plane-shear run (1,067 disks, 160,556 frames, 116 kB each)
writes about 19 GB of frames; :class:`FrameStore` gives the analyses, figures and slip
spectra the part of the :class:`fricstab.io.frames.Frames` interface they use
while holding only the per-frame series and a few chunks in memory:

- ``lx``, ``radius``, ``mass``, ``inertia``, ``kind``, ``meta`` (from the
  first chunk; every chunk must agree), ``n_frames``, ``n_particles``;
- the series ``time``, ``strain``, ``normal_force``, ``shear_force``,
  ``tau``, ``height`` (T,), read from every chunk at opening (a few kB each);
- ``pos[k]``, ``angle[k]``, ``vel[k]``, ``omega[k]`` and ``contacts(k)`` of
  one frame k, which load k's chunk (validated as :meth:`Frames.load` does)
  and keep the last ``cache`` chunks: the analyses walk the frames in order
  and look one frame back, so two chunks suffice;
- ``subset(frames)``: a :class:`Frames` in memory of the frames asked for.
"""

import bisect
from collections import OrderedDict
from pathlib import Path

import numpy as np

from fricstab.io.frames import (_PER_PARTICLE, Frames, _readonly, frame_index, read_arrays,
                                 subset_of)
from fricstab.laws import ParameterError

__all__ = ["FrameStore"]

SERIES = ("time", "strain", "normal_force", "shear_force", "tau", "height")


class _Column:
    """``store.pos[k]``: one frame's row of a per-frame array, read through the chunk cache."""

    def __init__(self, store, name):
        self._store, self._name = store, name

    def __len__(self):
        return self._store.n_frames

    def __getitem__(self, k):
        if not isinstance(k, (int, np.integer)):
            raise TypeError(f"FrameStore.{self._name}[k] takes one frame index k; use "
                            "subset() for a Frames in memory")
        chunk, i = self._store._locate(k)
        return getattr(chunk, self._name)[i]


class FrameStore:
    """The frames of the chunk files ``files`` (in order), read on demand (module doc).

    Raises ParameterError naming the file when a chunk is unreadable, holds
    non-finite series, or differs from the first in lx, particles or
    histories, or when time decreases across chunks.
    """

    def __init__(self, files, cache=2):
        self.files = [Path(f) for f in files]
        if not self.files:
            raise ParameterError("FrameStore: no frame files given")
        if cache < 2:
            raise ParameterError(f"FrameStore: cache must be >= 2 chunks, got {cache}")
        self._cache, self._size = OrderedDict(), int(cache)
        series, counts = {n: [] for n in SERIES}, []
        header0 = first = None
        for f in self.files:
            header, a = read_arrays(f, _PER_PARTICLE + SERIES + ("contact_hist",))
            if first is None:     # the first chunk: what every other must agree with
                header0, first = header, a
            if header["lx"] != header0["lx"] or a["contact_hist"].shape[1:] != \
                    first["contact_hist"].shape[1:] or not all(
                    np.array_equal(a[n], first[n]) for n in ("radius", "kind")):
                raise ParameterError(f"{f}: differs from {self.files[0].name} in lx, "
                                     "particles or histories (chunks of another run?)")
            for n in SERIES:
                if not np.all(np.isfinite(a[n])):
                    raise ParameterError(f"{f}: {n} contains non-finite values")
                series[n].append(a[n])
            counts.append(len(a["time"]))
        self.lx, self.meta = float(header0["lx"]), header0.get("meta", {})
        for n in _PER_PARTICLE:
            setattr(self, n, _readonly(first[n]))
        for n in SERIES:
            setattr(self, n, _readonly(np.concatenate(series[n])))
        if np.any(np.diff(self.time) < 0):
            raise ParameterError("FrameStore: time decreases across chunks (wrong order?)")
        self.n_history = first["contact_hist"].shape[1]
        self._start = np.concatenate([[0], np.cumsum(counts)])
        self.pos, self.angle = _Column(self, "pos"), _Column(self, "angle")
        self.vel, self.omega = _Column(self, "vel"), _Column(self, "omega")

    @property
    def n_frames(self):
        """Number of frames T."""
        return int(self._start[-1])

    @property
    def n_particles(self):
        """Number of particles N (walls included)."""
        return self.radius.shape[0]

    def _locate(self, k):
        """(the chunk's Frames, the frame's index in it) of frame ``k`` (negative from the end)."""
        k = frame_index(k, self.n_frames)
        c = bisect.bisect_right(self._start, k) - 1
        if c not in self._cache:
            chunk = Frames.load(self.files[c])
            if chunk.n_frames != self._start[c + 1] - self._start[c]:
                raise ParameterError(f"{self.files[c]}: changed while it was read")
            self._cache[c] = chunk
            while len(self._cache) > self._size:
                self._cache.popitem(last=False)
        self._cache.move_to_end(c)
        return self._cache[c], k - int(self._start[c])

    def contacts(self, k):
        """Contacts of frame ``k``: ``(ij, force, fn, hist, flag)``."""
        chunk, i = self._locate(k)
        return chunk.contacts(i)

    def _frame_kwargs(self, k):
        chunk, i = self._locate(k)
        return chunk._frame_kwargs(i)

    def subset(self, frames):
        """A :class:`Frames` in memory with the frames ``frames`` (int indices, in order)."""
        return subset_of(self, frames)
