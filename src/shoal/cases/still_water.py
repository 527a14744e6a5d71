"""Still water in a closed tank: the hydrostatic test.

After the initial transient has settled the pressure must follow
p = rho0 g (H - z) and the free surface stay at H; mass is conserved
exactly (particle masses never change).
"""

from __future__ import annotations

import numpy as np

from ..case import Case
from ..geometry import box_fill, tank_walls
from ..options import SPHOptions
from ._checks import check_count, check_dp, check_positive


def still_water_2d(dp=0.01, depth=0.5, length=1.0, layers=3, end_time=2.0, output_interval=0.1, options=None):
    """Still water of depth `depth` [m] in a 2D tank `length` [m] long."""
    check_positive("depth", depth, "m")
    check_positive("length", length, "m")
    check_dp(dp, min(depth, length), "the water depth")
    check_count(length * depth / dp**2, 2)
    fluid = box_fill((0, 0, 0), (length, 0, depth), dp, 2)
    walls = tank_walls((0, 0, 0), (length, 0, 1.5 * depth), dp, 2, layers=layers)
    pos = np.vstack([fluid, walls])
    kinds = np.r_[np.zeros(len(fluid), np.int8), np.ones(len(walls), np.int8)]
    m = (layers + 1) * dp
    domain = ((-m, 0, -m), (length + m, 0, 2.0 * depth))
    return Case("still-water-2d", 2, float(dp), pos, kinds, domain, options=options or SPHOptions(),
                fluid_height=depth, surface_z=depth, end_time=float(end_time),
                output_interval=float(output_interval), description="2D hydrostatic tank",
                parameters=dict(dp=dp, depth=depth, length=length, layers=layers))


def still_water_3d(dp=0.02, depth=0.3, length=0.5, width=0.3, layers=3, end_time=1.0, output_interval=0.1,
                   options=None):
    """Still water of depth `depth` [m] in a 3D tank `length` x `width` [m]."""
    for n, v in (("depth", depth), ("length", length), ("width", width)):
        check_positive(n, v, "m")
    check_dp(dp, min(depth, length, width), "the smallest tank dimension")
    check_count(length * width * depth / dp**3, 3)
    fluid = box_fill((0, 0, 0), (length, width, depth), dp, 3)
    walls = tank_walls((0, 0, 0), (length, width, 1.5 * depth), dp, 3, layers=layers)
    pos = np.vstack([fluid, walls])
    kinds = np.r_[np.zeros(len(fluid), np.int8), np.ones(len(walls), np.int8)]
    m = (layers + 1) * dp
    domain = ((-m, -m, -m), (length + m, width + m, 2.0 * depth))
    return Case("still-water-3d", 3, float(dp), pos, kinds, domain, options=options or SPHOptions(),
                fluid_height=depth, surface_z=depth, end_time=float(end_time),
                output_interval=float(output_interval), description="3D hydrostatic tank",
                parameters=dict(dp=dp, depth=depth, length=length, width=width, layers=layers))
