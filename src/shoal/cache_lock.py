"""An inter-process lock on Numba's on-disk cache.

Numba keeps the compiled specialisations of a ``cache=True`` function in one
index file (``<function>.nbi``) that maps each signature to a data file
(``<function>.<n>.nbc``). Saving an entry is a read-modify-write of that
index: read it, take the first free number ``n``, write the index back, write
the data file. Two processes that compile two signatures of one function at
the same moment (MPI ranks, a parameter sweep, pytest-xdist workers on one
cache directory) can both read the same index, both take ``n = 1``, and
leave an index whose entry for one signature names the other's machine code;
a later process then loads it and computes garbage or crashes (shoal saw a
test worker segfault that way). The last writer also drops the other's
entry, so every later process compiles it again.

`install` wraps `numba.core.caching.IndexDataCacheFile`'s ``save`` and
``flush`` in an exclusive ``flock`` on ``<index>.lock`` beside the index,
and ``load`` in a shared one, so each read-modify-write of an index is
atomic across processes. Compiling is not serialised (the lock is held only
while an index and its data file are read or written). Where ``flock`` is
missing (Windows) or the lock file cannot be opened, the cache works as
Numba's own does, unlocked.
"""

from __future__ import annotations

import contextlib
import functools

try:
    import fcntl
except ImportError:  # not POSIX
    fcntl = None


@contextlib.contextmanager
def _flock(index_path, exclusive):
    """Hold ``flock`` on ``index_path + ".lock"`` (exclusive or shared) inside the block."""
    try:
        f = open(index_path + ".lock", "a")
    except OSError:  # a read-only cache directory: Numba will not write there either
        yield
        return
    with f:
        try:
            fcntl.flock(f.fileno(), fcntl.LOCK_EX if exclusive else fcntl.LOCK_SH)
        except OSError:  # a file system without locks
            pass
        yield  # closing the file releases the lock


def _locked(method, exclusive):
    @functools.wraps(method)
    def wrapper(self, *args):
        with _flock(self._index_path, exclusive):
            return method(self, *args)
    wrapper._shoal_cache_lock = True
    return wrapper


def install():
    """Make Numba's cache index reads and writes atomic across processes.

    Idempotent; returns True when the lock is in place, False where it cannot
    be (no ``fcntl``, or a Numba whose cache lacks the methods wrapped).
    """
    if fcntl is None:
        return False
    try:
        from numba.core.caching import IndexDataCacheFile as cls
    except ImportError:
        return False
    if not all(callable(getattr(cls, m, None)) for m in ("save", "load", "flush")):
        return False
    if getattr(cls.save, "_shoal_cache_lock", False):
        return True
    cls.save = _locked(cls.save, exclusive=True)
    cls.flush = _locked(cls.flush, exclusive=True)
    cls.load = _locked(cls.load, exclusive=False)
    return True
