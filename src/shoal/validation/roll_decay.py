"""Roll decay of a floating 2D box against linear potential-flow theory (issue 32, must-show 3).

The heave-decay case's section (`shoal.validation.heave_decay`: beam B = 0.2 m, draft T = 0.1 m, B/T = 2,
Vugts' (1968) "rectangle B/T = 2", in water h = 0.4 m deep), ballasted so that it is stable in roll: its
centre of gravity at half the draft (KG = T/2, where a homogeneous box 0.2 m square would capsize), so
GM = KB + BM - KG = T/2 + B^2/(12 T) - T/2 = 0.0333 m. The box is pinned at its centre of gravity (free in
roll only), started upright with an angular velocity, and rings down. Its natural period and damping ratio
are measured from the ``ry`` column of ``body_<name>.csv`` (`shoal.validation.heave_decay.
decay_period_and_damping`) and compared with linear potential-flow theory for the same section rolling about
the same point (`rectangle_roll_coefficients`, `roll_decay_prediction`):

    omega_n = sqrt(C44 / (I + a44(omega_n))),   zeta = b44(omega_n) / (2 (I + a44(omega_n)) omega_n),

C44 = rho g B T GM the hydrostatic restoring moment per radian and metre, I the body's moment of inertia about
its centre of gravity, a44 and b44 its roll added inertia and radiation damping per metre about that point at
the frequency of oscillation, from the exact (eigenfunction-matching) solution of the antisymmetric radiation
problem of a rectangle in water of finite depth (Black, Mei & Bray 1971; Porter 2008), computed here; their
numbers for the case are kept in ``src/shoal/data/rollDecay_rectangle_BT2_h2B_potential_flow.csv``.

Linear potential flow leaves out the eddies shed at the box's sharp bilge corners, which damp the roll of a
barge beyond its wave radiation in experiments (Vugts 1968; Jung, Chang & Jo 2006; Himeno 1981): the
measured damping ratio is reported against the radiation damping, not held to it.

References
----------
J. H. Vugts, "The hydrodynamic coefficients for swaying, heaving and rolling cylinders in a free surface",
International Shipbuilding Progress 15 (167), 251-276, 1968.
J. L. Black, C. C. Mei, M. C. G. Bray, "Radiation and scattering of water waves by rigid bodies", J. Fluid
Mech. 46 (1), 151-164, 1971.
R. Porter, "Calculation of the hydrodynamic coefficients for cylinders of rectangular cross-section oscillating
in the free surface", technical report, School of Mathematics, University of Bristol, 2008.
Y. Himeno, "Prediction of ship roll damping: state of the art", report 239, Department of Naval Architecture
and Marine Engineering, University of Michigan, 1981.
K. H. Jung, K.-A. Chang, H. J. Jo, "Viscous effect on the roll motion of a rectangular structure", Journal of
Engineering Mechanics 132 (2), 190-200, 2006.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from .heave_decay import BEAM, DEPTH, DRAFT, G, RHO, FreeDecay, free_oscillation, run_decay, water_wavenumbers

DATA_FILE = "rollDecay_rectangle_BT2_h2B_potential_flow.csv"
"""The reference numbers of the case (in ``src/shoal/data/``): a44, b44 against omega and the predicted decay."""


def _cos_moments(k, lo, hi):
    """int_lo^hi cos(k u) du, int u cos(k u) du and int u^2 cos(k u) du (k > 0)."""
    s1, c1, s0, c0 = math.sin(k * hi), math.cos(k * hi), math.sin(k * lo), math.cos(k * lo)
    m0 = (s1 - s0) / k
    m1 = (hi * s1 + c1 / k - lo * s0 - c0 / k) / k
    m2 = (hi * hi * s1 + 2 * hi * c1 / k - 2 * s1 / k ** 2 - lo * lo * s0 - 2 * lo * c0 / k + 2 * s0 / k ** 2) / k
    return m0, m1, m2


def _cosh_moments(k, lo, hi, scale):
    """int_lo^hi cosh(k u) / cosh(k scale) du, and with u and u^2 (k > 0; the scale keeps deep water finite)."""

    def sh(u):  # sinh(k u) / cosh(k scale), cosh(k u) / cosh(k scale)
        e = math.exp(k * (u - scale))
        f = math.exp(-k * (u + scale))
        den = 1 + math.exp(-2 * k * scale)
        return (e - f) / den, (e + f) / den

    s1, c1 = sh(hi)
    s0, c0 = sh(lo)
    m0 = (s1 - s0) / k
    m1 = (hi * s1 - c1 / k - lo * s0 + c0 / k) / k
    m2 = (hi * hi * s1 - 2 * hi * c1 / k + 2 * s1 / k ** 2 - lo * lo * s0 + 2 * lo * c0 / k - 2 * s0 / k ** 2) / k
    return m0, m1, m2


def rectangle_roll_coefficients(omega, beam, draft, depth, centre=0.0, rho=RHO, g=G, modes=80, far_field=False):
    """Roll added inertia a44 and radiation damping b44 per metre of a rectangular cylinder in the free surface,
    about the axis through (0, `centre`) (z up from the still water; e.g. the centre of gravity).

    Linear potential flow, water of finite `depth`, the exact solution by eigenfunction matching (Black, Mei &
    Bray 1971; Porter 2008), the antisymmetric companion of
    `shoal.validation.heave_decay.rectangle_heave_coefficients`. With x across the body (half-beam a = B/2),
    u = z + h, s = h - T the gap under the keel and a unit angular velocity about y (body velocity
    (z - z_r, -x) in the x-z plane, time factor exp(-i omega t)):

    * outside (x > a, odd in x): phi = sum_n A_n Z_n(u) exp(-r_n (x - a)), Z_0 = cosh(k0 u), r_0 = -i k0,
      Z_n = cos(kappa_n u), r_n = kappa_n;
    * under the body (|x| < a, u < s): phi = -(x u^2 - x^3 / 3) / (2 s) + B_0 x / a + sum_m B_m cos(l_m u)
      sinh(l_m x) / sinh(l_m a), l_m = m pi / s (the first term gives d phi/dz = -x on the keel, 0 on the bed);

    d phi/dx = z - z_r on the body's side, phi and d phi/dx continuous under it, projected on Z_n and
    cos(l_m u), give the linear system for A_n, B_m. The moment of the pressure p = i omega rho phi is
    (i omega a44 - b44) Omega with

        a44 = -rho Re f,  b44 = -rho omega Im f,  f = int_keel phi x dx + 2 int_{-T}^{0} phi(a, z) (z - z_r) dz

    (f = -int phi d phi/dn over the wetted surface, n into the water, as a33's f for heave).

    Parameters
    ----------
    omega : float
        Frequency [rad/s].
    beam, draft, depth : float
        B, T and h [m] (T < h).
    centre : float
        z_r, the height of the roll axis above the still water [m] (negative below it).
    rho, g : float
    modes : int
        Evanescent modes outside.
    far_field : bool
        Also return b44 from the radiated waves' energy flux, 2 rho omega k0 N0 |A0|^2 (Newman 1977,
        section 6.17): an independent check of the solution.

    Returns
    -------
    (float, float) or (float, float, float)
        a44 [kg m], b44 [kg m / s] (and the far-field b44), per metre of length.
    """
    a, s, h, zr = 0.5 * beam, depth - draft, depth, centre
    k0, kap = water_wavenumbers(omega, h, modes, g)
    rn = np.concatenate([[-1j * k0], kap]).astype(complex)
    M = max(int(math.ceil(modes * s / h)), 10)
    lam = np.arange(M + 1) * math.pi / s
    sign = (-1.0) ** np.arange(M + 1)
    nA, nB = modes + 1, M + 1
    # L[n, m] = int_0^s Z_n cos(l_m u) du, N[n] = int_0^h Z_n^2 du (Z_0 scaled by cosh(k0 h))
    kk, ll = kap[:, None], lam[None, :]
    L = np.empty((nA, nB), complex)
    L[1:] = kk * np.sin(kk * s) * sign[None, :] / (kk * kk - ll * ll)
    ratio = (math.exp(k0 * (s - h)) - math.exp(-k0 * (s + h))) / (1 + math.exp(-2 * k0 * h))
    L[0] = k0 * ratio * sign / (k0 * k0 + lam * lam)
    N = np.concatenate([[0.5 * h * (2 * math.exp(-k0 * h) / (1 + math.exp(-2 * k0 * h))) ** 2
                         + math.tanh(k0 * h) / (2 * k0)],
                        0.5 * h + np.sin(2 * kap * h) / (4 * kap)]).astype(complex)
    # moments of Z_n: under the body (0, s) and on the body's side (s, h)
    under = np.array([_cosh_moments(k0, 0.0, s, h)] + [_cos_moments(k, 0.0, s) for k in kap])
    side = np.array([_cosh_moments(k0, s, h, h)] + [_cos_moments(k, s, h) for k in kap])
    R = side[:, 1] - (h + zr) * side[:, 0]  # int_s^h (u - h - z_r) Z_n du
    coth = np.zeros(nB)
    coth[1:] = 1.0 / np.tanh(lam[1:] * a)
    A = np.zeros((nA + nB, nA + nB), complex)
    rhs = np.zeros(nA + nB, complex)
    # d phi/dx at x = a over the whole depth, projected on Z_n
    A[:nA, :nA] = np.diag(-rn * N)
    A[:nA, nA] = -L[:, 0] / a
    A[:nA, nA + 1:] = -(lam[1:] * coth[1:])[None, :] * L[:, 1:]
    rhs[:nA] = (-under[:, 2] + a * a * under[:, 0]) / (2 * s) + R
    # phi at x = a under the body, projected on cos(l_m u)
    A[nA:, :nA] = L.T
    A[nA:, nA:] = -np.diag(np.where(np.arange(nB) == 0, s, 0.5 * s))
    rhs[nA:] = np.concatenate([[(a ** 3 - a * s * s) / 6], -a * sign[1:] / lam[1:] ** 2])
    sol = np.linalg.solve(A, rhs)
    An, Bm = sol[:nA], sol[nA:]
    keel = (-(s * s * 2 * a ** 3 / 3 - 2 * a ** 5 / 15) / (2 * s) + Bm[0] * 2 * a * a / 3
            + np.sum(Bm[1:] * sign[1:] * 2 * (a * coth[1:] / lam[1:] - 1 / lam[1:] ** 2)))
    f = keel + 2 * np.sum(An * R)
    a44, b44 = -rho * f.real, -rho * omega * f.imag
    if not far_field:
        return float(a44), float(b44)
    return float(a44), float(b44), float(2 * rho * omega * k0 * N[0].real * abs(An[0]) ** 2)


def roll_decay_prediction(beam, draft, depth, centre, inertia, rho=RHO, g=G, modes=80):
    """Natural frequency, period and damping ratio of the free roll of a floating rectangle pinned at its
    centre of gravity, linear theory.

    GM = KB + BM - KG = T/2 + B^2 / (12 T) - (T + z_G) with z_G = `centre` the centre of gravity's height
    above the still water, C44 = rho g B T GM; the fixed point omega_n = sqrt(C44 / (I + a44(omega_n))), then
    zeta = b44(omega_n) / (2 (I + a44(omega_n)) omega_n) and T_d = 2 pi / (omega_n sqrt(1 - zeta^2))
    (`rectangle_roll_coefficients` about the centre of gravity).

    Parameters
    ----------
    beam, draft, depth : float
        B, T, h [m].
    centre : float
        z_G [m] above the still water (negative below).
    inertia : float
        I [kg m] per metre, about the centre of gravity.

    Returns
    -------
    dict
        omega_n [rad/s], period_n, period_d [s], zeta, a44, b44, inertia, stiffness (C44), gm [m].
    """
    gm = 0.5 * draft + beam * beam / (12 * draft) - (draft + centre)
    if gm <= 0:
        raise ValueError(f"GM = {gm:.4g} m: the section is not stable in roll")
    C = rho * g * beam * draft * gm
    p = free_oscillation(C, inertia, lambda w: rectangle_roll_coefficients(w, beam, draft, depth, centre, rho, g,
                                                                           modes), math.sqrt(C / inertia))
    return _roll_keys(p, inertia, C, gm)


def _roll_keys(p, inertia, stiffness, gm):
    """`free_oscillation`'s dict with roll's names (a44, b44), the inertia, stiffness and GM."""
    p = dict(p, a44=p.pop("a"), b44=p.pop("b"))
    return dict(p, inertia=inertia, stiffness=stiffness, gm=gm)


# ------------------------------------------------------------------ the case's numbers
CENTRE = -0.5 * DRAFT
"""z_G: the centre of gravity at half the draft [m above the still water] (KG = T/2)."""

MASS = RHO * BEAM * DRAFT
"""M = rho B T = 20 kg/m, the box floating at T."""

INERTIA = MASS * (0.35 * BEAM) ** 2
"""I = M (0.35 B)^2 = 0.098 kg m about the centre of gravity: the radius of gyration of 0.35 B typical of
barges (e.g. DNV-RP-C205, section 7.3)."""


def roll_decay_case(dp=0.02, spin=1.0, length=4.0, zone=1.0, end_time=3.0, interval=0.005, options=None,
                    precision="float32"):
    """The 2D case: the ballasted box (B = 0.2 m square, M = 20 kg/m, T = 0.1 m, centre of gravity at half
    the draft, I = `INERTIA`) at the middle of a tank `length` long with water h = 0.4 m deep, pinned at its
    centre of gravity (x and z fixed) and started upright with the angular velocity `spin` [rad/s] about y;
    damping zones `zone` [m] long at both ends absorb its waves. The wave flumes' scheme
    (`shoal.cases.wave_flume.WAVE_OPTIONS`) unless `options` are given."""
    from ..case import Case, DampingZone, Fluid, FluidRegion, Output, Solid
    from ..cases.wave_flume import WAVE_OPTIONS
    from ..floating import FloatingBody
    from ..geometry.shapes import Box, Tank

    opts = dict(options if options is not None else WAVE_OPTIONS[2])
    opts["precision"] = precision
    zb = DEPTH - DRAFT
    xc = 0.5 * length
    body = Solid(name="box", shape=Box(lo=(xc - BEAM / 2, 0, zb), hi=(xc + BEAM / 2, 0, zb + BEAM)),
                 floating=FloatingBody(mass=MASS, centre_of_gravity=(xc, 0.0, DEPTH + CENTRE),
                                       inertia=(INERTIA, INERTIA, INERTIA), angular_velocity=(0.0, spin, 0.0),
                                       interval=interval, fixed=["x", "z"]))
    return Case(name="roll-decay", dim=2, dp=dp, end_time=end_time, fluid=Fluid(depth=DEPTH, surface_level=DEPTH),
                options=opts, output=Output(interval=end_time),
                solids=[Solid(name="tank", shape=Tank(lo=(0, 0, 0), hi=(length, 0, 2 * DEPTH))), body],
                fluids=[FluidRegion(shape=Box(lo=(0, 0, 0), hi=(length, 0, DEPTH)))],
                damping=[DampingZone(start=(zone, 0, 0), end=(0, 0, 0)),
                         DampingZone(start=(length - zone, 0, 0), end=(length, 0, 0))])


# ------------------------------------------------------------------ the reference table
TABLE_OMEGAS = np.round(np.arange(4.0, 12.01, 0.25), 2)
"""Frequencies of the reference table [rad/s] (the natural frequency, 7.2 rad/s, well inside)."""


def data_path():
    """The reference table's path (``src/shoal/data/``, shipped with the package)."""
    return Path(__file__).resolve().parent.parent / "data" / DATA_FILE


def write_reference_table(path=None, modes=200):
    """Write the reference table: a44, b44 (and b44 from the far field) of the case's rectangle about its
    centre of gravity against omega, with a header giving the method and its sources. Regenerate with
    ``python -c "from shoal.validation.roll_decay import write_reference_table; write_reference_table()"``."""
    path = Path(path) if path is not None else data_path()
    rows = [(w, *rectangle_roll_coefficients(w, BEAM, DRAFT, DEPTH, CENTRE, modes=modes, far_field=True))
            for w in TABLE_OMEGAS]
    pred = roll_decay_prediction(BEAM, DRAFT, DEPTH, CENTRE, INERTIA, modes=modes)
    head = [
        "# Roll added inertia a44 and radiation damping b44 per metre of a 2D rectangular cylinder in the free",
        f"# surface, about the axis {-CENTRE} m below the still water (the centre of gravity, at half the draft);",
        f"# beam B = {BEAM} m, draft T = {DRAFT} m (B/T = 2, as Vugts 1968), still-water depth h = {DEPTH} m,",
        f"# rho = {RHO} kg/m^3, g = {G} m/s^2; linear potential flow (small roll amplitude, inviscid).",
        "# Method: exact eigenfunction-matching solution of the 2D radiation problem of a rectangle in water of",
        "# finite depth: J. L. Black, C. C. Mei & M. C. G. Bray (1971), 'Radiation and scattering of water waves",
        "# by rigid bodies', J. Fluid Mech. 46(1) 151-164; R. Porter (2008), 'Calculation of the hydrodynamic",
        "# coefficients for cylinders of rectangular cross-section oscillating in the free surface', technical",
        "# report, School of Mathematics, University of Bristol. Computed (not digitised) by",
        "# shoal.validation.roll_decay.rectangle_roll_coefficients with 200 evanescent modes; b44_far_field is",
        "# b44 from the radiated waves' energy flux (Newman 1977, Marine Hydrodynamics, section 6.17), an",
        "# independent check of the solution.",
        f"# Free roll decay of the box pinned at its centre of gravity: mass M = {MASS:g} kg/m, inertia",
        f"# I = M (0.35 B)^2 = {INERTIA:g} kg m, GM = {pred['gm']:.5f} m, C44 = rho g B T GM = "
        f"{pred['stiffness']:.4f} N m/m",
        "# (omega_n = sqrt(C44 / (I + a44(omega_n))), zeta = b44 / (2 (I + a44) omega_n)):",
        f"# omega_n = {pred['omega_n']:.5f} rad/s, T_n = {pred['period_n']:.5f} s, "
        f"T_d = {pred['period_d']:.5f} s, zeta = {pred['zeta']:.5f}",
        "# Regenerate: python -c \"from shoal.validation.roll_decay import write_reference_table; "
        "write_reference_table()\"",
        "omega,a44,b44,b44_far_field",
    ]
    text = "\n".join(head + [f"{w:.2f},{a:.7f},{b:.7f},{bf:.7f}" for w, a, b, bf in rows]) + "\n"
    path.write_text(text)
    return path


def prediction_from_table(path=None, inertia=INERTIA, stiffness=None):
    """The linear decay prediction (as `roll_decay_prediction`) from the stored table: a44 and b44
    interpolated linearly in omega, the fixed point for omega_n solved on them."""
    from .core import read_csv_with_comments

    head, data = read_csv_with_comments(path or data_path())
    w_tab, a_tab, b_tab = (data[:, head.index(c)] for c in ("omega", "a44", "b44"))
    gm = 0.5 * DRAFT + BEAM * BEAM / (12 * DRAFT) - (DRAFT + CENTRE)
    C = RHO * G * BEAM * DRAFT * gm if stiffness is None else stiffness
    p = free_oscillation(C, inertia, lambda w: (float(np.interp(w, w_tab, a_tab)), float(np.interp(w, w_tab, b_tab))),
                         math.sqrt(C / inertia))
    return _roll_keys(p, inertia, C, gm)


def run_roll_decay(out, backend="cpu", **kw):
    """Run `roll_decay_case` (keywords passed on) in `out`; return (t, roll angle [deg], wall seconds, fluid
    particles). The 2D section rolls about y: the ``pitch`` column of ``body_box.csv``."""
    return run_decay(roll_decay_case(**kw), out, "pitch", backend)


class RollDecay(FreeDecay):
    """Free roll decay of a floating 2D box (B/T = 2, ballasted) against linear potential-flow theory."""

    name = "roll-decay"
    title = "Floating box: free roll decay against potential-flow theory"
    cost = 240.0
    setup = ("2D: a box 0.2 m square of mass 20 kg/m (beam B = 0.2 m, draft T = 0.1 m, B/T = 2) ballasted to "
             "its centre of gravity at half the draft (GM = 0.033 m), I = M (0.35 B)^2, at the middle of a tank "
             "with water 0.4 m deep, pinned at its centre of gravity and started upright at 1 rad/s; damping "
             "zones 1 m long at both ends absorb its radiated waves. The wave flumes' scheme (laminar viscosity, "
             "coef_h = 1.5), float32. The damped period (mean zero-crossing period) and the damping ratio (log "
             "decrement of successive peak-to-trough heights) of the roll angle over the first 2 full cycles "
             "after the first extremum (`shoal.validation.roll_decay`). `--quick`: dp = 0.02 m (B = 10 dp), "
             "tank 4 m, 3 s; `--full`: dp = 0.01 m (B = 20 dp).")
    reference = ("Linear potential flow for the same rectangle rolling about the same point in the same depth: roll "
                 "added inertia a44 and radiation damping b44 by the exact eigenfunction-matching solution (Black, "
                 "Mei & Bray 1971, J. Fluid Mech. 46; Porter 2008, Univ. Bristol report), omega_n = sqrt(C44 / "
                 "(I + a44(omega_n))), zeta = b44 / (2 (I + a44) omega_n): T_d = 0.872 s, zeta = 0.046. Table: "
                 "`src/shoal/data/" + DATA_FILE + "`.")
    tolerance_text = ("Issue 32, must-show 3: damped period within 10 % of the reference; the damping ratio is "
                      "reported against the radiation damping alone, not judged (see the case's README).")
    column, scale, ylabel, figure_name = "pitch", 1.0, "roll [deg]", "roll_decay.png"
    metric_names = ("damped roll period against potential flow", "roll damping ratio against the radiation damping")
    judge_damping = False

    def make_case(self, **kw):
        return roll_decay_case(**kw)

    def prediction(self):
        return prediction_from_table()
