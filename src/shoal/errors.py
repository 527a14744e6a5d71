"""Exceptions that shoal turns into one-line messages for the user.

`InputError` is bad input (unknown case, impossible resolution, unknown option);
the command line prints its message and exits with status 2.
`InstabilityError` is a run that went unstable; the run stops, keeps what it
wrote, and the command line prints where and why (exit status 3).
"""


class ShoalError(Exception):
    """Base class of shoal's own errors."""


class InputError(ShoalError, ValueError):
    """Bad user input: the message names what is wrong and what is allowed."""


class InstabilityError(ShoalError, RuntimeError):
    """A run became unstable (NaN, density out of range, dt collapse)."""
