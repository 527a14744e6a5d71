"""The `Model` of a `Case`: its particles generated and its scheme compiled."""

from __future__ import annotations

import numpy as np

from .active_absorption import absorbing_paddles
from .body_coupling import floating_bodies
from .errors import InputError
from .joints import joint_loads
from .model import Model
from .motions import check_motion_speeds
from .physics.spec import FIXED, FLUID, MOVING, REPULSIVE, REPULSIVE_MOVING
from .probes.placement import check_buried_probes, check_probes


def build_model(case, backend="cpu"):
    """The `Model` of a `Case`: generate its particles and compile the scheme."""
    case.revalidate()  # a copy (model_copy) skipped the checks across its fields
    p = case.particles()
    check_probes(case, len(p))  # a probe outside the domain or a tracked id that is no particle
    check_buried_probes(case)  # a gauge or probe point inside a fixed wall
    check_motion_speeds(case.motions, case.sound_speed, case.end_time, case.motion_reach())  # a wall faster than sound
    sym = None
    if case.symmetry_planes:
        if len(case.symmetry_planes) > 1:
            raise InputError("one symmetry plane per case is supported")
        sp = case.symmetry_planes[0]
        n = np.asarray(sp.normal, float)
        if case.dim != 3 or abs(abs(n[1]) - 1.0) > 1e-9:
            raise InputError(f"symmetry plane normal {list(sp.normal)}: only planes y = const (normal [0, 1, 0] or "
                             "[0, -1, 0]) in 3D cases are supported")
        sym = (float(sp.point[1]), float(np.sign(n[1])))
    index = {m.name: k for k, m in enumerate(case.motions)}
    floating, moorings = floating_bodies(case, case.fluid.gravity)
    k_float = iter(range(len(case.motions), len(case.motions) + len(floating)))
    body_motion = np.array([next(k_float) if s.floating is not None else index.get(s.motion, -1) if s.motion else -1
                            for s in case.solids] + [-1], np.int32)
    motion_of = np.where(p.body >= 0, body_motion[p.body], -1)
    kinds = p.kinds.copy()
    rep = np.array([s.boundary == "repulsive" for s in case.solids] + [False])
    on_rep = (p.body >= 0) & rep[p.body]
    kinds[on_rep & (p.kinds == FIXED)] = REPULSIVE
    kinds[on_rep & (p.kinds == MOVING)] = REPULSIVE_MOVING
    fl = case.fluid
    still = fl.surface_level
    if still is None and any(getattr(m, "absorption", None) is not None for m in case.motions):
        still = float(p.positions[p.kinds == FLUID, 2].max()) + 0.5 * case.dp  # the top layer's surface
    motions = absorbing_paddles(case.motions, p.positions, motion_of, still_water=still, dp=case.dp,
                                h=Model.smoothing_length(case.options, case.dim, case.dp), dim=case.dim)
    motions = list(motions) + floating  # after the case's motions: the rows body_motion gave them
    from .parallel import world

    cls = Model
    if world() is not None:  # under mpiexec with several ranks: this rank's slab (shoal.parallel)
        from .parallel.model import DistributedModel as cls
    model = cls(p.positions, kinds, dp=case.dp, dim=case.dim, domain=case.resolved_domain(),
                options=case.options, rho0=fl.rho0, gravity=fl.gravity, fluid_height=fl.depth, u_max=fl.u_max,
                surface_z=fl.surface_level, velocities=p.velocities, motions=motions, motion_of=motion_of,
                wall_normals=p.normals,
                periodic=tuple(case.domain.periodic) if case.domain else (),
                planes=[(pl.point, pl.normal) for pl in case.planes], symmetry_y=sym, backend=backend)
    model.floating.moorings = moorings
    model.floating.joints = joint_loads(case, [b.name for b in floating], [b.body for b in floating])
    if case.open_boundaries:
        from .particle_buffers import BufferZones

        model.buffers = BufferZones(model, case.open_boundaries, p.zone, case.lattice_origin,
                                    float(np.linalg.norm(fl.gravity)))
    model.body_of = p.body.astype(np.int32)  # the solid of each particle id (-1: fluid), for force gauges
    model.body_names = [s.name for s in case.solids]
    return model
