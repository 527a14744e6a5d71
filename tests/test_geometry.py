"""Geometry primitives -> particles: exact lattice counts, no fluid inside
solids, wall thickness, bathymetry sampled where it should be."""

import math

import numpy as np
import pytest
from scipy.spatial import cKDTree

from shoal.case import Case, Domain, Fluid, FluidRegion, Solid
from shoal.errors import InputError
from shoal.geometry.generate import FIXED, FLUID, MOVING, support_layers
from shoal.geometry.shapes import Bathymetry, Box, Cylinder, HeightGrid, Mesh, Plane, Prism, Profile, Slope, Tank

DP = 0.1


def make(dim, solids, fluids, dp=DP, domain=None, **kw):
    return Case(name="t", dim=dim, dp=dp, fluid=Fluid(depth=1.0), solids=solids, fluids=fluids,
                domain=domain, **kw)


def test_box_fill_count_is_the_exact_lattice_count():
    # 1.0 x 0.5 x 0.3 m box on the lattice of 0.1 m: 10 x 5 x 3 nodes, 2D: 10 x 3
    c3 = make(3, [], [FluidRegion(shape=Box(lo=(0, 0, 0), hi=(1.0, 0.5, 0.3)))])
    assert c3.particles().counts() == {"fluid": 150, "fixed": 0, "moving": 0}
    c2 = make(2, [], [FluidRegion(shape=Box(lo=(0, 0, 0), hi=(1.0, 0, 0.3)))])
    assert c2.particles().counts()["fluid"] == 30
    # a box not aligned with the lattice holds the nodes whose centres it contains: 0.05 .. 0.95 -> 10 nodes,
    # and a face through node centres counts as half-open [lo, hi): [0.05, 0.95] -> 9 nodes
    c = make(2, [], [FluidRegion(shape=Box(lo=(0.05, 0, 0.0), hi=(0.96, 0, 0.1)))])
    assert c.particles().counts()["fluid"] == 10
    c = make(2, [], [FluidRegion(shape=Box(lo=(0.05, 0, 0.0), hi=(0.95, 0, 0.1)))])
    assert c.particles().counts()["fluid"] == 9
    p = c3.particles().positions
    assert np.allclose(np.sort(np.unique(p[:, 0])), 0.05 + 0.1 * np.arange(10))


@pytest.mark.parametrize("dim", [2, 3])
@pytest.mark.parametrize("layers", [1, 3])
def test_tank_walls_have_the_asked_layers_and_exact_count(dim, layers):
    L, W, H = 1.0, 0.6, 0.8
    tank = Tank(lo=(0, 0, 0), hi=(L, W if dim == 3 else 0, H))
    c = make(dim, [Solid(shape=tank, layers=layers)],
             [FluidRegion(shape=Box(lo=(0, 0, 0), hi=(L, W if dim == 3 else 0, 0.4)))])
    p = c.particles()
    n = [round(L / DP), round(W / DP), round(H / DP)]
    t = layers
    if dim == 2:
        outer = (n[0] + 2 * t) * (n[2] + t)
        inner = n[0] * n[2]
    else:
        outer = (n[0] + 2 * t) * (n[1] + 2 * t) * (n[2] + t)
        inner = n[0] * n[1] * n[2]
    assert p.counts()["fixed"] == outer - inner
    w = p.positions[p.kinds == FIXED]
    # thickness: the outermost layer is (layers - 1/2) dp outside the walls
    assert w[:, 0].min() == pytest.approx(-(t - 0.5) * DP)
    assert w[:, 2].min() == pytest.approx(-(t - 0.5) * DP)
    assert w[:, 2].max() == pytest.approx(H - 0.5 * DP)  # open top: walls up to the tank height
    assert p.counts()["fluid"] == n[0] * (n[1] if dim == 3 else 1) * 4


@pytest.mark.parametrize("dim", [2, 3])
def test_default_walls_cover_the_kernel_support(dim):
    """Without `layers`, a wall is as deep as the kernel support: a fluid
    particle next to the wall sees wall particles all through its support."""
    tank = Tank(lo=(0, 0, 0), hi=(1.0, 0.5 if dim == 3 else 0, 0.6))
    c = make(dim, [Solid(shape=tank)], [FluidRegion(shape=Box(lo=(0, 0, 0), hi=(1.0, 0.5 if dim == 3 else 0, 0.3)))])
    p = c.particles()
    h2 = 2 * c.smoothing_length
    k = support_layers(h2 / DP)
    assert k == (2 if dim == 2 else 3)  # 2h = 2.83 dp (2D), 3.46 dp (3D) with coef_h = 1
    wall = p.positions[p.kinds == FIXED]
    fluid = p.positions[p.kinds == FLUID]
    assert wall[:, 2].min() == pytest.approx(-(k - 0.5) * DP)
    # every lattice node below the bed within 2h of a fluid particle is a wall particle
    tree = cKDTree(wall)
    probe = fluid[np.argmin(fluid[:, 2])] * [1, 1, 0] + [0, 0, 0.5 * DP]  # a bottom-row fluid particle
    for j in range(1, 6):
        node = probe - [0, 0, j * DP]
        d = np.linalg.norm(node - probe)
        hit = tree.query(node)[0] < 1e-9
        assert hit == (d < h2), (j, d, h2)


def test_fluid_never_overlaps_solids_and_keeps_one_spacing():
    solids = [Solid(shape=Tank(lo=(0, 0, 0), hi=(3, 1, 1))),
              Solid(shape=Cylinder(center=(1.0, 0.5), radius=0.2, axis="z", lo=0.0, hi=1.0)),
              Solid(shape=Prism(vertices=[(2, 0), (2.3, 0.3), (2.6, 0)], axis="z", lo=0, hi=1)),
              Solid(shape=Plane(point=(0, 0, 0.15), normal=(-0.2, 0, 1.0), lo=(0, 0, -1), hi=(3, 1, 1)))]
    c = make(3, solids, [FluidRegion(shape=Box(lo=(0, 0, 0), hi=(3, 1, 0.6)))], dp=0.05)
    p = c.particles()
    fl = p.positions[p.kinds == FLUID]
    for s in solids:
        assert not np.any(s.shape.contains(fl, 3, 3 * 0.05))
    # same lattice: the closest fluid - wall pair is exactly one spacing apart
    d, _ = cKDTree(p.positions[p.kinds != FLUID]).query(fl)
    assert d.min() == pytest.approx(0.05)
    # every solid got particles
    for k in range(len(solids)):
        assert np.count_nonzero(p.body == k) > 0


def test_obstacle_keeps_only_its_surface_layers():
    box = Box(lo=(0.4, 0.0, 0.0), hi=(1.2, 0, 0.8))  # 8 x 8 nodes, solid
    c = make(2, [Solid(shape=box, layers=2)], [FluidRegion(shape=Box(lo=(0, 0, 0), hi=(2.0, 0, 1.0)))])
    p = c.particles()
    # a hollow 8 x 8 square two deep: its 4 x 4 core is more than 2 spacings from the outside
    assert p.counts()["fixed"] == 8 * 8 - 4 * 4
    assert p.counts()["fluid"] == 20 * 10 - 64


def test_moving_solid_particles_are_moving():
    from shoal.motions import ConstantVelocity

    c = make(2, [Solid(shape=Box(lo=(0.9, 0, 0), hi=(1.2, 0, 0.5)), motion="w", layers=1),
                 Solid(shape=Tank(lo=(0, 0, 0), hi=(1.2, 0, 0.5)), layers=1)],
             [FluidRegion(shape=Box(lo=(0, 0, 0), hi=(0.9, 0, 0.3)), velocity=(0.5, 0, 0))],
             motions=[ConstantVelocity(name="w", velocity=(-0.1, 0, 0))])
    p = c.particles()
    assert np.all(p.kinds[p.body == 0] == MOVING) and np.count_nonzero(p.body == 0) > 0
    assert np.all(p.velocities[p.kinds == FLUID] == [0.5, 0, 0])


def test_bathymetry_profile_is_sampled_where_expected():
    prof = Profile(x=[0.0, 2.0, 4.0], z=[0.0, 0.0, 0.5])  # flat, then a 1:4 slope
    c = make(2, [Solid(shape=Bathymetry(profile=prof), layers=2)],
             [FluidRegion(shape=Box(lo=(0, 0, -1), hi=(4, 0, 0.6)))],
             dp=0.05, domain=Domain(lo=(0, 0, -0.5), hi=(4, 0, 1.0)))
    p = c.particles()
    w = p.positions[p.kinds == FIXED]
    fl = p.positions[p.kinds == FLUID]
    zb = np.interp(w[:, 0], prof.x, prof.z)
    assert np.all(w[:, 2] < zb)                       # walls below the bed
    assert np.all(fl[:, 2] >= np.interp(fl[:, 0], prof.x, prof.z))  # fluid above
    # the top wall node of each column is within one spacing of the bed (the bed is sampled, not stepped)
    for x in np.unique(w[:, 0]):
        top = w[w[:, 0] == x, 2].max()
        assert 0 < np.interp(x, prof.x, prof.z) - top <= 0.05 + 1e-12


def test_bathymetry_grid_file_and_function_agree(tmp_path):
    xs = np.linspace(0, 2, 5)
    ys = np.linspace(0, 1, 3)
    Z = 0.1 * xs[:, None] + 0.05 * ys[None, :]
    grid = HeightGrid(x=xs, y=ys, z=Z)
    pts = np.column_stack([np.repeat(xs, 3), np.tile(ys, 5), Z.ravel()])
    np.savetxt(tmp_path / "bed.csv", pts, delimiter=",", header="x,y,z")
    np.savez(tmp_path / "bed.npz", x=xs, y=ys, z=Z)
    shapes = [Bathymetry(grid=grid), Bathymetry(file=str(tmp_path / "bed.csv")),
              Bathymetry(file=str(tmp_path / "bed.npz")),
              Bathymetry(function=lambda x, y: 0.1 * x + 0.05 * y)]
    rng = np.random.default_rng(1)
    q = np.column_stack([rng.uniform(0, 2, 500), rng.uniform(0, 1, 500), rng.uniform(0, 0.3, 500)])
    ref = shapes[0].contains(q, 3)
    exact = q[:, 2] < 0.1 * q[:, 0] + 0.05 * q[:, 1]
    np.testing.assert_array_equal(ref, exact)  # bilinear is exact on a plane
    for s in shapes[1:]:
        np.testing.assert_array_equal(s.contains(q, 3), ref)


def test_bathymetry_file_errors(tmp_path):
    (tmp_path / "bad.csv").write_text("1,2,3\n4,5\n")
    with pytest.raises(InputError, match="bad.csv"):
        Bathymetry(file=str(tmp_path / "bad.csv")).level([0.0], [0.0])
    with pytest.raises(InputError, match="not found"):
        Bathymetry(file=str(tmp_path / "none.csv")).level([0.0], [0.0])


def test_slope_and_plane_are_the_same_beach():
    s = Slope(x0=1.0, z0=0.0, gradient=0.25, x1=3.0)
    n = np.array([-0.25, 0.0, 1.0])
    p = Plane(point=(1.0, 0, 0), normal=tuple(n), lo=(1.0, -1, -1), hi=(3.0, 1, 1))
    rng = np.random.default_rng(2)
    q = np.column_stack([rng.uniform(0, 4, 2000), np.zeros(2000), rng.uniform(-0.5, 0.8, 2000)])
    inside = (q[:, 0] >= 1) & (q[:, 0] <= 3) & (q[:, 2] >= -1) & (q[:, 2] <= 1)
    np.testing.assert_array_equal(s.contains(q, 2) & inside, p.contains(q, 2))


def test_prism_pier_and_cylinder_counts():
    # a 0.4 x 0.2 m rectangular prism: 4 x 2 nodes per level at dp = 0.1, 5 levels
    pr = Prism(vertices=[(1.0, 0.0), (1.4, 0.0), (1.4, 0.2), (1.0, 0.2)], axis="z", lo=0.0, hi=0.5)
    g = np.stack(np.meshgrid(np.arange(30) * 0.1 + 0.05, np.arange(10) * 0.1 + 0.05, np.arange(10) * 0.1 + 0.05,
                             indexing="ij"), -1).reshape(-1, 3)
    assert np.count_nonzero(pr.contains(g + 1e-9, 3)) == 4 * 2 * 5
    cyl = Cylinder(center=(1.5, 0.5), radius=0.3, axis="z", lo=0.0, hi=1.0)
    n = np.count_nonzero(cyl.contains(g, 3))
    assert n == pytest.approx(math.pi * 0.3**2 * 1.0 / 0.1**3, rel=0.15)  # the lattice disc, 10 levels
    disc = (g[:, 2] == 0.05) & ((g[:, 0] - 1.5) ** 2 + (g[:, 1] - 0.5) ** 2 <= 0.09)
    assert n == 10 * np.count_nonzero(disc)


def test_stl_mesh_solid(tmp_path):
    from stl import mesh as stl_mesh

    # a closed cube 0.4 m wide as an STL, standing on the floor of a tank
    v = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1]], float)
    f = np.array([[0, 3, 1], [1, 3, 2], [0, 4, 7], [0, 7, 3], [4, 5, 6], [4, 6, 7], [5, 1, 2], [5, 2, 6],
                  [2, 3, 6], [3, 7, 6], [0, 1, 5], [0, 5, 4]])
    m = stl_mesh.Mesh(np.zeros(len(f), dtype=stl_mesh.Mesh.dtype))
    m.vectors[:] = v[f]
    m.save(str(tmp_path / "cube.stl"))
    cube = Mesh(file=str(tmp_path / "cube.stl"), scale=0.4, offset=(0.8, 0.3, 0.0))
    box = Box(lo=(0.8, 0.3, 0.0), hi=(1.2, 0.7, 0.4))
    fl = [FluidRegion(shape=Box(lo=(0, 0, 0), hi=(2, 1, 0.6)))]
    a = make(3, [Solid(shape=Tank(lo=(0, 0, 0), hi=(2, 1, 1))), Solid(shape=cube)], fl).particles()
    b = make(3, [Solid(shape=Tank(lo=(0, 0, 0), hi=(2, 1, 1))), Solid(shape=box)], fl).particles()
    np.testing.assert_array_equal(a.positions, b.positions)
    np.testing.assert_array_equal(a.body, b.body)


def test_repulsive_walls_are_one_layer_at_half_spacing():
    c = make(2, [Solid(shape=Tank(lo=(0, 0, 0), hi=(1.0, 0, 0.6)), boundary="repulsive")],
             [FluidRegion(shape=Box(lo=(0, 0, 0), hi=(1.0, 0, 0.3)))])
    p = c.particles()
    w = p.positions[p.kinds == FIXED]
    assert np.all(p.spacing[p.kinds == FIXED] == DP / 2)
    # bottom: one row dp/4 below the floor, every dp/2 along x (plus the corner nodes)
    bottom = w[np.isclose(w[:, 2], -DP / 4)]
    assert len(bottom) == round(1.0 / (DP / 2)) + 2
    assert w[:, 2].min() == pytest.approx(-DP / 4)
    sides = w[np.isclose(w[:, 0], -DP / 4)]
    assert len(sides) == round(0.6 / (DP / 2)) + 1


def test_unbounded_shapes_need_a_domain():
    c = make(2, [Solid(shape=Plane(point=(0, 0, 0), normal=(0, 0, 1)))],
             [FluidRegion(shape=Box(lo=(0, 0, 0), hi=(1, 0, 0.5)))])
    # the fluid box bounds x and z here, so the plane is clipped to it
    assert c.particles().counts()["fluid"] == 50
    c = make(2, [Solid(shape=Plane(point=(0, 0, 0), normal=(0, 0, 1)))],
             [FluidRegion(shape=Slope(x0=0, z0=0, gradient=1.0))])
    with pytest.raises(InputError, match="domain"):
        c.particles()


def test_faces_on_an_explicit_domain_boundary_get_no_walls():
    """Beyond an explicit domain is not fluid: a block standing on the domain's bottom face gets no wall
    particles on that face (they would never see fluid)."""
    box = Box(lo=(0.4, 0.0, 0.0), hi=(1.2, 0, 0.8))
    c = make(2, [Solid(shape=box, layers=2)], [FluidRegion(shape=Box(lo=(0, 0, 0), hi=(2.0, 0, 1.0)))],
             domain=Domain(lo=(0, 0, 0), hi=(2.0, 0, 1.0)))
    p = c.particles()
    assert p.counts()["fixed"] == 8 * 8 - 4 * 6  # the core 4 x 6 (rows 0..5 from the bottom) is not a wall


def test_walls_outside_an_explicit_domain_are_refused():
    c = make(2, [Solid(shape=Tank(lo=(0, 0, 0), hi=(1, 0, 1)), layers=3)],
             [FluidRegion(shape=Box(lo=(0, 0, 0), hi=(1, 0, 0.5)))], domain=Domain(lo=(-0.1, 0, -0.1), hi=(1.1, 0, 2)))
    with pytest.raises(InputError, match="outside the domain"):
        c.particles()


def test_slab_generation_equals_one_piece(monkeypatch):
    """Generation in x-slabs with halos gives exactly the particles of one piece."""
    import importlib

    gen = importlib.import_module("shoal.geometry.generate")

    solids = [Solid(shape=Tank(lo=(0, 0, 0), hi=(2, 0.5, 1))),
              Solid(shape=Bathymetry(profile=Profile(x=[0, 1, 2], z=[0, 0.2, 0.6])))]
    fluids = [FluidRegion(shape=Box(lo=(0, 0, 0), hi=(2, 0.5, 0.5)))]
    whole = make(3, solids, fluids, dp=0.05).particles()
    monkeypatch.setattr(gen, "_SLAB_NODES", 700)  # slabs of a few x-columns
    sliced = make(3, solids, fluids, dp=0.05).particles()
    np.testing.assert_array_equal(whole.positions, sliced.positions)
    np.testing.assert_array_equal(whole.body, sliced.body)


@pytest.mark.parametrize("factory", ["dam-break-dualsphysics", "tidal-bore-piers", "rip-current"])
def test_slabs_and_threads_generate_the_same_particles(monkeypatch, factory):
    """The lattice is generated in slabs along x, on up to 8 threads; neither the cut nor the threads
    change a particle. Cases with walls of explicit layers (chessboard distance: the DualSPHysics tank
    and column), of the support's thickness (Euclidean distance: the piers) and repulsive walls on the
    fine lattice (the rip-current basin's variant)."""
    import sys

    from shoal.cases import get_case

    gen = sys.modules["shoal.geometry.generate"]
    kwargs = {"dam-break-dualsphysics": dict(dp=0.02), "tidal-bore-piers": dict(dp=0.02, half=True),
              "rip-current": dict(dp=0.075, boundary="repulsive")}[factory]

    def particles(slab_nodes, workers):
        monkeypatch.setattr(gen, "_SLAB_NODES", slab_nodes)
        monkeypatch.setattr(gen, "_slab_workers", lambda n: min(n, workers))
        p = get_case(factory, **kwargs).particles()
        return p.positions, p.kinds, p.body, p.region, p.spacing

    whole = particles(10**9, 1)
    assert len(whole[0]) > 5000
    for cut in (particles(20_000, 1), particles(20_000, 4)):
        for a, b in zip(whole, cut):
            np.testing.assert_array_equal(a, b)
