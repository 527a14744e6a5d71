"""A 2D sluice gate in free flow (issue 33): a reservoir held at its level by an open boundary drains under a
vertical gate.

Water enters a level flume at x = 0 through an inlet that holds the `upstream_depth` y0 (the velocity that
holds the level, from the shallow-water Riemann invariant: ``velocity_mode = "riemann"``,
`shoal.open_boundary`), runs `reservoir_length` to a vertical sharp-edged gate whose lip stands `opening` a
above the bed, contracts beneath it into a supercritical jet and leaves the flume over its downstream end
(`downstream_length` past the gate), where the particles are removed. The gate is a plate with a vertical
upstream face, a flat lip 1.25 dp long and a 45-degree bevel on its downstream side, so that the jet springs
clear from a sharp edge as beneath a thin gate. The bed is free-slip (Adami walls, ``visco_bound_factor = 0``): the theory below has no
friction. The inlet's running mean of the water's speed is taken over `relaxation_time`
(`shoal.open_boundary.riemann_speed`): the reservoir's surges, 4 reservoir lengths over sqrt(g y0) long,
leave through it while the mean level holds.

Free flow under a gate (Henderson 1966, section 6.3): the jet contracts to y2 = Cc a (Cc about 0.61 for a
vertical gate), and the energy equation between the upstream section (depth y1) and the vena contracta gives

    q = Cc a sqrt(2 g y1 / (1 + Cc a / y1)),   Cd = q / (a sqrt(2 g y1)) = Cc / sqrt(1 + Cc a / y1).

Gauges: the depth upstream (wave gauge `y1` at mid-reservoir) and of the jet 3 a and 5 a past the gate's lip
(`jet3a`, `jet5a`; the profile through the contraction from 1 a on, `JET_GAUGES`), the discharge through the
reservoir and through the jet 4 a past the lip (flow gauges `upstream`, `downstream`;
`shoal.validation.sluice_gate` reads them).

References
----------
F. M. Henderson, *Open Channel Flow*, Macmillan (1966), section 6.3, eq. 6-8 and fig. 6-12.
"""

from __future__ import annotations

from ..case import Case, Domain, Fluid, FluidRegion, Output, Solid
from ..geometry.shapes import Box, Prism
from ..memory import check_count
from ..open_boundary import OpenBoundary
from ..options import SPHOptions
from ._checks import check_dp, check_positive

SLUICE_OPTIONS = dict(wall_pressure="adami", visco_bound_factor=0.0, alpha=0.01, coef_sound=10.0, delta=0.2)
"""The scheme's options beyond the defaults: Adami walls, a free-slip bed, an artificial viscosity of
alpha = 0.01 with c0 = 10 sqrt(g y0) (at the defaults, alpha = 0.1 and c0 = 20 sqrt(g y0), the viscosity
alpha h c0 / 8 makes the jet's Reynolds number U a / nu about 50 at a = 12 dp, and the jet under the gate a
viscous one that barely contracts), and twice the default density diffusion, delta = 0.2. The jet's depth
depends on delta: at dp = 0.01 m, a = 0.06 m, y2 / (0.61 a) - 1 is +24.7 % without the term, +6.3 % at
delta = 0.1, +4.5 % at 0.2 and +3.3 % at 0.3 (Cd +6.2, +1.7, +0.4, -0.8 %); at dp = 5 and 2.5 mm delta = 0.2
gives +4.9 and +4.8 % where 0.1 gives +6.2 and +5.4 % (`validation/sluice-gate/README.md`). The term is of
order h; its effect falls as dp does."""

JET_GAUGES = (1.0, 1.5, 2.0, 2.5, 3.0, 4.0, 5.0)
"""Where the jet's wave gauges stand, in openings a past the gate's upstream face: the validation's depth y2 is
the mean of those at 3 a and 5 a, past the contraction; the others give the surface's profile through it."""

GATE_BEVEL = 1.0
"""The gate's downstream bevel, rise over run (45 degrees)."""


def reservoir_inlet(level, top, relaxation_time):
    """The inlet at x = 0 (normal +x, its section from the bed z = 0 to `top`) that holds the `level` [m]
    (``velocity_mode = "riemann"``, `relaxation_time` [s])."""
    return OpenBoundary(name="reservoir", point=(0, 0, 0), normal=(1, 0, 0), lo=(0, 0, 0), hi=(0, 0, top),
                        level=level, velocity_mode="riemann", relaxation_time=relaxation_time)


def sluice_gate_2d(dp=0.01, upstream_depth=0.3, opening=0.06, reservoir_length=0.6, downstream_length=0.6,
                   end_time=6.0, relaxation_time=3.0, output_interval=0.5, gauge_interval=0.02, options=None):
    """A 2D sluice gate of `opening` a [m] fed from a reservoir held `upstream_depth` y0 [m] deep (module
    docstring)."""
    from ..errors import InputError
    from ..probes import FlowGauge, WaveGauge

    check_positive("upstream_depth", upstream_depth, "m")
    check_positive("opening", opening, "m")
    check_positive("reservoir_length", reservoir_length, "m")
    check_positive("downstream_length", downstream_length, "m")
    check_positive("relaxation_time", relaxation_time, "s")
    check_dp(dp, opening, "the gate opening")
    if not opening < 0.8 * upstream_depth:
        raise InputError(f"opening = {opening:g} m with upstream_depth = {upstream_depth:g} m: free flow under a "
                         "gate needs an opening below 0.8 of the upstream depth")
    if not downstream_length >= 6 * opening:
        raise InputError(f"downstream_length = {downstream_length:g} m: the jet's gauges stand 3 and 5 openings past "
                         f"the gate; give at least 6 openings ({6 * opening:g} m)")
    check_count(reservoir_length * upstream_depth / dp**2, 2)
    y0, a = float(upstream_depth), float(opening)
    top = 1.5 * y0
    layers = 4
    gate_x = float(reservoir_length)
    thick = layers * dp
    end = gate_x + float(downstream_length)
    # the lip: a flat 1.25 dp long at z = a (its lowest row of particles half a spacing above a, as the bed's
    # top row lies half a spacing below z = 0, so that the opening is a), then the bevel
    lip = 1.25 * dp
    gate = Prism(axis="y", vertices=[(gate_x, a), (gate_x + lip, a), (gate_x + thick, a + (thick - lip) * GATE_BEVEL),
                                     (gate_x + thick, top), (gate_x, top)])
    bed = Box(lo=(-3.0 * layers * dp, 0, -layers * dp), hi=(end, 0, 0))
    gauges = [WaveGauge(name="y1", x=0.5 * gate_x, z0=-dp, z1=top, interval=gauge_interval)]
    gauges += [WaveGauge(name=f"jet{k:g}a", x=gate_x + k * a, z0=-dp, z1=a + 2 * dp, interval=gauge_interval)
               for k in JET_GAUGES]
    flows = [FlowGauge(name="upstream", at=0.5 * gate_x, interval=gauge_interval),
             FlowGauge(name="downstream", at=gate_x + 4 * a, interval=gauge_interval)]
    case = Case(name="sluice-gate-2d", dim=2, dp=float(dp), end_time=float(end_time),
                description="2D sluice gate in free flow, fed from a reservoir held at its level",
                fluid=Fluid(depth=y0, surface_level=y0),
                options=options or SPHOptions(**SLUICE_OPTIONS),
                solids=[Solid(name="bed", shape=bed, layers=layers), Solid(name="gate", shape=gate, layers=layers)],
                fluids=[FluidRegion(shape=Box(lo=(0, 0, 0), hi=(gate_x, 0, y0)))],
                open_boundaries=[reservoir_inlet(y0, top, relaxation_time)],
                probes=gauges + flows,
                output=Output(interval=float(output_interval)),
                parameters=dict(dp=dp, upstream_depth=y0, opening=a, reservoir_length=reservoir_length,
                                downstream_length=downstream_length, relaxation_time=relaxation_time))
    # The domain ends where the bed does: the jet leaves it at the brink. With the automatic domain (2h past the
    # last particles) a particle falling off the end could reach the underside of the bed, where the Adami
    # walls' hydrostatic extrapolation, made for water above them, pulls it onto the wall; at dp = 2.5 mm one
    # slid back under the bed and stopped the run at t = 1.47 s with its density at 700 kg/m^3.
    lo, hi = case.resolved_domain()
    return case.model_copy(update={"domain": Domain(lo=tuple(lo), hi=(end, 0.0, float(hi[2])))}).revalidate()
