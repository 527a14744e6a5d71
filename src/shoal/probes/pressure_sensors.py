"""Pressure sensors on walls: the pressure the fluid puts on a point of a wall surface.

A laboratory pressure transducer sits flush with a wall and reads the water's pressure at the wall's
surface, averaged over its membrane. In SPH the wall surface is the edge of the fluid: a plain or
Shepard-normalised interpolation at a point on it averages the pressure over the half of the kernel
support that holds fluid, whose centroid lies about h/2 off the wall, so it reads low by the pressure
gradient times that distance (rho g h/2 under still water, and more during an impact, when the gradient
normal to the wall is large). DualSPHysics users place their probes off the wall for that reason.

Here the pressure is extrapolated to the wall point from the fluid alone (never from the boundary
particles, whose pressure depends on the boundary treatment). With the weights w_j = V_j W(x_s - x_j) of
the fluid particles j within 2h of the sensor point x_s and S = sum_j w_j, the default
(``method = "hydrostatic"``) is the Shepard average corrected for the hydrostatic pressure between each
particle and the point, the extrapolation of Adami, Hu & Adams (2012, Eq. 27) at a fixed wall:

    p_s = (sum_j w_j p_j + rho0 g . sum_j w_j (x_s - x_j)) / S.

It is exact under water at rest whatever part of the support holds fluid, and it is bounded by the
particles' own pressures (plus the hydrostatic term), so it does not amplify their noise.
``method = "linear"`` fits p(x) = a + h^-1 b . (x - x_s) by weighted least squares (first-order moving
least squares, Dilts 1999; the kernel correction of Bonet & Lok 1999, as mDBC uses at its ghost nodes,
English et al. 2022), with the offsets e_j = (x_j - x_s) / h:

    [ S        sum w e^T   ] [a]   [ sum w p   ]
    [ sum w e  sum w e e^T ] [b] = [ sum w p e ],

and reads p_s = a. It is exact for any pressure field linear in space (a uniform deceleration against
the wall too), but it extrapolates from the fluid's centroid, about h/2 off the wall, to the wall, and
multiplies the particles' pressure noise on the way: on SPHERIC Test 2's box at dp = 0.05 m
(`benchmarks/impact_pressure.py`) it read P1's impact peak 188 % above the measurement where the
hydrostatic average read 52 %, and swung to -4 to -19 rho0 g H0 at P2-P4 where the hydrostatic average
stayed above -1.8. Where its
moment matrix is ill-conditioned (fluid on a line or a thin sheet: the Hadamard ratio det M / prod M_kk
below `HADAMARD_MIN`) it falls back to the hydrostatic average. ``method = "shepard"`` is the plain
Shepard average, which reads low by the gradient times the centroid's offset.

With the wall's unit normal n (out of the wall into the fluid) the sums run only over the fluid in front
of the wall's plane through the point or less than half a spacing behind it, (x_j - x_s) . n >= -dp/2:
near an edge of the wall the support reaches over it, and the water that has run over the edge (or, on a
thin wall, the water on its other side) is not what a transducer on this face feels; the half spacing
keeps the particles an impact presses a fraction of a spacing past the wall's surface, which still touch
it.

A sensor whose kernel sum S is below `KERNEL_SUM_MIN` reads 0 (gauge pressure: dry). On a wall under
deep water S is 1/2 (half the support holds fluid); at the contact line of a water front it is about
0.2 (0.18 at the foot of a 3D column's face, 0.36 in 2D, measured at t = 0 of the dam breaks); half a
spacing beyond the front 0.09-0.22 and one spacing beyond it 0.03-0.10. So a point more than about
one spacing out of the water reads dry (the water's edge is known to a spacing), where the fit would
otherwise carry the pressure of the water nearby out to it. A sensor of diameter D averages the
fit over a disc of that diameter on the wall (3D; a segment of length D along the wall in 2D), sampled
on a square lattice of spacing at most dp/4, each sample weighing the same, as a transducer's membrane
integrates over its area; a sample that is dry reads 0.

References: G. A. Dilts, "Moving-least-squares-particle hydrodynamics -- I. Consistency and stability",
Int. J. Numer. Meth. Eng. 44 (1999) 1115-1155; J. Bonet, T.-S. L. Lok, Comput. Methods Appl. Mech.
Engrg. 180 (1999) 97-115; A. English et al., "Modified dynamic boundary conditions (mDBC) for
general-purpose smoothed particle hydrodynamics (SPH)", Comp. Part. Mech. 9 (2022) 1-15; S. Adami,
X. Y. Hu, N. A. Adams, J. Comput. Phys. 231 (2012) 7057-7075.
"""

from __future__ import annotations

import csv
import math
from pathlib import Path

import numpy as np

from .recorder_state import Recorder

HADAMARD_MIN = 1e-3
"""Below this Hadamard ratio of the moment matrix the linear fit falls back to the hydrostatic
Shepard average (the MLS density filter's threshold, `shoal.physics.filters`)."""

METHODS = ("hydrostatic", "linear", "shepard")

KERNEL_SUM_MIN = 0.1
"""Default kernel sum S = sum_j V_j W below which a sensor is dry and reads 0."""


def internal_gravity(gravity, dim):
    """Gravity [m/s^2] in the stored components: (gx, gy, gz) in 3D, (gx, gz) in 2D."""
    g = np.asarray(gravity, dtype=np.float64).ravel()
    if len(g) == 2:
        g = np.array([g[0], 0.0, g[1]])
    return g if dim == 3 else g[[0, 2]]


def fit_pressure(moments, dim, h, rho0, gravity, method="hydrostatic", kernel_sum_min=KERNEL_SUM_MIN):
    """The pressure [Pa] at each point from the fluid's moments around it (`Model.sensor_moments`).

    Parameters
    ----------
    moments : (M, 14) or (M, 9) array
        The sums of `shoal.physics.interpolation.make_sensor_moments` (3D or 2D).
    dim : int
    h : float
        Smoothing length [m] (the offsets of the moments are scaled by 1/h).
    rho0 : float
        Reference density [kg/m^3] (the hydrostatic correction of the fallback).
    gravity : array of 2 or 3 floats
        Gravity [m/s^2] (world components; 2D: (gx, gz) or (gx, gy, gz)).
    method : {"hydrostatic", "linear", "shepard"}
        The Shepard average corrected for the hydrostatic pressure, the linear least-squares fit (with
        the hydrostatic average where it is ill-conditioned), or the plain Shepard average.
    kernel_sum_min : float
        Points whose kernel sum S is below this are dry and read 0.

    Returns
    -------
    (M,) float64 array; 0 where dry.
    """
    m = np.asarray(moments, dtype=np.float64)
    n = dim + 1
    s = m[:, 0]
    e = m[:, 1:n]
    sym = m[:, n:n + dim * (dim + 1) // 2]
    sp = m[:, n + dim * (dim + 1) // 2]
    spe = m[:, n + dim * (dim + 1) // 2 + 1:]
    wet = (s > 0) & (s >= kernel_sum_min)
    safe = np.where(wet, s, 1.0)
    if method == "shepard":
        return np.where(wet, sp / safe, 0.0)
    g = internal_gravity(gravity, dim)
    # sum_j w_j (x_s - x_j) = -h sum_j w_j e_j
    hydro = np.where(wet, (sp - rho0 * h * (e @ g)) / safe, 0.0)
    if method == "hydrostatic":
        return hydro
    if method != "linear":
        raise ValueError(f"method = {method!r}; allowed {METHODS}")
    M = np.zeros((len(m), n, n))
    M[:, 0, 0] = s
    M[:, 0, 1:] = e
    M[:, 1:, 0] = e
    k = 0
    for a in range(dim):
        for b in range(a, dim):
            M[:, 1 + a, 1 + b] = M[:, 1 + b, 1 + a] = sym[:, k]
            k += 1
    rhs = np.concatenate([sp[:, None], spe], axis=1)
    diag = np.prod(np.diagonal(M, axis1=1, axis2=2), axis=1)
    ok = wet & (diag > 0)
    ok[ok] = np.linalg.det(M[ok]) / diag[ok] >= HADAMARD_MIN
    out = hydro.copy()
    if ok.any():
        out[ok] = np.linalg.solve(M[ok], rhs[ok][..., None])[:, 0, 0]
    return out


def sensor_points(centre, normal, diameter, dp, dim):
    """The points [m] (K, 3) a sensor averages over: its centre alone (diameter 0), or a square lattice of
    spacing at most dp/4 on the disc of `diameter` centred there, perpendicular to `normal` (2D: the
    segment of that length in the x-z plane, perpendicular to the normal), centre included."""
    c = np.asarray(centre, dtype=np.float64)
    if not diameter:
        return c[None, :]
    nvec = np.asarray(normal, dtype=np.float64)
    r = 0.5 * float(diameter)
    k = max(1, math.ceil(r / (0.25 * dp)))
    u = np.linspace(-r, r, 2 * k + 1)
    if dim == 2:
        t = np.array([nvec[2], 0.0, -nvec[0]])
        t /= np.linalg.norm(t)
        return c + u[:, None] * t
    nvec = nvec / np.linalg.norm(nvec)
    a = np.cross(nvec, [1.0, 0.0, 0.0] if abs(nvec[0]) < 0.9 else [0.0, 1.0, 0.0])
    a /= np.linalg.norm(a)
    b = np.cross(nvec, a)
    U, V = np.meshgrid(u, u, indexing="ij")
    inside = U**2 + V**2 <= r * r * (1 + 1e-12)
    return c + U[inside][:, None] * a + V[inside][:, None] * b


class PressureSensorRecorder(Recorder):
    """Samples a `shoal.probes.PressureSensors` spec and appends time, p_0, p_1, ... [Pa] to its CSV."""

    def __init__(self, spec, out_dir, model):
        self.spec = spec
        self.dim = model.dim
        self.h, self.rho0, self.gravity = model.h, model.rho0, model.gravity
        groups = [sensor_points(pt, spec.normal, spec.diameter, model.dp, model.dim) for pt in spec.points]
        self.points = np.concatenate(groups)
        self.owner = np.repeat(np.arange(len(groups)), [len(g) for g in groups])
        self.normals = None
        if spec.normal is not None:
            self.normals = np.repeat(np.asarray(spec.normal, dtype=np.float64)[None, :], len(self.points), axis=0)
        self.counts = np.array([len(g) for g in groups], dtype=np.float64)
        self.path = Path(out_dir) / f"pressure_{spec.name}.csv"
        self.file = open(self.path, "w", newline="")
        self.writer = csv.writer(self.file)
        self.writer.writerow(["time"] + [f"p_{k}" for k in range(len(groups))])
        self.rows = []

    def pressures(self, model):
        """The sensors' pressures [Pa] now (each averaged over its area)."""
        p = fit_pressure(model.sensor_moments(self.points, self.normals), self.dim, self.h, self.rho0, self.gravity,
                         self.spec.method, self.spec.kernel_sum_min)
        return np.bincount(self.owner, weights=p, minlength=len(self.counts)) / self.counts

    def __call__(self, sim):
        row = [sim.time, *map(float, self.pressures(sim.model))]
        self.rows.append(row)
        self.writer.writerow([f"{v:.9g}" for v in row])
        self.file.flush()

    def close(self):
        self.file.close()
