"""Stopping a run cleanly on SIGINT (Ctrl-C) and SIGTERM (a batch system's
time limit or ``kill``).

The first signal sets ``sim.stop_requested``: the loop ends after the step
in progress, the run writes a final checkpoint, closes its outputs and
raises `RunInterrupted` (``shoal run`` exits with status 128 + the signal
number: 130 for SIGINT, 143 for SIGTERM). A second signal aborts at once
(`Aborted`, a KeyboardInterrupt): the last checkpoint written is kept.
"""

from __future__ import annotations

import signal
import sys
import threading

SIGNALS = (signal.SIGINT, signal.SIGTERM)


class Aborted(KeyboardInterrupt):
    """A second stop signal: the run was abandoned at once.

    Attributes
    ----------
    signum : int
        The signal that aborted it.
    """

    def __init__(self, signum):
        super().__init__(f"aborted by a second {signal.Signals(signum).name}")
        self.signum = signum


class StopOnSignals:
    """Context manager installing the stop handlers for `sim` (main thread
    only; elsewhere it does nothing). The previous handlers come back on exit.

    Attributes
    ----------
    signum : int or None
        The first stop signal received, or None.
    """

    def __init__(self, sim, message=None):
        self.sim = sim
        self.signum = None
        self.message = message
        self._old = {}

    def _handler(self, signum, frame):
        if self.signum is not None:
            raise Aborted(signum)
        self.signum = signum
        self.sim.stop_requested = True
        name = signal.Signals(signum).name
        sys.stderr.write(f"\nshoal: {name} received: stopping after this step and writing a checkpoint "
                         f"(send it again to abort at once)\n")
        sys.stderr.flush()

    def __enter__(self):
        if threading.current_thread() is threading.main_thread():
            for s in SIGNALS:
                try:
                    self._old[s] = signal.signal(s, self._handler)
                except (ValueError, OSError):
                    pass
        return self

    def __exit__(self, *exc):
        for s, old in self._old.items():
            signal.signal(s, old)
        self._old = {}
        return False
