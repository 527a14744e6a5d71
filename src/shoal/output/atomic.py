"""Writing a text file atomically: a reader (ParaView, a resumed run) sees the old file or the new one,
never half of one."""

from __future__ import annotations

import os
from pathlib import Path


def write_text_atomic(path, text):
    """Write `text` to `path` through ``<path>.tmp``: flushed, fsynced, then renamed over `path`
    (``os.replace``, atomic on POSIX and Windows); the temporary file is removed on any failure."""
    path = Path(path)
    tmp = path.with_name(path.name + ".tmp")
    try:
        with open(tmp, "w", encoding="utf-8") as f:
            f.write(text)
            f.flush()
            os.fsync(f.fileno())
        os.replace(tmp, path)
    finally:
        if tmp.exists():
            tmp.unlink()
    return path
