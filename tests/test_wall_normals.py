"""Ghost vectors of the dynamic wall particles (mDBC, `shoal.geometry.normals`): each
wall particle's mirror image across the wall surface, checked against the exact geometry."""

import math

import numpy as np
import pytest

from shoal.geometry.generate import FIXED, FLUID, MOVING, FluidInput, SolidInput, generate
from shoal.geometry.normals import exit_distance, lattice_normals, stencil
from shoal.geometry.shapes import Box, Mesh, Slope, Tank

DP = 0.1
EXACT = 1e-6 * DP  # the bisection locates a surface to 2.4e-7 dp, the classification nudge is 1e-7 dp
R2, R3 = 2 * math.sqrt(2), 2 * math.sqrt(3)  # 2h/dp with coef_h = 1 (h = coef_h sqrt(dim) dp)


def unit(v):
    v = np.asarray(v, float)
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


def walls(p, body=None):
    m = (p.kinds != FLUID) if body is None else (p.body == body)
    return p.positions[m], p.normals[m]


# ------------------------------------------------------------------ flat bed

@pytest.mark.parametrize("dim", [2, 3])
def test_flat_bed_mirrors_vertically_across_its_top_face(dim):
    """A Box bed under the fluid, its top face between lattice rows, its other faces beyond the
    generation box (continued there): every wall particle's ghost node is its mirror image
    2 z_s - z_p straight above."""
    zs = 0.0337
    W = 0.6 if dim == 3 else 0.0
    box = ((0.0, 0.0, -0.6), (1.2, W, 0.5))
    bed = Box(lo=(-5, -5, -5), hi=(5, 5, zs))
    p = generate(dim, DP, box, [SolidInput(bed)], [FluidInput(Box(lo=(-5, -5, zs), hi=(5, 5, 0.3)))],
                 R2 if dim == 2 else R3, normals=True)
    x, g = walls(p)
    assert len(x) == (12 * (6 if dim == 3 else 1)) * (2 if dim == 2 else 3)  # 2 (2D) or 3 (3D) layers
    assert np.all(g[:, :2] == 0.0)  # integer lattice sums: exactly vertical
    np.testing.assert_allclose(x[:, 2] + g[:, 2], 2 * zs - x[:, 2], rtol=0, atol=EXACT)
    # fluid particles carry none
    assert np.all(p.normals[p.kinds == FLUID] == 0.0)
    assert p.normals.shape == (len(p), 3) and p.normals.dtype == np.float64


# ---------------------------------------------------------------------- tank

def tank_2d():
    lo, hi = np.array([0.013, 0.0, 0.021]), np.array([1.013, 0.0, 0.821])
    tank = Tank(lo=tuple(lo), hi=tuple(hi))
    p = generate(2, DP, ((-0.5, 0, -0.5), (1.5, 0, 1.3)), [SolidInput(tank)],
                 [FluidInput(Box(lo=tuple(lo), hi=(hi[0], 0, 0.4)))], R2, normals=True)
    return p, lo, hi


def test_tank_walls_mirror_across_the_inner_faces():
    """Floor and side walls, both layers (the outer one too: the space behind a tank's walls counts
    as solid for the normals), mirror across the tank's inner faces, exactly, away from the corners."""
    p, lo, hi = tank_2d()
    x, g = walls(p)
    reach = R2 * DP
    floor = (x[:, 2] < lo[2]) & (x[:, 0] > lo[0] + reach) & (x[:, 0] < hi[0] - reach)
    left = (x[:, 0] < lo[0]) & (x[:, 2] > lo[2] + reach)
    right = (x[:, 0] > hi[0]) & (x[:, 2] > lo[2] + reach)
    assert np.count_nonzero(floor) == 2 * 4 and np.count_nonzero(left) == np.count_nonzero(right) == 2 * 5
    for m, axis, face in ((floor, 2, lo[2]), (left, 0, lo[0]), (right, 0, hi[0])):
        other = 2 - axis
        np.testing.assert_allclose(x[m, axis] + g[m, axis], 2 * face - x[m, axis], rtol=0, atol=EXACT)
        assert np.all(g[m, other] == 0.0) and np.all(g[m, 1] == 0.0)
    # the side walls' top rows too (the wall is continued above its open top, not rounded off)
    rim = (x[:, 2] > hi[2] - DP) & (x[:, 0] < lo[0])
    assert np.count_nonzero(rim) == 2 and np.all(g[rim, 2] == 0.0)


def test_tank_corner_normal_is_diagonal_and_ghosts_lie_inside():
    p, lo, hi = tank_2d()
    x, g = walls(p)
    # the innermost corner particles: diagonal normals into the tank; the ray leaves the solid where
    # it crosses the second of the two inner faces
    for corner in ((lo[0], lo[2]), (hi[0], lo[2])):
        out = np.sign(corner[0] - 0.5 * (lo[0] + hi[0]))  # -1 left, +1 right
        c = np.flatnonzero((np.abs(x[:, 0] - corner[0]) < DP) & (out * (x[:, 0] - corner[0]) > 0)
                           & (x[:, 2] < lo[2]) & (x[:, 2] > lo[2] - DP))
        assert len(c) == 1
        xc, n = x[c[0]], unit(g[c[0]])
        assert -out * n[0] > 0.5 and n[2] > 0.5 and n[1] == 0.0
        d = max((corner[0] - xc[0]) / n[0], (lo[2] - xc[2]) / n[2])
        np.testing.assert_allclose(g[c[0]], 2 * d * n, rtol=0, atol=EXACT)
    # every ghost node lies inside the tank (on the fluid side); a zero ghost only where no
    # non-solid node is within the kernel support (the outermost corner particles)
    has = np.any(g != 0, axis=1)
    gx = x[has] + g[has]
    assert np.all((gx[:, 0] > lo[0]) & (gx[:, 0] < hi[0]) & (gx[:, 2] > lo[2]))
    deep = (x[:, 2] < lo[2] - DP) & ((x[:, 0] < lo[0] - DP) | (x[:, 0] > hi[0] + DP))
    np.testing.assert_array_equal(~has, deep)


# --------------------------------------------------------------------- slope

def test_slope_ghost_nodes_are_exact_mirror_images():
    """1:10 slope: the normal comes from the lattice staircase, the distance along it from the exact
    plane, so every ghost node is at the particle's distance from the plane, on the other side."""
    x0, z0, grad = 0.0, 0.0123, 0.1
    slope = Slope(x0=x0, z0=z0, gradient=grad)
    p = generate(2, DP, ((0.0, 0, -0.6), (4.0, 0, 1.0)), [SolidInput(slope)],
                 [FluidInput(Box(lo=(0, 0, -1), hi=(4, 0, 0.8)))], R2, normals=True)
    x, g = walls(p)
    nu = unit([-grad, 0.0, 1.0])  # the true normal, into the fluid

    def phi(q):  # signed distance to the slope plane, positive in the fluid
        return (q[:, 2] - z0 - grad * (q[:, 0] - x0)) / math.hypot(1.0, grad)

    assert np.all(np.any(g != 0, axis=1))
    # (a ray that left the generation box would meet the slope continued flat beyond it, by edge
    # replication: none does here)
    assert np.all(x[:, 0] + 0.5 * g[:, 0] > 0.0)
    np.testing.assert_allclose(phi(x + g), -phi(x), rtol=0, atol=EXACT)
    first = phi(x) > -DP
    assert np.count_nonzero(first) >= 40
    angle = np.degrees(np.arccos(np.clip(unit(g) @ nu, -1, 1)))
    # the lattice's steps tilt the normals: measured 12.7 deg at most in the first layer, 20.9 deg in
    # the deeper ones (which see fewer non-solid nodes inside the support)
    assert angle[first].max() < 15.0
    assert angle.max() < 25.0


# ---------------------------------------------------------------- mesh bed

def test_mesh_bed_ghosts_equal_those_of_the_same_box(tmp_path):
    """An STL box as the bed (no STL file ships with the tests: it is written here) gives the ghost
    vectors of the same Box bed, to the bisection's precision."""
    from stl import mesh as stl_mesh

    v = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1]], float)
    f = np.array([[0, 3, 1], [1, 3, 2], [0, 4, 7], [0, 7, 3], [4, 5, 6], [4, 6, 7], [5, 1, 2], [5, 2, 6],
                  [2, 3, 6], [3, 7, 6], [0, 1, 5], [0, 5, 4]])
    m = stl_mesh.Mesh(np.zeros(len(f), dtype=stl_mesh.Mesh.dtype))
    m.vectors[:] = v[f] * [2.0, 2.0, 1.0] + [-0.5, -0.5, -0.9663]  # top face at z = 0.0337
    m.save(str(tmp_path / "bed.stl"))
    box = ((0.0, 0.0, -0.4), (0.6, 0.4, 0.4))
    fl = [FluidInput(Box(lo=(-1, -1, 0.0337), hi=(1, 1, 0.2)))]
    a = generate(3, DP, box, [SolidInput(Mesh(file=str(tmp_path / "bed.stl")))], fl, R3, normals=True)
    b = generate(3, DP, box, [SolidInput(Box(lo=(-0.5, -0.5, -0.9663), hi=(1.5, 1.5, 0.0337)))], fl, R3,
                 normals=True)
    np.testing.assert_array_equal(a.positions, b.positions)
    np.testing.assert_allclose(a.normals, b.normals, rtol=0, atol=EXACT)
    x, g = walls(a)
    assert len(x) == 6 * 4 * 3
    np.testing.assert_allclose(x[:, 2] + g[:, 2], 2 * 0.0337 - x[:, 2], rtol=0, atol=EXACT)


# ------------------------------------------------------------ moving bodies

@pytest.mark.parametrize("dim", [2, 3])
def test_paddle_on_the_floor_points_along_its_stroke(dim):
    """A piston paddle (moving Box) standing on a tank's floor, between its side walls in 3D.
    Its normals come from its own body, continued through the fixed walls it slides on: its faces
    point along the stroke right down to the floor and out to the side walls (not tilted into
    them, nor up like a concave corner). The floor's normals ignore the paddle (it moves away and
    uncovers the floor): straight up, under the paddle too."""
    W = 1.0 if dim == 3 else 0.0
    a, b = 0.4, 0.8  # the paddle's back and front faces
    paddle = SolidInput(Box(lo=(a, 0, 0), hi=(b, W, 0.7)), moving=True, group="piston", name="paddle")
    tank = SolidInput(Tank(lo=(0, 0, 0), hi=(2.0, W, 0.9)), name="tank")
    p = generate(dim, DP, ((-0.4, -0.4, -0.4), (2.4, W + 0.4, 1.0)), [paddle, tank],
                 [FluidInput(Box(lo=(0, 0, 0), hi=(2.0, W, 0.5)))], R2 if dim == 2 else R3, normals=True)
    assert np.all(p.kinds[p.body == 0] == MOVING)
    x, g = walls(p, body=0)
    low = x[:, 2] < 0.7 - R3 * DP  # below the rows that see the paddle's top face
    x, g = x[low], g[low]
    assert np.all(g[:, 1:] == 0.0)
    front, back = x[:, 0] > 0.5 * (a + b), x[:, 0] < 0.5 * (a + b)
    np.testing.assert_allclose(x[front, 0] + g[front, 0], 2 * b - x[front, 0], rtol=0, atol=EXACT)
    np.testing.assert_allclose(x[back, 0] + g[back, 0], 2 * a - x[back, 0], rtol=0, atol=EXACT)
    assert np.any(front & (x[:, 2] < DP)) and np.all(g[front, 0] > 0) and np.all(g[back, 0] < 0)
    # the floor below and around the paddle
    xf, gf = walls(p, body=1)
    under = (xf[:, 2] < 0) & (xf[:, 0] > a - DP) & (xf[:, 0] < b + DP)
    if dim == 3:  # away from the concave corners with the side walls
        under &= (xf[:, 1] > R3 * DP) & (xf[:, 1] < W - R3 * DP)
    assert np.count_nonzero(under) > 0
    np.testing.assert_allclose(gf[under], np.c_[0 * xf[under, :2], -2 * xf[under, 2]], rtol=0, atol=EXACT)


def test_moving_groups_are_separate_from_each_other():
    """A moving box standing on a wider moving box: with its own motion its side faces are
    continued through the lower box and mirror straight across (a concave corner only where the
    two move together, as one body)."""
    lower = Box(lo=(0.2, 0, 0.0), hi=(1.4, 0, 0.5))
    upper = Box(lo=(0.6, 0, 0.5), hi=(1.0, 0, 1.5))
    fl = [FluidInput(Box(lo=(0, 0, 0), hi=(1.6, 0, 1.8)))]
    box = ((0, 0, 0), (1.6, 0, 1.8))
    for group, separate in (("b", True), ("a", False)):
        p = generate(2, DP, box, [SolidInput(lower, moving=True, group="a"),
                                  SolidInput(upper, moving=True, group=group)], fl, R2, normals=True)
        x, g = walls(p, body=1)
        side = x[:, 2] < 1.5 - R2 * DP  # all four columns, below the top face's reach
        assert np.count_nonzero(side) == 4 * 7
        face = np.where(x[side, 0] < 0.8, 0.6, 1.0)
        if separate:
            np.testing.assert_allclose(x[side, 0] + g[side, 0], 2 * face - x[side, 0], rtol=0, atol=EXACT)
            assert np.all(g[side, 2] == 0.0)
        else:  # the bottom row sees the lower box's top face beside it: tilted up
            bottom = side & (x[:, 2] < 0.6)
            assert np.all(g[bottom, 2] > 0.01)


# ---------------------------------------------------------------- other cases

def test_thin_plate_middle_layer_has_no_ghost():
    """A plate three layers thick with fluid on both sides: the middle layer's normal cancels (zero
    ghost vector); the outer layers mirror across their faces."""
    plate = Box(lo=(0.5, 0, 0.0), hi=(0.8, 0, 2.0))  # lattice columns 0.55, 0.65, 0.75
    p = generate(2, DP, ((0, 0, 0), (1.3, 0, 2.0)), [SolidInput(plate)],
                 [FluidInput(Box(lo=(0, 0, 0), hi=(1.3, 0, 2.0)))], R2, normals=True)
    x, g = walls(p)
    row = (x[:, 2] > 0.5) & (x[:, 2] < 1.5)
    mid = row & np.isclose(x[:, 0], 0.65)
    assert np.count_nonzero(mid) == 10 and np.all(g[mid] == 0.0)
    left, right = row & np.isclose(x[:, 0], 0.55), row & np.isclose(x[:, 0], 0.75)
    np.testing.assert_allclose(g[left, 0], -0.1, atol=EXACT)
    np.testing.assert_allclose(g[right, 0], 0.1, atol=EXACT)


def test_repulsive_particles_have_no_ghost():
    tank = Tank(lo=(0, 0, 0), hi=(1.0, 0, 0.6))
    bed = Box(lo=(0.3, 0, 0), hi=(0.7, 0, 0.2))
    p = generate(2, DP, ((-0.4, 0, -0.4), (1.4, 0, 0.9)), [SolidInput(bed), SolidInput(tank, method="repulsive")],
                 [FluidInput(Box(lo=(0, 0, 0), hi=(1, 0, 0.4)))], R2, normals=True)
    rep = p.body == 1
    assert np.all(p.spacing[rep] == DP / 2) and np.all(p.normals[rep] == 0.0)
    x, g = walls(p, body=0)
    top = (x[:, 0] > 0.45) & (x[:, 0] < 0.55)  # the bed's middle column: up, through its top face
    np.testing.assert_allclose(x[top, 2] + g[top, 2], 0.4 - x[top, 2], atol=EXACT)


def test_without_normals_the_output_is_unchanged():
    solids = [SolidInput(Box(lo=(0.4, 0, 0), hi=(0.8, 0, 0.7)), moving=True, group="p"),
              SolidInput(Slope(x0=1.0, z0=0.0, gradient=0.2)),
              SolidInput(Tank(lo=(0, 0, 0), hi=(2.0, 0, 0.9)), layers=3)]
    fluids = [FluidInput(Box(lo=(0, 0, 0), hi=(2.0, 0, 0.5)))]
    box = ((-0.4, 0, -0.4), (2.4, 0, 1.0))
    a = generate(2, DP, box, solids, fluids, R2)
    b = generate(2, DP, box, solids, fluids, R2, normals=False)
    c = generate(2, DP, box, solids, fluids, R2, normals=True)
    assert a.normals is None and b.normals is None
    for name in ("positions", "kinds", "velocities", "body", "region", "spacing"):
        np.testing.assert_array_equal(getattr(a, name), getattr(b, name))
        np.testing.assert_array_equal(getattr(a, name), getattr(c, name))
    assert c.normals.shape == (len(c), 3)
    assert np.all(c.normals[c.kinds == FLUID] == 0) and np.any(c.normals[c.kinds == FIXED] != 0)


def test_slab_cuts_and_threads_leave_the_ghosts_unchanged(monkeypatch):
    import sys

    W = 0.4
    solids = [SolidInput(Box(lo=(0.4, 0, 0), hi=(0.8, W, 0.6)), moving=True, group="p"),
              SolidInput(Slope(x0=1.0, z0=0.0, gradient=0.3)),
              SolidInput(Tank(lo=(0, 0, 0), hi=(2.0, W, 0.8)))]
    fluids = [FluidInput(Box(lo=(0, 0, 0), hi=(2.0, W, 0.4)))]
    box = ((-0.4, -0.4, -0.4), (2.4, W + 0.4, 0.9))
    whole = generate(3, DP, box, solids, fluids, R3, normals=True)
    gen = sys.modules["shoal.geometry.generate"]  # the package exports a function of the same name
    monkeypatch.setattr(gen, "_SLAB_NODES", 300)  # slabs of one to three x-columns
    for workers in (1, 3):
        monkeypatch.setattr(gen, "_slab_workers", lambda n, w=workers: min(n, w))
        cut = generate(3, DP, box, solids, fluids, R3, normals=True)
        np.testing.assert_array_equal(whole.positions, cut.positions)
        np.testing.assert_array_equal(whole.normals, cut.normals)


def test_case_asks_for_normals_with_mdbc():
    from shoal.case import Case, Fluid, FluidRegion, Solid
    from shoal.motions import ConstantVelocity
    from shoal.options import SPHOptions

    def case(wall_pressure):
        return Case(name="t", dim=2, dp=DP, fluid=Fluid(depth=0.4),
                    solids=[Solid(shape=Box(lo=(0.4, 0, 0), hi=(0.8, 0, 0.7)), motion="m"),
                            Solid(shape=Tank(lo=(0, 0, 0), hi=(2.0, 0, 0.9)))],
                    fluids=[FluidRegion(shape=Box(lo=(0, 0, 0), hi=(2.0, 0, 0.4)))],
                    motions=[ConstantVelocity(name="m", velocity=(0.1, 0, 0))],
                    options=SPHOptions(wall_pressure=wall_pressure))

    assert case("dynamic").particles().normals is None
    p = case("mdbc").particles()
    x, g = p.positions[p.body == 0], p.normals[p.body == 0]
    front = (x[:, 0] > 0.6) & (x[:, 2] < 0.7 - R2 * DP)
    np.testing.assert_allclose(x[front, 0] + g[front, 0], 1.6 - x[front, 0], atol=EXACT)


def test_case_walls_on_its_edge_mirror_across_their_wetted_faces():
    """Without an explicit domain a case generates in its shapes' box plus an empty ring; the ring is
    never wetted, so a flume's end wall (fluid on one side only, three layers thick) mirrors its
    layers across its wetted face, like the tank's floor, instead of pointing out of the case."""
    from shoal.case import Case, Fluid, FluidRegion, Solid
    from shoal.motions import ConstantVelocity
    from shoal.options import SPHOptions

    t = 3 * DP
    c = Case(name="t", dim=2, dp=DP, fluid=Fluid(depth=0.4),
             solids=[Solid(shape=Box(lo=(2.0, 0, 0), hi=(2.0 + t, 0, 1.0)), motion="m"),
                     Solid(shape=Tank(lo=(0, 0, 0), hi=(2.0 + t, 0, 1.0), open=["top", "xmax"]))],
             fluids=[FluidRegion(shape=Box(lo=(0, 0, 0), hi=(2.0, 0, 0.4)))],
             motions=[ConstantVelocity(name="m", velocity=(-0.1, 0, 0))],
             options=SPHOptions(wall_pressure="mdbc"))
    p = c.particles()
    x, g = walls(p, body=0)
    assert len(x) == 3 * 10
    wet = x[:, 0] < 2.0 + 2 * DP
    np.testing.assert_allclose(x[wet, 0] + g[wet, 0], 4.0 - x[wet, 0], rtol=0, atol=EXACT)
    assert np.all(g[:, 2] == 0.0)
    # the back layer, 2.5 dp behind the wetted face, sees no non-solid node within 2h = 2.83 dp (nor does
    # any fluid particle see it): no ghost
    assert np.count_nonzero(~wet) == 10 and np.all(g[~wet] == 0.0)
    x, g = walls(p, body=1)
    floor = (x[:, 2] < 0) & (x[:, 0] > R2 * DP) & (x[:, 0] < 2.0 - R2 * DP)
    assert np.count_nonzero(floor) == 2 * 14
    np.testing.assert_allclose(g[floor, 2], -2 * x[floor, 2], rtol=0, atol=EXACT)
    assert np.all(g[floor, 0] == 0.0)


# ------------------------------------------------------------------ helpers

def test_stencil_is_half_the_offsets_inside_the_support():
    for dim, R, count in ((2, R2, 20), (3, R3, 170)):  # |o|^2 <= 7 in 2D, <= 11 in 3D
        o = stencil(dim, R)
        d = np.linalg.norm(o, axis=1)
        assert np.all((d > 0) & (d < R)) and 2 * len(o) == count
        both = np.concatenate([o, -o])
        assert len(np.unique(both, axis=0)) == count  # o and -o never both listed


def test_lattice_normals_are_exact_on_symmetric_staircases():
    """A 45-degree staircase (solid where i + j < 40) and a flat floor: exact unit normals, integer
    sums that cancel exactly by symmetry."""
    i, j = np.meshgrid(np.arange(40), np.arange(40), indexing="ij")
    o = stencil(2, R2)
    diagonal = np.argwhere((i + j == 39) & (i > 5) & (i < 34))  # the stencil stays in the array
    assert len(diagonal) == 28
    n = lattice_normals(i + j < 40, diagonal, o)
    np.testing.assert_array_equal(n, np.full_like(n, 1 / math.sqrt(2)))
    floor = np.argwhere((j == 19) & (i > 5) & (i < 34))
    n = lattice_normals(j < 20, floor, o)
    np.testing.assert_array_equal(n, np.tile([0.0, 1.0], (len(n), 1)))
    assert np.all(lattice_normals(np.ones((9, 9), bool), np.array([[4, 4]]), o) == 0.0)


def test_exit_distance_finds_a_plane_and_gives_up_beyond_reach():
    inside = lambda q: q[:, 2] < 0.123  # noqa: E731
    pts = np.array([[0, 0, 0.05], [0, 0, -0.3], [0, 0, 0.1], [0, 0, 0.0]])
    dirs = np.array([[0, 0, 1.0], [0, 0, 1.0], [0, 0, 0.0], [0, 0, -1.0]])
    d = exit_distance(pts, dirs, inside, DP, 0.3)
    assert d[0] == pytest.approx(0.073, abs=2.5e-7 * DP)
    assert np.isnan(d[1])  # 0.423 m away: beyond the 0.3 m reach
    assert np.isnan(d[2]) and np.isnan(d[3])  # no direction; never leaves
