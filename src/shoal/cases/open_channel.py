"""Open channels between an inlet and an outlet (issue 33): the mass-balance cases of open boundaries, 2D and 3D.

Water `depth` deep enters a level flume `length` long through an inlet at x = 0 that imposes the `discharge`
(spread over the depth: u = Q / depth) and the level, and leaves through an outlet at x = `length` that holds
the level and lets the water go at its own velocity (`shoal.open_boundary`). The bed is free-slip (Adami walls,
no viscous stress at the wall: ``visco_bound_factor = 0``), so the stream keeps its speed and depth along the
flume; it runs on under both buffers. Flow gauges (the discharge, counted particle by particle) and wave
gauges (the depth) at `gauges_x`. `open_channel_3d` is the same flume `width` wide between free-slip side walls,
the inlet and the outlet across its whole section, its gauges on the centre line.

Run time on 2 cores at the default dp = 0.02 m (about 1,600 particles): 20 s of flow in about 2.5 minutes.
"""

from __future__ import annotations

from ..case import Case, Fluid, FluidRegion, Output, Solid
from ..geometry.shapes import Box, Tank
from ..memory import check_count
from ..open_boundary import OpenBoundary
from ..options import SPHOptions
from ..probes import FlowGauge, WaveGauge
from ._checks import check_dp, check_positive

CHANNEL_OPTIONS = dict(wall_pressure="adami", visco_bound_factor=0.0)
"""The scheme's options beyond the defaults: Adami walls and a free-slip bed."""


def open_channel_2d(dp=0.02, depth=0.2, length=2.0, discharge=0.04, end_time=20.0, output_interval=0.5,
                    gauges_x=(0.5, 1.0, 1.5), gauge_interval=0.1, options=None):
    """A level 2D flume `length` [m] long with water `depth` [m] deep flowing in at `discharge` [m^2/s] through
    an inlet at x = 0 and out through an outlet at x = `length` (module docstring)."""
    check_positive("depth", depth, "m")
    check_positive("length", length, "m")
    check_positive("discharge", discharge, "m^2/s")
    check_dp(dp, depth, "the water depth")
    check_count(length * depth / dp**2, 2)
    gauges = [float(x) for x in gauges_x]
    bad = [x for x in gauges if not 0.0 < x < length]
    if bad:
        from ..errors import InputError

        raise InputError(f"gauges_x = {bad}: each gauge lies inside the flume, 0 < x < length = {length:g} m")
    top = 2.0 * depth
    speed = discharge / depth
    layers = 4
    bed = Box(lo=(-0.3 * length, 0, -layers * dp), hi=(1.3 * length, 0, 0))
    return Case(name="open-channel-2d", dim=2, dp=float(dp), end_time=float(end_time),
                description="2D open channel: inlet of imposed discharge, outlet, free-slip bed",
                fluid=Fluid(depth=depth, surface_level=depth),
                options=options or SPHOptions(**CHANNEL_OPTIONS),
                solids=[Solid(name="bed", shape=bed, layers=layers)],
                fluids=[FluidRegion(shape=Box(lo=(0, 0, 0), hi=(length, 0, depth)), velocity=(speed, 0, 0))],
                open_boundaries=[
                    OpenBoundary(name="inlet", point=(0, 0, 0), normal=(1, 0, 0), lo=(0, 0, 0), hi=(0, 0, top),
                                 discharge=discharge, level=depth),
                    OpenBoundary(name="outlet", point=(length, 0, 0), normal=(-1, 0, 0), lo=(length, 0, 0),
                                 hi=(length, 0, top), level=depth)],
                probes=[FlowGauge(name=f"x{x:g}", at=x, interval=gauge_interval) for x in gauges] +
                       [WaveGauge(name=f"x{x:g}", x=x, z0=-dp, z1=top, interval=gauge_interval) for x in gauges],
                output=Output(interval=float(output_interval)),
                parameters=dict(dp=dp, depth=depth, length=length, discharge=discharge, gauges_x=gauges))


def open_channel_3d(dp=0.02, depth=0.2, width=0.2, length=2.0, discharge=0.008, end_time=20.0,
                    output_interval=0.5, gauges_x=(0.5, 1.0, 1.5), gauge_interval=0.1, options=None):
    """`open_channel_2d` in 3D: the flume `width` [m] wide between side walls, `discharge` [m^3/s] let in over the
    whole section (default 0.008 m^3/s: 0.2 m/s over 0.2 m x 0.2 m) (module docstring)."""
    check_positive("depth", depth, "m")
    check_positive("width", width, "m")
    check_positive("length", length, "m")
    check_positive("discharge", discharge, "m^3/s")
    check_dp(dp, min(depth, width), "the water depth and the channel's width")
    check_count(length * depth * width / dp**3, 3)
    gauges = [float(x) for x in gauges_x]
    bad = [x for x in gauges if not 0.0 < x < length]
    if bad:
        from ..errors import InputError

        raise InputError(f"gauges_x = {bad}: each gauge lies inside the flume, 0 < x < length = {length:g} m")
    top = 2.0 * depth
    speed = discharge / (depth * width)
    layers = 3
    margin = 10.0 * dp  # walls under and beside the buffers (4 rows) and a kernel support beyond them
    channel = Tank(lo=(-margin, 0, 0), hi=(length + margin, width, top), open=["top", "xmin", "xmax"])
    y = 0.5 * width
    return Case(name="open-channel-3d", dim=3, dp=float(dp), end_time=float(end_time),
                description="3D open channel between side walls: inlet of imposed discharge, outlet, free-slip walls",
                fluid=Fluid(depth=depth, surface_level=depth),
                options=options or SPHOptions(**CHANNEL_OPTIONS),
                solids=[Solid(name="channel", shape=channel, layers=layers)],
                fluids=[FluidRegion(shape=Box(lo=(0, 0, 0), hi=(length, width, depth)), velocity=(speed, 0, 0))],
                open_boundaries=[
                    OpenBoundary(name="inlet", point=(0, 0, 0), normal=(1, 0, 0), lo=(0, 0, 0), hi=(0, width, top),
                                 discharge=discharge, level=depth),
                    OpenBoundary(name="outlet", point=(length, 0, 0), normal=(-1, 0, 0), lo=(length, 0, 0),
                                 hi=(length, width, top), level=depth)],
                probes=[FlowGauge(name=f"x{x:g}", at=x, interval=gauge_interval) for x in gauges] +
                       [WaveGauge(name=f"x{x:g}", x=x, y=y, z0=-dp, z1=top, interval=gauge_interval) for x in gauges],
                output=Output(interval=float(output_interval)),
                parameters=dict(dp=dp, depth=depth, width=width, length=length, discharge=discharge,
                                gauges_x=gauges))
