"""Symmetry plane ("domain separation", tidal-bore paper section 2.4): half a symmetric 3D dam
break with a mirror plane gives the full run's flow."""

import time

import numpy as np
import pytest

import shoal
from shoal.case import SymmetryPlane
from shoal.geometry import Box, Tank
from shoal.runner import build_model
from shoal.simulation import TimeInterval

L, W, HT = 1.0, 0.4, 0.4


def dam_break(half, dp=0.02, end_time=0.5):
    w = W / 2 if half else W
    solids = [shoal.Solid(name="tank", shape=Tank(lo=(0, 0, 0), hi=(L, w, HT), open=["top"] + (["ymax"] if half else []))),
              shoal.Solid(name="column", shape=Box(lo=(0.6, 0.15, 0), hi=(0.7, 0.25 if not half else 0.2, 0.3)))]
    return shoal.Case(name="sym", dim=3, dp=dp, end_time=end_time, fluid=shoal.Fluid(depth=0.25, surface_level=0.25),
                      solids=solids, fluids=[shoal.FluidRegion(shape=Box(lo=(0, 0, 0), hi=(0.3, w, 0.25)))],
                      symmetry_planes=[SymmetryPlane(point=(0, W / 2, 0), normal=(0, -1, 0))] if half else [])


def run(case):
    m = build_model(case)
    sim = shoal.Simulation(m, case.end_time)
    rec = []

    def sample(s):
        p = s.model.world_positions()[s.model.host(s.model.kind) == 0]
        front = p[:, 0].max()
        # water depth at (x, y) = (0.45 m, 0.1 m): top fluid particle within dp
        g = (np.abs(p[:, 0] - 0.45) < case.dp) & (np.abs(p[:, 1] - 0.1) < case.dp)
        level = p[g, 2].max() if g.any() else 0.0
        rec.append((s.time, front, level))

    sim.add_callback(sample, TimeInterval(0.05))
    t0 = time.perf_counter()
    sim.run()
    return np.array(rec), time.perf_counter() - t0, m


def check(dp, end_time):
    full, t_full, mf = run(dam_break(False, dp, end_time))
    half, t_half, mh = run(dam_break(True, dp, end_time))
    assert mh.n_total < 0.6 * mf.n_total
    assert mh.n_escaped == 0 and mf.n_escaped == 0
    # y of every half-run particle stays on its side
    assert mh.world_positions()[:, 1].max() <= W / 2 + 1e-12
    late = full[:, 0] >= 0.2
    front_err = np.max(np.abs(half[late, 1] - full[late, 1]) / full[late, 1])
    level_err = np.max(np.abs(half[late, 2] - full[late, 2])) / 0.25
    print(f"symmetry plane: {mf.n_total} particles full, {mh.n_total} half; wall {t_full:.1f} s vs {t_half:.1f} s; "
          f"front max rel. difference {front_err:.4f}, level at (0.45, 0.1) max difference {level_err:.4f} of 0.25 m")
    assert front_err < 0.02
    assert level_err < 0.02


def test_half_dam_break_with_a_symmetry_plane_matches_the_full_one():
    """dp = 1/30 m (the column 3 dp wide, the half tank 6 dp) to t = 0.3 s."""
    check(1 / 30, 0.3)


@pytest.mark.validation
def test_half_dam_break_fine():
    """dp = 0.02 m to t = 0.5 s (measured: front 1.4 %, level 1.25 % of the depth; wall 47.9 s half vs
    81.7 s full on 2 cores, compile included)."""
    check(0.02, 0.5)


def test_mirror_rates_equal_those_of_the_mirrored_box():
    """Rates with a symmetry plane = rates of the same particles plus their explicit mirror images
    (position reflected, y velocity reversed), for every particle of the half (1e-12)."""
    from shoal.model import Model
    from shoal.options import SPHOptions

    rng = np.random.default_rng(11)
    dp = 0.02
    ys = 5 * dp
    g = np.stack(np.meshgrid((np.arange(8) + 0.5) * dp, (np.arange(5) + 0.5) * dp, (np.arange(6) + 0.5) * dp,
                             indexing="ij"), -1).reshape(-1, 3)
    g += 0.15 * dp * rng.standard_normal(g.shape)
    g[:, 1] = np.minimum(g[:, 1], ys - 1e-4)
    v = 0.1 * rng.standard_normal(g.shape)
    opts = SPHOptions(precision="float64", xsph=0.5, turbulence="sps")
    common = dict(dp=dp, dim=3, options=opts, gravity=(0, 0, -9.81), fluid_height=0.1)
    dom = ((-0.05, -0.05, -0.05), (0.21, 2 * ys + 0.05, 0.17))
    half = Model(g, np.zeros(len(g), np.int8), domain=dom, symmetry_y=(ys, -1.0), velocities=v, **common)
    gm, vm = g.copy(), v.copy()
    gm[:, 1] = 2 * ys - g[:, 1]
    vm[:, 1] = -v[:, 1]
    full = Model(np.vstack([g, gm]), np.zeros(2 * len(g), np.int8), domain=dom, velocities=np.vstack([v, vm]),
                 **common)
    out = []
    for m in (half, full):
        m.sort()
        m.compute_rates()
        ids = m.host(m.idp)
        res = {}
        for k in ("ace", "drho", "xsph", "tau"):
            a = m.host(getattr(m, k))
            o = np.empty_like(a)
            o[ids] = a
            res[k] = o[: len(g)]
        out.append(res)
    for k in ("ace", "drho", "xsph", "tau"):
        scale = np.max(np.abs(out[1][k]))
        np.testing.assert_allclose(out[0][k], out[1][k], atol=1e-12 * scale, err_msg=k)
