"""The compile-time description of a scheme and its run-time constants.

`SchemeSpec` holds the discrete choices that select a specialised kernel
(dimension, precision, kernel, viscosity, diffusion, tensile correction,
XSPH, neighbour cells per support). `Params` holds the floating-point
constants, cast to the working precision, passed to kernels at run time so
that changing the resolution does not recompile anything.
"""

from __future__ import annotations

import math
from collections import namedtuple
from dataclasses import dataclass
from enum import IntEnum

import numpy as np

from .eos import tait_coefficient

class Kind(IntEnum):
    """What a particle is (the ``kind`` array, int8; the ``kind`` field of snapshots)."""

    FLUID = 0
    FIXED = 1
    """A fixed boundary particle (dynamic, Adami or mDBC walls)."""
    MOVING = 2
    """A boundary particle moved by a motion."""
    REPULSIVE = 3
    """A fixed repulsive (Monaghan & Kajtar 2009) boundary particle; kind >= REPULSIVE: repulsive."""
    REPULSIVE_MOVING = 4
    """A moving repulsive boundary particle."""


FLUID, FIXED, MOVING, REPULSIVE, REPULSIVE_MOVING = (int(k) for k in Kind)
"""The kinds as plain ints, for the compiled kernels (which compare the int8 ``kind`` array with them)."""

KERNEL_IDS = {"wendland": 0, "cubic": 1}
VISC_IDS = {"artificial": 0, "laminar": 1}
DIFF_IDS = {"none": 0, "molteni": 1, "fourtakas": 2}
WALL_IDS = {"dynamic": 0, "adami": 1, "mdbc": 2}
"""How dynamic boundary particles get their density: integrated continuity (DBC), the Adami et
al. (2012) extrapolation at the particle (`wall_pressure`), or the mDBC ghost node (`mdbc`)."""
ADAMI, MDBC = WALL_IDS["adami"], WALL_IDS["mdbc"]


@dataclass(frozen=True)
class SchemeSpec:
    """Discrete choices compiled into a kernel (one cached specialisation each)."""

    dim: int
    precision: str
    kernel: int
    viscosity: int
    diffusion: int
    tensile: bool
    xsph: bool
    cells_per_support: int
    periodic: int = 0
    """Periodic axes as a bit mask of the stored axes: 1 = x, 2 = y (3D only)."""
    sps: bool = False
    """SPS turbulence (Dalrymple & Rogers 2006)."""
    repulsive: bool = False
    """The run has Monaghan-Kajtar repulsive boundary particles."""
    planes: bool = False
    """The run has wall planes (`shoal.physics.planes`)."""
    symmetry: int = 0
    """A symmetry plane y = const (3D): 0 none, 1 fluid on the low side, 2 on the high side."""
    no_slip: bool = False
    """Boundary particles enter the viscous term with the no-slip velocity of Adami et al. (2012)."""
    riemann: bool = False
    """Pair pressures and velocities from the Riemann solver of Zhang, Hu & Adams (2017)."""
    wall_pressure: int = 0
    """`WALL_IDS`: 0 DBC walls integrate their continuity equation; 1 (Adami et al. 2012) and
    2 (mDBC, English et al. 2022) extrapolate the walls' density from the fluid at every rate
    evaluation (nonzero: the walls' density is not integrated)."""

    @classmethod
    def from_options(cls, options, dim, periodic=(), repulsive=False, planes=False, symmetry=0):
        mask = (1 if "x" in periodic else 0) | (2 if "y" in periodic else 0)
        return cls(
            dim=int(dim),
            precision=options.precision,
            kernel=KERNEL_IDS[options.kernel],
            viscosity=VISC_IDS[options.viscosity],
            diffusion=DIFF_IDS[options.density_diffusion],
            tensile=bool(options.tensile_correction),
            xsph=options.xsph > 0,
            cells_per_support=int(options.cells_per_support),
            periodic=mask,
            sps=options.turbulence == "sps",
            repulsive=bool(repulsive),
            planes=bool(planes),
            symmetry=int(symmetry),
            no_slip=bool(options.no_slip),
            wall_pressure=WALL_IDS[options.wall_pressure],
            riemann=bool(options.riemann),
        )

    @property
    def key(self):
        """Short deterministic string naming the specialisation."""
        return (f"d{self.dim}-{self.precision}-k{self.kernel}-v{self.viscosity}-"
                f"dd{self.diffusion}-t{int(self.tensile)}-x{int(self.xsph)}-c{self.cells_per_support}"
                f"-p{self.periodic}-s{int(self.sps)}-r{int(self.repulsive)}-w{int(self.planes)}-m{self.symmetry}-n{int(self.no_slip)}"
                + (f"-a{self.wall_pressure}" if self.wall_pressure else "") + ("-R" if self.riemann else ""))

    @property
    def float_type(self):
        return np.float32 if self.precision == "float32" else np.float64


Params = namedtuple("Params", [
    "h", "inv_h", "supp2", "eta2",
    "aw", "agrad", "inv_wdp",
    "rho0", "inv_rho0", "B", "c0", "rho0_c02",
    "alpha", "nu4", "ddt_coef", "visc_bound",
    "mass_f", "mass_b",
    "gx", "gy", "gz",
    "xsph_eps",
    "sps_smag", "sps_blin", "mk_k",
    "per_len_x", "per_len_y",
    "sym_y", "grid_lo_x", "grid_lo_y", "grid_lo_z", "inv_cs",
    "dim",
])
"""Run-time constants of a kernel, all in the working precision.

h : smoothing length [m]; inv_h = 1/h; supp2 = (2h)^2; eta2 = 0.01 h^2.
aw : kernel normalisation alpha_D (W = aw * f(q)); agrad : gradient
normalisation such that grad W = agrad * g(q) * r_ij; inv_wdp = 1/W(dp)
(tensile correction). rho0 [kg/m^3]; B = c0^2 rho0 / gamma [Pa]; c0 [m/s];
rho0_c02 = rho0 / c0^2 [kg s^2/m^5] (Fourtakas
hydrostatic density difference, linearised EOS). alpha: artificial
viscosity; nu4 = 4 nu [m^2/s]; ddt_coef = 2 delta h c0; visc_bound: factor on
the viscous term of fluid-boundary pairs (DualSPHysics's ViscoBoundFactor). mass_f, mass_b:
fluid and boundary particle masses [kg]. gx, gy, gz: gravity [m/s^2] in the
internal components (2D runs store (x, z) and use gx, gz). xsph_eps: XSPH
epsilon. sps_smag = (Cs dp)^2 [m^2], sps_blin = (2/3) C_I dp^2 [m^2]: SPS
turbulence. mk_k = K / beta [m^2/s^2]: Monaghan-Kajtar boundary force,
K = g D, beta = dp / dp_b = 2. per_len_x, per_len_y: periods [m] of periodic x and y (float64:
they shift float64 position differences; 0 when not periodic). sym_y:
the symmetry plane's y [m]; grid_lo_x, grid_lo_y, grid_lo_z, inv_cs: the cell
grid's lower corner [m] and 1 / cell size [1/m] (to trim the gather's rows to
the support, and to find the mirror point's cell); float64. dim: the
dimension (an int, which also keeps the tuple heterogeneous:
Numba's parallel loops reject homogeneous named tuples as loop arguments).
"""


def params_dtype(spec):
    """NumPy record dtype holding `Params` in the working precision.

    Kernels receive the constants as a one-element record array (Numba's
    parallel loops accept arrays, not named tuples, as loop arguments) and
    turn it into a `Params` tuple with `make_unpack`.

    The fields are aligned (C struct layout, padding before an 8-byte field
    that follows an odd number of 4-byte ones): Numba's CUDA target refuses
    to load a record member at an unaligned offset, which a packed float32
    record has (its first float64 field at byte 100).
    """
    F = spec.float_type
    wide = {"dim": np.int64, "per_len_x": np.float64, "per_len_y": np.float64, "sym_y": np.float64,
            "grid_lo_x": np.float64, "grid_lo_y": np.float64, "grid_lo_z": np.float64, "inv_cs": np.float64}
    return np.dtype([(name, wide.get(name, F)) for name in Params._fields], align=True)


def params_array(spec, params):
    """One-element record array of `params` (see `params_dtype`)."""
    a = np.zeros(1, dtype=params_dtype(spec))
    for name in Params._fields:
        a[0][name] = getattr(params, name)
    return a


def make_unpack(jit):
    """Return ``unpack(Parr) -> Params`` compiled with `jit`."""

    @jit
    def unpack(Parr):
        r = Parr[0]
        # r["name"]: works on Numba records (CPU and CUDA) and on NumPy records
        # (the CUDA simulator runs kernels as Python)
        return Params(r["h"], r["inv_h"], r["supp2"], r["eta2"], r["aw"], r["agrad"], r["inv_wdp"],
                      r["rho0"], r["inv_rho0"], r["B"], r["c0"], r["rho0_c02"], r["alpha"], r["nu4"],
                      r["ddt_coef"], r["visc_bound"], r["mass_f"], r["mass_b"], r["gx"], r["gy"], r["gz"], r["xsph_eps"],
                      r["sps_smag"], r["sps_blin"], r["mk_k"], r["per_len_x"], r["per_len_y"], r["sym_y"], r["grid_lo_x"],
                      r["grid_lo_y"], r["grid_lo_z"], r["inv_cs"], r["dim"])

    return unpack


def kernel_normalisation(kernel, dim, h):
    """alpha_D of the kernel so that the integral of W over space is 1.

    Wendland C2: 7/(4 pi h^2) in 2D, 21/(16 pi h^3) in 3D (Wendland 1995).
    Cubic spline: 10/(7 pi h^2) in 2D, 1/(pi h^3) in 3D (Monaghan & Lattanzio 1985).
    """
    if kernel == KERNEL_IDS["wendland"]:
        return 7.0 / (4.0 * math.pi * h**2) if dim == 2 else 21.0 / (16.0 * math.pi * h**3)
    return 10.0 / (7.0 * math.pi * h**2) if dim == 2 else 1.0 / (math.pi * h**3)


def make_params(spec, *, dp, h, rho0, c0, gamma, gravity, options, mass_f, mass_b, grid_lo, inv_cs,
                periods=(0.0, 0.0), mk_k=0.0, sym_y=0.0):
    """Build `Params` for a run, cast to the working precision.

    `grid_lo` (x, y, z) [m] and `inv_cs` [1/m] are the neighbour grid's lower corner and 1 / cell
    size (`CellGrid`; in 2D, x and z are used): the gather trims its rows with them."""
    F = spec.float_type
    aw = kernel_normalisation(spec.kernel, spec.dim, h)
    B = tait_coefficient(c0, rho0, gamma)
    # gradient: grad W = (dW/dr / r) r_ij = aw/h^2 * (dW/dq / q) r_ij
    agrad = aw / (h * h)
    qdp = dp / h
    if spec.kernel == KERNEL_IDS["wendland"]:
        wdp = aw * (1 - qdp / 2) ** 4 * (2 * qdp + 1)
    else:
        wdp = aw * (0.25 * max(2 - qdp, 0) ** 3 - max(1 - qdp, 0) ** 3)
    g = np.asarray(gravity, dtype=float)
    if spec.dim == 2:
        gx, gy, gz = g[0], 0.0, g[-1]
    else:
        gx, gy, gz = g
    vals = dict(
        h=h, inv_h=1.0 / h, supp2=4.0 * h * h, eta2=0.01 * h * h,
        aw=aw, agrad=agrad, inv_wdp=1.0 / wdp if wdp > 0 else 0.0,
        rho0=rho0, inv_rho0=1.0 / rho0, B=B, c0=c0, rho0_c02=rho0 / (c0 * c0),
        alpha=options.alpha, nu4=4.0 * options.nu, ddt_coef=2.0 * options.delta * h * c0,
        visc_bound=options.visco_bound_factor,
        mass_f=mass_f, mass_b=mass_b, gx=gx, gy=gy, gz=gz, xsph_eps=options.xsph,
        sps_smag=(options.sps_cs * dp) ** 2, sps_blin=(2.0 / 3.0) * options.sps_ci * dp * dp,
        mk_k=mk_k,
    )
    return Params(**{k: F(v) for k, v in vals.items()}, per_len_x=float(periods[0]), per_len_y=float(periods[1]),
                  sym_y=float(sym_y), grid_lo_x=float(grid_lo[0]), grid_lo_y=float(grid_lo[1]),
                  grid_lo_z=float(grid_lo[2]), inv_cs=float(inv_cs), dim=int(spec.dim))
