"""Validation of built-in case parameters (one-line errors)."""

import math

from ..errors import InputError

def check_dp(dp, length_scale, what="the smallest fluid dimension"):
    """dp must be positive and at least a few particles across `length_scale`."""
    if not isinstance(dp, (int, float)) or not math.isfinite(dp) or dp <= 0:
        raise InputError(f"dp = {dp!r} m must be a positive number of metres")
    if dp * 4 > length_scale:
        raise InputError(f"dp = {dp!r} m is too coarse: {what} is {length_scale:g} m; "
                         f"use dp <= {length_scale / 4:g} m (at least 4 particles across)")
    if dp < 1e-6 * length_scale:  # a million particles across, a million times over: no machine holds it
        raise InputError(f"dp = {dp!r} m is more than a million times finer than {what} ({length_scale:g} m); "
                         f"use dp >= {1e-6 * length_scale:g} m")


def check_positive(name, value, unit):
    if not isinstance(value, (int, float)) or not math.isfinite(value) or value <= 0:
        raise InputError(f"{name} = {value!r} {unit} must be a positive number")
