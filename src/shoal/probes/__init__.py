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
  DualSPHysics's MeasureTool.
"""

from __future__ import annotations

import csv
from pathlib import Path
from typing import Annotated, Literal, Union

import numpy as np
from pydantic import Field, model_validator

from ..geometry.shapes import PositiveReal, Real, Spec, Vec3


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


AnyProbe = Annotated[Union[PointProbes, WaveGauge], Field(discriminator="type")]


def surface_level(z, s, threshold=0.5):
    """Highest z where the kernel sum s (sampled upwards at z) is >= threshold,
    linearly interpolated to the crossing; NaN if the line is all dry, z[-1]
    if it is all wet."""
    wet = s >= threshold
    if not wet.any():
        return float("nan")
    k = int(np.flatnonzero(wet)[-1])
    if k == len(z) - 1:
        return float(z[-1])
    s0, s1 = s[k], s[k + 1]
    return float(z[k] + (s0 - threshold) / (s0 - s1) * (z[k + 1] - z[k]))


class ProbeRecorder:
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
