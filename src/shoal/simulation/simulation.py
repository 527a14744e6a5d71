"""Simulation: runs a Model with a time integrator, per-step stages and scheduled callbacks.

Each step is the integrator's, then the `stages` in their stated order
(`shoal.simulation.stages`: damping, relaxation, density filter, stability check).

Everything periodic (writers, probes, checks, progress) is a callback with
a schedule. Output times of `TimeInterval` schedules are hit exactly: the
step before one is shortened. A callback whose function has a
``finalize(sim)`` method also runs that when the run ends (`finalize`): the
last snapshot, the last checkpoint.
"""

from __future__ import annotations

import math
import time as _time

from ..errors import InstabilityError
from ..faults import reached
from ..timestepping import make_integrator
from .stages import default_stages


class Callback:
    """A function ``func(sim)`` run when ``schedule.due(sim)``."""

    def __init__(self, func, schedule, name=None):
        self.func = func
        self.schedule = schedule
        self.name = name or getattr(func, "__name__", "callback")


class Simulation:
    """Run a `Model` from t = 0 to `end_time`.

    Parameters
    ----------
    model : Model or Case
        A Case is turned into its Model on `backend` (particles generated,
        scheme compiled).
    end_time : float, optional
        Simulated time to reach [s] (default: the case's end_time).
    dt_floor_ratio : float
        The run stops as unstable if dt falls below this fraction of the
        first step's dt.
    check_every : int
        Steps between NaN / density checks.
    backend : str
        Backend of the Model built from a Case ("cpu" or "cuda").
    """

    def __init__(self, model, end_time=None, dt_floor_ratio=1e-3, check_every=1, backend="cpu"):
        from ..case import Case

        self.damping = []
        self.relaxation = []  # shoal.relaxation.RelaxationTerms: the case's zones resolved
        if isinstance(model, Case):
            from ..build import build_model

            self.case = model
            self.damping = list(model.damping)
            self.relaxation = model.relaxation_terms()
            if end_time is None:
                end_time = model.end_time
            model = build_model(model, backend)
        if end_time is None:
            raise TypeError("Simulation(model, end_time): give the end time [s] (or pass a Case)")
        self.model = model
        self.end_time = float(end_time)
        self.integrator = make_integrator(model)
        self.callbacks = []
        self.time = 0.0
        self.step_count = 0
        self.dt = None
        self.dt0 = None
        self.dt_floor_ratio = dt_floor_ratio
        self.check_every = check_every
        self.wall_seconds = 0.0  # the finished `run` calls' wall time (and, on a resume, the checkpoint's)
        self._run_t0 = None  # perf_counter at the start of the `run` call in progress
        self.compile_seconds = 0.0  # the part of wall_seconds spent on first calls (compiling, cache loads)
        self.stop_requested = False  # set (e.g. by a signal handler) to end the run after the current step
        # func(sim) run after every step's callbacks, with no schedule and no state in checkpoints
        # (the MPI ranks' agreement on a stop signal)
        self.after_step = []
        self.started = False  # the initial sort, check and t = 0 callbacks are done (or restored from a checkpoint)
        self.finalized_step = None  # the step `finalize` last ran at
        self.options = model.options
        self.stages = default_stages(model.options, check_every, open_boundaries=model.buffers is not None)

    def add_callback(self, func, schedule, name=None):
        """Attach ``func(sim)`` to run on `schedule`."""
        cb = Callback(func, schedule, name)
        self.callbacks.append(cb)
        return cb

    def _run_callbacks(self):
        for cb in self.callbacks:
            if cb.schedule.due(self):
                cb.func(self)

    def finalize(self):
        """End the run at the current step: each callback whose function has a ``finalize(sim)`` method
        runs it, in the callbacks' order (a snapshot writer writes the last state unless its schedule just
        did; a checkpoint writer, added last, the last checkpoint, after the others' files are complete).

        `run` calls it when the end time is reached; a caller that ends the run earlier (after
        ``run(max_steps=...)``) calls it itself. Once per step: a second call at the same step does
        nothing."""
        if self.finalized_step == self.step_count:
            return
        self.finalized_step = self.step_count
        for cb in self.callbacks:
            end = getattr(cb.func, "finalize", None)
            if end is not None:
                end(self)

    def _choose_dt(self, dt_limit):
        """Clip the stable dt so the next scheduled output time is hit exactly."""
        if not math.isfinite(dt_limit) or dt_limit <= 0:
            raise InstabilityError(f"time step {dt_limit!r} s at step {self.step_count}, t = {self.time:.6g} s "
                                   "is not a positive number")
        if self.dt0 is None:
            self.dt0 = dt_limit
        if dt_limit < self.dt_floor_ratio * self.dt0:
            raise InstabilityError(
                f"dt fell to {dt_limit:.3g} s at step {self.step_count}, t = {self.time:.6g} s "
                f"(below {self.dt_floor_ratio:g} x the initial {self.dt0:.3g} s): accelerations are exploding, "
                "typically particles penetrating a wall or a pressure blow-up")
        t_next = self.end_time
        for cb in self.callbacks:
            t_next = min(t_next, cb.schedule.next_time())
        dt = dt_limit
        gap = t_next - self.time
        if gap > 0:
            if dt >= gap * (1 - 1e-12):
                dt = gap
            elif 2 * dt > gap:
                dt = 0.5 * gap  # two even steps rather than a normal one and a sliver
        if not self.time + dt > self.time:
            raise InstabilityError(f"the step dt = {dt:.3g} s no longer advances t = {self.time:.9g} s (a schedule's "
                                   "interval or a fixed time step far below the time's resolution)")
        self.dt = dt
        return dt

    def step(self):
        """Advance one time step: the integrator, then the `stages` in order
        (`shoal.simulation.stages`: damping, relaxation, density filter, stability check)."""
        m = self.model
        m.time = self.time
        try:
            dt = self.integrator.step(self._choose_dt)
        except InstabilityError as err:
            if " step " in str(err):
                raise
            raise InstabilityError(f"unstable at step {self.step_count + 1}, t = {self.time:.6g} s: {err}") from None
        reached("step")  # a test hook (shoal.faults): killed in the middle of a step
        self.time += dt
        m.time = self.time
        self.step_count += 1
        for stage in self.stages:
            stage(self, dt)
        return dt

    def elapsed_wall_seconds(self):
        """The wall time so far: `wall_seconds` plus the part of the `run` call in progress (what a
        checkpoint written from a callback must record, or a resumed run's total misses that part)."""
        if self._run_t0 is None:
            return self.wall_seconds
        return self.wall_seconds + (_time.perf_counter() - self._run_t0)

    def run(self, max_steps=None):
        """Run to `end_time` (or `max_steps` steps); at the end time, `finalize`. Returns self."""
        t0 = self._run_t0 = _time.perf_counter()
        c0 = self.model.backend.compile_seconds
        try:
            if not self.started:
                self.model.sort()
                self.model.check(0, 0.0)
                self._run_callbacks()
                self.started = True
            steps = 0
            while self.time < self.end_time * (1 - 1e-12) and not self.stop_requested:
                if max_steps is not None and steps >= max_steps:
                    break
                self.step()
                steps += 1
                self._run_callbacks()
                for func in self.after_step:
                    func(self)
            if self.time >= self.end_time * (1 - 1e-12) and not self.stop_requested:
                self.finalize()
        finally:
            self.wall_seconds += _time.perf_counter() - t0
            self._run_t0 = None
            self.compile_seconds += self.model.backend.compile_seconds - c0
        return self
