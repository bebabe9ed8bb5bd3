"""Files written atomically: a complete file or none; strict JSON.

A writer writes to a temporary file in the target's directory, which is then
renamed onto the target (``os.replace`` is atomic on one file system), so an
interrupted run never leaves a truncated result.  Temporary files are named
``.<name>.<random>.tmp``: :func:`temporaries` finds the ones a killed writer
left behind.
"""

import json
import math
import os
import tempfile
from pathlib import Path

import numpy as np

__all__ = ["atomic_write", "json_clean", "temporaries", "write_json"]


def atomic_write(path, write):
    """Call ``write(tmp_path)``, then rename onto ``path`` (same directory)."""
    path = Path(path)
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    os.close(fd)
    try:
        write(tmp)
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(tmp, 0o666 & ~umask)  # mkstemp creates 0600
        os.replace(tmp, path)
    finally:
        if os.path.exists(tmp):
            os.unlink(tmp)


def json_clean(obj):
    """A JSON-safe copy: numpy scalars and arrays to Python, nan/inf to None, paths to str."""
    if isinstance(obj, dict):
        return {str(k): json_clean(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [json_clean(v) for v in obj]
    if isinstance(obj, np.ndarray):
        return json_clean(obj.tolist())
    if isinstance(obj, (bool, np.bool_)):
        return bool(obj)
    if isinstance(obj, (int, np.integer)):
        return int(obj)
    if isinstance(obj, (float, np.floating)):
        return float(obj) if math.isfinite(obj) else None
    if isinstance(obj, (complex, np.complexfloating)):
        return [json_clean(obj.real), json_clean(obj.imag)]
    if isinstance(obj, Path):
        return str(obj)
    return obj


def write_json(path, doc):
    """Write ``doc`` (cleaned by :func:`json_clean`) atomically as indented JSON."""
    text = json.dumps(json_clean(doc), indent=2, allow_nan=False) + "\n"
    atomic_write(path, lambda tmp: Path(tmp).write_text(text))


def temporaries(folder, name=None):
    """Temporary files of :func:`atomic_write` left in ``folder`` (of target ``name`` if given)."""
    folder = Path(folder)
    if not folder.is_dir():
        return []
    pattern = f".{name}.*.tmp" if name else ".*.tmp"
    return [p for p in folder.glob(pattern) if p.is_file()]
