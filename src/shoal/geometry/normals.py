r"""Ghost vectors of dynamic wall particles for the modified dynamic boundary condition.

The modified dynamic boundary condition (mDBC) of English et al. (2022), as
in DualSPHysics 5.4, gives each dynamic wall particle at x_p the density of
the fluid around its *ghost node*, the particle's mirror image across the
wall surface::

    x_ghost = x_p + g_p,    g_p = 2 d_p n_p,

with n_p the unit normal of the wall surface pointing into the fluid side
and d_p the distance from the particle to the surface along n_p. This
module computes the *ghost vector* g_p of every dynamic wall particle at
generation time (`WallNormals`, called by `shoal.geometry.generate` slab by
slab), in two steps:

1. **Direction from the lattice** (`lattice_normals`): n_p is the gradient
   of the smoothed non-solid indicator on the generation lattice,

   .. math:: \mathbf n_p \propto -\sum_{j\,\mathrm{solid},\ |x_p - x_j| < R}
             \nabla W(\mathbf x_p - \mathbf x_j),

   over the solid lattice nodes j within R = (2h/dp) dp of the wall node,
   with the radially decreasing weight W(r) = 1 - (r/R)^2 (Epanechnikov),
   whose gradient makes the sum -Σ_solid (x_j - x_p) = Σ_nonsolid (x_j -
   x_p): n_p points from the particle to the centroid of the non-solid
   nodes within R. The sum is over integer offsets, so it is exact: a
   flat wall's normals are exactly normal to it, and a sum that cancels
   (the middle layer of a plate with fluid on both sides) leaves n_p = 0.
   The lattice's steps tilt the normals of sloping walls: on a 1:10 slope
   the first wall layer's stay within 12.7 deg of the true normal in 2D
   (R = 2 sqrt 2) and 10.2 deg in 3D (R = 2 sqrt 3), on 1:17 and 1:30
   slopes within 17.2 and 14.0 deg (measured over lattice offsets of the
   slope); the Wendland C2 kernel's gradient, which weights the nearest
   nodes most, gave 21 deg on 1:10 in 2D. The ghost node stays the exact
   mirror image along n_p: at the particle's distance from the wall, on
   the other side.
2. **Distance from the exact geometry** (`exit_distance`): from x_p the ray
   x_p + s n_p is sampled every dp/4 up to L_max = 1.5 (2h/dp + 1) dp with
   the shapes' own ``contains`` (the test that classified the lattice:
   same wall pads, same 1e-7 dp nudge); the first sample outside the
   solids brackets the surface, which `BISECTIONS` halvings then locate to
   dp/4 / 2^20 (2.4e-7 dp), so that a plane wall's ghost node is its exact
   mirror image to better than 1e-6 dp. No exit within L_max, or n_p = 0,
   gives g_p = 0 (the run then extrapolates at the particle itself).

Which lattice nodes count as solid for a particle's normal (its *mask*):

* a **fixed** wall particle sees the union of the fixed solids; moving
  solids count as empty space, since they move off the fixed walls they
  touch and uncover them (the floor under a piston paddle points up);
* a **moving** wall particle sees its own group of solids (the solids
  moving with one motion). The other solids it touches are neither solid
  nor empty for it: each of their nodes takes the value of the nearest node
  that is its own solid or empty space (the body is continued through its
  neighbours, as the geometry is continued beyond the generation box), so
  the faces it keeps in contact with (a paddle sliding on the floor and
  between the side walls) do not bend its normals: a paddle's front face
  points along its stroke down to the floor;
* the space **behind a shell** (`Tank`: outside its inside, extended
  through its open faces) counts as solid of the shell's group: a tank wall
  is only as thick as the kernel support, and its outer layers would
  otherwise point out of the tank, away from any fluid;
* beyond the generation box the geometry is continued by edge replication,
  so a flat bed meeting a domain face stays flat there (right for periodic
  and open faces alike). `shoal.case.Case` moves that edge in to where its
  shapes end (the automatic domain's empty ring of one spacing around them
  is never wetted): a wall on the edge of the case, such as the end wall of
  a flume, then mirrors all its layers across its wetted face.

Wall particles with no non-solid node within R (the outer corner and edge
lines of a tank's walls, a wall's deep layers behind an obstacle) get no
ghost vector: no fluid comes within the kernel support of them.

The distance march uses the same solids as the mask of the particle's
group (fixed: the fixed solids; moving: its group's own solids), without
the virtual solid behind shells.

References
----------
.. [1] A. English, J. M. Domínguez, R. Vacondio, A. J. C. Crespo,
   P. K. Stansby, S. J. Lind, L. Chiapponi, M. Gómez-Gesteira, "Modified
   dynamic boundary conditions (mDBC) for general-purpose smoothed particle
   hydrodynamics (SPH): application to tank sloshing, dam break and fish
   pass problems", Computational Particle Mechanics 9, 911-925 (2022).
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["WallNormals", "stencil", "lattice_normals", "exit_distance", "fill_neutral",
           "BISECTIONS", "MARCH_STEP", "MARCH_REACH"]

BISECTIONS = 20
"""Halvings of the bracket [s, s + dp/4] around the wall surface: 2.4e-7 dp at the end."""
MARCH_STEP = 0.25
"""Sampling step of the march along the normal, in lattice spacings."""
MARCH_REACH = 1.5
"""Longest march, in units of (2h/dp + 1) lattice spacings (the deepest wall layer is below 2h/dp)."""


def stencil(dim, support_ratio):
    """Lattice offsets inside the kernel support, one of each pair (o, -o).

    Parameters
    ----------
    dim : {2, 3}
    support_ratio : float
        Kernel support over spacing, R = 2h/dp.

    Returns
    -------
    (K, dim) int64
        The offsets o with 0 < |o| < R whose first non-zero component is
        positive. A solid node at p + o contributes -∇W(-o dp) ∝ -o to the
        normal at p (W(r) = 1 - (r/R)^2), the one at p - o contributes +o.
    """
    R = float(support_ratio)
    r = int(math.ceil(R))
    span = np.arange(-r, r + 1)
    o = np.stack(np.meshgrid(*([span] * dim), indexing="ij"), -1).reshape(-1, dim)
    dist = np.sqrt((o.astype(float) ** 2).sum(1))
    first = o[np.arange(len(o)), np.argmax(o != 0, axis=1)]  # first non-zero component
    return o[(dist > 0) & (dist < R) & (first > 0)].astype(np.int64)


def lattice_normals(mask, nodes, offsets):
    """Unit normals at lattice nodes from a solid mask: the gradient of the smoothed non-solid indicator.

    Parameters
    ----------
    mask : (n0, n1[, n2]) bool
        Solid nodes; must hold every node within the stencil of `nodes`.
    nodes : (M, dim) int
        Multi-indices of the nodes to compute the normal at.
    offsets : (K, dim) int
        From `stencil` (one offset of each pair +-o).

    Returns
    -------
    (M, dim) float64
        n = -Σ_o o (s(p + o) - s(p - o)) over the stencil's half (s: the
        mask, 0 or 1), normalised: -Σ_solid ∇W(x_p - x_j) for the kernel
        W(r) = 1 - (r/R)^2, i.e. the direction from the node to the
        centroid of the non-solid nodes within R. The sum is over integers,
        hence exact: symmetric neighbourhoods cancel exactly, and a zero
        sum (the middle layer of a plate with fluid on both sides, or a
        node with no non-solid node within R) gives a zero row.
    """
    dim = mask.ndim
    flat = mask.ravel().view(np.int8)
    strides = np.array([int(np.prod(mask.shape[a + 1:])) for a in range(dim)], np.int64)
    base = np.asarray(nodes, np.int64) @ strides
    # n_a = -Σ_v v Σ_{o: o_a = v} diff_o: sum the pairs' differences by the value of each component
    # first (additions only), then weight those few sums
    by_value = {}
    for o, shift in zip(offsets, offsets @ strides):
        diff = flat[base + shift] - flat[base - shift]  # -1, 0 or 1
        for a in range(dim):
            if o[a]:
                key = (a, int(o[a]))
                if key in by_value:
                    by_value[key] += diff
                else:
                    by_value[key] = diff.astype(np.int16)
    n = np.zeros((len(base), dim))
    for (a, v), total in by_value.items():
        n[:, a] -= v * total
    norm = np.linalg.norm(n, axis=1)
    ok = norm > 0.5  # integer vectors: zero or at least 1 long
    n[ok] /= norm[ok, None]
    return n


def fill_neutral(mask, neutral):
    """`mask` with each `neutral` node given the value of the nearest non-neutral node.

    Continues a body through the solids it touches (ties between equally
    near nodes are broken by `scipy.ndimage.distance_transform_edt`).
    """
    if not neutral.any() or neutral.all():
        return mask
    from scipy.ndimage import distance_transform_edt

    nearest = distance_transform_edt(neutral, return_distances=False, return_indices=True)
    return mask[tuple(nearest)]


def exit_distance(points, directions, inside, step, max_length, bisections=BISECTIONS):
    """Distance from each point along its direction to where it leaves the solid.

    Parameters
    ----------
    points : (M, 3) float64
        Start points, inside the solid.
    directions : (M, 3) float64
        Unit directions (zero rows are skipped).
    inside : callable
        ``inside(points) -> (len(points),) bool``.
    step : float
        Lattice spacing dp [m]; the ray is sampled every `MARCH_STEP` dp.
    max_length : float
        Longest march [m].
    bisections : int
        Halvings of the bracket around the first sample outside.

    Returns
    -------
    (M,) float64
        The exit distance [m] (midpoint of the last bracket), NaN where the
        ray stays inside up to `max_length` or the direction is zero.
    """
    m = len(points)
    d = np.full(m, np.nan)
    active = np.flatnonzero(np.any(directions != 0.0, axis=1))
    lo = np.zeros(m)
    hi = np.zeros(m)
    found = np.zeros(m, bool)
    ds = MARCH_STEP * step
    n_steps = int(math.ceil(max_length / ds - 1e-9))
    prev = 0.0
    for k in range(1, n_steps + 1):
        if not len(active):
            break
        s = min(k * ds, max_length)
        out = ~inside(points[active] + s * directions[active])
        done = active[out]
        lo[done], hi[done], found[done] = prev, s, True
        active = active[~out]
        prev = s
    idx = np.flatnonzero(found)
    if len(idx):
        a, b = lo[idx], hi[idx]
        p, u = points[idx], directions[idx]
        mid = np.empty(len(idx))
        q = np.empty_like(p)
        for _ in range(bisections):
            np.add(a, b, out=mid)
            mid *= 0.5
            np.multiply(u, mid[:, None], out=q)
            q += p
            ins = inside(q)
            np.copyto(a, mid, where=ins)
            np.copyto(b, mid, where=~ins)
        d[idx] = 0.5 * (a + b)
    return d


def _behind_shell(shape, coords, dim, pad, margin):
    """Nodes behind a shell's walls: outside its inside (extended through its
    open faces) and within `margin` [m] of its outer box.

    `coords` are the (nudged) node coordinates along each lattice axis of a
    block of the lattice; the result is a boolean array of that block.
    """
    cols = [0, 2] if dim == 2 else [0, 1, 2]
    lo, hi = np.asarray(shape.lo, float), np.asarray(shape.hi, float)
    olo, ohi = shape.bounds(dim, pad)
    inner = near = True
    for k, (a, c) in enumerate(zip(cols, coords)):
        c = c.reshape([-1 if j == k else 1 for j in range(len(cols))])
        into = np.ones(c.shape, bool)
        if f"{'xyz'[a]}min" not in shape.open:
            into &= c > lo[a]
        if f"{'xyz'[a]}max" not in shape.open:
            into &= c < hi[a]
        inner = inner & into
        near = near & (c >= olo[a] - margin) & (c <= ohi[a] + margin)
    return near & ~inner


class WallNormals:
    """Ghost vectors of the dynamic wall particles of one lattice, slab by slab.

    Parameters
    ----------
    dim : {2, 3}
    step : float
        Lattice spacing dp [m].
    solids : list of SolidInput
        Their `moving` flag and `group` (motion name) decide the masks: the
        fixed solids form one group, the moving solids one group per
        `group` (a moving solid without one is a group of its own).
    pads : list of float
        The wall pads [m] the lattice was classified with (one per solid).
    support_ratio : float
        Kernel support over spacing, 2h/dp.
    nudge : (3,) float
        Classification nudge in spacings (a node x is classified at x + nudge dp).
    coords : list of 1-D arrays
        World coordinates [m] of the generation box's nodes along each
        lattice axis (x, z in 2D; x, y, z in 3D).
    limits : (lo, hi) of (dim,) int, optional
        The lattice nodes [lo, hi) (indices into `coords`) where the
        geometry ends for the normals: beyond them the masks are continued
        by edge replication. Default: the whole generation box.
    box : (lo, hi) of 3 floats, optional
        The same end in world coordinates [m]: the march along the normals
        evaluates the shapes at points clamped into it (their edge
        replication). Default: no clamping.

    Attributes
    ----------
    halo : int
        Lattice columns a slab needs beyond its core on each side: the
        stencil (ceil(R)) plus the nearest-node search that continues a
        moving body through its neighbours (another ceil(R)), plus one.
    """

    def __init__(self, dim, step, solids, pads, support_ratio, nudge, coords, limits=None, box=None):
        self.dim = dim
        self.step = float(step)
        self.cols = [0, 2] if dim == 2 else [0, 1, 2]
        self.solids = solids
        self.pads = list(pads)
        self.nudge = np.asarray(nudge, float) * step
        self.coords = [np.asarray(c, float) + self.nudge[a] for a, c in zip(self.cols, coords)]
        self.limits = limits
        self.box = None
        if box is not None:
            self.box = (np.asarray(box[0], float), np.asarray(box[1], float))
        self.offsets = stencil(dim, support_ratio)
        self.reach = int(math.ceil(support_ratio))
        self.halo = 2 * self.reach + 1
        self.max_length = MARCH_REACH * (support_ratio + 1.0) * step
        keys, group = [], []
        for k, s in enumerate(solids):
            key = ("moving", getattr(s, "group", None) or f"#{k}") if s.moving else ("fixed",)
            if key not in keys:
                keys.append(key)
            group.append(keys.index(key))
        self.group = np.array(group, np.int64)
        self.moving = [key[0] == "moving" for key in keys]
        self.dynamic = np.array([s.method != "repulsive" for s in solids], bool)
        self.shells = [k for k, s in enumerate(solids) if getattr(s.shape, "shell", False)]
        self.cull = []
        for k, s in enumerate(solids):
            if getattr(s.shape, "type", None) == "mesh":
                lo, hi = s.shape.bounds(dim, self.pads[k])
                self.cull.append((np.asarray(lo, float) - step, np.asarray(hi, float) + step))
            else:
                self.cull.append(None)

    def inside(self, probe, members):
        """Which (already nudged, (M, 3)) points lie inside the union of the solids `members`."""
        if self.box is not None:
            # beyond the geometry's end the shapes are continued by edge replication, like the masks
            probe = probe.copy()
            for a in self.cols:
                np.clip(probe[:, a], self.box[0][a], self.box[1][a], out=probe[:, a])
        m = np.zeros(len(probe), bool)
        for k in members:
            shape, pad = self.solids[k].shape, self.pads[k]
            if self.cull[k] is None:
                m |= shape.contains(probe, self.dim, pad)  # cheap: cheaper than selecting points first
                continue
            # a mesh's inside test sums the solid angles of all its triangles: only the points in its box
            lo, hi = self.cull[k]
            cand = ~m
            for a in self.cols:
                cand &= (probe[:, a] >= lo[a]) & (probe[:, a] <= hi[a])
            if cand.any():
                m[cand] = shape.contains(probe[cand], self.dim, pad)
        return m

    def __call__(self, owner, core, wall, points, x0=0):
        """Ghost vectors of the wall nodes of one slab.

        Parameters
        ----------
        owner : (n0, n1[, n2]) int
            Solid owning each node of the slab and its halo (-1: none).
        core : slice
            The slab's own columns (first axis) within `owner`.
        wall : (M,) int
            The wall nodes, as flat indices into ``owner[core]``.
        points : (M, 3) float64
            Their world positions.
        x0 : int
            Index of the first column of `owner` in the generation box.

        Returns
        -------
        (M, 3) float64
            Ghost vectors 2 d n [m]; zero rows for the wall nodes of
            repulsive solids and where no surface was found.
        """
        ghosts = np.zeros((len(wall), 3))
        if not len(wall):
            return ghosts
        shape = np.array(owner.shape)
        shift = np.zeros(len(shape), np.int64)
        shift[0] = x0
        # the nodes whose values the masks continue beyond the geometry's end, in slab indices
        first, last = np.zeros(len(shape), np.int64), shape - 1
        if self.limits is not None:
            first = np.maximum(first, np.asarray(self.limits[0]) - shift)
            last = np.minimum(last, np.asarray(self.limits[1]) - 1 - shift)
        node = np.array(np.unravel_index(wall, owner[core].shape)).T
        node[:, 0] += core.start or 0
        solid_of = owner[tuple(node.T)]
        group_of = self.group[solid_of]
        probe = points + self.nudge
        for g, moving in enumerate(self.moving):
            sel = np.flatnonzero((group_of == g) & self.dynamic[solid_of])
            if not len(sel):
                continue
            members = np.flatnonzero(self.group == g)
            # a window around the group's wall nodes: the stencil reaches `reach` nodes, the
            # nearest-node search that continues a moving body another `reach`; clamped indices
            # continue the geometry by edge replication beyond its end
            margin = self.reach * (2 if moving else 1) + 1
            lo = node[sel].min(0) - margin
            span = node[sel].max(0) + margin + 1 - lo
            index = [np.clip(np.arange(a, a + n), f, l) for a, n, f, l in zip(lo, span, first, last)]
            sub = owner[np.ix_(*index)]
            if self.shells:
                coords = [c[i + s] for c, i, s in zip(self.coords, index, shift)]
                free = sub < 0
                for k in self.shells:
                    behind = free & _behind_shell(self.solids[k].shape, coords, self.dim, self.pads[k],
                                                  (self.halo + 1) * self.step)
                    sub[behind] = k
                    free &= ~behind
            member = np.zeros(len(self.solids) + 1, bool)
            member[members + 1] = True
            mask = member[sub + 1]
            if moving:
                mask = fill_neutral(mask, (sub >= 0) & ~mask)
            n = np.zeros((len(sel), 3))
            n[:, self.cols] = lattice_normals(mask, node[sel] - lo, self.offsets)
            d = exit_distance(probe[sel], n, lambda q: self.inside(q, members), self.step, self.max_length)
            ok = np.isfinite(d)
            ghosts[sel[ok]] = 2.0 * d[ok, None] * n[ok]
        return ghosts
