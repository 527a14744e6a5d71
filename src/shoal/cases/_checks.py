"""Validation of built-in case parameters (one-line errors)."""

import math
import os

from ..errors import InputError

BYTES_PER_PARTICLE = 600
"""Peak bytes per particle while a case is generated and run (float64 generation
arrays plus solver arrays of either precision), a deliberate over-estimate."""


def physical_memory():
    """Bytes of physical memory of this machine (0 if unknown)."""
    try:
        return os.sysconf("SC_PHYS_PAGES") * os.sysconf("SC_PAGE_SIZE")
    except (ValueError, OSError, AttributeError):
        return 0


def check_dp(dp, length_scale, what="the smallest fluid dimension"):
    """dp must be positive and at least a few particles across `length_scale`."""
    if not isinstance(dp, (int, float)) or not math.isfinite(dp) or dp <= 0:
        raise InputError(f"dp = {dp!r} m must be a positive number of metres")
    if dp * 4 > length_scale:
        raise InputError(f"dp = {dp!r} m is too coarse: {what} is {length_scale:g} m; "
                         f"use dp <= {length_scale / 4:g} m (at least 4 particles across)")


def check_count(n_estimate, dim):
    """Refuse a particle count whose arrays cannot fit in this machine's memory."""
    mem = physical_memory()
    if mem and n_estimate * BYTES_PER_PARTICLE > 0.8 * mem:
        fit = int(0.8 * mem / BYTES_PER_PARTICLE)
        raise InputError(f"about {n_estimate:.3g} particles would be generated, needing about "
                         f"{n_estimate * BYTES_PER_PARTICLE / 2**30:.1f} GiB; this machine has "
                         f"{mem / 2**30:.1f} GiB, enough for about {fit:.2g} particles: use a larger dp")


def check_positive(name, value, unit):
    if not isinstance(value, (int, float)) or not math.isfinite(value) or value <= 0:
        raise InputError(f"{name} = {value!r} {unit} must be a positive number")
