"""A Case: everything that defines a simulation, as plain data.

A `Case` holds the domain, the fluid constants, the SPH options, the solids
(walls, bed, obstacles: shapes plus a boundary method), the fluid regions,
the motions and the run controls. Its particles are generated from the
geometry on demand (:meth:`Case.particles`). The Python API and TOML case
files (:mod:`shoal.casefile`) build the same objects: every TOML table maps
one-to-one onto a constructor here or in :mod:`shoal.geometry.shapes`, and
every value is validated (unknown keys are errors)::

    import shoal
    from shoal.geometry import Box, Tank

    case = shoal.Case(
        name="my-tank", dim=2, dp=0.01, end_time=2.0,
        fluid=shoal.Fluid(depth=0.5, surface_level=0.5),
        solids=[shoal.Solid(name="tank", shape=Tank(lo=(0, 0, 0), hi=(1, 0, 0.8)))],
        fluids=[shoal.FluidRegion(shape=Box(lo=(0, 0, 0), hi=(1, 0, 0.5)))],
    )

Built-in cases (:mod:`shoal.cases`) are functions returning a Case.
"""

from __future__ import annotations

import math
from typing import Annotated, Any, Literal

import numpy as np
from pydantic import AfterValidator, BaseModel, BeforeValidator, ConfigDict, Field, PrivateAttr, StrictBool, model_validator

from .errors import InputError
from .floating import FloatingBody, MooringLines
from .joints import Joint
from .open_boundary import OpenBoundary
from .geometry.generate import FluidInput, Particles, SolidInput, generate, support_layers
from .geometry.shapes import AnyShape, PositiveReal, Real, Spec, UnitVec3, Vec3
from .motions import AnyMotion
from .probes import AnyProbe
from .relaxation import RelaxationZone, resolve_zone
from .options import SPHOptions
from .physics.constants import smoothing_length, speed_of_sound
from .physics.spec import FLUID

def _exact_int(name, allowed):
    def check(v):
        if isinstance(v, bool) or not isinstance(v, int):
            shown = ("true" if v else "false") if isinstance(v, bool) else repr(v)
            raise ValueError(f"{name} = {shown} must be the integer {allowed}")
        return v
    return check


Options = Annotated[SPHOptions, BeforeValidator(SPHOptions.from_table)]


def _plain_record(d):
    """`Case.parameters` holds plain values only (what a TOML case file can
    hold: numbers, strings, booleans, arrays, tables); None is allowed at the
    top level (left out when written)."""
    if not isinstance(d, dict):
        return d

    def plain(v, where, depth=0):
        if isinstance(v, np.generic):
            v = v.item()
        if isinstance(v, (bool, int, float, str)):
            return v
        if depth >= 100 and isinstance(v, (list, tuple, dict)):  # deeper, the case could not be written back
            raise ValueError(f"{where[:40]}...: arrays or tables nested more than 100 deep (a parameter is a "
                             "number, string, boolean, array or table)")
        if isinstance(v, (list, tuple)):
            return [plain(x, f"{where}[{i}]", depth + 1) for i, x in enumerate(v)]
        if isinstance(v, dict) and all(isinstance(k, str) for k in v):
            return {k: plain(x, f"{where}.{_shown_key(k)}", depth + 1) for k, x in v.items()}
        shown = "nothing" if v is None else repr(v)[:60]
        raise ValueError(f"{where} = {shown}: a parameter is a number, string, boolean, array or table")

    return {k: (None if v is None else plain(v, _shown_key(str(k)))) for k, v in d.items()}


def _shown_key(k):
    """A key as an error message shows it: as written, or quoted with its escapes when it holds characters
    that are not printable (a line break would split the one-line message)."""
    return k if k.isprintable() else repr(k)


class Domain(Spec):
    """The computational box [lo, hi] [m]: particles leaving it are removed
    from the computation (and counted). y is ignored in 2D.

    `periodic` names the periodic axes ("x"; "y" in 3D): along them the box
    is one period (a whole number of particle spacings), the neighbour
    search wraps round, and a particle leaving through one face re-enters
    through the other.
    """

    lo: Vec3
    hi: Vec3
    periodic: list[Literal["x", "y"]] = []

    @model_validator(mode="after")
    def _order(self):
        for a, (l, h) in zip("xyz", zip(self.lo, self.hi)):
            if not h > l and a != "y":
                raise ValueError(f"hi.{a} = {h} must be above lo.{a} = {l}")
        return self


class Fluid(Spec):
    """The fluid's constants.

    Parameters
    ----------
    rho0 : float
        Reference density [kg/m^3].
    gravity : 3 floats
        Gravity [m/s^2] (x, y, z); z is up.
    depth : float, optional
        Reference depth H [m]: the speed of sound is ``c0 = coef_sound *
        sqrt(|g| H)`` (the still-water depth for waves and bores, the column
        height for a dam break).
    u_max : float, optional
        Largest expected flow speed [m/s]; when given, c0 = coef_sound * u_max
        instead (e.g. sqrt(g H) + U for an inflow at speed U).
    surface_level : float, optional
        Still free-surface level [m]: fluid starts with the hydrostatic
        density ``rho0 (1 + rho0 |g| (surface_level - z) / B)^(1/7)``.
    """

    rho0: PositiveReal = 1000.0
    gravity: Vec3 = (0.0, 0.0, -9.81)
    depth: PositiveReal | None = None
    u_max: PositiveReal | None = None
    surface_level: Real | None = None


FLOATING_SHAPES = ("box", "cylinder", "prism", "mesh")
"""The shapes a floating body may have: closed ones, whose inside is its mass."""


class Solid(Spec):
    """A solid body: a shape whose surface layers become boundary particles.

    Parameters
    ----------
    shape : Shape
        Its region (see :mod:`shoal.geometry.shapes`).
    name : str
        A name for logs, plots and motions.
    boundary : {"dynamic", "repulsive"}
        Dynamic boundary particles (Crespo et al. 2007; several layers obeying
        the continuity equation, fixed in place) or the single-layer repulsive
        particles of Monaghan & Kajtar (2009) at spacing dp/2.
    layers : int, optional
        Layers of dynamic particles; default: as many as the kernel support
        2h reaches (every wall particle a fluid particle can see).
    motion : str, optional
        Name of a motion in the case's `motions` that moves this body.
    floating : shoal.floating.FloatingBody, optional
        The body floats: the water moves it (`shoal.body_coupling`), with this mass, these constraints
        and loads. A closed shape (box, cylinder, prism, mesh) with dynamic particles; not with `motion`.
    fit_surface : bool
        For a bed (`Slope`, `Bathymetry`) with dynamic particles: put its wall
        particles on layers parallel to its surface, at normal depths
        (k + 1/2) dp, instead of on the lattice's staircase, and lift the
        fluid's lowest particles to dp/2 above it
        (:mod:`shoal.geometry.surface_fit`); columns steeper than 45 degrees
        stay on the lattice. For thin water on a slope: run-up, swash.
    """

    shape: AnyShape
    name: str = ""
    boundary: Literal["dynamic", "repulsive"] = "dynamic"
    layers: Annotated[int, Field(ge=1, strict=True)] | None = None
    motion: str | None = None
    floating: FloatingBody | None = None
    fit_surface: StrictBool = False

    @model_validator(mode="after")
    def _a_body_that_floats(self):
        if self.floating is None:
            return self
        if self.motion is not None:
            raise ValueError(f"motion = {self.motion!r} and floating both given: a floating body is moved by the "
                             "water; give one of the two")
        if self.shape.type not in FLOATING_SHAPES:
            raise ValueError(f"a {self.shape.type} cannot float: a floating body is a closed shape "
                             f"({', '.join(FLOATING_SHAPES)})")
        if self.boundary != "dynamic":
            raise ValueError("a floating body has dynamic boundary particles (boundary = \"dynamic\")")
        return self

    @model_validator(mode="after")
    def _fit_surface_on_a_bed(self):
        if self.fit_surface and (self.shape.type not in ("slope", "bathymetry") or self.boundary != "dynamic"):
            raise ValueError(f"fit_surface = true is for a bed with dynamic particles (shape slope or "
                             f"bathymetry, boundary dynamic); this solid is a {self.shape.type} with "
                             f"{self.boundary} particles")
        return self


class FluidRegion(Spec):
    """Fluid filling a shape (where no solid is), with an initial velocity [m/s]."""

    shape: AnyShape
    velocity: Vec3 = (0.0, 0.0, 0.0)


class SymmetryPlane(Spec):
    """A symmetry plane ("domain separation" of the tidal-bore paper, section
    2.4): the flow is mirrored across the plane through ``point`` with unit
    `normal` (pointing into the fluid), so half a symmetric flume stands for
    the whole one.

    Every particle within the kernel support 2h of the plane is mirrored
    across it (same density and pressure, opposite normal velocity) as a
    neighbour of the particles on this side, at every evaluation (mirror
    images in the neighbour search, no extra particles); a particle that
    crosses the plane comes back as its image. Supported: planes y = const
    in 3D (normal [0, 1, 0] or [0, -1, 0]), the case of the half-width flume.
    """

    point: Vec3
    normal: Vec3


class WallPlane(Spec):
    """A wall without particles (GPUSPH's planes): the plane through ``point``
    with `normal` pointing into the fluid pushes fluid away with the force of
    a Monaghan-Kajtar particle wall in the continuum limit
    (`shoal.physics.planes`); free-slip. Fluid behind it is not generated."""

    point: Vec3
    normal: UnitVec3


class DampingZone(Spec):
    """A wave-absorbing zone (a sponge layer, as DualSPHysics's damping):
    from the plane through `start` to the plane through `end` (normal to
    end - start), a fluid particle a fraction f of the way in has its
    velocity multiplied by max(1 - dt rate f^2, 0) every step, so waves
    entering it die out without reflecting from a wall. Typical: one or two
    wavelengths long, rate 10 1/s (raise it if waves still reflect).
    """

    start: Vec3
    end: Vec3
    rate: PositiveReal = 10.0

    @model_validator(mode="after")
    def _length(self):
        if not np.linalg.norm(np.subtract(self.end, self.start)) > 0:
            raise ValueError("end must differ from start (the zone has zero length)")
        return self


class Output(Spec):
    """What a run writes: particle snapshots (VTU + PVD) every `interval` s."""

    interval: PositiveReal = 0.05


NonNegativeReal = Annotated[float, Field(ge=0, allow_inf_nan=False, strict=True)]


class Checkpointing(Spec):
    """When a run writes checkpoints (``ckpt_NNNNNN.h5``, the whole state, for
    ``shoal run --resume``; see `shoal.simulation.checkpoint`).

    A checkpoint is written every `interval` s of simulated time and every
    `wall_interval` s of wall-clock time (whichever comes first; 0 turns
    either off), when the run stops on SIGINT/SIGTERM, and at the end of the
    run. Checkpoint times never shorten a time step, so a run gives the same
    result with or without them.

    Attributes
    ----------
    interval : float
        Simulated time between checkpoints [s]; 0 (default): none on
        simulated time.
    wall_interval : float
        Wall-clock time between checkpoints [s]; default 900 (15 minutes, as
        GROMACS's default): a crash or a killed job loses at most that much
        computing. 0: none on wall-clock time.
    keep : int
        How many checkpoints to keep (the newest; default 2, so a file
        damaged by a crash while it was written still leaves an older one).
    """

    interval: NonNegativeReal = 0.0
    wall_interval: NonNegativeReal = 900.0
    keep: Annotated[int, Field(ge=1, strict=True)] = 2


def _short_name(name):
    """A case name is part of every output file's name: at most 100 characters."""
    if len(name) > 100:
        raise ValueError(f"{len(name)} characters: a case name has at most 100 (it starts every output file's name)")
    return name


class Case(BaseModel):
    """A simulation set-up (see the module docstring for an example).

    Parameters
    ----------
    name : str
        Case name (output file names): letters, digits, _ . - (not only dots), at most 100 characters.
    dim : {2, 3}
        2D runs use the x-z plane.
    dp : float
        Particle spacing [m].
    end_time : float
        Simulated time [s].
    fluid : Fluid
    options : SPHOptions
    solids : list of Solid
    fluids : list of FluidRegion
    motions : list of motions (see :mod:`shoal.motions`)
    symmetry_planes : list of SymmetryPlane
    damping : list of DampingZone
    relaxation : list of RelaxationZone
        Relaxation zones (`shoal.relaxation`): the velocity relaxed toward still water (an absorber), a
        linear wave or the sea of an irregular or focused motion (a generator).
    planes : list of WallPlane
    moorings : list of MooringLines
        Mooring lines (MoorDyn v2) holding the floating solids (`shoal.floating.MooringLines`).
    joints : list of Joint
        Pins and hinges between two floating solids (`shoal.joints.Joint`).
    open_boundaries : list of OpenBoundary
        Inflow and outflow planes with their buffers of particles (`shoal.open_boundary`).
    probes : list of PointProbes / WaveGauge (`shoal.probes`)
    domain : Domain, optional
        Default: the particles' bounding box grown by the kernel support 2h
        on every side and by the fluid's height above.
    lattice_origin : 3 floats
        Particles sit at lattice_origin + (i + 1/2) dp.
    output : Output
    checkpoint : Checkpointing
        When checkpoints are written (and how many kept).
    max_escaped_fraction : float
        The run stops (exit status 3) when more than this fraction of the
        fluid particles has left the domain; default 1: never (DualSPHysics's
        PartsOutMax, same meaning and default). Escaped particles are listed
        in ``escaped.csv`` either way.
    description : str
        What the case is and what it is compared with.
    parameters : dict
        The parameters a built-in case function was called with (a record).
    """

    model_config = ConfigDict(extra="forbid", validate_assignment=True, arbitrary_types_allowed=False)

    name: Annotated[str, Field(min_length=1, pattern=r"^[A-Za-z0-9_.\-]*[A-Za-z0-9_\-][A-Za-z0-9_.\-]*$", strict=True),
                    AfterValidator(_short_name)]
    dim: Annotated[Literal[2, 3], BeforeValidator(_exact_int("dim", "2 or 3"))]
    dp: PositiveReal
    end_time: PositiveReal = 1.0
    description: str = ""
    fluid: Fluid = Fluid()
    options: Options = SPHOptions()
    solids: list[Solid] = []
    fluids: Annotated[list[FluidRegion], Field(min_length=1)]
    motions: list[AnyMotion] = []
    symmetry_planes: list[SymmetryPlane] = []
    damping: list[DampingZone] = []
    relaxation: list[RelaxationZone] = []
    planes: list[WallPlane] = []
    moorings: list[MooringLines] = []
    joints: list[Joint] = []
    open_boundaries: list[OpenBoundary] = []
    probes: list[AnyProbe] = []
    domain: Domain | None = None
    lattice_origin: Vec3 = (0.0, 0.0, 0.0)
    output: Output = Output()
    checkpoint: Checkpointing = Checkpointing()
    max_escaped_fraction: Annotated[float, Field(gt=0, le=1, allow_inf_nan=False, strict=True)] = 1.0
    parameters: Annotated[dict[str, Any], BeforeValidator(_plain_record)] = {}

    _particles: Particles | None = PrivateAttr(default=None)
    _key: Any = PrivateAttr(default=None)

    @model_validator(mode="after")
    def _links(self):
        names = [m.name for m in self.motions]
        dup = {n for n in names if names.count(n) > 1}
        if dup:
            raise ValueError(f"motion names must be unique; repeated: {', '.join(sorted(dup))}")
        floating = [s.name or f"solid{i}" for i, s in enumerate(self.solids) if s.floating is not None]
        twice = sorted({n for n in floating if floating.count(n) > 1})
        if twice:
            raise ValueError(f"floating bodies named {', '.join(twice)} more than once: each writes its own "
                             "file; give each a name of its own")
        for i, m in enumerate(self.moorings):
            for k, f in enumerate(m.fairleads):
                if f.body not in floating:
                    raise ValueError(f"moorings[{i}].fairleads[{k}].body = {f.body!r} is no floating solid "
                                     f"(floating: {', '.join(map(repr, floating)) or 'none'})")
            if self.dim == 2 and m.width is None:
                raise ValueError(f"moorings[{i}]: a 2D case's bodies are per metre of width and MoorDyn's lines "
                                 "whole: give width, the flume's width [m] the lines hold")
            if self.dim == 3 and m.width is not None:
                raise ValueError(f"moorings[{i}].width = {m.width:g}: only for 2D cases (per metre of width)")
        for i, j in enumerate(self.joints):
            for k, name in enumerate(j.bodies):
                if name not in floating:
                    raise ValueError(f"joints[{i}].bodies[{k}] = {name!r} is no floating solid "
                                     f"(floating: {', '.join(map(repr, floating)) or 'none'})")
            if self.dim == 2 and j.axis is not None and not (j.axis[0] == 0.0 and j.axis[2] == 0.0):
                raise ValueError(f"joints[{i}].axis = {list(j.axis)}: a 2D joint turns about y; leave the axis out")
        mnames = [m.name for m in self.moorings]
        if len(set(mnames)) != len(mnames):
            raise ValueError(f"moorings named {sorted({n for n in mnames if mnames.count(n) > 1})} more than once: "
                             "each writes its own files; give each a name of its own")
        for i, s in enumerate(self.solids):
            if s.motion is not None and s.motion not in names:
                allowed = ", ".join(names) if names else "none defined"
                raise ValueError(f"solids[{i}].motion = {s.motion!r} names no motion (motions: {allowed})")
        for i, m in enumerate(self.motions):
            axis = m.rotation_axis
            if self.dim == 2 and axis is not None and not (axis[0] == 0.0 and axis[2] == 0.0):
                raise ValueError(f"motions[{i}] ({m.name!r}) rotates about the axis {[float(a) for a in axis]}: a 2D "
                                 "case (the x-z plane) rotates only about the y axis; give axis = [0, 1, 0] (a "
                                 "flap: a direction along x)")
        if self.domain is not None and "y" in self.domain.periodic and self.dim == 2:
            raise ValueError("domain.periodic = ['y'] is not allowed in 2D (the x-z plane); use ['x']")
        if self.fluid.depth is None and self.fluid.u_max is None:
            raise ValueError("fluid needs a depth (m) or a u_max (m/s) to set the speed of sound")
        g = float(np.linalg.norm(self.fluid.gravity))  # as the Model computes it (inf if it overflows)
        c0 = speed_of_sound(self.options.coef_sound, self.fluid.gravity, self.fluid.depth, self.fluid.u_max)
        if not (0.0 < c0 < math.inf):
            if self.fluid.u_max is None and g == 0.0:
                raise ValueError(f"fluid.gravity = {list(self.fluid.gravity)}: without gravity the speed of sound "
                                 "c0 = coef_sound sqrt(|g| depth) is 0; give fluid.u_max, the largest expected "
                                 "speed [m/s]")
            raise ValueError(f"the speed of sound c0 = coef_sound x {'u_max' if self.fluid.u_max else 'sqrt(|g| depth)'}"
                             f" = {c0:g} m/s must be a positive finite number: check fluid.gravity, fluid.depth, "
                             "fluid.u_max and options.coef_sound")
        self._check_scales(c0)
        self._check_times(c0)
        if (self.planes or any(s.boundary == "repulsive" for s in self.solids)) and \
                (self.fluid.depth is None or g == 0.0):
            raise ValueError("repulsive boundaries and wall planes push with K = |g| depth (Monaghan & Kajtar "
                             "2009): they need gravity and a fluid.depth")
        for a in (self.domain.periodic if self.domain is not None else []):
            k = "xyz".index(a)
            length = self.domain.hi[k] - self.domain.lo[k]
            if abs(length / self.dp - round(length / self.dp)) > 1e-6:
                raise ValueError(f"domain.periodic = {self.domain.periodic}: the domain is {length:.6g} m long in {a}, "
                                 f"not a whole number of particle spacings dp = {self.dp:g} m (the lattice would not "
                                 f"join up across the period); make it {max(1, round(length / self.dp)) * self.dp:.6g} m")
        names = [ob.name for ob in self.open_boundaries]
        for i, ob in enumerate(self.open_boundaries):
            if self.dim == 2 and ob.axis == 1:
                raise ValueError(f"open_boundaries[{i}] ({ob.name!r}): normal = {list(ob.normal)} points along y, which a "
                                 "2D case (the x-z plane) does not have; use [1, 0, 0] or [-1, 0, 0]")
            periodic = self.domain.periodic if self.domain is not None else []
            if "xy"[ob.axis] in periodic:
                c = "xy"[ob.axis]
                raise ValueError(f"open_boundaries[{i}] ({ob.name!r}) is a plane {c} = const of a domain periodic along "
                                 f"{c}: water cannot both wrap around and leave there; drop one")
            if names.count(ob.name) > 1:
                raise ValueError(f"open boundaries named {ob.name!r} more than once; give each its own name")
        if len(self.symmetry_planes) > 1:
            raise ValueError(f"{len(self.symmetry_planes)} symmetry_planes given; one per case is supported")
        for i, sp in enumerate(self.symmetry_planes):
            if self.dim != 3:
                raise ValueError(f"symmetry_planes[{i}]: a symmetry plane is a plane y = const of a 3D case; a 2D "
                                 "case (the x-z plane) has none")
            n = sp.normal
            if abs(n[0]) > 1e-9 or abs(n[2]) > 1e-9 or abs(abs(n[1]) - 1.0) > 1e-9:
                raise ValueError(f"symmetry_planes[{i}].normal = {list(n)}: only planes y = const are supported; "
                                 "use [0.0, 1.0, 0.0] or [0.0, -1.0, 0.0]")
        for i, zone in enumerate(self.relaxation):
            try:
                resolve_zone(zone, self.motions, self.fluid.surface_level)
            except ValueError as err:
                raise ValueError(f"relaxation[{i}]: {err}") from None
        seen = set()
        for i, pr in enumerate(self.probes):
            if (pr.type, pr.name) in seen:
                raise ValueError(f"probes[{i}]: a second {pr.type!r} probe named {pr.name!r} would write the same "
                                 "file; give each probe its own name")
            seen.add((pr.type, pr.name))
        return self

    def relaxation_terms(self):
        """The relaxation zones resolved against the case (`shoal.relaxation.RelaxationTerms`: the target's
        components, the still-water level), in the order of `relaxation`."""
        return [resolve_zone(z, self.motions, self.fluid.surface_level) for z in self.relaxation]

    def _check_times(self, c0):
        """Refuse an interval or a fixed time step below a hundredth of the stable time step.

        The stable step is about dt = min(CFL h / c0, 0.125 h^2 / nu) (Monaghan & Kos 1999 without the
        force term; the viscous limit with laminar viscosity, as `shoal.model.Model.time_step_limit`).
        An output or probe time must be landed on, so a shorter interval cuts every step to it; a
        checkpoint interval that short writes one every step; a fixed step that short runs end_time / dt
        steps. Below dt / 100 each of these is certainly a mistake (a run of 10^300 steps, a disk filled
        with snapshots), whatever the flow does to the time step."""
        o = self.options
        h = smoothing_length(o.coef_h, self.dim, self.dp)
        dt = o.cfl * h / c0
        if o.viscosity == "laminar" and o.nu > 0:
            dt = min(dt, 0.125 * h * h / o.nu)
        floor = 0.01 * dt
        items = [("output.interval", self.output.interval)]
        if self.checkpoint.interval > 0:
            items.append(("checkpoint.interval", self.checkpoint.interval))
        items += [(f"probes[{i}].interval", p.interval) for i, p in enumerate(self.probes)]
        if o.fixed_dt is not None:
            items.append(("options.fixed_dt", o.fixed_dt))
        for name, value in items:
            if value < floor:
                raise ValueError(f"{name} = {value:.3g} s is below a hundredth of the stable time step (about "
                                 f"{dt:.3g} s: CFL h / c0 with h = {h:.3g} m, c0 = {c0:.3g} m/s): the run would "
                                 f"take {self.end_time / value:.3g} steps; give at least {floor:.3g} s")

    def _check_scales(self, c0):
        """Refuse numbers the kernels cannot hold in the working precision, and fluid faster than sound.

        The kernels form rho^2 (the pressure term p / rho^2), c0^2 and the Tait coefficient
        B = rho0 c0^2 / 7 in the working precision (float32: 1.2e-38 to 3.4e38). Each must lie a
        factor 10^6 inside that range (room for the density's variation, powers of rho / rho0 and
        the sums over neighbours); outside it the first step is all inf or NaN, which reads as an
        instability. A fluid region moving at c0 or faster cannot be weakly compressible (as for
        the walls, `shoal.motions.check_motion_speeds`)."""
        f = np.finfo(np.float32 if self.options.precision == "float32" else np.float64)
        lo, hi = float(f.tiny) * 1e6, float(f.max) * 1e-6
        rho0 = self.fluid.rho0
        scales = [("fluid.rho0", f"= {rho0:.3g} kg/m^3", "rho0^2", rho0 * rho0),
                  ("the speed of sound", f"c0 = {c0:.3g} m/s", "c0^2", c0 * c0),
                  ("the pressure scale", f"B = rho0 c0^2 / 7 = {rho0 * c0 * c0 / 7.0:.3g} Pa", "B",
                   rho0 * c0 * c0 / 7.0)]
        for name, shown, what, value in scales:
            if not lo <= value <= hi:
                fits64 = self.options.precision == "float32" and 1e-290 <= value <= 1e290
                raise ValueError(f"{name} {shown} gives {what} = {value:.3g}, outside what {self.options.precision} "
                                 f"holds with room for the kernels' sums ({lo:.1e} to {hi:.1e}): "
                                 + ('use options.precision = "float64", or ' if fits64 else "")
                                 + "check the units (SI: water is rho0 = 1000 kg/m^3, c0 = coef_sound sqrt(|g| "
                                 "depth) or coef_sound u_max)")
        for i, f_ in enumerate(self.fluids):
            u = math.hypot(*f_.velocity)
            if not u < c0:
                raise ValueError(f"fluids[{i}].velocity = {list(f_.velocity)} m/s ({u:.3g} m/s) is not below the "
                                 f"speed of sound c0 = {c0:.3g} m/s of the weakly compressible fluid; keep it below "
                                 "0.1 c0 (check the units), or raise c0 with options.coef_sound or fluid.u_max")

    # ------------------------------------------------------------ derived
    def data_files(self):
        """The data files the case reads (bathymetries, STL meshes, time series), each with its SHA-256.

        Returns
        -------
        dict of str to str or None
            Absolute path -> hex digest (None for a file that cannot be read). A run records this in
            ``resolved.json``; a resume compares it (`shoal.simulation.resume.check_same_data`), since
            the case file names a data file only by its path.
        """
        import hashlib
        from pathlib import Path

        found = set()

        def walk(v):
            if isinstance(v, dict):
                for k, x in v.items():
                    if k == "file" and isinstance(x, str):
                        found.add(x)
                    else:
                        walk(x)
            elif isinstance(v, list):
                for x in v:
                    walk(x)

        walk(self.resolved())
        out = {}
        for f in sorted(found):
            try:
                with open(Path(f), "rb") as fh:
                    out[f] = hashlib.file_digest(fh, "sha256").hexdigest()
            except OSError:
                out[f] = None
        return out

    def motion_reach(self):
        """{name: reach [m]} of each motion that rotates: the largest distance from its pivot of the particles of
        the solids it moves (in the x-z plane in 2D), where its wall moves fastest
        (`shoal.motions.check_motion_speeds`); empty when no motion rotates (no particles generated)."""
        rotating = [m for m in self.motions if m.rotation_axis is not None]
        if not rotating:
            return {}
        p = self.particles()
        out = {}
        for m in rotating:
            bodies = [i for i, s in enumerate(self.solids) if s.motion == m.name]
            mine = np.isin(p.body, bodies)
            if not mine.any():
                continue
            r = p.positions[mine] - np.asarray(m.rotation_pivot, float)
            if self.dim == 2:
                r[:, 1] = 0.0
            out[m.name] = float(np.sqrt((r * r).sum(axis=1).max()))
        return out

    @property
    def sound_speed(self):
        """c0 = coef_sound sqrt(|g| depth), or coef_sound u_max [m/s] (`shoal.physics.constants.speed_of_sound`)."""
        return speed_of_sound(self.options.coef_sound, self.fluid.gravity, self.fluid.depth, self.fluid.u_max)

    @property
    def smoothing_length(self):
        """h = coef_h sqrt(dim) dp [m] (`shoal.physics.constants.smoothing_length`)."""
        return smoothing_length(self.options.coef_h, self.dim, self.dp)

    def _generation_box(self):
        h2 = 2.0 * self.smoothing_length
        layers = max([support_layers(h2 / self.dp)] + [s.layers or 0 for s in self.solids])
        pad = layers * self.dp
        ring = self.dp  # one empty ring of nodes beyond the shapes, so every outer face gets its wall
        if self.domain is not None:
            lo, hi = np.array(self.domain.lo, float), np.array(self.domain.hi, float)
            axes = (0, 2) if self.dim == 2 else (0, 1, 2)
            for i, s in enumerate(self.solids):
                if s.shape.type not in ("tank", "box", "prism", "cylinder", "mesh"):
                    continue
                t = (s.layers or layers) * self.dp if s.shape.type == "tank" else 0.0
                slo, shi = s.shape.bounds(self.dim, t)
                for a in axes:
                    if np.isfinite(slo[a]) and slo[a] < lo[a] - 0.5 * self.dp or \
                            np.isfinite(shi[a]) and shi[a] > hi[a] + 0.5 * self.dp:
                        raise InputError(
                            f"solids[{i}] ({s.name or s.shape.type}) reaches {'xyz'[a]} = "
                            f"[{slo[a]:.4g}, {shi[a]:.4g}] m (walls included), outside the domain "
                            f"[{lo[a]:.4g}, {hi[a]:.4g}] m: enlarge the domain or leave it out (automatic)")
            return lo, hi
        los, his = [], []
        for what, items in (("solids", self.solids), ("fluids", self.fluids)):
            for i, item in enumerate(items):
                lo, hi = item.shape.bounds(self.dim, pad)
                los.append(lo)
                his.append(hi)
        los, his = np.array(los), np.array(his)
        with np.errstate(invalid="ignore"):
            lo = np.min(np.where(np.isfinite(los), los, np.inf), axis=0) - ring
            hi = np.max(np.where(np.isfinite(his), his, -np.inf), axis=0) + ring
        axes = (0, 2) if self.dim == 2 else (0, 1, 2)
        for a in axes:
            if not (np.isfinite(lo[a]) and np.isfinite(hi[a])):
                raise InputError(f"the case's shapes do not bound the {'xyz'[a]} axis (a plane, slope or "
                                 "bathymetry reaches to infinity): give a [domain] with lo and hi")
        if self.dim == 2:
            lo[1] = hi[1] = 0.0
        return lo, hi

    def particles(self):
        """The generated particles (cached until the case changes)."""
        key = self.model_dump_json(exclude={"end_time", "output", "description", "parameters"})
        if self._particles is not None and self._key == key:
            return self._particles
        lo, hi = self._generation_box()
        from .memory import check_generation_size

        check_generation_size(self, lo, hi)  # a tiny dp on a big case: refused now, not after hours
        solids = self.solid_inputs()
        fluids = [FluidInput(f.shape, f.velocity) for f in self.fluids]
        support = 2.0 * self.smoothing_length / self.dp
        # without an explicit domain, the shapes end one spacing inside the generation box (the empty ring
        # `_generation_box` adds): for the wall normals nothing lies beyond them
        shapes_box = (lo + self.dp, hi - self.dp) if self.domain is None else None
        p = generate(self.dim, self.dp, (lo, hi), solids, fluids, support, self.lattice_origin,
                     normals=self.options.wall_pressure == "mdbc" or self.options.riemann,
                     normals_box=shapes_box)
        if self.planes:
            behind = np.zeros(len(p), bool)
            for pl in self.planes:
                n = np.asarray(pl.normal) * ([1.0, 0.0, 1.0] if self.dim == 2 else 1.0)
                behind |= (p.kinds == FLUID) & ((p.positions - np.asarray(pl.point)) @ n < 0.0)
            if behind.any():
                keep = ~behind
                p = Particles(p.positions[keep], p.kinds[keep], p.velocities[keep], p.body[keep], p.region[keep],
                              p.spacing[keep], p.body_names, None if p.normals is None else p.normals[keep])
        for k in range(len(self.fluids)):
            if not np.any(p.region == k):
                what = f"fluids[{k}] ({self.fluids[k].shape.type}) holds no particle"
                flo, fhi = self.fluids[k].shape.bounds(self.dim)
                axes = (0, 2) if self.dim == 2 else (0, 1, 2)
                dom = " x ".join(f"[{lo[a]:.4g}, {hi[a]:.4g}]" for a in axes)
                if any(fhi[a] < lo[a] or flo[a] > hi[a] for a in axes):
                    raise InputError(f"{what}: it lies outside the domain {dom} m; move it or enlarge the domain")
                thin = [f"{'xyz'[a]} ({fhi[a] - flo[a]:.4g} m)" for a in axes if fhi[a] - flo[a] < self.dp]
                if thin:
                    raise InputError(f"{what}: it is thinner than dp = {self.dp:g} m along {', '.join(thin)}; "
                                     "make it thicker or dp smaller")
                raise InputError(f"{what}: it lies inside solids (a lattice node inside a solid belongs to the "
                                 "solid), outside the domain, or is thinner than dp; check the solids' shapes")
        if self.dim == 2:
            p.positions[:, 1] = 0.0
        if self.open_boundaries:
            p = self._with_buffers(p)
        self._particles, self._key = p, key
        return p

    def _with_buffers(self, p):
        """`p` with the open boundaries' buffer particles after the fluid's (before the walls', so that the
        walls' ids stay one block): fluid particles at rest or at the imposed velocity, `zone` naming each
        one's boundary."""
        from scipy.spatial import cKDTree

        support = 2.0 * self.smoothing_length
        add, zones, vels = [], [], []
        for k, ob in enumerate(self.open_boundaries):
            bounds = ob.level_bounds(0.0, self.end_time)
            if bounds is not None and bounds[0] <= ob.bed:
                raise InputError(f"open boundary {ob.name!r}: its level falls to {bounds[0]:g} m by t = "
                                 f"{self.end_time:g} s, not above the bottom of its section ({ob.bed:g} m): keep the "
                                 "level above it (or lower the section's lo)")
            try:
                pts = ob.buffer_lattice(self.dim, self.dp, np.asarray(self.lattice_origin, float), support)
            except ValueError as err:
                raise InputError(str(err)) from None
            if self.dim == 2:
                pts[:, 1] = 0.0
            v = np.zeros_like(pts)
            u = ob.speed(pts[:, 2], self.dim)
            if u is not None:
                v[:, ob.axis] = ob.sign * u
            add.append(pts)
            zones.append(np.full(len(pts), k, np.int16))
            vels.append(v)
        pts, zone, vel = np.concatenate(add), np.concatenate(zones), np.concatenate(vels)
        near, _ = cKDTree(p.positions).query(pts, distance_upper_bound=0.5 * self.dp)
        clash = np.isfinite(near)
        if clash.any():
            k = int(zone[np.argmax(clash)])
            raise InputError(f"open boundary {self.open_boundaries[k].name!r}: its buffer overlaps the case's "
                             f"particles at {int(clash.sum())} places (first at {pts[np.argmax(clash)].round(6).tolist()} "
                             "m): the buffer lies behind its plane, outside the fluid regions and the solids; "
                             "end them at the plane")
        n_fl = int(np.count_nonzero(p.body < 0))
        cat = lambda a, b: np.concatenate([a[:n_fl], b, a[n_fl:]])  # noqa: E731
        m = len(pts)
        normals = None if p.normals is None else cat(p.normals, np.zeros((m, 3)))
        return Particles(cat(p.positions, pts), cat(p.kinds, np.full(m, FLUID, p.kinds.dtype)),
                         cat(p.velocities, vel), cat(p.body, np.full(m, -1, p.body.dtype)),
                         cat(p.region, np.full(m, -1, p.region.dtype)), cat(p.spacing, np.full(m, self.dp)),
                         p.body_names, normals, cat(np.full(len(p), -1, np.int16), zone))

    def solid_inputs(self):
        """The solids as the particle generator takes them (`shoal.geometry.generate.SolidInput`): a solid
        with a motion or that floats has moving particles, grouped by its motion (a floating body: its own
        group)."""
        return [SolidInput(s.shape, s.boundary, s.layers, s.motion is not None or s.floating is not None,
                           s.name or f"solid{i}", group=s.motion if s.floating is None else f"floating {i}",
                           fit_surface=s.fit_surface, whole=s.floating is not None)
                for i, s in enumerate(self.solids)]

    def resolved_domain(self):
        """(lo, hi) of the computational box [m] (3 floats each)."""
        if self.domain is not None:
            return np.array(self.domain.lo, float), np.array(self.domain.hi, float)
        p = self.particles()
        m = 2.0 * self.smoothing_length
        lo = p.positions.min(axis=0) - m
        hi = p.positions.max(axis=0) + m
        fl = p.positions[p.kinds == FLUID]
        hi[2] += max(float(np.ptp(fl[:, 2])) if len(fl) else 0.0, m)
        if self.dim == 2:
            lo[1] = hi[1] = 0.0
        return lo, hi

    @property
    def positions(self):
        return self.particles().positions

    @property
    def kinds(self):
        return self.particles().kinds

    @property
    def n_particles(self):
        return len(self.particles())

    @property
    def n_fluid(self):
        return self.particles().n_fluid

    def with_options(self, **changes):
        """A copy with some SPH options changed (validated, the options alone and with the rest of the
        case: `revalidate`)."""
        from dataclasses import replace

        return self.model_copy(update={"options": replace(self.options, **changes)}).revalidate()

    def revalidate(self):
        """Run the checks across fields again (`model_copy` does not), as `InputError`; returns the case.
        A copy with a changed interval, option or fluid is checked this way before it is built."""
        try:
            self._links()
        except ValueError as err:
            raise InputError(str(err)) from None
        return self

    def sampled(self):
        """The case with the open boundaries' series given as Python functions replaced by their tables over
        [0, end_time] (`shoal.time_series.TimeSeries.sampled`): what a run runs and writes."""
        obs = [ob.sampled(0.0, self.end_time) for ob in self.open_boundaries]
        if all(a is b for a, b in zip(obs, self.open_boundaries)):
            return self
        return self.model_copy(update={"open_boundaries": obs})

    def resolved(self):
        """The case as a plain dict with every default filled in (what
        ``resolved.toml`` holds; ``Case.model_validate`` of it rebuilds the case)."""
        for s in self.solids:
            if getattr(s.shape, "function", None) is not None:
                raise InputError(f"solid {s.name!r}: a bathymetry given as a Python function cannot be written "
                                 "to a case file; sample it on a grid (Bathymetry(grid=...))")
        d = self.model_dump(mode="json", exclude_none=True)
        # from the field itself (plain values, see _plain_record): the JSON dump would turn inf and nan into None
        d["parameters"] = {k: v for k, v in self.parameters.items() if v is not None}
        return d
