"""Schedules: when a callback (writer, probe, check) runs.

`TimeInterval(dt)` fires at t = 0, dt, 2 dt, ... and (with ``exact=True``,
the default) the simulation shortens the steps before each of these times
so they are hit exactly;
`IterationInterval(n)` fires every n steps; `WallTimeInterval(s)` every s
seconds of wall-clock time.
"""

from __future__ import annotations

import math
import time as _time

from ..errors import InputError


class TimeInterval:
    """Fire at multiples of `interval` seconds of simulated time."""

    def __init__(self, interval, start=0.0, exact=True):
        if not (interval > 0 and math.isfinite(interval)):
            raise InputError(f"output interval = {interval!r} s must be a positive number of seconds")
        self.interval = float(interval)
        self.start = float(start)
        self.exact = exact
        self.count = 0

    def next_time(self):
        """The next time the simulation must land on exactly (inf if not exact)."""
        return self.start + self.count * self.interval if self.exact else math.inf

    def _next(self):
        return self.start + self.count * self.interval

    def _pass(self, time):
        """Advance `count` to the first output time after `time` (within 1e-9 interval): the smallest
        count >= the current one whose time is later. Computed, then corrected by a step or two for
        rounding, so a tiny interval or a late time never loops for ever."""
        eps = 1e-9 * self.interval
        k = self.count
        if self.start + k * self.interval <= time + eps:
            q = (time + eps - self.start) / self.interval
            k = max(k, math.floor(q)) if q < 2.0**52 else -1  # beyond 2^52 steps the times are not distinct
            for _ in range(4):
                if k < 0 or k == self.count or self.start + (k - 1) * self.interval <= time + eps:
                    break
                k -= 1
            for _ in range(4):
                if k < 0 or self.start + k * self.interval > time + eps:
                    break
                k += 1
            else:
                k = -1
            if k < 0:
                raise InputError(f"interval = {self.interval!r} s is too short to step to t = {time!r} s: its "
                                 "times are not distinct numbers there")
        self.count = k

    def due(self, sim):
        t_next = self._next()
        if sim.time >= t_next - 1e-9 * self.interval:
            self._pass(sim.time)
            return True
        return False

    def get_state(self):
        """What a checkpoint must hold to continue the schedule exactly: the
        number of output times passed (`count`)."""
        return {"count": self.count}

    def set_state(self, state):
        """Continue from a checkpoint's `get_state()`."""
        self.count = int(state["count"])

    def skip_to(self, time):
        """Fire next at the first multiple strictly after `time` [s] (a
        schedule added on a restart)."""
        self.count = 0
        self._pass(time)


class IterationInterval:
    """Fire every `n` steps (and at step 0)."""

    def __init__(self, n):
        if int(n) < 1:
            raise InputError(f"iteration interval = {n!r}; use an integer >= 1")
        self.n = int(n)

    def next_time(self):
        return math.inf

    def due(self, sim):
        return sim.step_count % self.n == 0

    def get_state(self):
        """No state: the schedule follows the step count."""
        return {}

    def set_state(self, state):
        pass


class WallTimeInterval:
    """Fire every `seconds` of wall-clock time."""

    def __init__(self, seconds):
        if not seconds > 0:
            raise InputError(f"wall-time interval = {seconds!r} s must be positive")
        self.seconds = float(seconds)
        self._last = _time.monotonic()

    def next_time(self):
        return math.inf

    def due(self, sim):
        now = _time.monotonic()
        if now - self._last >= self.seconds:
            self._last = now
            return True
        return False

    def get_state(self):
        """No state worth keeping: wall-clock time restarts with the process."""
        return {}

    def set_state(self, state):
        """Restart the wall-clock interval from now."""
        self._last = _time.monotonic()


class AnyOf:
    """Fire when any of `schedules` is due (each is asked every step, so
    their counters advance); never shortens a step."""

    def __init__(self, *schedules):
        self.schedules = list(schedules)

    def next_time(self):
        return math.inf

    def due(self, sim):
        fired = [s.due(sim) for s in self.schedules]
        return any(fired)

    def get_state(self):
        return {"schedules": [s.get_state() for s in self.schedules]}

    def set_state(self, state):
        for s, st in zip(self.schedules, state.get("schedules", [])):
            s.set_state(st)


def checkpoint_schedule(cfg):
    """When a run writes checkpoints: every `cfg.interval` s of simulated time (never shortening a
    step) and every `cfg.wall_interval` s of wall-clock time, whichever comes first (0: not)."""
    parts = []
    if cfg.interval > 0:
        parts.append(TimeInterval(cfg.interval, start=cfg.interval, exact=False))  # never shortens a step
    if cfg.wall_interval > 0:
        parts.append(WallTimeInterval(cfg.wall_interval))
    return AnyOf(*parts)
