"""Open boundaries: planes where water enters or leaves the domain through a buffer of particles.

An `OpenBoundary` is a plane section of the domain with a **buffer** behind it: `layers` rows of particles
(at least the kernel support 2h deep) on the far side of the plane, outside the fluid domain, which the fluid
near the plane sees as its neighbours, so that its kernel sums are complete there. The buffer's particles
take part in every pair term as fluid, but their own state is imposed, not integrated
(`shoal.particle_buffers.BufferZones`):

* the **velocity**: `velocity` [m/s] along the normal (positive: into the domain), or a profile u(z)
  (`profile`), or the `discharge` spread uniformly over the section below the `level`; without any of them
  (an outlet) the velocity of the water at the particle's mirror image across the plane; or, with a `level`
  and ``velocity_mode = "riemann"`` (a reservoir, a tide, a tailwater), the velocity that holds the level:
  from the shallow-water Riemann invariant carried out of the domain (`riemann_speed`);
* the **density**: hydrostatic below the `level` (``density = "hydrostatic"``, p = rho0 g (level - z)
  through the equation of state; the default with a level), the density of the water at the particle's
  mirror image inside (``"extrapolated"``, the default without a level), or that of a fixed `pressure`
  (``"fixed"``).

The velocity, the discharge and the level may each be a `shoal.time_series.TimeSeries` (a hydrograph, a
tide): a buffer whose level changes is filled to the level of the moment. With ``level_mode = "water"`` the
level follows the water's depth next to the plane. What is taken from the water at the mirror image is its
Shepard average there, or with ``extrapolation = "first_order"`` its value and gradient there carried back
to the particle (Tafuni et al. 2018).

Each step (as DualSPHysics's inlet/outlet zones, Tafuni et al. 2018): a buffer particle that crosses the plane
into the domain becomes fluid and a new buffer particle is created `layers` dp behind it (the buffer refills
from its back); a fluid particle that crosses the plane out of the domain becomes a buffer particle; a
buffer particle that leaves the buffer's far end is removed. The same boundary is an inlet where its velocity
points in and an outlet where the water leaves. New particles get new ids (never reused); the arrays grow
without a restart (`shoal.particle_store.ParticleStore`).

In a case file::

    [[open_boundaries]]
    name = "inlet"
    point = [0.0, 0.0, 0.0]        # on the plane
    normal = [1.0, 0.0, 0.0]       # into the domain (along x or y)
    lo = [0.0, 0.0, 0.0]           # the section: the plane's part between lo and hi
    hi = [0.0, 0.0, 0.3]           #   (their components along the normal are ignored)
    velocity = 0.2                 # m/s into the domain
    level = 0.2                    # the water's surface there [m]: the buffer is filled below it

References
----------
J. J. Stoker, *Water Waves*, Interscience (1957), ch. 10 (the characteristics of shallow-water flow).
G. K. Verboom, A. Slob, "Weakly-reflective boundary conditions for two-dimensional shallow water flow
problems", Adv. Water Resources 7 (1984) 192-197 (boundaries of given level through the outgoing invariant).
A. Tafuni, J. M. Dominguez, R. Vacondio, A. J. C. Crespo, "A versatile algorithm for the treatment of open
boundary conditions in smoothed particle hydrodynamics GPU models", Comput. Methods Appl. Mech. Engrg. 342
(2018) 604-624.
"""

from __future__ import annotations

import math
from typing import Annotated, Literal

import numpy as np
from pydantic import Field, model_validator

from .geometry.shapes import Real, Spec, Vec3
from .time_series import TimeSeries, value_at, value_bounds


class VelocityProfile(Spec):
    """u(z): the velocity along the boundary's normal [m/s] at heights `z` [m], linear between them and held
    beyond the ends (a log or power law tabulated, a measured profile)."""

    z: Annotated[list[Real], Field(min_length=2)]
    u: Annotated[list[Real], Field(min_length=2)]

    @model_validator(mode="after")
    def _table(self):
        if len(self.z) != len(self.u):
            raise ValueError(f"z has {len(self.z)} values and u {len(self.u)}: give one u per z")
        if any(b <= a for a, b in zip(self.z, self.z[1:])):
            raise ValueError("z must increase from one value to the next")
        return self


class OpenBoundary(Spec):
    """An inflow or outflow plane with its buffer (module docstring).

    Attributes
    ----------
    name : str
    point : 3 floats
        A point of the plane [m]; the plane must lie on the particle lattice (lattice_origin + k dp along the
        normal), so that the buffer's lattice continues the fluid's.
    normal : 3 floats
        Into the domain: along x or y (2D: x).
    lo, hi : 3 floats
        The section: the part of the plane between them (the components along the normal are ignored) [m].
    layers : int, optional
        Rows of buffer particles; default: enough to cover the kernel support 2h.
    velocity : float or TimeSeries, optional
        Speed along the normal [m/s], positive into the domain; a `shoal.time_series.TimeSeries` for one that
        changes in time (a ramp, a hydrograph).
    profile : VelocityProfile, optional
        u(z) along the normal instead of one speed.
    discharge : float or TimeSeries, optional
        Q [m^3/s; 2D: m^2/s] into the domain, spread uniformly over the wet section (below `level`).
    level : float or TimeSeries, optional
        Height of the water's surface at the boundary [m]: the buffer holds particles below it and its density
        is hydrostatic from it. Without it the whole section is wet (a submerged boundary). A level that changes
        in time (a tide) fills the buffer to the level of the moment: a row is added where the level stands a
        dp above the buffer's top row, the particles more than dp/2 above it are removed.
    density : {"hydrostatic", "extrapolated", "fixed"}
        Default: "hydrostatic" with a level, "fixed" with a `pressure`, else "extrapolated".
    pressure : float, optional
        The buffer's pressure [Pa] with ``density = "fixed"`` (e.g. 0 at the outlet of a pressure-driven
        channel).
    velocity_mode : {"extrapolated", "riemann"}, optional
        Where no velocity is imposed: the water's at the mirror image (``"extrapolated"``, the default), or
        the speed that holds the `level` (``"riemann"``, `riemann_speed`; needs a level; the section's
        bottom is the bed).
    relaxation_time : float
        With ``velocity_mode = "riemann"``: the time over which the running mean of the water's speed at the
        plane is taken [s] (longer than the waves it should let out).
    level_mode : {"imposed", "water"}
        ``"imposed"`` (the default): the buffer is filled to `level` (a number or a time series).
        ``"water"``: `level` is the starting level, then the buffer follows the water inside: at every step
        its level is the bottom of the section plus the water's depth next to the plane (the particles'
        volumes in a band three kernel supports long, the band of ``velocity_mode = "riemann"``), capped at
        the section's top, and the buffer is filled to it (rows added and removed) with the hydrostatic
        density from it, as DualSPHysics's inlet/outlet with its surface calculated from the fluid. For an
        outlet where the water's depth changes (waves, a surge or a flood leaving the domain); not with a
        discharge (spread over a depth that would follow the flow it sets) or ``velocity_mode = "riemann"``
        (which holds its level).
    extrapolation : {"shepard", "first_order"}
        How what is taken from the water (the velocity where none is imposed, an extrapolated density) is
        carried to a buffer particle from the water around its mirror image: the Shepard average at the mirror
        image (zeroth order; the default), or to first order, exact for a linear field (the corrected-kernel
        system of Tafuni et al. 2018, as DualSPHysics), where the mirror image's support determines it (else
        the Shepard average). First order carries the gradient along the normal over the distance to the
        mirror image, up to twice the buffer's depth, and with it the gradient's particle noise: in the open
        Poiseuille channel (D = 16 dp, `tests/test_open_boundary.py`) the profile at three quarters of the
        length is 3.7 % of u_max off with it and 2.7 % with the Shepard average.
    """

    name: Annotated[str, Field(min_length=1, pattern=r"^[A-Za-z0-9_.\-]+$")] = "open"
    point: Vec3
    normal: Vec3
    lo: Vec3
    hi: Vec3
    layers: Annotated[int, Field(ge=1, le=20, strict=True)] | None = None
    velocity: Real | TimeSeries | None = None
    profile: VelocityProfile | None = None
    discharge: Real | TimeSeries | None = None
    level: Real | TimeSeries | None = None
    density: Literal["hydrostatic", "extrapolated", "fixed"] | None = None
    pressure: Real | None = None
    velocity_mode: Literal["extrapolated", "riemann"] | None = None
    relaxation_time: Annotated[float, Field(gt=0, allow_inf_nan=False)] = 3.0
    level_mode: Literal["imposed", "water"] = "imposed"
    extrapolation: Literal["shepard", "first_order"] = "shepard"

    @model_validator(mode="after")
    def _consistent(self):
        n = np.asarray(self.normal, float)
        axes = [a for a in range(3) if n[a] != 0.0]
        if len(axes) != 1 or axes[0] == 2:
            raise ValueError(f"normal = {list(self.normal)}: an open boundary's normal runs along x or y (e.g. "
                             "[1, 0, 0] for an inlet at the upstream end of a flume along x)")
        given = [k for k in ("velocity", "profile", "discharge") if getattr(self, k) is not None]
        if len(given) > 1:
            raise ValueError(f"{' and '.join(given)} given: impose one of velocity, profile or discharge (or none, "
                             "for an outlet)")
        if self.velocity_mode is not None and given:
            raise ValueError(f'velocity_mode = "{self.velocity_mode}" with {given[0]} given: the velocity is either '
                             'imposed (velocity, profile or discharge) or not (velocity_mode "extrapolated" or '
                             '"riemann")')
        if self.velocity_mode == "riemann" and self.level is None:
            raise ValueError('velocity_mode = "riemann" holds a level: give the level of the water at the boundary '
                             '(level = ...)')
        if (self.velocity_mode == "riemann" and not isinstance(self.level, TimeSeries)
                and self.level <= min(self.lo[2], self.hi[2])):
            raise ValueError(f'velocity_mode = "riemann": level = {self.level:g} m is not above the bottom of the '
                             f'section ({min(self.lo[2], self.hi[2]):g} m, the bed there)')
        if self.level_mode == "water":
            if self.level is None or isinstance(self.level, TimeSeries):
                raise ValueError('level_mode = "water" follows the water from a starting level: give level = a '
                                 'number (the level at the start)')
            if self.discharge is not None or self.velocity_mode == "riemann":
                what = "a discharge" if self.discharge is not None else 'velocity_mode = "riemann"'
                raise ValueError(f'level_mode = "water" with {what}: a buffer that follows the water takes an '
                                 'imposed velocity or profile, or the water\'s (an outlet)')
        if self.discharge is not None and self.level is None:
            raise ValueError("a discharge needs the level of the water at the boundary (level = ...), over "
                             "which it is spread")
        if self.density == "hydrostatic" and self.level is None:
            raise ValueError('density = "hydrostatic" needs the level of the water at the boundary (level = ...)')
        if self.density == "fixed" and self.pressure is None:
            raise ValueError('density = "fixed" needs the pressure to hold (pressure = ... Pa)')
        if self.pressure is not None and self.density not in (None, "fixed"):
            raise ValueError(f'pressure = {self.pressure:g} Pa with density = "{self.density}": a pressure is held '
                             'with density = "fixed" (or no density given)')
        return self

    # ------------------------------------------------------------- geometry
    @property
    def axis(self):
        """Index of the normal's axis (0: x, 1: y)."""
        return int(np.flatnonzero(np.asarray(self.normal, float))[0])

    @property
    def sign(self):
        """+1 when the normal points along +axis, -1 along -axis."""
        return 1.0 if self.normal[self.axis] > 0 else -1.0

    @property
    def density_mode(self):
        """The density treatment: `density`, or its default."""
        if self.density is not None:
            return self.density
        if self.pressure is not None:
            return "fixed"
        return "hydrostatic" if self.level is not None else "extrapolated"

    @property
    def follows_water(self):
        """True when the buffer's level follows the water inside (``level_mode = "water"``)."""
        return self.level_mode == "water"

    @property
    def holds_level(self):
        """True when the velocity is the one that holds the level (``velocity_mode = "riemann"``)."""
        return self.velocity_mode == "riemann"

    @property
    def varies(self):
        """True when the velocity, the discharge or the level is a `TimeSeries`."""
        return any(isinstance(v, TimeSeries) for v in (self.velocity, self.discharge, self.level))

    def level_at(self, t):
        """The level at time t [m], or None."""
        return value_at(self.level, t)

    def level_bounds(self, t0, t1):
        """(lowest, highest) level over [t0, t1] [s], or None without a level."""
        return None if self.level is None else value_bounds(self.level, t0, t1)

    def inflow_bounds(self, t0, t1):
        """(smallest, largest) imposed velocity or discharge over [t0, t1], or None (a profile or none)."""
        v = self.velocity if self.velocity is not None else self.discharge
        return None if v is None else value_bounds(v, t0, t1)

    def sampled(self, t0, t1):
        """The boundary with each series given as a function replaced by its table over [t0, t1]
        (`shoal.time_series.TimeSeries.sampled`)."""
        update = {k: v.sampled(t0, t1) for k in ("velocity", "discharge", "level")
                  if isinstance(v := getattr(self, k), TimeSeries) and v.function is not None}
        return self.model_copy(update=update) if update else self

    @property
    def bed(self):
        """The bottom of the section [m], the bed under a boundary that holds a level."""
        return float(min(self.lo[2], self.hi[2]))

    def section_width(self, dim):
        """The section's horizontal width [m] (1 in 2D: per metre of width)."""
        if dim == 2:
            return 1.0
        t = 1 - self.axis
        return float(abs(self.hi[t] - self.lo[t]))

    def buffer_layers(self, support, dp):
        """`layers`, or the rows that cover the kernel support `support` [m] (at least 2)."""
        return self.layers if self.layers is not None else max(int(math.ceil(support / dp - 1e-9)), 2)

    def section_box(self, dim):
        """(lo, hi) of the section in world coordinates, the normal's components set to -inf, inf, and in 2D
        y to -inf, inf (3 floats each)."""
        lo = np.minimum(self.lo, self.hi).astype(float)
        hi = np.maximum(self.lo, self.hi).astype(float)
        lo[self.axis], hi[self.axis] = -math.inf, math.inf
        if dim == 2:
            lo[1], hi[1] = -math.inf, math.inf
        return lo, hi

    def wet_top(self, dim, t=0.0):
        """The top of the wet section at time t [m]: the level, or the section's top."""
        top = max(self.lo[2], self.hi[2])
        return min(top, self.level_at(t)) if self.level is not None else top

    def speed(self, z, dim, t=0.0):
        """The imposed speed along the normal [m/s] at heights `z` (array) at time t [s], or None (not
        imposed)."""
        z = np.asarray(z, float)
        if self.velocity is not None:
            return np.full(z.shape, float(value_at(self.velocity, t)))
        if self.profile is not None:
            return np.interp(z, self.profile.z, self.profile.u)
        if self.discharge is not None:
            return np.full(z.shape, float(value_at(self.discharge, t)) / self.wet_area(dim, t))
        return None

    def wet_area(self, dim, t=0.0):
        """Area of the section below the level at time t [m^2; 2D: m]."""
        lo, hi = np.minimum(self.lo, self.hi), np.maximum(self.lo, self.hi)
        height = max(self.wet_top(dim, t) - lo[2], 0.0)
        if dim == 2:
            return height
        t = 1 - self.axis  # the horizontal tangent
        return height * (hi[t] - lo[t])

    def buffer_lattice(self, dim, dp, origin, support, t=0.0):
        """The buffer's particles at time t: lattice nodes origin + (i + 1/2) dp behind the plane, `layers`
        rows deep, inside the section and below the level.

        Returns
        -------
        (M, 3) float64 array
            World positions [m] (y = 0 in 2D).

        Raises
        ------
        ValueError
            The plane is not on the lattice, or the section holds no lattice node.
        """
        a, s = self.axis, self.sign
        rows = self.buffer_layers(support, dp)
        k = (self.point[a] - origin[a]) / dp
        if abs(k - round(k)) > 1e-6:
            raise ValueError(f"open boundary {self.name!r}: its plane {'xy'[a]} = {self.point[a]:g} m is not on the "
                             f"particle lattice (lattice_origin + k dp, dp = {dp:g} m); move it to "
                             f"{origin[a] + round(k) * dp:.6g} m")
        x0 = origin[a] + round(k) * dp
        normal_coords = x0 - s * (np.arange(rows) + 0.5) * dp
        lo, hi = np.minimum(self.lo, self.hi), np.maximum(self.lo, self.hi)
        axes = [0, 1, 2] if dim == 3 else [0, 2]
        coords = []
        for b in axes:
            if b == a:
                coords.append(normal_coords)
                continue
            top = self.wet_top(dim, t) if b == 2 else hi[b]
            i0 = math.ceil((lo[b] - origin[b]) / dp - 0.5 - 1e-9)
            i1 = math.floor((top - origin[b]) / dp - 0.5 - 1e-9)
            coords.append(origin[b] + (np.arange(i0, i1 + 1) + 0.5) * dp)
        grids = np.meshgrid(*coords, indexing="ij")
        pts = np.zeros((grids[0].size, 3))
        for g, b in zip(grids, axes):
            pts[:, b] = g.ravel()
        if not len(pts):
            raise ValueError(f"open boundary {self.name!r}: its section between lo and hi (below the level) holds "
                             f"no particle of the lattice at dp = {dp:g} m")
        return pts


def riemann_speed(level_depth, depth, speed, mean_speed, g):
    """The speed along the normal [m/s] at a boundary of subcritical flow that holds the mean depth
    `level_depth` and lets waves out.

    Of the two shallow-water characteristics dx/dt = u -+ c (c = sqrt(g d), u along the normal, into the
    domain), the one of u - c leaves the domain through the boundary, carrying the invariant R- = u_i - 2 c_i of
    the water inside (depth d_i = `depth`, speed u_i = `speed`); the boundary gives the one that enters,
    R+ = U + 2 c_b, with c_b = sqrt(g d_b) of the level and U the running mean of u_i (`mean_speed`): a wave
    arriving at the plane changes R- alone and leaves without reflection, while the mean flow keeps the depth
    d_b at the plane. The boundary's speed is the state of the two invariants:

        u_b = (R+ + R-) / 2 = (U + u_i) / 2 + c_b - c_i

    (Stoker 1957, ch. 10; Verboom & Slob 1984). Water inside lower than the level draws more inflow, higher
    less; in a steady flow u_i = U and d_i = d_b.

    Parameters
    ----------
    level_depth : float
        d_b, the depth the boundary holds [m] (level - bed).
    depth, speed : float
        d_i [m] and u_i [m/s] of the water next to the plane.
    mean_speed : float
        U [m/s], the running mean of u_i.
    g : float
        |g| [m/s^2].
    """
    return 0.5 * (mean_speed + speed) + math.sqrt(g * max(level_depth, 0.0)) - math.sqrt(g * max(depth, 0.0))


def plane_coordinate(zone, dp, origin):
    """The plane's coordinate along its normal's axis, snapped to the lattice [m]."""
    a = zone.axis
    return origin[a] + round((zone.point[a] - origin[a]) / dp) * dp


__all__ = ["OpenBoundary", "VelocityProfile", "plane_coordinate", "riemann_speed"]
