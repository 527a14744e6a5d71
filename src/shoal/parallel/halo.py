"""A rank's halo (`Halo`), the exchanges with the left and right neighbour ranks, and the packing of
particle rows.

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


class Halo:
    """Ghost copies of the neighbour ranks' particles within `width` of this rank's slab.

    The ghosts are rows ``n_owned .. n_owned + n_ghost`` of the model's arrays
    when `append` receives them, flagged 1 in ``model.ghost`` (an array that
    follows the sort); after the sort they are spread over the cell order and
    `reorder` records where: `ghost_rows`, and `send` (the rows that
    neighbours hold copies of, left and right). Between sorts `refresh`
    copies the owners' current position, velocity and density into the
    ghosts; `clear_rates` zeroes the ghosts' rates (each particle's rates are
    its owner's).

    Parameters
    ----------
    model : DistributedModel
        The rank's model (its store of arrays, ``keep_rows``, ``append_rows``).
    link : TimedComm
        The messages to the neighbour ranks.
    slabs : Slabs
        The ranks' slabs.
    width : float
        Halo width [m] (see `shoal.parallel.model`).
    """

    def __init__(self, model, link, slabs, width):
        self.model, self.link, self.slabs, self.width = model, link, slabs, float(width)
        none = np.zeros(0, np.int64)
        self.n_owned = model.n
        self.n_ghost = 0
        self.send = (none, none)
        """(left, right): rows whose copies the left / right neighbour holds."""
        self.ghost_rows = none
        """Rows of the ghosts, those from the left neighbour first."""
        self.counts = (0, 0)
        """Ghosts received from the left and from the right."""
        self.fresh = False
        """Whether the ghosts hold their owners' current values."""
        self._buffers = {}
        self.place_rows()

    def sends(self, x):
        """(to the left, to the right): the rows of positions `x` within the halo width of this
        slab's left / right bound, for the neighbour on that side (none at an end without one)."""
        r, w, s = self.slabs.rank, self.width, self.slabs
        lo, hi = s.bounds()
        none = np.zeros(0, np.int64)
        left = np.flatnonzero(x < lo + w) if r > 0 or s.ring else none
        right = np.flatnonzero(x >= hi - w) if r < s.size - 1 or s.ring else none
        return left, right

    def estimate(self):
        """Rough number of ghosts: this rank's particles within the halo width of its slab bounds."""
        m = self.model
        left, right = self.sends(m.store.host_of(m.pos)[: m.n, 0])
        return len(left) + len(right)

    def drop(self):
        """Forget the ghosts: the owned rows move to the front (host arrays)."""
        m = self.model
        if self.n_ghost:
            m.keep_rows(np.flatnonzero(m.store.host_of(m.ghost)[: m.n] == 0))
        self.n_ghost = 0

    def append(self):
        """Receive the neighbours' particles within the halo width as ghost rows n.. (host arrays)."""
        m = self.model
        n = m.n
        send_l, send_r = self.sends(m.store.host_of(m.pos)[:n, 0])
        arrays = m.host_state()
        from_l, from_r = self.link.shift(pack(arrays, send_l), pack(arrays, send_r), columns(arrays))
        g = m.append_rows(np.concatenate([from_l, from_r]), ghost=1)
        m.store.host_of(m.ghost)[:n] = 0
        self.n_owned, self.n_ghost = n, g
        self.send = (send_l, send_r)
        self.counts = (len(from_l), len(from_r))

    def reorder(self, perm):
        """Follow the sort: `perm` (host, rows 0..n) maps each new row to its row before the sort."""
        n = len(perm)
        inv = np.empty(n, np.int64)
        inv[perm] = np.arange(n)
        self.send = (inv[self.send[0]], inv[self.send[1]])
        self.ghost_rows = inv[self.n_owned + np.arange(self.n_ghost)]
        self.place_rows()
        self.fresh = True

    def _buffer(self, name, shape, dtype, device):
        """The preallocated work array `name` with at least ``shape[0]`` rows: a backend
        array (`device`) or a NumPy one, allocated again (25 % larger) only when too small."""
        buf = self._buffers.get(name)
        if buf is None or buf.shape[0] < shape[0] or buf.shape[1:] != tuple(shape[1:]):
            full = (int(1.25 * shape[0]) + 64,) + tuple(shape[1:])
            buf = self.model.backend.zeros(full, dtype) if device else np.zeros(full, dtype)
            self._buffers[name] = buf
        return buf

    def place_rows(self):
        """Put the rows `refresh` sends (left, then right) and the ghost rows it writes where
        the backend's kernels read them (after a sort or a restore)."""
        b = self.model.backend
        send = np.concatenate(self.send).astype(np.int64)
        ghosts = np.asarray(self.ghost_rows, np.int64)
        if b.host_memory:
            self._send_rows, self._ghost_rows = send, ghosts
            return
        self._send_rows = self._buffer("send_rows", (len(send),), np.int64, True)
        self._ghost_rows = self._buffer("ghost_rows", (len(ghosts),), np.int64, True)
        b.copy_into(self._send_rows, send, len(send))
        b.copy_into(self._ghost_rows, ghosts, len(ghosts))

    def refresh(self):
        """Copy the owners' current position, velocity and density into the ghosts.

        Only the send and ghost rows travel: the backend packs the send rows into a
        float64 buffer (a kernel on the device), which is copied to a host buffer, sent
        (``Sendrecv``) into the host receive buffer, copied back and unpacked into the
        ghost rows (a kernel). On the CPU the backend and host buffers are one array.
        The buffers are allocated once (again only when a halo outgrows them)."""
        m = self.model
        b = m.backend
        arrays = [m.pos, m.vel, m.rho]
        ncols = columns(arrays)
        kl, kr = len(self.send[0]), len(self.send[1])
        gl, gr = self.counts
        d_send = self._buffer("send", (kl + kr, ncols), np.float64, True)
        d_recv = self._buffer("recv", (gl + gr, ncols), np.float64, True)
        host = b.host_memory
        h_send = d_send if host else self._buffer("send_host", (kl + kr, ncols), np.float64, False)
        h_recv = d_recv if host else self._buffer("recv_host", (gl + gr, ncols), np.float64, False)
        b.pack_rows(arrays, self._send_rows, kl + kr, d_send)
        if not host:
            b.copy_to_host(h_send, d_send, kl + kr)
        self.link.shift(h_send[:kl], h_send[kl:kl + kr], ncols, out=(h_recv[:gl], h_recv[gl:gl + gr]))
        if not host:
            b.copy_into(d_recv, h_recv, gl + gr)
        b.unpack_rows(arrays, d_recv, self._ghost_rows, len(self.ghost_rows))
        self.fresh = True

    def clear_rates(self):
        """Zero the ghosts' rates: each particle's rates are its owner's."""
        m = self.model
        g = len(self.ghost_rows)
        if g:
            rates = [m.ace, m.drho, m.mu_max] + ([m.xsph] if m.spec.xsph else [])
            m.backend.zero_rows(rates, self._ghost_rows, g)

    def checkpoint_state(self):
        """(scalars, arrays) an exact restart needs: the counts and the send and ghost rows."""
        scalars = {"n_owned": int(self.n_owned), "n_ghost": int(self.n_ghost),
                   "ghost_counts": [int(c) for c in self.counts], "halo_fresh": bool(self.fresh)}
        arrays = {"send_left": np.asarray(self.send[0], np.int64), "send_right": np.asarray(self.send[1], np.int64),
                  "ghost_rows": np.asarray(self.ghost_rows, np.int64)}
        return scalars, arrays

    def restore_state(self, scalars, arrays):
        """Put `checkpoint_state`'s (scalars, arrays) back."""
        self.n_owned = int(scalars["n_owned"])
        self.n_ghost = int(scalars["n_ghost"])
        self.counts = tuple(int(c) for c in scalars["ghost_counts"])
        self.fresh = bool(scalars["halo_fresh"])
        self.send = (np.asarray(arrays["send_left"], np.int64).copy(),
                     np.asarray(arrays["send_right"], np.int64).copy())
        self.ghost_rows = np.asarray(arrays["ghost_rows"], np.int64).copy()
        self.place_rows()
