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
