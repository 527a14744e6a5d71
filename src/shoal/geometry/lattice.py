"""Cartesian-lattice particle generation.

Fluid blocks are filled with particles at the centres of cubes of side dp,
so a block [lo, hi] holds exactly its volume of fluid. Wall particles sit
on the same lattice outside the walls, at distances dp/2, 3dp/2, ... from
the wall surface, so the wall surface lies half a spacing from both.
All positions are world (x, y, z); 2D generators return y = 0.
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError


def _axis(a, b, dp):
    n = int(np.floor((b - a) / dp + 1e-9))
    return a + dp * (np.arange(n) + 0.5)


def box_fill(lo, hi, dp, dim):
    """Particles filling the box [lo, hi] on a lattice of spacing dp.

    Parameters
    ----------
    lo, hi : sequence of 3 floats
        Box corners [m] (y ignored in 2D).
    dp : float
        Particle spacing [m].
    dim : {2, 3}

    Returns
    -------
    (N, 3) float64 array of positions.
    """
    lo = np.asarray(lo, float)
    hi = np.asarray(hi, float)
    xs = _axis(lo[0], hi[0], dp)
    zs = _axis(lo[2], hi[2], dp)
    if dim == 2:
        X, Z = np.meshgrid(xs, zs, indexing="ij")
        return np.column_stack([X.ravel(), np.zeros(X.size), Z.ravel()])
    ys = _axis(lo[1], hi[1], dp)
    X, Y, Z = np.meshgrid(xs, ys, zs, indexing="ij")
    return np.column_stack([X.ravel(), Y.ravel(), Z.ravel()])


def tank_walls(lo, hi, dp, dim, layers=3, open_top=True):
    """Wall particles around the inside box [lo, hi] (a tank).

    `layers` rows of particles on the lattice outside the box, on the
    bottom and side walls (and the top unless `open_top`), corners filled.
    """
    if layers < 1:
        raise InputError(f"wall layers = {layers!r}; use an integer >= 1")
    lo = np.asarray(lo, float)
    hi = np.asarray(hi, float)
    t = layers * dp
    outer_lo = lo - t
    outer_hi = hi + t
    if open_top:
        outer_hi[2] = hi[2]
    if dim == 2:
        outer_lo[1], outer_hi[1] = 0.0, 1.0
    pts = box_fill(outer_lo, outer_hi, dp, dim)
    inside = np.all((pts[:, [0, 2]] > lo[[0, 2]]) & (pts[:, [0, 2]] < hi[[0, 2]]), axis=1)
    if dim == 3:
        inside &= (pts[:, 1] > lo[1]) & (pts[:, 1] < hi[1])
    return pts[~inside]


def hollow_box_walls(lo, hi, dp, dim, layers=1):
    """Particles forming the shell of a solid box [lo, hi] (an obstacle):
    `layers` rows inward from its surface, at dp/2, 3dp/2, ... inside."""
    lo = np.asarray(lo, float)
    hi = np.asarray(hi, float)
    pts = box_fill(lo, hi, dp, dim)
    t = layers * dp
    axes = [0, 2] if dim == 2 else [0, 1, 2]
    core = np.all((pts[:, axes] > lo[axes] + t) & (pts[:, axes] < hi[axes] - t), axis=1)
    return pts[~core]
