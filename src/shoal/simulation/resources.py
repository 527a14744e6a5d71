"""During a run: its directory's lock and a full disk.

`lock_run_dir` keeps two processes out of one run directory;
`disk_full_message` words an ENOSPC/EDQUOT error for the user. (Whether a
run fits in memory is decided before it starts: `shoal.memory`.)
"""

from __future__ import annotations

import errno
import os

from ..errors import InputError

DISK_FULL = (errno.ENOSPC, errno.EDQUOT)


def lock_run_dir(out_dir):
    """Hold an exclusive lock on ``out_dir/.shoal.lock`` (flock) for the
    run: a second shoal process in the same directory (a job submitted
    twice, a ``--resume`` while the run is still going) is refused with
    `InputError`. Returns the open lock file; closing it releases the lock
    (the process ending does too, however it ends)."""
    import fcntl

    path = os.path.join(out_dir, ".shoal.lock")
    f = open(path, "a+")
    try:
        fcntl.flock(f.fileno(), fcntl.LOCK_EX | fcntl.LOCK_NB)
    except BlockingIOError:
        f.seek(0)
        pid = f.read().strip()
        f.close()
        raise InputError(f"another shoal process{f' (pid {pid})' if pid else ''} is running in {out_dir}; "
                         "wait for it to end or stop it (SIGTERM writes a checkpoint) before running or "
                         "resuming there") from None
    except OSError:
        return f  # a file system without locks: run unlocked
    f.seek(0)
    f.truncate()
    f.write(f"{os.getpid()}\n")
    f.flush()
    return f


def disk_full_message(err, out_dir, checkpoint=None):
    """One line for a write that failed with ENOSPC/EDQUOT."""
    what = "no space left on device" if err.errno == errno.ENOSPC else "disk quota exceeded"
    where = f" writing {err.filename}" if getattr(err, "filename", None) else f" writing to {out_dir}"
    then = (f"; resume from {checkpoint.name} with `shoal run --resume {out_dir}` once space is freed"
            if checkpoint is not None else "; free space and run again")
    return f"{what}{where}: the run stopped, files already written are intact{then}"
