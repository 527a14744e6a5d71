"""MPI domain decomposition (issue 9): slabs along x, halos, migration, load balancing.

Under ``mpiexec -n N`` (N > 1) `build_model` returns a `DistributedModel`
holding this rank's slab of particles plus a halo of ghost copies of the
neighbour ranks' particles, and `run_case` runs over the ranks (`run.Ranks`). Outside
MPI nothing here is imported beyond this module, and `world()` only reads
the environment: the single-process path is unchanged.

- `decomposition`: slab cuts from the particles' x coordinates (weighted counts), at
  the start from the whole set and during a run (load balancing) from the ranks' slabs.
- `halo`: the exchange with the left and right neighbour ranks (mpi4py
  buffers, ``Sendrecv``) and the packing of particle rows.
- `model`: `DistributedModel`, the Model whose ``sort`` drops the old ghosts,
  migrates particles that left the slab, re-cuts the slabs when the load is
  unbalanced (on a schedule), receives a fresh halo and re-sorts;
  ``compute_rates`` refreshes the halo values first (every stage of every
  integrator); the time step is an MPI min.
- `gpu`: with the CUDA backend, each rank's GPU (its rank on the node
  modulo the node's devices), chosen before any CUDA context exists.
- `checkpoint`: per-rank checkpoint files and their manifest; ``--resume`` on
  the same number of ranks (bitwise), another (re-distributed) or one process
  (the union of the ranks' particles in a single-process Model).
- `collective`: the errors every rank raises together.
- `run`: `Ranks`, what a run does on several ranks (`shoal.runner` runs every run):
  per-rank VTU pieces and a ``.pvtu`` per snapshot, gauges and probes written by rank 0, checkpoints.
"""

from __future__ import annotations

import os

# environment variables an MPI launcher sets (MPICH/Intel MPI hydra and PMI-1/2, Open MPI, MVAPICH, PMIx)
_SIZE_VARS = ("PMI_SIZE", "OMPI_COMM_WORLD_SIZE", "MV2_COMM_WORLD_SIZE", "PMIX_SIZE")
_world = False  # not looked up yet


def launched_by_mpi():
    """True when an MPI launcher started this process with more than one rank
    (read from the environment only; mpi4py is not imported)."""
    if os.environ.get("SHOAL_MPI", "") == "0":
        return False
    for v in _SIZE_VARS:
        try:
            if int(os.environ.get(v, "1")) > 1:
                return True
        except ValueError:
            pass
    return os.environ.get("SHOAL_MPI", "") == "1"


def world():
    """``MPI.COMM_WORLD`` when running on more than one MPI rank, else None.

    Zero cost outside MPI: mpi4py is imported only when the environment says
    an MPI launcher started more than one process (``SHOAL_MPI=0`` forces the
    single-process path; ``SHOAL_MPI=1`` asks mpi4py, and takes the MPI path
    even on one rank: ``SHOAL_MPI=1 mpiexec -n 1 shoal run ...`` runs a
    `DistributedModel` over `shoal.parallel.run.Ranks`, which a test compares
    with a single-process run)."""
    global _world
    if _world is False:
        comm = None
        if launched_by_mpi():
            try:
                from mpi4py import MPI
            except ImportError:
                from ..errors import InputError

                raise InputError("started by an MPI launcher (mpiexec) but mpi4py is not installed; install the "
                                 "extra: pip install 'shoal[mpi]'") from None
            if MPI.COMM_WORLD.Get_size() > 1 or os.environ.get("SHOAL_MPI", "") == "1":
                comm = MPI.COMM_WORLD
        _world = comm
    return _world


def rank():
    """This process's MPI rank (0 outside MPI)."""
    c = world()
    return 0 if c is None else c.Get_rank()


def quiet_other_ranks():
    """Under mpiexec, send the stdout and stderr of ranks other than 0 to /dev/null (the
    command line's messages are printed once; a rank that fails alone still writes its
    error to the real stderr before ending every rank, see `run.abort`)."""
    if not launched_by_mpi():
        return
    for v in ("PMI_RANK", "OMPI_COMM_WORLD_RANK", "MV2_COMM_WORLD_RANK", "PMIX_RANK"):
        r = os.environ.get(v)
        if r is not None:
            if r.strip() not in ("", "0"):
                import sys

                sys.stdout = open(os.devnull, "w")
                sys.stderr = open(os.devnull, "w")
            return
