"""Wall layers parallel to a bed's surface instead of on the lattice's steps.

On the common lattice (`shoal.geometry.generate`) a sloping bed is a staircase: on a 1:10 beach the
wall particles form treads ten spacings long and risers one spacing high. Water a few spacings deep
does not notice, but a film one or two spacings thick, the tongue of run-up on a beach, meets a riser
every ten spacings. With ``fit_surface = true`` a bed's wall particles are moved, each along the bed's
normal n, onto layers parallel to its surface: in each lattice column (x, y) the wall particle k
lattice steps below the column's highest goes to the normal depth (k + 1/2) dp, where the fluid's first
layer would be mirrored (the surface lies half a spacing from both, as on a flat wall). A particle keeps
its position along the surface, so a layer is as dense as a lattice row seen along the slope (spacing
dp cos(beta), and dp (cos(beta) + sin(beta)) across a step of the lattice: dp / cos(beta) on average,
1.005 dp on 1:10). The fluid's rows above the bed are fitted too (`fit_fluid`): the lowest particle of
each column goes to dp/2 above the surface, and the rows above return to the lattice over `BLEND`
rows. Left on the lattice, a fluid particle could start as close as dp/2 to a fitted wall particle, where
the kernel's gradient is weak, and sink through the layer under the water's weight; dropping the
particles that lie too close leaves holes the water falls into. With mDBC the fitted particles' ghost
vectors are exact: 2 (k + 1/2) dp n.

The columns rank the particles of a bed whose gradient is at most 1 (slopes up to 45 degrees); where a
bed is steeper, its particles stay on the lattice. Beds are the shapes with a level z_b(x, y):
`Slope` and `Bathymetry` (the normal from z_b's gradient; on a curved bed each column uses its own
tangent plane).
"""

from __future__ import annotations

import numpy as np

STEEPEST = 1.0
"""Largest |grad z_b| whose columns are fitted (45 degrees); steeper columns keep the lattice."""


def bed_normal(shape, x, y):
    """(n (N, 3) upward unit normals, |grad z_b| (N,)) of the bed `shape` at the columns (x, y)."""
    gx, gy = shape.level_gradient(x, y)
    norm = np.sqrt(1.0 + gx * gx + gy * gy)
    return np.column_stack([-gx / norm, -gy / norm, 1.0 / norm]), np.hypot(gx, gy)


def lattice_columns(pos, dp, origin, dim):
    """Integer lattice column keys (x index, and y index in 3D) of the positions."""
    ix = np.floor((pos[:, 0] - origin[0]) / dp).astype(np.int64)
    if dim == 2:
        return ix
    iy = np.floor((pos[:, 1] - origin[1]) / dp).astype(np.int64)
    return ix * (1 << 32) + (iy + (1 << 31))


def _sorted_in_columns(key, value):
    """(order, start): the particles sorted by column `key`, then by `value`; start[i] is the position
    in that order of the first particle of the i-th sorted particle's column."""
    order = np.lexsort((value, key))
    first = np.ones(len(order), bool)
    first[1:] = key[order][1:] != key[order][:-1]
    return order, np.maximum.accumulate(np.where(first, np.arange(len(order)), 0))


def fit_walls(shape, pos, dp, origin, dim):
    """Fit the lattice wall particles `pos` ((N, 3), one bed's, changed in place) to layers parallel to
    the bed's surface.

    Returns
    -------
    ghosts : (N, 3) ndarray
        The mDBC ghost vectors of the particles, 2 (k + 1/2) dp n (the lattice's, from the generator,
        are replaced where a column was fitted; zero rows where it was not).
    fitted : (N,) bool
        The particles that were moved (their columns' gradient is at most `STEEPEST`).
    columns : ndarray
        The column keys of the fitted particles (for `fit_fluid`).
    """
    n, steep = bed_normal(shape, pos[:, 0], pos[:, 1])
    level = shape.level(pos[:, 0], pos[:, 1])
    depth = (level - pos[:, 2]) * n[:, 2]  # normal distance below the column's tangent plane
    key = lattice_columns(pos, dp, origin, dim)
    # k: lattice steps below the column's highest wall particle (a gap in a column stays a gap)
    order, start = _sorted_in_columns(key, -pos[:, 2])
    top = np.empty(len(order))
    top[order] = pos[order, 2][start]
    rank = np.rint((top - pos[:, 2]) / dp).astype(np.int64)
    target = (rank + 0.5) * dp
    fitted = steep <= STEEPEST
    shift = np.where(fitted, depth - target, 0.0)
    pos += shift[:, None] * n
    ghosts = np.where(fitted[:, None], 2.0 * target[:, None] * n, 0.0)
    return ghosts, fitted, np.unique(key[fitted])


BLEND = 4
"""Fluid rows over which the fitted columns return to the lattice (`fit_fluid`)."""


def fit_fluid(shape, pos, dp, origin, dim, columns):
    """Fit the fluid particles `pos` ((M, 3), changed in place) of the fitted `columns` to the bed: in
    each column the k-th particle from the bottom moves along the normal by (1 - k / BLEND) of the
    distance that puts the lowest one at dp/2 above the surface (for k < BLEND), so the first row lies
    parallel to the surface, as far from it as the first wall layer is, and the rows return to the
    lattice over BLEND rows (their spacing within (1 +- 1/(2 BLEND)) dp); no particle is added or
    removed. Returns how many moved."""
    if not len(pos) or not len(columns):
        return 0
    key = lattice_columns(pos, dp, origin, dim)
    idx = np.flatnonzero(np.isin(key, columns))
    if not len(idx):
        return 0
    n, steep = bed_normal(shape, pos[idx, 0], pos[idx, 1])
    height = (pos[idx, 2] - shape.level(pos[idx, 0], pos[idx, 1])) * n[:, 2]
    k_idx = key[idx]
    order, start = _sorted_in_columns(k_idx, height)
    rank = np.empty(len(order), np.int64)
    rank[order] = np.arange(len(order)) - start
    lowest = np.empty(len(order))
    lowest[order] = height[order][start]
    weight = np.clip(1.0 - rank / BLEND, 0.0, 1.0) * (steep <= STEEPEST)
    shift = weight * (0.5 * dp - lowest)
    pos[idx] += shift[:, None] * n
    return int(np.count_nonzero(shift))
