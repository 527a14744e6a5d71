"""SPH scheme options: which kernel, viscosity, diffusion, filters and integrator.

`SPHOptions` is frozen: the discrete choices (kernel, viscosity model, density
diffusion, XSPH on/off, tensile correction, dimension, precision) select a
specialised, cached compiled kernel (see :mod:`shoal.backends.cpu`), so a
disabled term costs nothing inside the pair loop.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass, fields

import numpy as np
from pydantic import ConfigDict

from .errors import InputError

KERNELS = ("wendland", "cubic")
VISCOSITIES = ("artificial", "laminar")
DENSITY_DIFFUSIONS = ("none", "molteni", "fourtakas")
INTEGRATORS = ("verlet", "symplectic", "predictor_corrector")
TURBULENCE = ("none", "sps")
PRECISIONS = ("float32", "float64")
WALL_PRESSURES = ("dynamic", "adami", "mdbc")
SHIFTINGS = ("none", "delta_plus")


def _choice(name, value, allowed):
    if value not in allowed:
        raise InputError(f"{name} = {value!r} is not allowed; choose one of {', '.join(map(repr, allowed))}")


def _positive(name, value, allow_zero=False):
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise InputError(f"{name} = {value!r} must be a number") from None
    if not np.isfinite(v) or v < 0 or (v == 0 and not allow_zero):
        bound = ">= 0" if allow_zero else "> 0"
        raise InputError(f"{name} = {value!r} must be a finite number {bound}")


@dataclass(frozen=True)
class SPHOptions:
    """Weakly-compressible SPH scheme options (defaults as in DualSPHysics 5).

    Parameters
    ----------
    kernel : {"wendland", "cubic"}
        Smoothing kernel: Wendland (1995) C2 ("quintic") or the Monaghan &
        Lattanzio (1985) cubic spline. Support radius 2h.
    coef_h : float
        Smoothing length h = coef_h * sqrt(dim) * dp (DualSPHysics convention,
        so coef_h = 1 gives h = sqrt(3) dp in 3D and sqrt(2) dp in 2D).
    coef_sound : float
        Speed of sound c0 = coef_sound * U_max, with U_max = sqrt(g H) by
        default (H the still fluid height); both papers use c0 >= 10 U_max.
    viscosity : {"artificial", "laminar"}
        Monaghan (1992) artificial viscosity with coefficient `alpha`, or the
        laminar viscosity of Lo & Shao (2002) / Morris et al. (1997) with
        kinematic viscosity `nu` [m^2/s].
    alpha : float
        Artificial viscosity coefficient (DualSPHysics dam break: 0.1).
    nu : float
        Kinematic viscosity [m^2/s] for the laminar model (water: 1e-6).
    visco_bound_factor : float
        Factor on the viscous term (artificial or laminar) between a fluid
        particle and a boundary particle (DualSPHysics's ViscoBoundFactor,
        default 1). The artificial viscosity alpha h c0 is a numerical
        viscosity hundreds of times water's, and on a wall it acts as a bed
        friction of that size; 0 makes the walls free-slip for the viscous
        term (the pressure term still keeps fluid out). Bores and waves over
        a flat bed, whose theory is frictionless, are run with 0.
    no_slip : bool
        Walls enter the viscous term with the no-slip velocity of Adami, Hu &
        Adams (2012), u_b = 2 u_wall - (Shepard average of the fluid velocity
        at the boundary particle), so the no-slip condition holds at the wall
        surface rather than at the first boundary layer (`shoal.physics.no_slip`).
        Off by default (DualSPHysics's DBC: boundary particles carry the wall
        velocity).
    wall_pressure : {"dynamic", "adami", "mdbc"}
        How dynamic boundary particles get their density (and pressure):
        "adami" (the default) extrapolates the surrounding fluid's pressure
        to each wall particle with the hydrostatic and wall-acceleration
        terms at every rate evaluation (Adami, Hu & Adams 2012; PySPH's
        ``SolidWallPressureBC``; `shoal.physics.wall_pressure`); "dynamic"
        integrates their own continuity equation (DBC, Crespo et al. 2007;
        DualSPHysics's default); "mdbc" takes each wall particle's
        density from the fluid at its ghost node, the particle's mirror
        image across the wall surface, extrapolated back to first order
        (modified DBC, English et al. 2022, as DualSPHysics 5.4;
        `shoal.physics.mdbc`), so the fluid sits half a spacing from the
        wall surface. With "mdbc", ``no_slip`` takes the wall velocity from
        the ghost node too.

        Adami is the default because it was measured the best or equal best
        of the three where they differ, at DBC's cost (mDBC: 38 % more on
        a 3D tank of 87 % walls): a dam-break surge floats 0.8 dp over its
        bed (DBC 1.65 dp), whose front stays within the band of Martin &
        Moyce and Koshizuka & Oka as dp shrinks (DBC leaves it by 8 % at
        a/dp = 36), a stream sliding over a free-slip bed keeps its speed
        (0.7 % lost; DBC 5.5 %), the impact on a wall reads a lower peak and
        less negative pressure than with DBC or mDBC, and a solitary wave
        keeps its height (mDBC grew one by 10 %); it needs no wall normals,
        so it serves any geometry, moving walls included (issue 28's
        measurements: ``benchmarks/results/issue28-mdbc/``).
    density_diffusion : {"none", "molteni", "fourtakas"}
        Density diffusion term: Molteni & Colagrossi (2009) or Fourtakas et
        al. (2019) (with the hydrostatic correction). Default "fourtakas".
    delta : float
        Density diffusion coefficient (0.1 in DualSPHysics).
    riemann : bool
        Take each pair of fluid particles' pressure and velocity in the
        momentum and continuity equations from the linearised Riemann
        solution between the two, with the low-dissipation limiter of Zhang, Hu &
        Adams (2017) (`shoal.physics.riemann`): a dissipation that acts on
        compression and on acoustic pressure jumps, in place of artificial
        viscosity and density diffusion (use it with ``alpha = 0`` or
        laminar viscosity and ``density_diffusion = "none"``, as they do).
        Against a wall, the problem of the fluid particle and its mirror
        image along the wall's normal (from the geometry, computed when the
        particles are generated), which damps an impact's ringing and leaves
        a flow along the wall alone.
    xsph : float
        XSPH velocity-correction coefficient epsilon (Monaghan 1989);
        0 disables it; 0.5 in the tidal-bore paper.
    turbulence : {"none", "sps"}
        Sub-particle-scale (SPS) turbulence: a Smagorinsky eddy viscosity
        ``nu_t = (Cs dp)^2 |S|`` in the SPS stress tensor of Dalrymple & Rogers
        (2006) (Gotoh et al. 2001), as in both papers.
    sps_cs : float
        Smagorinsky constant Cs (0.12).
    sps_ci : float
        Isotropic (Yoshizawa) coefficient C_I (0.0066).
    tensile_correction : bool
        Monaghan (2000) tensile-instability correction (used with the cubic
        spline in DualSPHysics).
    shepard_every : int
        Re-initialise fluid density with the Shepard filter every N steps
        (0 = off; 20 in the rip-current paper).
    mls_every : int
        Re-initialise fluid density with the MLS filter of Colagrossi &
        Landrini (2003) every N steps (0 = off; 30 in the tidal-bore paper).
    shifting : {"none", "delta_plus"}
        Particle shifting once per step after the integrator (`shoal.physics.shifting`): "delta_plus"
        moves each fluid particle by delta r = -C Ma (2h)^2 sum_j [1 + R (W_ij / W(dp))^4] grad W_ij V_j
        (R = 0.2; Sun, Colagrossi, Marrone & Zhang 2017, the delta-plus-SPH model), keeping only the
        part tangential to the free surface for particles at it (Marrone et al. 2010's detection) or
        within 2h of it, and none for isolated particles; positions only. "none" (the default): off.
    shifting_coef : float
        The CFL-type coefficient C of the shift (0.2, shoal's default `cfl`); Ma = U_max / c0 is the
        run's, 1 / `coef_sound`.
    integrator : {"symplectic", "verlet", "predictor_corrector"}
        Symplectic position-Verlet (Leimkuhler 1996; the default, as in
        DualSPHysics's examples), Verlet with an Euler step every
        `verlet_euler_every` steps (one force evaluation per step instead of
        two), or the predictor-corrector of Monaghan (1994). Note: Verlet
        integrates the density-diffusion term with leapfrog, which is
        unstable for a diffusion term; the periodic Euler step keeps it in
        check for dynamic flows, but a quiescent 3D tank with the Wendland
        kernel and delta = 0.1 grows a density mode after ~3000 steps (seen
        here). Use Verlet with the cubic kernel, a smaller delta, or a more
        frequent Euler step.
    verlet_euler_every : int
        Euler step frequency of the Verlet scheme (40 in DualSPHysics).
    cfl : float
        CFL number of the variable time step (0.2).
    fixed_dt : float or None
        A fixed time step [s]; None selects the variable step of Monaghan &
        Kos (1999).
    precision : {"float32", "float64"}
        Floating-point precision of particle arrays and arithmetic.
    cells_per_support : int
        Neighbour cells per kernel support 2h: 1 gives the classic 3^dim cells
        of size 2h; 2 (default) searches 5^dim cells of size h as 5^(dim-1)
        contiguous x-ranges, about half as many candidate pairs.
    """

    kernel: str = "wendland"
    coef_h: float = 1.0
    coef_sound: float = 20.0
    viscosity: str = "artificial"
    alpha: float = 0.1
    nu: float = 1.0e-6
    visco_bound_factor: float = 1.0
    no_slip: bool = False
    wall_pressure: str = "adami"
    density_diffusion: str = "fourtakas"
    delta: float = 0.1
    riemann: bool = False
    xsph: float = 0.0
    turbulence: str = "none"
    sps_cs: float = 0.12
    sps_ci: float = 0.0066
    tensile_correction: bool = False
    shepard_every: int = 0
    mls_every: int = 0
    shifting: str = "none"
    shifting_coef: float = 0.2
    integrator: str = "symplectic"
    verlet_euler_every: int = 40
    cfl: float = 0.2
    fixed_dt: float | None = None
    precision: str = "float32"
    cells_per_support: int = 2

    def __post_init__(self):
        _choice("kernel", self.kernel, KERNELS)
        _choice("viscosity", self.viscosity, VISCOSITIES)
        _choice("density_diffusion", self.density_diffusion, DENSITY_DIFFUSIONS)
        _choice("integrator", self.integrator, INTEGRATORS)
        _choice("precision", self.precision, PRECISIONS)
        _choice("turbulence", self.turbulence, TURBULENCE)
        _choice("wall_pressure", self.wall_pressure, WALL_PRESSURES)
        _choice("shifting", self.shifting, SHIFTINGS)
        _positive("shifting_coef", self.shifting_coef)
        _positive("sps_cs", self.sps_cs, allow_zero=True)
        _positive("sps_ci", self.sps_ci, allow_zero=True)
        _positive("coef_h", self.coef_h)
        _positive("coef_sound", self.coef_sound)
        _positive("alpha", self.alpha, allow_zero=True)
        _positive("nu", self.nu, allow_zero=True)
        _positive("visco_bound_factor", self.visco_bound_factor, allow_zero=True)
        _positive("delta", self.delta, allow_zero=True)
        _positive("xsph", self.xsph, allow_zero=True)
        _positive("cfl", self.cfl)
        if self.cfl > 1.0:
            raise InputError(f"cfl = {self.cfl!r} is unstable; use 0 < cfl <= 1 (0.2 is usual)")
        if self.xsph > 1.0:
            raise InputError(f"xsph = {self.xsph!r} is out of range; use 0 <= xsph <= 1")
        for name in ("shepard_every", "mls_every", "verlet_euler_every"):
            v = getattr(self, name)
            if not isinstance(v, (int, np.integer)) or isinstance(v, bool) or v < 0:
                raise InputError(f"{name} = {v!r} must be an integer >= 0")
        if self.verlet_euler_every == 0 and self.integrator == "verlet":
            raise InputError("verlet_euler_every = 0 is not allowed with the verlet integrator; use an integer >= 1 (40 is usual)")
        if self.shepard_every and self.mls_every:
            raise InputError("shepard_every and mls_every are both set; choose one density filter")
        if self.fixed_dt is not None:
            _positive("fixed_dt", self.fixed_dt)
        if self.cells_per_support not in (1, 2, 3):
            raise InputError(f"cells_per_support = {self.cells_per_support!r}; allowed 1, 2 or 3")

    # validated as a table of a case file: unknown keys are errors (see `from_table`)
    __pydantic_config__ = ConfigDict(extra="forbid")

    @property
    def dtype(self):
        """NumPy float type of the run."""
        return np.dtype(self.precision)

    def to_dict(self):
        """Plain dict of the options (for the resolved-case file)."""
        return asdict(self)

    @classmethod
    def from_table(cls, d):
        """Build from a case-file table, checking each value's type exactly
        (a string is not a number, a boolean is not an integer)."""
        if isinstance(d, cls):
            return d
        if not isinstance(d, dict):
            raise InputError(f"must be a table of options, got {d!r}")
        cls.check_types(d)
        return cls(**d)

    @classmethod
    def check_types(cls, d):
        """Raise `InputError` for an unknown key of `d` or a value of the wrong
        type (a string is not a number, a boolean is not an integer)."""
        known = {f.name: f for f in fields(cls)}
        for k, v in d.items():
            if k not in known:
                raise InputError(f"unknown key {k!r} in options; allowed keys: {', '.join(sorted(known))}")
            default = known[k].default
            if isinstance(default, bool):
                ok, what = isinstance(v, bool), "true or false"
            elif isinstance(default, int):
                ok, what = isinstance(v, int) and not isinstance(v, bool), "an integer"
            elif isinstance(default, float) or k == "fixed_dt":
                ok, what = isinstance(v, (int, float)) and not isinstance(v, bool), "a number"
            else:
                ok, what = isinstance(v, str), "a string"
            if not ok:
                shown = {True: "true", False: "false"}.get(v, v) if isinstance(v, bool) else v
                raise InputError(f"{k} = {shown!r} must be {what}".replace("'true'", "true").replace("'false'", "false"))

    @classmethod
    def from_dict(cls, d):
        """Build from a dict, rejecting unknown keys with a clear message."""
        known = {f.name for f in fields(cls)}
        unknown = sorted(set(d) - known)
        if unknown:
            raise InputError(f"unknown SPH option(s) {', '.join(unknown)}; allowed: {', '.join(sorted(known))}")
        return cls(**d)
