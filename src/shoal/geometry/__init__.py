"""Geometry: shapes, and the particles generated from them.

* :mod:`shoal.geometry.shapes` -- `Box`, `Tank`, `Plane`, `Slope`, `Prism`,
  `Cylinder`, `Bathymetry`, `Mesh` (STL): regions that solids and fluid
  regions are made of;
* :mod:`shoal.geometry.generate` -- lattice filling and wall layers;
* :mod:`shoal.geometry.normals` -- the walls' ghost vectors (mirror images
  across the wall surface) for the mDBC boundary condition;
* :mod:`shoal.geometry.mesh` -- STL reading and inside tests;
* :mod:`shoal.geometry.lattice` -- low-level lattice helpers.
"""

from .generate import Particles, generate
from .lattice import box_fill, hollow_box_walls, tank_walls
from .shapes import (SHAPES, Bathymetry, Box, Cylinder, HeightGrid, Mesh, Plane, Prism, Profile, Shape, Slope,
                     Tank)

__all__ = ["Shape", "Box", "Tank", "Plane", "Slope", "Prism", "Cylinder", "Bathymetry", "Profile", "HeightGrid",
           "Mesh", "SHAPES", "Particles", "generate", "box_fill", "tank_walls", "hollow_box_walls"]
