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
        elif pr.type == "grid":  # the nodes' reach from lo, hi and counts (`axes()` of billions of nodes: no memory)
            for a, (p0, p1, n, name) in enumerate(zip(pr.lo, pr.hi, pr.counts, "xyz")):
                first, last = (min(p0, p1), max(p0, p1)) if n > 1 else (0.5 * (p0 + p1),) * 2
                if a in axes and (first < lo[a] - tol or last > hi[a] + tol):
                    raise InputError(f"{where}: its nodes reach {name} = [{first:.4g}, {last:.4g}] m, outside the "
                                     f"domain {dom}; a grid must lie inside it")
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



def check_buried_probes(case):
    """`InputError` for a wave gauge, max-z gauge or probe point buried in fixed solids.

    A point is buried when it lies inside the shapes of the solids without a motion, and so do the
    points half a particle spacing from it along each axis (a point on a wall's face is not
    buried). Fluid is generated only where no solid is, and fixed walls neither move nor let it
    through, so a buried point never has water at it: a probe there records NaN or nonsense for
    the whole run. A gauge is refused when every point of its column within the domain is buried.

    Parameters
    ----------
    case : shoal.Case
    """
    from ..geometry.generate import support_layers

    columns = []  # (description, (M, 3) points) of each probe that must not be buried whole
    lo, hi = case.resolved_domain()
    dp = case.dp
    for i, pr in enumerate(case.probes):
        where = f"probes[{i}] ({pr.type} {pr.name!r})"
        if pr.type in ("gauge", "maxz"):
            z0, z1 = (pr.z0, pr.z1) if pr.type == "gauge" else (lo[2], hi[2])
            z0, z1 = max(z0, lo[2]), min(z1, hi[2])
            if z1 < z0:
                continue
            zs = np.linspace(z0, z1, max(2, int(np.ceil((z1 - z0) / (0.5 * dp))) + 1))
            pts = np.column_stack([np.full(len(zs), pr.x), np.full(len(zs), pr.y if case.dim == 3 else 0.0), zs])
            columns.append((f"{where}: its whole column x = {pr.x:g} m"
                            + (f", y = {pr.y:g} m" if case.dim == 3 else "") + f", z = {z0:.4g} .. {z1:.4g} m", pts))
        elif pr.type == "points":
            columns += [(f"{where}: points[{k}] = {list(pt)}", np.asarray([pt], float)) for k, pt in enumerate(pr.points)]
    fixed = [(k, s) for k, s in enumerate(case.solids) if s.motion is None]
    if not columns or not fixed:
        return
    axes = [0, 2] if case.dim == 2 else [0, 1, 2]
    offsets = [np.zeros(3)]
    for a in axes:
        for sign in (-0.5, 0.5):
            o = np.zeros(3)
            o[a] = sign * dp
            offsets.append(o)
    offsets = np.array(offsets)
    layers = support_layers(2.0 * case.smoothing_length / dp)
    for what, pts in columns:
        probe = (pts[:, None, :] + offsets[None, :, :]).reshape(-1, 3)
        covered = np.zeros(len(probe), bool)
        owner = -1
        for k, s in fixed:
            inside = s.shape.contains(probe, case.dim, (s.layers or layers) * dp)
            if owner < 0 and inside.reshape(len(pts), -1)[:, 0].any():
                owner = k
            covered |= inside
        buried = covered.reshape(len(pts), -1).all(axis=1)
        if buried.all():
            s = case.solids[owner]
            raise InputError(f"{what} lies inside solids[{owner}] ({s.name or s.shape.type}) and no water can "
                             "reach it there: it would record NaN or nonsense for the whole run; move it into the "
                             "water")
