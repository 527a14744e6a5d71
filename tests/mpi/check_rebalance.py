"""Load balancing (tests/test_mpi.py): a 3D dam break from a deliberately unbalanced slab cut.

``python check_rebalance.py OUT.npz`` runs the single-process reference;
``mpiexec -n 2 python check_rebalance.py OUT.npz`` runs 2 ranks starting from
a cut that gives rank 0 a quarter of the weighted count, re-balanced every 5
steps (threshold 1.05); ``mpiexec -n N ... OUT.npz F1,F2,...`` starts from the
cuts at the weighted fractions F1, F2, ... (e.g. 0.8,0.9 on 3 ranks: the first
re-cut sends particles of rank 0 through rank 1 to rank 2). Both write the final state by particle id to OUT.npz
(rank 0), the MPI run also the re-cut records and the weighted counts at the
end, as JSON in the ``info`` entry.
"""

import json
import sys

import numpy as np

import shoal
import shoal.parallel as par
from shoal.cases.dam_break import dam_break_3d
from shoal.parallel.decomposition import weighted_counts
from shoal.parallel.decomposition import BOUNDARY_WEIGHT
from shoal.parallel.model import DistributedModel
from shoal.physics.spec import FLUID
from shoal.runner import build_model
from shoal.simulation import Simulation

END = 0.08
case = dam_break_3d(dp=0.02, end_time=END, options=shoal.SPHOptions(integrator="symplectic"))
out = sys.argv[1]
comm = par.world()
info = {}

if comm is None:
    model = build_model(case)
    Simulation(model, END).run()
    ids = model.idp[: model.n]
    order = np.argsort(ids)
    np.savez(out, ids=ids[order], pos=model.world_positions()[order], steps=0, info="{}")
    sys.exit(0)

p = case.particles()
x = p.positions[:, 0]
w = np.where(p.kinds == FLUID, 1.0, BOUNDARY_WEIGHT)
order = np.argsort(x, kind="stable")
cw = np.cumsum(w[order])
fracs = [float(f) for f in sys.argv[2].split(",")] if len(sys.argv) > 2 else [0.25]
start_cuts = []
for f in fracs:
    i = int(np.searchsorted(cw, f * cw[-1]))
    start_cuts.append(0.5 * (x[order][i - 1] + x[order][i]))


class Unbalanced(DistributedModel):
    def __init__(self, *args, **kw):
        super().__init__(*args, cuts=start_cuts, rebalance_interval=5, rebalance_threshold=1.05, **kw)


import shoal.parallel.model as pm  # noqa: E402

pm.DistributedModel = Unbalanced  # build_model looks it up at call time
model = build_model(case)
assert isinstance(model, Unbalanced)
model.sort()
start = weighted_counts(comm, model.weighted_count()).tolist()
sim = Simulation(model, END)
sim.run()
end = weighted_counts(comm, model.weighted_count()).tolist()
owned_counts = comm.allgather(int(model.n_owned))
own = model.owned
mine = (model.idp[: model.n][own].copy(), model.world_positions())
inside = bool(np.all((model.pos[: model.n, 0][own] >= model.cuts[model.mpi_rank])
                     & (model.pos[: model.n, 0][own] < model.cuts[model.mpi_rank + 1])))
# the run-time cut code on the ranks' slabs gives the start's cut code on the gathered particles
from shoal.parallel.decomposition import distributed_cuts, slab_cuts  # noqa: E402

wk = np.where(model.kind[: model.n][own] == FLUID, 1.0, BOUNDARY_WEIGHT)
dcuts = distributed_cuts(comm, model.pos[: model.n, 0][own], wk, model.halo_width, keys=model.idp[: model.n][own])
xw = comm.gather((model.pos[: model.n, 0][own].copy(), wk), root=0)
parts = comm.gather(mine, root=0)
inside_all = comm.gather(inside, root=0)
if comm.Get_rank() == 0:
    ids = np.concatenate([q[0] for q in parts])
    pos = np.concatenate([q[1] for q in parts])
    order = np.argsort(ids)
    xa = np.concatenate([q[0] for q in xw])
    wa = np.concatenate([q[1] for q in xw])
    serial = slab_cuts(xa, wa, comm.Get_size(), model.halo_width)
    info = {"distributed_cuts": dcuts[1:-1].tolist(), "serial_cuts": serial[1:-1].tolist(), "start_cuts": start_cuts,
            "weighted_start": start, "weighted_end": end, "owned_end": owned_counts,
            "rebalances": model.rebalances, "steps": sim.step_count, "owned_inside_slab": all(inside_all),
            "n_global": model.n_global, "cuts_end": model.cuts[1:-1].tolist()}
    np.savez(out, ids=ids[order], pos=pos[order], steps=sim.step_count, info=json.dumps(info))
