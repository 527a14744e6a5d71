"""The loop kernels every backend offers, built from the shared physics.

`attach_loops` compiles the per-particle functions of `shoal.physics` and
`shoal.timestepping.updates` (the integrators' updates) with a backend's decorator and wraps each in
that backend's particle loop, so both backends expose the same kernels
(``pr2``, ``rates``, ``sps``, ``shepard``, ``mls``, ``verlet``, ``save_state``,
``half_step``, ``symplectic_correct``, ``pc_correct``; ``damp``, ``relax``, ``hold_buffers``,
``hold_shift``, ``shift``, ``shift_apply``, ``move_bodies``, ``rotate_wall_vectors``, ``wrap_periodic``) from one source.
"""

from ..neighbours.gather import make_gather
from ..physics import build_physics
from ..physics.body_motion import make_body_motion, make_wall_vector_rotation
from ..physics.buffer_hold import make_buffer_hold, make_shift_hold
from ..physics.damping import make_damping
from ..physics.periodic_wrap import make_periodic_wrap
from ..physics.relaxation import make_relaxation
from ..physics.shifting import make_shifting
from ..timestepping.updates import make_updates

PHYSICS_LOOPS = {"pr2": "particle_pr2", "rates": "particle_rates", "shepard": "shepard", "mls": "mls",
                 "sps": "particle_sps", "wall_velocity": "particle_wall_velocity",
                 "wall_pressure": "particle_wall_pressure", "mdbc": "particle_mdbc", "wall_force": "particle_wall_force", "contact": "particle_contact", "probe": "probe",
                 "sensor_moments": "sensor_moments",
                 "free_surface": "free_surface",
                 "wet_walls": "wet_walls"}


def attach_loops(backend, jit, for_each, spec, target):
    """Set the loop kernels of `spec` as attributes of `backend`.

    Parameters
    ----------
    backend : object receiving the kernels and ``physics`` (the compiled functions).
    jit : decorator compiling a per-particle function for the target.
    for_each : ``fn -> run(n, args)`` wrapping a per-particle function in a loop.
    spec : SchemeSpec.
    target : str, names the specialisation in Numba's cache ("cpu", "cuda").
    """
    phys = build_physics(jit, spec, target=target)
    backend.physics = phys
    for name, fn in PHYSICS_LOOPS.items():
        setattr(backend, name, for_each(getattr(phys, fn)))
    for name, fn in make_updates(phys.named_jit, spec, phys.unpack).items():
        setattr(backend, name, for_each(fn))
    backend.move_bodies = for_each(make_body_motion(phys.named_jit, spec))
    backend.rotate_wall_vectors = for_each(make_wall_vector_rotation(phys.named_jit, spec))
    backend.wrap_periodic = for_each(make_periodic_wrap(phys.named_jit, spec, phys.unpack))
    backend.damp = for_each(make_damping(phys.named_jit, spec))
    backend.relax = for_each(make_relaxation(phys.named_jit, spec))
    backend.hold_buffers = for_each(make_buffer_hold(phys.named_jit, spec))
    backend.hold_shift = for_each(make_shift_hold(phys.named_jit, spec))
    shift, shift_apply = make_shifting(phys.named_jit, spec, (phys.w, phys.grad_factor), phys.surface_normal,
                                       make_gather, phys.unpack)
    backend.shift = for_each(shift)
    backend.shift_apply = for_each(shift_apply)
    phys.named_jit.verify()  # every factory has returned: the identities name what will be compiled


def row_columns(arrays):
    """(array, first column, width) of each of `arrays` laid side by side in a row buffer (the MPI
    halo's `pack_rows` / `unpack_rows` of both backends): one column per 1D array, w per (N, w) one."""
    c = 0
    for a in arrays:
        w = 1 if a.ndim == 1 else a.shape[1]
        yield a, c, w
        c += w
