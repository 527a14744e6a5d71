"""The gap between still water and its walls, and the pressure on them, by boundary treatment (issue 28).

Still water of depth H at rest over four beds: a flat bed (2D), a 1:10 slope (2D), the same slope with
its wall particles on layers parallel to its surface (`fit_surface = true`, "slope-fit") and a 1:10
ramp read from an STL file (3D), each run to t = `--end` s with the case defaults and the chosen
`wall_pressure`. Printed per bed:

* **gap**: over bins one spacing wide along the wall (away from the tank's ends), the distance of the
  closest fluid particle to the wall surface, averaged over the bins, in spacings. The lattice starts
  the flat bed's lowest layer at 0.5 dp; on a slope the lattice's stair-steps put the closest particle
  of a bin between 0 and 1 dp from the plane (0.5 dp on average);
* **surge**: the same gap under the surge of the 2D dam break (column a x 2a, a = 0.146 m, dp = a/30
  unless `--surge-dp`) at T = t sqrt(2 g / a) = 2, over the bed from x = 1.5 a to two spacings behind
  the front: the flowing thin layer, where dynamic boundaries push the water off the bed;
* **bed pressure**: wall pressure sensors (`type = "pressure"`) on the wall surface at three depths,
  averaged over the last quarter of the run, against rho0 g d (d the still-water depth above the
  sensor), as a percentage of rho0 g H.

    python benchmarks/wall_gap.py --wall dynamic adami --dp 0.01 --end 1.0
"""

from __future__ import annotations

import argparse
import tempfile
from pathlib import Path

import numpy as np

import shoal
from shoal.case import Case, Fluid, FluidRegion, Output, Solid
from shoal.geometry.shapes import Box, Mesh, Slope, Tank
from shoal.options import SPHOptions
from shoal.output.vtu import read_vtu
from shoal.probes import PressureSensors

RHO0, G = 1000.0, 9.81
SLOPE = 0.1


def ramp_stl(path, x0, x1, z0, width):
    """A closed triangular prism, 1:10 up from (x0, z0) to x1, `width` wide in y, as a binary STL."""
    from stl import mesh as stl_mesh

    z1 = z0 + SLOPE * (x1 - x0)
    zb = z0 - 1.0  # a deep base, so the ramp's solid fills the walls' layers below it
    v = np.array([[x0, zb], [x1, zb], [x1, z1], [x0, z0]])  # a quadrilateral section, counter-clockwise
    tris = []
    lo = [np.array([x, 0.0, z]) for x, z in v]
    hi = [np.array([x, width, z]) for x, z in v]
    tris += [[lo[0], lo[2], lo[1]], [lo[0], lo[3], lo[2]], [hi[0], hi[1], hi[2]], [hi[0], hi[2], hi[3]]]
    for a in range(4):
        b = (a + 1) % 4
        tris += [[lo[a], lo[b], hi[b]], [lo[a], hi[b], hi[a]]]
    m = stl_mesh.Mesh(np.zeros(len(tris), dtype=stl_mesh.Mesh.dtype))
    m.vectors[:] = np.array(tris)
    m.save(str(path))
    return path


def bed_case(kind, dp, depth, end, wall, tmp):
    """(case, wall surface z(x), sensor points, sensor depths) of one bed."""
    L = 8 * depth
    o = SPHOptions(wall_pressure=wall)
    if kind == "flat":
        solids = [Solid(name="tank", shape=Tank(lo=(0, 0, 0), hi=(L, 0, 1.5 * depth)))]
        surface = lambda x: np.zeros_like(x)  # noqa: E731
        xs = [0.25 * L, 0.5 * L, 0.75 * L]
        dim, width = 2, 0.0
    else:
        x0 = 0.25 * L  # the slope rises from the bed at x0 and reaches the still-water level at x0 + 10 H
        L = x0 + depth / SLOPE + 2 * depth
        surface = lambda x: np.clip(SLOPE * (x - x0), 0.0, None)  # noqa: E731
        xs = [x0 + 0.25 * depth / SLOPE, x0 + 0.5 * depth / SLOPE, x0 + 0.75 * depth / SLOPE]
        if kind in ("slope", "slope-fit"):
            dim, width = 2, 0.0
            ramp = Slope(x0=x0, z0=0.0, gradient=SLOPE)
        else:
            dim, width = 3, 6 * dp
            ramp = Mesh(file=str(ramp_stl(Path(tmp) / "ramp.stl", x0, L + dp, 0.0, width + 2 * dp)))
        solids = [Solid(name="tank", shape=Tank(lo=(0, 0, 0), hi=(L, width, 1.5 * depth))),
                  Solid(name="bed", shape=ramp, fit_surface=kind == "slope-fit")]
    y = 0.5 * width
    pts = [[x, y, float(surface(np.array([x]))[0])] for x in xs]
    depths = [depth - p[2] for p in pts]
    sensors = PressureSensors(name="bed", points=pts, interval=end / 40)
    case = Case(name=f"gap-{kind}", dim=dim, dp=dp, end_time=end, fluid=Fluid(depth=depth, surface_level=depth),
                options=o, solids=solids, fluids=[FluidRegion(shape=Box(lo=(0, 0, 0), hi=(L, width, depth)))],
                probes=[sensors], output=Output(interval=end))
    return case, surface, pts, depths


def measure(kind, dp, depth, end, wall):
    with tempfile.TemporaryDirectory() as tmp:
        case, surface, pts, depths = bed_case(kind, dp, depth, end, wall, tmp)
        out = Path(tmp) / "run"
        shoal.run_case(case, out, progress=False, plot=False)
        last = sorted(out.glob("*.vtu"))[-1]
        points, data = read_vtu(last)
        fluid = data["kind"] == 0
        x, z = points[fluid, 0], points[fluid, 2]
        cos = 1.0 / np.sqrt(1 + SLOPE**2) if kind != "flat" else 1.0
        d = (z - surface(x)) * np.where(surface(x) > 0, cos, 1.0)
        lo, hi = (pts[0][0] - 2 * depth, pts[-1][0] + 2 * depth) if kind == "flat" else (pts[0][0], pts[-1][0])
        bins = np.floor((x - lo) / dp).astype(int)
        sel = (x >= lo) & (x < hi)
        mins = [d[sel & (bins == b)].min() for b in np.unique(bins[sel])]
        p = np.loadtxt(out / "pressure_bed.csv", delimiter=",", skiprows=1)
        late = p[p[:, 0] >= 0.75 * end, 1:].mean(axis=0)
        err = (late - RHO0 * G * np.array(depths)) / (RHO0 * G * depth) * 100
        return dict(particles=case.n_particles, gap=float(np.mean(mins)) / dp, gap_min=float(np.min(mins)) / dp,
                    pressure_err=err.tolist())


def measure_surge(dp, wall, T=2.0):
    """The gap (bin mean and minimum, in spacings) under the 2D dam break's surge at T."""
    from shoal.cases import dam_break_2d

    a = 0.146
    case = dam_break_2d(dp=dp, a=a, end_time=T / np.sqrt(2 * G / a), options=SPHOptions(wall_pressure=wall))
    case = case.model_copy(update={"output": Output(interval=case.end_time)})
    with tempfile.TemporaryDirectory() as tmp:
        shoal.run_case(case, Path(tmp), progress=False, plot=False)
        points, data = read_vtu(sorted(Path(tmp).glob("*.vtu"))[-1])
    fluid = data["kind"] == 0
    x, z = points[fluid, 0], points[fluid, 2]
    front = x[z < 0.1 * a].max()
    sel = (x >= 1.5 * a) & (x < front - 2 * dp)
    bins = np.floor((x[sel] - 1.5 * a) / dp).astype(int)
    mins = np.array([z[sel][bins == b].min() for b in np.unique(bins)])
    return dict(particles=case.n_particles, gap=float(mins.mean()) / dp, gap_min=float(mins.min()) / dp,
                front=front / a)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--wall", nargs="+", default=["dynamic", "adami"])
    ap.add_argument("--bed", nargs="+", default=["flat", "slope", "slope-fit", "stl", "surge"])
    ap.add_argument("--dp", type=float, default=0.01)
    ap.add_argument("--depth", type=float, default=0.2)
    ap.add_argument("--end", type=float, default=1.0)
    ap.add_argument("--surge-dp", type=float, default=0.146 / 30)
    a = ap.parse_args(argv)
    print(f"H = {a.depth} m, dp = {a.dp} m (H/dp = {a.depth / a.dp:g}), t = {a.end} s")
    print(f"{'bed':6} {'wall':8} {'particles':>9} {'gap/dp':>7} {'min/dp':>7}  bed pressure - rho0 g d [% rho0 g H]")
    for bed in a.bed:
        for wall in a.wall:
            if bed == "surge":
                r = measure_surge(a.surge_dp, wall)
                print(f"{bed:6} {wall:8} {r['particles']:9d} {r['gap']:7.2f} {r['gap_min']:7.2f}  (dp = "
                      f"{a.surge_dp:.4g} m; front at x = {r['front']:.2f} a)", flush=True)
                continue
            r = measure(bed, a.dp, a.depth, a.end, wall)
            errs = " ".join(f"{e:+.2f}" for e in r["pressure_err"])
            print(f"{bed:6} {wall:8} {r['particles']:9d} {r['gap']:7.2f} {r['gap_min']:7.2f}  {errs}", flush=True)


if __name__ == "__main__":
    main()
