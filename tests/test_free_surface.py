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


@pytest.mark.parametrize("dim", [2, 3])
def test_still_water_surface_is_its_top_layer(dim):
    """In a tank (dynamic walls) only top-layer fluid particles are flagged -- none against the bed
    or the side walls below the surface, none inside -- and all of the top layer but the contact
    line: a top particle next to a side wall sees the wall particles rising above the water
    within the wider cone (pi/4) used near walls and may go either way."""
    case = still_water_2d(dp=0.02, depth=0.3, length=0.6) if dim == 2 else still_water_3d(
        dp=0.04, depth=0.3, length=0.4, width=0.4)
    m = build_model(case)
    f = _flags(m)
    p = case.particles()
    fluid = p.kinds == 0
    top = fluid & np.isclose(p.positions[:, 2], p.positions[fluid, 2].max())
    f = f.astype(bool)
    assert not np.any(f & ~top)
    lo, hi = p.positions[fluid].min(0), p.positions[fluid].max(0)
    axes = [0, 1] if dim == 3 else [0]
    away = np.all((p.positions[:, axes] > lo[axes] + 0.5 * case.dp) & (p.positions[:, axes] < hi[axes] - 0.5 * case.dp),
                  axis=1)
    assert np.all(f[top & away])
    print(f"{dim}D: {int(f.sum())} flagged of {int(top.sum())} top-layer particles")


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
