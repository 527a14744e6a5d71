"""Errors every MPI rank raises together, and the checks that make them so.

A check that some rank may fail (a write, a particle leaving a slab, bad
input decided on rank 0) must end every rank the same way, or the others
wait forever in the next collective call: `collective_check` and `agree`
exchange the outcome and raise on every rank; the errors carry
``collective = True`` so the run's error handling knows no rank is left
behind (`shoal.parallel.run`).
"""

from __future__ import annotations

from ..errors import InputError, InstabilityError, OutputError
from ..simulation.resources import DISK_FULL, disk_full_message


class CollectiveError(InstabilityError):
    """An InstabilityError every rank raises together (a collective check)."""

    collective = True


class CollectiveInputError(InputError):
    """An InputError every rank raises together."""

    collective = True


def agree(comm, message):
    """Raise InputError(message of rank 0) on every rank when rank 0 found one."""
    message = comm.bcast(message, root=0)
    if message:
        raise InputError(message)


class CollectiveOutputError(OutputError):
    """An OutputError every rank raises together (a write failed on some rank)."""

    collective = True


def write_error(err, path):
    """One line for a failed write of `path` (`OSError` `err`)."""
    if err.errno in DISK_FULL:
        return disk_full_message(err, path.parent)
    return f"cannot write {path}: {err.strerror or err}"


def collective_check(comm, message):
    """Raise CollectiveOutputError on every rank when any rank passes a message (the first rank's)."""
    msgs = comm.allgather(message)
    for r, m in enumerate(msgs):
        if m:
            raise CollectiveOutputError(f"{m} (MPI rank {r})")
