"""One GPU per MPI rank (the CUDA backend under ``mpiexec``).

Each rank uses the CUDA device numbered by its rank among the ranks on its
node (the ``MPI.COMM_TYPE_SHARED`` split of the world communicator) modulo
the number of devices the node shows it (``CUDA_VISIBLE_DEVICES`` applies):
4 ranks on a node with 4 GPUs get one each; with fewer devices than ranks,
ranks share a device (rank 4 of a node with 4 GPUs shares device 0 with
rank 0), which works but runs them one after the other on that GPU. The
device is chosen before this process creates any CUDA context
(`DistributedModel` does it before compiling the backend). No CUDA-aware
MPI is needed: halos and migrating particles travel through host memory
(`shoal.parallel.model`).
"""

from __future__ import annotations

from ..errors import InputError


def device_for_rank(local_rank, n_devices):
    """The CUDA device a rank uses: its rank on the node modulo the node's device count.

    Parameters
    ----------
    local_rank : int
        The rank's number among the ranks on its node (0-based).
    n_devices : int
        Number of CUDA devices visible to the rank.

    Returns
    -------
    int
        The device number, in ``0 .. n_devices - 1``.

    Raises
    ------
    InputError
        No device visible, or a negative rank.
    """
    if isinstance(local_rank, bool) or int(local_rank) != local_rank or local_rank < 0:
        raise InputError(f"local rank {local_rank!r}: give a whole number >= 0")
    if isinstance(n_devices, bool) or int(n_devices) != n_devices or n_devices < 1:
        raise InputError(f"{n_devices!r} CUDA devices visible to this rank: the cuda backend needs at least one "
                         "(check CUDA_VISIBLE_DEVICES and the job's GPU request), or use --backend cpu")
    return int(local_rank) % int(n_devices)


def describe(assignment):
    """Lines for ``run.log`` and ``shoal info`` naming each rank's device.

    Parameters
    ----------
    assignment : list of dict
        One per rank, in rank order (`select_device`): ``rank``, ``host``,
        ``local_rank``, ``local_size``, ``devices``, ``device``, ``name``.

    Returns
    -------
    list of str
        One line per rank (``rank 1 (node n1, local rank 1): CUDA device 1 (NAME) of 2``),
        then one line per node whose ranks share a device.
    """
    lines = [f"rank {a['rank']} (node {a['host']}, local rank {a['local_rank']}): CUDA device {a['device']} "
             f"({a['name']}) of {a['devices']}" for a in assignment]
    nodes = {}
    for a in assignment:
        nodes.setdefault(a["host"], []).append(a)
    for host, ranks in nodes.items():
        used = {a["device"] for a in ranks}
        if len(used) < len(ranks):
            lines.append(f"node {host}: {len(ranks)} ranks share {len(used)} CUDA device(s) ({ranks[0]['devices']} "
                         "visible): ranks on one device take turns on it")
    return lines


def _device_name(cuda, k):
    import os

    if os.environ.get("NUMBA_ENABLE_CUDASIM") == "1":
        return "CUDA simulator"
    name = cuda.gpus[k].name
    return name.decode() if isinstance(name, bytes) else str(name)


def local_rank(comm):
    """(rank, size) of this process among the ranks on its node (collective over `comm`)."""
    from mpi4py import MPI

    local = comm.Split_type(MPI.COMM_TYPE_SHARED, key=comm.Get_rank())
    try:
        return local.Get_rank(), local.Get_size()
    finally:
        local.Free()


def select_device(comm, activate=True):
    """Choose this rank's CUDA device (`device_for_rank`) and make it current (collective).

    Call before this process creates a CUDA context: `DistributedModel` does,
    before it compiles the CUDA backend.

    Parameters
    ----------
    comm : mpi4py communicator
        The ranks of the run.
    activate : bool
        Make the device current (``numba.cuda.select_device``); False only
        reports what each rank would use (``shoal info``).

    Returns
    -------
    list of dict
        Every rank's choice, the same on every rank (see `describe`).

    Raises
    ------
    InputError
        On every rank, when any rank sees no device or cannot use its own
        (a CUDA context on another device already exists in that process).
    """
    import platform

    from numba import cuda

    lr, ls = local_rank(comm)
    msg = None
    info = {"rank": comm.Get_rank(), "host": platform.node(), "local_rank": lr, "local_size": ls,
            "devices": 0, "device": -1, "name": ""}
    try:
        n = len(cuda.gpus)
        k = device_for_rank(lr, n)
        info.update(devices=n, device=k, name=_device_name(cuda, k))
        if activate:
            cuda.select_device(k)
    except InputError as err:
        msg = str(err)
    except Exception as err:  # noqa: BLE001 -- a driver error, or a context already current on another device
        why = " ".join(str(err).split())
        msg = f"cannot use CUDA device {info['device']}: {why}"
    out = comm.allgather((info, msg))
    for r, (_, m) in enumerate(out):
        if m:
            raise InputError(f"MPI rank {r}: {m}")
    return [i for i, _ in out]
