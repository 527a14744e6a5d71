"""Warnings about a case's numerics that its author may not intend.

The default scheme (`shoal.SPHOptions`: artificial viscosity alpha = 0.1, h = sqrt(dim) dp, walls that
rub) is DualSPHysics's, tuned for dam breaks, where it keeps violent flows stable. It damps waves: a
case that makes waves with a paddle and leaves the scheme at those defaults loses wave height along the
flume (`benchmarks/wave_decay.py` measures how much). The built-in wave flumes use the wave scheme
`WAVE_OPTIONS` of `shoal.cases.wave_flume` (laminar viscosity, free-slip walls for the viscous term, a
wider kernel); `wave_scheme_warnings` says so when a case with a wave paddle does not. `case_warnings`
adds the motions fast enough to compress the fluid.
"""

from __future__ import annotations

WAVE_MOTIONS = ("piston", "solitary", "irregular", "focused", "flap")
"""Motion types that make waves (`shoal.motions.PistonWavemaker`, `SolitaryPiston`, `IrregularWaves`,
`FocusedWaves`, `FlapWavemaker`)."""

ALPHA_FOR_WAVES = 0.01
"""Artificial viscosity above which a wave case is warned about (DualSPHysics's wave examples use 0.01)."""


def case_warnings(case):
    """Every warning about `case` (one line each): `wave_scheme_warnings`, and the motions and fluid
    regions faster than `shoal.motions.MACH_LIMIT` c0 (`shoal.motions.check_motion_speeds`)."""
    import math

    from .motions import MACH_LIMIT, check_motion_speeds, fast_warning

    c0 = case.sound_speed
    fast = [fast_warning(f"fluids[{i}] starts at", math.hypot(*f.velocity), c0)
            for i, f in enumerate(case.fluids) if math.hypot(*f.velocity) > MACH_LIMIT * c0]
    return wave_scheme_warnings(case) + check_motion_speeds(case.motions, c0, case.end_time,
                                                            case.motion_reach()) + fast


def wave_scheme_warnings(case):
    """Warnings (one line each) for a case that makes waves with dissipative numerics.

    Parameters
    ----------
    case : shoal.Case

    Returns
    -------
    list of str
        Empty unless the case has a wave paddle (a motion whose type is in `WAVE_MOTIONS`) and runs with the
        artificial viscosity above `ALPHA_FOR_WAVES`, or with a smaller kernel than the wave scheme's,
        or with wall friction.
    """
    from .cases.wave_flume import WAVE_OPTIONS

    paddles = [m.name for m in case.motions if getattr(m, "type", None) in WAVE_MOTIONS]
    if not paddles:
        return []
    o = case.options
    wave = WAVE_OPTIONS[case.dim]
    found = []
    if o.viscosity == "artificial" and o.alpha > ALPHA_FOR_WAVES:
        found.append(f"artificial viscosity alpha = {o.alpha:g}")
    if o.coef_h < wave["coef_h"]:
        found.append(f"coef_h = {o.coef_h:g}")
    if o.visco_bound_factor > 0 and o.viscosity == "artificial":
        found.append(f"visco_bound_factor = {o.visco_bound_factor:g} (wall friction)")
    if not found:
        return []
    advice = ", ".join(f"{k} = {v!r}" if isinstance(v, str) else f"{k} = {v:g}" for k, v in wave.items())
    return [f"the case makes waves (motion {paddles[0]!r}) with numerics that damp them: {', '.join(found)}; "
            f"the wave flumes' [options] are {advice} (benchmarks/wave_decay.py measures the loss)"]
