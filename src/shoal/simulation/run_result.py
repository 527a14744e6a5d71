"""What a finished run reports (`RunResult`) and records of its set-up (`run_summary`)."""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

from ..model import Model
from .simulation import Simulation


@dataclass
class RunResult:
    """What a finished run reports."""

    out_dir: Path
    steps: int
    time: float
    wall_seconds: float
    compile_seconds: float
    particles: int
    escaped: int
    snapshots: int
    model: Model
    simulation: Simulation
    checkpoint: Path | None = None  # the last checkpoint written (the final state)
    resumed_from: Path | None = None  # the checkpoint a resumed run started from

    @property
    def particle_steps_per_second(self):
        """Particles times steps over the run's wall time less the compiling done inside it (kernels first
        called while the model was built are compiled outside `wall_seconds`: subtracting all of
        `compile_seconds` could leave nothing, or less than the run took)."""
        run = self.wall_seconds - self.simulation.compile_seconds
        return self.particles * self.steps / run if run > 0 else math.nan


def run_summary(case, model):
    """What a run records about its set-up (``resolved.json``)."""
    lo, hi = case.resolved_domain()
    counts = case.particles().counts()
    return {
        "name": case.name, "dim": case.dim, "dp": case.dp, "particles": counts, "total_particles": model.n_total,
        "domain": [lo.tolist(), hi.tolist()], "end_time": case.end_time, "output_interval": case.output.interval,
        "parameters": case.parameters, "data_files": case.data_files(),
    }
