"""A moored box in a 3D basin: a floating box held by four chains, in regular waves (issue 32).

Physics: a piston paddle makes regular waves of height H and period T in a basin 2 m wide with water 0.5 m
deep (the `wave-flume-3d` flume, `shoal.cases.wave_flume`); 2 m from the paddle a box 0.4 x 0.4 x 0.2 m of
density rho_b floats at the still-water level (B / H_b = 2: upright for any density between 0.21 and 0.79 of
the water's, B / H_b > sqrt(6 s (1 - s))), held by four chains from anchors on the bed to its bottom corners,
spread 1 m fore and aft and 0.4 m to the sides of them. The chains are MoorDyn v2 lines
(``src/shoal/data/mooredBox3d_moordyn.txt``: 0.1 kg/m, EA = 10 kN, 1.2 m long in 30 segments, part of each on the bed at
rest; `shoal.mooring`); a damping zone over the beach absorbs what passes the box. The box's motion and the
water's loads on it are in ``body_box.csv``, the chains' tensions and shapes in ``mooring_line<k>.csv`` and
``mooring_line<k>_nodes.csv``, a wave gauge 1 m from the paddle in ``gauge_x1.csv``.
"""

from __future__ import annotations

from pathlib import Path

from ..case import DampingZone, Solid
from ..errors import InputError
from ..floating import Fairlead, FloatingBody, MooringLines
from ..geometry.shapes import Box
from ._checks import check_positive
from .wave_flume import wave_flume_3d

MOORDYN_FILE = Path(__file__).resolve().parent.parent / "data" / "mooredBox3d_moordyn.txt"
"""The chains of the case (a MoorDyn v2 input file shipped with the package)."""

DEPTH, WIDTH, LENGTH = 0.5, 2.0, 4.0
BOX_LO, BOX_HI = (1.8, 0.8), (2.2, 1.2)  # the box's plan [m]: its x and y extents
BOX_HEIGHT = 0.2


def moored_box_3d(dp=0.04, wave_height=0.04, period=1.2, ramp_periods=2.0, box_density=500.0, end_time=10.0,
                  output_interval=0.1, body_interval=None, options=None):
    """3D basin with a moored floating box in regular waves (module docstring).

    Parameters
    ----------
    dp : float
        Particle spacing [m]; the box's faces lie on the lattice when 0.2 m is a whole number of spacings
        (0.05, 0.04, 0.025, 0.02, ... m).
    wave_height, period : float
        The paddle's regular waves: height H [m] and period T [s] (`shoal.motions.PistonWavemaker`).
    ramp_periods : float
        The paddle's start-up ramp [periods].
    box_density : float
        [kg/m^3], between 210 and 790 (upright); it floats with box_density / 1000 of its 0.2 m height under
        water, its bottom placed at that draft at t = 0.
    end_time, output_interval : float
        [s].
    body_interval : float, optional
        Seconds between the rows of ``body_box.csv`` and the chains' CSVs; default T / 40.
    options : SPHOptions, optional
        Default: the wave flumes' scheme.

    Returns
    -------
    Case
    """
    check_positive("box_density", box_density, "kg/m^3")
    s = box_density / 1000.0
    if not 0.21 < s < 0.79:
        raise InputError(f"box_density = {box_density:g} kg/m^3: the 0.4 x 0.2 m box floats upright only between "
                         "210 and 790 kg/m^3 (B / H > sqrt(6 s (1 - s))); give a density in that range")
    if abs(0.2 / dp - round(0.2 / dp)) > 1e-6:
        raise InputError(f"dp = {dp:g} m: 0.2 m must be a whole number of spacings (0.05, 0.04, 0.025, 0.02 ...) "
                         "so that the box's faces and its fairleads lie on the lattice")
    base = wave_flume_3d(dp=dp, depth=DEPTH, length=LENGTH, beach_slope=0.2, width=WIDTH, wave_height=wave_height,
                         period=period, ramp_periods=ramp_periods, end_time=end_time, output_interval=output_interval,
                         gauges_x=(1.0,), options=options)
    bottom = DEPTH - s * BOX_HEIGHT
    box = Solid(name="box", shape=Box(lo=(BOX_LO[0], BOX_LO[1], bottom), hi=(BOX_HI[0], BOX_HI[1], bottom + BOX_HEIGHT)),
                floating=FloatingBody(density=float(box_density), interval=body_interval or period / 40))
    corners = [(x, y, bottom) for x in (BOX_LO[0], BOX_HI[0]) for y in (BOX_LO[1], BOX_HI[1])]  # the file's order
    chains = MooringLines(file=str(MOORDYN_FILE), origin=(0.0, 0.0, DEPTH), interval=body_interval or period / 40,
                          fairleads=[Fairlead(body="box", point=c) for c in corners])
    x_end = base.solids[-1].shape.hi[0]
    zone = DampingZone(start=(3.0, 0.0, 0.0), end=(x_end, 0.0, 0.0))
    return base.model_copy(update={
        "name": "moored-box-3d",
        "description": f"3D basin: a box of {box_density:g} kg/m^3 moored by four chains (MoorDyn) in regular waves "
                       f"H = {wave_height:g} m, T = {period:g} s, d = {DEPTH:g} m",
        "solids": [*base.solids, box], "moorings": [chains], "damping": [zone],
        "parameters": dict(dp=dp, wave_height=wave_height, period=period, ramp_periods=ramp_periods,
                           box_density=box_density, moordyn_file=MOORDYN_FILE.name),
    }).revalidate()
