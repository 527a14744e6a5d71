"""A 2D wave basin: irregular waves of a JONSWAP sea from a piston paddle, gauges, a beach.

Physics: a random sea of significant height Hs, peak period Tp and peak enhancement gamma
(`shoal.waves.JonswapSpectrum`), made by a piston paddle as a sum of wave components, each through
Biesel's transfer function (`shoal.motions.IrregularWaves`), propagating over constant depth d and
breaking on a plane beach, which absorbs most of it. The defaults are the wave basin of issue 31:
Hs = 0.05 m, Tp = 1.5 s, d = 0.5 m, gamma = 3.3, so k_p d = 1.11 (intermediate depth; the peak
wavelength L_p = 2.83 m).

Gauges: one near the paddle (1 m) and a Mansard & Funke (1980) array one peak wavelength from it
(2.9, 3.2 and 3.6 m: spacings 0.106 L_p and 0.247 L_p, near their recommended x12 = L/10 and within
L/6 < x13 < L/3) for the incident and reflected spectra (`shoal.analysis.irregular_reflection`), and a
run-up gauge on the beach (`shoal.analysis.runup_statistics`). Each gauge is sampled 40 times per peak
period; the measured spectra against the target: ``shoal post RUN --spectra`` (`shoal.post.plot_spectra`).

Record length: a spectrum estimated over T seconds scatters by about sqrt(1.2 / (T B)) in a band of
width B (Welch's method, `shoal.analysis.band_ratios`): 200 peak periods (end_time = 300 s) are what
a spectral comparison in 0.1 f_p bands needs; the default 30 s is a first look at the sea. The paddle
signal repeats after its repeat period (1 / df of its components, 153.6 s at the defaults).

The scheme is the wave flumes' (`shoal.cases.wave_flume.WAVE_OPTIONS`): laminar viscosity, no
artificial viscosity, h = 2.1 dp. At the default dp = 0.01 m (Hs / dp = 5, about 56,000 particles)
the sea is resolved coarsely; Hs / dp = 10 (dp = 0.005 m) is the resolution of the wave-decay
criterion of issue 31.
"""

from __future__ import annotations

import math

from ..case import Case, Fluid, FluidRegion, Output, Solid
from ..errors import InputError
from ..geometry.shapes import Box, Slope, Tank
from ..memory import check_count
from ..motions import IrregularWaves
from ..options import SPHOptions
from ..probes import RunupGauge, WaveGauge
from ..waves.spectra import JonswapSpectrum
from ._checks import check_dp, check_positive
from .wave_flume import WAVE_OPTIONS

MF_GAUGES = (2.9, 3.2, 3.6)
"""The default Mansard & Funke gauge array [m from the paddle]."""


def wave_basin_2d(dp=0.01, depth=0.5, length=8.0, beach_slope=0.1, hs=0.05, tp=1.5, gamma=3.3, seed=0,
                  components=256, ramp_time=None, end_time=30.0, output_interval=0.5,
                  gauges_x=(1.0,) + MF_GAUGES, options=None):
    """2D wave basin: a JONSWAP sea from a piston paddle over constant depth, gauges, a plane beach.

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
    hs, tp, gamma : float
        The JONSWAP spectrum's significant wave height Hs = Hm0 [m], peak period Tp [s] and peak
        enhancement factor (`shoal.waves.JonswapSpectrum`).
    seed : int
        Seed of the components' random phases (the same seed gives the same sea).
    components : int
        Number of wave components between 0.5 and 3 f_p (`shoal.motions.IrregularWaves`).
    ramp_time : float, optional
        Start-up ramp of the paddle [s] (default 2 Tp).
    end_time, output_interval : float
        [s].
    gauges_x : sequence of float
        Wave gauges [m from the paddle], sampled 40 times per peak period (``gauge_x*.csv``).

    Returns
    -------
    Case
    """
    for n, v, unit in (("depth", depth, "m"), ("length", length, "m"), ("beach_slope", beach_slope, ""),
                       ("hs", hs, "m"), ("tp", tp, "s")):
        check_positive(n, v, unit)
    check_dp(dp, depth, "the water depth")
    gauges_x = tuple(float(x) for x in gauges_x)
    for x in gauges_x:
        if not 0.0 < x < length:
            raise InputError(f"gauges_x: {x:g} m is not between the paddle (0) and the toe of the beach "
                             f"({length:g} m); give gauge positions over the flat bed")
    paddle = IrregularWaves(name="paddle", spectrum=JonswapSpectrum(hs=hs, tp=tp, gamma=gamma), depth=depth,
                            components=components, seed=seed, ramp_time=ramp_time)
    top = depth + max(3.0 * hs, 0.2 * depth)
    x_end = length + top / beach_slope  # the beach reaches the top of the walls
    paddle_t = 4 * dp
    x_back = -paddle.max_displacement - paddle_t - 2 * dp  # room behind the paddle for its back stroke
    check_count((x_end - x_back) * top / dp**2, 2)
    solids = [
        Solid(name="paddle", shape=Box(lo=(-paddle_t, 0.0, 0.0), hi=(0.0, 0.0, top)), motion="paddle"),
        Solid(name="beach", shape=Slope(x0=length, z0=0.0, gradient=beach_slope)),
        Solid(name="flume", shape=Tank(lo=(x_back, 0.0, 0.0), hi=(x_end, 0.0, top))),
    ]
    fluids = [FluidRegion(shape=Box(lo=(0.0, 0.0, 0.0), hi=(x_end, 0.0, depth)))]
    interval = tp / 40
    probes = [WaveGauge(name=f"x{x:g}", x=x, z0=depth - 4.0 * hs, z1=top, interval=interval) for x in gauges_x]
    probes.append(RunupGauge(name="beach", x0=length, x1=x_end, interval=interval))
    return Case(name="wave-basin-2d", dim=2, dp=float(dp), end_time=float(end_time),
                description=f"2D wave basin: a JONSWAP sea Hs = {hs:g} m, Tp = {tp:g} s, gamma = {gamma:g} from a "
                            f"piston paddle in d = {depth:g} m, on a 1:{1 / beach_slope:.3g} beach",
                fluid=Fluid(depth=depth, surface_level=depth), options=options or SPHOptions(**WAVE_OPTIONS[2]),
                solids=solids, fluids=fluids, motions=[paddle], probes=probes,
                output=Output(interval=float(output_interval)),
                parameters=dict(dp=dp, depth=depth, length=length, beach_slope=beach_slope, hs=hs, tp=tp,
                                gamma=gamma, seed=seed, components=components, ramp_time=paddle.ramp,
                                gauges_x=list(gauges_x), repeat_period=paddle.repeat_period,
                                peak_wavelength=_peak_wavelength(tp, depth)))


def _peak_wavelength(tp, depth):
    from ..waves.dispersion import wavenumber

    return 2.0 * math.pi / wavenumber(tp, depth)
