"""What a run tells its user while it goes: ``run.log``, warnings, a progress bar."""

from __future__ import annotations

import logging
import sys
import time as _time


def open_run_log(out_dir, append=False):
    """The run's logger, writing ``out_dir/run.log`` (appending to it on a resume)."""
    log = logging.getLogger(f"shoal.run.{out_dir}")
    log.setLevel(logging.INFO)
    log.propagate = False
    for h in list(log.handlers):
        log.removeHandler(h)
    fh = logging.FileHandler(out_dir / "run.log", mode="a" if append else "w")
    fh.setFormatter(logging.Formatter("%(asctime)s %(levelname)s %(message)s"))
    log.addHandler(fh)
    return log


def close_run_log(log):
    """Close ``run.log`` (a failing close, a full disk, is ignored: the run's outcome is already decided)."""
    for h in list(log.handlers):
        try:
            h.close()
        except OSError:
            pass
        log.removeHandler(h)


def print_warning(message):
    """One line ``shoal: warning: ...`` on standard error."""
    sys.stderr.write(f"shoal: warning: {message}\n")


class ProgressBar:
    """A rich progress bar: simulated time, dt, steps/s and ETA."""

    def __init__(self, end_time, enabled):
        self.enabled = enabled
        self.end_time = end_time
        self.t0 = _time.perf_counter()
        self.last_steps = 0
        if enabled:
            from rich.progress import BarColumn, Progress, TextColumn, TimeRemainingColumn

            self.bar = Progress(TextColumn("[bold]t = {task.fields[t]:.4f} s"), BarColumn(),
                                TextColumn("dt = {task.fields[dt]:.2e} s  {task.fields[sps]:.0f} steps/s"),
                                TimeRemainingColumn(), transient=False)
            self.task = self.bar.add_task("run", total=end_time, t=0.0, dt=0.0, sps=0.0)
            self.bar.start()

    def __call__(self, sim):
        if not self.enabled:
            return
        now = _time.perf_counter()
        sps = (sim.step_count - self.last_steps) / max(now - self.t0, 1e-9)
        self.t0, self.last_steps = now, sim.step_count
        self.bar.update(self.task, completed=sim.time, t=sim.time, dt=sim.dt or 0.0, sps=sps)

    def stop(self):
        if self.enabled:
            self.bar.stop()
