"""Solids given as triangle meshes (STL files) in shoal's case geometry.

A case can describe a fluid region, a wall or a body by a closed triangle
mesh read from an STL file instead of a box. Particles of the Cartesian
lattice (`shoal.geometry.lattice`) are then kept or dropped by whether they
lie inside that solid: this module reads the mesh (`load_stl`) and answers
the inside/outside question for many points at once (`points_inside`),
through the generalized winding number (`winding_number`), which is robust
to the small gaps, overlaps and slivers that exported meshes often have.

Triangles are (M, 3, 3) float64 arrays: ``triangles[k, j]`` is vertex ``j``
(x, y, z) of triangle ``k``, in world coordinates [m]. A mesh is "outward
oriented" when the normal ``(v1 - v0) x (v2 - v0)`` of each triangle points
out of the solid (the STL convention, counter-clockwise seen from outside).

References
----------
.. [1] A. Jacobson, L. Kavan, O. Sorkine-Hornung, "Robust inside-outside
   segmentation using generalized winding numbers", ACM Transactions on
   Graphics 32(4), 33 (SIGGRAPH 2013).
.. [2] A. Van Oosterom, J. Strackee, "The solid angle of a plane triangle",
   IEEE Transactions on Biomedical Engineering BME-30(2), 125-126 (1983).
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from ..errors import InputError

__all__ = ["load_stl", "winding_number", "points_inside", "mesh_bounds"]

# Number of (point, triangle) pairs evaluated at once. The kernel keeps about
# 15 float64 arrays of this many elements alive, so a block costs ~120 MB.
_PAIR_BUDGET = 1_000_000


def _one_line(text):
    return " ".join(str(text).split())


def load_stl(path, scale=1.0, offset=(0.0, 0.0, 0.0)):
    """Read the triangles of an STL file (ASCII or binary).

    Parameters
    ----------
    path : str or os.PathLike
        The STL file.
    scale : float, optional
        Factor applied to every vertex (e.g. 0.001 for a file in mm),
        a positive finite number.
    offset : sequence of 3 floats, optional
        Shift [m] added to every vertex after scaling:
        ``x_world = scale * x_file + offset``.

    Returns
    -------
    triangles : ndarray, shape (M, 3, 3), float64
        ``triangles[k, j]`` is vertex ``j`` of triangle ``k``. The vertex
        order (hence the orientation) of the file is kept; the normals
        stored in the file are ignored.

    Raises
    ------
    shoal.errors.InputError
        With a one-line message naming the file: file missing, not a file,
        not readable as STL, no triangles, non-finite vertices, an open
        or flat mesh (`_check_closed`), `scale` not a positive finite
        number, `offset` not 3 finite numbers.
    """
    name = os.fspath(path)
    where = f"STL file '{name}'"
    try:
        s = float(scale)
    except (TypeError, ValueError):
        s = float("nan")
    if not (np.isfinite(s) and s > 0.0):
        raise InputError(f"{where}: scale = {scale!r}; use a positive finite number")
    try:
        off = np.asarray(offset, dtype=np.float64).reshape(3)
    except (TypeError, ValueError):
        raise InputError(
            f"{where}: offset = {offset!r}; use 3 finite numbers (x, y, z)"
        ) from None
    if not np.all(np.isfinite(off)):
        raise InputError(f"{where}: offset = {offset!r}; use 3 finite numbers (x, y, z)")

    p = Path(name)
    if not p.exists():
        raise InputError(f"{where} not found")
    if not p.is_file():
        raise InputError(f"{where} is not a file")
    try:
        size = p.stat().st_size
        with open(p, "rb") as fh:
            head = fh.read(84)
    except OSError as exc:
        raise InputError(f"{where} cannot be read: {_one_line(exc.strerror or exc)}") from None
    is_ascii_header = head.lstrip().lower().startswith(b"solid")
    if not is_ascii_header and size < 84:
        raise InputError(
            f"{where} is not an STL file ({size} bytes: too short for a binary "
            "STL and no ASCII 'solid' header)"
        )
    count = int.from_bytes(head[80:84], "little") if len(head) == 84 else 0
    if not is_ascii_header and size < 84 + 50 * count:  # numpy-stl would read the triangles that are there
        raise InputError(f"{where} is truncated: its binary header announces {count:,} triangles "
                         f"({84 + 50 * count:,} bytes) but the file has {size:,} bytes")

    from stl import mesh as stl_mesh

    try:
        m = stl_mesh.Mesh.from_file(str(p))
    except Exception as exc:  # numpy-stl raises assorted types on bad input
        raise InputError(
            f"{where} could not be read as ASCII or binary STL "
            f"({type(exc).__name__}: {_one_line(exc)})"
        ) from None
    tri = np.array(m.vectors, dtype=np.float64).reshape(-1, 3, 3)
    if tri.shape[0] == 0:
        raise InputError(f"{where} contains no triangles")
    bad = ~np.all(np.isfinite(tri), axis=(1, 2))
    if bad.any():
        k = int(np.flatnonzero(bad)[0])
        raise InputError(
            f"{where} has non-finite vertex coordinates in {int(bad.sum())} "
            f"triangle(s), the first is triangle {k}"
        )
    tri *= s
    tri += off
    _check_closed(tri, where)
    return tri


OPEN_RIM_FRACTION = 0.01
"""Largest share of a mesh's edge length that may lie on holes (edges of one triangle only): the
winding number classifies points correctly away from small holes (Jacobson et al. 2013), not
inside an open surface."""


def _check_closed(tri, where):
    """`InputError` for a mesh that bounds no solid: one with holes whose rims make more than
    `OPEN_RIM_FRACTION` of its edge length (a sheet, a surface with missing faces), or one that
    encloses no volume (flat, or every triangle degenerate). Vertices are matched within 1e-9 of
    the mesh's size, which joins the copies of a vertex that STL stores once per triangle."""
    size = float(np.ptp(tri.reshape(-1, 3), axis=0).max())
    if not size > 0.0:
        raise InputError(f"{where}: every vertex is at one point; the mesh bounds no solid")
    keys = np.round(tri.reshape(-1, 3) / (1e-9 * size)).astype(np.int64)
    _, vid = np.unique(keys, axis=0, return_inverse=True)
    vid = vid.reshape(-1, 3)
    edges = np.sort(np.concatenate([vid[:, [0, 1]], vid[:, [1, 2]], vid[:, [2, 0]]]), axis=1)
    lengths = np.linalg.norm(np.concatenate([tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 1], tri[:, 0] - tri[:, 2]]),
                             axis=1)
    _, inverse, counts = np.unique(edges, axis=0, return_inverse=True, return_counts=True)
    rim = counts[inverse.ravel()] == 1
    if lengths[rim].sum() > OPEN_RIM_FRACTION * lengths.sum():
        raise InputError(f"{where} is open: {int(rim.sum()):,} edges belong to one triangle only (holes with rims "
                         f"of {lengths[rim].sum():.3g} m in all, {100 * lengths[rim].sum() / lengths.sum():.0f} % "
                         "of its edges), so its inside is undefined; close the surface (fill its holes) and "
                         "export it again")
    volume = abs(float(np.einsum("ij,ij->i", tri[:, 0], np.cross(tri[:, 1], tri[:, 2])).sum())) / 6.0
    if not volume > 1e-9 * size**3:
        raise InputError(f"{where} encloses no volume ({volume:.3g} m^3 inside a mesh {size:.3g} m across): it is flat "
                         "or its triangles are degenerate; a solid or fluid needs a closed surface around a volume")


def _as_triangles(triangles):
    tri = np.asarray(triangles, dtype=np.float64)
    if tri.ndim != 3 or tri.shape[1:] != (3, 3) or tri.shape[0] == 0:
        raise InputError(
            f"triangles of shape {tri.shape}; expected (M, 3, 3) with M >= 1"
        )
    return tri


def _as_points(points):
    pts = np.asarray(points, dtype=np.float64)
    if pts.ndim == 1 and pts.shape == (3,):
        pts = pts[None, :]
    if pts.ndim != 2 or pts.shape[1] != 3:
        raise InputError(f"points of shape {pts.shape}; expected (N, 3)")
    return pts


def _solid_angle_sum(tri_c, pts):
    """Sum over the triangles of the solid angle (Van Oosterom & Strackee).

    `tri_c` is a tuple of 9 (m,) arrays (v0x, v0y, v0z, v1x, ..., v2z) and
    `pts` an (n, 3) array; returns (n,) sums of Omega in steradians.
    """
    px = pts[:, 0:1]
    py = pts[:, 1:2]
    pz = pts[:, 2:3]
    v0x, v0y, v0z, v1x, v1y, v1z, v2x, v2y, v2z = tri_c
    ax = v0x - px
    ay = v0y - py
    az = v0z - pz
    bx = v1x - px
    by = v1y - py
    bz = v1z - pz
    cx = v2x - px
    cy = v2y - py
    cz = v2z - pz
    # |a|, |b|, |c|
    la = np.sqrt(ax * ax + ay * ay + az * az)
    lb = np.sqrt(bx * bx + by * by + bz * bz)
    lc = np.sqrt(cx * cx + cy * cy + cz * cz)
    # numerator a . (b x c)
    num = ax * (by * cz - bz * cy)
    num += ay * (bz * cx - bx * cz)
    num += az * (bx * cy - by * cx)
    # denominator |a||b||c| + (a.b)|c| + (b.c)|a| + (c.a)|b|
    den = la * lb * lc
    den += (ax * bx + ay * by + az * bz) * lc
    den += (bx * cx + by * cy + bz * cz) * la
    den += (cx * ax + cy * ay + cz * az) * lb
    del ax, ay, az, bx, by, bz, cx, cy, cz, la, lb, lc
    omega = np.arctan2(num, den, out=num)
    return 2.0 * omega.sum(axis=1)


def winding_number(triangles, points, chunk=None):
    r"""Generalized winding number of points with respect to a triangle mesh.

    For a closed, outward-oriented mesh the winding number is 1 at points
    inside the solid and 0 outside (-1 inside for an inward-oriented mesh,
    n inside a region enclosed n times). For a mesh with small holes it
    varies smoothly and stays close to those values away from the holes,
    which is what makes the inside test robust [1]_.

    Following Jacobson et al. [1]_,

    .. math:: w(p) = \frac{1}{4\pi} \sum_k \Omega_k(p),

    where :math:`\Omega_k(p)` is the signed solid angle under which triangle
    k is seen from p, given by Van Oosterom & Strackee [2]_ with
    :math:`a, b, c` the triangle's vertices minus p:

    .. math:: \tan\frac{\Omega}{2} = \frac{a \cdot (b \times c)}
        {|a||b||c| + (a \cdot b)|c| + (b \cdot c)|a| + (c \cdot a)|b|},

    evaluated as :math:`\Omega = 2\,\mathrm{atan2}(\mathrm{num}, \mathrm{den})`
    so that the branch is right for all :math:`|\Omega| \le 2\pi`. Points on
    the surface get an ill-defined value (about 1/2 on a face); a point at a
    vertex gets no contribution from the triangles sharing it.

    Parameters
    ----------
    triangles : array_like, shape (M, 3, 3)
        Vertex ``j`` of triangle ``k`` is ``triangles[k, j]``.
    points : array_like, shape (N, 3)
        Query points.
    chunk : int, optional
        Points evaluated together. Default ``max(1, 1_000_000 // M)``, which
        keeps the temporary arrays to about 120 MB whatever N and M. With
        more than ``1_000_000 // chunk`` triangles the triangles are also
        taken in blocks. The result does not depend on `chunk` beyond
        rounding.

    Returns
    -------
    w : ndarray, shape (N,), float64

    References
    ----------
    .. [1] A. Jacobson, L. Kavan, O. Sorkine-Hornung, "Robust inside-outside
       segmentation using generalized winding numbers", ACM Trans. Graph.
       32(4), 33 (2013).
    .. [2] A. Van Oosterom, J. Strackee, "The solid angle of a plane
       triangle", IEEE Trans. Biomed. Eng. BME-30(2), 125-126 (1983).
    """
    tri = _as_triangles(triangles)
    pts = _as_points(points)
    m = tri.shape[0]
    n = pts.shape[0]
    if chunk is None:
        chunk = max(1, _PAIR_BUDGET // m)
    else:
        chunk = int(chunk)
        if chunk < 1:
            raise InputError(f"chunk = {chunk}; use an integer >= 1")
    tblock = max(1, _PAIR_BUDGET // chunk)
    # Component arrays (m,), contiguous, broadcast against (n, 1) point columns.
    comps = tuple(np.ascontiguousarray(tri[:, j, d]) for j in range(3) for d in range(3))
    total = np.zeros(n, dtype=np.float64)
    for i0 in range(0, n, chunk):
        p = pts[i0:i0 + chunk]
        acc = total[i0:i0 + chunk]
        for t0 in range(0, m, tblock):
            acc += _solid_angle_sum(tuple(c[t0:t0 + tblock] for c in comps), p)
    total /= 4.0 * np.pi
    return total


def points_inside(triangles, points, chunk=None):
    """Whether each point lies inside the solid bounded by a triangle mesh.

    A point is inside when ``abs(winding_number) > 0.5``. The absolute value
    makes the test work for either orientation of a consistently oriented
    mesh: outward normals give +1 inside, inward normals -1; both give 0
    outside. Meshes with a few small holes still classify points away from
    the holes correctly. Triangles oriented inconsistently *within* one
    mesh are not repaired (their contributions partly cancel). Points on
    the surface itself may fall either way.

    Parameters
    ----------
    triangles : array_like, shape (M, 3, 3)
    points : array_like, shape (N, 3)
    chunk : int, optional
        Passed to `winding_number`.

    Returns
    -------
    inside : ndarray, shape (N,), bool
    """
    return np.abs(winding_number(triangles, points, chunk=chunk)) > 0.5


def mesh_bounds(triangles):
    """Axis-aligned bounding box of a triangle mesh.

    Parameters
    ----------
    triangles : array_like, shape (M, 3, 3)

    Returns
    -------
    lo, hi : ndarray, shape (3,), float64
        Smallest and largest vertex coordinates along x, y, z.
    """
    v = _as_triangles(triangles).reshape(-1, 3)
    return v.min(axis=0), v.max(axis=0)
