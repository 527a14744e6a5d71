"""Where a case's probes stand: each must measure something in the domain."""

from __future__ import annotations

import numpy as np

from ..errors import InputError


def check_probes(case, n_particles):
    """`InputError` for a probe that would measure nothing: a point, gauge,
    grid node or tracker start outside the computational domain, a run-up
    range that misses it, a tracked id that is no particle."""
    lo, hi = case.resolved_domain()
    axes = (0, 2) if case.dim == 2 else (0, 1, 2)
    flat = (0,) if case.dim == 2 else (0, 1)
    dom = " x ".join(f"[{lo[a]:.4g}, {hi[a]:.4g}]" for a in axes) + (" m (x, z)" if case.dim == 2 else " m (x, y, z)")
    tol = 1e-9 * max(1.0, float(np.max(np.abs(np.concatenate([lo, hi])))))

    def outside(pt, which=axes):
        return any(not (lo[a] - tol <= pt[a] <= hi[a] + tol) for a in which)

    for i, pr in enumerate(case.probes):
        where = f"probes[{i}] ({pr.type} {pr.name!r})"
        if pr.type in ("points", "tracker", "pressure"):
            pts = pr.start if pr.type == "tracker" else pr.points
            for k, pt in enumerate(pts):
                if outside(pt):
                    key = "start" if pr.type == "tracker" else "points"
                    raise InputError(f"{where}: {key}[{k}] = {list(pt)} lies outside the domain {dom}; a probe must "
                                     "lie inside it")
            bad = [j for j in getattr(pr, "ids", []) if j >= n_particles]
            if bad:
                raise InputError(f"{where}: ids {bad[:5]} are no particles; the case has {n_particles:,} "
                                 f"(ids 0 to {n_particles - 1:,})")
        elif pr.type in ("gauge", "maxz"):
            if outside((pr.x, pr.y, 0.0), flat):
                xy = f"x = {pr.x:g}" + (f", y = {pr.y:g}" if case.dim == 3 else "")
                raise InputError(f"{where}: {xy} lies outside the domain {dom}; a gauge must stand inside it")
            if pr.type == "gauge" and (pr.z1 < lo[2] or pr.z0 > hi[2]):
                raise InputError(f"{where}: z0 .. z1 = {pr.z0:g} .. {pr.z1:g} m misses the domain's z range "
                                 f"[{lo[2]:.4g}, {hi[2]:.4g}] m")
        elif pr.type == "grid":
            for a, (node_axis, name) in enumerate(zip(pr.axes(), "xyz")):
                if a in axes and (node_axis.min() < lo[a] - tol or node_axis.max() > hi[a] + tol):
                    raise InputError(f"{where}: its nodes reach {name} = [{node_axis.min():.4g}, "
                                     f"{node_axis.max():.4g}] m, outside the domain {dom}; a grid must lie inside it")
        elif pr.type == "flow":
            a = "xyz".index(pr.axis)
            if case.dim == 2 and pr.axis == "y":
                raise InputError(f"{where}: axis = 'y' in a 2D run (the x-z plane); allowed 'x' or 'z'")
            if not lo[a] - tol <= pr.at <= hi[a] + tol:
                raise InputError(f"{where}: the section {pr.axis} = {pr.at:g} m lies outside the domain {dom}")
            if pr.lo is not None and pr.hi is not None:
                for k in axes:
                    if k != a and pr.hi[k] == pr.lo[k]:
                        raise InputError(f"{where}: lo[{k}] = hi[{k}] = {pr.lo[k]:g} m: the section has no extent in "
                                         f"{'xyz'[k]}; give hi[{k}] > lo[{k}], or leave lo and hi out")
        elif pr.type == "force":
            names = [s.name for s in case.solids]
            if pr.solid not in names:
                raise InputError(f"{where}: solid = {pr.solid!r} is none of the case's solids; allowed: "
                                 + ", ".join(repr(n) for n in names))
            if case.solids[names.index(pr.solid)].boundary != "dynamic":
                raise InputError(f"{where}: solid {pr.solid!r} has repulsive (Monaghan-Kajtar) boundary particles; "
                                 "force gauges measure solids of dynamic boundary particles (boundary = 'dynamic')")
        elif pr.type == "runup":
            if pr.x1 < lo[0] or pr.x0 > hi[0] or (case.dim == 3 and outside((0.0, pr.y, 0.0), (1,))):
                raise InputError(f"{where}: x0 .. x1 = {pr.x0:g} .. {pr.x1:g} m"
                                 + (f" at y = {pr.y:g} m" if case.dim == 3 else "")
                                 + f" misses the domain {dom}")
