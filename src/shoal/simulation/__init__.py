"""Simulation loop, schedules and callbacks."""

from .schedules import IterationInterval, TimeInterval, WallTimeInterval
from .simulation import Callback, Simulation

__all__ = ["Simulation", "Callback", "TimeInterval", "IterationInterval", "WallTimeInterval"]
