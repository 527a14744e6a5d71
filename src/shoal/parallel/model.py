"""`DistributedModel`: one rank's slab of particles plus a halo of ghosts.

Layout. The rank's arrays hold its owned particles and ghost copies of the
neighbour ranks' particles within the halo width `w` of its slab bounds,
all sorted together into cell order on the same global cell grid as a
single-process run (so the neighbour search, the physics and the integrators
are the unchanged single-process code). ``ghost[i]`` (int8, follows the
sort) flags the ghosts. Ghosts are neighbours of owned particles; their own
rates are computed too (the simplest correct choice; the cost is the halo's
share of the particles) and then zeroed, so an integrator update leaves a
ghost's density unchanged and it just drifts until it is replaced.

Halo width. w = 2h + h/4 without SPS or no-slip walls. SPS's tau and the
no-slip wall velocity of a particle are sums over its own neighbours, used
by its neighbours' rates: a ghost within 2h of the slab feeds an owned
particle, and its tau / wall velocity needs the ghosts 2h beyond it, so
with SPS or no-slip walls w = 4h + h/4 and the ghosts compute their own
tau exactly (no second exchange). The h/4 margin covers the particles'
motion between the sort and the second rate evaluation of the two-stage
integrators (dt/2 at most CFL h c/c0 / 2, about 0.1 h).

Per step (``sort``): drop the ghosts; the single-process sort of the owned
particles (periodic y / symmetry wrap, escapes from the domain); migrate
the owned particles whose x left the slab to the rank on that side (a
particle may cross one boundary per step); receive a fresh halo (every
state array, the integrator's included); sort again. Per rate evaluation
(``compute_rates``): refresh the ghosts' position, velocity and density
from their owners (rows recorded at the sort), then the usual rates. The
time step is the min over ranks (``Allreduce``). Mass is exact: particles
have fixed mass and each is owned by exactly one rank.

Load balancing. Every `rebalance_interval` steps (at the sort) the ranks
compare their weighted counts (fluid 1, wall 0.25); when max / mean exceeds
`rebalance_threshold`, the cuts move to the weighted quantiles of the
particles' current x (`decomposition.distributed_cuts`, the start's cut code
run on the ranks' slabs: a few numbers per rank travel, no particles) and
the particles migrate to their new owners (several hops if a cut moved past
a neighbour's slab) before the fresh halo is fetched; the physics is
unchanged (a particle's rates do not depend on which rank owns it). Defaults: every 20
steps, threshold 1.1; the environment variables
``SHOAL_MPI_REBALANCE_INTERVAL`` (0: never) and
``SHOAL_MPI_REBALANCE_THRESHOLD`` set them for ``shoal run``, the keyword
arguments for the Python API. Each re-cut is recorded in ``rebalances``.

Backends. The same code runs on the CPU and the CUDA backend (one GPU per
rank, chosen by `shoal.parallel.gpu` before the backend creates its CUDA
context). The bookkeeping of a sort (dropping the ghosts, migration,
re-cuts, the new halo) edits NumPy arrays (`_host_of`): on the CPU the
particle arrays themselves; with CUDA host copies of the state, filled from
the device before and copied back after (the whole state, twice per sort),
while the single-process sort, the physics and the integrators stay on the
device. The halo refresh of every rate evaluation moves the send and ghost
rows only: the backend packs the send rows into a float64 buffer (a kernel),
the buffer goes through preallocated host memory to ``Sendrecv`` and back,
and the backend writes the received rows into the ghost rows (a kernel);
the ghosts' rates are zeroed on the device, and the time step, the checks
and the probes reduce the backend's results over the ranks as on the CPU.
No CUDA-aware MPI is needed.

Memory. Each rank's particle arrays hold its own particles and ghosts:
after the start's cut they shrink to `rows_wanted` (1.3 times the owned
particles, or the owned plus twice the estimated ghosts, and 1024 spare
rows; never more than the whole case), and grow by 25 % when a migration, a
re-cut or a new halo needs more rows. The CPU's NumPy arrays are resized in
place; device arrays cannot be, so `_reallocate` allocates new ones, copies
the rows on the device and re-points every reference (the model's
attributes, the integrator's, registered by ``new_array(..., owner=)``,
the host copies and the neighbour grid's work arrays). The motions'
initial positions (``pos_init``, indexed by the global particle id) keep
the whole case's size; so does each rank's host copy while the case is
built (every rank generates it, then builds the Model of its slab).

Outputs: ``world_positions``, ``fields`` etc. give the owned particles;
``sample`` (probes, gauges) gives every rank the same values: each point is
evaluated by the rank whose slab holds it (whose halo covers its support),
with a fresh halo. The particle probes (trackers, max-z and run-up gauges)
run the single-process code (`Model.particle_positions`, ``nearest_fluid``,
``highest_fluid``) on the owned particles (``owned_particles``: never the
ghosts) and combine the ranks' results, the same on every rank. ``check``
is collective: every rank raises the same `InstabilityError` when any rank
finds a bad particle.
"""

from __future__ import annotations

import time as _time

import numpy as np

from ..errors import InputError, InstabilityError
from ..model import Model
from ..options import SPHOptions
from ..physics.spec import FLUID, MOVING, REPULSIVE, REPULSIVE_MOVING
from . import halo as _halo
from .collective import CollectiveError
from .decomposition import distributed_cuts, imbalance, slab_cuts, weighted_counts

BOUNDARY_WEIGHT = 0.25
REBALANCE_INTERVAL = 20
REBALANCE_THRESHOLD = 1.1


def rebalance_settings(interval=None, threshold=None, environ=None):
    """(interval, threshold) of the load balancing: the arguments, else the
    environment (``SHOAL_MPI_REBALANCE_INTERVAL``, ``SHOAL_MPI_REBALANCE_THRESHOLD``),
    else the defaults (20 steps, 1.1).

    Parameters
    ----------
    interval : int, optional
        Steps between balance checks; 0 turns load balancing off.
    threshold : float, optional
        Re-cut when the ranks' max / mean weighted count exceeds it (>= 1).
    environ : mapping, optional
        Where to read the variables (default: ``os.environ``).

    Raises
    ------
    InputError
        A value that is not an integer >= 0 / a number >= 1.
    """
    import math
    import os

    env = os.environ if environ is None else environ
    if interval is None:
        text = env.get("SHOAL_MPI_REBALANCE_INTERVAL", "").strip()
        try:
            interval = int(text) if text else REBALANCE_INTERVAL
        except ValueError:
            raise InputError(f"SHOAL_MPI_REBALANCE_INTERVAL = {text!r}: give a whole number of steps >= 0 "
                             "(0: no load balancing)") from None
    if threshold is None:
        text = env.get("SHOAL_MPI_REBALANCE_THRESHOLD", "").strip()
        try:
            threshold = float(text) if text else REBALANCE_THRESHOLD
        except ValueError:
            raise InputError(f"SHOAL_MPI_REBALANCE_THRESHOLD = {text!r}: give a number >= 1 (the max / mean "
                             "weighted particle count that triggers a re-cut)") from None
    if isinstance(interval, bool) or int(interval) != interval or interval < 0:
        raise InputError(f"rebalance interval {interval!r}: give a whole number of steps >= 0 (0: no load balancing)")
    if not (math.isfinite(float(threshold)) and float(threshold) >= 1.0):
        raise InputError(f"rebalance threshold {threshold!r}: give a number >= 1 (max / mean weighted particle count)")
    return int(interval), float(threshold)


class DistributedModel(Model):
    """A Model holding one MPI rank's slab (see the module docstring).

    Called like a `Model` with the whole particle set (every rank generates
    it), it cuts the slabs, builds a `Model` of its own slab only (so a
    rank's arrays, on the device with CUDA, never hold the whole case) and
    sizes the arrays by `rows_wanted`.

    Parameters
    ----------
    positions, kinds, **kw
        As for `Model` (the whole particle set).
    comm : mpi4py communicator, optional
        Default ``shoal.parallel.world()``.
    cuts : sequence of float, optional
        The nranks - 1 inner slab bounds along x [m] to start from (default:
        the weighted quantiles, `slab_cuts`); load balancing moves them.
    rebalance_interval, rebalance_threshold : optional
        Load balancing (see the module docstring and `rebalance_settings`).
    """

    require_fluid = False  # a slab may hold no fluid; the whole case is checked for some

    def __init__(self, positions, kinds, *, comm=None, cuts=None, rebalance_interval=None,
                 rebalance_threshold=None, **kw):
        from . import world

        self.rebalance_interval, self.rebalance_threshold = rebalance_settings(rebalance_interval,
                                                                               rebalance_threshold)
        self.comm = comm if comm is not None else world()
        if self.comm is None:
            raise InputError("DistributedModel needs an MPI communicator (run under mpiexec with mpi4py)")
        self.gpus = None  # the CUDA device of every rank (`shoal.parallel.gpu.select_device`), CUDA only
        if kw.get("backend", "cpu") == "cuda":
            from ..backends import check_backend
            from .gpu import select_device

            check_backend("cuda")
            self.gpus = select_device(self.comm)  # before the backend creates this process's CUDA context
        positions, kinds = self.checked_particles(positions, kinds, kw.get("dp"), kw.get("dim"))
        self.ring = "x" in tuple(kw.get("periodic") or ())  # periodic x: the slabs close into a ring
        self.comm_seconds = 0.0
        self.mpi_rank = self.comm.Get_rank()
        self.mpi_size = self.comm.Get_size()
        options = kw.get("options") or SPHOptions()
        h = self.smoothing_length(options, kw["dim"], kw["dp"])
        # a first pass over the neighbours (SPS stress, no-slip wall velocity, Adami wall pressure) before
        # the rates: the ghosts that pass reads need their own neighbours, two supports deep
        wide = options.turbulence == "sps" or bool(options.no_slip) or options.wall_pressure == "adami"
        self.halo_width = (4.0 if wide else 2.0) * h + 0.25 * h
        if options.wall_pressure == "mdbc" and kw.get("wall_normals") is not None:
            # a wall ghost's density comes from the fluid within 2h of its ghost node, which lies up
            # to the largest x component of a ghost vector away across the slab cut (the cuts are
            # planes x = const): that fluid must be on the rank too
            g = np.asarray(kw["wall_normals"], np.float64)
            reach = float(np.abs(g[:, 0]).max()) if len(g) else 0.0
            self.halo_width = max(self.halo_width, 4.0 * h + reach + 0.25 * h)
        # with a ring of 2 ranks the neighbour on both sides is the same rank: a slab narrower than
        # two halo widths would send it a particle twice
        self.min_slab_width = (2.0 if self.ring and self.mpi_size == 2 else 1.0) * self.halo_width
        weights = np.where(kinds == FLUID, 1.0, BOUNDARY_WEIGHT)
        if cuts is None:
            self.cuts = slab_cuts(positions[:, 0], weights, self.mpi_size, self.min_slab_width)
        else:
            inner = np.asarray(cuts, np.float64).ravel()
            if len(inner) != self.mpi_size - 1 or np.any(np.diff(inner) < self.min_slab_width):
                raise InputError(f"cuts {inner.tolist()}: give {self.mpi_size - 1} increasing slab bounds at least "
                                 f"{self.min_slab_width:.4g} m apart")
            self.cuts = np.concatenate([[-np.inf], inner, [np.inf]])
        # build this rank's slab only (its arrays, on the device with CUDA); the particle ids stay
        # global: idp indexes pos_init / motion_of, which the motions keep for the whole case
        x = positions[:, 0]
        own = np.flatnonzero((x >= self.cuts[self.mpi_rank]) & (x < self.cuts[self.mpi_rank + 1]))
        mine = dict(kw)
        for key in ("velocities", "motion_of", "wall_normals"):
            if kw.get(key) is not None:
                mine[key] = np.asarray(kw[key])[own]
        super().__init__(positions[own], kinds[own], repulsive=bool(np.any(kinds >= REPULSIVE)), **mine)
        self.n_global = self.n_total = len(positions)
        self.x_period = (self._period_lo[0], float(self.params.per_len_x)) if self.ring else None  # (lo, L) [m]
        self.backend.copy_into(self.idp, own.astype(np.int32), len(own))
        if np.any((kinds == MOVING) | (kinds == REPULSIVE_MOVING)):  # a moving particle may come to any rank
            motion_of = kw.get("motion_of")
            cols = [0, 1, 2] if self.dim == 3 else [0, 2]
            self._init_motions(positions[:, cols], kinds, kw.get("motions"),
                               None if motion_of is None else np.asarray(motion_of))
        # the ghost vectors by global id, whole on every rank (a wall particle may come to any rank)
        self._init_wall_normals(kinds, kw.get("wall_normals"))
        self.sort_count = 0
        self.rebalances = []  # one dict per re-cut (see rebalance)
        self._capacity = self.n
        self.resizes = 0  # times the particle arrays were given another size (see `_resize`)
        self.ghost = self.backend.zeros(max(self.n, 1), np.int8)
        self.extra_arrays.append(self.ghost)  # follows the sort
        # host copies of the state (a backend whose arrays are not in host memory, see `_host_of`)
        self._host_copies = {}
        if not self.backend.host_memory:
            for a in self._state_arrays() + [self.ghost]:
                self._add_host_copy(a)
            self._to_host()
        self.n_ghost = 0
        self.n_owned = self.n
        self._in_sort = False
        self._halo_fresh = False
        self._send = (np.zeros(0, np.int64), np.zeros(0, np.int64))
        self._ghost_rows = np.zeros(0, np.int64)
        self._ghost_counts = (0, 0)
        self._buffers = {}
        self._set_halo_rows()
        self._resize(self.rows_wanted(self.n, self.n_ghost_estimate()))

    # ---------------------------------------------------------------- arrays
    spare_rows = 1024
    """Rows the particle arrays hold beyond 1.3 times the owned particles (or the owned plus twice
    the estimated ghosts): room for the water to move in before the arrays must grow."""

    @property
    def capacity(self):
        """Rows each per-particle array holds now (owned, ghosts and spare)."""
        return self._capacity

    def rows_wanted(self, owned, ghosts):
        """Rows to allocate for `owned` particles and about `ghosts` ghosts: max(1.3 owned +
        `spare_rows`, owned + 2 ghosts + `spare_rows`), at most the whole case (owned and ghosts
        are distinct particles of the case)."""
        want = max(int(1.3 * owned), owned + 2 * ghosts) + self.spare_rows
        return max(1, min(want, self.n_global))

    def slab(self, r=None):
        """(lo, hi) [m] of rank `r`'s slab (default this rank's): the cuts, with the domain's ends
        for the outer ranks along a periodic x axis (elsewhere they are -inf / +inf)."""
        r = self.mpi_rank if r is None else r
        lo, hi = float(self.cuts[r]), float(self.cuts[r + 1])
        if self.x_period is not None:
            lo = self.x_period[0] if r == 0 else lo
            hi = self.x_period[0] + self.x_period[1] if r == self.mpi_size - 1 else hi
        return lo, hi

    def _sends(self, x):
        """(to the left, to the right): the rows of positions `x` within the halo width of this
        slab's left / right bound, for the neighbour on that side (none at an end without one)."""
        r, w = self.mpi_rank, self.halo_width
        lo, hi = self.slab()
        none = np.zeros(0, np.int64)
        left = np.flatnonzero(x < lo + w) if r > 0 or self.ring else none
        right = np.flatnonzero(x >= hi - w) if r < self.mpi_size - 1 or self.ring else none
        return left, right

    def n_ghost_estimate(self):
        """Rough number of ghosts: particles within the halo width of the slab bounds."""
        left, right = self._sends(self._host_of(self.pos)[: self.n, 0])
        return len(left) + len(right)

    def _state_arrays(self):
        """The per-particle state that migrates and is copied to ghosts (the integrator's included)."""
        return [self.pos, self.vel, self.rho, self.kind, self.idp] + [a for a in self.extra_arrays
                                                                       if a is not self.ghost]

    def _host_of(self, a):
        """The host array the NumPy code of this class reads and edits for the particle array `a`:
        `a` itself when the backend keeps its arrays in host memory (CPU), else `a`'s host copy.

        The host copies (CUDA) hold the state at the sort: `sort` copies the state to them
        (`_to_host`), edits them with NumPy (dropping the ghosts, migration, re-cuts, the new
        halo) and copies them back (`_to_device`); those of ``kind``, ``idp`` and the ghost
        flags stay valid until the next sort (only a sort moves rows), the others do not
        (positions, velocities and densities change on the device every step)."""
        entry = self._host_copies.get(id(a))
        return a if entry is None else entry[1]

    def _add_host_copy(self, a):
        self._host_copies[id(a)] = (a, np.zeros(a.shape, a.dtype))  # holds `a`: its id stays unique

    def _host_state(self):
        """`_state_arrays` as the host arrays the NumPy code edits (`_host_of`)."""
        return [self._host_of(a) for a in self._state_arrays()]

    def _to_host(self, arrays=None):
        """Copy rows 0..n of `arrays` (default: the state and the ghost flags) to their host
        copies (nothing when the backend works in host memory)."""
        if not self._host_copies:
            return
        for a in self._state_arrays() + [self.ghost] if arrays is None else arrays:
            self.backend.copy_to_host(self._host_of(a), a, self.n)

    def _to_device(self):
        """Copy rows 0..n of the state and the ghost flags from their host copies back to the
        backend's arrays (nothing when the backend works in host memory)."""
        if not self._host_copies:
            return
        for a in self._state_arrays() + [self.ghost]:
            self.backend.copy_into(a, self._host_of(a), self.n)

    def _buffer(self, name, shape, dtype, device):
        """The preallocated work array `name` with at least ``shape[0]`` rows: a backend
        array (`device`) or a NumPy one, allocated again (25 % larger) only when too small."""
        buf = self._buffers.get(name)
        if buf is None or buf.shape[0] < shape[0] or buf.shape[1:] != tuple(shape[1:]):
            full = (int(1.25 * shape[0]) + 64,) + tuple(shape[1:])
            buf = self.backend.zeros(full, dtype) if device else np.zeros(full, dtype)
            self._buffers[name] = buf
        return buf

    def _set_halo_rows(self):
        """Put the rows the halo refresh sends (left, then right) and the ghost rows it
        writes where the backend's kernels read them (after a sort or a restore)."""
        send = np.concatenate(self._send).astype(np.int64)
        ghosts = np.asarray(self._ghost_rows, np.int64)
        if self.backend.host_memory:
            self._send_rows, self._ghost_rows_b = send, ghosts
            return
        self._send_rows = self._buffer("send_rows", (len(send),), np.int64, True)
        self._ghost_rows_b = self._buffer("ghost_rows", (len(ghosts),), np.int64, True)
        self.backend.copy_into(self._send_rows, send, len(send))
        self.backend.copy_into(self._ghost_rows_b, ghosts, len(ghosts))

    def _per_particle_arrays(self):
        """The model's arrays with a row per particle (state, rates, work arrays, the integrator's;
        xsph, tau and vwall when in use), not the neighbour grid's."""
        cap = self._capacity
        arrays = [self.pos, self.vel, self.rho, self.kind, self.idp, self.ace, self.drho, self.mu_max, self.pr2,
                  *self.scratch.values(), *self.extra_arrays]
        arrays += [a for a in (self.xsph, self.tau, self.vwall) if a.shape[0] == cap and cap > 1]
        return arrays

    def _resize(self, capacity):
        """Give every per-particle array `capacity` rows, keeping rows 0..n.

        NumPy arrays (CPU) are resized in place, so every reference stays valid. Device arrays
        (CUDA) cannot be: new ones are allocated, rows 0..n copied on the device, and every
        reference re-pointed (`_reallocate`)."""
        capacity = max(int(capacity), 1)
        if capacity == self._capacity:
            return
        if self.backend.host_memory:
            seen = set()
            for a in self._per_particle_arrays() + [self.grid.cell, self.grid.perm, self.grid._unsorted]:
                if id(a) in seen:
                    continue
                seen.add(id(a))
                a.resize((capacity,) + a.shape[1:], refcheck=False)
        else:
            self._reallocate(capacity)
        self._capacity = capacity
        self.resizes += 1

    def _reallocate(self, capacity):
        """Device arrays of `capacity` rows in place of the current ones (rows 0..n copied on the
        device), the references re-pointed: this model's attributes, ``scratch``,
        ``extra_arrays``, the attributes of ``array_owners`` (the integrator), the host copies
        (resized with them) and the neighbour grid's per-particle work arrays."""
        b = self.backend
        keep = min(self.n, capacity)
        old = self._per_particle_arrays()
        new = {}
        for a in old:
            if id(a) not in new:
                c = b.zeros((capacity,) + tuple(a.shape[1:]), a.dtype)
                b.copy_into(c, a, keep)
                new[id(a)] = c

        def swap(v):
            return new.get(id(v), v)

        for obj in [self, *self.array_owners]:
            for name, value in list(vars(obj).items()):
                if id(value) in new:
                    setattr(obj, name, new[id(value)])
        for key in list(self.scratch):
            self.scratch[key] = swap(self.scratch[key])
        self.extra_arrays[:] = [swap(a) for a in self.extra_arrays]
        copies = {}
        for a, host in self._host_copies.values():
            host.resize((capacity,) + host.shape[1:], refcheck=False)
            c = swap(a)
            copies[id(c)] = (c, host)
        self._host_copies = copies
        self.grid.resize(capacity)
        del old  # the old arrays were alive until here, so no id above was reused

    def _ensure(self, rows):
        """Grow the particle arrays (25 % beyond `rows`, plus `spare_rows`) when `rows` do not fit."""
        if rows > self._capacity:
            self._resize(min(int(1.25 * rows) + self.spare_rows, max(self.n_global, rows)))

    def new_array(self, like, owner=None):
        a = super().new_array(like, owner)
        if not self.backend.host_memory:
            self._add_host_copy(a)
        # keep the ghost flag last (it is not state)
        self.extra_arrays[:] = [b for b in self.extra_arrays if b is not self.ghost] + [self.ghost]
        return a

    def _compact(self, rows):
        """Move `rows` (ascending) of the state arrays to the front; n = len(rows) (host arrays)."""
        for a in self._host_state() + [self._host_of(self.ghost)]:
            a[: len(rows)] = a[rows]
        self.n = len(rows)

    # ------------------------------------------------------------ exchanges
    def _exchange(self, to_left, to_right, ncols, counts=None, out=None):
        t0 = _time.perf_counter()
        out = _halo.shift(self.comm, to_left, to_right, ncols, counts, out, ring=self.ring)
        self.comm_seconds += _time.perf_counter() - t0
        return out

    def _drop_ghosts(self):
        if self.n_ghost:
            self._compact(np.flatnonzero(self._host_of(self.ghost)[: self.n] == 0))
        self.n_ghost = 0

    def _migrate(self, multi_hop=False):
        """Send the owned particles whose x left the slab to the neighbour on that side.

        Normally a particle crosses one cut at most per step (slabs are at least
        the halo width wide; farther is a blow-up). After a re-cut (`multi_hop`)
        a particle may be several slabs from its new owner: the exchange repeats,
        forwarding it one rank per round, until no rank holds a particle outside
        its slab (collective). Works on the host arrays (`_host_of`)."""
        while True:
            r, cuts, n = self.mpi_rank, self.cuts, self.n
            x = self._host_of(self.pos)[:n, 0]
            lo, hi = cuts[r], cuts[r + 1]
            if self.ring:  # the shorter way round: a particle that left the domain's end was wrapped
                lo, hi = self.slab()
                L = self.x_period[1]
                out = (x < lo) | (x >= hi)
                leftwards = out & (np.mod(lo - x, L) <= np.mod(x - hi, L))
                to_left, to_right = np.flatnonzero(leftwards), np.flatnonzero(out & ~leftwards)
            else:
                to_left = np.flatnonzero(x < lo)
                to_right = np.flatnonzero(x >= hi)
            if not multi_hop and not self.ring:
                too_far = r > 0 and np.any(x[to_left] < cuts[r - 1])
                too_far = too_far or (r + 2 < len(cuts) and np.any(x[to_right] >= cuts[r + 2]))
                if too_far:
                    raise InstabilityError(f"rank {r}: a particle crossed more than one slab in one step (slabs are "
                                           f"at least {self.halo_width:.3g} m wide): the run blew up or the time step "
                                           "is far too large")
            arrays = self._host_state()
            ncols = _halo.columns(arrays)
            send_l = _halo.pack(arrays, to_left)
            send_r = _halo.pack(arrays, to_right)
            if len(to_left) or len(to_right):
                self._compact(np.flatnonzero((x >= lo) & (x < hi)))
            from_l, from_r = self._exchange(send_l, send_r, ncols)
            k = len(from_l) + len(from_r)
            if k:
                n = self.n
                self._ensure(n + k)
                arrays = self._host_state()  # the same objects, resized in place
                _halo.unpack(arrays, np.concatenate([from_l, from_r]), slice(n, n + k))
                self._host_of(self.ghost)[n:n + k] = 0
                self.n = n + k
            if not multi_hop:
                return
            x = self._host_of(self.pos)[: self.n, 0]
            outside = int(np.count_nonzero((x < self.cuts[r]) | (x >= self.cuts[r + 1])))
            if self.allreduce(outside, "sum") == 0:
                return

    # --------------------------------------------------------- load balance
    def weighted_count(self):
        """This rank's owned active particles weighted by cost (fluid 1, wall `BOUNDARY_WEIGHT`)."""
        kind = self._host_of(self.kind)[: self.n][self.owned]
        nf = int(np.count_nonzero(kind == FLUID))
        return nf + BOUNDARY_WEIGHT * (len(kind) - nf)

    def rebalance(self, force=False):
        """Collective: when the ranks' max / mean weighted count exceeds
        `rebalance_threshold` (or `force`), move the cuts to the weighted
        quantiles of the particles' current x and migrate the particles to
        their new owners. Call with no ghosts held (``sort`` does, between
        dropping the ghosts and fetching the new halo, on the host arrays).

        Returns
        -------
        dict or None
            The record appended to ``rebalances`` (``sort``: the sort count,
            ``time`` [s], ``imbalance_before`` / ``imbalance_after`` (max /
            mean weighted count), ``weighted_before`` / ``weighted_after``
            and ``counts_before`` / ``counts_after`` (particles per rank),
            ``cuts`` (the new inner cuts [m])), or None when no re-cut was made
            (balanced within the threshold, the cuts already where they would
            go, or no room for slabs one halo wide).
        """
        t0 = _time.perf_counter()
        own = self.owned
        before = weighted_counts(self.comm, self.weighted_count())
        self.comm_seconds += _time.perf_counter() - t0
        ratio = imbalance(before)
        if not force and ratio <= self.rebalance_threshold:
            return None
        kind = self._host_of(self.kind)[: self.n][own]
        w = np.where(kind == FLUID, 1.0, BOUNDARY_WEIGHT)
        t0 = _time.perf_counter()
        cuts = distributed_cuts(self.comm, self._host_of(self.pos)[: self.n, 0][own], w, self.min_slab_width,
                                keys=self._host_of(self.idp)[: self.n][own])
        self.comm_seconds += _time.perf_counter() - t0
        if cuts is None or np.array_equal(cuts, self.cuts):  # no room to move, or already the best cut
            return None
        counts_before = self.comm.allgather(int(np.count_nonzero(own)))
        self.cuts = cuts
        self._migrate(multi_hop=True)
        after = weighted_counts(self.comm, self.weighted_count())
        rec = {"sort": self.sort_count, "time": float(self.time), "imbalance_before": ratio,
               "imbalance_after": imbalance(after), "weighted_before": before.tolist(),
               "weighted_after": after.tolist(), "counts_before": counts_before,
               "counts_after": self.comm.allgather(int(self.n)), "cuts": cuts[1:-1].tolist()}
        self.rebalances.append(rec)
        return rec

    def _append_halo(self):
        """Receive the neighbours' particles within the halo width as ghost rows n.. (host arrays)."""
        n = self.n
        send_l, send_r = self._sends(self._host_of(self.pos)[:n, 0])
        arrays = self._host_state()
        from_l, from_r = self._exchange(_halo.pack(arrays, send_l), _halo.pack(arrays, send_r),
                                        _halo.columns(arrays))
        g = len(from_l) + len(from_r)
        self._ensure(n + g)
        _halo.unpack(self._host_state(), np.concatenate([from_l, from_r]), slice(n, n + g))
        ghost = self._host_of(self.ghost)
        ghost[:n] = 0
        ghost[n:n + g] = 1
        self.n_owned = n
        self.n_ghost = g
        self.n = n + g
        self._send = (send_l, send_r)
        self._ghost_counts = (len(from_l), len(from_r))

    def _refresh_halo(self):
        """Copy the owners' current position, velocity and density into the ghosts.

        Only the send and ghost rows travel: the backend packs the send rows into a
        float64 buffer (a kernel on the device), which is copied to a host buffer, sent
        (``Sendrecv``) into the host receive buffer, copied back and unpacked into the
        ghost rows (a kernel). On the CPU the backend and host buffers are one array.
        The buffers are allocated once (again only when a halo outgrows them)."""
        b = self.backend
        arrays = [self.pos, self.vel, self.rho]
        ncols = _halo.columns(arrays)
        kl, kr = len(self._send[0]), len(self._send[1])
        gl, gr = self._ghost_counts
        d_send = self._buffer("send", (kl + kr, ncols), np.float64, True)
        d_recv = self._buffer("recv", (gl + gr, ncols), np.float64, True)
        host = b.host_memory
        h_send = d_send if host else self._buffer("send_host", (kl + kr, ncols), np.float64, False)
        h_recv = d_recv if host else self._buffer("recv_host", (gl + gr, ncols), np.float64, False)
        b.pack_rows(arrays, self._send_rows, kl + kr, d_send)
        if not host:
            b.copy_to_host(h_send, d_send, kl + kr)
        self._exchange(h_send[:kl], h_send[kl:kl + kr], ncols, out=(h_recv[:gl], h_recv[gl:gl + gr]))
        if not host:
            b.copy_into(d_recv, h_recv, gl + gr)
        b.unpack_rows(arrays, d_recv, self._ghost_rows_b, len(self._ghost_rows))
        self._halo_fresh = True

    def allreduce(self, value, op="min"):
        from mpi4py import MPI

        t0 = _time.perf_counter()
        out = self.comm.allreduce(value, op={"min": MPI.MIN, "max": MPI.MAX, "sum": MPI.SUM}[op])
        self.comm_seconds += _time.perf_counter() - t0
        return out

    # ------------------------------------------------------------- operations
    @property
    def owned(self):
        """(n,) bool mask of the owned (not ghost) active rows."""
        return self._host_of(self.ghost)[: self.n] == 0

    @property
    def n_fluid(self):
        """Active fluid particles owned by this rank."""
        if self._in_sort:
            return 1  # a rank may hold no fluid; the whole run's fluid is checked collectively
        return int(np.count_nonzero((self._host_of(self.kind)[: self.n] == FLUID) & self.owned))

    def sort(self):
        """Drop the ghosts, sort and escape the owned particles, migrate, fetch a new halo, sort again.

        The single-process sort runs on the backend (the device); dropping the ghosts,
        the migration, the re-cuts and the new halo edit the host arrays (`_host_of`):
        with the CUDA backend the whole state is copied to the host and back around
        them (twice per sort), never in a rate evaluation."""
        if self.n_ghost:
            self._to_host()
            self._drop_ghosts()
            self._to_device()
        self.n_ghost = 0
        self._in_sort = True
        self.sort_count += 1
        k, every = self.sort_count - 1, self.rebalance_interval
        try:
            super().sort()
            self._to_host()
            self._migrate()  # first: the slabs are ordered along x again, as distributed_cuts needs
            if every > 0 and k > 0 and k % every == 0:  # the start of step k + 1 (sort 1 is before step 1)
                self.rebalance()
            self._append_halo()
            self._to_device()
            n_before = self.n
            super().sort()
            assert self.n == n_before, "a migrated particle or a ghost fell outside the domain"
        finally:
            self._in_sort = False
        n = self.n
        inv = np.empty(n, np.int64)
        inv[self.host(self.grid.perm, 0, n)] = np.arange(n)
        self._send = (inv[self._send[0]], inv[self._send[1]])
        self._ghost_rows = inv[self.n_owned + np.arange(self.n_ghost)]
        self._set_halo_rows()
        self._to_host([self.kind, self.idp, self.ghost])  # valid until the next sort (see `_host_of`)
        self._halo_fresh = True
        return self.n_owned

    # ---------------------------------------------------------------- the Model's hooks
    def refresh_ghosts(self, always=True):
        """Refresh the halo's values from their owners (unless the last sort has just done so and
        `always` is false)."""
        if always or not self._halo_fresh:
            self._refresh_halo()

    def ghosts_spent(self):
        self._halo_fresh = False

    def clear_ghost_rates(self):
        """Zero the ghosts' rates: each particle's rates are its owner's."""
        g = len(self._ghost_rows)
        if g:
            rates = [self.ace, self.drho, self.mu_max] + ([self.xsph] if self.spec.xsph else [])
            self.backend.zero_rows(rates, self._ghost_rows_b, g)

    def reduce(self, value, op="min"):
        """`value` over every rank (`allreduce`; collective)."""
        return self.allreduce(value, op)

    def raise_together(self, message):
        """Collective: every rank raises the first failing rank's message, as a `CollectiveError`."""
        t0 = _time.perf_counter()
        msgs = self.comm.allgather(message)
        self.comm_seconds += _time.perf_counter() - t0
        for k, m in enumerate(msgs):
            if m is not None:
                raise CollectiveError(f"{m} (MPI rank {k})")

    def sample(self, points, shepard=True):
        """SPH interpolation at fixed points, the same on every rank (collective)."""
        from mpi4py import MPI

        self._refresh_halo()
        self._halo_fresh = False
        pts = np.asarray(points, dtype=np.float64).reshape(-1, 3)
        raw = super().sample(pts, shepard=False)
        mine = (pts[:, 0] >= self.cuts[self.mpi_rank]) & (pts[:, 0] < self.cuts[self.mpi_rank + 1])
        buf = np.zeros((len(pts), 6))
        buf[:, 0] = raw["kernel_sum"]
        buf[:, 1] = raw["pressure"]
        buf[:, 2] = raw["density"]
        buf[:, 3:6] = raw["velocity"]
        buf[~mine] = 0.0
        out = np.empty_like(buf)
        t0 = _time.perf_counter()
        self.comm.Allreduce(buf, out, op=MPI.SUM)
        self.comm_seconds += _time.perf_counter() - t0
        s, vel = out[:, 0], out[:, 3:6]
        if shepard:
            with np.errstate(invalid="ignore", divide="ignore"):
                inv = np.where(s > 0, 1.0 / s, np.nan)
            return {"kernel_sum": s, "pressure": out[:, 1] * inv, "density": out[:, 2] * inv,
                    "velocity": vel * inv[:, None]}
        return {"kernel_sum": s, "pressure": out[:, 1], "density": out[:, 2], "velocity": vel}

    def sensor_moments(self, points):
        """The fluid's moments around fixed points (`Model.sensor_moments`), the same on every rank
        (collective): each point's sums come from the rank whose slab holds it, with a fresh halo."""
        from mpi4py import MPI

        self._refresh_halo()
        self._halo_fresh = False
        pts = np.asarray(points, dtype=np.float64).reshape(-1, 3)
        buf = super().sensor_moments(pts)
        mine = (pts[:, 0] >= self.cuts[self.mpi_rank]) & (pts[:, 0] < self.cuts[self.mpi_rank + 1])
        buf[~mine] = 0.0
        out = np.empty_like(buf)
        t0 = _time.perf_counter()
        self.comm.Allreduce(buf, out, op=MPI.SUM)
        self.comm_seconds += _time.perf_counter() - t0
        return out

    # ----------------------------------------------------------- checkpoint
    def checkpoint_arrays(self):
        """The per-particle arrays a checkpoint of this rank saves (rows ``0..n``: owned
        and ghosts, in their current order), by attribute name; the integrator's
        arrays and the ghost flags are ``extra_arrays``."""
        out = {name: getattr(self, name) for name in self.STATE_ARRAYS}
        for name in ("xsph", "tau", "vwall"):
            a = getattr(self, name)
            if a.shape[0] == self._capacity and self._capacity > 1:
                out[name] = a
        return out

    def checkpoint_state(self):
        """(scalars, arrays) of the decomposition a checkpoint of this rank must hold for an
        exact restart: the counts, the cuts, the rows the halo refresh sends and
        receives, the sort count of the load balancing and its records."""
        scalars = {"rank": self.mpi_rank, "size": self.mpi_size, "n_owned": int(self.n_owned),
                   "n_ghost": int(self.n_ghost), "ghost_counts": [int(c) for c in self._ghost_counts],
                   "sort_count": int(self.sort_count), "halo_fresh": bool(self._halo_fresh),
                   "rebalances": self.rebalances, "rebalance_interval": self.rebalance_interval,
                   "rebalance_threshold": self.rebalance_threshold}
        arrays = {"cuts": np.asarray(self.cuts, np.float64), "send_left": np.asarray(self._send[0], np.int64),
                  "send_right": np.asarray(self._send[1], np.int64),
                  "ghost_rows": np.asarray(self._ghost_rows, np.int64)}
        return scalars, arrays

    def restore_checkpoint(self, n, particles, extra, scalars, arrays):
        """Put a checkpoint of this rank back (the inverse of `checkpoint_arrays`,
        `checkpoint_state`): `n` active rows of `particles` (by name) and `extra`
        (the ``extra_arrays``, in order), the decomposition's `scalars` and `arrays`.

        Raises
        ------
        ValueError
            The arrays do not match this model's (another scheme or precision).
        """
        self._ensure(n)
        mine = self.checkpoint_arrays()
        if set(mine) != set(particles) or len(extra) != len(self.extra_arrays):
            raise ValueError(f"the particle arrays {sorted(particles)} (+{len(extra)} integrator arrays) are not "
                             f"this model's {sorted(mine)} (+{len(self.extra_arrays)})")
        for name, dst in list(mine.items()) + list(zip(range(len(extra)), self.extra_arrays)):
            src = particles[name] if isinstance(name, str) else extra[name]
            if src.shape[0] != n or src.shape[1:] != dst.shape[1:] or src.dtype != dst.dtype:
                raise ValueError(f"array {name} is {src.dtype}{tuple(src.shape)}, the model's "
                                 f"{dst.dtype}(n{tuple(dst.shape[1:])})")
            self.backend.copy_into(dst, np.ascontiguousarray(src), n)
        self.n = int(n)
        self.n_owned = int(scalars["n_owned"])
        self.n_ghost = int(scalars["n_ghost"])
        self._ghost_counts = tuple(int(c) for c in scalars["ghost_counts"])
        self.sort_count = int(scalars["sort_count"])
        self._halo_fresh = bool(scalars["halo_fresh"])
        self.rebalances = list(scalars.get("rebalances", []))
        self.cuts = np.asarray(arrays["cuts"], np.float64).copy()
        self._send = (np.asarray(arrays["send_left"], np.int64).copy(),
                      np.asarray(arrays["send_right"], np.int64).copy())
        self._ghost_rows = np.asarray(arrays["ghost_rows"], np.int64).copy()
        self._set_halo_rows()
        self._to_host()

    # ---------------------------------------------------------------- output
    def world_positions(self, active_only=True):
        """(n_owned, 3) positions of this rank's particles."""
        return super().world_positions()[self.owned]

    def world_velocities(self):
        return super().world_velocities()[self.owned]

    def pressure(self):
        return super().pressure()[self.owned]

    def fields(self):
        """Point data of this rank's particles (free-surface flags with a fresh halo)."""
        own = self.owned
        fs = self.free_surface()[own]
        return {
            "velocity": self.world_velocities(),
            "density": self.host(self.rho)[own].astype(np.float64),
            "pressure": self.pressure(),
            "id": self.host(self.idp)[own].copy(),
            "kind": self.host(self.kind)[own].astype(np.int32),
            "free_surface": fs.astype(np.int32),
        }

    def owned_particles(self):
        """(positions, kinds, ids) of this rank's owned particles, never the ghosts
        (the particle probes measure these, then reduce over the ranks)."""
        own = self.owned
        return self.world_positions(), self.host(self.kind)[own], self.host(self.idp)[own]

    def _allgather(self, value):
        t0 = _time.perf_counter()
        out = self.comm.allgather(value)
        self.comm_seconds += _time.perf_counter() - t0
        return out

    def particle_positions(self, ids):
        """World positions [m] of the particles with `ids`, the same on every rank
        (collective): each is read on the rank that owns it (`Model.particle_positions`
        over the owned particles) and the ranks' rows are gathered; NaN rows for
        particles no rank owns (escaped)."""
        parts = np.stack(self._allgather(super().particle_positions(ids)))  # (ranks, K, 3)
        found = ~np.isnan(parts[:, :, 0])
        return parts[np.argmax(found, axis=0), np.arange(parts.shape[1])]

    def nearest_fluid(self, points):
        """Ids of the fluid particles nearest to `points` over every rank, the same on
        every rank (collective); ties as in `shoal.probes.nearest_particles` (the
        smallest id), so the choice equals the single-process one."""
        from ..probes import nearest_particles

        pos, kinds, idp = self.owned_particles()
        fluid = kinds == FLUID
        d2, ids = (np.stack(a) for a in zip(*self._allgather(nearest_particles(pos[fluid], idp[fluid], points))))
        best = d2.min(axis=0)
        out = np.where(d2 == best, ids, np.iinfo(np.int64).max).min(axis=0)
        return np.where(np.isfinite(best), out, -1)

    def _owned_rows(self):
        return self.owned

    @property
    def n_ids(self):
        """Particle ids of the whole case (0 .. n_global - 1)."""
        return self.n_global

    def flow_sample(self, spec, prev):
        """A `FlowGauge` sample over every rank's fluid, the same on every rank (collective): each
        rank measures its owned particles against the whole-case `prev`; the coordinates by id are
        merged (a particle is owned by one rank), the crossings and slab sums added."""
        from mpi4py import MPI

        new, crossed, q = super().flow_sample(spec, prev)
        t0 = _time.perf_counter()
        buf = np.where(np.isnan(new), -np.inf, new)
        out = np.empty_like(buf)
        self.comm.Allreduce(buf, out, op=MPI.MAX)
        self.comm_seconds += _time.perf_counter() - t0
        q = self.allreduce(q, "sum")
        if crossed is not None:
            crossed = self.allreduce(crossed, "sum")
        return np.where(np.isneginf(out), np.nan, out), crossed, q

    def _shoreline_ylim(self, spec):
        lo, hi = super()._shoreline_ylim(spec)
        return (self.allreduce(lo, "min"), self.allreduce(hi, "max"))

    def _shoreline_columns(self, spec, ylim):
        """The shoreline columns (`shoal.probes.shoreline_columns`) of every rank's owned fluid, the same
        on every rank (collective): counts added, lowest z and most landward x over the ranks."""
        from mpi4py import MPI

        counts, zmin, xland = super()._shoreline_columns(spec, ylim)
        out = []
        t0 = _time.perf_counter()
        for a, op in ((counts, MPI.SUM), (zmin, MPI.MIN), (xland, MPI.MAX)):
            b = np.empty_like(a)
            self.comm.Allreduce(np.ascontiguousarray(a), b, op=op)
            out.append(b)
        self.comm_seconds += _time.perf_counter() - t0
        return tuple(out)

    def highest_fluid(self, spec, tie=0.0):
        """(zmax, x, y) [m] of a `MaxZGauge` or `RunupGauge` over every rank's fluid,
        the same on every rank (collective): zmax is the MPI max of the ranks' highest
        owned particles (NaN when no rank's owned fluid is in the region); (x, y) is
        that of the run-up's most landward owned particle within `tie` below it over
        the ranks (the max-z gauge: the rank holding the highest particle's)."""
        from ..probes import RunupGauge, highest_fluid

        pos, kinds, _ = self.owned_particles()
        z = highest_fluid(pos, kinds, self.dim, spec, tie)[0]
        zmax = self.allreduce(-np.inf if np.isnan(z) else z, "max")
        if zmax == -np.inf:
            return (float("nan"),) * 3
        xy = np.array(self._allgather(highest_fluid(pos, kinds, self.dim, spec, tie, zmax=zmax)[1:]), float)
        here = np.flatnonzero(~np.isnan(xy[:, 0]))  # ranks with a particle at (within tie of) zmax
        if isinstance(spec, RunupGauge):
            sign = 1.0 if spec.landward == "+x" else -1.0
            k = here[np.argmax(sign * xy[here, 0])]
        else:
            k = here[0]
        return zmax, float(xy[k, 0]), float(xy[k, 1])

    def gather_particles(self, root=0):
        """(positions, fields) of every rank's particles on `root` (None elsewhere), in id order."""
        t0 = _time.perf_counter()
        parts = self.comm.gather((self.world_positions(), self.fields()), root=root)
        self.comm_seconds += _time.perf_counter() - t0
        if parts is None:
            return None
        pos = np.concatenate([p for p, _ in parts])
        fields = {k: np.concatenate([f[k] for _, f in parts]) for k in parts[0][1]}
        order = np.argsort(fields["id"], kind="stable")
        return pos[order], {k: v[order] for k, v in fields.items()}

    def global_count(self):
        """Particles owned over all ranks (collective)."""
        return self.allreduce(int(self.n_owned if self.n_ghost else np.count_nonzero(self.owned)), "sum")
