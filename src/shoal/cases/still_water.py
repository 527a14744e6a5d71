"""Still water in a closed tank: the hydrostatic test.

After the initial transient has settled the pressure must follow
p = rho0 g (H - z) and the free surface stay at H; mass is conserved
exactly (particle masses never change).

Run time on 2 cores: `still-water-2d` at its default dp = 0.01 m (2 s of
flow) about a minute; `still-water-3d` at dp = 0.02 m (1 s) a few minutes.
"""

from __future__ import annotations


from ..case import Case, Fluid, FluidRegion, Output, Solid
from ..geometry.shapes import Box, Tank
from ..options import SPHOptions
from ..memory import check_count
from ._checks import check_dp, check_positive


def still_water_2d(dp=0.01, depth=0.5, length=1.0, layers=3, end_time=2.0, output_interval=0.1, options=None):
    """Still water of depth `depth` [m] in a 2D tank `length` [m] long."""
    check_positive("depth", depth, "m")
    check_positive("length", length, "m")
    check_dp(dp, min(depth, length), "the water depth")
    check_count(length * depth / dp**2, 2)
    return Case(name="still-water-2d", dim=2, dp=float(dp), end_time=float(end_time),
                description="2D hydrostatic tank", fluid=Fluid(depth=depth, surface_level=depth),
                options=options or SPHOptions(),
                solids=[Solid(name="tank", shape=Tank(lo=(0, 0, 0), hi=(length, 0, 1.5 * depth)), layers=layers)],
                fluids=[FluidRegion(shape=Box(lo=(0, 0, 0), hi=(length, 0, depth)))],
                output=Output(interval=float(output_interval)),
                parameters=dict(dp=dp, depth=depth, length=length, layers=layers))


def still_water_3d(dp=0.02, depth=0.3, length=0.5, width=0.3, layers=3, end_time=1.0, output_interval=0.1,
                   options=None):
    """Still water of depth `depth` [m] in a 3D tank `length` x `width` [m]."""
    for n, v in (("depth", depth), ("length", length), ("width", width)):
        check_positive(n, v, "m")
    check_dp(dp, min(depth, length, width), "the smallest tank dimension")
    check_count(length * width * depth / dp**3, 3)
    return Case(name="still-water-3d", dim=3, dp=float(dp), end_time=float(end_time),
                description="3D hydrostatic tank", fluid=Fluid(depth=depth, surface_level=depth),
                options=options or SPHOptions(),
                solids=[Solid(name="tank", shape=Tank(lo=(0, 0, 0), hi=(length, width, 1.5 * depth)),
                              layers=layers)],
                fluids=[FluidRegion(shape=Box(lo=(0, 0, 0), hi=(length, width, depth)))],
                output=Output(interval=float(output_interval)),
                parameters=dict(dp=dp, depth=depth, length=length, width=width, layers=layers))
