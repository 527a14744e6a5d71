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

Composition. The model takes part in the physics only through the
`Model`'s hooks (`refresh_ghosts`, `ghosts_spent`, `clear_ghost_rates`,
`reduce`, `raise_together`); what is particular to many ranks is one object
per concern: `Slabs` (the cuts, `shoal.parallel.decomposition`), `Halo`
(`shoal.parallel.halo`), `Migration`, `Rebalancer` and `TimedComm` (every
message, timed), with the Model's `ParticleStore` for the arrays' capacity,
growth and host mirrors.

Load balancing (`shoal.parallel.rebalancer`). Every `rebalance_interval`
steps (at the sort) the ranks compare their weighted counts (fluid 1, wall
0.25); when max / mean exceeds `rebalance_threshold`, the cuts move to the
weighted quantiles of the particles' current x and the particles migrate to
their new owners before the fresh halo is fetched. Defaults: every 20
steps, threshold 1.1; the environment variables
``SHOAL_MPI_REBALANCE_INTERVAL`` (0: never) and
``SHOAL_MPI_REBALANCE_THRESHOLD`` set them for ``shoal run``, the keyword
arguments for the Python API. Each re-cut is recorded in ``rebalances``.

Backends. The same code runs on the CPU and the CUDA backend (one GPU per
rank, chosen by `shoal.parallel.gpu` before the backend creates its CUDA
context). The bookkeeping of a sort (dropping the ghosts, migration,
re-cuts, the new halo) edits NumPy arrays (`host_state`): on the CPU the
particle arrays themselves; with CUDA the store's host copies, filled from
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
re-cut or a new halo needs more rows (`ParticleStore.ensure`). The motions'
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

import numpy as np

from ..errors import InputError
from ..model import Model
from ..options import SPHOptions
from ..physics.spec import FLUID, MOVING, REPULSIVE, REPULSIVE_MOVING
from . import halo as _halo
from .collective import CollectiveError
from .decomposition import BOUNDARY_WEIGHT, Slabs, particle_weights, slab_cuts
from .halo import Halo
from .migration import Migration
from .rebalancer import Rebalancer, rebalance_settings
from .timed_comm import TimedComm

__all__ = ["DistributedModel", "BOUNDARY_WEIGHT", "rebalance_settings"]


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

    require_fluid = False  # a slab may hold no fluid; the whole run's fluid is checked at each sort

    def __init__(self, positions, kinds, *, comm=None, cuts=None, rebalance_interval=None,
                 rebalance_threshold=None, **kw):
        from . import world

        interval, threshold = rebalance_settings(rebalance_interval, rebalance_threshold)
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
        ring = "x" in tuple(kw.get("periodic") or ())  # periodic x: the slabs close into a ring
        self.mpi_rank = self.comm.Get_rank()
        self.mpi_size = self.comm.Get_size()
        options = kw.get("options") or SPHOptions()
        h = self.smoothing_length(options, kw["dim"], kw["dp"])
        # a first pass over the neighbours (SPS stress, no-slip wall velocity, Adami wall pressure) before
        # the rates: the ghosts that pass reads need their own neighbours, two supports deep
        wide = options.turbulence == "sps" or bool(options.no_slip) or options.wall_pressure == "adami"
        width = (4.0 if wide else 2.0) * h + 0.25 * h
        if options.wall_pressure == "mdbc" and kw.get("wall_normals") is not None:
            # a wall ghost's density comes from the fluid within 2h of its ghost node, which lies up
            # to the largest x component of a ghost vector away across the slab cut (the cuts are
            # planes x = const): that fluid must be on the rank too
            g = np.asarray(kw["wall_normals"], np.float64)
            reach = float(np.abs(g[:, 0]).max()) if len(g) else 0.0
            width = max(width, 4.0 * h + reach + 0.25 * h)
        # with a ring of 2 ranks the neighbour on both sides is the same rank: a slab narrower than
        # two halo widths would send it a particle twice
        min_width = (2.0 if ring and self.mpi_size == 2 else 1.0) * width
        if cuts is None:
            cuts = slab_cuts(positions[:, 0], particle_weights(kinds), self.mpi_size, min_width)
        else:
            inner = np.asarray(cuts, np.float64).ravel()
            if len(inner) != self.mpi_size - 1 or np.any(np.diff(inner) < min_width):
                raise InputError(f"cuts {inner.tolist()}: give {self.mpi_size - 1} increasing slab bounds at least "
                                 f"{min_width:.4g} m apart")
            cuts = np.concatenate([[-np.inf], inner, [np.inf]])
        # build this rank's slab only (its arrays, on the device with CUDA); the particle ids stay
        # global: idp indexes pos_init / motion_of, which the motions keep for the whole case
        x = positions[:, 0]
        own = np.flatnonzero((x >= cuts[self.mpi_rank]) & (x < cuts[self.mpi_rank + 1]))
        mine = dict(kw)
        for key in ("velocities", "motion_of", "wall_normals"):
            if kw.get(key) is not None:
                mine[key] = np.asarray(kw[key])[own]
        super().__init__(positions[own], kinds[own], repulsive=bool(np.any(kinds >= REPULSIVE)), **mine)
        self.n_global = self.n_total = len(positions)
        x_period = (self._period_lo[0], float(self.params.per_len_x)) if ring else None  # (lo, L) [m]
        self.slabs = Slabs(cuts, self.mpi_rank, min_width, x_period)
        self.link = TimedComm(self.comm, ring=ring)
        self.backend.copy_into(self.idp, own.astype(np.int32), len(own))
        if np.any((kinds == MOVING) | (kinds == REPULSIVE_MOVING)):  # a moving particle may come to any rank
            motion_of = kw.get("motion_of")
            cols = [0, 1, 2] if self.dim == 3 else [0, 2]
            self._init_motions(positions[:, cols], kinds, kw.get("motions"),
                               None if motion_of is None else np.asarray(motion_of))
        # the ghost vectors by global id, whole on every rank (a wall particle may come to any rank)
        self._init_wall_normals(kinds, kw.get("wall_normals"))
        self.sort_count = 0
        self.ghost = self.backend.zeros(max(self.n, 1), np.int8)
        self.extra_arrays.append(self.ghost)  # follows the sort
        self.store.mirror(self.state_arrays() + [self.ghost])
        self.to_host()
        self.halo = Halo(self, self.link, self.slabs, width)
        self.migration = Migration(self, self.link, self.slabs)
        self.rebalancer = Rebalancer(self, self.link, self.slabs, self.migration, interval, threshold)
        self.store.resize(self.rows_wanted(self.n, self.halo.estimate()))

    # ------------------------------------------------------- the parts, under the model's names
    @property
    def cuts(self):
        """(nranks + 1,) slab bounds along x [m] (`Slabs.cuts`)."""
        return self.slabs.cuts

    @property
    def halo_width(self):
        """Halo width [m] (`Halo.width`)."""
        return self.halo.width

    @property
    def min_slab_width(self):
        """Smallest slab width [m] a cut may make (`Slabs.min_width`)."""
        return self.slabs.min_width

    @property
    def n_owned(self):
        """Rows 0..n_owned held this rank's own particles when the halo was received."""
        return self.halo.n_owned

    @property
    def n_ghost(self):
        """Ghost rows held now."""
        return self.halo.n_ghost

    @property
    def rebalances(self):
        """One dict per re-cut (`Rebalancer.rebalance`)."""
        return self.rebalancer.records

    @property
    def rebalance_interval(self):
        """Steps between balance checks (0: none)."""
        return self.rebalancer.interval

    @property
    def rebalance_threshold(self):
        """Max / mean weighted count above which the slabs are cut again."""
        return self.rebalancer.threshold

    @property
    def comm_seconds(self):
        """Wall time [s] this rank spent communicating (`TimedComm.seconds`)."""
        return self.link.seconds

    def weighted_count(self):
        """This rank's owned particles weighted by cost (`Rebalancer.weighted_count`)."""
        return self.rebalancer.weighted_count()

    # ---------------------------------------------------------------- arrays
    spare_rows = 1024
    """Rows the particle arrays hold beyond 1.3 times the owned particles (or the owned plus twice
    the estimated ghosts): room for the water to move in before the arrays must grow."""

    def rows_wanted(self, owned, ghosts):
        """Rows to allocate for `owned` particles and about `ghosts` ghosts: max(1.3 owned +
        `spare_rows`, owned + 2 ghosts + `spare_rows`), at most the whole case (owned and ghosts
        are distinct particles of the case)."""
        want = max(int(1.3 * owned), owned + 2 * ghosts) + self.spare_rows
        return max(1, min(want, self.n_global))

    def state_arrays(self):
        """The per-particle state that migrates and is copied to ghosts (the integrator's included)."""
        return [self.pos, self.vel, self.rho, self.kind, self.idp] + [a for a in self.extra_arrays
                                                                       if a is not self.ghost]

    def host_state(self):
        """`state_arrays` as the host arrays the NumPy bookkeeping edits (`ParticleStore.host_of`):
        with CUDA their host copies, valid between `to_host` and `to_device`; those of ``kind``,
        ``idp`` and the ghost flags stay valid until the next sort (only a sort moves rows)."""
        return [self.store.host_of(a) for a in self.state_arrays()]

    def to_host(self, arrays=None):
        """Copy rows 0..n of `arrays` (default: the state and the ghost flags) to their host copies."""
        self.store.to_host(self.state_arrays() + [self.ghost] if arrays is None else arrays, self.n)

    def to_device(self):
        """Copy rows 0..n of the state and the ghost flags from their host copies back."""
        self.store.to_device(self.state_arrays() + [self.ghost], self.n)

    def new_array(self, like, owner=None):
        a = super().new_array(like, owner)
        self.store.mirror([a])
        # keep the ghost flag last (it is not state)
        self.extra_arrays[:] = [b for b in self.extra_arrays if b is not self.ghost] + [self.ghost]
        return a

    def keep_rows(self, rows):
        """Move `rows` (ascending) of the state and the ghost flags to the front; n = len(rows)
        (host arrays)."""
        for a in self.host_state() + [self.store.host_of(self.ghost)]:
            a[: len(rows)] = a[rows]
        self.n = len(rows)

    def append_rows(self, packed, ghost):
        """Write the packed rows `packed` (`shoal.parallel.halo.pack` of `state_arrays`) after row n,
        flagged `ghost` (0 or 1), growing the arrays when they do not fit; returns how many
        (host arrays)."""
        n, k = self.n, len(packed)
        if k:
            self.store.ensure(n + k, spare=self.spare_rows, limit=self.n_global)
            _halo.unpack(self.host_state(), packed, slice(n, n + k))
            self.store.host_of(self.ghost)[n:n + k] = ghost
            self.n = n + k
        return k

    # ------------------------------------------------------------- operations
    @property
    def owned(self):
        """(n,) bool mask of the owned (not ghost) active rows."""
        return self.store.host_of(self.ghost)[: self.n] == 0

    @property
    def n_fluid(self):
        """Active fluid particles owned by this rank."""
        return int(np.count_nonzero((self.store.host_of(self.kind)[: self.n] == FLUID) & self.owned))

    def sort(self):
        """Drop the ghosts, sort and escape the owned particles, migrate, maybe re-cut, fetch a
        new halo, sort again.

        The single-process sort runs on the backend (the device); dropping the ghosts,
        the migration, the re-cuts and the new halo edit the host arrays (the store's
        mirrors): with the CUDA backend the whole state is copied to the host and back
        around them (twice per sort), never in a rate evaluation. Collective: when no
        fluid is left in the run, every rank raises the same error."""
        if self.halo.n_ghost:
            self.to_host()
            self.halo.drop()
            self.to_device()
        self.sort_count += 1
        super().sort()
        self.to_host()
        self.migration.run()  # first: the slabs are ordered along x again, as distributed_cuts needs
        if self.rebalancer.due(self.sort_count):
            self.rebalancer.rebalance()
        if self.reduce(self.n_fluid, "sum") == 0:
            raise CollectiveError("every fluid particle has left the domain box "
                                  f"{self.grid.lo.tolist()} - {self.grid.hi.tolist()} m")
        self.halo.append()
        self.to_device()
        n_before = self.n
        super().sort()
        assert self.n == n_before, "a migrated particle or a ghost fell outside the domain"
        self.halo.reorder(self.host(self.grid.perm, 0, self.n))
        self.to_host([self.kind, self.idp, self.ghost])  # valid until the next sort (see `host_state`)
        return self.n_owned

    # ---------------------------------------------------------------- the Model's hooks
    def refresh_ghosts(self, always=True):
        """Refresh the halo's values from their owners (unless the last sort has just done so and
        `always` is false)."""
        if always or not self.halo.fresh:
            self.halo.refresh()

    def ghosts_spent(self):
        self.halo.fresh = False

    def clear_ghost_rates(self):
        """Zero the ghosts' rates: each particle's rates are its owner's."""
        self.halo.clear_rates()

    def ghost_flags(self):
        """``ghost``: 1 on the rows that copy a neighbour rank's particles (the halo)."""
        return self.ghost

    def reduce(self, value, op="min"):
        """`value` over every rank (`TimedComm.allreduce`; collective)."""
        return self.link.allreduce(value, op)

    def raise_together(self, message):
        """Collective: every rank raises the first failing rank's message, as a `CollectiveError`."""
        msgs = self.link.allgather(message)
        for k, m in enumerate(msgs):
            if m is not None:
                raise CollectiveError(f"{m} (MPI rank {k})")

    def reduce_array(self, values, op="sum"):
        """`values` combined element by element over every rank (`TimedComm.reduce_array`; collective)."""
        return self.link.reduce_array(values, op)

    def gather(self, value):
        """[`value` of each rank], in rank order, on every rank (collective)."""
        return self.link.allgather(value)

    def answers(self, points):
        """The points in this rank's slab: its halo covers their support, and no other rank's slab
        holds them."""
        return self.slabs.holds(np.asarray(points)[:, 0])

    def owned_rows(self):
        """The owned rows (`owned`), never the ghosts."""
        return self.owned

    # ----------------------------------------------------------- checkpoint
    def checkpoint_arrays(self):
        """The per-particle arrays a checkpoint of this rank saves (rows ``0..n``: owned
        and ghosts, in their current order), by attribute name; the integrator's
        arrays and the ghost flags are ``extra_arrays``."""
        out = {name: getattr(self, name) for name in self.STATE_ARRAYS}
        for name in ("xsph", "tau", "vwall"):
            a = getattr(self, name)
            if a.shape[0] == self.capacity and self.capacity > 1:
                out[name] = a
        return out

    def checkpoint_state(self):
        """(scalars, arrays) of the decomposition a checkpoint of this rank must hold for an
        exact restart: the counts, the cuts, the rows the halo refresh sends and
        receives, the sort count of the load balancing and its records."""
        halo_scalars, halo_arrays = self.halo.checkpoint_state()
        scalars = {"rank": self.mpi_rank, "size": self.mpi_size, **halo_scalars, "sort_count": int(self.sort_count),
                   "rebalances": self.rebalances, "rebalance_interval": self.rebalance_interval,
                   "rebalance_threshold": self.rebalance_threshold}
        arrays = {"cuts": np.asarray(self.cuts, np.float64), **halo_arrays}
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
        self.store.ensure(n, spare=self.spare_rows, limit=self.n_global)
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
        self.sort_count = int(scalars["sort_count"])
        self.rebalancer.records = list(scalars.get("rebalances", []))
        self.slabs.cuts = np.asarray(arrays["cuts"], np.float64).copy()
        self.halo.restore_state(scalars, arrays)
        self.to_host()

    # ---------------------------------------------------------------- output
    def gather_particles(self, root=0):
        """(positions, fields) of every rank's particles on `root` (None elsewhere), in id order."""
        parts = self.link.gather((self.world_positions(), self.fields()), root=root)
        if parts is None:
            return None
        pos = np.concatenate([p for p, _ in parts])
        fields = {k: np.concatenate([f[k] for _, f in parts]) for k in parts[0][1]}
        order = np.argsort(fields["id"], kind="stable")
        return pos[order], {k: v[order] for k, v in fields.items()}

    def global_count(self):
        """Particles owned over all ranks (collective)."""
        return self.reduce(int(self.n_owned if self.n_ghost else np.count_nonzero(self.owned)), "sum")
