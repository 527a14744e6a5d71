"""Where the floating box's extra lift comes from: the fluid's force on the box held at Archimedes' draft,
taken apart.

The box of `shoal validate archimedes` (density rho0 / 2), held fixed with its bottom at the draft that floats
it (the water around it at the still-water level), runs until the water has settled; then the vertical force of
the fluid on its particles (the coupling's sum, `Model.wall_forces`) is compared with its weight, and the pair
sum of the pressure term (`shoal.physics.forces`) is evaluated again in NumPy with parts of the state replaced:

* the simulation's fluid pressures and wall pressures (checks that the NumPy sum is the solver's);
* the wall pressure (Adami et al. 2012) without its clamp at zero;
* the fluid's pressure replaced by the linear hydrostatic field rho0 g (eta - z), eta the level the deep
  water's pressure gives (a fit away from the box), with and without the clamp;
* the same at the design level (the still-water level the case starts with).

The differences give the share of each: the fluid's pressure near the free surface above the linear field,
the level, the clamp, and what is left of the pair sum on the lattice. Also printed: the fluid's pressure
above that linear field by layers near the free surface, by horizontal distance from the box.

    python validation/archimedes/force_budget.py --dim 3 --dp 0.025 --time 0.5
    python validation/archimedes/force_budget.py --dim 2 --dp 0.02 --time 1.0
"""

from __future__ import annotations

import argparse

import numpy as np
from scipy.spatial import cKDTree

from shoal.physics.eos import pressure_of, tait_coefficient
from shoal.physics.kernels import WENDLAND, grad_factor_array
from shoal.physics.spec import kernel_normalisation
from shoal.simulation import Simulation
from shoal.validation.archimedes import archimedes_case

RHO, G = 1000.0, 9.81


def held_box(dim, dp, end_time):
    """The Archimedes case of `dim` at `dp` (3D: the quick case's box and tank) with the box held at its draft,
    run to `end_time`; returns the model and the box's corners."""
    kw = dict(dim=dim, dp=dp, offset=0.0, end_time=end_time,
              floating=dict(fixed=["x", "y", "z", "rx", "ry", "rz"]))
    if dim == 3:
        kw.update(beam=0.2, height=0.1, depth=0.2, length=0.4, interval=0.005)
    case = archimedes_case(**kw)
    assert case.options.kernel == "wendland", "the NumPy sums below are Wendland's"
    box = case.solids[1]
    sim = Simulation(case)
    while sim.time < end_time:
        sim.step()
    return sim.model, np.array(box.shape.lo), np.array(box.shape.hi), box.floating.density


def budget(dim, dp, end_time):
    m, lo, hi, density = held_box(dim, dp, end_time)
    f, ids = m.wall_forces()
    rows = m.owned_rows()
    pos = m.host(m.pos)[rows].astype(float)
    rho = m.host(m.rho)[rows].astype(float)
    axes = [0, 1, 2] if dim == 3 else [0, 2]
    lo, hi = lo[axes], hi[axes]
    solid = np.full(len(ids), -1)
    walls = ids < len(m.body_of)
    solid[walls] = m.body_of[ids[walls]]
    fluid, body = solid == -1, solid == 1
    p = pressure_of(rho, RHO, tait_coefficient(m.c0, RHO))
    h = m.h
    aw = kernel_normalisation(WENDLAND, dim, h)

    def w(q):
        return aw * np.clip(1 - q / 2, 0, None) ** 4 * (2 * q + 1)

    weight = density * G * np.prod(hi - lo)
    fp, frho, fpr = pos[fluid], rho[fluid], p[fluid]
    z = fp[:, -1]
    centre, half = (lo + hi) / 2, (hi - lo) / 2
    outside = np.max(np.abs(fp[:, :-1] - centre[:-1]) - half[:-1], axis=1)  # horizontal distance from the box
    deep = (outside > 2 * dp) & (z < lo[-1])
    slope, icpt = np.polyfit(z[deep], fpr[deep], 1)
    eta = -icpt / slope
    design = lo[-1] + (hi[-1] - lo[-1]) * density / RHO
    bidx = np.where(body)[0]
    near = cKDTree(fp).query_ball_point(pos[bidx], 2 * h)
    mass = RHO * dp ** dim

    def lift(fluid_p, clamp=True, solver_wall=False, solver_density=False):
        """Fz / W - 1 of the pressure pair sum: the fluid's pressure `fluid_p`, the wall pressure the solver's
        (`solver_wall`) or Adami's from `fluid_p` (clamped at 0 with `clamp`), the densities the solver's
        (`solver_density`) or rho0."""
        fz = 0.0
        for i, js in zip(bidx, near):
            js = np.asarray(js, int)
            if not len(js):
                continue
            r = pos[i] - fp[js]
            q = np.linalg.norm(r, axis=1) / h
            pf = fluid_p(js)
            rb, rf = (rho[i], frho[js]) if solver_density else (RHO, RHO)
            if solver_wall:
                pb = p[i]
            else:
                wq = w(q)
                pb = (np.sum(pf * wq) - G * np.sum(rf * r[:, -1] * wq)) / max(np.sum(wq), 1e-300)
                pb = max(pb, 0.0) if clamp else pb
            fz += np.sum(mass * mass * (pf / rf ** 2 + pb / rb ** 2) * -grad_factor_array(WENDLAND, dim, h, q)
                         * r[:, -1])
        return fz / weight - 1

    def hydrostatic(level):
        return lambda js: np.clip(RHO * G * (level - fp[js, -1]), 0, None)

    print(f"{dim}D, dp = {dp} m, H = {(hi[-1] - lo[-1]) / dp:.0f} dp, box held at its draft for {end_time} s; "
          f"a change of draft of 0.1 dp changes the lift by {0.1 * dp * RHO / (density * (hi[-1] - lo[-1])):.2%}")
    print(f"  deep water: dp/dz = {-slope / (RHO * G):.4f} rho0 g, level eta = design {(eta - design) / dp:+.3f} dp")
    rows = [("the coupling's sum (all terms)", f[body, -1].sum() / weight - 1),
            ("pressure pair sum, the solver's fluid and wall pressures",
             lift(lambda js: fpr[js], solver_wall=True, solver_density=True)),
            ("  the wall pressure Adami's again", lift(lambda js: fpr[js], solver_density=True)),
            ("  the same without its clamp at 0", lift(lambda js: fpr[js], clamp=False, solver_density=True)),
            ("fluid pressure rho0 g (eta - z)", lift(hydrostatic(eta))),
            ("  wall pressure without its clamp", lift(hydrostatic(eta), clamp=False)),
            ("fluid pressure rho0 g (design level - z)", lift(hydrostatic(design))),
            ("  wall pressure without its clamp", lift(hydrostatic(design), clamp=False))]
    for name, v in rows:
        print(f"  Fz / W - 1 = {v:+.4f}   {name}")
    res = (fpr - np.polyval((slope, icpt), z)) / (RHO * G * dp)
    top = z.max()
    print("  fluid pressure above the deep water's linear field [rho0 g dp], by layer below the top particle:")
    for band in [(0, 1), (1, 3), (3, 6)]:
        m_ = (outside > band[0] * dp) & (outside <= band[1] * dp)
        cells = []
        for k in range(4):
            mm = m_ & (z > top - (k + 0.5) * dp) & (z <= top - (k - 0.5) * dp)
            if mm.any():
                cells.append(f"layer {k}: {res[mm].mean():+.3f}")
        print(f"    {band[0]}-{band[1]} dp from the box: " + ", ".join(cells))


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--dim", type=int, choices=(2, 3), default=3)
    ap.add_argument("--dp", type=float, default=0.025)
    ap.add_argument("--time", type=float, default=0.5, help="how long the water settles around the held box [s]")
    a = ap.parse_args(argv)
    budget(a.dim, a.dp, a.time)


if __name__ == "__main__":
    main()
