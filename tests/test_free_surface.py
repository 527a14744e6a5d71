"""Free-surface detection (Marrone et al. 2010, cone test) on shapes whose surface is known."""

import numpy as np
import pytest

import shoal
from shoal.cases import still_water_2d, still_water_3d
from shoal.case import Domain, WallPlane
from shoal.geometry import Box
from shoal.model import Model
from shoal.options import SPHOptions
from shoal.runner import build_model


def _flags(model):
    model.sort()
    f = model.free_surface()
    ids = model.host(model.idp)
    out = np.zeros(model.n_total, np.int8)
    out[ids] = f
    return out


def _precision_recall(flags, truth):
    hit = np.sum(flags & truth)
    return hit / max(np.sum(flags), 1), hit / max(np.sum(truth), 1)


@pytest.mark.parametrize("dim", [2, 3])
def test_still_water_surface_is_its_top_layer(dim):
    """In a tank (dynamic walls) the flagged particles are exactly the top layer, contact line
    included: none against the bed or the side walls below the surface, none inside (issue 6:
    precision and recall >= 0.98 on a lattice; measured 1 and 1). The walls rising above the water
    are dry there and left out of the test; before, they tilted the contact-line particles'
    normals and 64 of 100 top particles were flagged in 3D."""
    case = still_water_2d(dp=0.02, depth=0.3, length=0.6) if dim == 2 else still_water_3d(
        dp=0.04, depth=0.3, length=0.4, width=0.4)
    m = build_model(case)
    f = _flags(m).astype(bool)
    p = case.particles()
    fluid = p.kinds == 0
    top = fluid & np.isclose(p.positions[:, 2], p.positions[fluid, 2].max())
    precision, recall = _precision_recall(f, top)
    print(f"{dim}D lattice: {int(f.sum())} flagged of {int(top.sum())} top-layer particles; "
          f"precision {precision:.3f}, recall {recall:.3f}")
    assert precision >= 0.98 and recall >= 0.98


def _outer_layer(model, dp, lo, hi):
    """Fluid particles facing air (outer) and those far from it (deep).

    Air: the nodes of a dp/4 lattice over the box [lo, hi] (x-z, or x-y-z) farther than 1.25 dp from
    every particle, fluid or wall (so neither the gap between the fluid and a particle wall nor a
    hole in a disordered flow counts as air). Measured on a settled tank and a dam break: the
    particles the cone test flags lie 1.25-2.1 dp from air, the layer below a flat surface 1.5-1.75
    dp. Outer: within 1.45 dp of air; deep: farther than 2.5 dp."""
    from scipy.spatial import cKDTree

    pos = model.host(model.pos).astype(float)
    fluid = model.host(model.kind) == 0
    axes = [np.arange(a, b + 1e-9, dp / 4) for a, b in zip(lo, hi)]
    nodes = np.stack(np.meshgrid(*axes, indexing="ij"), -1).reshape(-1, len(axes))
    d_all, _ = cKDTree(pos).query(nodes)
    d_air, _ = cKDTree(nodes[d_all > 1.25 * dp]).query(pos)
    return fluid & (d_air <= 1.45 * dp), fluid & (d_air > 2.5 * dp)


@pytest.mark.parametrize("dim", [2, 3])
def test_settled_still_water_surface(dim):
    """After 0.3 s of settling (about ten acoustic crossings of the depth) the flags are the layer
    facing the air: precision and recall >= 0.95 (issue 6), no deep particle flagged."""
    from shoal.simulation import Simulation

    case = still_water_2d(dp=0.02, depth=0.3, length=0.6) if dim == 2 else still_water_3d(
        dp=0.04, depth=0.3, length=0.4, width=0.4)
    m = build_model(case)
    Simulation(m, 0.3).run()
    m.sort()
    f = m.free_surface().astype(bool)
    pos = m.host(m.pos)
    outer, deep = _outer_layer(m, case.dp, pos.min(0) - case.dp, pos.max(0) + 3 * case.dp)
    precision, recall = _precision_recall(f, outer)
    print(f"{dim}D settled: {int(f.sum())} flagged, {int(outer.sum())} facing air; "
          f"precision {precision:.3f}, recall {recall:.3f}")
    assert precision >= 0.95 and recall >= 0.95
    assert not np.any(f & deep)


def test_dam_break_surge_surface():
    """A 2D dam break at t = 0.3 s (the surge has run along the bed past x = 2a): the particles
    facing air -- the column's falling top, its face and the surge's upper side -- are flagged
    (recall >= 0.95), and none deep inside is (issue 6: "flags the surface of the surge")."""
    from shoal.cases import dam_break_2d
    from shoal.simulation import Simulation

    a = 0.146
    dp = a / 24  # at a / 12 the tip of the two-particle-thick surge is ambiguous (recall 0.93)
    case = dam_break_2d(dp=dp, a=a, layers=3)
    m = build_model(case)
    Simulation(m, 0.3).run()
    m.sort()
    f = m.free_surface().astype(bool)
    pos = m.host(m.pos)
    fluid = m.host(m.kind) == 0
    assert pos[fluid, 0].max() > 2 * a  # the surge is out
    outer, deep = _outer_layer(m, dp, pos.min(0) - dp, pos.max(0) + dp)
    precision, recall = _precision_recall(f, outer)
    print(f"dam break t = 0.3 s: {int(f.sum())} flagged, {int(outer.sum())} facing air; "
          f"recall {recall:.3f}, precision {precision:.3f}, deep flagged {int(np.sum(f & deep))}")
    assert recall >= 0.95
    assert not np.any(f & deep)


def test_drop_surface_is_its_outer_ring():
    """A 2D disc of fluid without walls: flagged = the particles within one spacing of the rim."""
    dp = 0.01
    R = 0.1
    g = np.stack(np.meshgrid(np.arange(-12, 12) * dp + dp / 2, [0.0], np.arange(-12, 12) * dp + dp / 2,
                             indexing="ij"), -1).reshape(-1, 3)
    r = np.hypot(g[:, 0], g[:, 2])
    g = g[r < R]
    r = r[r < R]
    m = Model(g, np.zeros(len(g), np.int8), dp=dp, dim=2, domain=((-0.2, 0, -0.2), (0.2, 0, 0.2)),
              options=SPHOptions(), gravity=(0, 0, 0), u_max=1.0)
    f = _flags(m).astype(bool)
    assert np.all(f[r > R - 0.6 * dp])       # the outermost ring is all surface
    assert not np.any(f[r < R - 2.5 * dp])    # nothing deep inside


def test_plane_normal_correction():
    """Water standing on a wall plane (no particles below): the bottom layer is not surface."""
    dp = 0.02
    case = shoal.Case(name="p", dim=2, dp=dp, fluid=shoal.Fluid(depth=0.2, surface_level=0.2),
                      planes=[WallPlane(point=(0, 0, 0), normal=(0, 0, 1))],
                      fluids=[shoal.FluidRegion(shape=Box(lo=(0, 0, 0), hi=(0.6, 0, 0.2)))],
                      domain=Domain(lo=(-0.1, 0, -0.1), hi=(0.7, 0, 0.4)))
    m = build_model(case)
    f = _flags(m).astype(bool)
    z = case.particles().positions[:, 2]
    x = case.particles().positions[:, 0]
    inner = (x > 3 * dp) & (x < 0.6 - 3 * dp)
    assert not np.any(f[inner & (z < 0.1)])   # bottom rows: corrected by the plane normal
    assert np.all(f[inner & np.isclose(z, z.max())])
