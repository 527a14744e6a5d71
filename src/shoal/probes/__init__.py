"""Measuring the flow at fixed places: point probes and wave gauges.

Probes are data in a case (``[[probes]]`` tables) and callbacks of a
Simulation on a `TimeInterval`; each writes a CSV file (one row per sample,
flushed as it goes, so a crash loses nothing already measured):

* `PointProbes`: velocity, pressure and density interpolated at fixed
  points (Shepard-normalised SPH interpolation, see `interpolate`);
* `WaveGauge`: the free-surface elevation at (x, y): the highest point of a
  vertical line of sample points (spacing dp/2) where the kernel sum
  S = sum_j V_j W >= 1/2 (water on at least half of the support), linearly
  interpolated between sample points -- the kernel-sum threshold of
  DualSPHysics's MeasureTool;
* `TestPoints`: a Cartesian grid of probe nodes (GPUSPH's TESTPOINTS),
  written at the end of the run as a NetCDF dataset (xarray; coordinates
  time, z, y, x with CF units; variables u, v, w, p, rho, kernel_sum);
* `Tracker`: the trajectories of chosen fluid particles (by id, or the
  particles nearest to given starting points), ``track_<name>.csv``;
* `MaxZGauge`: the highest fluid particle within a horizontal distance of
  (x, y) (DualSPHysics's GaugeMaxZ), ``maxz_<name>.csv``;
* `RunupGauge`: the highest elevation reached by fluid particles in a
  cross-shore range [x0, x1] (and a y band in 3D), and where: the shoreline
  run-up on a beach, ``runup_<name>.csv``;
* `FlowGauge`: the volume of water that has passed a cross-section and the
  flow rate through it (DualSPHysics's FlowTool), ``flow_<name>.csv``
  (`shoal.probes.flow`);
* `PressureSensors`: the pressure on a wall's surface, as a flush-mounted
  transducer reads it (`shoal.probes.pressure_sensors`),
  ``pressure_<name>.csv``;
* `ForceGauge`: the hydrodynamic force of the fluid on a solid
  (DualSPHysics's ComputeForces), ``force_<name>.csv``
  (`shoal.physics.forces`).

The max-z and run-up gauges read particle centres, as DualSPHysics's
GaugeMaxZ does: in still water the top particles sit dp/2 below the free
surface (the lattice puts them at (i + 1/2) dp), so both read the
still-water level minus about dp/2. Every fluid particle counts, so a
detached splash above the range counts too.
"""

from __future__ import annotations

import csv
from pathlib import Path
from typing import Annotated, Literal, Union

import numpy as np
from pydantic import Field, model_validator

from ..analysis.kernel_sum import surface_level
from ..geometry.shapes import PositiveReal, Real, Spec, Vec3
from .recorder_state import Recorder

NonNegativeReal = Annotated[float, Field(ge=0, allow_inf_nan=False, strict=True)]


class PointProbes(Spec):
    """Velocity, pressure and density at fixed `points` [m] every `interval` s,
    written to ``probe_<name>.csv`` (columns time, then u, v, w, p, rho per point)."""

    type: Literal["points"] = "points"
    name: Annotated[str, Field(min_length=1, pattern=r"^[A-Za-z0-9_.\-]+$")]
    points: Annotated[list[Vec3], Field(min_length=1)]
    interval: PositiveReal
    shepard: bool = True


class WaveGauge(Spec):
    """Free-surface elevation at (x, y) [m], searched between z0 and z1 [m],
    every `interval` s, written to ``gauge_<name>.csv`` (time, level [m])."""

    type: Literal["gauge"] = "gauge"
    name: Annotated[str, Field(min_length=1, pattern=r"^[A-Za-z0-9_.\-]+$")]
    x: Real
    y: Real = 0.0
    z0: Real
    z1: Real
    interval: PositiveReal

    @model_validator(mode="after")
    def _range(self):
        if not self.z1 > self.z0:
            raise ValueError(f"z1 = {self.z1} must be above z0 = {self.z0}")
        return self


class TestPoints(Spec):
    """A grid of `counts` = (nx, ny, nz) nodes spanning [lo, hi] [m] (ny = 1 in
    2D), sampled every `interval` s; written as ``testpoints_<name>.nc``."""

    __test__ = False  # not a pytest test class

    type: Literal["grid"] = "grid"
    name: Annotated[str, Field(min_length=1, pattern=r"^[A-Za-z0-9_.\-]+$")]
    lo: Vec3
    hi: Vec3
    counts: tuple[Annotated[int, Field(ge=1, strict=True)], Annotated[int, Field(ge=1, strict=True)],
                  Annotated[int, Field(ge=1, strict=True)]]
    interval: PositiveReal
    shepard: bool = True

    def axes(self):
        return [np.linspace(a, b, n) if n > 1 else np.array([0.5 * (a + b)])
                for a, b, n in zip(self.lo, self.hi, self.counts)]


class Tracker(Spec):
    """Trajectories of fluid particles: those with the given `ids`, or the ones
    nearest to the `start` points at t = 0; every `interval` s to
    ``track_<name>.csv`` (time, then x, y, z per particle)."""

    type: Literal["tracker"] = "tracker"
    name: Annotated[str, Field(min_length=1, pattern=r"^[A-Za-z0-9_.\-]+$")]
    ids: list[Annotated[int, Field(ge=0, strict=True)]] = []
    start: list[Vec3] = []
    interval: PositiveReal

    @model_validator(mode="after")
    def _some(self):
        if not self.ids and not self.start:
            raise ValueError("give the particle ids or the start points to track")
        return self


class MaxZGauge(Spec):
    """The highest fluid particle centre [m] within a horizontal distance
    `radius` [m] of (x, y) (2D: ``|x_j - x| <= radius``), every `interval` s,
    written to ``maxz_<name>.csv`` (time, zmax; NaN when no fluid particle
    is within reach) -- DualSPHysics's GaugeMaxZ."""

    type: Literal["maxz"] = "maxz"
    name: Annotated[str, Field(min_length=1, pattern=r"^[A-Za-z0-9_.\-]+$")]
    x: Real
    y: Real = 0.0
    radius: PositiveReal
    interval: PositiveReal


class RunupGauge(Spec):
    """Shoreline run-up: the highest fluid particle centre [m] with x0 <= x_j
    <= x1 (and, in 3D, ``|y_j - y| <= band / 2``; `band` omitted: every y),
    every `interval` s, written to ``runup_<name>.csv`` (time, zmax, and the
    x, y where it is reached; NaN when the range holds no fluid).

    The position is that of the most `landward` particle ("+x": largest x,
    the built-in flumes' beaches; "-x": smallest) among those within dp/4 of
    the highest: still water has a whole top row at one level, and its
    landward end is the shoreline.

    With `min_depth` [m] the gauge follows the wet shoreline instead, as a
    laboratory run-up wire mounted that high above the slope does: the range
    is cut into columns dp wide in x (and dp in y, 3D); a column is wet where
    its water layer, the fluid volume over the column's plan area (N dp in a
    column of N particles), is at least `min_depth` thick; from the first wet
    column on the seaward side the shoreline is the last of the unbroken run
    of wet columns landward (a splash ahead of the tongue, or a film thinner
    than `min_depth`, does not count). zmax is then the bed's elevation
    there, its lowest particle centre minus dp/2, x the most landward
    particle of that column and y the column's centre; in 3D the highest
    shoreline over the y columns (`shoal.probes.shoreline`).

    With `max_gap` [m] the run goes on across stretches of dry columns up
    to `max_gap` wide: a film thinner than one particle is represented by
    particles spaced more than dp apart along the bed, and with `max_gap`
    the kernel support 2h (and `min_depth` dp: any particle) the gauge
    follows the tip of the water that still interacts with the body, as
    SPH run-up studies read the foremost particle of the tongue, without
    counting a splash that has left it."""

    type: Literal["runup"] = "runup"
    name: Annotated[str, Field(min_length=1, pattern=r"^[A-Za-z0-9_.\-]+$")]
    x0: Real
    x1: Real
    y: Real = 0.0
    band: PositiveReal | None = None
    landward: Literal["+x", "-x"] = "+x"
    min_depth: PositiveReal | None = None
    max_gap: NonNegativeReal = 0.0
    interval: PositiveReal

    @model_validator(mode="after")
    def _range(self):
        if not self.x1 > self.x0:
            raise ValueError(f"x1 = {self.x1} must be beyond x0 = {self.x0}")
        if self.max_gap > 0 and self.min_depth is None:
            raise ValueError(f"max_gap = {self.max_gap} needs min_depth (it bridges dry columns of the wet "
                             "shoreline)")
        return self


class FlowGauge(Spec):
    """Flow through the cross-section ``axis = at`` [m] (x, y or z = const),
    limited in the other two coordinates to [lo, hi] (the component along
    `axis` is ignored; omitted: unbounded), every `interval` s, written to
    ``flow_<name>.csv``: time, the net volume that has passed in the +axis
    direction since t = 0 (counted particle by particle, exact), the mean flow
    rate since the previous sample, and the instantaneous flow rate from the
    particles in a slab 2 dp wide (`shoal.probes.flow`). 3D: m^3, m^3/s; 2D:
    per metre of width, m^2, m^2/s."""

    type: Literal["flow"] = "flow"
    name: Annotated[str, Field(min_length=1, pattern=r"^[A-Za-z0-9_.\-]+$")]
    axis: Literal["x", "y", "z"] = "x"
    at: Real
    lo: Vec3 | None = None
    hi: Vec3 | None = None
    interval: PositiveReal

    @model_validator(mode="after")
    def _extent(self):
        if self.lo is not None and self.hi is not None:
            for k, c in enumerate("xyz"):
                if c != self.axis and self.hi[k] < self.lo[k]:
                    raise ValueError(f"hi[{k}] = {self.hi[k]} must not be below lo[{k}] = {self.lo[k]} (the "
                                     f"section's extent in {c})")
        return self


class ForceGauge(Spec):
    """The force [N] of the fluid on the solid named `solid` (one of the case's
    `solids`, with dynamic boundary particles), every `interval` s, written to
    ``force_<name>.csv`` (time, fx, fy, fz): the sum over the solid's boundary
    particles of the force each gets from its fluid neighbours by the momentum
    equation's pair terms (pressure and viscosity; `shoal.physics.forces`),
    DualSPHysics's ComputeForces. 2D: per metre of width [N/m], fy = 0."""

    type: Literal["force"] = "force"
    name: Annotated[str, Field(min_length=1, pattern=r"^[A-Za-z0-9_.\-]+$")]
    solid: Annotated[str, Field(min_length=1)]
    interval: PositiveReal


class PressureSensors(Spec):
    """Pressure sensors on a wall: the pressure [Pa] of the fluid at `points` [m] on a wall's surface,
    every `interval` s, written to ``pressure_<name>.csv`` (time, p_0, p_1, ...), as a flush-mounted
    laboratory transducer reads it (`shoal.probes.pressure_sensors`): extrapolated to the point from the
    fluid alone, by the Shepard average corrected for the hydrostatic pressure (`method =
    "hydrostatic"`, the default: exact at rest, robust in impacts), by a linear least-squares fit
    (`"linear"`: exact for any linear field, but it amplifies the particles' noise) or the plain Shepard
    average (`"shepard"`). A sensor where the kernel sum of the fluid is below `kernel_sum_min` (1/2 on a wall
    under deep water, about 0.2 at the contact line of a front) is dry and reads 0.

    `normal` (any length; the direction out of the wall into the fluid) makes each sensor count only the
    fluid in front of the wall's plane through it, or less than half a spacing behind it (a transducer
    sees nothing behind its face: water that has run over the wall's edge, or lies beyond a thin wall). `diameter` [m] > 0 averages each sensor
    over a disc of that diameter on the wall (a segment in 2D), perpendicular to `normal`, which it then
    needs. The wall surface of a built-in solid lies half a particle spacing outside its
    outermost boundary particles (the lattice puts fluid and wall nodes at (i + 1/2) dp)."""

    type: Literal["pressure"] = "pressure"
    name: Annotated[str, Field(min_length=1, pattern=r"^[A-Za-z0-9_.\-]+$")]
    points: Annotated[list[Vec3], Field(min_length=1)]
    interval: PositiveReal
    normal: Vec3 | None = None
    diameter: Annotated[float, Field(ge=0, allow_inf_nan=False, strict=True)] = 0.0
    method: Literal["hydrostatic", "linear", "shepard"] = "hydrostatic"
    kernel_sum_min: Annotated[float, Field(ge=0, le=1, allow_inf_nan=False, strict=True)] = 0.1

    @model_validator(mode="after")
    def _area(self):
        if self.normal is not None and not any(self.normal):
            raise ValueError("normal = [0, 0, 0] has no direction; give the direction out of the wall into "
                             "the fluid, e.g. [0, 0, 1] for a bed")
        if self.diameter > 0 and self.normal is None:
            raise ValueError(f"diameter = {self.diameter:g} m needs the wall's normal (the direction out of "
                             "the wall into the fluid, e.g. normal = [-1, 0, 0]) to lay the sensor's area on it")
        return self


AnyProbe = Annotated[Union[PointProbes, WaveGauge, TestPoints, Tracker, MaxZGauge, RunupGauge, FlowGauge,
                           ForceGauge, PressureSensors], Field(discriminator="type")]


def make_recorder(spec, out_dir, dp, model):
    """The recorder (a Simulation callback with a `close`) of a probe spec."""
    if isinstance(spec, TestPoints):
        return GridRecorder(spec, out_dir)
    if isinstance(spec, Tracker):
        return TrackRecorder(spec, out_dir, model)
    if isinstance(spec, (MaxZGauge, RunupGauge)):
        return MaxZRecorder(spec, out_dir, dp)
    if isinstance(spec, FlowGauge):
        from .flow import FlowRecorder

        return FlowRecorder(spec, out_dir, model)
    if isinstance(spec, ForceGauge):
        return ForceRecorder(spec, out_dir, model)
    if isinstance(spec, PressureSensors):
        from .pressure_sensors import PressureSensorRecorder

        return PressureSensorRecorder(spec, out_dir, model)
    return ProbeRecorder(spec, out_dir, dp)


class GridRecorder(Recorder):
    """Samples a `TestPoints` grid; writes the NetCDF file on `close`."""

    def __init__(self, spec, out_dir):
        self.spec = spec
        self.path = Path(out_dir) / f"testpoints_{spec.name}.nc"
        x, y, z = spec.axes()
        self.coords = (x, y, z)
        Z, Y, X = np.meshgrid(z, y, x, indexing="ij")
        self.points = np.column_stack([X.ravel(), Y.ravel(), Z.ravel()])
        self.times, self.samples = [], []

    def __call__(self, sim):
        r = sim.model.sample(self.points, shepard=self.spec.shepard)
        self.times.append(sim.time)
        self.samples.append(r)

    def dataset(self):
        """The samples as an xarray Dataset (time, z, y, x)."""
        import xarray as xr

        x, y, z = self.coords
        shape = (len(self.times), len(z), len(y), len(x))

        def stack(f):
            return np.array([f(r) for r in self.samples]).reshape(shape)

        units = {"u": "m s-1", "v": "m s-1", "w": "m s-1", "p": "Pa", "rho": "kg m-3", "kernel_sum": "1"}
        data = {"u": stack(lambda r: r["velocity"][:, 0]), "v": stack(lambda r: r["velocity"][:, 1]),
                "w": stack(lambda r: r["velocity"][:, 2]), "p": stack(lambda r: r["pressure"]),
                "rho": stack(lambda r: r["density"]), "kernel_sum": stack(lambda r: r["kernel_sum"])}
        names = {"u": "x velocity", "v": "y velocity", "w": "z velocity", "p": "pressure", "rho": "density",
                 "kernel_sum": "SPH kernel sum (1 in water, 1/2 at a free surface, 0 in air)"}
        ds = xr.Dataset(
            {k: (("time", "z", "y", "x"), v, {"units": units[k], "long_name": names[k]}) for k, v in data.items()},
            coords={"time": ("time", np.asarray(self.times), {"units": "s", "standard_name": "time"}),
                    "x": ("x", x, {"units": "m", "long_name": "cross-shore distance"}),
                    "y": ("y", y, {"units": "m", "long_name": "alongshore distance"}),
                    "z": ("z", z, {"units": "m", "long_name": "elevation", "positive": "up"})},
            attrs={"title": f"shoal test points {self.spec.name}", "Conventions": "CF-1.8",
                   "interpolation": "Shepard" if self.spec.shepard else "plain SPH sum"})
        return ds

    def close(self):
        if self.samples:
            tmp = self.path.with_suffix(".nc.tmp")
            self.dataset().to_netcdf(tmp, engine="scipy")
            tmp.replace(self.path)


class TrackRecorder(Recorder):
    """Appends the positions of tracked particles to a CSV.

    The particles are looked up by id in the model (`Model.particle_positions`;
    under MPI on the rank that owns each one now, see
    `shoal.parallel.model.DistributedModel`); the ones given by `start` are the
    fluid particles nearest to those points when the recorder is made
    (`Model.nearest_fluid`). A particle that has left the domain gives NaNs.
    """

    def __init__(self, spec, out_dir, model):
        self.spec = spec
        self.path = Path(out_dir) / f"track_{spec.name}.csv"
        ids = list(spec.ids)
        if spec.start:
            ids += [int(i) for i in model.nearest_fluid(spec.start)]
        self.ids = np.asarray(ids, dtype=np.int64)
        self.file = open(self.path, "w", newline="")
        self.writer = csv.writer(self.file)
        self.writer.writerow(["time"] + [f"{c}_{i}" for i in self.ids for c in ("x", "y", "z")])

    def __call__(self, sim):
        xyz = sim.model.particle_positions(self.ids)  # NaN once a particle escaped
        self.writer.writerow([f"{sim.time:.9g}"] + [f"{v:.9g}" for v in xyz.ravel()])
        self.file.flush()

    def close(self):
        self.file.close()


class ProbeRecorder(Recorder):
    """A Simulation callback sampling one probe spec and appending to its CSV."""

    def __init__(self, spec, out_dir, dp):
        self.spec = spec
        out_dir = Path(out_dir)
        if isinstance(spec, WaveGauge):
            n = max(2, int(np.ceil((spec.z1 - spec.z0) / (0.5 * dp))) + 1)
            zs = np.linspace(spec.z0, spec.z1, n)
            self.z = zs
            self.points = np.column_stack([np.full(n, spec.x), np.full(n, spec.y), zs])
            self.path = out_dir / f"gauge_{spec.name}.csv"
            header = ["time", "level"]
        else:
            self.points = np.asarray(spec.points, float)
            self.path = out_dir / f"probe_{spec.name}.csv"
            header = ["time"] + [f"{q}_{k}" for k in range(len(self.points)) for q in ("u", "v", "w", "p", "rho")]
        self.file = open(self.path, "w", newline="")
        self.writer = csv.writer(self.file)
        self.writer.writerow(header)
        self.rows = []

    def __call__(self, sim):
        m = sim.model
        if isinstance(self.spec, WaveGauge):
            r = m.sample(self.points, shepard=False)
            row = [sim.time, surface_level(self.z, r["kernel_sum"])]
        else:
            r = m.sample(self.points, shepard=self.spec.shepard)
            vals = np.column_stack([r["velocity"], r["pressure"], r["density"]])
            row = [sim.time] + vals.ravel().tolist()
        self.rows.append(row)
        self.writer.writerow([f"{v:.9g}" for v in row])
        self.file.flush()

    def close(self):
        self.file.close()


def positions_of(ids, positions, wanted):
    """Positions of the particles with ids `wanted` among (`ids`, `positions`).

    Parameters
    ----------
    ids : ndarray, shape (N,)
        Particle ids (unique, >= 0) of the rows of `positions`.
    positions : ndarray, shape (N, 3)
        Their positions [m].
    wanted : array_like of int, shape (K,)
        The ids to look up.

    Returns
    -------
    ndarray, shape (K, 3)
        float64 positions [m]; NaN rows for the ids not among `ids` (a
        particle that escaped, or, under MPI, one another rank owns).
    """
    ids = np.asarray(ids, np.int64)
    wanted = np.asarray(wanted, np.int64).reshape(-1)
    pos = np.asarray(positions, np.float64).reshape(-1, 3)
    size = int(max(ids.max(initial=-1), wanted.max(initial=-1))) + 1
    slot = np.full(size, -1, np.int64)
    slot[ids] = np.arange(len(ids))
    rows = np.where(wanted >= 0, slot[np.maximum(wanted, 0)], -1)
    if len(pos) == 0:
        return np.full((len(wanted), 3), np.nan)
    return np.where(rows[:, None] >= 0, pos[np.maximum(rows, 0)], np.nan)


def nearest_particles(positions, ids, points):
    """For each of `points`, the nearest of the particles (`positions`, `ids`).

    Parameters
    ----------
    positions : ndarray, shape (N, 3)
        Particle positions [m] (y = 0 in 2D).
    ids : ndarray, shape (N,)
        Their ids.
    points : array_like, shape (K, 3)
        The points [m].

    Returns
    -------
    d2 : ndarray, shape (K,)
        Squared distance [m^2] to the nearest particle (inf when N = 0).
    nearest : ndarray, shape (K,)
        Its id (-1 when N = 0); among particles at exactly the same distance,
        the smallest id, so that the choice does not depend on the order of
        the rows (nor, under MPI, on which rank holds them).
    """
    pos = np.asarray(positions, np.float64).reshape(-1, 3)
    ids = np.asarray(ids, np.int64)
    pts = np.asarray(points, np.float64).reshape(-1, 3)
    d2 = np.full(len(pts), np.inf)
    nearest = np.full(len(pts), -1, np.int64)
    if len(pos) == 0:
        return d2, nearest
    for k, p in enumerate(pts):  # a few points; vectorised over the particles
        d = pos - p
        dk = d[:, 0] ** 2 + d[:, 1] ** 2 + d[:, 2] ** 2
        d2[k] = dk.min()
        nearest[k] = ids[dk == d2[k]].min()
    return d2, nearest


def highest_fluid(positions, kinds, dim, spec, tie=0.0, zmax=None):
    """The highest fluid particle a `MaxZGauge` or `RunupGauge` sees.

    Parameters
    ----------
    positions : ndarray, shape (N, 3)
        Particle positions in world coordinates [m] (y = 0 in 2D).
    kinds : ndarray, shape (N,)
        Particle kinds; 0 is fluid.
    dim : {2, 3}
        Dimension of the run: in 2D the y coordinates are ignored.
    spec : MaxZGauge or RunupGauge
        The gauge.
    tie : float
        [m]: for a `RunupGauge`, (x, y) are those of the most landward
        particle within `tie` below the highest one.
    zmax : float, optional
        [m]: the elevation of the highest particle, when it was found among
        more particles than these (under MPI: the maximum over the ranks,
        see `shoal.model.Model.highest_fluid`); (x, y)
        are then those of a particle here at `zmax` (max-z) or within `tie`
        below it (run-up), NaN when none is. Default: the highest here.

    Returns
    -------
    tuple of float
        (zmax, x, y): the highest fluid particle centre in the gauge's
        region and where it is [m]; NaNs when the region holds no fluid.
    """
    pos = np.asarray(positions, float).reshape(-1, 3)
    sel = np.asarray(kinds) == 0
    if isinstance(spec, MaxZGauge):
        if dim == 3:
            d2 = (pos[:, 0] - spec.x) ** 2 + (pos[:, 1] - spec.y) ** 2
            sel &= d2 <= spec.radius**2
        else:
            sel &= np.abs(pos[:, 0] - spec.x) <= spec.radius
    else:
        sel &= (pos[:, 0] >= spec.x0) & (pos[:, 0] <= spec.x1)
        if dim == 3 and spec.band is not None:
            sel &= np.abs(pos[:, 1] - spec.y) <= 0.5 * spec.band
    cand = pos[sel]
    nan = float("nan")
    if zmax is None:
        if not len(cand):
            return (nan,) * 3
        zmax = float(cand[:, 2].max())
    zmax = float(zmax)
    if isinstance(spec, RunupGauge):
        top = np.flatnonzero(cand[:, 2] >= zmax - tie)
        if not len(top):
            return zmax, nan, nan
        sign = 1.0 if spec.landward == "+x" else -1.0
        k = int(top[np.argmax(sign * cand[top, 0])])
    else:
        top = np.flatnonzero(cand[:, 2] >= zmax)
        if not len(top):
            return zmax, nan, nan
        k = int(top[0])
    return zmax, float(cand[k, 0]), float(cand[k, 1])


def shoreline_columns(positions, kinds, dim, spec, dp, ylim):
    """Per-column sums of a `RunupGauge` with `min_depth` (see its docstring): the columns of width dp
    from x0 (and from ylim[0] in y, 3D) over the fluid particles here.

    Parameters
    ----------
    positions, kinds, dim, spec
        As `highest_fluid`.
    dp : float
        Particle spacing [m]: the columns' width.
    ylim : (float, float)
        [m] the y range of the columns (3D: the gauge's band, or the domain's y range).

    Returns
    -------
    counts, zmin, xland : ndarray, shape (ny, nx)
        Fluid particles in each column, their lowest z [m] (inf where none) and the most landward
        particle's x times +1 ("+x") or -1 ("-x") (-inf where none): sums, minima and maxima that MPI
        ranks combine (`shoreline` reads them).
    """
    nx = max(1, int(np.ceil((spec.x1 - spec.x0) / dp - 1e-9)))
    ny = max(1, int(np.ceil((ylim[1] - ylim[0]) / dp - 1e-9))) if dim == 3 else 1
    pos = np.asarray(positions, float).reshape(-1, 3)
    sel = (np.asarray(kinds) == 0) & (pos[:, 0] >= spec.x0) & (pos[:, 0] <= spec.x1)
    if dim == 3:
        sel &= (pos[:, 1] >= ylim[0]) & (pos[:, 1] <= ylim[1])
    p = pos[sel]
    ix = np.clip(((p[:, 0] - spec.x0) / dp).astype(np.int64), 0, nx - 1)
    iy = np.clip(((p[:, 1] - ylim[0]) / dp).astype(np.int64), 0, ny - 1) if dim == 3 else np.zeros(len(p), np.int64)
    flat = iy * nx + ix
    counts = np.bincount(flat, minlength=nx * ny).astype(np.float64)
    zmin = np.full(nx * ny, np.inf)
    np.minimum.at(zmin, flat, p[:, 2])
    xland = np.full(nx * ny, -np.inf)
    np.maximum.at(xland, flat, (1.0 if spec.landward == "+x" else -1.0) * p[:, 0])
    return counts.reshape(ny, nx), zmin.reshape(ny, nx), xland.reshape(ny, nx)


SHORELINE_TIE = 1e-3
"""Shoreline elevations of two rows of columns closer than this many dp are level (`shoreline`): a
thousandth of a particle spacing is far above the round-off of positions (1e-6 dp in float32) and far
below anything a gauge resolves."""


def shoreline(counts, zmin, xland, dim, spec, dp, ylim):
    """(zmax, x, y) [m] of a `RunupGauge` with `min_depth` from its columns (`shoreline_columns`, summed
    over the ranks): in each row of columns, the landward end of the unbroken run of wet columns (layer
    N dp**dim / dp**(dim - 1) >= min_depth) that starts at the first wet column on the seaward side,
    bridging dry stretches of up to floor(max_gap / dp) columns; the highest over the rows; NaNs when
    no column is wet. Rows within `SHORELINE_TIE` dp of the highest are level with it, and the first of
    them (smallest y) is the one reported: in a flow uniform in y the rows' shorelines differ by round-off
    only, which would otherwise pick the row (and differ between a run on one process and on several)."""
    nan = float("nan")
    wet = counts * dp >= spec.min_depth
    if spec.landward == "-x":
        wet, zmin, xland = wet[:, ::-1], zmin[:, ::-1], xland[:, ::-1]
    rows = []
    for r in range(wet.shape[0]):
        cols = np.flatnonzero(wet[r])
        if not len(cols):
            continue
        # the unbroken run, across up to `skip` dry columns
        skip = int(np.floor(spec.max_gap / dp + 1e-9))
        k = cols[0]
        for j in cols[1:]:
            if j - k - 1 > skip:
                break
            k = j
        z = float(zmin[r, k]) - 0.5 * dp
        x = float(xland[r, k]) * (1.0 if spec.landward == "+x" else -1.0)
        rows.append((z, x, ylim[0] + (r + 0.5) * dp if dim == 3 else 0.0))
    if not rows:
        return (nan, nan, nan)
    top = max(z for z, _, _ in rows)
    return next(row for row in rows if row[0] >= top - SHORELINE_TIE * dp)


class ForceRecorder(Recorder):
    """Samples a `ForceGauge` (`Model.body_force`: a pass over the boundary particles on the active
    backend; under MPI summed over the ranks) and appends time, fx, fy, fz to its CSV."""

    def __init__(self, spec, out_dir, model):
        from ..errors import InputError

        self.spec = spec
        names = getattr(model, "body_names", None)
        if model.body_of is None or not names:
            raise InputError(f"force gauge {spec.name!r}: the model was not built from a case (no solids to "
                             "measure); use shoal.build.build_model")
        self.body = names.index(spec.solid)
        self.path = Path(out_dir) / f"force_{spec.name}.csv"
        self.file = open(self.path, "w", newline="")
        self.writer = csv.writer(self.file)
        self.writer.writerow(["time", "fx", "fy", "fz"])
        self.rows = []

    def __call__(self, sim):
        f = sim.model.body_force(self.body)
        row = [sim.time, *map(float, f)]
        self.rows.append(row)
        self.writer.writerow([f"{v:.9g}" for v in row])
        self.file.flush()

    def close(self):
        self.file.close()


class MaxZRecorder(Recorder):
    """Samples a `MaxZGauge` or a `RunupGauge` (`Model.highest_fluid`: NumPy
    over the host copies of the particle positions; under MPI each rank's
    owned particles, reduced over the ranks) and appends to its CSV."""

    def __init__(self, spec, out_dir, dp):
        self.spec = spec
        self.tie = 0.25 * dp
        if isinstance(spec, MaxZGauge):
            self.path = Path(out_dir) / f"maxz_{spec.name}.csv"
            header = ["time", "zmax"]
        else:
            self.path = Path(out_dir) / f"runup_{spec.name}.csv"
            header = ["time", "zmax", "x", "y"]
        self.file = open(self.path, "w", newline="")
        self.writer = csv.writer(self.file)
        self.writer.writerow(header)
        self.rows = []

    def __call__(self, sim):
        if getattr(self.spec, "min_depth", None) is not None:
            z, x, y = sim.model.shoreline(self.spec)
        else:
            z, x, y = sim.model.highest_fluid(self.spec, self.tie)
        row = [sim.time, z] if isinstance(self.spec, MaxZGauge) else [sim.time, z, x, y]
        self.rows.append(row)
        self.writer.writerow([f"{v:.9g}" for v in row])
        self.file.flush()

    def close(self):
        self.file.close()
