"""Wall layers parallel to a bed's surface (`fit_surface = true`, `shoal.geometry.surface_fit`): the
wall particles of a slope or a bathymetry lie at normal depths (k + 1/2) dp, the fluid's first row at
dp/2 above the surface, no two particles start closer than the blend allows, and still water over the
fitted bed stays on it with the hydrostatic pressure (issue 28, item 1: the lowest fluid layer within
0.6 dp of the surface, the bed pressure within 1 %)."""

from __future__ import annotations

import numpy as np
import pytest
from pydantic import ValidationError
from scipy.spatial import cKDTree

from shoal.case import Case, Fluid, FluidRegion, Output, Solid
from shoal.geometry.shapes import Bathymetry, Box, Slope, Tank
from shoal.geometry.surface_fit import BLEND

DP, D = 0.02, 0.2
SLOPE = Slope(x0=0.4, z0=0.0, gradient=0.1)


def slope_case(bed=SLOPE, fit=True, dim=2, end=0.4, probes=(), dp=DP):
    L = 2.8
    W = 4 * dp if dim == 3 else 0.0
    solids = [Solid(name="tank", shape=Tank(lo=(0, 0, 0), hi=(L, W, 1.5 * D))),
              Solid(name="bed", shape=bed, fit_surface=fit)]
    return Case(name="fit", dim=dim, dp=dp, end_time=end, fluid=Fluid(depth=D, surface_level=D), solids=solids,
                fluids=[FluidRegion(shape=Box(lo=(0, 0, 0), hi=(L, W, D)))], probes=list(probes),
                output=Output(interval=end))


def normal_height(p, bed=SLOPE):
    g = bed.gradient
    return (p[:, 2] - bed.level(p[:, 0], p[:, 1])) / np.sqrt(1 + g * g)


@pytest.mark.parametrize("dim", [2, 3])
def test_fitted_layers_lie_parallel_to_the_surface(dim):
    parts = slope_case(dim=dim).particles()
    x, y = parts.positions[:, 0], parts.positions[:, 1]
    W = 4 * DP if dim == 3 else 0.0
    # under the slope, inside the tank (its end and side walls stay on the lattice), within the support
    bed = parts.positions[(parts.kinds != 0) & (x > SLOPE.x0 + 10 * DP) & (x < 2.8 - DP) & (y >= 0) & (y <= W)
                          & (parts.positions[:, 2] < SLOPE.level(x, 0) + 1e-9)]
    depth = -normal_height(bed) / DP
    layers = np.round(depth - 0.5)
    assert np.abs(depth - 0.5 - layers).max() < 1e-9  # every wall particle under the slope on a layer
    top = bed[(layers == 0) & (bed[:, 1] == bed[0, 1])]
    # a particle keeps its place along the surface: layer 0 is a lattice row seen along the slope,
    # spaced dp cos(beta), and dp (cos(beta) + sin(beta)) across a step, dp / cos(beta) on average
    b = np.arctan(0.1)
    along = np.sort(top[:, 0] * np.cos(b) + top[:, 2] * np.sin(b))
    gaps = np.diff(along)
    assert np.all((np.abs(gaps - DP * np.cos(b)) < 1e-9) | (np.abs(gaps - DP * (np.cos(b) + np.sin(b))) < 1e-9))
    assert gaps.mean() == pytest.approx(DP / np.cos(b), rel=0.01)
    fluid = parts.positions[parts.kinds == 0]
    over = fluid[fluid[:, 0] > SLOPE.x0 + 10 * DP]
    assert normal_height(over).min() == pytest.approx(0.5 * DP, abs=1e-9)


def test_no_two_particles_start_closer_than_the_blend_allows():
    """The fitted rows return to the lattice over BLEND rows: spacings within (1 - 1/(2 BLEND)) dp."""
    p = slope_case().particles().positions
    d, _ = cKDTree(p[:, [0, 2]]).query(p[:, [0, 2]], k=2)
    assert d[:, 1].min() >= (1 - 1 / (2 * BLEND)) * DP - 1e-9


def test_wall_pressure_of_the_fitted_layers_is_hydrostatic():
    """Adami's extrapolation is exact for the linear pressure of still water: p_b = rho0 g (H - z_b) at
    every fitted wall particle the fluid sees (as on a flat bed, `tests/test_wall_pressure.py`)."""
    from shoal.options import SPHOptions
    from shoal.physics.spec import FLUID
    from shoal.runner import build_model

    case = slope_case().model_copy(update={"options": SPHOptions(precision="float64")})
    model = build_model(case)
    model.sort()
    model.compute_rates()
    p, kind, pos = model.pressure(), model.host(model.kind), model.world_positions()
    tree = cKDTree(pos[kind == FLUID][:, [0, 2]])
    x = pos[:, 0]
    under = (kind != FLUID) & (x > SLOPE.x0 + 10 * DP) & (x < 2.8 - DP) & (pos[:, 2] < SLOPE.level(x, 0))
    seen = under & np.isfinite(tree.query(pos[:, [0, 2]], distance_upper_bound=2 * case.smoothing_length)[0])
    assert seen.sum() > 100
    err = np.abs(p[seen] - 1000.0 * 9.81 * (D - pos[seen, 2])) / (1000.0 * 9.81 * D)
    assert err.max() < 2e-3


def test_mdbc_ghost_vectors_of_the_fitted_layers_are_exact():
    from shoal.options import SPHOptions

    case = slope_case().model_copy(update={"options": SPHOptions(wall_pressure="mdbc")})
    parts = case.particles()
    x = parts.positions[:, 0]
    bed = (parts.kinds != 0) & (x > SLOPE.x0 + 10 * DP) & (x < 2.8 - DP) & (
        parts.positions[:, 2] < SLOPE.level(x, 0) + 1e-9)
    n = np.array([-0.1, 0.0, 1.0]) / np.sqrt(1.01)
    depth = -normal_height(parts.positions[bed])
    assert np.allclose(parts.normals[bed], 2 * depth[:, None] * n, atol=1e-12)


def test_a_bathymetry_profile_fits_as_the_slope_does():
    prof = Bathymetry(profile={"x": [0.0, 0.4, 3.0], "z": [0.0, 0.0, 0.26]})
    a = slope_case().particles().positions
    b = slope_case(bed=prof).particles().positions
    sel = lambda p: p[(p[:, 0] > 0.5) & (p[:, 0] < 2.5)]  # noqa: E731
    assert np.allclose(np.sort(sel(a), axis=0), np.sort(sel(b), axis=0), atol=1e-9)


def test_fit_surface_is_for_beds_with_dynamic_particles():
    with pytest.raises(ValidationError, match="fit_surface"):
        Solid(name="box", shape=Box(lo=(0, 0, 0), hi=(1, 0, 1)), fit_surface=True)
    with pytest.raises(ValidationError, match="fit_surface"):
        Solid(name="bed", shape=SLOPE, boundary="repulsive", fit_surface=True)


def test_still_water_stays_on_the_fitted_bed_with_hydrostatic_pressure(tmp_path):
    """0.4 s of still water, H/dp = 20: no fluid below the surface, the lowest layer within 0.6 dp of it
    on average, the bed pressure (wall sensors on the surface) within 1 % of rho0 g H of rho0 g d (at
    H/dp = 10 the flat bed's own sensors read 1.35 % high: the lattice's kernel moment)."""
    import shoal
    from shoal.output.vtu import read_vtu
    from shoal.probes import PressureSensors

    xs = [SLOPE.x0 + f * D / 0.1 for f in (0.25, 0.5, 0.75)]
    pts = [[x, 0.0, float(SLOPE.level(x, 0.0))] for x in xs]
    dp = 0.5 * DP
    case = slope_case(probes=[PressureSensors(name="bed", points=pts, interval=0.01)], dp=dp)
    shoal.run_case(case, tmp_path, progress=False, plot=False)
    points, data = read_vtu(sorted(tmp_path.glob("*.vtu"))[-1])
    f = points[(data["kind"] == 0) & (points[:, 0] > xs[0]) & (points[:, 0] < xs[-1])]
    h = normal_height(f)
    assert h.min() > 0.0
    bins = np.floor((f[:, 0] - xs[0]) / dp).astype(int)
    gap = np.mean([h[bins == b].min() for b in np.unique(bins)])
    assert gap < 0.6 * dp
    p = np.loadtxt(tmp_path / "pressure_bed.csv", delimiter=",", skiprows=1)
    late = p[p[:, 0] >= 0.3, 1:].mean(axis=0)
    rgh = 1000.0 * 9.81 * D
    err = (late - 1000.0 * 9.81 * (D - np.array([q[2] for q in pts]))) / rgh
    assert np.abs(err).max() < 0.01, err
