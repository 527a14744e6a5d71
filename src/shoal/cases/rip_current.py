"""The rip-current basin of Drønen et al. (2002), as modelled with GPUSPH by
Farahani, Dalrymple, Hérault & Bilotta.

Physics: regular waves from a piston wavemaker shoal and break on a
submerged bar cut by a rip channel. Breaking over the bar raises the mean
water level (set-up) more than in the channel; the set-up gradient drives
a current from the bar into the channel, which returns offshore as a rip
current, with a circulation cell over the bar and a counter-rotating cell
near the shore. Reference: the laboratory measurements of Drønen et al.
(2002) (mean velocities, set-up), compared in the paper with depth- and
period-averaged SPH results.

Geometry, from the paper (section "Rip current modeling"): a 30 m long,
4 m wide tank; a single bar 4.8 m long, 3 m wide and 0.13 m high with
1/27 slopes; a 1 m wide rip channel with the same slope; a 1/17 beach;
still-water depth 0.15 m at the bar crest; a piston wavemaker about 6 m
before the sloping bed and 12.4 m from the bar crest; H = 0.19 m, T = 1.5 s.
Test 3* of the resolution study: 0.10 m at the crest, H = 0.15 m.

The paper gives no full profile, so this reading of it is an assumption
(every number is a parameter): x is measured from the paddle's rest
position (waves travel towards +x, the beach is at the far end); the bed is
flat up to x = 6 m, then rises at 1/27 (this plane is the floor of the rip
channel, y in [0, 1] m); on the bar (y in [1, 4] m, 0.1 m wide transitions
at its side) a bump 0.13 m high sits on that slope, its offshore face
rising over 0.13 x 27 = 3.51 m (1/27 relative to the slope) to the crest at
x = 12.4 m and its onshore face dropping back over the remaining 1.29 m of
its 4.8 m length; 2 m past the crest the 1/17 beach starts and runs up to
0.3 m above still water (the dry rest of the 30 m tank is not modelled).
This gives 0.517 m of water over the flat bed, and about 3.1 million fluid
particles at dp = 0.02 m, in line with the paper's "about three million".

Run time: at the paper's dp = 0.02 m a GPU run (4.1 million particles, about
390,000 steps to t = 60 s: 1.6e12 particle-steps, weeks on 2 CPU cores at
7e5 particle-steps/s); dp = 0.06 m (246k particles) is a CPU check.
"""

from __future__ import annotations

from ..case import Case, Fluid, FluidRegion, Output, Solid
from ..errors import InputError
from ..geometry.shapes import Bathymetry, Box, HeightGrid, Tank
from ..motions import PistonWavemaker
from ..options import SPHOptions
from ..memory import check_count
from ._checks import check_dp, check_positive

PAPER_OPTIONS = dict(kernel="wendland", shepard_every=20, density_diffusion="none", alpha=0.1, turbulence="sps",
                     wall_pressure="dynamic")
"""The paper's scheme: Wendland kernel, Shepard filter every 20 steps, SPS turbulence
(its Monaghan-Kajtar boundary particles: ``rip_current(boundary="repulsive")``; the default is
dynamic boundary particles, the DualSPHysics choice, with which the validation report ran it)."""


def rip_current_bed(crest_x=12.4, slope_start=6.0, bar_height=0.13, bar_length=4.8, bar_slope=1 / 27,
                    beach_toe_gap=2.0, beach_slope=1 / 17, channel_width=1.0, basin_width=4.0, x_end=30.0):
    """Bed levels of the basin as a `HeightGrid` (z = 0 on the flat offshore bed).

    Returns the grid and the bed level at the crest (channel and bar).
    """
    x_off = crest_x - bar_height / bar_slope           # toe of the bar's offshore face
    x_on = x_off + bar_length                          # end of its onshore face
    x_toe = crest_x + beach_toe_gap                    # toe of the beach

    def base(x):
        if x <= slope_start:
            return 0.0
        if x <= x_toe:
            return (x - slope_start) * bar_slope
        return (x_toe - slope_start) * bar_slope + (x - x_toe) * beach_slope

    if not (slope_start < x_off < crest_x < x_on < x_toe):
        raise InputError("the bar must lie on the 1/27 slope before the beach: check crest_x, bar_length, "
                         "bar_height and beach_toe_gap")
    xs = sorted({-5.0, slope_start, x_off, crest_x, x_on, x_toe, x_end})
    channel = [base(x) for x in xs]
    bar = [base(x) + (bar_height if x == crest_x else 0.0) for x in xs]
    y_edge = channel_width
    ys = [0.0, y_edge - 0.05, y_edge + 0.05, basin_width]
    z = [[c, c, b, b] for c, b in zip(channel, bar)]
    return HeightGrid(x=xs, y=ys, z=z), base(crest_x), base(crest_x) + bar_height


def rip_current(dp=0.02, crest_depth=0.15, wave_height=0.19, period=1.5, test3=False, boundary="dynamic",
                ramp_periods=2.0, end_time=60.0, output_interval=0.5, options=None):
    """The Drønen et al. (2002) bar / rip-channel basin (see the module docstring).

    Parameters
    ----------
    dp : float
        Particle spacing [m] (the paper: 0.02 m, about three million
        particles; its resolution study also 0.03 and 0.04 m).
    crest_depth : float
        Still-water depth at the bar crest [m] (0.15).
    wave_height, period : float
        Regular waves from the piston [m], [s] (H = 0.19 m as the paper
        states, T = 1.5 s).
    test3 : bool
        The paper's "test 3*": crest depth 0.10 m and H = 0.15 m (overrides
        `crest_depth` and `wave_height`).
    boundary : {"dynamic", "repulsive"}
        Wall particles: dynamic boundary layers (DualSPHysics's DBC) or the
        paper's Monaghan-Kajtar repulsive particles at dp/2.
    end_time, output_interval : float
        [s]; the paper averaged after 10 wave periods, around t = 40 s.
    """
    if test3:
        crest_depth, wave_height = 0.10, 0.15
    check_positive("crest_depth", crest_depth, "m")
    check_positive("wave_height", wave_height, "m")
    check_positive("period", period, "s")
    if boundary not in ("dynamic", "repulsive"):
        raise InputError(f"boundary = {boundary!r}; allowed 'dynamic' or 'repulsive'")
    grid, z_channel, z_crest = rip_current_bed()
    swl = z_crest + crest_depth
    depth = swl  # over the flat offshore bed
    check_dp(dp, 2 * crest_depth, "twice the depth at the bar crest (the paper's coarsest run had 2.5 particles "
                                  "over the crest)")
    piston = PistonWavemaker(name="piston", height=wave_height, period=period, depth=depth,
                             ramp_periods=ramp_periods)
    top = swl + 0.3
    x_beach_top = 12.4 + 2.0 + (top - (12.4 + 2.0 - 6.0) / 27) * 17  # where the beach reaches the wall top
    W = 4.0
    paddle_t = 4 * dp
    x_back = -0.5 * piston.stroke - paddle_t - 2 * dp
    check_count((x_beach_top - x_back) * W * top / dp**3 * 0.6, 3)
    solids = [
        Solid(name="paddle", shape=Box(lo=(-paddle_t, 0.0, 0.0), hi=(0.0, W, top)), motion="piston",
              boundary=boundary),
        Solid(name="bed", shape=Bathymetry(grid=grid), boundary=boundary),
        Solid(name="basin", shape=Tank(lo=(x_back, 0.0, 0.0), hi=(x_beach_top, W, top)), boundary=boundary),
    ]
    fluids = [FluidRegion(shape=Box(lo=(0.0, 0.0, 0.0), hi=(x_beach_top, W, swl)))]
    name = "rip-current"
    return Case(name=name, dim=3, dp=float(dp), end_time=float(end_time),
                description=f"Drønen et al. (2002) bar / rip-channel basin: H = {wave_height:g} m, T = {period:g} s, "
                            f"{crest_depth:g} m at the bar crest" + (" (test 3*)" if test3 else ""),
                fluid=Fluid(depth=depth, surface_level=swl), options=options or SPHOptions(**PAPER_OPTIONS),
                solids=solids, fluids=fluids, motions=[piston], output=Output(interval=float(output_interval)),
                parameters=dict(dp=dp, crest_depth=crest_depth, wave_height=wave_height, period=period,
                                test3=test3, boundary=boundary, still_water_level=swl, stroke=piston.stroke))
