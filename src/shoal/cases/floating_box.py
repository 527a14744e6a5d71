"""A floating box in the wave flume: the `wave-flume-2d` flume with a box that the waves move (issue 32).

Physics: regular piston waves of height H and period T in water of depth d (`shoal.cases.wave_flume`) meet a
2D rectangular box of beam B, height H_b and density rho_b (per metre of width), floating free in surge, heave
and pitch at the still-water level `box_x` metres from the paddle; beyond it a damping zone (a sponge,
`shoal.case.DampingZone`) absorbs what the box lets through before the beach. The box's motion, and the
water's force and torque on it, are in ``body_box.csv``; the gauges (in front of the box) in ``gauge_x*.csv``.

A box of density s rho0 floats upright only when B / H_b > sqrt(6 s (1 - s)) (1.22 at s = 0.5): the default
box has B / H_b = 2 (a square of density 500 capsizes). In long waves (wavelength >> B, well below the box's
heave and pitch natural frequencies) it follows the water: heave amplitude the wave's, surge the water's
orbital excursion, pitch the wave slope, with a slow drift down-wave (`shoal validate floating-box-waves`).
"""

from __future__ import annotations

import math

from ..case import DampingZone, Solid
from ..errors import InputError
from ..floating import FloatingBody
from ..geometry.shapes import Box
from ._checks import check_positive
from .wave_flume import wave_flume_2d


def floating_box_2d(dp=0.01, depth=0.4, length=6.0, beach_slope=0.1, wave_height=0.05, period=1.2,
                    ramp_periods=2.0, end_time=10.0, output_interval=0.1, box_x=3.0, box_beam=0.2,
                    box_height=0.1, box_density=500.0, zone_start=4.5, zone_rate=10.0, gauges_x=(1.0, 2.0),
                    body_interval=None, options=None):
    """2D wave flume (`wave_flume_2d`) with a floating box at the surface and a damping zone at the far end.

    Parameters
    ----------
    dp, depth, length, beach_slope, wave_height, period, ramp_periods, end_time, output_interval
        As `wave_flume_2d`: particle spacing, still-water depth d, paddle-to-beach-toe distance [m], beach
        gradient, regular wave height H [m] and period T [s] of the piston paddle, its ramp [periods], the run's
        end and snapshot interval [s].
    box_x : float
        Centre of the box [m from the paddle's rest position].
    box_beam, box_height : float
        Its beam B and height H_b [m]; keep B / H_b > sqrt(6 s (1 - s)), s = box_density / 1000, for it to
        float upright.
    box_density : float
        Its density [kg/m^3] (below the water's, 1000): it floats with the fraction box_density / 1000 of its
        height under water, its bottom placed at that draft below the still-water level at t = 0.
    zone_start : float
        Where the damping zone starts [m]; it runs to the end of the flume (over the beach), rate `zone_rate`
        [1/s].
    gauges_x : sequence of float
        Wave gauges [m from the paddle] (``gauge_x*.csv``, 40 samples a period); not on the box.
    body_interval : float, optional
        Seconds between the rows of ``body_box.csv``; default T / 40.
    """
    for n, v, u in (("box_beam", box_beam, "m"), ("box_height", box_height, "m"),
                    ("box_density", box_density, "kg/m^3"), ("zone_rate", zone_rate, "1/s")):
        check_positive(n, v, u)
    if box_density >= 1000.0:
        raise InputError(f"box_density = {box_density:g} kg/m^3 does not float in water (1000 kg/m^3); "
                         "give a density below 1000")
    base = wave_flume_2d(dp=dp, depth=depth, length=length, beach_slope=beach_slope, wave_height=wave_height,
                         period=period, ramp_periods=ramp_periods, end_time=end_time, output_interval=output_interval,
                         gauges_x=tuple(gauges_x), options=options)
    s = box_density / 1000.0
    draft = s * box_height
    if draft >= depth:
        raise InputError(f"the box's draft {draft:g} m (box_height x box_density / 1000) reaches the bed "
                         f"(depth = {depth:g} m); use a lower box or deeper water")
    lo_x, hi_x = box_x - 0.5 * box_beam, box_x + 0.5 * box_beam
    if lo_x < 4 * dp or hi_x > length:
        raise InputError(f"box_x = {box_x:g} m puts the box outside the flume's constant depth "
                         f"(0 to {length:g} m); keep it between {0.5 * box_beam + 4 * dp:g} and "
                         f"{length - 0.5 * box_beam:g} m")
    if not hi_x < zone_start:
        raise InputError(f"zone_start = {zone_start:g} m must lie beyond the box (its back at {hi_x:g} m)")
    for g in gauges_x:
        if lo_x - 2 * dp <= g <= hi_x + 2 * dp:
            raise InputError(f"gauges_x = {g:g} m lies on the box ({lo_x:g} to {hi_x:g} m); move the gauge")
    top = base.solids[-1].shape.hi[2]
    x_end = base.solids[-1].shape.hi[0]
    if depth - draft + box_height >= top:
        raise InputError(f"box_height = {box_height:g} m sticks out of the flume's walls ({top:g} m high)")
    if upright_ratio(s) >= box_beam / box_height:
        raise InputError(f"box_beam / box_height = {box_beam / box_height:.3g} is too narrow to float upright "
                         f"at density {box_density:g} kg/m^3: it capsizes unless B / H_b > "
                         f"sqrt(6 s (1 - s)) = {upright_ratio(s):.3g}")
    z_bottom = depth - draft
    box = Solid(name="box", shape=Box(lo=(lo_x, 0.0, z_bottom), hi=(hi_x, 0.0, z_bottom + box_height)),
                floating=FloatingBody(density=float(box_density), interval=float(body_interval or period / 40)))
    zone = DampingZone(start=(zone_start, 0.0, 0.0), end=(x_end, 0.0, 0.0), rate=float(zone_rate))
    params = dict(base.parameters, box_x=box_x, box_beam=box_beam, box_height=box_height, box_density=box_density,
                  zone_start=zone_start, zone_rate=zone_rate, body_interval=body_interval)
    case = base.model_copy(update=dict(
        name="floating-box-2d", solids=base.solids + [box], damping=[zone], parameters=params,
        description=base.description.replace("2D wave flume", "2D wave flume with a floating box")
        + f"; box B = {box_beam:g} m x {box_height:g} m of {box_density:g} kg/m^3 at x = {box_x:g} m, "
          f"damping zone from {zone_start:g} m"))
    case.revalidate()
    return case


def upright_ratio(s):
    """The beam-to-height ratio above which a 2D box of relative density `s` floats upright: sqrt(6 s (1 - s))
    (metacentric height B^2 / (12 s H) - H (1 - s) / 2 > 0)."""
    return math.sqrt(6.0 * s * (1.0 - s))
