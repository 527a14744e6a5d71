"""Wave flumes: a piston wavemaker at one end, constant depth, a beach at the other.

Physics: regular waves of height H and period T made by a piston paddle
whose stroke comes from Biesel's transfer function (`shoal.motions`),
propagating over constant depth d (wavelength from the linear dispersion
relation omega^2 = g k tanh(kd)) and breaking on a plane beach.
Reference: linear wavemaker theory (Biesel & Suquet 1951; Dean & Dalrymple
1991, ch. 6) -- the wave height measured in the flume against the target
height (with probes, see the probes issue).

The scheme (`WAVE_OPTIONS`, unless `options` is given): the laminar viscosity of
water with no artificial viscosity and free-slip walls for the viscous term (linear
wave theory has no viscosity and no bed friction), and a wider kernel than
the default, h = 2.1 dp (coef_h = 1.5 in 2D, 1.2 in 3D): with h = 1.41 dp a
2D Wendland kernel damps a wave by 7.5 % of its height per wavelength and
runs it 4.6 % fast, with 2.1 dp by 1.1 % (0.6 % at twice the resolution) and
0.3 % (`benchmarks/wave_decay.py`, 2D; the 3D kernel is set to the same h/dp,
not measured separately).

Run time on 2 cores (with coef_h = 1; the wider kernel has about twice the
neighbours): `wave-flume-2d` at its default dp = 0.01 m (34,568
particles) simulates about 0.26 s of flow per minute (measured: 0.3 s in
70 s, 2.1e6 particle-steps/s), so its 10 s take about 40 minutes;
`wave-flume-3d` at dp = 0.02 m (325,053 particles) is a GPU run.
"""

from __future__ import annotations

from ..case import Case, Fluid, FluidRegion, Output, Solid
from ..geometry.shapes import Box, Slope, Tank
from ..motions import PistonWavemaker
from ..options import SPHOptions
from ..probes import WaveGauge
from ..memory import check_count
from ._checks import check_dp, check_positive

WAVE_OPTIONS = {2: dict(viscosity="laminar", nu=1e-6, visco_bound_factor=0.0, coef_h=1.5),
                3: dict(viscosity="laminar", nu=1e-6, visco_bound_factor=0.0, coef_h=1.2)}
"""Default scheme options of the wave flumes, by dimension (see the module docstring)."""


def _flume(dim, dp, depth, length, beach_slope, width, wave_height, period, ramp_periods, end_time,
           output_interval, options, name, gauges_x=(1.0, 2.0, 3.0)):
    for n, v in (("depth", depth), ("length", length), ("beach_slope", beach_slope), ("wave_height", wave_height),
                 ("period", period)):
        check_positive(n, v, "m" if n not in ("period", "beach_slope") else ("s" if n == "period" else ""))
    if dim == 3:
        check_positive("width", width, "m")
    check_dp(dp, depth if dim == 2 else min(depth, width), "the water depth" if dim == 2 else "depth or width")
    if wave_height >= 0.8 * depth:
        raise_height(wave_height, depth)
    piston = PistonWavemaker(name="piston", height=wave_height, period=period, depth=depth,
                             ramp_periods=ramp_periods)
    top = depth + max(2.0 * wave_height, 0.2 * depth)
    x_end = length + top / beach_slope  # the beach reaches the top of the walls
    paddle_t = 4 * dp
    x_back = -0.5 * piston.stroke - paddle_t - 2 * dp  # room behind the paddle for its back stroke
    W = width if dim == 3 else 0.0
    check_count((x_end - x_back) * top * (W if dim == 3 else 1.0) / dp**dim, dim)
    solids = [
        Solid(name="paddle", shape=Box(lo=(-paddle_t, 0.0, 0.0), hi=(0.0, W, top)), motion="piston"),
        Solid(name="beach", shape=Slope(x0=length, z0=0.0, gradient=beach_slope)),
        Solid(name="flume", shape=Tank(lo=(x_back, 0.0, 0.0), hi=(x_end, W, top))),
    ]
    fluids = [FluidRegion(shape=Box(lo=(0.0, 0.0, 0.0), hi=(x_end, W, depth)))]
    probes = [WaveGauge(name=f"x{x:g}", x=x, y=0.5 * W, z0=depth - 2 * wave_height, z1=top, interval=period / 40)
              for x in gauges_x]
    return Case(name=name, dim=dim, dp=float(dp), end_time=float(end_time),
                description=f"{dim}D wave flume: piston waves H = {wave_height:g} m, T = {period:g} s in "
                            f"d = {depth:g} m on a 1:{1 / beach_slope:.3g} beach (Biesel piston theory)",
                fluid=Fluid(depth=depth, surface_level=depth), options=options or SPHOptions(**WAVE_OPTIONS[dim]),
                solids=solids, fluids=fluids, motions=[piston], probes=probes,
                output=Output(interval=float(output_interval)),
                parameters=dict(dp=dp, depth=depth, length=length, beach_slope=beach_slope, width=width,
                                wave_height=wave_height, period=period, ramp_periods=ramp_periods,
                                gauges_x=list(gauges_x),
                                stroke=piston.stroke, wavelength=2 * 3.141592653589793 / piston.wavenumber))


def raise_height(h, d):
    from ..errors import InputError

    raise InputError(f"wave_height = {h:g} m is too large for depth = {d:g} m; regular waves break above "
                     f"about 0.78 d = {0.78 * d:.3g} m")


def wave_flume_2d(dp=0.01, depth=0.4, length=6.0, beach_slope=0.1, wave_height=0.05, period=1.2,
                  ramp_periods=2.0, end_time=10.0, output_interval=0.1, gauges_x=(1.0, 2.0, 3.0), options=None):
    """2D wave flume: piston wavemaker, constant depth, plane beach.

    Parameters
    ----------
    dp : float
        Particle spacing [m].
    depth : float
        Still-water depth d [m].
    length : float
        Distance from the paddle's rest position to the toe of the beach [m].
    beach_slope : float
        Beach gradient (0.1 is 1:10).
    wave_height, period : float
        Target regular wave height H [m] and period T [s] (paddle stroke
        from Biesel's transfer function).
    ramp_periods : float
        Start-up ramp of the paddle, in periods.
    end_time, output_interval : float
        [s].
    gauges_x : sequence of float
        Wave gauges [m from the paddle], sampled 40 times per period
        (``gauge_x*.csv``).
    """
    return _flume(2, dp, depth, length, beach_slope, None, wave_height, period, ramp_periods, end_time,
                  output_interval, options, "wave-flume-2d", tuple(gauges_x))


def wave_flume_3d(dp=0.02, depth=0.4, length=6.0, beach_slope=0.1, width=0.5, wave_height=0.05, period=1.2,
                  ramp_periods=2.0, end_time=10.0, output_interval=0.1, gauges_x=(1.0, 2.0, 3.0), options=None):
    """3D wave flume (the 2D flume extruded over `width` [m], side walls; gauges on the centre line)."""
    return _flume(3, dp, depth, length, beach_slope, width, wave_height, period, ramp_periods, end_time,
                  output_interval, options, "wave-flume-3d", tuple(gauges_x))
