"""Run under ``mpiexec -n N``: halo, migration and rates of a DistributedModel
against the single-process Model of the same particles (tests/test_mpi.py).

Prints one line per check on rank 0: ``CHECK name value`` and exits non-zero
when a check fails.
"""

import json
import sys

import numpy as np

import shoal
import shoal.parallel as par
from shoal.cases.dam_break import dam_break_3d
from shoal.parallel.model import DistributedModel
from shoal.physics.spec import FLUID
from shoal.runner import build_model

comm = par.world()
assert comm is not None and comm.Get_size() > 1, "run under mpiexec -n 2 or more"
rank = comm.Get_rank()
results = {}


def reference(case):
    saved, par._world = par._world, None  # build the single-process Model on this rank
    try:
        return build_model(case)
    finally:
        par._world = saved


def perturb(m, ids, seed):
    """The same random displacement and velocity by particle id on both models."""
    rng = np.random.default_rng(seed)
    n_all = m.n_global if isinstance(m, DistributedModel) else m.n_total
    dx = rng.uniform(-0.2, 0.2, (n_all, m.dim)) * m.dp
    dv = rng.normal(0.0, 0.3, (n_all, m.dim))
    drho = rng.uniform(-2.0, 2.0, n_all)
    fluid = m.kind[: m.n] == FLUID
    k = ids[fluid]
    m.pos[: m.n][fluid] += dx[k]
    m.vel[: m.n][fluid] += dv[k].astype(m.dtype)
    m.rho[: m.n] += drho[ids].astype(m.dtype)


def rates_by_id(m):
    n = m.n
    ids = m.idp[:n].copy()
    own = m.owned if isinstance(m, DistributedModel) else np.ones(n, bool)
    # with mDBC the walls' densities are set by the rates' first pass, from the fluid at their ghost nodes
    cols = [m.ace[:n].astype(np.float64), m.drho[:n, None].astype(np.float64), m.rho[:n, None].astype(np.float64)]
    if m.spec.xsph:
        cols.append(m.xsph[:n].astype(np.float64))
    return ids[own], np.hstack(cols)[own]


def compare(name, options, tank_length=1.5 * 0.146):
    # a short tank, so that the slab cut runs through the water column
    case = dam_break_3d(dp=0.012, tank_length=tank_length, options=options)
    ref = reference(case)
    perturb(ref, ref.idp[: ref.n].copy(), 1)
    ref.sort()
    ref.compute_rates()
    rid, rr = rates_by_id(ref)
    ref_dt = ref.time_step_limit()
    dm = build_model(case)
    assert isinstance(dm, DistributedModel)
    perturb(dm, dm.idp[: dm.n].copy(), 1)
    dm.sort()
    dm.compute_rates()
    did, dr = rates_by_id(dm)
    dt = dm.time_step_limit()
    parts = comm.gather((did, dr), root=0)
    if rank == 0:
        ids = np.concatenate([p[0] for p in parts])
        vals = np.concatenate([p[1] for p in parts])
        assert len(ids) == len(np.unique(ids)) == len(rid), (len(ids), len(np.unique(ids)), len(rid))
        full = np.empty_like(rr)
        full[rid] = rr
        scale = np.abs(full).max(axis=0) + 1e-30
        err = float((np.abs(vals - full[ids]) / scale).max())
        # particles within 2h of a cut (where the halo matters)
        near = np.zeros(len(rid), bool)
        pos = ref.pos[: ref.n, 0]
        for c in dm.cuts[1:-1]:
            near |= np.abs(pos - c) < 2 * ref.h
        near &= ref.kind[: ref.n] == FLUID
        results[f"{name}_rates_rel_err"] = err
        results[f"{name}_fluid_near_cut"] = int(near.sum())
        results[f"{name}_dt_rel_err"] = abs(dt - ref_dt) / ref_dt
        results[f"{name}_ghosts_rank0"] = int(dm.n_ghost)
    return dm, ref


def particle_probes(dm, ref):
    """Trackers, max-z and run-up gauges over a region across the cut: the DistributedModel's
    (each rank's owned particles, combined over the ranks) equal the single-process Model's on the
    same particles exactly (the same float64 positions; max and selection are exact), on every rank;
    then the ghosts are moved 1 m up and everything must be unchanged (owned particles only)."""
    from shoal.probes import MaxZGauge, RunupGauge

    cut, dp = float(dm.cuts[1]), dm.dp
    W = float(ref.world_positions()[:, 1].max())
    top = float(ref.world_positions()[ref.kind[: ref.n] == FLUID, 2].max())
    gauges = [MaxZGauge(name="m", x=cut, y=0.5 * W, radius=2 * dp, interval=1.0),
              MaxZGauge(name="m2", x=cut + 0.5 * dp, y=0.5 * W, radius=0.4 * dp, interval=1.0),
              MaxZGauge(name="dry", x=9.0, y=0.5 * W, radius=0.3 * dp, interval=1.0),
              RunupGauge(name="r", x0=cut - 4 * dp, x1=cut + 4 * dp, interval=1.0),
              RunupGauge(name="rb", x0=cut - 4 * dp, x1=cut + 4 * dp, y=0.5 * W, band=2 * dp, interval=1.0),
              RunupGauge(name="rw", x0=cut - 4 * dp, x1=cut + 4 * dp, landward="-x", interval=1.0)]
    ties = [0.0, 0.0, 0.0, 0.25 * dp, 0.5 * dp, 0.5 * dp]
    # ids on both sides of the cut (and near it), the nearest to points around the cut and above the water
    x_ref = ref.world_positions()[:, 0]
    ids_ref = ref.idp[: ref.n]
    fluid = ref.kind[: ref.n] == FLUID
    near = ids_ref[fluid][np.argsort(np.abs(x_ref[fluid] - cut))[:20]]
    ids = np.concatenate([near, ids_ref[fluid][:3], ids_ref[fluid][-3:]])
    points = [(cut, 0.5 * W, 0.5 * top), (cut - dp, 0.3 * W, top), (cut + 0.3 * dp, 0.7 * W, top + 1.0),
              (cut - 0.5 * dp, 0.5 * W, top + 0.9)]

    def measure(m):
        return (m.particle_positions(ids), m.nearest_fluid(points),
                np.array([m.highest_fluid(g, t) for g, t in zip(gauges, ties)]))

    want = measure(ref)
    got = measure(dm)
    dm.pos[dm.halo.ghost_rows, dm.dim - 1] += 1.0  # ghosts 1 m up: an owned-only measurement is unchanged
    moved = measure(dm)
    dm.pos[dm.halo.ghost_rows, dm.dim - 1] -= 1.0
    same = all(np.array_equal(a, b, equal_nan=True) for a, b in zip(want, got))
    same_moved = all(np.array_equal(a, b, equal_nan=True) for a, b in zip(want, moved))
    everywhere = comm.allgather(tuple(np.concatenate([np.ravel(a) for a in got])))
    ids_per_rank = comm.allgather(int(np.isin(ids, dm.idp[: dm.n][dm.owned]).sum()))
    # the run-up's highest particle and its landward end on different sides of the cut (the two-phase reduction)
    hf = want[2]
    split = 0
    for k, (g, t) in enumerate(zip(gauges, ties)):
        if isinstance(g, RunupGauge):
            sel = fluid & (x_ref >= g.x0) & (x_ref <= g.x1)
            zx = ref.world_positions()[sel]
            highest_x = zx[np.argmax(zx[:, 2]), 0]
            split += int((highest_x < cut) != (hf[k, 1] < cut))
    if rank == 0:
        results["particle_probes_equal"] = bool(same)
        results["particle_probes_ghosts_ignored"] = bool(same_moved)
        results["particle_probes_same_on_every_rank"] = bool(all(
            np.array_equal(np.array(e), np.array(everywhere[0]), equal_nan=True) for e in everywhere))
        results["particle_probes_ids_per_rank"] = ids_per_rank
        results["particle_probes_runup_split_across_cut"] = split
        results["particle_probes_dry_is_nan"] = bool(np.all(np.isnan(hf[2])))


def migration(dm):
    """Push fluid particles across the first cut both ways; each must be on exactly one rank."""
    cut = dm.cuts[1]
    n = dm.n
    own = dm.owned
    fluid = (dm.kind[:n] == FLUID) & own
    x = dm.pos[:n, 0]
    moved = []
    if rank == 0:  # the 5 fluid particles nearest the cut go just across it
        cand = np.flatnonzero(fluid)
        pick = cand[np.argsort(cut - x[cand])[:5]]
        dm.pos[pick, 0] = cut + 0.3 * dm.h
        moved = dm.idp[pick].tolist()
    elif rank == 1:
        cand = np.flatnonzero(fluid)
        pick = cand[np.argsort(x[cand] - cut)[:5]]
        dm.pos[pick, 0] = cut - 0.3 * dm.h
        moved = dm.idp[pick].tolist()
    moved_all = sum(comm.allgather(moved), [])
    dm.sort()
    ids = dm.idp[: dm.n][dm.owned]
    xs = dm.pos[: dm.n, 0][dm.owned]
    mine = [int(i) for i in moved_all if i in set(ids.tolist())]
    inside = bool(np.all((xs >= dm.cuts[rank]) & (xs < dm.cuts[rank + 1])))
    every = comm.gather((ids.copy(), mine, inside), root=0)
    if rank == 0:
        all_ids = np.concatenate([e[0] for e in every])
        results["migration_unique"] = bool(len(all_ids) == len(np.unique(all_ids)) == dm.n_global)
        results["migration_moved_on_one_rank"] = bool(
            sorted(sum([e[1] for e in every], [])) == sorted(moved_all) and len(moved_all) == 10)
        results["migration_owned_inside_slab"] = bool(all(e[2] for e in every))


dm, ref = compare("default", shoal.SPHOptions())
particle_probes(dm, ref)
migration(dm)
compare("sps_xsph_symplectic", shoal.SPHOptions(turbulence="sps", xsph=0.5, integrator="symplectic",
                                                 density_diffusion="fourtakas", delta=0.1))
# mDBC walls: a halo 4h deep at least (2.25h leaves 3e-3 of error here), and the end walls' ghost nodes
# 6 dp off them: a tank long enough for two slabs of that width
compare("mdbc", shoal.SPHOptions(wall_pressure="mdbc"), tank_length=2.5 * 0.146)
# the Riemann terms with DBC walls (the narrow 2.25h halo): the wall term reads the walls' normals by id
compare("riemann", shoal.SPHOptions(riemann=True, alpha=0.0, density_diffusion="none", wall_pressure="dynamic"))
if rank == 0:
    print("RESULTS " + json.dumps(results))
    ok = (results["default_rates_rel_err"] < 1e-5 and results["sps_xsph_symplectic_rates_rel_err"] < 1e-5
          and results["mdbc_rates_rel_err"] < 1e-5 and results["riemann_rates_rel_err"] < 1e-5
          and results["migration_unique"] and results["migration_moved_on_one_rank"]
          and results["migration_owned_inside_slab"] and results["default_fluid_near_cut"] > 0
          and results["default_dt_rel_err"] < 1e-6 and results["particle_probes_equal"]
          and results["particle_probes_ghosts_ignored"] and results["particle_probes_same_on_every_rank"])
    sys.exit(0 if ok else 1)
