"""One GPU per rank (tests/test_mpi_cuda.py): a tiny 2D dam break on 2 ranks with the CUDA backend.

``mpiexec -n 2 python check_cuda.py OUT_DIR STEPS`` (on GPUs, or with ``NUMBA_ENABLE_CUDASIM=1`` in
the ranks' environment: Numba's CUDA simulator) runs the dam break of `make_case` (float64,
symplectic, variable time step) for STEPS steps on 2 ranks through ``shoal.run_case(...,
backend="cuda")`` (the path of ``mpiexec shoal run --backend cuda``: run.log, resolved.json,
.pvtu snapshots, the final checkpoint) into OUT_DIR, from a deliberately unbalanced slab cut
(rank 0 holds 30 % of the weighted count) re-balanced at the 5th sort, the start of step 3
(every 4 sorts, threshold 1.05; ``run_case`` sorts once before the Simulation's first sort), so
the run has a re-cut and a migration (the whole state through host memory) besides the halo
refreshes of every rate evaluation (send and ghost rows only). The ranks' device arrays are sized to
their own particles and estimated ghosts with 4 spare rows, so rank 0's must grow (be reallocated) when the re-cut sends
it particles. Rank 0 then runs
the same case on one process with the CPU backend and prints one line ``RESULTS {json}``: the
particle ids of both runs, the largest differences by id of the positions, velocities and
densities, of the simulated times and of a probe sampled across the slab cut, the re-cut records
and the GPU assignment.
"""

import json
import os
import sys

import numpy as np

import shoal
import shoal.parallel as par
from shoal.cases import dam_break_2d
from shoal.parallel.decomposition import BOUNDARY_WEIGHT
from shoal.parallel.model import DistributedModel
from shoal.physics.spec import FLUID
from shoal.runner import build_model

from shoal.simulation import Simulation

A = 0.146
OUT = sys.argv[1]
STEPS = int(sys.argv[2]) if len(sys.argv) > 2 else 5
# probe points across the water column (x-z plane), on both sides of the cuts
POINTS = np.array([[0.03, 0.0, 0.05], [0.06, 0.0, 0.12], [0.09, 0.0, 0.05], [0.12, 0.0, 0.2]])


def make_case():
    """176 particles (72 fluid), dp = a / 6 = 24 mm, a tank 2a long, float64 (round-off is then
    small enough to see a stale ghost), cells of 2h (the simulator's sort is what costs: fewer
    cells, fewer radix passes)."""
    return dam_break_2d(dp=A / 6, a=A, layers=2, tank_length=2 * A, end_time=1.0, output_interval=1.0,
                        options=shoal.SPHOptions(precision="float64", integrator="symplectic", cells_per_support=1))


def by_id(ids, *arrays):
    order = np.argsort(ids)
    return (ids[order],) + tuple(a[order] for a in arrays)


comm = par.world()
assert comm is not None and comm.Get_size() == 2, "run under mpiexec -n 2"
rank = comm.Get_rank()
case = make_case()
p = case.particles()
x = p.positions[:, 0]
order = np.argsort(x, kind="stable")
cw = np.cumsum(np.where(p.kinds == FLUID, 1.0, BOUNDARY_WEIGHT)[order])
i = int(np.searchsorted(cw, 0.3 * cw[-1]))
start_cut = 0.5 * (x[order][i - 1] + x[order][i])


class Unbalanced(DistributedModel):
    spare_rows = 4

    def rows_wanted(self, owned, ghosts):  # tight, so that rank 0's arrays must grow at the re-cut
        return min(owned + ghosts + self.spare_rows, self.n_global)

    def __init__(self, *args, **kw):
        super().__init__(*args, cuts=[start_cut], rebalance_interval=4, rebalance_threshold=1.05, **kw)


import shoal.parallel.model as pm  # noqa: E402

pm.DistributedModel = Unbalanced  # build_model looks it up at call time
run = shoal.run_case(case, OUT, backend="cuda", plot=False, max_steps=STEPS)
model, sim = run.model, run.simulation
assert isinstance(model, Unbalanced) and model.backend.name == "cuda"
own = model.owned
mine = (model.host(model.idp)[own], model.world_positions(), model.world_velocities(),
        model.host(model.rho)[own].astype(np.float64))
# the last rate evaluation's rates: zero in the ghost rows (zeroed on the device), not in the owned ones
ace, drho = model.host(model.ace), model.host(model.drho)
ghost_rates = comm.allgather((bool(np.all(ace[~own] == 0) and np.all(drho[~own] == 0)), int(np.count_nonzero(~own)),
                              bool(np.any(ace[own] != 0))))
probe = model.sample(POINTS)  # collective: each point from the rank whose slab holds it
parts = comm.gather(mine, root=0)
counts = comm.allgather(int(model.n_owned))
ghosts = comm.allgather(int(model.n_ghost))
sizes = comm.allgather((int(model.capacity), int(model.store.resizes), int(model.pos.shape[0]), int(model.grid.capacity),
                        int(sim.integrator.pos_n.shape[0])))
if rank == 0:
    ids, pos, vel, rho = by_id(*(np.concatenate([q[k] for q in parts]) for k in range(4)))
    saved, par._world = par._world, None  # the single-process CPU run on this rank
    try:
        ref = build_model(case, "cpu")
    finally:
        par._world = saved
    rsim = Simulation(ref, 1.0).run(max_steps=STEPS)
    rids, rpos, rvel, rrho = by_id(ref.host(ref.idp).copy(), ref.world_positions(), ref.world_velocities(),
                                   ref.host(ref.rho).astype(np.float64))
    rprobe = ref.sample(POINTS)
    same = bool(np.array_equal(ids, rids))
    res = {
        "n_particles": case.n_particles, "n_ranks": len(parts), "ids_equal": same,
        "ids_unique": bool(len(np.unique(ids)) == len(ids)), "n_ids": int(len(ids)),
        "ids_missing": np.setdiff1d(rids, ids).tolist(), "ids_doubled": np.unique(ids[1:][ids[1:] == ids[:-1]]).tolist(),
        "steps": [sim.step_count, rsim.step_count], "time": [sim.time, rsim.time],
        "moved": float(np.max(np.abs(rpos - case.particles().positions[rids]))),
        "max_speed": float(np.max(np.linalg.norm(rvel, axis=1))),
        "pos_err": float(np.max(np.abs(pos - rpos))) if same else None,
        "vel_err": float(np.max(np.abs(vel - rvel))) if same else None,
        "rho_err": float(np.max(np.abs(rho - rrho))) if same else None,
        "probe_err": float(max(np.nanmax(np.abs(np.asarray(probe[k]) - np.asarray(rprobe[k])))
                               for k in ("pressure", "density", "velocity"))),
        "probe_finite": bool(np.all(np.isfinite(probe["density"]))),
        "ghost_rates_zero": all(g[0] for g in ghost_rates), "ghost_rows": [g[1] for g in ghost_rates],
        "owned_rates_nonzero": all(g[2] for g in ghost_rates),
        "rebalances": model.rebalances, "start_cut": start_cut, "cuts_end": model.cuts[1:-1].tolist(),
        "owned_end": counts, "ghosts_end": ghosts, "capacity": [c[0] for c in sizes],
        "resizes": [c[1] for c in sizes], "array_rows": [c[2:] for c in sizes], "gpus": model.gpus, "wall_seconds": sim.wall_seconds,
    }
    print("RESULTS " + json.dumps(res, default=float), flush=True)
