"""Neighbour search: a uniform cell grid with particles sorted by cell."""

from .grid import CellGrid
from .brute import brute_force_pairs

__all__ = ["CellGrid", "brute_force_pairs"]
