"""Run probes over the snapshots a run saved (offline post-processing).

The same recorders as during a run (`make_recorder`) sample a model
rebuilt from each snapshot (positions, velocities, densities, kinds, ids) with
the run's resolved case (``case.toml``), on the same backend kernels: the
interpolation is the same as in the run, only at the snapshot times.
"""

from __future__ import annotations

from pathlib import Path
from types import SimpleNamespace

import numpy as np

from ..errors import InputError
from ..physics.spec import FIXED, MOVING, REPULSIVE, REPULSIVE_MOVING


def load_run(run_dir):
    """(case, snapshot entries [(time, file name)]) of a finished run directory; InputError when it
    holds no resolved case or no readable snapshot collection."""
    from ..casefile import load_case
    from ..output.pvd import read_pvd

    run_dir = Path(run_dir)
    case_file = run_dir / "case.toml"
    if not case_file.is_file():
        raise InputError(f"{run_dir} holds no case.toml: not a shoal run directory")
    case = load_case(case_file)
    pvds = sorted(run_dir.glob("*.pvd"))
    if not pvds:
        raise InputError(f"{run_dir} holds no .pvd snapshot collection")
    try:
        entries = read_pvd(pvds[0])
    except ValueError as err:
        raise InputError(f"cannot read the snapshot collection {err}") from None
    return case, entries


def model_from_snapshot(case, path, backend="cpu"):
    """A sorted `Model` of the particles of one snapshot (positions, velocities, densities, kinds and
    ids) with the run's resolved `case`, on `backend`. Moving walls become fixed walls where the
    snapshot has them (no motion offline)."""
    from ..model import Model
    from ..output.vtu import read_vtu

    lo, hi = case.resolved_domain()
    fl = case.fluid
    pos, data = read_vtu(path)
    kinds = np.asarray(data["kind"], np.int8).copy()
    kinds[kinds == MOVING] = FIXED
    kinds[kinds == REPULSIVE_MOVING] = REPULSIVE
    model = Model(np.asarray(pos, float), kinds, dp=case.dp, dim=case.dim, domain=(lo, hi),
                  options=case.options, rho0=fl.rho0, gravity=fl.gravity, fluid_height=fl.depth, u_max=fl.u_max,
                  velocities=np.asarray(data["velocity"], float),
                  periodic=tuple(case.domain.periodic) if case.domain else (),
                  planes=[(p.point, p.normal) for p in case.planes], backend=backend)
    rho = np.asarray(data["density"], model.dtype)
    ids = np.asarray(data["id"], model.idp.dtype)  # the run's particle ids (rows are in cell order)
    if model.backend.name == "cpu":
        model.rho[:] = rho
        model.idp[:] = ids
    else:
        model.rho.copy_to_device(rho)
        model.idp.copy_to_device(ids)
    model.sort()
    model.body_of = case.particles().body.astype(np.int32)  # ids are the case's particle numbers
    model.body_names = [s.name for s in case.solids]
    return model


def run_probes_offline(run_dir, probes, out_dir=None, backend="cpu"):
    """Sample `probes` (probe specs) at every snapshot of the run in `run_dir`.

    Writes the probes' files to `out_dir` (default ``run_dir / "offline"``)
    and returns their recorders (with the rows they wrote).
    """
    from . import make_recorder

    run_dir = Path(run_dir)
    case, entries = load_run(run_dir)
    out_dir = Path(out_dir) if out_dir is not None else run_dir / "offline"
    out_dir.mkdir(parents=True, exist_ok=True)
    recorders = None
    for time, name in entries:
        model = model_from_snapshot(case, run_dir / name, backend)
        if recorders is None:
            recorders = [make_recorder(p, out_dir, case.dp, model) for p in probes]
        state = SimpleNamespace(time=float(time), model=model)
        for rec in recorders:
            rec(state)
    for rec in recorders or []:
        rec.close()
    return recorders or []
