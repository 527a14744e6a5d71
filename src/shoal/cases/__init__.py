"""Built-in cases: functions returning a `Case`.

`CASES` maps the command-line names to the functions.
"""

from ..errors import InputError
from .dam_break import dam_break_2d, dam_break_3d, dam_break_dualsphysics
from .still_water import still_water_2d, still_water_3d

CASES = {
    "dam-break-2d": dam_break_2d,
    "dam-break-3d": dam_break_3d,
    "dam-break-dualsphysics": dam_break_dualsphysics,
    "still-water-2d": still_water_2d,
    "still-water-3d": still_water_3d,
}


def get_case(name, **kwargs):
    """Build the built-in case `name` with keyword parameters."""
    try:
        fn = CASES[name]
    except KeyError:
        raise InputError(f"unknown case {name!r}; built-in cases: {', '.join(CASES)}") from None
    return fn(**kwargs)


__all__ = ["CASES", "get_case", "dam_break_2d", "dam_break_3d", "dam_break_dualsphysics",
           "still_water_2d", "still_water_3d"]
