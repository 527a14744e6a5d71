"""`TimedComm`: a rank's messages to the others, and the seconds they take.

Every exchange of a distributed model goes through one object, so the time
spent communicating (waiting for the slowest rank included) is measured in
one place: ``shoal run`` reports its min and max over the ranks.
"""

from __future__ import annotations

import time

import numpy as np

from . import halo


class TimedComm:
    """An mpi4py communicator whose collective calls add their wall time to `seconds`.

    Parameters
    ----------
    comm : mpi4py communicator
    ring : bool
        The ranks form a ring (a periodic x axis): `shift` sends the last rank's
        rightward rows to rank 0 and rank 0's leftward rows to the last.
    """

    def __init__(self, comm, ring=False):
        self.comm = comm
        self.ring = bool(ring)
        self.rank = comm.Get_rank()
        self.size = comm.Get_size()
        self.seconds = 0.0
        """Wall time [s] spent in the calls below."""

    def timed(self, call, *args, **kw):
        """`call(*args, **kw)`, its wall time added to `seconds`."""
        t0 = time.perf_counter()
        try:
            return call(*args, **kw)
        finally:
            self.seconds += time.perf_counter() - t0

    def shift(self, to_left, to_right, ncols, counts=None, out=None):
        """Rows to the left and right neighbour ranks (`shoal.parallel.halo.shift`); returns
        (from_left, from_right)."""
        return self.timed(halo.shift, self.comm, to_left, to_right, ncols, counts, out, ring=self.ring)

    def allreduce(self, value, op="min"):
        """A Python number combined over the ranks (`op`: "min", "max" or "sum")."""
        from mpi4py import MPI

        return self.timed(self.comm.allreduce, value, op={"min": MPI.MIN, "max": MPI.MAX, "sum": MPI.SUM}[op])

    def reduce_array(self, buf, op="sum"):
        """A NumPy array combined element by element over the ranks (`op`: "min", "max" or "sum")."""
        from mpi4py import MPI

        buf = np.ascontiguousarray(buf)
        out = np.empty_like(buf)
        self.timed(self.comm.Allreduce, buf, out, op={"min": MPI.MIN, "max": MPI.MAX, "sum": MPI.SUM}[op])
        return out

    def allgather(self, value):
        """Every rank's `value`, in rank order, on every rank."""
        return self.timed(self.comm.allgather, value)

    def gather(self, value, root=0):
        """Every rank's `value` on `root` (None elsewhere)."""
        return self.timed(self.comm.gather, value, root=root)
