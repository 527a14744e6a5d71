"""The static elastic catenary of a mooring line: the analytic check of the lines that MoorDyn computes.

A uniform line of unstretched length L, submerged weight w per unit length [N/m] and axial stiffness EA [N]
hangs in a vertical plane from its anchor A to its fairlead F, F being x_F [m] along and z_F [m] above A.
H is the horizontal and V the vertical force that the line pulls the fairlead with (towards the anchor and
down), so the fairlead tension is T_F = sqrt(H^2 + V^2). H is the same everywhere along the line (no
horizontal load acts on it), and the vertical force falls by w per unit unstretched length towards A.

Fully suspended (Irvine 1981, "Cable Structures", MIT Press, section 2.2; Jonkman 2007, "Dynamics modeling
and loads analysis of an offshore floating wind turbine", NREL/TP-500-41958, Appendix, eqs. (C-1) and (C-2))

    x_F = (H / w) [asinh(V / H) - asinh((V - w L) / H)] + H L / EA,
    z_F = (H / w) [sqrt(1 + (V / H)^2) - sqrt(1 + ((V - w L) / H)^2)] + (V L - w L^2 / 2) / EA.

Part of the line on a frictionless, flat seabed through A (Jonkman 2007, eqs. (C-3) and (C-4) with the
friction coefficient C_B = 0): the line touches down L_B = L - V / w from the fairlead's end, measured along
the unstretched line, and lies straight on the seabed from there to A with tension H,

    x_F = L - V / w + (H / w) asinh(V / H) + H L / EA,
    z_F = (H / w) [sqrt(1 + (V / H)^2) - 1] + V^2 / (2 EA w).

The two pairs agree at touch-down (V = w L), so the seabed case is the fully suspended one while V >= w L.
`catenary_tension` solves the pair for (H, V) with `scipy.optimize.root`, from the starting guess of
Peyrot & Goulois (1979, "Analysis of cable structures", Computers & Structures 10, 805-813) that FAST's
quasi-static line model and MAP++ use:

    lambda_0 = 0.2 if sqrt(x_F^2 + z_F^2) >= L, else sqrt(3 ((L^2 - z_F^2) / x_F^2 - 1)),
    H_0 = w x_F / (2 lambda_0),   V_0 = (w / 2) (z_F / tanh(lambda_0) + L).

EA = inf gives the inextensible catenary. H = 0 has closed forms: a slack line hangs straight down from the
fairlead over the length s that z_F = s + w s^2 / (2 EA) gives, with V = w s and its other L - s on the
seabed (when x_F <= L - s: the grounded part needs no tension to reach the anchor), or a vertical line
(x_F = 0) is taut, z_F = L + (V L - w L^2 / 2) / EA, that is V = EA (z_F - L) / L + w L / 2.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from scipy.optimize import root


class Catenary(NamedTuple):
    """The static line's forces (`catenary_tension`).

    Attributes
    ----------
    horizontal : float
        H [N], the horizontal tension (the same along the line).
    vertical : float
        V [N], the vertical force of the line on the fairlead (downwards).
    fairlead_tension : float
        sqrt(H^2 + V^2) [N].
    anchor_tension : float
        [N]: H where the line lies on the (frictionless) seabed at the anchor, else
        sqrt(H^2 + (V - w L)^2).
    grounded_length : float
        L_B [m], the unstretched length lying on the seabed (0 when fully suspended).
    """

    horizontal: float
    vertical: float
    fairlead_tension: float
    anchor_tension: float
    grounded_length: float


def _spans(h, v, length, weight, stiffness, seabed):
    """(x_F, z_F) of the line pulled by (H, V) (module docstring): the fully suspended pair, or the pair with
    L_B = L - V / w on the seabed when `seabed` and V < w L."""
    w, el = weight, length
    compliance = 0.0 if math.isinf(stiffness) else 1.0 / stiffness
    if seabed and v < w * el:
        x = el - v / w + (h / w) * math.asinh(v / h) + h * el * compliance
        z = (h / w) * (math.hypot(1.0, v / h) - 1.0) + v * v * compliance / (2.0 * w)
        return x, z
    va = v - w * el
    x = (h / w) * (math.asinh(v / h) - math.asinh(va / h)) + h * el * compliance
    z = (h / w) * (math.hypot(1.0, v / h) - math.hypot(1.0, va / h)) + (v * el - 0.5 * w * el * el) * compliance
    return x, z


def _vertical_line(vertical_span, length, weight, stiffness, seabed):
    """H = 0: a line hanging straight down from the fairlead (module docstring)."""
    w, el, z = weight, length, vertical_span
    compliance = 0.0 if math.isinf(stiffness) else 1.0 / stiffness
    if z >= el * (1.0 + 0.5 * w * el * compliance):  # taut: all of it off the seabed
        if compliance == 0.0:
            raise ValueError(f"an inextensible line as long as its vertical span ({el:g} m) has any tension "
                             f"above {w * el:g} N: no single catenary")
        v = w * el / 2.0 + (z - el) / (el * compliance)
        return Catenary(0.0, v, abs(v), abs(v - w * el), 0.0)
    if not seabed:
        raise ValueError("a vertical line shorter than its span's hanging length without a seabed folds: "
                         "no catenary")
    # z = s + w s^2 / (2 EA): the positive root, written to keep its precision when EA is large
    s = z if compliance == 0.0 else 2.0 * z / (1.0 + math.sqrt(1.0 + 2.0 * w * z * compliance))
    return Catenary(0.0, w * s, w * s, 0.0, el - s)


def catenary_tension(horizontal_span, vertical_span, length, weight, stiffness, seabed=True, tol=1e-12):
    """The static elastic catenary's fairlead and anchor forces (module docstring for the equations).

    Parameters
    ----------
    horizontal_span : float
        x_F >= 0 [m], the fairlead's horizontal distance from the anchor.
    vertical_span : float
        z_F [m], the fairlead's height above the anchor (> 0 with a seabed).
    length : float
        L > 0 [m], the unstretched length.
    weight : float
        w > 0 [N/m], the weight in water per unit unstretched length, (m - rho_w A) g, A the line's
        volume-equivalent cross-section.
    stiffness : float
        EA > 0 [N], the axial stiffness; ``math.inf`` for an inextensible line.
    seabed : bool
        True: a flat frictionless seabed through the anchor carries the part of the line that reaches it;
        False: the line is fully suspended whatever its sag (it may hang below the anchor).
    tol : float
        Relative tolerance of the solve.

    Returns
    -------
    Catenary
        H, V, the fairlead tension sqrt(H^2 + V^2), the anchor tension and the grounded length.

    Raises
    ------
    ValueError
        A non-positive length, weight or stiffness, a negative horizontal span, a fairlead not above the
        anchor with a seabed, a line too short for an inextensible span, or no convergence.
    """
    x, z = float(horizontal_span), float(vertical_span)
    el, w, ea = float(length), float(weight), float(stiffness)
    for name, value in (("length", el), ("weight", w), ("stiffness", ea)):
        if not value > 0:
            raise ValueError(f"{name} = {value:g}: must be above 0")
    if not (x >= 0 and math.isfinite(x) and math.isfinite(z)):
        raise ValueError(f"spans ({x:g}, {z:g}) m: the horizontal span must be finite and >= 0")
    if seabed and not z > 0:
        raise ValueError(f"vertical span = {z:g} m: with a seabed through the anchor the fairlead is above it")
    if math.isinf(ea) and math.hypot(x, z) > el:
        raise ValueError(f"an inextensible line of length {el:g} m cannot reach a fairlead {math.hypot(x, z):g} m "
                         "from its anchor")
    if x == 0.0:
        return _vertical_line(z, el, w, ea, seabed)
    if seabed:
        # slack: with H -> 0 the line hangs straight down over s (z = s + w s^2 / (2 EA)) and its L - s on the
        # seabed reach at most L - s from the anchor; a fairlead nearer needs no horizontal tension
        compliance = 0.0 if math.isinf(ea) else 1.0 / ea
        s = z if compliance == 0.0 else 2.0 * z / (1.0 + math.sqrt(1.0 + 2.0 * w * z * compliance))
        if s < el and x <= el - s:
            return Catenary(0.0, w * s, w * s, 0.0, el - s)

    # Peyrot & Goulois (1979)'s starting guess
    if math.hypot(x, z) >= el:
        lam = 0.2
    else:
        lam = math.sqrt(3.0 * ((el * el - z * z) / (x * x) - 1.0))
    starts = [(abs(w * x / (2.0 * lam)), 0.5 * w * (z / math.tanh(lam) + el))]
    # and, for a taut line (where that guess can be far off when the line is near vertical), the chord's
    # tension EA (d / L - 1) along the chord d, with the weight shared between the ends
    chord = math.hypot(x, z)
    if chord > el and not math.isinf(ea):
        tension = ea * (chord / el - 1.0)
        starts.append((tension * x / chord, tension * z / chord + 0.5 * w * el))

    # unknowns: ln(H / (w L)) (keeps H > 0) and V / (w L); residuals in units of L
    scale = w * el

    def residual(p):
        h, v = scale * math.exp(min(float(p[0]), 700.0)), scale * float(p[1])
        if h == 0.0:
            return [1e3, 1e3]  # underflow: far from any solution
        xs, zs = _spans(h, v, el, w, ea, seabed)
        return [(xs - x) / el, (zs - z) / el]

    best = None
    for h0, v0 in starts:
        for method in ("hybr", "lm"):
            sol = root(residual, [math.log(h0 / scale), v0 / scale], method=method, tol=tol)
            err = float(np.max(np.abs(residual(sol.x))))
            if best is None or err < best[0]:
                best = (err, sol)
            if err < 1e-9:
                break
        if best[0] < 1e-9:
            break
    err, sol = best
    if not err < 1e-9:
        raise ValueError(f"the catenary solve did not converge (span error {err * el:.3g} m): {sol.message}")
    h, v = scale * math.exp(float(sol.x[0])), scale * float(sol.x[1])
    grounded = max(el - v / w, 0.0) if seabed else 0.0
    anchor = h if grounded > 0 else math.hypot(h, v - w * el)
    return Catenary(h, v, math.hypot(h, v), anchor, grounded)
