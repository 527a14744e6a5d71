"""Built-in cases: functions returning a `Case`.

`CASES` maps the command-line names to the functions.
"""

from ..errors import InputError
from .dam_break import dam_break_2d, dam_break_3d, dam_break_dualsphysics, spheric_benchmark
from .floating_box import floating_box_2d
from .moored_box import moored_box_3d
from .open_channel import open_channel_2d, open_channel_3d
from .rip_current import rip_current
from .sluice_gate import sluice_gate_2d
from .still_water import still_water_2d, still_water_3d
from .tidal_bore import tidal_bore, tidal_bore_piers
from .wave_basin import wave_basin_2d
from .wave_flume import wave_flume_2d, wave_flume_3d
from .weir import weir_2d

CASES = {
    "dam-break-2d": dam_break_2d,
    "dam-break-3d": dam_break_3d,
    "dam-break-dualsphysics": dam_break_dualsphysics,
    "spheric-benchmark": spheric_benchmark,
    "still-water-2d": still_water_2d,
    "still-water-3d": still_water_3d,
    "wave-flume-2d": wave_flume_2d,
    "wave-flume-3d": wave_flume_3d,
    "wave-basin-2d": wave_basin_2d,
    "tidal-bore": tidal_bore,
    "tidal-bore-piers": tidal_bore_piers,
    "rip-current": rip_current,
    "floating-box-2d": floating_box_2d,
    "moored-box-3d": moored_box_3d,
    "open-channel-2d": open_channel_2d,
    "open-channel-3d": open_channel_3d,
    "sluice-gate-2d": sluice_gate_2d,
    "weir-2d": weir_2d,
}


def case_parameters(name):
    """The parameters (and defaults) the built-in case `name` takes."""
    import inspect

    sig = inspect.signature(CASES[name])
    return {k: p.default for k, p in sig.parameters.items() if k != "options"}


def get_case(name, **kwargs):
    """Build the built-in case `name` with keyword parameters (checked by name)."""
    try:
        fn = CASES[name]
    except KeyError:
        raise InputError(f"unknown case {name!r}; built-in cases: {', '.join(CASES)}") from None
    allowed = case_parameters(name)
    for k in kwargs:
        if k not in allowed and k != "options":
            raise InputError(f"case {name!r} has no parameter {k!r}; its parameters: {', '.join(allowed)}")
    return fn(**kwargs)


__all__ = ["CASES", "get_case", "case_parameters", "dam_break_2d", "dam_break_3d", "dam_break_dualsphysics",
           "spheric_benchmark",
           "still_water_2d", "still_water_3d", "wave_flume_2d", "wave_flume_3d", "wave_basin_2d", "tidal_bore",
           "tidal_bore_piers",
           "rip_current", "floating_box_2d", "moored_box_3d", "open_channel_2d", "open_channel_3d", "sluice_gate_2d",
           "weir_2d"]
