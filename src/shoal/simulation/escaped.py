"""The record of particles that leave the domain: ``escaped.csv``.

A particle that leaves the domain box is taken out of the computation at
the next sort (`Model.sort`). `EscapedRecorder` is the Model's
``on_escape`` hook: it appends one row per particle, when it is found
outside, to ``escaped.csv``:

``id, kind, time, x, y, z, u, v, w``
    the particle id, its kind (0 fluid, 1-4 boundary), the simulated time
    [s] at which it was found outside, its position [m] and velocity [m/s]
    then (world coordinates; y = 0 in 2D).

As a Simulation callback (every step) it also stops the run, with an
`InstabilityError` naming how many fluid particles left and where the last
one went, when more than `max_fraction` of the fluid particles has left
(``max_escaped_fraction`` of the case; DualSPHysics's PartsOutMax).
"""

from __future__ import annotations

import csv
from pathlib import Path

import numpy as np

from ..errors import InstabilityError
from ..physics.spec import FLUID
from ..probes.recorder_state import Recorder

HEADER = ["id", "kind", "time", "x", "y", "z", "u", "v", "w"]


class EscapedRecorder(Recorder):
    """Append escaped particles to ``out_dir/escaped.csv``; stop the run when
    more than `max_fraction` of the fluid has left.

    Parameters
    ----------
    out_dir : path
        Run directory.
    model : Model
        The model; the recorder installs itself as ``model.on_escape``.
    max_fraction : float
        Largest fraction (0, 1] of the fluid particles allowed to leave; 1:
        the run never stops for it.
    name : str
        The file's name (an MPI rank other than 0 writes ``escaped.rank<r>.csv``).
    resume_bytes : int, optional
        On a resume, the file's length at the checkpoint: the file is cut back
        to it and appended to (None or 0: a new file).
    """

    def __init__(self, out_dir, model, max_fraction=1.0, name="escaped.csv", resume_bytes=None):
        self.path = Path(out_dir) / name
        self.max_fraction = float(max_fraction)
        # the fluid at the start, for the stop check (a rank of a run on several does not check alone)
        kinds = model.host(model.kind, 0, model.n_total) if self.max_fraction < 1.0 else np.zeros(0)
        self.n_fluid0 = int(np.count_nonzero(kinds == FLUID))
        if resume_bytes and self.path.exists():
            self.file = open(self.path, "r+", newline="")
            self.file.truncate(int(resume_bytes))
            self.file.seek(0, 2)
            self.writer = csv.writer(self.file)
        else:
            self.file = open(self.path, "w", newline="")
            self.writer = csv.writer(self.file)
            self.writer.writerow(HEADER)
        self.file.flush()
        self.last = None
        model.on_escape = self.on_escape

    def on_escape(self, model, start, stop):
        """Record rows start..stop of the model's arrays (the particles that just left)."""
        p = model.host(model.pos, start, stop).astype(np.float64)
        v = model.host(model.vel, start, stop).astype(np.float64)
        ids = model.host(model.idp, start, stop)
        kinds = model.host(model.kind, start, stop)
        if model.dim == 2:
            z = np.zeros(len(p))
            p = np.column_stack([p[:, 0], z, p[:, 1]])
            v = np.column_stack([v[:, 0], z, v[:, 1]])
        t = model.time
        for k in range(len(ids)):
            self.writer.writerow([int(ids[k]), int(kinds[k]), f"{t:.9g}"] + [f"{x:.9g}" for x in p[k]] +
                                 [f"{x:.9g}" for x in v[k]])
        self.file.flush()
        self.last = (t, p[-1].copy()) if len(ids) else self.last

    def fluid_escaped(self, model):
        """Number of fluid particles that have left the domain: those missing from the count at the start,
        less what open boundaries created and removed (`shoal.particle_buffers`)."""
        b = model.buffers
        return self.n_fluid0 + ((b.created - b.removed) if b is not None else 0) - model.n_fluid

    def __call__(self, sim):
        """Stop the run if too much fluid has left (a callback, every step)."""
        if self.max_fraction >= 1.0 or sim.model.n_escaped == 0:
            return
        gone = self.fluid_escaped(sim.model)
        if gone > self.max_fraction * self.n_fluid0:
            m = sim.model
            lo, hi = m.grid.lo.tolist(), m.grid.hi.tolist()
            where = ""
            if self.last is not None:
                x = self.last[1]
                where = f"; the last left at (x, y, z) = ({x[0]:.4g}, {x[1]:.4g}, {x[2]:.4g}) m, t = {self.last[0]:.6g} s"
            raise InstabilityError(
                f"{gone} of {self.n_fluid0} fluid particles ({100.0 * gone / self.n_fluid0:.1f} %) have left the "
                f"domain by step {sim.step_count}, t = {sim.time:.6g} s, more than max_escaped_fraction = "
                f"{self.max_fraction:g}{where} (domain {lo} - {hi} m, internal coordinates; list in "
                f"{self.path.name}): enlarge the domain, or check the inflow, the walls and the time step")

    def close(self):
        self.file.close()
