"""A floating body as case data: what a solid that the water moves needs besides its shape.

`FloatingBody` validates what a case gives (density or mass, centre of gravity, inertia, initial
velocities, fixed degrees of freedom, a hinge, spring-dampers) and builds the `shoal.rigid_body.RigidBody`
of a body from its particles. In a case file, a solid's ``floating`` table (`shoal.case.Solid`)::

    floating = { density = 500, fixed = ["y", "rx", "rz"] }
    floating = { mass = 12.5, centre_of_gravity = [1.0, 0.0, 0.2], inertia = [0.4, 0.5, 0.3] }
    floating = { density = 800, hinge = { point = [2.0, 0.0, 0.5], axis = [0, 1, 0] } }
    floating = { density = 2000, friction = 0.4 }
"""

from __future__ import annotations

from typing import Annotated, Literal

import numpy as np
from pydantic import BeforeValidator, Field, field_validator, model_validator

from .body_loads import SpringDamper
from .geometry.shapes import CasePath, PositiveReal, Spec, Vec3
from .mass_properties import check_inertia, given_mass_properties, mass_properties
from .rigid_body import RigidBody


def _inertia_table(v):
    """A 3-vector of moments is the diagonal of the table."""
    if isinstance(v, np.ndarray):
        v = v.tolist()
    if isinstance(v, (list, tuple)) and len(v) == 3 and not any(isinstance(x, (list, tuple)) for x in v):
        return [[v[0], 0.0, 0.0], [0.0, v[1], 0.0], [0.0, 0.0, v[2]]]
    return v


Inertia = Annotated[tuple[Vec3, Vec3, Vec3], BeforeValidator(_inertia_table)]


class Hinge(Spec):
    """A hinge to the ground: the body only rotates about ``axis`` through ``point`` [m] (world, fixed)."""

    point: Vec3
    axis: Vec3

    @field_validator("axis")
    @classmethod
    def _an_axis(cls, v):
        if not np.linalg.norm(np.asarray(v, float)) > 0:
            raise ValueError("axis = [0, 0, 0] is no axis; give the hinge's direction, e.g. [0, 1, 0]")
        return v


class FloatingBody(Spec):
    """A rigid body that the water moves (issue 32): its mass properties, initial motion and constraints.

    Attributes
    ----------
    density : float, optional
        rho [kg/m^3] of a homogeneous body: each particle's mass is rho dp^dim. Give this or `mass`.
    mass : float, optional
        M [kg] (2D: kg per metre of width), shared equally among the particles.
    centre_of_gravity : 3 floats, optional
        [m] at t = 0; default: the particles' centroid.
    inertia : 3 floats or 3 x 3 table, optional
        [kg m^2] (2D: per metre of width) about the centre of gravity, world axes at t = 0 (3 floats: the
        diagonal); symmetric, positive definite, its principal moments obeying I1 + I2 >= I3. Default:
        the particles' (`shoal.mass_properties.mass_properties`), scaled to `mass` and moved to
        `centre_of_gravity` when those are given.
    velocity : 3 floats
        Initial velocity of the centre of gravity [m/s].
    angular_velocity : 3 floats
        Initial angular velocity [rad/s], world frame.
    fixed : list of str
        Degrees of freedom held fixed: "x", "y", "z", "rx", "ry", "rz" (world axes; rotations about the
        centre of gravity). Rotations are free about three axes, one or none. 2D fixes y, rx and rz itself.
    hinge : Hinge, optional
        Rotation about a fixed axis through a fixed point only. Not with `fixed` or `velocity`.
    springs : list of shoal.body_loads.SpringDamper
        Linear spring-dampers from body points to fixed anchors.
    friction : float
        Coulomb's friction coefficient mu >= 0 of the body's contacts with the walls and the other bodies
        (`shoal.physics.contact`; two floating bodies take the mean of theirs); default 0, frictionless.
    release_time : float
        [s] The body is held where it starts until this time, its loads measured and written, so that the
        water settles around it before it moves (DualSPHysics's ``FtPause``); default 0, free from the start.
    interval : float, optional
        Seconds between the rows of the body's CSV (``body_<name>.csv``, `shoal.probes.body_recorder`);
        default: the case's output interval.
    """

    density: PositiveReal | None = None
    mass: PositiveReal | None = None
    centre_of_gravity: Vec3 | None = None
    inertia: Inertia | None = None
    velocity: Vec3 = (0.0, 0.0, 0.0)
    angular_velocity: Vec3 = (0.0, 0.0, 0.0)
    fixed: list[Literal["x", "y", "z", "rx", "ry", "rz"]] = Field(default_factory=list)
    hinge: Hinge | None = None
    springs: list[SpringDamper] = Field(default_factory=list)
    friction: Annotated[float, Field(ge=0, allow_inf_nan=False, strict=True)] = 0.0
    release_time: Annotated[float, Field(ge=0, allow_inf_nan=False)] = 0.0
    interval: PositiveReal | None = None

    @field_validator("inertia")
    @classmethod
    def _an_inertia(cls, v):
        if v is not None:
            check_inertia(np.array(v, float))
        return v

    @field_validator("fixed")
    @classmethod
    def _dofs(cls, v):
        if len(set(v)) != len(v):
            twice = sorted({d for d in v if v.count(d) > 1})
            raise ValueError(f"{', '.join(twice)} given twice; name each fixed degree of freedom once")
        free = [r for r in ("rx", "ry", "rz") if r not in v]
        if len(free) == 2:
            raise ValueError(f"fixes one rotation and leaves {free[0]} and {free[1]} free; a body rotates about "
                             "all three axes, about one (fix the two others) or none")
        return v

    @model_validator(mode="after")
    def _consistent(self):
        if (self.density is None) == (self.mass is None):
            raise ValueError("give the body's density or its mass, one of the two"
                             if self.density is None else
                             "density and mass both given; give one (the mass fixes the density)")
        if self.hinge is not None and self.fixed:
            raise ValueError("a hinge already fixes every degree of freedom but its rotation; "
                             "leave out fixed")
        if self.hinge is not None and any(self.velocity):
            raise ValueError("a hinged body's velocity follows from its angular velocity about the "
                             "hinge; leave out velocity")
        return self

    def mass_properties(self, points, dp, dim):
        """The body's `shoal.mass_properties.MassProperties`: from its particles ((N, 3) positions [m],
        spacing `dp` [m], dimension `dim`), with the values given here in place of theirs."""
        computed = mass_properties(points, dp, dim, density=self.density, mass=self.mass)
        return given_mass_properties(computed, centre=self.centre_of_gravity,
                                     inertia=None if self.inertia is None else np.array(self.inertia, float))

    def rigid_body(self, points, dp, dim):
        """(`shoal.rigid_body.RigidBody`, its initial `shoal.rigid_body.BodyState`) of the body made of the
        particles at `points` ((N, 3) [m], spacing `dp` [m], dimension `dim`)."""
        hinge = self.hinge
        body = RigidBody(self.mass_properties(points, dp, dim), dim=dim, fixed=self.fixed,
                         hinge_point=None if hinge is None else hinge.point,
                         hinge_axis=None if hinge is None else hinge.axis)
        return body, body.initial_state(self.velocity, self.angular_velocity)


class Fairlead(Spec):
    """Where a mooring line holds a floating body: the point of the body named `body` (a floating solid's
    name) that is at ``point`` [m] at t = 0."""

    body: Annotated[str, Field(min_length=1)]
    point: Vec3


class MooringLines(Spec):
    """Mooring lines computed by MoorDyn v2 (`shoal.mooring`), holding floating bodies at their fairleads.

    Attributes
    ----------
    file : str
        A MoorDyn v2 input file (relative to the case file's folder). Its POINTS of type ``Coupled`` are the
        fairleads, in the order of `fairleads`.
    fairleads : list of Fairlead
        One per coupled point of the file, in its order.
    name : str
        Starts the names of the lines' CSV files: ``<name>_line<k>.csv`` (fairlead and anchor tension) and
        ``<name>_line<k>_nodes.csv`` (node positions), k numbered as in the file.
    origin : 3 floats
        The point [m] of the case's frame that is the origin of MoorDyn's (its z = 0 is the still-water
        level: a case with its bed at z = 0 and water d deep has origin = [0, 0, d]).
    width : float, optional
        2D cases only, and required there: the width [m] of the flume that the lines hold (MoorDyn's forces
        are whole, a 2D body's per metre of width: they are divided by it).
    interval : float, optional
        Seconds between the rows of the CSV files; default: the case's output interval.
    """

    file: CasePath
    fairleads: Annotated[list[Fairlead], Field(min_length=1)]
    name: Annotated[str, Field(min_length=1, pattern=r"^[A-Za-z0-9_.\-]+$")] = "mooring"
    origin: Vec3 = (0.0, 0.0, 0.0)
    width: PositiveReal | None = None
    interval: PositiveReal | None = None
