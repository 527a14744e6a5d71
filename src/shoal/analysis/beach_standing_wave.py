r"""The standing long wave on a plane beach (Carrier & Greenspan 1958): the periodic run-up reference.

Water of depth h = s X over a plane beach of slope s = tan(beta), X the distance offshore from the
still-water shoreline, carries the standing wave of the linear shallow-water equations

.. math::

    \eta(X, t) = A J_0(\sigma) \sin\omega t, \qquad
    u(X, t) = \frac{2 A \omega}{s \sigma} J_1(\sigma) \cos\omega t, \qquad
    \sigma = 2 \omega \sqrt{X / (g s)},

with u the depth-uniform velocity towards the shore (Lamb 1932, Hydrodynamics, section 186; the
phase is chosen so that at t = 0 the surface is flat and the shoreline moves landward at A omega / s).
The shoreline rises and falls between z = +A and -A about the still level, and runs horizontally
between +A/s and -A/s. Carrier & Greenspan (1958, J. Fluid Mech. 4, 97-109) solved the nonlinear
shallow-water equations for the same periodic wave by a hodograph transformation: for the standing
wave with the same offshore field, the shoreline's highest and lowest elevations are +A and -A as in
the linear theory (only the timing of the excursion is distorted), as long as the wave does not
break, which needs the breaking parameter

.. math:: \epsilon = A \omega^2 / (g s^2) < 1

(Carrier & Greenspan 1958; Synolakis 1987, J. Fluid Mech. 185, 523-545, for the run-up invariance).
The waves of shallow-water theory are long: the local wavenumber at depth d, k = omega / sqrt(g d),
needs k d small (at k d = 0.3 linear wave theory's celerity is 1.5 % below sqrt(g d)).

A flume reproduces the wave with a piston paddle at X = L (depth d = s L) that moves with the
solution's velocity there, the displacement

.. math:: \xi(t) = \frac{2 A}{s \sigma_L} J_1(\sigma_L) \sin\omega t, \qquad \sigma_L = 2 \omega \sqrt{L/(g s)},

and with the fluid started from the solution at t = 0: a flat surface at rest pressure and the
velocity u(X, 0) with the vertical velocity that keeps the flow on the bed and divergence-free,

.. math:: w = s u - (z - z_b) \partial u / \partial x, \qquad
          \partial u / \partial x = \frac{4 A \omega^3}{g s^2 \sigma^2} J_2(\sigma) \cos\omega t

(x = -X landward, z_b the bed elevation). Started so, the flume has no transient to wait out. The
paddle must not sit at a natural frequency of the closed basin, J_1(sigma_L) = 0 (sigma_L = 3.83,
7.02, ...), where it would stand still.

**The nonlinear wave.** Carrier & Greenspan's hodograph transformation makes the nonlinear
shallow-water equations linear. In units of length l = g s / omega^2 (horizontal; s l vertical), time
1 / omega and speed g s / omega, with x = X / l offshore and u the velocity offshore, the variables
a = 2 c (c = sqrt(x + eta), the long-wave speed of the local depth) and b turn the solution into

.. math::

    u = -2 \epsilon \frac{J_1(a)}{a} \cos b, \qquad
    \eta = -\epsilon J_0(a) \sin b - \frac{u^2}{2}, \qquad
    x = \frac{a^2}{4} - \eta, \qquad t = u - b,

which solves eta_t + ((x + eta) u)_x = 0 and u_t + u u_x + eta_x = 0 exactly (the hodograph plane's
wave equation (a phi_a)_a = a phi_bb, phi = 8 epsilon J_0(a) cos b, with u = phi_a / (2a) and
eta = phi_b / 8 - u^2 / 2 in these variables; Carrier & Greenspan 1958, Eqs. 3.1-3.6, derived
again and checked against the equations in `tests/test_beach_standing_wave.py`). For epsilon -> 0
it is the linear wave above (a -> sigma, b -> -omega t). The shoreline (a = 0) reaches exactly +A
and -A; at b = +-pi/2 the whole water body is at rest (u = 0 everywhere): at t = -T/4 the shoreline
is at its lowest, -A, and the surface is eta = -A J_0(a) at x = a^2 / 4 + epsilon J_0(a). The mapping
(a, b) -> (x, t) is one-to-one as long as epsilon < 1.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.special import j0, j1, jv

__all__ = ["BeachStandingWave"]


@dataclass(frozen=True)
class BeachStandingWave:
    """The standing long wave of shoreline amplitude `amplitude` on a beach of slope `slope`.

    Parameters
    ----------
    amplitude : float
        A [m]: the shoreline's vertical excursion about the still level (and the surface's amplitude
        there).
    slope : float
        s = tan(beta) of the beach.
    omega : float
        Angular frequency [rad/s].
    g : float
        Gravity [m/s^2].
    """

    amplitude: float
    slope: float
    omega: float
    g: float = 9.81

    @classmethod
    def for_flume(cls, depth, slope, sigma_paddle, breaking, g=9.81):
        """The wave whose paddle, at depth `depth`, sits at sigma_L = `sigma_paddle`, with the
        breaking parameter `breaking` (epsilon = A omega^2 / (g s^2)).

        omega = sigma_L s sqrt(g / d) / 2 (so k d = sigma_L s / 2 at the paddle) and
        A = epsilon g s^2 / omega^2."""
        omega = 0.5 * sigma_paddle * slope * math.sqrt(g / depth)
        return cls(amplitude=breaking * g * slope**2 / omega**2, slope=slope, omega=omega, g=g)

    @property
    def period(self):
        return 2.0 * math.pi / self.omega

    @property
    def breaking(self):
        """epsilon = A omega^2 / (g s^2): the wave breaks at epsilon >= 1."""
        return self.amplitude * self.omega**2 / (self.g * self.slope**2)

    def sigma(self, X):
        """sigma = 2 omega sqrt(X / (g s)) at the offshore distance X [m] (X < 0 clipped to 0)."""
        return 2.0 * self.omega * np.sqrt(np.maximum(np.asarray(X, float), 0.0) / (self.g * self.slope))

    def elevation(self, X, t):
        """eta [m] at offshore distance X [m], time t [s]."""
        return self.amplitude * j0(self.sigma(X)) * np.sin(self.omega * np.asarray(t, float))

    def _j1_over_sigma(self, s):
        s = np.asarray(s, float)
        safe = np.where(s > 1e-8, s, 1.0)
        return np.where(s > 1e-8, j1(safe) / safe, 0.5 - s**2 / 16.0)

    def velocity(self, X, t):
        """u [m/s] towards the shore, depth-uniform."""
        return (2.0 * self.amplitude * self.omega / self.slope * self._j1_over_sigma(self.sigma(X))
                * np.cos(self.omega * np.asarray(t, float)))

    def du_dx(self, X, t):
        """du/dx [1/s] along x = -X (landward)."""
        s = self.sigma(X)
        safe = np.where(s > 1e-6, s, 1.0)
        j2_over_s2 = np.where(s > 1e-6, jv(2, safe) / safe**2, 0.125 - s**2 / 96.0)
        return (4.0 * self.amplitude * self.omega**3 / (self.g * self.slope**2) * j2_over_s2
                * np.cos(self.omega * np.asarray(t, float)))

    def vertical_velocity(self, X, height, t):
        """w [m/s] at `height` [m] above the bed: s u - height du/dx (on the bed it follows the bed)."""
        return self.slope * self.velocity(X, t) - np.asarray(height, float) * self.du_dx(X, t)

    def shoreline(self, t):
        """The shoreline's elevation above the still level [m] (A sin omega t; its horizontal
        position is that over s, landward positive)."""
        return self.amplitude * np.sin(self.omega * np.asarray(t, float))

    def paddle_stroke(self, X_paddle):
        """The paddle's displacement amplitude [m] (landward positive) at offshore distance X_paddle:
        xi(t) = stroke sin omega t, stroke = 2 A J_1(sigma_L) / (s sigma_L)."""
        return float(2.0 * self.amplitude / self.slope * self._j1_over_sigma(self.sigma(X_paddle)))

    # the nonlinear solution (Carrier & Greenspan 1958), in the units of the module docstring

    @property
    def _length(self):
        """l = g s / omega^2 [m]: the hodograph's horizontal length unit (its vertical one is s l)."""
        return self.g * self.slope / self.omega**2

    def _hodograph(self, a, b):
        """(x, t, u, eta, (x_a, x_b, t_a, t_b)) at hodograph points (a, b), in the units of l."""
        e = self.breaking
        safe = np.where(a > 1e-8, a, 1.0)
        G = np.where(a > 1e-8, j1(safe) / safe, 0.5 - a**2 / 16.0)  # J1(a) / a
        dG = np.where(a > 1e-8, -jv(2, safe) / safe, -a / 8.0)  # its derivative, -J2(a) / a
        cb, sb = np.cos(b), np.sin(b)
        u = -2.0 * e * G * cb
        u_a, u_b = -2.0 * e * dG * cb, 2.0 * e * G * sb
        eta = -e * j0(a) * sb - 0.5 * u * u
        eta_a = e * j1(a) * sb - u * u_a
        eta_b = -e * j0(a) * cb - u * u_b
        return 0.25 * a * a - eta, u - b, u, eta, (0.5 * a - eta_a, -eta_b, u_a, u_b - 1.0)

    def nonlinear(self, X, t):
        """The nonlinear wave at offshore distance `X` [m] and time `t` [s]: (eta [m], u [m/s] towards
        the shore), NaN where the beach is dry (landward of the shoreline).

        Each (X, t) is mapped to its hodograph point by Newton's method, started from the linear
        wave's (a = sigma, b = -omega t)."""
        X, t = np.broadcast_arrays(np.asarray(X, float), np.asarray(t, float))
        x, tt = X / self._length, self.omega * t
        a = 2.0 * np.sqrt(np.maximum(x, 0.0)) + 1e-3
        b = -tt.copy()
        for _ in range(60):
            xa, ta, _, _, (x_a, x_b, t_a, t_b) = self._hodograph(a, b)
            r1, r2 = xa - x, ta - tt
            det = x_a * t_b - x_b * t_a
            with np.errstate(divide="ignore", invalid="ignore"):  # dry points pin a at 0, where det = 0
                da = np.nan_to_num((r1 * t_b - r2 * x_b) / det)
                db = np.nan_to_num((x_a * r2 - t_a * r1) / det)
            a = np.maximum(a - da, 0.0)
            b = b - db
            if np.all(np.abs(da) + np.abs(db) < 1e-13):
                break
        xa, ta, u, eta, _ = self._hodograph(a, b)
        wet = (np.abs(xa - x) < 1e-10 * (1.0 + np.abs(x))) & (np.abs(ta - tt) < 1e-10 * (1.0 + np.abs(tt)))
        speed = self.g * self.slope / self.omega
        return np.where(wet, eta * self.slope * self._length, np.nan), np.where(wet, -u * speed, np.nan)

    def nonlinear_shoreline(self, t):
        """The nonlinear wave's shoreline elevation [m] at time `t` [s] (a = 0, where t = -epsilon cos b
        - b): its extremes are +A and -A as in the linear wave, their timing is distorted."""
        tt = self.omega * np.asarray(t, float)
        e = self.breaking
        b = -tt.copy()
        for _ in range(60):  # dt/db = e sin b - 1 < 0 for e < 1
            db = (-e * np.cos(b) - b - tt) / (e * np.sin(b) - 1.0)
            b = b - db
            if np.all(np.abs(db) < 1e-14):
                break
        u = -e * np.cos(b)
        return (-e * np.sin(b) - 0.5 * u * u) * self.slope * self._length

    @property
    def rundown_time(self):
        """-T/4 [s]: the moment the shoreline is at its lowest (-A) and all the water is at rest (b = pi/2)."""
        return -0.25 * self.period

    def rundown_surface(self, X):
        """The surface elevation eta [m] at offshore distance `X` [m] at `rundown_time`, when the water
        is at rest: eta = -A J0(a) at x = a^2 / 4 + epsilon J0(a) (NaN landward of the shoreline,
        X < -A / s)."""
        l, e = self._length, self.breaking
        X = np.asarray(X, float)
        a_max = 2.0 * np.sqrt(max(float(np.max(X, initial=0.0)) / l, 0.0) + 2.0 * e) + 1.0
        a = np.linspace(0.0, a_max, 20001)
        xa = 0.25 * a * a + e * j0(a)  # increasing for e < 1: dx/da = a / 2 - e J1(a) > 0
        eta = np.interp(X / l, xa, -e * j0(a)) * self.slope * l
        return np.where(X / l >= xa[0], eta, np.nan)

    def column_path(self, X0, t0, t):
        """The offshore distance [m] at times `t` [s] of the water column that stands at `X0` [m] at time
        `t0` [s] in the nonlinear wave: the path of a paddle that moves with the water at its face,
        dX/dt = -u(X, t) (u towards the shore), integrated by `scipy.integrate.solve_ivp` (DOP853,
        relative tolerance 1e-10)."""
        from scipy.integrate import solve_ivp

        t = np.asarray(t, float)

        def rate(tau, y):
            return [-float(self.nonlinear(y[0], tau)[1])]

        out = np.empty_like(t)
        for sel, end in ((t >= t0, float(t.max())), (t < t0, float(t.min()))):
            if not sel.any():
                continue
            sol = solve_ivp(rate, (t0, end), [float(X0)], method="DOP853", dense_output=True, rtol=1e-10,
                            atol=1e-10 * abs(X0), max_step=self.period / 50)
            out[sel] = sol.sol(t[sel])[0]
        return out
