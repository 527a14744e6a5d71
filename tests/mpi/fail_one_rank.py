"""Run under ``mpiexec -n 2``: rank 1 fails alone in its 5th rate evaluation (tests/test_mpi.py);
the run must end on every rank with rank 1's message, never hang."""

import sys

import shoal
import shoal.parallel as par
from shoal.cases.dam_break import dam_break_3d
from shoal.parallel.model import DistributedModel

calls = [0]
original = DistributedModel.compute_rates


def failing(self):
    calls[0] += 1
    if self.mpi_rank == 1 and calls[0] == 5:
        raise RuntimeError("injected failure on rank 1")
    return original(self)


DistributedModel.compute_rates = failing
assert par.world() is not None
shoal.run_case(dam_break_3d(dp=0.02, end_time=0.01), sys.argv[1], plot=False, overwrite=True)
