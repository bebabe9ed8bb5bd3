"""Issue 39: a record carries its digest; readers refuse a record edited after its run.

``ResultDir.finish`` writes ``record_sha256``, the SHA-256 of the canonical JSON of the
record without it (:func:`fricstab.io.rundir.record_digest`); :func:`fricstab.io.rundir.verify`
refuses a mismatch, a missing digest on a record with a manifest, and a record of this
``record_version`` without a manifest, in one line naming the file and "rerun with --force".
A record of ``record_version`` 1 (or none) without a manifest, written before manifests, is
still read unchecked.
"""

import json

import numpy as np
import pytest

from fricstab.errors import ParameterError
from fricstab.io import rundir
from fricstab.io.files import json_clean
from fricstab.io.results import RECORD_VERSION, ResultDir


def _finished(path, params=None):
    params = params or {"x": 1, "y": [0.1, float("nan")]}
    rd = ResultDir(path, "demo", fingerprint=params).create()
    rd.write_npz("a.npz", a=np.arange(3))
    return rd.finish({"n": 1, "v": np.float64(1 / 3)}, parameters=params)


def _edit(path, change):
    record = path / "demo.json"
    doc = json.loads(record.read_text())
    change(doc)
    record.write_text(json.dumps(doc))


def test_the_record_holds_the_digest_of_what_is_on_disk(tmp_path):
    doc = _finished(tmp_path)
    on_disk = json.loads((tmp_path / "demo.json").read_text())
    assert json_clean(doc) == on_disk and doc["record_version"] == RECORD_VERSION == 2
    assert on_disk[rundir.DIGEST] == rundir.record_digest(on_disk)
    assert rundir.verify(tmp_path, "demo") == on_disk
    # the index keeps its own version: its format did not change
    assert json.loads((tmp_path / "result.json").read_text())["index_version"] == 1


EDITS = {
    "a parameter": (lambda r: r["parameters"].update(x=2), "does not match its digest"),
    "a number": (lambda r: r.update(n=2), "does not match its digest"),
    "the fingerprint": (lambda r: r["fingerprint"].update(sha256="0" * 64),
                        "does not match its digest"),
    "the manifest deleted": (lambda r: r.pop("files"), "does not match its digest"),
    "the digest deleted": (lambda r: r.pop(rundir.DIGEST), "has no record digest"),
    "the digest changed": (lambda r: r.update({rundir.DIGEST: "f" * 64}),
                           "does not match its digest"),
    "manifest and digest deleted": (lambda r: (r.pop("files"), r.pop(rundir.DIGEST)),
                                    "no manifest and no digest"),
    # a knowing edit: the digest recomputed, the manifest gone
    "manifest deleted, digest recomputed": (
        lambda r: (r.pop("files"), r.update({rundir.DIGEST: rundir.record_digest(r)})),
        "has no manifest"),
}


@pytest.mark.parametrize("edit", sorted(EDITS))
def test_an_edited_record_is_refused_naming_it(edit, tmp_path):
    """Before: every one of these but 'the digest changed' (no digest then) was accepted:
    the manifest's files still matched, and a record without a manifest passed as old."""
    _finished(tmp_path)
    change, words = EDITS[edit]
    _edit(tmp_path, change)
    with pytest.raises(ParameterError) as exc:
        rundir.verify(tmp_path, "demo")
    msg = str(exc.value)
    assert "demo.json" in msg and words in msg and "rerun with --force" in msg, msg
    assert "\n" not in msg


def test_reindenting_the_record_keeps_it_readable(tmp_path):
    """The digest is of the JSON's content, not its bytes."""
    _finished(tmp_path)
    _edit(tmp_path, lambda r: None)      # json.dumps without indent: other bytes
    assert rundir.verify(tmp_path, "demo")["n"] == 1


def test_a_record_from_before_manifests_is_read_unchecked(tmp_path):
    _finished(tmp_path)
    _edit(tmp_path, lambda r: (r.pop("files"), r.pop(rundir.DIGEST),
                               r.update(record_version=1)))
    assert rundir.verify(tmp_path, "demo")["n"] == 1
    _edit(tmp_path, lambda r: r.pop("record_version"))
    assert rundir.verify(tmp_path, "demo")["n"] == 1


def test_a_record_from_before_digests_is_refused(tmp_path):
    """A record_version 1 record with a manifest (no digest yet): rerun with --force."""
    _finished(tmp_path)
    _edit(tmp_path, lambda r: (r.pop(rundir.DIGEST), r.update(record_version=1)))
    with pytest.raises(ParameterError, match=r"demo.json has no record digest .*--force"):
        rundir.verify(tmp_path, "demo")
