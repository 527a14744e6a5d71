"""Exceptions that shoal turns into one-line messages for the user.

`InputError` is bad input (unknown case, impossible resolution, unknown option);
the command line prints its message and exits with status 2.
`InstabilityError` is a run that went unstable; the run stops, keeps what it
wrote, and the command line prints where and why (exit status 3).
`RunInterrupted` is a run stopped by SIGINT/SIGTERM after a final checkpoint
(exit status 130/143); `OutputError` is output that could not be written,
e.g. a full disk (exit status 4).
"""


class ShoalError(Exception):
    """Base class of shoal's own errors."""


class InputError(ShoalError, ValueError):
    """Bad user input: the message names what is wrong and what is allowed."""


class InstabilityError(ShoalError, RuntimeError):
    """A run became unstable (NaN, density out of range, dt collapse)."""


class RunInterrupted(ShoalError):
    """A run stopped by SIGINT or SIGTERM after writing a final checkpoint.

    Attributes
    ----------
    signum : int
        The signal (2 SIGINT, 15 SIGTERM); ``shoal run`` exits with 128 + signum.
    checkpoint : pathlib.Path or None
        The checkpoint written at the stop.
    """

    def __init__(self, message, signum, checkpoint=None):
        super().__init__(message)
        self.signum = signum
        self.checkpoint = checkpoint

    @property
    def exit_status(self):
        return 128 + int(self.signum)


class OutputError(ShoalError, OSError):
    """Output could not be written (disk full, quota, permissions): the run
    stopped; files written before are intact and ``shoal run --resume``
    continues from the last checkpoint (exit status 4)."""
