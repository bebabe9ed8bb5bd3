"""The ensemble runner: members stored as they finish, skipped on rerun, worker death survived."""

import os
import signal
import uuid
from pathlib import Path

import numpy as np
import pytest

from fricstab.io.ensemble import member_path, run_ensemble
from fricstab.laws import ParameterError


def chain_member(markers, key, kill_key, **kwargs):
    """A cheap chain realization; counts its starts and completions in marker files.

    The member ``kill_key`` kills its own worker process (SIGKILL) the first time.
    """
    from fricstab.protocols.waves import realization_member
    markers = Path(markers)
    (markers / f"start.{key}.{uuid.uuid4().hex}").touch()
    if key == kill_key and not (markers / "killed").exists():
        (markers / "killed").touch()
        os.kill(os.getpid(), signal.SIGKILL)
    result = realization_member(**kwargs)
    (markers / f"done.{key}.{uuid.uuid4().hex}").touch()
    return result


def _members(markers, kill_key):
    from fricstab.protocols.ramp import ramped_equilibrium
    from fricstab.scenes.chain import ChainScene
    scene = ChainScene(n=4).with_fx(0.02)
    eq = ramped_equilibrium(scene, 0.02, step=5e-3)
    return {f"seed{s}": dict(markers=str(markers), key=f"seed{s}", kill_key=kill_key,
                             scene=scene, equilibrium=eq, seed=s, duration=200.0,
                             slide_threshold=0.02) for s in range(25)}


def _count(markers, kind):
    names = [p.name.split(".")[1] for p in Path(markers).glob(f"{kind}.*")]
    return {k: names.count(k) for k in set(names)}


def test_inline_stores_and_skips(tmp_path):
    markers = tmp_path / "m"
    markers.mkdir()
    members = dict(list(_members(markers, None).items())[:3])
    first = run_ensemble(chain_member, members, tmp_path, scheduler="inline", progress=False)
    again = run_ensemble(chain_member, members, tmp_path, scheduler="inline", progress=False)
    assert _count(markers, "done") == {k: 1 for k in members}      # nothing computed twice
    for k in members:
        assert member_path(tmp_path, k).is_file()
        assert all(np.array_equal(first[k][a], again[k][a], equal_nan=True) for a in first[k])
    with pytest.raises(ParameterError, match="not a file name"):
        run_ensemble(chain_member, {"../x": {}}, tmp_path, scheduler="inline")


def test_local_cluster_survives_a_killed_worker(tmp_path):
    markers = tmp_path / "m"
    markers.mkdir()
    members = _members(markers, kill_key="seed7")
    res = run_ensemble(chain_member, members, tmp_path / "out", scheduler="local", workers=2,
                       progress=False)
    assert (markers / "killed").exists()                            # a worker did die
    assert sorted(res) == sorted(members) and len(res) == 25
    done = _count(markers, "done")
    assert done == {k: 1 for k in members}                          # each completed once
    assert _count(markers, "start")["seed7"] == 2                   # the killed one reran
    # rerun: all 25 come from storage, none is computed again
    again = run_ensemble(chain_member, members, tmp_path / "out", scheduler="local", workers=2,
                         progress=False)
    assert _count(markers, "done") == done
    for k in members:
        assert int(again[k]["seed"]) == int(res[k]["seed"]) == int(k.removeprefix("seed"))
        assert np.array_equal(again[k]["tau"], res[k]["tau"], equal_nan=True)
