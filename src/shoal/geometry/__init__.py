"""Particle generation from simple solids: filled boxes and walls."""

from .lattice import box_fill, tank_walls, hollow_box_walls

__all__ = ["box_fill", "tank_walls", "hollow_box_walls"]
