"""The free surface as a mesh: DualSPHysics's IsoSurface for shoal's snapshots.

The SPH kernel sum S(x) = sum_j (m_j / rho_j) W(x - x_j) of the fluid particles (the colour
function: 1 inside the water, 1/2 at a free surface, 0 in air; the same field as the wave gauges'
threshold) is sampled on a uniform grid with the run's kernels (`Model.sample`, on the CPU or the
CUDA backend), and its level set S = `level` (1/2) is extracted: by marching cubes in 3D (Lorensen
& Cline 1987, scikit-image's `measure.marching_cubes`, Lewiner et al. 2003) as a triangle mesh, by
marching squares in 2D (`measure.find_contours`) as line segments in the x-z plane. The meshes are
written as VTK unstructured grids (``.vtu``, meshio) with a ``.pvd`` time series, for ParaView.

Near a wall the kernel sum also drops (the wall particles are not in the sum), so the surface
closes along the walls half a spacing inside them: the mesh is the boundary of the water body,
free surface and wetted walls alike, as DualSPHysics's IsoSurface draws it.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..errors import InputError
from ..physics.spec import FLUID

CHUNK = 1_000_000
"""Grid nodes sampled per call (bounds the temporary arrays of `Model.sample`)."""


def kernel_sum_grid(model, lo, hi, spacing):
    """The plain kernel sum of the fluid on a uniform grid.

    Parameters
    ----------
    model : Model
        Sorted particles (any backend).
    lo, hi : sequence of 3 float
        Corners of the grid [m] (world coordinates; y is ignored in 2D).
    spacing : float
        Node spacing [m].

    Returns
    -------
    axes : list of ndarray
        The node coordinates along x, y, z (3D) or x, z (2D).
    values : ndarray
        S at the nodes, shape (nx, ny, nz) in 3D, (nx, nz) in 2D.
    """
    dims = (0, 1, 2) if model.dim == 3 else (0, 2)
    axes = [lo[k] + spacing * np.arange(int(np.floor((hi[k] - lo[k]) / spacing)) + 2) for k in dims]
    shape = tuple(len(a) for a in axes)
    mesh = np.meshgrid(*axes, indexing="ij")
    pts = np.zeros((int(np.prod(shape)), 3))
    for c, k in enumerate(dims):
        pts[:, k] = mesh[c].ravel()
    values = np.empty(len(pts))
    for a in range(0, len(pts), CHUNK):
        values[a:a + CHUNK] = model.sample(pts[a:a + CHUNK], shepard=False)["kernel_sum"]
    return axes, values.reshape(shape)


def surface_mesh(model, spacing=None, level=0.5):
    """The iso-surface S = `level` of the fluid's kernel sum.

    Parameters
    ----------
    model : Model
        Sorted particles (any backend).
    spacing : float, optional
        Grid spacing [m] (default dp / 2).
    level : float
        The kernel-sum level (0 < level < 1; 1/2: the free surface).

    Returns
    -------
    points : ndarray, shape (P, 3)
        Vertices [m] (y = 0 in 2D).
    cells : tuple
        ("triangle", (T, 3) int array) in 3D, ("line", (L, 2) int array) in 2D.
    """
    if not 0.0 < level < 1.0:
        raise InputError(f"level = {level:g}; allowed 0 < level < 1 (the kernel sum is 1 in water, 0 in air)")
    spacing = 0.5 * model.dp if spacing is None else float(spacing)
    if not spacing > 0.0:
        raise InputError(f"spacing = {spacing:g} m; allowed > 0")
    from skimage import measure

    pos, kinds, _ = model.owned_particles()
    fluid = pos[kinds == FLUID]
    if not len(fluid):
        return np.zeros((0, 3)), ("triangle" if model.dim == 3 else "line", np.zeros((0, 3 if model.dim == 3 else 2),
                                                                                     np.int64))
    pad = 2.0 * model.h + spacing  # S is 0 beyond the kernel support: the grid's edges lie in air
    lo, hi = fluid.min(axis=0) - pad, fluid.max(axis=0) + pad
    n_nodes = np.prod([(hi[k] - lo[k]) / spacing + 2 for k in ((0, 1, 2) if model.dim == 3 else (0, 2))])
    if n_nodes > 2e9:
        raise InputError(f"an iso-surface grid of {n_nodes:.3g} nodes at spacing {spacing:g} m; give a larger "
                         "spacing")
    axes, S = kernel_sum_grid(model, lo, hi, spacing)
    origin = np.array([a[0] for a in axes])
    if model.dim == 3:
        verts, faces, _, _ = measure.marching_cubes(S, level=level, spacing=(spacing,) * 3)
        # scikit-image winds the triangles with their normals into the water: reversed, they point out
        return verts + origin, ("triangle", faces[:, ::-1].astype(np.int64))
    points, segments = [], []
    n = 0
    for c in measure.find_contours(S, level):  # (k, 2) in (ix, iz) index coordinates
        xz = origin + spacing * c[::-1]  # anticlockwise round the water in the x-z plane
        points.append(np.column_stack([xz[:, 0], np.zeros(len(xz)), xz[:, 1]]))
        segments.append(np.column_stack([np.arange(n, n + len(xz) - 1), np.arange(n + 1, n + len(xz))]))
        n += len(xz)
    if not points:
        return np.zeros((0, 3)), ("line", np.zeros((0, 2), np.int64))
    return np.concatenate(points), ("line", np.concatenate(segments))


def enclosed_volume(points, cells, dim):
    """Volume [m^3] enclosed by a closed triangle mesh (3D: sum of the signed tetrahedra from the
    origin, the divergence theorem), or area [m^2] enclosed by closed polylines in the x-z plane (2D:
    the shoelace sum over the segments); the sign follows the orientation."""
    kind, conn = cells
    p = np.asarray(points, float)
    if dim == 3:
        a, b, c = p[conn[:, 0]], p[conn[:, 1]], p[conn[:, 2]]
        return float(np.einsum("ij,ij->i", a, np.cross(b, c)).sum() / 6.0)
    a, b = p[conn[:, 0]], p[conn[:, 1]]
    return float(0.5 * np.sum(a[:, 0] * b[:, 2] - b[:, 0] * a[:, 2]))


def write_isosurfaces(run_dir, out=None, spacing=None, level=0.5, backend="cpu"):
    """The iso-surface of every snapshot of a finished run, as ``<case>_surface_NNNN.vtu`` files and a
    ``<case>_surface.pvd`` collection in `out` (default ``run_dir / "post" / "isosurface"``).

    Returns
    -------
    list of pathlib.Path
        The .pvd file, then the .vtu files.
    """
    import meshio

    from ..output.pvd import PVDWriter
    from ..probes.offline import load_run, model_from_snapshot

    run_dir = Path(run_dir)
    case, entries = load_run(run_dir)
    if spacing is not None and not spacing > 0.0:
        raise InputError(f"--iso-spacing = {spacing:g} m; allowed > 0")
    if not 0.0 < level < 1.0:
        raise InputError(f"--iso-level = {level:g}; allowed 0 < level < 1 (the kernel sum is 1 in water, 0 in air)")
    out = Path(out) if out is not None else run_dir / "post" / "isosurface"
    name = f"{case.name}_surface"
    pvd = None  # made once the first mesh exists: a request refused there writes nothing
    written = []
    for k, (time, snap) in enumerate(entries):
        model = model_from_snapshot(case, run_dir / snap, backend)
        points, cells = surface_mesh(model, spacing, level)
        if pvd is None:
            out.mkdir(parents=True, exist_ok=True)
            pvd = PVDWriter(out, name)
        path = out / f"{name}_{k:04d}.vtu"
        meshio.write(path, meshio.Mesh(points, [cells]), file_format="vtu")
        pvd.add(float(time), path.name)
        written.append(path)
    if pvd is None:
        raise InputError(f"{run_dir} holds no snapshot to mesh")
    return [pvd.path, *written]
