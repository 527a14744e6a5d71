"""Tidal bores in a flume, after the SPH study of Liu, Li, Shao & Tan.

Physics: water of depth d0 = 0.1 m flowing at U towards a closed gate
stops at the gate; the positive surge (bore) travels upstream. Its
celerity and conjugate depth follow the Rankine-Hugoniot (Belanger)
relations; with Froude number Fr = (U + c) / sqrt(g d0) = 1.19 (U = 0.3 m/s)
the bore is undular, with Fr = 1.63 (U = 0.7 m/s) it breaks. The inflow is
made, as in the paper, by a vertical wall pushed at speed U at the upstream
end (a moving-wall inflow), or (``inflow = "open"``) by an open boundary there
that lets water in at U with the depth d0 (`shoal.open_boundary`; one
process on the CPU).

Geometry (paper, section 3.2): a 3 m x 0.3 m x 0.4 m flume; here the gate
is the wall at x = 0, the water moves towards it (velocity -U along x) and
the bore travels towards +x; the moving wall starts at x = 3 m. The paper
ran dp = 0.005 m on half the width (580,752 particles: 360,000 fluid,
212,634 fixed and 8,118 moving boundary particles) to t = 1.6 s with
predictor-corrector steps of 2e-5 s, XSPH (0.5), an MLS filter every 30
steps and SPS turbulence.

`tidal_bore_piers` adds the bridge-pier constriction of the paper's
section 4: two half-channel constrictions, one on each side wall, from
x = 1.0 m (1.0 m upstream of the gate), narrowing the channel with 1:1
convergent and divergent sections; wave gauges at x = 1.0, 1.4 and 1.6 m
(entrance, mid-section and exit). The paper's Fig. 11 (dimensions in cm)
is not in the text; here each constriction protrudes 0.05 m (the junction
the paper mentions "at around x = 1.0 m and 1.05 m" fits a 1:1 section
0.05 m long) and the constriction ends at x = 1.6 m; all three are
parameters.

Run time on 2 cores: at dp = 0.02 m (about 16k particles) a second of
flow takes a few minutes; the paper's dp = 0.005 m is a GPU run.
"""

from __future__ import annotations

import math

from ..case import Case, Fluid, FluidRegion, Output, Solid, SymmetryPlane
from ..errors import InputError
from ..geometry.shapes import Box, Prism, Tank
from ..motions import ConstantVelocity
from ..open_boundary import OpenBoundary
from ..probes import WaveGauge
from ..options import SPHOptions
from ..memory import check_count
from ._checks import check_dp, check_positive

LENGTH, WIDTH, HEIGHT, DEPTH = 3.0, 0.3, 0.4, 0.1
PAPER_OPTIONS = dict(kernel="cubic", xsph=0.5, mls_every=30, integrator="predictor_corrector",
                     density_diffusion="none", alpha=0.1, turbulence="sps", visco_bound_factor=0.0,
                     wall_pressure="dynamic")
"""The paper's scheme: predictor-corrector, XSPH 0.5, MLS every 30 steps, SPS turbulence, artificial
viscosity (the paper's Eq. 2; it gives no alpha: 0.1 here), dynamic boundary particles (SPHysics's,
which the validation report's bore and bridge-pier runs used; Adami walls left Favre's first-wave
amplitude where it was, -30.3 % against -30.9 % at d0/10). The walls are free-slip for the viscous
term (visco_bound_factor = 0): on a bed of dynamic particles the artificial viscosity, about 1700
times water's at dp = 5 mm, acts as a bed friction that slowed the inflow by a third within 0.8 s
and the undular bore by 7.5 %; a real smooth bed's boundary layer is about 1 mm thick over the run."""


def _bore(dp, inflow_speed, depth, half, end_time, output_interval, options, piers, pier_start, pier_length,
          constriction, dim=3, length=LENGTH, gauges_x=None, inflow="wall"):
    check_positive("inflow_speed", inflow_speed, "m/s")
    check_positive("length", length, "m")
    check_positive("depth", depth, "m")
    if depth >= HEIGHT / 2:
        raise InputError(f"depth = {depth:g} m leaves no room for the bore in a {HEIGHT:g} m deep flume; "
                         f"use depth < {HEIGHT / 2:g} m")
    if dim not in (2, 3):
        raise InputError(f"dim = {dim!r}; allowed 2 (the flume's x-z section) or 3")
    if dim == 2 and (half or piers):
        raise InputError("the 2D flume (dim = 2) has no width: no half-width model, no piers")
    W = (WIDTH / 2 if half else WIDTH) if dim == 3 else 0.0
    check_dp(dp, min(depth, W if not piers else W - constriction) if dim == 3 else depth,
             "the water depth (or the channel width)")
    g = 9.81
    t_wall = 3 * dp
    check_count((length + t_wall) * (W if dim == 3 else dp) * HEIGHT / dp**3, 3)
    if inflow not in ("wall", "open"):
        raise InputError(f"inflow = {inflow!r}; allowed \"wall\" (a moving wall pushes the water) or \"open\" "
                         "(an open boundary lets it in)")
    open_faces = ["top", "xmax"] + (["ymax"] if half else [])
    opened = []
    if inflow == "wall":
        solids = [Solid(name="inflow wall", shape=Box(lo=(length, 0.0, 0.0), hi=(length + t_wall, W, HEIGHT)),
                        motion="inflow")]
        motions = [ConstantVelocity(name="inflow", velocity=(-inflow_speed, 0.0, 0.0))]
        x_end = length + t_wall
    else:  # the flume runs on under the buffer; water at d0 comes in at U
        solids, motions = [], []
        x_end = length + 6 * dp
        opened = [OpenBoundary(name="inflow", point=(length, 0.0, 0.0), normal=(-1.0, 0.0, 0.0), lo=(length, 0.0, 0.0),
                               hi=(length, W, HEIGHT), velocity=inflow_speed, level=depth)]
    solids.append(Solid(name="flume", shape=Tank(lo=(0.0, 0.0, 0.0), hi=(x_end, W, HEIGHT), open=open_faces)))
    if piers:
        check_positive("constriction", constriction, "m")
        check_positive("pier_length", pier_length, "m")
        if constriction >= WIDTH / 2:
            raise InputError(f"constriction = {constriction:g} m closes the {WIDTH:g} m channel; "
                             f"use constriction < {WIDTH / 2:g} m")
        if pier_length < 2 * constriction:
            raise InputError(f"pier_length = {pier_length:g} m is shorter than the two 1:1 sections "
                             f"({2 * constriction:g} m)")
        x0, x1, c = pier_start, pier_start + pier_length, constriction
        if not (0 < x0 and x1 < length - 0.5):
            raise InputError(f"the piers from x = {x0:g} to {x1:g} m must lie inside the flume (0, {length - 0.5:g}) m")
        # a constriction on the y = 0 wall, 1:1 convergent and divergent ends (plan view, x-y)
        solids.append(Solid(name="pier y0", shape=Prism(
            vertices=[(x0, -0.01), (x0, 0.0), (x0 + c, c), (x1 - c, c), (x1, 0.0), (x1, -0.01)],
            axis="z", lo=0.0, hi=HEIGHT)))
        if not half:
            solids.append(Solid(name="pier y1", shape=Prism(
                vertices=[(x0, WIDTH + 0.01), (x0, WIDTH), (x0 + c, WIDTH - c), (x1 - c, WIDTH - c), (x1, WIDTH),
                          (x1, WIDTH + 0.01)], axis="z", lo=0.0, hi=HEIGHT)))
    fluids = [FluidRegion(shape=Box(lo=(0.0, 0.0, 0.0), hi=(length, W, depth)), velocity=(-inflow_speed, 0.0, 0.0))]
    sym = [SymmetryPlane(point=(0.0, W, 0.0), normal=(0.0, -1.0, 0.0))] if half else []
    c0_speed = inflow_speed + math.sqrt(g * depth)
    # Belanger: bore celerity c (relative to the ground) with still water downstream of the front moving at
    # -U: the conjugate depth d1 solves (U + c) ... reported in the description as the Froude number.
    fr = froude_of_bore(inflow_speed, depth)
    name = "tidal-bore-piers" if piers else "tidal-bore"
    desc = (f"{'undular' if fr < 1.3 else 'breaking'} tidal bore, U = {inflow_speed:g} m/s, d0 = {depth:g} m, "
            f"Fr = {fr:.2f}" + (", bridge-pier constriction" if piers else "") + (", half width" if half else ""))
    params = dict(dp=dp, inflow_speed=inflow_speed, depth=depth, half=half, froude=fr, length=length)
    if inflow != "wall":
        params["inflow"] = inflow
    y_gauge = W / 2 if not half else W - 2 * dp  # on the centre line (next to the symmetry plane)
    if piers:
        params.update(pier_start=pier_start, pier_length=pier_length, constriction=constriction)
        gx = {"entrance": pier_start, "middle": pier_start + 0.4, "exit": pier_start + pier_length}
    elif gauges_x is None:
        gx = {"x0.5": 0.5, "x1.0": 1.0, "x1.5": 1.5}
    else:
        gx = {f"x{float(x):g}": float(x) for x in gauges_x}
        bad = [x for x in gx.values() if not 0 < x < length]
        if bad:
            raise InputError(f"gauges_x = {bad[0]:g} m lies outside the flume; allowed 0 < x < length = {length:g} m")
        params["gauges_x"] = list(gx.values())
    probes = [WaveGauge(name=k, x=x, y=y_gauge, z0=0.5 * depth, z1=HEIGHT, interval=0.01) for k, x in gx.items()]
    return Case(name=name, dim=dim, dp=float(dp), end_time=float(end_time), description=desc,
                fluid=Fluid(depth=depth, u_max=c0_speed, surface_level=depth),
                options=options or SPHOptions(**PAPER_OPTIONS),
                solids=solids, fluids=fluids,
                motions=motions, open_boundaries=opened, symmetry_planes=sym, probes=probes, output=Output(interval=float(output_interval)),
                parameters=params)


def froude_of_bore(inflow_speed, depth, g=9.81):
    """Froude number (U + c) / sqrt(g d0) of the bore (`shoal.analysis.bore_from_inflow`)."""
    from ..analysis.bore import bore_from_inflow

    return bore_from_inflow(inflow_speed, depth, g)[2]


def tidal_bore(dp=0.01, inflow_speed=0.3, depth=DEPTH, half=False, dim=3, end_time=1.6, output_interval=0.05,
               options=None, length=LENGTH, gauges_x=None, inflow="wall"):
    """Tidal bore in the 3 m x 0.3 m x 0.4 m flume (moving-wall inflow).

    Parameters
    ----------
    dp : float
        Particle spacing [m]; the paper used 0.005 m (and 0.01 m in its
        sensitivity test); 0.02 m is a quick run.
    inflow_speed : float
        Inflow speed U [m/s]: 0.3 makes the paper's undular bore (Fr 1.19),
        0.7 its breaking bore (Fr 1.63).
    depth : float
        Initial depth d0 [m] (0.1).
    half : bool
        Model half the width with a symmetry plane at y = 0.15 m, as the
        paper did (`shoal.case.SymmetryPlane`).
    dim : {3, 2}
        2 runs the flume's x-z section (a 2D bore: dp = 0.005 m, 13,610
        particles, about 15 minutes on 2 cores to t = 1.6 s).
    end_time, output_interval : float
        [s]; the paper ran to 1.6 s.

    length : float
        Flume length [m] from the gate to the inflow wall (the paper's 3 m);
        a longer flume lets an undular bore develop further (Favre's
        undulations were measured tens of depths from where they formed).
    gauges_x : sequence of float, optional
        Wave-gauge positions [m from the gate] (gauges ``gauge_x<X>.csv``);
        default x = 0.5, 1.0 and 1.5 m.
    inflow : {"wall", "open"}
        How the water comes in at x = `length`: pushed by a wall moving at U
        (the paper's), or through an open boundary imposing U and the depth
        d0 (issue 33).

    Wave gauges on the centre line record the bore every 0.01 s
    (``gauge_*.csv`` in the run's directory).
    """
    return _bore(dp, inflow_speed, depth, half, end_time, output_interval, options, False, 1.0, 0.6, 0.05, dim,
                 length, gauges_x, inflow)


def tidal_bore_piers(dp=0.01, inflow_speed=0.3, depth=DEPTH, half=False, pier_start=1.0, pier_length=0.6,
                     constriction=0.05, end_time=1.6, output_interval=0.05, options=None):
    """The undular bore through the bridge-pier constriction (paper section 4).

    Parameters as `tidal_bore`, and `pier_start` [m] (x of the entrance of
    the constriction, 1.0 m from the gate), `pier_length` [m] and
    `constriction` [m] (how far each constriction narrows the channel).
    Wave gauges at x = pier_start, pier_start + 0.4 m and pier_start +
    pier_length (the paper's 1.0, 1.4 and 1.6 m: entrance, mid-section and
    exit) on the centre line, every 0.01 s (``gauge_*.csv``).
    """
    return _bore(dp, inflow_speed, depth, half, end_time, output_interval, options, True, pier_start,
                 pier_length, constriction)
