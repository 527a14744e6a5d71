"""The WCSPH physics, written once as per-particle functions.

`build_physics(jit, spec)` compiles every per-particle function of a scheme
with the given decorator: ``numba.njit`` for the CPU backend (a ``prange``
loop calls them) or ``numba.cuda.jit(device=True)`` for the CUDA backend
(one thread per particle calls them). Each concern lives in its own module:
`kernels`, `eos`, `viscosity`, `density_diffusion`, `turbulence`, `rates`,
`filters`.
"""

from types import SimpleNamespace

from ..neighbours.gather import make_gather, make_point_gather
from ..neighbours.half_sweep import make_half_gather
from .density_diffusion import make_density_diffusion
from .eos import make_eos
from .contact import make_contact
from .forces import make_wall_force
from .filters import make_filters
from .free_surface import make_free_surface
from .identity import named
from .interpolation import make_probe, make_sensor_moments
from .kernels import make_kernels
from .rates import make_rates
from .spec import FIXED, FLUID, MOVING, Params, SchemeSpec, make_params, make_unpack
from .planes import make_plane_force
from .turbulence import make_sps
from .no_slip import make_wall_velocity
from .wall_pressure import make_wall_pressure
from .mdbc import make_mdbc
from .mutual import make_particle_mutual, mutual_supported
from .viscosity import make_viscosity

__all__ = ["build_physics", "SchemeSpec", "Params", "make_params", "FLUID", "FIXED", "MOVING"]


def build_physics(jit, spec, target="cpu"):
    """Compile the per-particle physics of `spec` with decorator `jit`.

    Each function is compiled through `identity.named`: it is named by its content (code, captured
    values, the functions it calls) rather than by the whole scheme, so a function that two schemes
    build alike is one compiled function, shared within the process and in Numba's disk cache.

    Returns a namespace with ``pressure``, ``particle_pr2``, ``particle_rates``, ``shepard``,
    ``mls``, ``w`` and ``grad_factor`` (and the other per-particle functions of the loops, the
    decorator ``named_jit`` and ``unpack``); ``mutual_tile``, the CPU's rates a pair at a time
    (`shoal.physics.mutual`), where the target is the CPU and the scheme allows, else None.
    """
    j = named(jit, target)
    unpack = make_unpack(j)
    w, grad_factor = make_kernels(j, spec)
    pressure = make_eos(j, spec)
    viscous = make_viscosity(j, spec)
    diffusion = make_density_diffusion(j, spec)
    plane_accel = make_plane_force(j, spec)
    particle_pr2, particle_rates = make_rates(j, spec, (w, grad_factor), pressure, viscous, diffusion,
                                              make_gather, unpack, plane_accel,
                                              compact=target == "cpu")
    shepard, mls = make_filters(j, spec, (w, grad_factor), make_gather, unpack)
    particle_sps = make_sps(j, spec, (w, grad_factor), make_gather, unpack)
    particle_wall_velocity = make_wall_velocity(j, spec, (w, grad_factor), make_gather, unpack)
    particle_wall_pressure = make_wall_pressure(j, spec, (w, grad_factor), pressure, make_gather, unpack)
    particle_mdbc = make_mdbc(j, spec, (w, grad_factor), make_point_gather, unpack)
    particle_wall_force = make_wall_force(j, spec, (w, grad_factor), viscous, make_gather, unpack)
    particle_contact = make_contact(j, spec, make_gather, unpack)
    probe = make_probe(j, spec, (w, grad_factor), pressure, make_point_gather, unpack)
    sensor_moments = make_sensor_moments(j, spec, (w, grad_factor), pressure, make_point_gather, unpack)
    wet_walls, free_surface, surface_normal = make_free_surface(j, spec, (w, grad_factor), make_gather, unpack)
    # the CPU's rates a pair at a time, where the scheme's pair terms allow (`shoal.physics.mutual`)
    mutual_tile = None
    if target == "cpu" and mutual_supported(spec):
        mutual_tile, _ = make_particle_mutual(j, spec, (w, grad_factor), viscous, diffusion, make_half_gather, unpack,
                                              plane_accel)
    return SimpleNamespace(w=w, grad_factor=grad_factor, pressure=pressure,
                           particle_pr2=particle_pr2, particle_rates=particle_rates, shepard=shepard, mls=mls,
                           particle_sps=particle_sps, particle_wall_velocity=particle_wall_velocity,
                           particle_wall_pressure=particle_wall_pressure, particle_mdbc=particle_mdbc,
                           particle_wall_force=particle_wall_force, particle_contact=particle_contact,
                           probe=probe, sensor_moments=sensor_moments, free_surface=free_surface, wet_walls=wet_walls,
                           surface_normal=surface_normal, mutual_tile=mutual_tile,
                           named_jit=j,
                           unpack=unpack)
