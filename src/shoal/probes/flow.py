"""Flow through a cross-section: the volume of water that has passed a plane, and the flow rate.

A `FlowGauge` (``type = "flow"``) is DualSPHysics's FlowTool for one section: the plane
``axis = at`` (x, y or z = const), limited in the other two coordinates to [lo, hi]. Two
measures, both over the fluid particles:

* **Volume passed** (exact, by counting): each fluid particle's coordinate along `axis` is kept
  from one sample to the next (by particle id); every particle that went from below `at` to at or
  above it since the last sample, and is within the section's extent now, adds its volume
  V0 = m / rho0 = dp^dim, and every one that went back subtracts it. The running sum is the net
  volume (mass / rho0) that has passed the section in the +axis direction since t = 0, exact
  for the particles, so the volume between two sections changes by exactly what passed them.
  With a periodic axis the path between samples is taken the short way round the period and
  every image of the plane counts. The mean flow rate over the sampling interval is the change
  of that volume over the interval.
* **Instantaneous rate** (a slab sum): Q = (1 / delta) sum_j (m / rho_j) u_j . n over the fluid
  particles within delta / 2 of the plane (delta = 2 dp) and inside the extent -- the volume flux
  through the slab, the SPH estimate of integral u . n dA (e.g. Monaghan 2005, Rep. Prog. Phys.
  68, 1703, section 2 for particle sums as integrals). On a lattice two layers always lie in a
  slab two spacings wide, whatever its offset, so a uniform stream is measured exactly.
* **Wetted area** (a slab sum): A = (1 / delta) sum_j m / rho_j over the same particles -- the area of the
  section the water fills (2D: its depth) from the particles' volumes, with no free surface to find; Q / A
  is the section's mean velocity. Where the flow has loosened the particles' arrangement, their continuity
  densities no longer give the space they take and A reads low: 3-5 % below the wave gauge's surface and
  the pressure head in the reservoir of the sluice-gate case at y / dp = 30 (`shoal.validation.sluice_gate`).

Units: 3D volumes [m^3] and rates [m^3/s]; 2D runs are per metre of width ([m^2], [m^2/s]).
"""

from __future__ import annotations

import csv
import math
from pathlib import Path

import numpy as np

from .recorder_state import Recorder, recorder_state, restore_recorder_files

AXES = {"x": 0, "y": 1, "z": 2}


def section_mask(positions, spec, dim):
    """(N,) bool: the particles within the section's extent in the two coordinates other than
    `spec.axis` (y ignored in 2D)."""
    pos = np.asarray(positions, float).reshape(-1, 3)
    a = AXES[spec.axis]
    inside = np.ones(len(pos), bool)
    for k in range(3):
        if k == a or (dim == 2 and k == 1):
            continue
        if spec.lo is not None:
            inside &= pos[:, k] >= spec.lo[k]
        if spec.hi is not None:
            inside &= pos[:, k] <= spec.hi[k]
    return inside


def crossings(prev, now, at, period=0.0):
    """Signed number of times each particle crossed the plane ``coordinate = at`` between two samples.

    Parameters
    ----------
    prev, now : ndarray, shape (N,)
        The coordinate along the gauge's axis at the previous sample (NaN: not known then, e.g. a
        particle this process did not hold) and now [m].
    at : float
        The plane [m].
    period : float
        The period length along the axis [m], 0 if the axis is not periodic. With a period the
        path is the shortest one round it, and every image ``at + k period`` counts.

    Returns
    -------
    ndarray of int64, shape (N,)
        +1 for a crossing towards +axis (from below `at` to at or above it), -1 for one back, 0
        for none (and for unknown `prev`).
    """
    prev = np.asarray(prev, float)
    now = np.asarray(now, float)
    known = np.isfinite(prev)
    p = np.where(known, prev, at)
    if period > 0.0:
        d = now - p
        d -= period * np.round(d / period)
        n = np.floor((p + d - at) / period) - np.floor((p - at) / period)
    else:
        n = (now >= at).astype(float) - (p >= at).astype(float)
    return np.where(known, n, 0.0).astype(np.int64)


def slab_rate(positions, velocities, density, spec, dim, mass, dp):
    """The instantaneous volume flux Q = (1/delta) sum (m / rho_j) u_j . n through the slab of
    width delta = 2 dp centred on the plane, within the section's extent, and the wetted area
    A = (1/delta) sum m / rho_j (arrays of fluid particles only): (Q [m^3/s; 2D: m^2/s], A [m^2;
    2D: m])."""
    a = AXES[spec.axis]
    pos = np.asarray(positions, float).reshape(-1, 3)
    delta = 2.0 * dp
    sel = (pos[:, a] >= spec.at - 0.5 * delta) & (pos[:, a] < spec.at + 0.5 * delta) & section_mask(pos, spec, dim)
    u = np.asarray(velocities, float).reshape(-1, 3)[sel, a]
    vol = mass / np.asarray(density, float)[sel]
    return float(np.sum(vol * u) / delta), float(np.sum(vol) / delta)


def flow_measure(positions, velocities, density, kinds, ids, spec, dim, dp, mass, prev, n_ids, period=0.0):
    """One sample of a `FlowGauge` over a set of particles.

    Parameters
    ----------
    positions, velocities : ndarray, shape (N, 3)
        World coordinates [m] and velocities [m/s] (y = 0 in 2D).
    density : ndarray, shape (N,)
        [kg/m^3].
    kinds, ids : ndarray, shape (N,)
        Particle kinds (0 = fluid) and ids.
    spec : FlowGauge
    dim : {2, 3}
    dp, mass : float
        Particle spacing [m] and mass [kg; 2D: kg/m].
    prev : ndarray, shape (n_ids,), or None
        Each particle's coordinate along the axis at the previous sample (NaN: unknown).
    n_ids : int
        Number of particle ids of the case.
    period : float
        Period length along the axis [m] (0: not periodic).

    Returns
    -------
    now : ndarray, shape (n_ids,)
        The fluid particles' coordinates along the axis now, by id (NaN for the others).
    crossed : int or None
        Net particles that crossed the section towards +axis since `prev` and are inside its
        extent now (None when `prev` is None).
    rate_slab, area_slab : float
        `slab_rate`: the flux [m^3/s; 2D: m^2/s] and the wetted area [m^2; 2D: m].
    """
    pos = np.asarray(positions, float).reshape(-1, 3)
    fluid = np.asarray(kinds) == 0
    a = AXES[spec.axis]
    c = pos[fluid, a]
    fid = np.asarray(ids, np.int64)[fluid]
    now = np.full(max(int(n_ids), int(fid.max(initial=-1)) + 1), np.nan)
    now[fid] = c
    crossed = None
    if prev is not None:
        prev = np.asarray(prev, float)
        if len(prev) < len(now):  # ids beyond the previous sample's (a model rebuilt from a snapshot)
            prev = np.concatenate([prev, np.full(len(now) - len(prev), np.nan)])
        n = crossings(prev[fid], c, spec.at, period)
        crossed = int(np.sum(n[section_mask(pos[fluid], spec, dim)]))
    vel = np.asarray(velocities, float).reshape(-1, 3)[fluid]
    q, area = slab_rate(pos[fluid], vel, np.asarray(density, float)[fluid], spec, dim, mass, dp)
    return now, crossed, q, area


class FlowRecorder(Recorder):
    """Samples a `FlowGauge` (`Model.flow_sample`, NumPy over the host copies of the particle
    arrays; under MPI each rank's owned particles, reduced over the ranks) and appends
    ``time, volume, rate, rate_slab, area_slab`` to ``flow_<name>.csv``.

    Its state -- the running volume, the previous sample's time and each particle's coordinate
    along the axis (by id) -- is kept in checkpoints, so a resumed run counts on.
    """

    def __init__(self, spec, out_dir, model):
        self.spec = spec
        self.path = Path(out_dir) / f"flow_{spec.name}.csv"
        self.file = open(self.path, "w", newline="")
        self.writer = csv.writer(self.file)
        self.writer.writerow(["time", "volume", "rate", "rate_slab", "area_slab"])
        self.rows = []
        self.prev = None            # (n_ids,) coordinate along the axis at the last sample, NaN unknown
        self.volume = 0.0
        self.t_prev = math.nan

    def __call__(self, sim):
        prev, crossed, q, area = sim.model.flow_sample(self.spec, self.prev)
        self.prev = prev
        rate = math.nan
        if crossed is not None:  # None: the first sample (nothing to compare with)
            dv = crossed * sim.model.particle_volume
            self.volume += dv
            if sim.time > self.t_prev:
                rate = dv / (sim.time - self.t_prev)
        self.t_prev = float(sim.time)
        row = [sim.time, self.volume, rate, q, area]
        self.rows.append(row)
        self.writer.writerow([f"{v:.9g}" for v in row])
        self.file.flush()

    def checkpoint_state(self):
        state = recorder_state(self)
        state["volume"] = float(self.volume)
        if math.isfinite(self.t_prev):
            state["t_prev"] = float(self.t_prev)
        if self.prev is not None:
            state["prev"] = np.asarray(self.prev, np.float64)
        return state

    def restore_checkpoint_state(self, scalars, arrays, backup=None):
        restore_recorder_files(self, scalars, arrays, backup)
        self.volume = float(scalars.get("volume", 0.0))
        self.t_prev = float(scalars.get("t_prev", math.nan))
        self.prev = arrays.get("prev")

    def close(self):
        self.file.close()
