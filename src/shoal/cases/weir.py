"""A 2D broad-crested weir with a free overfall (issue 33): a reservoir held at its level by an open boundary
spills over a long flat crest.

Water enters a level flume at x = 0 through an inlet that holds the level `upstream_depth` y0 (the velocity
that holds it, from the shallow-water Riemann invariant: ``velocity_mode = "riemann"``,
`shoal.open_boundary`), runs `reservoir_length` to a weir of height P = `weir_height`, climbs its upstream ramp
(rise 1 in `ramp_run`, no separation at its toe or its top), crosses its flat crest `crest_length` long and
falls off the crest's downstream end, where the flume ends and the falling water leaves the domain. The bed
and the weir are free-slip (Adami walls, ``visco_bound_factor = 0``): the critical-flow theory below has no
friction. The smoothing length is h = 1.3 sqrt(2) dp (`WEIR_OPTIONS`).

Critical flow over a broad crest (Henderson 1966, section 6.5; Bos 1976): with the energy head above the
crest H = h1 - P + V1^2 / (2 g) (h1 the depth upstream, V1 = q / h1 the approach velocity), the flow over the
crest passes through critical depth y_c = 2 H / 3, and

    q = y_c sqrt(g y_c) = (2/3)^(3/2) sqrt(g) H^(3/2) = 0.385 sqrt(2 g) H^(3/2)

per metre of width. Gauges: the depth upstream (`h1`, at mid-reservoir) and on the crest (`crest_mid`, its
middle), the discharge through the reservoir and over the crest (`shoal.validation.weir` reads them).

References
----------
F. M. Henderson, *Open Channel Flow*, Macmillan (1966), section 6.5.
M. G. Bos, *Discharge measurement structures*, publication 20, International Institute for Land Reclamation and
Improvement (ILRI), Wageningen (1976), section 1.10 and chapter 4.
Q. Zhu, L. Hernquist, Y. Li, "Numerical convergence in smoothed particle hydrodynamics", The Astrophysical
Journal 800 (2015) 6.
"""

from __future__ import annotations

from ..case import Case, Fluid, FluidRegion, Output, Solid
from ..geometry.shapes import Box, Prism
from ..memory import check_count
from ..options import SPHOptions
from ._checks import check_dp, check_positive
from .sluice_gate import SLUICE_OPTIONS, reservoir_inlet

WEIR_OPTIONS = dict(SLUICE_OPTIONS, coef_h=1.3, delta=0.1)
"""The sluice gate's scheme (`shoal.cases.sluice_gate.SLUICE_OPTIONS`) with the default density diffusion
(delta = 0.1, with which the weir was validated; the gate's 0.2 is for its jet) and h = 1.3 sqrt(2) dp (coef_h = 1.3, 42
neighbours in the support against 25 at coef_h = 1). Over the crest the discharge depends on the neighbour
count as much as on dp: C of the critical-flow relation is 8.2 % below the theory at coef_h = 1.0, 6.0 % at 1.2
and 5.1 % at 1.3 with dp = 0.01 m, and 7.1 % at 1.0 and 3.8 % at 1.3 with dp = 0.005 m
(`validation/weir/README.md`): the particle approximation's error, which at a fixed h / dp does not vanish as
dp does (the scheme converges as h and dp go to zero with the neighbour count growing, Zhu, Hernquist & Li
2015). The support, 3.7 dp, stays within the walls' 4 layers."""


def weir_2d(dp=0.01, upstream_depth=0.2, weir_height=0.1, crest_length=0.4, ramp_run=2.0, reservoir_length=0.6,
            end_time=8.0, relaxation_time=3.0, output_interval=0.5, gauge_interval=0.02, options=None):
    """A 2D broad-crested weir `weir_height` P [m] high with a crest `crest_length` [m] long, fed from a
    reservoir held `upstream_depth` y0 [m] deep (module docstring)."""
    from ..errors import InputError
    from ..probes import FlowGauge, WaveGauge

    for name, value in (("upstream_depth", upstream_depth), ("weir_height", weir_height),
                        ("crest_length", crest_length), ("ramp_run", ramp_run),
                        ("reservoir_length", reservoir_length)):
        check_positive(name, value, "m" if name != "ramp_run" else "(run per unit rise)")
    check_positive("relaxation_time", relaxation_time, "s")
    y0, P = float(upstream_depth), float(weir_height)
    if not P < y0:
        raise InputError(f"weir_height = {P:g} m with upstream_depth = {y0:g} m: the reservoir's level must stand "
                         "above the crest")
    check_dp(dp, y0 - P, "the head over the crest")
    check_count(reservoir_length * y0 / dp**2, 2)
    layers = 4
    toe = float(reservoir_length)
    crest0 = toe + ramp_run * P
    end = crest0 + float(crest_length)
    top = 2.0 * y0
    weir = Prism(axis="y", vertices=[(toe, 0.0), (crest0, P), (end, P), (end, 0.0)])
    bed = Box(lo=(-3.0 * layers * dp, 0, -layers * dp), hi=(end, 0, 0))
    probes = [WaveGauge(name="h1", x=0.5 * toe, z0=-dp, z1=top, interval=gauge_interval),
              WaveGauge(name="crest_mid", x=crest0 + 0.5 * crest_length, z0=P - dp, z1=top, interval=gauge_interval),
              FlowGauge(name="reservoir", at=0.5 * toe, interval=gauge_interval),
              FlowGauge(name="crest", at=crest0 + 0.5 * crest_length, interval=gauge_interval)]
    return Case(name="weir-2d", dim=2, dp=float(dp), end_time=float(end_time),
                description="2D broad-crested weir with a free overfall, fed from a reservoir held at its level",
                fluid=Fluid(depth=y0, surface_level=y0),
                options=options or SPHOptions(**WEIR_OPTIONS),
                solids=[Solid(name="bed", shape=bed, layers=layers), Solid(name="weir", shape=weir, layers=layers)],
                fluids=[FluidRegion(shape=Box(lo=(0, 0, 0), hi=(crest0, 0, y0)))],
                open_boundaries=[reservoir_inlet(y0, top, relaxation_time)],
                probes=probes, output=Output(interval=float(output_interval)),
                parameters=dict(dp=dp, upstream_depth=y0, weir_height=P, crest_length=crest_length,
                                ramp_run=ramp_run, reservoir_length=reservoir_length,
                                relaxation_time=relaxation_time))
