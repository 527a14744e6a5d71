"""Analysis of simulation results against reference data."""

from .front import surge_front
from .reference import load_reference, mean_relative_error

__all__ = ["surge_front", "load_reference", "mean_relative_error"]
