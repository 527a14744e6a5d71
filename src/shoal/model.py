"""A Model: particles + scheme options + domain + compiled backend.

The Model owns the particle arrays (in the working precision, stored in
cell order), the neighbour grid and the run-time constants, and offers the
operations a time integrator is written with: `sort`, `compute_rates`,
`time_step_limit`, `apply_filter`, `check`.

Internal coordinates: 3D runs store (x, y, z); 2D runs store (x, z) (the
x-z plane, gravity along -z). `world_positions` returns (N, 3) arrays.
"""

from __future__ import annotations

import math

import numpy as np

from .backends import get_backend
from .body_coupling import BodyCoupling
from .errors import InputError, InstabilityError
from .options import SPHOptions
from .particle_store import ParticleStore
from .physics.body_motion import fill_motion_row, motion_layout
from .physics.contact import contact_constants
from .physics.constants import particle_mass, reference_speed, smoothing_length, speed_of_sound
from .physics.eos import GAMMA, density_of, pressure_of, tait_coefficient
from .physics.spec import (ADAMI, FIXED, FLUID, MDBC, MOVING, REPULSIVE, REPULSIVE_MOVING, SchemeSpec,
                           make_params, params_array)

KIND_NAMES = {FLUID: "fluid", FIXED: "fixed boundary", MOVING: "moving boundary",
              REPULSIVE: "repulsive boundary", REPULSIVE_MOVING: "moving repulsive boundary"}


class Model:
    """Particles, scheme and backend of one simulation.

    Parameters
    ----------
    positions : (N, 3) array
        Initial particle positions [m] (world x, y, z; y ignored in 2D).
    kinds : (N,) int array
        0 fluid, 1 fixed boundary, 2 moving boundary (dynamic boundary
        particles); 3 fixed, 4 moving repulsive boundary particles (Monaghan &
        Kajtar 2009, with K = g fluid_height).
    dp : float
        Initial particle spacing [m].
    dim : {2, 3}
        Dimension; 2D runs use the x-z plane.
    domain : (lo, hi)
        Corners of the computational box [m] (3 numbers each; y ignored in
        2D). Particles leaving it are taken out of the computation.
    options : SPHOptions
        Scheme options.
    rho0 : float
        Reference density [kg/m^3].
    gravity : sequence of 3 floats
        Gravity [m/s^2] (world x, y, z).
    fluid_height : float
        Reference fluid depth H [m]: c0 = coef_sound * sqrt(|g| H) unless
        `u_max` is given.
    u_max : float, optional
        Maximum expected flow speed [m/s]; c0 = coef_sound * u_max.
    surface_z : float, optional
        Still free-surface level [m] for the initial hydrostatic density
        rho = rho0 (1 + rho0 |g| (surface_z - z) / B)^(1/gamma); None starts
        at rho0.
    velocities : (N, 3) array, optional
        Initial velocities [m/s].
    motions : list of motions, optional
        Prescribed motions (:mod:`shoal.motions`) of the moving boundaries.
    motion_of : (N,) int array, optional
        Index into `motions` of each moving particle (-1 for the others).
    wall_normals : (N, 3) array, optional
        Ghost vector of each dynamic boundary particle [m] (world x, y, z): from the particle to its
        mirror image across the wall surface (`shoal.geometry.normals`; zero rows elsewhere).
        Needed by ``wall_pressure = "mdbc"``, ignored otherwise.
    planes : sequence of pairs
        Wall planes without particles (`shoal.physics.planes`), each (point, normal): a point on
        each [m] and its normal pointing into the fluid (world x, y, z).
    symmetry_y : (y, side), optional
        A symmetry plane y = const (3D): fluid on the low side (side = -1:
        normal -y) or the high side (+1). Mirror images of the particles
        within 2h stand in for the other half (see `neighbours.gather`).
    periodic : sequence of {"x", "y"}
        Periodic axes: the domain's extent along each is the period; the
        neighbour search wraps round and particles crossing a face re-enter
        at the opposite one.
    backend : str
        "cpu" (default).
    repulsive : bool, optional
        Compile the Monaghan-Kajtar boundary terms (default: when `kinds`
        holds repulsive particles; a rank's slab of a case passes the whole
        case's answer).
    """

    require_fluid = True  # a Model of the whole case needs fluid (a rank's slab may have none)

    @staticmethod
    def checked_particles(positions, kinds, dp, dim, require_fluid=True):
        """(positions as float64 (N, 3), kinds as int8 (N,)), or a one-line `InputError` for a bad
        dimension, spacing or shape, or no fluid particle (with `require_fluid`)."""
        if dim not in (2, 3):
            raise InputError(f"dim = {dim!r}; allowed 2 or 3")
        if not (np.isfinite(dp) and dp > 0):
            raise InputError(f"dp = {dp!r} m must be a positive number of metres")
        positions = np.asarray(positions, dtype=np.float64)
        kinds = np.asarray(kinds, dtype=np.int8)
        if positions.ndim != 2 or positions.shape[1] != 3 or len(kinds) != len(positions):
            raise InputError("positions must be an (N, 3) array with one kind per particle")
        if require_fluid and not np.any(kinds == FLUID):
            raise InputError("the case has no fluid particles; check the fluid region lies inside the domain "
                             "and is larger than dp")
        return positions, kinds

    @staticmethod
    def smoothing_length(options, dim, dp):
        """h = coef_h sqrt(dim) dp [m] (`shoal.physics.constants.smoothing_length`)."""
        return smoothing_length(options.coef_h, dim, dp)

    STATE_ARRAYS = ("pos", "vel", "rho", "kind", "idp", "ace", "drho", "mu_max", "pr2")
    """The per-particle arrays every checkpoint saves (`checkpoint_arrays`); the integrator's are
    `extra_arrays`."""

    buffers = None
    """The open boundaries' `shoal.particle_buffers.BufferZones`, or None."""
    body_of = None
    """(n_ids,) int32: the solid (index in the case's `solids`) of each particle id, -1 for fluid; set by
    `shoal.build.build_model` (a Model built from bare arrays has none: no force gauges)."""
    body_names = None
    """Names of the case's solids, in the order of `body_of`'s indices."""

    def __init__(self, positions, kinds, *, dp, dim, domain, options=None, rho0=1000.0,
                 gravity=(0.0, 0.0, -9.81), fluid_height=None, u_max=None, surface_z=None,
                 velocities=None, motions=None, motion_of=None, wall_normals=None, periodic=(), planes=(),
                 symmetry_y=None, backend="cpu", repulsive=None):
        options = options or SPHOptions()
        positions, kinds = self.checked_particles(positions, kinds, dp, dim, require_fluid=self.require_fluid)
        self.dim = dim
        self.dp = float(dp)
        self.options = options
        periodic = tuple(periodic or ())
        for a in periodic:
            if a not in ("x", "y") or (a == "y" and dim == 2):
                raise InputError(f"periodic axis {a!r} is not allowed; use 'x'" + (" or 'y'" if dim == 3 else
                                                                                " (2D runs are in the x-z plane)"))
        self.periodic = periodic
        planes = list(planes or ())
        sym_code = 0
        if symmetry_y is not None:
            if dim != 3:
                raise InputError("a symmetry plane is for 3D cases (normal along y)")
            if "y" in periodic:
                raise InputError("a symmetry plane y = const and a periodic y axis exclude each other")
            sym_code = 1 if symmetry_y[1] < 0 else 2
        if repulsive is None:
            repulsive = bool(np.any(kinds >= REPULSIVE))
        self.spec = SchemeSpec.from_options(options, dim, periodic, repulsive=bool(repulsive), planes=bool(planes),
                                            symmetry=sym_code)
        self.dtype = options.dtype
        self.rho0 = float(rho0)
        self.gravity = np.asarray(gravity, dtype=np.float64)
        g = float(np.linalg.norm(self.gravity))
        self.h = self.smoothing_length(options, dim, dp)
        if u_max is None and (fluid_height is None or g == 0):
            raise InputError("give u_max (maximum expected speed, m/s) or a fluid_height with gravity "
                             "to set the speed of sound")
        self.u_max = reference_speed(self.gravity, fluid_height, u_max)
        self.c0 = speed_of_sound(options.coef_sound, self.gravity, fluid_height, u_max)
        self.B = tait_coefficient(self.c0, self.rho0)
        self.mass = particle_mass(self.rho0, self.dp, dim)
        lo3 = np.asarray(domain[0], dtype=np.float64)
        hi3 = np.asarray(domain[1], dtype=np.float64)
        periods = [hi3[k] - lo3[k] if a in periodic else 0.0 for k, a in ((0, "x"), (1, "y"))]
        for L, a in zip(periods, "xy"):
            if L and abs(L / self.dp - round(L / self.dp)) > 1e-6:
                raise InputError(f"the periodic length along {a} is {L:.6g} m, not a whole number of particle "
                                 f"spacings dp = {self.dp:g} m: the lattice would not join up across the period")
        self._period_lo = (float(lo3[0]), float(lo3[1]))
        mk_k = 0.0
        if self.spec.repulsive or self.spec.planes:
            if fluid_height is None or g == 0:
                raise InputError("repulsive boundary particles and wall planes need gravity and a fluid depth "
                                 "(K = g D, Monaghan & Kajtar 2009)")
            mk_k = g * float(fluid_height) / 2.0  # K / beta, beta = dp / (dp/2)
        self.params = make_params(self.spec, dp=self.dp, h=self.h, rho0=self.rho0, c0=self.c0, gamma=GAMMA,
                                  gravity=self.gravity, options=options, mass_f=self.mass, mass_b=self.mass,
                                  periods=periods, mk_k=mk_k,
                                  sym_y=float(symmetry_y[0]) if symmetry_y is not None else 0.0,
                                  grid_lo=tuple(float(v) for v in lo3), inv_cs=options.cells_per_support / (2.0 * self.h))
        self.P = params_array(self.spec, self.params)  # what kernels receive (moved to the device below)
        from .physics.planes import plane_tables

        parr = np.zeros((len(planes), 4))
        for k, (point, normal) in enumerate(planes):
            nrm = np.asarray(normal, float).copy()
            if dim == 2:
                nrm[1] = 0.0
            if not np.linalg.norm(nrm) > 0:
                raise InputError(f"wall plane {k}: its normal {list(normal)} has no x-z component in a 2D case")
            nrm /= np.linalg.norm(nrm)
            parr[k, :3] = nrm
            parr[k, 3] = float(nrm @ np.asarray(point, float))
        ptable = plane_tables(self.spec, self.dp, self.h, mk_k) if planes else np.zeros((2, 2))

        cols = [0, 1, 2] if dim == 3 else [0, 2]
        lo = np.asarray(domain[0], dtype=np.float64)[cols]
        hi = np.asarray(domain[1], dtype=np.float64)[cols]
        n = len(positions)
        self.n_total = n
        self.backend = b = get_backend(backend, self.spec)
        flags = [("x" in periodic), ("y" in periodic)] + ([False] if dim == 3 else [])
        self.grid = b.make_grid(lo, hi, 2.0 * self.h, options.cells_per_support, n,
                                periodic=flags if dim == 3 else [flags[0], False])
        F = self.dtype
        vel = np.zeros((n, 3)) if velocities is None else np.asarray(velocities, dtype=np.float64)
        rho = np.full(n, self.rho0)
        if surface_z is not None and g > 0:
            depth = np.clip(float(surface_z) - positions[:, 2], 0.0, None)
            rho = density_of(self.rho0 * g * depth, self.rho0, self.B)  # hydrostatic
        # particle state (on the backend's device), in cell order after each sort
        # positions in float64 in every precision (see neighbours.gather)
        self.pos = b.asarray(np.ascontiguousarray(positions[:, cols], dtype=np.float64))
        self.vel = b.asarray(np.ascontiguousarray(vel[:, cols], dtype=F))
        self.rho = b.asarray(rho.astype(F))
        self.kind = b.asarray(kinds.copy())
        self.idp = b.asarray(np.arange(n, dtype=np.int32))
        self.P = b.asarray(self.P)
        self.planes = b.asarray(parr)
        self.ptable = b.asarray(ptable.astype(F))
        # rates and work arrays
        self.ace = b.zeros((n, dim), F)
        self.drho = b.zeros(n, F)
        self.mu_max = b.zeros(n, F)  # max over the neighbours of |h v_ij.r_ij / (r^2 + eta^2)| [m/s], for dt
        self.pr2 = b.zeros(n, F)
        self.xsph = b.zeros((n, dim) if self.spec.xsph else (1, dim), F)
        self.tau = b.zeros((n, 3 if dim == 2 else 6) if self.spec.sps else (1, 3 if dim == 2 else 6), F)
        self.vwall = b.zeros((n, dim) if self.spec.no_slip else (1, dim), F)
        self.scratch = {
            (np.dtype(np.float64).str, dim): b.zeros((n, dim), np.float64),
            (np.dtype(F).str, dim): b.zeros((n, dim), F),
            (np.dtype(F).str, 0): b.zeros(n, F),
            (np.dtype(np.int32).str, 0): b.zeros(n, np.int32),
            (np.dtype(np.int8).str, 0): b.zeros(n, np.int8),
        }
        self.extra_arrays = []  # integrator state arrays that follow the sort
        self.array_owners = []  # objects holding extra_arrays as attributes (see new_array)
        self.store = ParticleStore(self, n)  # the per-particle arrays' capacity and growth
        self.time = 0.0  # simulated time of the state (set by the Simulation)
        self.n = n
        self.n_escaped = 0
        self.on_escape = None  # on_escape(model, start, stop): rows start..stop just left the domain
        self._init_motions(positions[:, cols], kinds, motions, motion_of)
        self._init_wall_normals(kinds, wall_normals)
        self._no_ghosts = b.asarray(np.zeros((1, dim), F))  # the rates' ghost table when there is none
        self._no_spos = b.asarray(np.zeros((2 * dim, 1), np.float32))  # the rates' split positions where unread
        self._split_lo = np.array([self.params.grid_lo_x, self.params.grid_lo_y, self.params.grid_lo_z][:dim]
                                  if dim == 3 else [self.params.grid_lo_x, self.params.grid_lo_z])
        if self.spec.wall_pressure == ADAMI and self.motion_of is None:
            # the Adami wall-pressure kernel reads a motion table; without moving walls, one unused row
            # (not a per-particle array: a checkpoint saves only arrays of n_total rows, each once)
            self._motion_table = b.asarray(np.zeros((1, motion_layout(dim).width)))
            self._no_motion_of = b.asarray(np.zeros(1, np.int32))
        self.rho_range = (0.7 * self.rho0, 1.3 * self.rho0)

    def _init_motions(self, positions, kinds, motions, motion_of):
        """The motions' state: each particle's start position and motion by id, the motion table
        (`shoal.physics.body_motion.motion_layout`) and, where a motion rotates, the t = 0 copies of the
        id-indexed wall vectors (`_init_wall_normals`) that turn with it."""
        self.motions = list(motions or [])
        self.floating = BodyCoupling(self.motions, self.dim)  # the floating bodies among them (none: a no-op)
        if self.floating:  # the per-particle forces their loads are summed from
            self._force = self.backend.zeros((max(len(kinds), 1), self.dim), self.dtype)
            self._contact = self.backend.zeros((max(len(kinds), 1), self.dim), np.float64)
        # each motion's Coulomb friction coefficient in contact (shoal.physics.contact; 0: not a floating body)
        self._friction = self.backend.asarray(np.array([float(getattr(m, "friction", 0.0)) for m in self.motions]
                                                       or [0.0]))
        self._rotating = False
        self._wall_vectors = []  # (initial, current) id-indexed tables that turn with a rotating wall
        for m in self.motions:
            axis = getattr(m, "rotation_axis", None)
            if axis is not None and self.dim == 2 and not (axis[0] == 0.0 and axis[2] == 0.0):
                raise InputError(f"motion {m.name!r} rotates about the axis {[float(a) for a in axis]}: a 2D case "
                                 "(the x-z plane) rotates only about the y axis; give axis = [0, 1, 0]")
        moving = (kinds == MOVING) | (kinds == REPULSIVE_MOVING)
        if not moving.any():
            self.motion_of = None
            return
        motion_of = np.full(len(kinds), -1, np.int32) if motion_of is None else np.asarray(motion_of, np.int32)
        bad = moving & ((motion_of < 0) | (motion_of >= len(self.motions)))
        if bad.any():
            raise InputError(f"{int(bad.sum())} moving boundary particles have no motion; give each moving solid "
                             f"a motion (motions defined: {len(self.motions)})")
        b = self.backend
        self.pos_init = b.asarray(np.ascontiguousarray(positions, dtype=np.float64))
        self.motion_of = b.asarray(motion_of)
        used = np.unique(motion_of[moving])
        self._rotating = any(getattr(self.motions[k], "rotation_axis", None) is not None for k in used)
        # one float64 row per motion, filled at every stage by move_bodies (its only host-device copy)
        self._motion_host = np.zeros((len(self.motions), motion_layout(self.dim).width))
        self._motion_table = b.asarray(self._motion_host.copy())
        self.move_bodies(0.0)

    def _init_wall_normals(self, kinds, wall_normals):
        """The mDBC ghost-vector table `ghost_of` ((n_ids - ghost_id0, dim), working precision),
        indexed by particle id less `ghost_id0`, the first boundary particle's id (the generator puts
        the fluid first, so the table holds the walls only); with ``riemann``, `wall_normal_of`, the
        same rows as unit normals (zero where a wall particle has no ghost vector)."""
        self.ghost_of, self.ghost_id0, self.ghost_reach, self.wall_normal_of = None, 0, 0.0, None
        if self.spec.wall_pressure != MDBC and not (self.spec.riemann and wall_normals is not None):
            return
        dynamic = (kinds == FIXED) | (kinds == MOVING)
        if wall_normals is None:
            if dynamic.any():
                raise InputError('wall_pressure = "mdbc" needs the walls\' ghost vectors (wall_normals); build '
                                 'the model from a Case, whose generator computes them from the geometry')
            wall_normals = np.zeros((len(kinds), 3))
        g = np.asarray(wall_normals, dtype=np.float64)
        if g.shape != (len(kinds), 3) or not np.all(np.isfinite(g)):
            raise InputError(f"wall_normals must be a finite (N, 3) array, one row per particle (N = {len(kinds)})")
        cols = [0, 1, 2] if self.dim == 3 else [0, 2]
        ids = np.flatnonzero(dynamic)
        id0 = int(ids[0]) if len(ids) else 0
        table = np.zeros((max(len(kinds) - id0, 1), self.dim), self.dtype)
        table[:len(kinds) - id0] = np.where(dynamic[id0:, None], g[id0:][:, cols], 0.0)
        self.ghost_id0 = id0
        self.ghost_reach = float(np.sqrt((g[dynamic] ** 2).sum(axis=1)).max()) if len(ids) else 0.0
        self.ghost_of = self.backend.asarray(table) if self.spec.wall_pressure == MDBC else None
        if self.spec.riemann:
            # the Riemann wall term's unit normals, so that a fluid-wall pair reads no square root
            size = np.sqrt((table.astype(np.float64) ** 2).sum(axis=1, keepdims=True))
            unit = np.divide(table, size, out=np.zeros_like(table, dtype=np.float64), where=size > 0)
            self.wall_normal_of = self.backend.asarray(unit.astype(self.dtype))
        if self._rotating:
            # a rotating wall's ghost vectors and normals turn with it: R(t) times their values at t = 0
            b = self.backend
            self._wall_vectors = [(b.copy(a), a) for a in (self.ghost_of, self.wall_normal_of) if a is not None]
            self._rotate_wall_vectors()

    def sample(self, points, shepard=True):
        """SPH interpolation at fixed points (`shoal.physics.interpolation`).

        Parameters
        ----------
        points : (M, 3) array
            World coordinates [m].
        shepard : bool
            Divide by the kernel sum (default) or return the plain sums.

        Returns
        -------
        dict of (M,) or (M, 3) float64 arrays: "kernel_sum", "pressure" [Pa],
        "density" [kg/m^3], "velocity" [m/s] (NaN where no fluid particle is
        within 2h, in the Shepard form).
        """
        from .physics.interpolation import n_probe_columns

        internal = self._internal_points(points)
        b = self.backend
        self.refresh_ghosts()
        self.ghosts_spent()
        out, glo = self._point_buffers("_probe_buf", len(internal), n_probe_columns(self.dim))
        inv_cs = 1.0 / self.grid.cell_size
        b.timed(b.probe, len(internal), (b.asarray(internal), self.pos, self.vel, self.rho, self.kind,
                                         self.grid.cell_start, self.grid.gdims_arr, glo, inv_cs, self.P, out))
        o = self.backend.to_host(out, 0, len(internal)).astype(np.float64)
        sums = np.zeros((len(internal), 6))  # kernel sum, pressure, density, velocity (x, y, z)
        sums[:, :3] = o[:, :3]
        if self.dim == 3:
            sums[:, 3:6] = o[:, 3:6]
        else:
            sums[:, 3], sums[:, 5] = o[:, 3], o[:, 4]
        sums[~self.answers(internal)] = 0.0
        sums = self.reduce_array(sums, "sum")
        s, vel = sums[:, 0], sums[:, 3:6]
        if shepard:
            with np.errstate(invalid="ignore", divide="ignore"):
                inv = np.where(s > 0, 1.0 / s, np.nan)
            return {"kernel_sum": s, "pressure": sums[:, 1] * inv, "density": sums[:, 2] * inv,
                    "velocity": vel * inv[:, None]}
        return {"kernel_sum": s, "pressure": sums[:, 1], "density": sums[:, 2], "velocity": vel}

    def sensor_moments(self, points, normals=None):
        """The fluid's weighted moments around fixed points (`shoal.physics.interpolation.make_sensor_moments`),
        from which `shoal.probes.pressure_sensors.fit_pressure` extrapolates the pressure to each point.

        Parameters
        ----------
        points : (M, 3) array
            World coordinates [m].
        normals : (M, 3) array, optional
            The normal of the wall at each point (out of the wall into the fluid, any length; zero for
            none): only the fluid in front of the wall's plane through the point, or less than half a
            spacing behind it, counts.

        Returns
        -------
        (M, 14) float64 array in 3D, (M, 9) in 2D.
        """
        from .physics.interpolation import n_moment_columns

        internal = self._internal_points(points)
        faced = np.zeros((len(internal), 7))
        faced[:, :3] = internal
        if normals is not None:
            n = self._internal_points(normals)
            length = np.linalg.norm(n, axis=1, keepdims=True)
            faced[:, 3:6] = np.divide(n, length, out=np.zeros_like(n), where=length > 0)
            faced[:, 6] = 0.5 * self.dp
        b = self.backend
        self.refresh_ghosts()
        self.ghosts_spent()
        key = len(internal)
        out, glo = self._point_buffers("_moment_buf", key, n_moment_columns(self.dim))
        b.timed(b.sensor_moments, key, (b.asarray(faced), self.pos, self.rho, self.kind, self.grid.cell_start,
                                        self.grid.gdims_arr, glo, 1.0 / self.grid.cell_size, self.P, out))
        moments = b.to_host(out, 0, key).astype(np.float64)
        moments[~self.answers(internal)] = 0.0
        return self.reduce_array(moments, "sum")

    def _point_buffers(self, attr, n, columns):
        """(out, grid corner) device buffers of a point kernel for `n` points, kept in `attr` while n holds."""
        b = self.backend
        if getattr(self, attr, (None,))[0] != n:
            setattr(self, attr, (n, b.zeros((n, columns), self.dtype), b.asarray(np.asarray(self.grid.lo, np.float64))))
        _, out, glo = getattr(self, attr)
        return out, glo

    def _internal_points(self, points):
        """(M, 3) float64 points in the gather's coordinates: (x, y, z) in 3D, (x, 0, z) in 2D."""
        pts = np.asarray(points, dtype=np.float64).reshape(-1, 3)
        internal = pts.copy()
        if self.dim == 2:
            internal[:, 1] = 0.0
        return internal

    def free_surface(self):
        """(n,) int8 flags of the active particles: 1 on the free surface (Marrone et
        al. 2010 as in the rip-current paper, `shoal.physics.free_surface`), else 0."""
        self.refresh_ghosts()
        self.ghosts_spent()
        b = self.backend
        out = self.scratch[(np.dtype(np.int8).str, 0)]
        wet = self.scratch[(np.dtype(np.int32).str, 0)]  # free between sorts
        g = self.grid
        b.timed(b.wet_walls, self.n, (self.pos, self.kind, g.cell, g.cell_start, g.gdims_arr, self.P, wet))
        b.timed(b.free_surface, self.n, (self.pos, self.rho, self.kind, g.cell, g.cell_start,
                                         g.gdims_arr, self.P, self.planes, wet, out))
        return self.host(out).copy()

    def apply_shifting(self):
        """Move the fluid particles by the particle shifting of the options (``shifting = "delta_plus"``:
        Sun et al. 2017, `shoal.physics.shifting`), positions only.

        Three passes over the positions of the step's end, then one that moves them: the wet walls and
        the free-surface flags (`free_surface`'s), each particle's shift delta r_i = -C Ma (2h)^2
        sum_j [1 + R (W_ij / W(dp))^4] grad_i W_ij V_j (tangential at and near the free surface, capped
        at 0.1 dp) into a buffer, then r_i += delta r_i, so no shift reads a moved neighbour. The open
        boundaries' buffer particles are not shifted (`shoal.particle_buffers.BufferZones.hold_shift`). C is
        ``shifting_coef``, Ma = U_max / c0. The ghosts of a distributed model are refreshed first (their
        own shifts are computed and dropped: the next sort replaces them); no array is allocated."""
        self.refresh_ghosts()
        self.ghosts_spent()
        b, g = self.backend, self.grid
        surface = self.scratch[(np.dtype(np.int8).str, 0)]
        wet = self.scratch[(np.dtype(np.int32).str, 0)]  # free between sorts
        out = self.scratch[(np.dtype(np.float64).str, self.dim)]  # the sort's; free between sorts
        coef = self.options.shifting_coef * (self.u_max / self.c0) * (2.0 * self.h) ** 2
        b.timed(b.wet_walls, self.n, (self.pos, self.kind, g.cell, g.cell_start, g.gdims_arr, self.P, wet))
        b.timed(b.free_surface, self.n, (self.pos, self.rho, self.kind, g.cell, g.cell_start,
                                         g.gdims_arr, self.P, self.planes, wet, surface))
        b.timed(b.shift, self.n, (self.pos, self.rho, self.kind, g.cell, g.cell_start, g.gdims_arr, self.P,
                                  self.planes, wet, surface, float(coef), 0.1 * self.dp, out))
        if self.buffers is not None:
            self.buffers.hold_shift(self, out)
        b.timed(b.shift_apply, self.n, (self.pos, self.kind, out))

    def apply_damping(self, zones, dt):
        """Apply the damping zones (`shoal.case.DampingZone`) over a step dt [s]."""
        b = self.backend
        for z in zones:
            s0 = np.asarray(z.start, float)
            e = np.asarray(z.end, float) - s0
            if self.dim == 2:
                e[1] = 0.0
            L = float(np.linalg.norm(e))
            e /= L
            b.timed(b.damp, self.n, (self.pos, self.vel, self.kind, s0[0], s0[1], s0[2], e[0], e[1], e[2],
                                     1.0 / L, float(z.rate), float(dt)))

    def apply_relaxation(self, zones, t, dt):
        """Relax the fluid velocity in the relaxation zones (`shoal.relaxation.RelaxationTerms`) toward their
        targets at time `t` [s], over a step `dt` [s] (`shoal.physics.relaxation`). Each zone's per-component
        terms are written on the host into a buffer made at its first step, and copied into the backend's."""
        b = self.backend
        buffers = self.__dict__.setdefault("_relaxation_buffers", {})
        for z in zones:
            if id(z) not in buffers or buffers[id(z)][0] is not z:
                host = z.buffer()
                buffers[id(z)] = (z, host, host if b.name == "cpu" else b.asarray(host))
            _, host, terms = buffers[id(z)]
            z.fill(float(t), host)
            if terms is not host:
                b.copy_into(terms, host, len(host))
            b.timed(b.relax, self.n, (self.pos, self.vel, self.kind, z.start, z.inv_len, z.sign, z.origin, z.level,
                                      z.depth, float(dt) / z.time_scale, z.count, terms))

    def move_bodies(self, t):
        """Place the moving boundary particles where their motions put them at time `t` [s], with their
        velocities (`shoal.physics.body_motion`): one `rigid_kinematics` call per motion fills the motion
        table, which the kernels read (the Adami wall pressure, its accelerations too); the ghost vectors
        and normals of a rotating wall turn with it."""
        if self.motion_of is None:
            return
        adami = self.spec.wall_pressure == ADAMI
        host = self._motion_host
        for k, m in enumerate(self.motions):
            fill_motion_row(host[k], self.dim, m.rigid_kinematics(t, acceleration=adami))
        b = self.backend
        self._motion_table = b.asarray(host.copy()) if b.name != "cpu" else host
        b.timed(b.move_bodies, self.n, (self.pos, self.vel, self.kind, self.idp, self.pos_init, self.motion_of,
                                        self._motion_table))
        if self._rotating:
            self._rotate_wall_vectors()

    def _rotate_wall_vectors(self):
        """Turn the id-indexed wall vectors (mDBC ghost vectors, Riemann normals) of the rotating walls
        to the motion table's orientation."""
        b = self.backend
        for initial, current in self._wall_vectors:
            b.timed(b.rotate_wall_vectors, self.n, (self.kind, self.idp, self.motion_of, self._motion_table,
                                                    int(self.ghost_id0), initial, current))

    # ------------------------------------------------------------------ sizes
    @property
    def n_fluid(self):
        """Number of active fluid particles."""
        return int(np.count_nonzero(self.host(self.kind) == FLUID))

    @property
    def capacity(self):
        """Rows each per-particle array holds (`ParticleStore`): the active particles, then room."""
        return self.store.capacity

    def per_particle_arrays(self):
        """The arrays with a row per particle that `ParticleStore` sizes together: the state, the
        rates, the work arrays, the integrator's (``extra_arrays``) and, where the scheme keeps
        them, the XSPH velocity, SPS stress and no-slip wall velocity. Not the arrays indexed by
        particle id (``pos_init``, ``motion_of``, ``ghost_of``) nor the neighbour grid's."""
        arrays = [self.pos, self.vel, self.rho, self.kind, self.idp, self.ace, self.drho, self.mu_max, self.pr2,
                  *self.scratch.values(), *self.extra_arrays]
        return arrays + [a for a, kept in ((self.xsph, self.spec.xsph), (self.tau, self.spec.sps),
                                           (self.vwall, self.spec.no_slip)) if kept]

    def host(self, array, start=0, stop=None):
        """Rows start..stop (default: the active particles) of a particle array, as NumPy."""
        return self.backend.to_host(array, start, self.n if stop is None else stop)

    def nbytes(self):
        """Bytes of particle, work and grid arrays held by the model."""
        arrays = [self.pos, self.vel, self.kind, self.idp, self.rho, self.ace, self.drho, self.mu_max,
                  self.pr2, self.xsph, self.tau, self.vwall, *self.scratch.values(), *self.extra_arrays]
        if self.motion_of is not None:
            arrays += [self.pos_init, self.motion_of]
        if self.floating:
            arrays += [self._force, self._contact]
        arrays += [a for a in (self.ghost_of, self.wall_normal_of) if a is not None]
        arrays += [initial for initial, _ in getattr(self, "_wall_vectors", ())]
        return sum(int(a.size) * a.dtype.itemsize for a in arrays) + self.grid.nbytes

    def new_array(self, like, owner=None):
        """Allocate an integrator state array that follows the particle sort.

        Parameters
        ----------
        like : backend array
            The array to copy (shape, dtype and contents).
        owner : object, optional
            The object that keeps the array as an attribute (an integrator):
            when the device arrays grow (`ParticleStore.resize`), that
            attribute is re-pointed to the new array.
        """
        a = self.backend.copy(like)
        self.extra_arrays.append(a)
        if owner is not None and all(o is not owner for o in self.array_owners):
            self.array_owners.append(owner)
        return a

    # ------------------------------------------------------------- operations
    def sort(self):
        """Bin particles into cells and reorder all arrays in cell order.

        Particles outside the domain go to the end and leave the computation.
        """
        n_before = self.n
        if self.periodic or self.spec.symmetry:
            b = self.backend
            b.timed(b.wrap_periodic, n_before, (self.pos, self.vel, self._period_lo[0], self._period_lo[1], self.P))
        n = self.grid.bin(self.pos, n_before)
        arrays = [self.pos, self.vel, self.rho, self.kind, self.idp, *self.extra_arrays]
        self.grid.reorder(arrays, n_before, self.scratch)
        if n < n_before:
            gone_pos = self.host(self.pos, n, n_before)
            gone_vel = self.host(self.vel, n, n_before)
            bad = ~np.all(np.isfinite(gone_pos), axis=1) | ~np.all(np.isfinite(gone_vel), axis=1)
            if np.any(bad):
                k = int(np.argmax(bad))
                pid = int(self.host(self.idp, n, n_before)[k])
                pkind = int(self.host(self.kind, n, n_before)[k])
                raise InstabilityError(
                    f"particle id {pid} ({KIND_NAMES.get(pkind, 'particle')}) has a "
                    f"non-finite position or velocity: the run blew up; likely causes: a time step too large "
                    f"(lower cfl or raise coef_sound), particles penetrating a wall, or too coarse a resolution")
            self.n_escaped += n_before - n
            self.n = n
            if self.on_escape is not None:
                self.on_escape(self, n, n_before)
            if self.require_fluid and self.n_fluid == 0:
                raise InstabilityError("every fluid particle has left the domain box "
                                       f"{self.grid.lo.tolist()} - {self.grid.hi.tolist()} m")
        return n

    # ------------------------------------------------ what a model spread over processes fills in
    # A Model holds every particle; `shoal.parallel.model.DistributedModel` holds a rank's slab and copies
    # of its neighbours' particles (ghosts), and takes part in the physics only through these hooks.
    def refresh_ghosts(self, always=True):
        """Before a pass that reads the neighbours' current values: bring the ghosts up to date (`always`:
        even if the last sort has just done so). One process: nothing."""

    def ghosts_spent(self):
        """After such a pass: the ghosts' values are no longer current (the next pass refreshes them)."""

    def clear_ghost_rates(self):
        """After the rates: the ghosts' rates belong to their owners (a distributed model zeroes them)."""

    def reduce(self, value, op="min"):
        """`value` combined over the processes of the run (`op`: "min", "max", "sum"); one process: itself."""
        return value

    def raise_together(self, message):
        """Raise `InstabilityError(message)` where a check failed (`message` not None); a distributed model
        raises on every rank, with the first failing rank's message."""
        if message is not None:
            raise InstabilityError(message)

    def reduce_array(self, values, op="sum"):
        """An array combined element by element over the processes (`op`: "min", "max", "sum"); one
        process: itself."""
        return values

    def gather(self, value):
        """[`value` of each process], in rank order, on every process; one process: [value]."""
        return [value]

    def answers(self, points):
        """(M,) bool: which of the (M, 3) points (the gather's coordinates) this process measures, each
        point by exactly one process of the run; one process: all of them (a distributed model: those
        in its slab, whose support its halo covers)."""
        return np.ones(len(points), bool)

    def owned_rows(self):
        """Rows of the active particles this process reports (all of them; a distributed model: those
        it owns, never its ghosts): an index for the arrays of ``n`` rows."""
        return slice(None)

    def compute_rates(self):
        """Evaluate d rho/dt, dv/dt (and XSPH) of the active particles."""
        self.refresh_ghosts(always=False)
        self.ghosts_spent()
        self._rates()
        self.clear_ghost_rates()
        if self.buffers is not None:
            self.buffers.hold(self)
        if self.floating:
            self.floating.measure(self)

    def _rates(self):
        b, n, P = self.backend, self.n, self.P
        if self.spec.wall_pressure == ADAMI:
            motion_of = self.motion_of if self.motion_of is not None else self._no_motion_of
            b.timed(b.wall_pressure, n, (self.pos, self.rho, self.kind, self.idp, motion_of, self._motion_table,
                                         self.grid.cell, self.grid.cell_start, self.grid.gdims_arr, P))
        elif self.spec.wall_pressure == MDBC:
            # also the walls' no-slip velocity, from the same ghost nodes
            b.timed(b.mdbc, n, (self.pos, self.vel, self.rho, self.kind, self.idp, self.ghost_of, self.ghost_id0,
                                self.grid.cell_start, self.grid.gdims_arr, P, self.vwall))
        b.timed(b.pr2, n, (self.rho, self.pr2, P))
        if self.spec.sps:
            b.timed(b.sps, n, (self.pos, self.vel, self.rho, self.kind, self.grid.cell, self.grid.cell_start,
                               self.grid.gdims_arr, P, self.tau))
        if self.spec.no_slip and self.spec.wall_pressure != MDBC:
            b.timed(b.wall_velocity, n, (self.pos, self.vel, self.kind, self.grid.cell, self.grid.cell_start,
                                         self.grid.gdims_arr, P, self.vwall))
        ghosts, gid0 = self._ghost_args()
        b.timed(b.rates, n, (self.pos, self.split_positions(), self.vel, self.rho, self.pr2, self.kind, self.grid.cell,
                             self.grid.cell_start, self.grid.gdims_arr, P, self.ace, self.drho, self.xsph,
                             self.mu_max, self.tau, self.planes, self.ptable, self.vwall, self.idp, ghosts, gid0))

    def split_positions(self):
        """The CPU rates' split float32 coordinates, (2 dim, >= n): the positions less the grid's lower
        corner as high and low float32 parts (`shoal.backends.cpu.split_positions`), which the compact
        gather reads instead of the float64 positions (`shoal.neighbours.gather.make_gather`). Written
        into the sort's float64 work array (free between sorts; 2 dim float32 a particle fill its dim
        float64), viewed as float32: no memory of their own. On a backend without `split_positions`, or with
        periodic axes or a symmetry plane, a placeholder the kernels do not read."""
        split = getattr(self.backend, "split_positions", None)
        if split is None or self.periodic or self.spec.symmetry:  # the periodic gather reads none
            return self._no_spos
        work = self.scratch[(np.dtype(np.float64).str, self.dim)]
        rows = work.shape[0]
        spos = work.reshape(-1).view(np.float32)[:2 * self.dim * rows].reshape(2 * self.dim, rows)
        split(self.n, self.pos, self._split_lo, spos)
        return spos

    def _ghost_args(self):
        """(unit-normal table, first id) for the rates and wall forces: with ``riemann`` and wall normals
        the fluid-wall pairs read the walls' normals from it; -1 when there is no table."""
        if self.wall_normal_of is None:
            return self._no_ghosts, -1
        return self.wall_normal_of, int(self.ghost_id0)

    def time_step_limit(self):
        """Variable time step of Monaghan & Kos (1999), as in DualSPHysics:

        dt = CFL min( sqrt(h / max|a|), h / (c0 + max |h v_ij.r_ij/(r^2+eta^2)|) ),
        and dt <= 0.125 h^2 / nu for laminar viscosity (Morris et al. 1997).
        """
        o = self.options
        if o.fixed_dt is not None:
            return o.fixed_dt
        a2, vm = self.backend.dt_terms(self.n, self.ace, self.mu_max, self.kind)
        h = self.h
        dt_f = math.sqrt(h / math.sqrt(a2)) if a2 > 0 else math.inf
        dt_cv = h / (self.c0 + vm)
        dt = o.cfl * min(dt_f, dt_cv)
        if o.viscosity == "laminar" and o.nu > 0:
            dt = min(dt, 0.125 * h * h / o.nu)
        return self.reduce(dt, "min")

    def apply_filter(self, kind):
        """Re-initialise fluid density with the "shepard" or "mls" filter."""
        self.refresh_ghosts()
        b, n, P = self.backend, self.n, self.P
        out = self.scratch[(np.dtype(self.dtype).str, 0)]
        kernel = b.shepard if kind == "shepard" else b.mls
        b.timed(kernel, n, (self.pos, self.rho, self.kind, self.grid.cell, self.grid.cell_start,
                            self.grid.gdims_arr, P, out))
        b.copy_into(self.rho, out, n)
        self.ghosts_spent()

    def check(self, step, time):
        """Raise InstabilityError naming the first particle with NaN/inf state
        or a fluid density outside the sane band (0.7 rho0, 1.3 rho0)."""
        self.raise_together(self._bad_particle(step, time))

    def _bad_particle(self, step, time):
        """The message of `check` for this process's first bad particle, or None."""
        i, code = self.backend.find_bad(self.n, self.pos, self.vel, self.rho, self.kind, *self.rho_range)
        if i < 0:
            return None
        where = self._world(self.host(self.pos, i, i + 1))[0]  # row i of the rows scanned (ghosts included)
        what = "non-finite position, velocity or density" if code == 1 else (
            f"density {float(self.host(self.rho, i, i + 1)[0]):.6g} kg/m^3 outside the sane band "
            f"[{self.rho_range[0]:.4g}, {self.rho_range[1]:.4g}]")
        return (
            f"unstable at step {step}, t = {time:.6g} s: "
            f"{KIND_NAMES.get(int(self.host(self.kind, i, i + 1)[0]), 'particle')} "
            f"particle id {int(self.host(self.idp, i, i + 1)[0])} at (x, y, z) = ({where[0]:.4g}, {where[1]:.4g}, {where[2]:.4g}) m "
            f"has {what}; likely causes: a time step too large (lower cfl or raise coef_sound), "
            f"particles penetrating a wall, or too coarse a resolution")

    # ---------------------------------------------------------------- output
    def world_positions(self, active_only=True):
        """(N, 3) float64 positions in world coordinates of the particles this process reports
        (`owned_rows`; with `active_only` false, all ``n_total`` rows)."""
        if active_only:
            return self._world(self.host(self.pos)[self.owned_rows()])
        return self._world(self.host(self.pos, 0, self.n_total))

    def _world(self, p):
        """(N, 3) float64 world coordinates of the stored positions `p` ((x, z) in 2D)."""
        out = np.zeros((len(p), 3))
        if self.dim == 3:
            out[:] = p
        else:
            out[:, 0] = p[:, 0]
            out[:, 2] = p[:, 1]
        # a particle that crossed a periodic face in the last step is wrapped at the next sort;
        # report it inside the period already
        for k, a in ((0, "x"), (1, "y")):
            if a in self.periodic:
                L = self.params.per_len_x if a == "x" else self.params.per_len_y
                lo = self._period_lo[k]
                out[:, k] = lo + np.mod(out[:, k] - lo, L)
        return out

    def world_velocities(self):
        """(N, 3) float64 velocities of the particles `world_positions` gives."""
        v = self.host(self.vel)[self.owned_rows()]
        out = np.zeros((len(v), 3))
        if self.dim == 3:
            out[:] = v
        else:
            out[:, 0] = v[:, 0]
            out[:, 2] = v[:, 1]
        return out

    def checkpoint_arrays(self):
        """The per-particle state a checkpoint saves, by attribute name: `STATE_ARRAYS`; the XSPH
        velocity, the SPS stress and the no-slip wall velocity where the scheme keeps them per particle
        (otherwise they are one-row placeholders); with moving bodies, each particle's start position and
        motion (indexed by id). Not state: the case's geometry (``body_of``, ``ghost_of``,
        ``wall_normal_of``), work arrays (``scratch``, a force gauge's), the neighbour grid's."""
        out = {name: getattr(self, name) for name in self.STATE_ARRAYS}
        for name in ("xsph", "tau", "vwall"):
            a = getattr(self, name)
            if a.shape[0] == self.capacity and self.capacity > 1:
                out[name] = a
        if self.motion_of is not None:
            out["pos_init"], out["motion_of"] = self.pos_init, self.motion_of
        return out

    def pressure(self):
        """Tait pressure [Pa] (float64) of the particles `world_positions` gives."""
        return pressure_of(self.host(self.rho)[self.owned_rows()], self.rho0, self.B)

    def fields(self):
        """Point data for snapshots of the particles `world_positions` gives."""
        own = self.owned_rows()
        free = self.free_surface()[own]
        return {
            "velocity": self.world_velocities(),
            "density": self.host(self.rho)[own].astype(np.float64),
            "pressure": self.pressure(),
            "id": self.host(self.idp)[own].copy(),
            "kind": self.host(self.kind)[own].astype(np.int32),
            "free_surface": free.astype(np.int32),
        }

    # ------------------------------------------------------ particle probes
    def owned_particles(self):
        """The particles this process measures: all the active ones (under MPI a
        `DistributedModel` gives its owned particles, never its halo's ghosts).

        Returns
        -------
        positions : ndarray, shape (N, 3)
            World coordinates [m], float64.
        kinds : ndarray, shape (N,)
            Particle kinds.
        ids : ndarray, shape (N,)
            Particle ids.
        """
        own = self.owned_rows()
        return self.world_positions(), self.host(self.kind)[own], self.host(self.idp)[own]

    def particle_positions(self, ids):
        """World positions [m] of the particles with `ids` (a `Tracker`).

        Parameters
        ----------
        ids : array_like of int, shape (K,)
            Particle ids.

        Returns
        -------
        ndarray, shape (K, 3)
            float64; NaN rows for particles that have left the domain.
        """
        from .probes import positions_of

        pos, _, idp = self.owned_particles()
        parts = np.stack(self.gather(positions_of(idp, pos, ids)))  # (processes, K, 3): NaN where not held
        found = ~np.isnan(parts[:, :, 0])
        return parts[np.argmax(found, axis=0), np.arange(parts.shape[1])]

    def nearest_fluid(self, points):
        """Ids of the fluid particles nearest to `points` [m] (shape (K, 3)) over every process;
        among particles at exactly the same distance the smallest id (-1: no fluid)."""
        from .probes import nearest_particles

        pos, kinds, idp = self.owned_particles()
        fluid = kinds == FLUID
        d2, ids = (np.stack(a) for a in zip(*self.gather(nearest_particles(pos[fluid], idp[fluid], points))))
        best = d2.min(axis=0)
        out = np.where(d2 == best, ids, np.iinfo(np.int64).max).min(axis=0)
        return np.where(np.isfinite(best), out, -1)

    def wall_forces(self):
        """The force [N; 2D: N/m] the fluid exerts on each dynamic boundary particle now
        (`shoal.physics.forces`; 0 on fluid and repulsive particles).

        Returns
        -------
        forces : ndarray, shape (N, 3)
            World components, float64, of the particles `owned_particles` gives (in its order).
        ids : ndarray, shape (N,)
            Their ids.
        """
        n = self.n
        self._wall_force_pass()
        f = self.host(self._force, 0, n).astype(np.float64)
        out = np.zeros((n, 3))
        out[:, [0, 1, 2] if self.dim == 3 else [0, 2]] = f
        return out[self.owned_rows()], self.host(self.idp)[self.owned_rows()]

    def _wall_force_pass(self, only_moving=False):
        """The force of the fluid on each boundary particle into ``self._force`` (`shoal.physics.forces`); with
        `only_moving` on the moving ones only (0 on the others)."""
        b, n, P = self.backend, self.n, self.P
        if getattr(self, "_force", None) is None or self._force.shape[0] < n:
            self._force = b.zeros((max(n, 1), self.dim), self.dtype)
        b.timed(b.pr2, n, (self.rho, self.pr2, P))
        ghosts, gid0 = self._ghost_args()
        b.timed(b.wall_force, n, (self.pos, self.vel, self.rho, self.pr2, self.kind, self.grid.cell,
                                  self.grid.cell_start, self.grid.gdims_arr, P, self.vwall, self.idp, ghosts, gid0,
                                  bool(only_moving), self._force))

    def ghost_flags(self):
        """(N,) int8 array flagging the rows that are copies of another process's particles, or None (one
        process: there are none)."""
        return None

    def floating_loads(self, row, centres, contact=False):
        """The fluid's force and torque on each floating body now (`shoal.body_coupling`), or with `contact`
        those of the contact forces of the walls and the other bodies (`shoal.physics.contact`).

        Parameters
        ----------
        row : (M,) int32 array
            For each motion, its body's row in `centres` (-1: not a floating body).
        centres : (B, 3) float64 array
            Each body's centre of gravity [m], about which its torque is taken.

        Returns
        -------
        (B, 6) float64 array
            F [N] (columns 0-2) and T = sum (x_b - c) x F_b [N m] (3-5), world frame (2D: per metre of
            width, T about y), summed over the body's particles of every process.
        """
        b, n = self.backend, self.n
        if getattr(self, "_body_buffers", None) is None or self._body_buffers[0].shape != centres.shape:
            self._body_buffers = (b.asarray(centres.copy()), b.zeros((centres.shape[0], 6), np.float64),
                                  b.asarray(np.asarray(row, np.int32).copy()), np.zeros((centres.shape[0], 6)))
        dev_c, dev_out, dev_row, host_out = self._body_buffers
        b.copy_into(dev_c, centres, centres.shape[0])
        if contact:
            if getattr(self, "_contact", None) is None or self._contact.shape[0] < n:
                self._contact = b.zeros((max(n, 1), self.dim), np.float64)
            dc, k, c = contact_constants(self.rho0, self.c0, self.dp, self.dim)
            b.timed(b.contact, n, (self.pos, self.vel, self.kind, self.idp, self.motion_of, dev_row, self._friction,
                                   self.planes, self.grid.cell, self.grid.cell_start, self.grid.gdims_arr, self.P, dc, k, c,
                                   self._contact))
            force = self._contact
        else:
            self._wall_force_pass(only_moving=True)
            force = self._force
        ghost = self.ghost_flags()
        use_ghost = ghost is not None
        if ghost is None:
            if getattr(self, "_body_no_ghost", None) is None:
                self._body_no_ghost = b.zeros(1, np.int8)
            ghost = self._body_no_ghost
        b.body_sums(n, self.pos, force, self.kind, self.idp, self.motion_of, ghost, use_ghost, dev_row, dev_c, dev_out)
        b.copy_to_host(host_out, dev_out, host_out.shape[0])
        return self.reduce_array(host_out, "sum")

    def body_force(self, body):
        """Total force [N; 2D: N/m] of the fluid on the solid numbered `body` (the case's `solids`
        order; `body_of` maps each particle id to its solid, -1 for fluid): the sum of `wall_forces`
        over its particles."""
        f, ids = self.wall_forces()
        walls = ids < len(self.body_of)  # ids from there on are fluid particles an open boundary made
        return np.asarray(self.reduce(f[walls][self.body_of[ids[walls]] == body].sum(axis=0), "sum"), float)

    @property
    def particle_volume(self):
        """Volume of one particle at the reference density, m / rho0 = dp^dim [m^3; 2D: m^2 per metre]."""
        return self.mass / self.rho0

    @property
    def n_ids(self):
        """Number of particle ids so far (ids run from 0 to n_ids - 1): the case's, and those open boundaries
        gave the particles they made (`shoal.particle_buffers.BufferZones.next_id`, the same on every rank)."""
        return self.n_total if self.buffers is None else max(self.n_total, self.buffers.next_id)

    def owned_density(self):
        """(N,) float64 densities of the particles `owned_particles` gives."""
        return self.host(self.rho)[self.owned_rows()].astype(np.float64)

    def flow_sample(self, spec, prev):
        """One sample of a `FlowGauge` `spec` (`shoal.probes.flow.flow_measure` over the fluid).

        Returns (each fluid particle's coordinate along the axis by id, NaN for the other ids;
        the net number of particles that crossed the section since `prev`, None without `prev`;
        the instantaneous slab flow rate and wetted area)."""
        from .probes.flow import flow_measure

        pos, kinds, ids = self.owned_particles()
        axis = spec.axis
        period = 0.0
        if axis in self.periodic:
            period = self.params.per_len_x if axis == "x" else self.params.per_len_y
        new, crossed, q, area = flow_measure(pos, self.world_velocities(), self.owned_density(), kinds, ids, spec,
                                             self.dim, self.dp, self.mass, prev, self.n_ids, period)
        # each particle's coordinate comes from the one process that holds it (NaN on the others)
        new = self.reduce_array(np.where(np.isnan(new), -np.inf, new), "max")
        if crossed is not None:
            crossed = self.reduce(crossed, "sum")
        return np.where(np.isneginf(new), np.nan, new), crossed, self.reduce(q, "sum"), self.reduce(area, "sum")

    def shoreline(self, spec):
        """(zmax, x, y) [m] of a `RunupGauge` `spec` with `min_depth`: the wet shoreline's highest point
        (`shoal.probes.shoreline`; NaNs when no column is wet)."""
        from .probes import shoreline, shoreline_columns

        if self.dim == 2:
            ylim = (0.0, 0.0)
        elif spec.band is not None:
            ylim = (spec.y - 0.5 * spec.band, spec.y + 0.5 * spec.band)
        else:
            ylim = (float(self.grid.lo[1]), float(self.grid.hi[1]))
        pos, kinds, _ = self.owned_particles()
        counts, zmin, xland = shoreline_columns(pos, kinds, self.dim, spec, self.dp, ylim)
        # the columns over every process: counts added, lowest z and most landward x
        cols = tuple(self.reduce_array(a, op) for a, op in ((counts, "sum"), (zmin, "min"), (xland, "max")))
        return shoreline(*cols, self.dim, spec, self.dp, ylim)

    def highest_fluid(self, spec, tie=0.0):
        """(zmax, x, y) [m] of a `MaxZGauge` or `RunupGauge` `spec` over the fluid
        particles of every process (`shoal.probes.highest_fluid`; NaNs when its region holds none):
        zmax is the highest; (x, y) that of the run-up's most landward particle within `tie` below it
        (the max-z gauge: the first process's holding the highest particle)."""
        from .probes import RunupGauge, highest_fluid

        pos, kinds, _ = self.owned_particles()
        z = highest_fluid(pos, kinds, self.dim, spec, tie)[0]
        zmax = self.reduce(-np.inf if np.isnan(z) else z, "max")
        if zmax == -np.inf:
            return (float("nan"),) * 3
        xy = np.array(self.gather(highest_fluid(pos, kinds, self.dim, spec, tie, zmax=zmax)[1:]), float)
        here = np.flatnonzero(~np.isnan(xy[:, 0]))  # processes with a particle at (within tie of) zmax
        if isinstance(spec, RunupGauge):
            sign = 1.0 if spec.landward == "+x" else -1.0
            k = here[np.argmax(sign * xy[here, 0])]
        else:
            k = here[0]
        return zmax, float(xy[k, 0]), float(xy[k, 1])
