"""A test hook: the process kills itself with SIGKILL at a named point of a run (``SHOAL_FAULT``).

``tests/test_kill_anywhere.py`` kills ``shoal run`` while the particles are generated, while the kernels
compile, in the middle of a time step, in the middle of writing a checkpoint or a snapshot, and checks
that a re-run or a ``--resume`` then always works. A kill sent from outside at a random moment hits a
phase of a few milliseconds (a checkpoint write) only by chance; this hook hits it every time.

``SHOAL_FAULT=PATTERN`` or ``SHOAL_FAULT=PATTERN@N``: the N-th time (default: the first) the process
reaches a point whose name matches the shell pattern PATTERN (`fnmatch.fnmatchcase`), it sends itself
SIGKILL: no handler, ``finally`` block or buffered write runs, as when the kernel's out-of-memory killer or
a batch system's time limit ends a run. The points:

``generate``
    particle generation, at the start of each slab of lattice columns (`shoal.geometry.generate`);
``compile``
    a kernel's first call on the CPU, before it runs (its compilation, or its load from Numba's cache);
``step``
    the middle of a time step: the integrator has moved the particles, the time and the step count are
    not advanced yet, the step's callbacks have not run;
``write:NAME``
    an atomic write of the file NAME (a checkpoint ``ckpt_NNNNNN.h5``, a snapshot ``<case>_NNNN.vtu``,
    ``<case>.pvd``, ``resolved.json``, ``case.toml``): its first bytes are in ``NAME.tmp``, which is not
    yet complete, fsynced or renamed over NAME;
``remove:NAME``
    ``--overwrite`` clearing an earlier run's files, before it removes NAME.

Unset, as everywhere outside those tests, `reached` returns at once: the variable is read once, when this
module is imported.
"""

from __future__ import annotations

import os

_SPEC = os.environ.get("SHOAL_FAULT") or None
_seen = 0


def reached(point):
    """Kill this process with SIGKILL if `point` is the one ``SHOAL_FAULT`` names (a test hook; see the
    module docstring); otherwise do nothing.

    Parameters
    ----------
    point : str
        The name of the point reached, e.g. ``"step"`` or ``"write:ckpt_000066.h5"``.
    """
    if _SPEC is None:
        return
    global _seen
    import fnmatch
    import signal

    pattern, _, nth = _SPEC.partition("@")
    if fnmatch.fnmatchcase(point, pattern):
        _seen += 1
        if _seen == int(nth or 1):
            os.kill(os.getpid(), signal.SIGKILL)
