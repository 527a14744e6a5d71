"""Settings in the environment that shoal cannot run with, found before Numba reads them.

Numba reads its variables when it is first imported (which ``import shoal`` does): a thread count of 0
ends that import in a traceback, an unreadable one is dropped with a warning, and ``NUMBA_DISABLE_JIT``
leaves shoal's kernels uncompiled. `numba_environment_error` names the first such setting in one line.
`interrupted_while_starting` answers Ctrl-C while the command's modules load.
"""

from __future__ import annotations

import os

NUMBA_LAYERS = ("default", "safe", "forksafe", "threadsafe", "tbb", "omp", "workqueue")
"""The values ``NUMBA_THREADING_LAYER`` may take."""


def numba_environment_error(env):
    """One line naming a Numba setting of `env` (a mapping such as ``os.environ``) that shoal cannot run
    with, and what is allowed; None when there is none: ``NUMBA_NUM_THREADS`` not a whole number >= 1, an
    unknown ``NUMBA_THREADING_LAYER``, ``NUMBA_DISABLE_JIT`` set."""
    threads = env.get("NUMBA_NUM_THREADS")
    if threads is not None:
        try:
            ok = int(threads.strip()) >= 1
        except ValueError:
            ok = False
        if not ok:
            return (f"NUMBA_NUM_THREADS = {threads!r}: give a whole number of threads >= 1, or unset it (all the "
                    "cores)")
    layer = env.get("NUMBA_THREADING_LAYER")
    if layer is not None and layer.strip() not in NUMBA_LAYERS:
        return (f"NUMBA_THREADING_LAYER = {layer!r} is not a Numba threading layer; allowed: "
                f"{', '.join(NUMBA_LAYERS)}, or unset it")
    if env.get("NUMBA_DISABLE_JIT", "0").strip() not in ("", "0"):
        return f"NUMBA_DISABLE_JIT = {env['NUMBA_DISABLE_JIT']!r}: shoal's kernels run only compiled; unset it"
    return None


def on_command_line(argv):
    """Whether this process is the ``shoal`` command: ``shoal ...``, or ``python -m shoal ...`` while
    its package loads (Python sets ``argv[0]`` to ``"-m"`` until the module is found)."""
    return os.path.basename(argv[0] if argv else "") in ("shoal", "-m")


def interrupted_while_starting(signum, frame):
    """SIGINT handler of the command while its modules load (NumPy, SciPy, Numba: a second or more):
    one line instead of a traceback from whichever import Ctrl-C hit, exit status 128 + signum."""
    os.write(2, b"shoal: interrupted while starting; nothing was written\n")
    os._exit(128 + signum)
