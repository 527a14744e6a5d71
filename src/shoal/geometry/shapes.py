"""Shapes: the regions that solids and fluid regions are made of.

Every shape answers one question, ``contains(points)``: which of these
points lie inside it. The particle generator (:mod:`shoal.geometry.generate`)
asks it on a lattice of spacing dp and turns the answers into fluid and
wall particles, so any shape can be a solid (walls, bed, obstacle) or a
fluid region.

Shapes are data (pydantic models with a ``type`` tag), so a TOML case file
maps one-to-one onto them::

    shape = { type = "box", lo = [0, 0, 0], hi = [1, 0.5, 0.3] }

In 2D runs (the x-z plane) the y coordinate is ignored: a `Box` is a
rectangle in x-z, a `Prism` with ``axis = "y"`` is a polygon in x-z, a
`Bathymetry` is a profile z_b(x).

Units are metres; x along the flume (cross-shore), y lateral, z up.
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Annotated, Callable, ClassVar, Literal, Union

import numpy as np
from pydantic import (AfterValidator, BaseModel, BeforeValidator, ConfigDict, Field, ValidationInfo,
                      field_validator, model_validator)

from ..errors import InputError


def _to_list(v):
    return v.tolist() if isinstance(v, np.ndarray) else v


Real = Annotated[float, Field(allow_inf_nan=False, strict=True)]
"""A finite number (strict: a string or a boolean is not a number; an integer is)."""
PositiveReal = Annotated[float, Field(gt=0, allow_inf_nan=False, strict=True)]
Vec2 = Annotated[tuple[Real, Real], BeforeValidator(_to_list)]
Vec3 = Annotated[tuple[Real, Real, Real], BeforeValidator(_to_list)]
RealList = Annotated[list[Real], BeforeValidator(_to_list)]


def _unit_vector(v):
    n = np.asarray(v, float)
    if not np.linalg.norm(n) > 0:
        raise ValueError("normal must be a non-zero vector")
    return tuple(float(x) for x in n / np.linalg.norm(n))


def _case_relative(v, info: ValidationInfo):
    """The absolute path of a data file named in a case: relative to the case file's folder (the current
    folder for a case built in Python), so that the resolved case a run writes beside its output, and a
    resumed run, point at the same file from wherever they are read."""
    base = (info.context or {}).get("base_dir")
    p = Path(v).expanduser()
    if not p.is_absolute() and base is not None:
        p = Path(base) / p
    return os.path.abspath(p)


UnitVec3 = Annotated[Vec3, AfterValidator(_unit_vector)]
"""A direction, normalised to unit length (a zero vector is refused)."""
CasePath = Annotated[str, AfterValidator(_case_relative)]
"""A file path, stored absolute; relative paths are relative to the case file's directory."""

FACES = ("xmin", "xmax", "ymin", "ymax", "zmin", "zmax")
Face = Literal["xmin", "xmax", "ymin", "ymax", "zmin", "zmax", "top", "bottom"]


def python_function(v, instead):
    """`v` if it is None or callable, else the ValueError of a case file that gives a function (a case file is
    data and cannot hold code), telling what to give `instead`."""
    if v is not None and not callable(v):
        raise ValueError(f"a function is Python-API only: a case file is data and cannot hold code; {instead}")
    return v


class Spec(BaseModel):
    """Base of shoal's case objects: unknown keys are errors, values validated."""

    model_config = ConfigDict(extra="forbid", frozen=True, validate_default=True)


def _cols(dim):
    return [0, 2] if dim == 2 else [0, 1, 2]


class Shape(Spec):
    """A region of space (abstract)."""

    def contains(self, points, dim, pad=0.0):
        """Boolean mask of the `points` ((N, 3) world coordinates) inside the shape.

        `pad` is the wall thickness [m] the generator will use; only shells
        (`Tank`) depend on it.
        """
        raise NotImplementedError

    def bounds(self, dim, pad=0.0):
        """(lo, hi) corners of a box holding the shape (3 floats each; +-inf
        along an axis where the shape is unbounded)."""
        raise NotImplementedError


class Box(Shape):
    """An axis-aligned box [lo, hi] (a rectangle in x-z in 2D).

    As a solid: a block obstacle (only its surface layers become particles).
    As a fluid region: a block of water.
    """

    type: Literal["box"] = "box"
    lo: Vec3
    hi: Vec3

    @model_validator(mode="after")
    def _order(self):
        for a, (l, h) in zip("xyz", zip(self.lo, self.hi)):
            if h < l:
                raise ValueError(f"hi.{a} = {h} is below lo.{a} = {l}; hi must be >= lo on every axis")
        return self

    def contains(self, points, dim, pad=0.0):
        c = _cols(dim)
        lo, hi = np.asarray(self.lo)[c], np.asarray(self.hi)[c]
        p = points[:, c]
        return np.all((p >= lo) & (p <= hi), axis=1)

    def bounds(self, dim, pad=0.0):
        return np.array(self.lo, float), np.array(self.hi, float)


class Tank(Shape):
    """The walls of a tank or flume whose inside is the box [lo, hi].

    A shell of thickness `pad` (decided by the wall's layers) around the
    inside, without the faces named in `open` (default: the top). An open
    face leaves that end of the tank without a wall (e.g. ``open =
    ["top", "xmax"]`` for a flume outlet); walls reach up to hi.z.
    """

    type: Literal["tank"] = "tank"
    lo: Vec3
    hi: Vec3
    open: list[Face] = ["top"]

    shell: ClassVar[bool] = True  # the generator keeps all of it (its thickness is its layers)

    @field_validator("open")
    @classmethod
    def _faces(cls, v):
        return sorted({{"top": "zmax", "bottom": "zmin"}.get(f, f) for f in v})

    @model_validator(mode="after")
    def _order(self):
        for a, (l, h) in zip("xyz", zip(self.lo, self.hi)):
            if h <= l and not (a == "y" and h == l):
                raise ValueError(f"hi.{a} = {h} must be above lo.{a} = {l}")
        return self

    def _outer(self, dim, pad):
        lo = np.array(self.lo, float)
        hi = np.array(self.hi, float)
        olo, ohi = lo - pad, hi + pad
        for k, a in enumerate("xyz"):
            if f"{a}min" in self.open:
                olo[k] = lo[k]
            if f"{a}max" in self.open:
                ohi[k] = hi[k]
        return lo, hi, olo, ohi

    def contains(self, points, dim, pad=0.0):
        c = _cols(dim)
        lo, hi, olo, ohi = self._outer(dim, pad)
        p = points[:, c]
        in_outer = np.all((p >= olo[c]) & (p <= ohi[c]), axis=1)
        inside = np.all((p > lo[c]) & (p < hi[c]), axis=1)
        return in_outer & ~inside

    def bounds(self, dim, pad=0.0):
        _, _, olo, ohi = self._outer(dim, pad)
        return olo, ohi


class Plane(Shape):
    """The half-space behind a plane: points with (p - point) . normal < 0.

    `normal` points from the solid into the fluid (for a flat bed:
    ``normal = [0, 0, 1]``). Optional `lo`/`hi` clip it to a box.
    """

    type: Literal["plane"] = "plane"
    point: Vec3
    normal: UnitVec3
    lo: Vec3 | None = None
    hi: Vec3 | None = None

    def contains(self, points, dim, pad=0.0):
        n = np.asarray(self.normal)
        if dim == 2:
            n = n * [1.0, 0.0, 1.0]
        inside = (points - np.asarray(self.point)) @ n < 0.0
        return inside & _clip(points, dim, self.lo, self.hi)

    def bounds(self, dim, pad=0.0):
        return _clip_bounds(self.lo, self.hi)


class Slope(Shape):
    """A sloping bed (beach, ramp): solid below z = z0 + gradient (x - x0)
    for x0 <= x <= x1 (x1 default: no end), optionally clipped in y.

    ``gradient = 1/17`` is a beach rising 1 m per 17 m in +x.
    """

    type: Literal["slope"] = "slope"
    x0: Real
    z0: Real
    gradient: Real
    x1: Real | None = None
    y: Vec2 | None = None

    def level(self, x, y):
        """Surface level z [m] of the plane at the points (x, y) (also beyond x0 and x1)."""
        return self.z0 + self.gradient * (np.asarray(x, float) - self.x0)

    def level_gradient(self, x, y):
        """(dz/dx, dz/dy) of the surface at the points (x, y)."""
        x = np.asarray(x, float)
        return np.full(x.shape, float(self.gradient)), np.zeros(x.shape)

    def contains(self, points, dim, pad=0.0):
        x, z = points[:, 0], points[:, 2]
        m = (x >= self.x0) & (z < self.z0 + self.gradient * (x - self.x0))
        if self.x1 is not None:
            m &= x <= self.x1
        if self.y is not None and dim == 3:
            m &= (points[:, 1] >= self.y[0]) & (points[:, 1] <= self.y[1])
        return m

    def bounds(self, dim, pad=0.0):
        lo = np.array([self.x0, -np.inf, -np.inf])
        hi = np.array([np.inf if self.x1 is None else self.x1, np.inf, np.inf])
        if self.x1 is not None:
            hi[2] = max(self.z0, self.z0 + self.gradient * (self.x1 - self.x0))
        if self.y is not None:
            lo[1], hi[1] = self.y
        return lo, hi


class Prism(Shape):
    """A polygon extruded along an axis (bridge piers, channel constrictions).

    `vertices` are the polygon's corners in the plane normal to `axis`
    (for ``axis = "z"``: (x, y) pairs; ``"y"``: (x, z); ``"x"``: (y, z)),
    extruded from `lo` to `hi` along the axis. In 2D use ``axis = "y"``
    (a polygon in the x-z plane). Inside test: matplotlib's Path.
    """

    type: Literal["prism"] = "prism"
    vertices: Annotated[list[Vec2], Field(min_length=3)]
    axis: Literal["x", "y", "z"] = "z"
    lo: Real | None = None
    hi: Real | None = None

    @model_validator(mode="after")
    def _area(self):
        v = np.asarray(self.vertices, float)
        area = 0.5 * abs(np.dot(v[:, 0], np.roll(v[:, 1], -1)) - np.dot(v[:, 1], np.roll(v[:, 0], -1)))
        extent = float(np.max(np.ptp(v, axis=0)))
        if not area > 1e-9 * extent**2:
            raise ValueError("the polygon has zero area; give at least 3 corners not on one line")
        if self.lo is not None and self.hi is not None and self.hi < self.lo:
            raise ValueError(f"hi = {self.hi} is below lo = {self.lo}")
        return self

    def _axes(self):
        return {"z": (0, 1, 2), "y": (0, 2, 1), "x": (1, 2, 0)}[self.axis]

    def contains(self, points, dim, pad=0.0):
        from matplotlib.path import Path as MplPath

        a, b, e = self._axes()
        if dim == 2 and self.axis != "y":
            raise InputError(f"a prism along {self.axis!r} has no meaning in a 2D (x-z) case; use axis = 'y'")
        path = MplPath(np.asarray(self.vertices, float))
        m = path.contains_points(points[:, [a, b]], radius=1e-12)
        if dim == 3 or e != 1:
            m &= _within(points[:, e], self.lo, self.hi)
        return m

    def bounds(self, dim, pad=0.0):
        a, b, e = self._axes()
        v = np.asarray(self.vertices, float)
        lo = np.full(3, -np.inf)
        hi = np.full(3, np.inf)
        lo[[a, b]], hi[[a, b]] = v.min(0), v.max(0)
        lo[e] = -np.inf if self.lo is None else self.lo
        hi[e] = np.inf if self.hi is None else self.hi
        return lo, hi


class Cylinder(Shape):
    """A circular cylinder of `radius` around the axis through `center`
    (for ``axis = "z"``: center = (x, y)), from `lo` to `hi` along the axis
    (a round pier). In 2D use ``axis = "y"`` (a circle in x-z)."""

    type: Literal["cylinder"] = "cylinder"
    center: Vec2
    radius: PositiveReal
    axis: Literal["x", "y", "z"] = "z"
    lo: Real | None = None
    hi: Real | None = None

    def _axes(self):
        return {"z": (0, 1, 2), "y": (0, 2, 1), "x": (1, 2, 0)}[self.axis]

    def contains(self, points, dim, pad=0.0):
        a, b, e = self._axes()
        if dim == 2 and self.axis != "y":
            raise InputError(f"a cylinder along {self.axis!r} has no meaning in a 2D (x-z) case; use axis = 'y'")
        d2 = (points[:, a] - self.center[0]) ** 2 + (points[:, b] - self.center[1]) ** 2
        m = d2 <= self.radius**2
        if dim == 3 or e != 1:
            m &= _within(points[:, e], self.lo, self.hi)
        return m

    def bounds(self, dim, pad=0.0):
        a, b, e = self._axes()
        lo = np.full(3, -np.inf)
        hi = np.full(3, np.inf)
        lo[[a, b]] = np.subtract(self.center, self.radius)
        hi[[a, b]] = np.add(self.center, self.radius)
        lo[e] = -np.inf if self.lo is None else self.lo
        hi[e] = np.inf if self.hi is None else self.hi
        return lo, hi


class Profile(Spec):
    """A piecewise-linear bed profile z_b(x) through the points (x[i], z[i])."""

    x: Annotated[RealList, Field(min_length=2)]
    z: Annotated[RealList, Field(min_length=2)]

    @model_validator(mode="after")
    def _check(self):
        if len(self.x) != len(self.z):
            raise ValueError(f"x has {len(self.x)} values and z {len(self.z)}; give one z per x")
        if np.any(np.diff(self.x) <= 0):
            raise ValueError("x must increase strictly")
        return self


class HeightGrid(Spec):
    """A gridded height map: z[i][j] is the bed level at (x[i], y[j])."""

    x: Annotated[RealList, Field(min_length=2)]
    y: Annotated[RealList, Field(min_length=2)]
    z: Annotated[list[RealList], BeforeValidator(_to_list)]

    @model_validator(mode="after")
    def _check(self):
        z = self.z
        if len(z) != len(self.x) or any(len(row) != len(self.y) for row in z):
            raise ValueError(f"z must have {len(self.x)} rows (one per x) of {len(self.y)} values (one per y)")
        if np.any(np.diff(self.x) <= 0) or np.any(np.diff(self.y) <= 0):
            raise ValueError("x and y must increase strictly")
        return self


def _check_height_grid(path, x, y, z):
    """InputError unless x and y are increasing 1D arrays of at least 2 and z a finite (len(x), len(y)) array."""
    for name, a in (("x", x), ("y", y)):
        if a.ndim != 1 or len(a) < 2 or not np.all(np.isfinite(a)) or np.any(np.diff(a) <= 0):
            raise InputError(f"bathymetry file {str(path)!r}: {name} must be at least 2 finite, increasing values")
    if z.shape != (len(x), len(y)):
        raise InputError(f"bathymetry file {str(path)!r}: z is {z.shape}, not (len(x), len(y)) = {(len(x), len(y))}")
    if not np.all(np.isfinite(z)):
        raise InputError(f"bathymetry file {str(path)!r}: z holds {int(np.count_nonzero(~np.isfinite(z)))} NaN or "
                         "infinite values; give the bed's height at every node")


def _read_height_file(path):
    """(x, y, z) of a height map file: .npz with arrays x, y, z (z[i, j] at
    (x[i], y[j])), .npy of an (N, 3) array or .csv/.txt of x, y, z columns
    (one row per grid node, '#' comments, optional header)."""
    p = Path(path)
    if not p.is_file():
        raise InputError(f"bathymetry file {str(path)!r} not found")
    try:
        if p.suffix == ".npz":
            with np.load(p) as d:
                x, y, z = (np.asarray(d[k], float) for k in ("x", "y", "z"))
            _check_height_grid(path, x, y, z)
            return x, y, z
        if p.suffix == ".npy":
            pts = np.load(p)
        else:
            pts = np.genfromtxt(p, delimiter="," if p.suffix == ".csv" else None, comments="#",
                                skip_header=0, invalid_raise=True)
            pts = pts[np.all(np.isfinite(pts), axis=1)] if pts.ndim == 2 else pts
    except InputError:
        raise
    except Exception as exc:  # any parse failure is bad input
        raise InputError(f"bathymetry file {str(path)!r} could not be read: {' '.join(str(exc).split())}") from None
    pts = np.asarray(pts, float)
    if pts.ndim != 2 or pts.shape[1] != 3 or len(pts) < 4:
        raise InputError(f"bathymetry file {str(path)!r} must hold x, y, z columns for the nodes of a "
                         "regular grid (at least 2 x 2)")
    xs, ys = np.unique(pts[:, 0]), np.unique(pts[:, 1])
    if len(xs) * len(ys) != len(pts):
        raise InputError(f"bathymetry file {str(path)!r}: its {len(pts)} points are not the nodes of a "
                         f"regular grid ({len(xs)} distinct x by {len(ys)} distinct y)")
    z = np.full((len(xs), len(ys)), np.nan)
    z[np.searchsorted(xs, pts[:, 0]), np.searchsorted(ys, pts[:, 1])] = pts[:, 2]
    if not np.all(np.isfinite(z)):
        raise InputError(f"bathymetry file {str(path)!r}: some grid nodes are missing or repeated")
    return xs, ys, z


class Bathymetry(Shape):
    """The bed: solid below the surface z = z_b(x, y) (and above `base`).

    Give exactly one of

    - `profile`: a piecewise-linear z_b(x), uniform in y (beaches, bars);
    - `grid`: a height map on a regular (x, y) grid, interpolated bilinearly;
    - `file`: a height map file (.csv/.txt with x, y, z columns, .npy of an
      (N, 3) array, or .npz with x, y and z[i, j]); relative paths are
      relative to the case file;
    - `function`: a Python callable z_b(x, y) on arrays (Python API only: a
      case file is data and cannot hold code).

    Outside the profile or grid, z_b is held at its edge value.
    """

    type: Literal["bathymetry"] = "bathymetry"
    profile: Profile | None = None
    grid: HeightGrid | None = None
    file: CasePath | None = None
    function: Annotated[Callable | None, Field(exclude=True)] = None
    base: Real | None = None

    @field_validator("function", mode="before")
    @classmethod
    def _code(cls, v):
        return python_function(v, "give the bed as a profile, a grid or a file")

    @model_validator(mode="after")
    def _one(self):
        given = [k for k in ("profile", "grid", "file", "function") if getattr(self, k) is not None]
        if len(given) != 1:
            raise ValueError("give exactly one of profile, grid, file or function "
                             f"(got {', '.join(given) if given else 'none'})")
        return self

    def _grid(self):
        if self.grid is not None:
            return np.asarray(self.grid.x), np.asarray(self.grid.y), np.asarray(self.grid.z, float)
        return _read_height_file(self.file)

    def level(self, x, y):
        """Bed level z_b [m] at the points (x, y)."""
        x = np.asarray(x, float)
        y = np.asarray(y, float)
        if self.profile is not None:
            return np.interp(x, self.profile.x, self.profile.z)
        if self.function is not None:
            return np.broadcast_to(np.asarray(self.function(x, y), float), x.shape)
        from scipy.interpolate import RegularGridInterpolator

        gx, gy, gz = self._grid()
        f = RegularGridInterpolator((gx, gy), gz, method="linear")
        return f(np.column_stack([np.clip(x, gx[0], gx[-1]), np.clip(y, gy[0], gy[-1])]))

    def level_gradient(self, x, y):
        """(dz_b/dx, dz_b/dy) at the points (x, y), by centred differences over 1e-6 m (across a kink of
        a profile or a grid, the mean of the two sides)."""
        x = np.asarray(x, float)
        y = np.asarray(y, float)
        e = 1e-6
        return ((self.level(x + e, y) - self.level(x - e, y)) / (2 * e),
                (self.level(x, y + e) - self.level(x, y - e)) / (2 * e))

    def contains(self, points, dim, pad=0.0):
        zb = self.level(points[:, 0], points[:, 1])
        return (points[:, 2] < zb) & _within(points[:, 2], self.base, None)

    def bounds(self, dim, pad=0.0):
        lo = np.full(3, -np.inf)
        hi = np.full(3, np.inf)
        if self.profile is not None:
            hi[2] = max(self.profile.z)
        elif self.function is None:
            _, _, gz = self._grid()
            hi[2] = float(np.max(gz))
        lo[2] = -np.inf if self.base is None else self.base
        return lo, hi


class Mesh(Shape):
    """A closed triangulated surface read from an STL file (ASCII or binary),
    scaled by `scale` then shifted by `offset`; inside by the generalized
    winding number (see :mod:`shoal.geometry.mesh`). Relative paths are
    relative to the case file. 3D cases only."""

    type: Literal["mesh"] = "mesh"
    file: CasePath
    scale: PositiveReal = 1.0
    offset: Vec3 = (0.0, 0.0, 0.0)

    def triangles(self):
        from .mesh import load_stl

        return load_stl(self.file, scale=self.scale, offset=self.offset)

    def contains(self, points, dim, pad=0.0):
        from .mesh import points_inside

        if dim == 2:
            raise InputError("mesh shapes are for 3D cases; in 2D use a prism with axis = 'y'")
        return points_inside(self.triangles(), points)

    def bounds(self, dim, pad=0.0):
        from .mesh import mesh_bounds

        return mesh_bounds(self.triangles())


def _within(v, lo, hi):
    m = np.ones(len(v), bool)
    if lo is not None:
        m &= v >= lo
    if hi is not None:
        m &= v <= hi
    return m


def _clip(points, dim, lo, hi):
    m = np.ones(len(points), bool)
    c = _cols(dim)
    if lo is not None:
        m &= np.all(points[:, c] >= np.asarray(lo)[c], axis=1)
    if hi is not None:
        m &= np.all(points[:, c] <= np.asarray(hi)[c], axis=1)
    return m


def _clip_bounds(lo, hi):
    return (np.full(3, -np.inf) if lo is None else np.array(lo, float),
            np.full(3, np.inf) if hi is None else np.array(hi, float))


AnyShape = Annotated[Union[Box, Tank, Plane, Slope, Prism, Cylinder, Bathymetry, Mesh],
                     Field(discriminator="type")]
"""Any shape, selected by its ``type`` key."""

SHAPES = {c.model_fields["type"].default: c for c in (Box, Tank, Plane, Slope, Prism, Cylinder, Bathymetry, Mesh)}
