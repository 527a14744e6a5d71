"""Writing a file atomically: a reader (ParaView, a resumed run) sees the old file or the new one, never
half of one; and a file the user points shoal at is replaced only if it is a plain file.

`write_text_atomic` is for files inside a run directory. `replace_file` is for files the user names on
the command line or in the Python API (a case file from ``shoal new``, a picture from ``plot-case`` or
``post``): it refuses a symbolic link, a directory or a special file (a FIFO, a device), creates the
missing folders, and turns a full disk or another failed write into one line (`OutputError`), with the
temporary file removed and the target untouched.
"""

from __future__ import annotations

import errno
import os
import stat
from pathlib import Path

from ..errors import InputError, OutputError
from ..faults import reached

_KINDS = ((stat.S_ISDIR, "a directory"), (stat.S_ISFIFO, "a FIFO"), (stat.S_ISCHR, "a character device"),
          (stat.S_ISBLK, "a block device"), (stat.S_ISSOCK, "a socket"))


def write_bytes_atomic(path, data, chunk=1 << 24):
    """Write `data` to `path` through ``<path>.tmp``: written in chunks with ``os.write`` (a full disk is an
    `OSError` ENOSPC), fsynced, then renamed over `path` (``os.replace``, atomic on POSIX and Windows). On
    any error the temporary file is removed and the error re-raised; `path` is untouched."""
    path = Path(path)
    tmp = path.with_name(path.name + ".tmp")
    try:
        fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o644)
        try:
            view = memoryview(data).cast("B")
            done = 0
            while done < len(view):
                done += os.write(fd, view[done:done + chunk])
                reached(f"write:{path.name}")  # a test hook (shoal.faults): killed mid-write
            os.fsync(fd)
        finally:
            os.close(fd)
        os.replace(tmp, path)
    except BaseException:
        try:
            tmp.unlink()
        except OSError:
            pass
        raise
    return path


def write_text_atomic(path, text):
    """Write `text` (UTF-8) to `path` atomically (`write_bytes_atomic`)."""
    return write_bytes_atomic(path, text.encode("utf-8"))


def check_target(path):
    """Raise `InputError` unless `path` is absent or a regular file: shoal never replaces a symbolic link,
    a directory or a special file (a FIFO, a device, a socket) with a file of its own."""
    path = Path(path)
    try:
        mode = os.lstat(path).st_mode
    except FileNotFoundError:
        return
    except NotADirectoryError:
        raise InputError(f"cannot write {path}: a part of {path.parent} is a file, not a folder") from None
    except OSError as err:
        raise InputError(f"cannot use {path} as an output file: {err.strerror or err}") from None
    if stat.S_ISLNK(mode):
        raise InputError(f"{path} is a symbolic link; shoal does not write through links: give the file's own "
                         "path or another name")
    for test, kind in _KINDS:
        if test(mode):
            raise InputError(f"{path} is {kind}, not a regular file; give a file name to write")


def _folder(path):
    """Create `path`'s missing parent folders; `InputError` when a part of the way is a file."""
    parent = Path(path).parent
    try:
        parent.mkdir(parents=True, exist_ok=True)
    except (FileExistsError, NotADirectoryError):
        raise InputError(f"cannot write {path}: a part of {parent} is a file, not a folder") from None


def write_failed(err, path):
    """The `OutputError` for a failed write of `path` (`OSError` `err`): a full disk or quota, else the
    system's reason."""
    if err.errno in (errno.ENOSPC, errno.EDQUOT):
        what = "no space left on device" if err.errno == errno.ENOSPC else "disk quota exceeded"
        return OutputError(f"{what} writing {path}: nothing was replaced; free space and try again")
    return OutputError(f"cannot write {path}: {err.strerror or err}")


def replace_file(path, write):
    """Create or replace the regular file `path`: ``write(tmp)`` writes ``<path>.tmp``, which is fsynced and
    renamed over `path`. Raises `InputError` for a target that is a link, a directory or a special file
    (`check_target`) or under a file; `OutputError` (one line) when the write fails, with the temporary file
    removed and `path` as it was."""
    path = Path(path)
    check_target(path)
    _folder(path)
    tmp = path.with_name(path.name + ".tmp")
    check_target(tmp)
    try:
        write(tmp)
        reached(f"write:{path.name}")  # a test hook (shoal.faults): killed before the rename
        fd = os.open(tmp, os.O_RDONLY)
        try:
            os.fsync(fd)
        finally:
            os.close(fd)
        os.replace(tmp, path)
    except OSError as err:
        raise write_failed(err, path) from None
    finally:
        try:
            if os.path.lexists(tmp):
                os.unlink(tmp)
        except OSError:
            pass
    return path
