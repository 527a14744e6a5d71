"""Exchanges with the left and right neighbour ranks, and the packing of particle rows.

Particle rows travel as one float64 matrix per direction (float32 and
integer columns are exact in float64): the receiver knows the column layout
from its own arrays. Every exchange is a pair of ``Sendrecv`` calls, first
rightwards (send to rank + 1, receive from rank - 1), then leftwards, with
``MPI.PROC_NULL`` at the ends (or, along a periodic x axis, round the ring:
the last rank and rank 0 are neighbours; with 2 ranks each is the other's
left and right, the tags keep the two directions apart), so it never
deadlocks.
"""

from __future__ import annotations

import numpy as np

from ..backends.loops import row_columns


def columns(arrays):
    """Number of float64 columns a row of `arrays` packs into."""
    return sum(w for _, _, w in row_columns(arrays))


def pack(arrays, rows):
    """(len(rows), columns) float64 matrix of the given rows of each array."""
    rows = np.asarray(rows, np.int64)
    out = np.empty((len(rows), columns(arrays)), np.float64)
    for a, c, w in row_columns(arrays):
        out[:, c:c + w] = a[rows].reshape(len(rows), w)
    return out


def unpack(arrays, buf, rows):
    """Write the packed matrix `buf` into `rows` (an index array or a slice) of each array."""
    for a, c, w in row_columns(arrays):
        vals = buf[:, c:c + w]
        a[rows] = (vals[:, 0] if a.ndim == 1 else vals).astype(a.dtype)


def neighbours(comm, ring=False):
    """(left, right) ranks: MPI.PROC_NULL at the ends, or with `ring` (a periodic x axis) the
    last rank left of rank 0 and rank 0 right of the last."""
    from mpi4py import MPI

    r, s = comm.Get_rank(), comm.Get_size()
    if ring:
        return (r - 1) % s, (r + 1) % s
    return (r - 1 if r > 0 else MPI.PROC_NULL), (r + 1 if r < s - 1 else MPI.PROC_NULL)


def shift(comm, to_left, to_right, ncols, counts=None, out=None, ring=False):
    """Send `to_left` to rank - 1 and `to_right` to rank + 1 (round the ring with `ring`); return
    what arrives (from_left, from_right) as (k, ncols) float64 matrices.

    `counts` = (from_left, from_right) row counts when the receiver knows
    them already (a halo refresh); otherwise they are exchanged first.
    `out` = (from_left, from_right): C-contiguous float64 matrices of those
    counts to receive into (preallocated buffers; then `counts` is ignored)."""
    from mpi4py import MPI

    left, right = neighbours(comm, ring)
    if out is not None:
        counts = (len(out[0]), len(out[1]))
    elif counts is None:
        sl = np.array([len(to_left)], np.int64)
        sr = np.array([len(to_right)], np.int64)
        rl = np.zeros(1, np.int64)
        rr = np.zeros(1, np.int64)
        comm.Sendrecv([sr, MPI.INT64_T], dest=right, sendtag=11, recvbuf=[rl, MPI.INT64_T], source=left, recvtag=11)
        comm.Sendrecv([sl, MPI.INT64_T], dest=left, sendtag=12, recvbuf=[rr, MPI.INT64_T], source=right, recvtag=12)
        counts = (int(rl[0]), int(rr[0]))
    if out is None:
        from_left = np.empty((counts[0], ncols), np.float64)
        from_right = np.empty((counts[1], ncols), np.float64)
    else:
        from_left, from_right = out
    sr = np.ascontiguousarray(to_right, np.float64)
    sl = np.ascontiguousarray(to_left, np.float64)
    comm.Sendrecv([sr, MPI.DOUBLE], dest=right, sendtag=13, recvbuf=[from_left, MPI.DOUBLE], source=left,
                  recvtag=13)
    comm.Sendrecv([sl, MPI.DOUBLE], dest=left, sendtag=14, recvbuf=[from_right, MPI.DOUBLE], source=right,
                  recvtag=14)
    return from_left, from_right
