"""Geometry -> particles: fill fluid regions and build walls on one lattice.

Every particle sits at a node of one Cartesian lattice of spacing dp,
``origin + (i + 1/2) dp`` along each axis (the y axis is dropped in 2D), as
in DualSPHysics's GenCase. A lattice node belongs to the first solid that
contains it; otherwise to the first fluid region that contains it; otherwise
it stays empty. So fluid never overlaps a solid and the closest fluid-wall
pair is one spacing apart, whatever the shapes.

Walls are the solid nodes near the space the fluid can reach (a `Tank` is
a shell exactly as thick as its layers, kept whole, corners included):

* **dynamic boundary particles** (several layers): the solid nodes whose
  Euclidean distance to the nearest non-solid node is below the kernel
  support 2h (default), i.e. every wall particle some fluid particle can
  see; or, with ``layers = n``, within n spacings in the chessboard metric
  (diagonal steps count one, so box corners are filled; it holds every node
  within n spacings Euclidean);
* **repulsive boundary particles** (Monaghan & Kajtar 2009): a single
  layer on a lattice of spacing dp/2 (same origin), the fine solid nodes
  with a face neighbour outside the solids.

Distances come from the exact Euclidean distance transform
(`scipy.ndimage.distance_transform_edt`, Maurer et al. 2003) of the solid
mask, computed slab by slab along x with a halo, so memory stays bounded
for basins of millions of particles; the slabs are built on up to 8 threads
(NumPy and SciPy release the GIL on large arrays), and each distance
transform only where a solid needs it (the DualSPHysics dam break at 20.8M
particles: 14.6 s on 2 cores). Nodes are classified at points nudged
by 1e-7 dp, so a node lying exactly on a shape's face is decided the same
way everywhere (faces behave as half-open intervals [lo, hi)).

For the modified dynamic boundary condition (mDBC) the generator also
gives each dynamic wall particle its ghost vector, to its mirror image
across the wall surface (``normals=True``; `shoal.geometry.normals`),
computed in the same slabs from the same classification.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..errors import InputError
from ..faults import reached

FLUID, FIXED, MOVING = 0, 1, 2
_NUDGE = 1e-7 * np.array([0.731, 0.547, 0.613])
_SLAB_NODES = 4_000_000
_MAX_SLAB_WORKERS = 8
"""Slabs generated at once (threads): each holds about 100 bytes a node (0.4 GB) while it is built."""


def _slab_workers(n_slabs):
    """Threads for `n_slabs` slabs: the CPU cores this process may use, at most `_MAX_SLAB_WORKERS`."""
    import os

    try:
        cores = len(os.sched_getaffinity(0))
    except AttributeError:  # not Linux
        cores = os.cpu_count() or 1
    return max(1, min(n_slabs, cores, _MAX_SLAB_WORKERS))


@dataclass
class Particles:
    """Generated particles.

    Attributes
    ----------
    positions : (N, 3) float64
        World positions [m] (y = 0 in 2D).
    kinds : (N,) int8
        0 fluid, 1 fixed boundary, 2 moving boundary.
    velocities : (N, 3) float64
        Initial velocities [m/s].
    body : (N,) int16
        Index of the solid a boundary particle belongs to (-1 for fluid).
    region : (N,) int16
        Index of the fluid region a fluid particle belongs to (-1 for walls).
    spacing : (N,) float64
        Lattice spacing the particle was generated on (dp, or dp/2 for
        repulsive boundary particles).
    body_names : list of str
        Name of each solid (indexed by `body`).
    zone : (N,) int16 or None
        Index of the open boundary whose buffer a fluid particle starts in (-1 for the others;
        `shoal.open_boundary`), or None: the case has none.
    normals : (N, 3) float64 or None
        Ghost vectors [m] of the modified dynamic boundary condition (mDBC):
        from each dynamic wall particle to its mirror image across the wall
        surface, 2 d n (`shoal.geometry.normals`); zero rows for fluid and
        repulsive particles and where no surface was found. None unless
        generated with ``normals=True``.
    """

    positions: np.ndarray
    kinds: np.ndarray
    velocities: np.ndarray
    body: np.ndarray
    region: np.ndarray
    spacing: np.ndarray
    body_names: list = field(default_factory=list)
    normals: np.ndarray | None = None
    zone: np.ndarray | None = None

    def __len__(self):
        return len(self.positions)

    @property
    def n_fluid(self):
        return int(np.count_nonzero(self.kinds == FLUID))

    def counts(self):
        """Particle counts by kind: {"fluid": n, "fixed": n, "moving": n}."""
        return {name: int(np.count_nonzero(self.kinds == k))
                for name, k in (("fluid", FLUID), ("fixed", FIXED), ("moving", MOVING))}


@dataclass
class SolidInput:
    """What the generator needs to know about one solid."""

    shape: object
    method: str = "dynamic"  # or "repulsive"
    layers: int | None = None
    moving: bool = False
    name: str = ""
    group: str | None = None
    """Moving solids of one group (one motion) share their wall normals' mask (`shoal.geometry.normals`)."""
    fit_surface: bool = False
    """A bed (`Slope`, `Bathymetry`) whose wall particles go onto layers parallel to its surface
    (`shoal.geometry.surface_fit`)."""
    whole: bool = False
    """Its wall layers on every face of its own, measured from its own surface, not only where the fluid is at
    the start: a floating body may meet the water with any face (one resting on the bed at t = 0 has its
    bottom layers too)."""


@dataclass
class FluidInput:
    shape: object
    velocity: tuple = (0.0, 0.0, 0.0)


def _axis_range(lo, hi, origin, step):
    """Lattice indices i with origin + (i + 1/2) step in [lo, hi]."""
    i0 = math.ceil((lo - origin) / step - 0.5 - 1e-9)
    i1 = math.floor((hi - origin) / step - 0.5 + 1e-9)
    return i0, i1 + 1


def _nudged_range(lo, hi, origin, step, nudge):
    """Lattice indices i [i0, i1) whose node, nudged by `nudge` spacings, lies in [lo, hi]: the
    nodes a box holds as the shapes classify them (a node on the upper face lies outside)."""
    return (math.ceil((lo - origin) / step - 0.5 - nudge),
            math.floor((hi - origin) / step - 0.5 - nudge) + 1)


def support_layers(support_ratio):
    """Number of wall layers inside the kernel support: the integers k >= 1
    with k < 2h/dp (layer k is k spacings from the first fluid row)."""
    return max(1, math.ceil(support_ratio - 1e-9) - 1)


def generate(dim, dp, box, solids, fluids, support_ratio, origin=(0.0, 0.0, 0.0), normals=False,
             normals_box=None):
    """Particles of a case on the lattice of spacing `dp`.

    Parameters
    ----------
    dim : {2, 3}
    dp : float
        Lattice spacing [m].
    box : (lo, hi)
        Region to generate in [m] (the computational domain).
    solids : list of SolidInput
    fluids : list of FluidInput
    support_ratio : float
        Kernel support over spacing, 2h/dp: walls without explicit `layers`
        reach this far from the fluid.
    origin : 3 floats
        Lattice origin [m].
    normals : bool
        Also compute the ghost vectors of the dynamic wall particles for the
        modified dynamic boundary condition (mDBC, English et al. 2022):
        ``Particles.normals``, see `shoal.geometry.normals`.
    normals_box : (lo, hi), optional
        Where the geometry ends for those normals [m] (default: `box`):
        beyond it the solids are continued by edge replication, as beyond a
        domain face. `shoal.case.Case` gives the box of its shapes, without
        the empty ring the automatic domain adds around them, so that the
        outer faces of the walls on the edge of a case (a tank's, an end
        wall's) do not count as wetted.

    Returns
    -------
    Particles
    """
    origin = np.asarray(origin, float)
    lo = np.asarray(box[0], float)
    hi = np.asarray(box[1], float)
    for a in (0, 2) if dim == 2 else (0, 1, 2):  # lattice indices are counted from the origin, in floats
        if not abs(float(lo[a]) - float(origin[a])) / dp < 1e15:
            raise InputError(f"lattice_origin.{'xyz'[a]} = {origin[a]:.4g} m is more than 1e15 spacings "
                             f"(dp = {dp:g} m) from the case, which starts at {'xyz'[a]} = {lo[a]:.4g} m: no "
                             "lattice can be placed from it; give an origin near the case")
    thick = []
    for s in solids:
        if s.layers is not None and (not isinstance(s.layers, (int, np.integer)) or s.layers < 1):
            raise InputError(f"solid {s.name!r}: layers = {s.layers!r}; use an integer >= 1 or leave it out "
                             "for walls as thick as the kernel support")
        if s.method == "repulsive":
            thick.append(1.0)
        elif s.layers is None:
            thick.append(float(support_layers(support_ratio)))
        else:
            thick.append(float(s.layers))
    parts = [_generate_on(dim, dp, lo, hi, origin, solids, fluids, support_ratio, thick, fine=False,
                          normals=normals, normals_box=normals_box)]
    if any(s.method == "repulsive" for s in solids):
        parts.append(_generate_on(dim, dp / 2, lo, hi, origin, solids, [], support_ratio, thick, fine=True))
    pos = np.concatenate([p[0] for p in parts])
    kinds = np.concatenate([p[1] for p in parts])
    vel = np.concatenate([p[2] for p in parts])
    body = np.concatenate([p[3] for p in parts])
    region = np.concatenate([p[4] for p in parts])
    spacing = np.concatenate([np.full(len(p[0]), dp if k == 0 else dp / 2) for k, p in enumerate(parts)])
    ghosts = None
    if normals:  # repulsive particles (the fine lattice) have none
        ghosts = np.concatenate([p[5] if p[5] is not None else np.zeros((len(p[0]), 3)) for p in parts])
    # fluid first, then the walls solid by solid (stable: lattice order within each)
    order = np.lexsort((np.arange(len(pos)), body))
    pos, kinds, vel, body, region, spacing = (a[order] for a in (pos, kinds, vel, body, region, spacing))
    ghosts = None if ghosts is None else ghosts[order]
    for k, s in enumerate(solids):
        if s.fit_surface:
            _fit_surface(s, k, pos, kinds, body, spacing, ghosts, dp, origin, dim)
    return Particles(pos, kinds, vel, body, region, spacing, [s.name for s in solids], ghosts)


def solid_nodes(dim, dp, solids, k, origin=(0.0, 0.0, 0.0)):
    """The lattice nodes [m] that solid `k` of `solids` owns, all of them, not only its wall layers: the
    region a floating body fills (its mass properties, `shoal.mass_properties`).

    A node belongs to the first solid whose shape holds it, as `generate` classifies nodes (nudged by
    1e-7 dp, faces half-open), so a body's nodes are those its wall particles are taken from.

    Parameters
    ----------
    dim : {2, 3}
    dp : float
        Lattice spacing [m].
    solids : list of SolidInput
    k : int
        Which solid.
    origin : 3 floats
        Lattice origin [m].

    Returns
    -------
    ndarray, shape (N, 3)
    """
    origin = np.asarray(origin, float)
    axes = [0, 2] if dim == 2 else [0, 1, 2]
    lo, hi = solids[k].shape.bounds(dim)
    ranges = [_axis_range(lo[a], hi[a], origin[a], dp) for a in axes]
    coords = [origin[a] + (np.arange(i0, i1) + 0.5) * dp for a, (i0, i1) in zip(axes, ranges)]
    grids = np.meshgrid(*coords, indexing="ij")
    pts = np.zeros((grids[0].size, 3))
    for a, g in zip(axes, grids):
        pts[:, a] = g.ravel()
    probe = pts + _NUDGE * dp
    mine = solids[k].shape.contains(probe, dim, 0.0)
    for s in solids[:k]:
        mine[mine] &= ~s.shape.contains(probe[mine], dim, 0.0)
    return pts[mine]


def _fit_surface(solid, k, pos, kinds, body, spacing, ghosts, dp, origin, dim):
    """Move solid `k`'s wall particles onto layers parallel to its surface and fit the fluid's rows
    above it (`pos` and `ghosts` change in place; `shoal.geometry.surface_fit`)."""
    from .surface_fit import fit_fluid, fit_walls, lattice_columns

    if not hasattr(solid.shape, "level_gradient") or solid.method == "repulsive":
        raise InputError(f"solid {solid.name!r}: fit_surface = true is for the dynamic walls of a bed "
                         f"(a slope or a bathymetry); this one is a {getattr(solid.shape, 'type', 'shape')} "
                         f"with {solid.method} particles")
    own = (body == k) & (spacing == dp)
    if not own.any():
        return
    # the fixed wall particles below the surface in the bed's columns, whoever owns them (a tank's floor
    # under a beach listed after the tank), so that the layers are whole
    columns = lattice_columns(pos[own], dp, origin, dim)
    below = (kinds == FIXED) & (spacing == dp) & (pos[:, 2] < solid.shape.level(pos[:, 0], pos[:, 1]))
    below &= np.isin(lattice_columns(pos, dp, origin, dim), columns)
    walls = np.flatnonzero(own | below)
    p = pos[walls]
    g, fitted, columns = fit_walls(solid.shape, p, dp, origin, dim)
    pos[walls] = p
    if ghosts is not None:
        ghosts[walls[fitted]] = g[fitted]
    fluid = np.flatnonzero(kinds == FLUID)
    q = pos[fluid]
    fit_fluid(solid.shape, q, dp, origin, dim, columns)
    pos[fluid] = q


def _generate_on(dim, step, lo, hi, origin, solids, fluids, support_ratio, thick, fine, normals=False,
                 normals_box=None):
    """(positions, kinds, velocities, body, region, ghost vectors or None) of one lattice."""
    from scipy.ndimage import distance_transform_cdt, distance_transform_edt

    axes = [0, 2] if dim == 2 else [0, 1, 2]
    ranges = [_axis_range(lo[a], hi[a], origin[a], step) for a in axes]
    shape = [max(0, r[1] - r[0]) for r in ranges]
    if 0 in shape:
        raise InputError(f"the domain {lo.tolist()} - {hi.tolist()} m is thinner than one particle spacing "
                         f"({step:g} m) along some axis")
    halo = int(math.ceil(max(thick, default=1.0))) + 1
    per_x = int(np.prod(shape[1:]))
    nx_slab = max(1, _SLAB_NODES // max(per_x, 1))
    # wall-generation pad for shells (tanks): the thickness of their layers
    pads = [t * step if not fine else step for t in thick]
    dynamic = np.array([s.method != "repulsive" for s in solids], bool)
    ghost_vectors = None
    if normals and not fine:
        from .normals import WallNormals

        limits, end = None, (lo, hi)
        if normals_box is not None:
            inner = [_nudged_range(normals_box[0][a], normals_box[1][a], origin[a], step, _NUDGE[a]) for a in axes]
            limits = (np.array([max(i0 - r[0], 0) for (i0, _), r in zip(inner, ranges)]),
                      np.array([min(i1 - r[0], n) for (_, i1), r, n in zip(inner, ranges, shape)]))
            if np.all(limits[1] > limits[0]):
                end = (np.maximum(lo, normals_box[0]), np.minimum(hi, normals_box[1]))
            else:  # holds no node: the generation box is the end
                limits = None
        coords = [origin[a] + (np.arange(r[0], r[1]) + 0.5) * step for a, r in zip(axes, ranges)]
        ghost_vectors = WallNormals(dim, step, solids, pads, support_ratio, _NUDGE, coords, limits, box=end)
        halo = max(halo, ghost_vectors.halo)  # the normals' stencil needs real neighbours across slab cuts

    def slab(xs):
        """Walls and fluid of the slab of lattice columns [xs, xs + nx_slab), with a halo."""
        reached("generate")  # a test hook (shoal.faults)
        out_pos, out_kind, out_vel, out_body, out_region, out_ghost = [], [], [], [], [], []
        xe = min(shape[0], xs + nx_slab)
        gs, ge = max(0, xs - halo), min(shape[0], xe + halo)
        idx = [np.arange(ranges[0][0] + gs, ranges[0][0] + ge)] + [np.arange(r[0], r[1]) for r in ranges[1:]]
        coords = [origin[a] + (i + 0.5) * step for a, i in zip(axes, idx)]
        grids = np.meshgrid(*coords, indexing="ij")
        local_shape = grids[0].shape
        pts = np.zeros((grids[0].size, 3))
        for a, g in zip(axes, grids):
            pts[:, a] = g.ravel()
        probe = pts + _NUDGE * step
        owner = np.full(len(pts), -1, np.int32)
        for k, s in enumerate(solids):
            free = owner < 0
            if not free.any():
                break
            m = np.zeros(len(pts), bool)
            m[free] = s.shape.contains(probe[free], dim, pads[k])
            owner[m] = k
        solid = (owner >= 0).reshape(local_shape)
        core = slice(xs - gs, xe - gs)
        keep = np.zeros(local_shape, bool)
        if solid.any():
            # beyond the generation box counts as solid (no walls on the domain faces),
            # except across the slab cuts, where the halo supplies the neighbours
            pad_width = [(1 if gs == 0 else 0, 1 if ge == shape[0] else 0)] + [(1, 1)] * (len(axes) - 1)
            padded = np.pad(solid, pad_width, constant_values=True)
            inner = tuple(slice(p0, p0 + n) for (p0, _), n in zip(pad_width, local_shape))
            inner1 = tuple(slice(1, 1 + n) for n in local_shape)
            own = owner.reshape(local_shape)
            # the distance transforms are the slowest step: each is computed only if a solid needs it
            d_e = d_c = None
            if fine:
                for k, s in enumerate(solids):
                    if s.method == "repulsive":
                        if d_e is None:
                            d_e = distance_transform_edt(padded)[inner]
                        keep |= (own == k) & (d_e <= 1.0 + 1e-6)
            else:
                for k, s in enumerate(solids):
                    if not dynamic[k]:
                        continue
                    if getattr(s.shape, "shell", False):
                        keep |= own == k  # a shell (tank) is exactly as thick as its layers: all of it
                    elif s.whole:
                        # distances to its own outside (other solids count as outside); across the slab
                        # cuts the halo, at least as deep as the layers, holds its true neighbours
                        mine = own == k
                        if s.layers is None:
                            keep |= mine & (distance_transform_edt(np.pad(mine, 1))[inner1] < support_ratio - 1e-6)
                        else:
                            keep |= mine & (distance_transform_cdt(np.pad(mine, 1), metric="chessboard")[inner1]
                                            <= s.layers)
                    elif s.layers is None:
                        if d_e is None:
                            d_e = distance_transform_edt(padded)[inner]
                        keep |= (own == k) & (d_e < support_ratio - 1e-6)
                    else:
                        # `layers` lattice layers: the nodes within that many steps of the outside,
                        # diagonal steps included (chessboard distance). The Euclidean distance is never
                        # below the chessboard one, so the nodes within `layers` of it are among these.
                        if d_c is None:
                            d_c = distance_transform_cdt(padded, metric="chessboard")[inner]
                        keep |= (own == k) & (d_c <= s.layers)
        keep_c = keep[core].ravel()
        owner_c = owner.reshape(local_shape)[core].ravel()
        pts_c = pts.reshape(*local_shape, 3)[core].reshape(-1, 3)
        probe_c = probe.reshape(*local_shape, 3)[core].reshape(-1, 3)
        wall_idx = np.flatnonzero(keep_c)
        if len(wall_idx):
            b = owner_c[wall_idx]
            moving = np.array([s.moving for s in solids], bool)[b]
            out_pos.append(pts_c[wall_idx])
            out_kind.append(np.where(moving, MOVING, FIXED).astype(np.int8))
            out_vel.append(np.zeros((len(wall_idx), 3)))
            out_body.append(b.astype(np.int16))
            out_region.append(np.full(len(wall_idx), -1, np.int16))
            if ghost_vectors is not None:
                out_ghost.append(ghost_vectors(owner.reshape(local_shape), core, wall_idx, pts_c[wall_idx], x0=gs))
        if fluids:
            region = np.full(len(pts_c), -1, np.int32)
            for k, f in enumerate(fluids):
                free = (owner_c < 0) & (region < 0)
                if not free.any():
                    break
                m = np.zeros(len(pts_c), bool)
                m[free] = f.shape.contains(probe_c[free], dim, 0.0)
                region[m] = k
            fidx = np.flatnonzero(region >= 0)
            if len(fidx):
                vels = np.asarray([f.velocity for f in fluids], float)
                out_pos.append(pts_c[fidx])
                out_kind.append(np.full(len(fidx), FLUID, np.int8))
                out_vel.append(vels[region[fidx]])
                out_body.append(np.full(len(fidx), -1, np.int16))
                out_region.append(region[fidx].astype(np.int16))
                if ghost_vectors is not None:
                    out_ghost.append(np.zeros((len(fidx), 3)))
        return out_pos, out_kind, out_vel, out_body, out_region, out_ghost

    starts = range(0, shape[0], nx_slab)
    workers = _slab_workers(len(starts))
    if workers > 1:
        # NumPy and the distance transforms release the GIL on large arrays; map keeps the slab order
        from concurrent.futures import ThreadPoolExecutor

        with ThreadPoolExecutor(workers) as pool:
            slabs = list(pool.map(slab, starts))
    else:
        slabs = [slab(xs) for xs in starts]
    out_pos, out_kind, out_vel, out_body, out_region, out_ghost = (
        [x for sl in slabs for x in sl[k]] for k in range(6))
    empty_ghosts = np.zeros((0, 3)) if ghost_vectors is not None else None
    if not out_pos:
        return (np.zeros((0, 3)), np.zeros(0, np.int8), np.zeros((0, 3)), np.zeros(0, np.int16),
                np.zeros(0, np.int16), empty_ghosts)
    return (np.concatenate(out_pos), np.concatenate(out_kind), np.concatenate(out_vel),
            np.concatenate(out_body), np.concatenate(out_region),
            np.concatenate(out_ghost) if ghost_vectors is not None else None)
