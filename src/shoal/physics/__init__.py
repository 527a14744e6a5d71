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
from .density_diffusion import make_density_diffusion
from .eos import make_eos
from .forces import make_wall_force
from .filters import make_filters
from .free_surface import make_free_surface
from .interpolation import make_probe, make_sensor_moments
from .kernels import make_kernels
from .rates import make_rates
from .spec import FIXED, FLUID, MOVING, Params, SchemeSpec, make_params, make_unpack
from .planes import make_plane_force
from .turbulence import make_sps
from .no_slip import make_wall_velocity
from .wall_pressure import make_wall_pressure
from .mdbc import make_mdbc
from .viscosity import make_viscosity

__all__ = ["build_physics", "SchemeSpec", "Params", "make_params", "FLUID", "FIXED", "MOVING"]


def _source_hash():
    """Hash of the kernel source files (physics, neighbours, timestepping,
    backends): part of every compiled function's cache
    identity, so that editing any module a kernel inlines (not only the file
    that defines the outer loop, which is all Numba's cache checks)
    recompiles instead of loading a stale kernel."""
    import hashlib
    from pathlib import Path

    root = Path(__file__).resolve().parent.parent
    files = [f for d in ("physics", "neighbours", "timestepping", "backends") for f in (root / d).rglob("*.py")]
    h = hashlib.sha1()
    for f in sorted(files):
        h.update(f.relative_to(root).as_posix().encode())
        h.update(f.read_bytes())
    return h.hexdigest()[:12]


_SOURCE = None


def _named(jit, prefix):
    """Wrap `jit` so each compiled function gets a deterministic identity.

    Numba's on-disk cache keys a closure on its captured values; compiled
    functions captured by other closures are keyed by their uuid, random by
    default. Naming them after the scheme makes the cache hit across runs.
    """
    count = [0]

    def deco(fn):
        d = jit(fn)
        count[0] += 1
        if hasattr(d, "_set_uuid"):
            name = f"{prefix}:{fn.__module__}.{fn.__qualname__}#{count[0]}"
            d._set_uuid(name)
        return d
    return deco


def build_physics(jit, spec, target="cpu"):
    """Compile the per-particle physics of `spec` with decorator `jit`.

    Returns a namespace with ``pressure``, ``particle_pr2``, ``particle_rates``, ``shepard``,
    ``mls``, ``w`` and ``grad_factor``.
    """
    global _SOURCE
    if _SOURCE is None:
        _SOURCE = _source_hash()
    j = _named(jit, f"shoal:{_SOURCE}:{target}:{spec.key}")
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
    probe = make_probe(j, spec, (w, grad_factor), pressure, make_point_gather, unpack)
    sensor_moments = make_sensor_moments(j, spec, (w, grad_factor), pressure, make_point_gather, unpack)
    wet_walls, free_surface = make_free_surface(j, spec, (w, grad_factor), make_gather, unpack)
    return SimpleNamespace(w=w, grad_factor=grad_factor, pressure=pressure,
                           particle_pr2=particle_pr2, particle_rates=particle_rates, shepard=shepard, mls=mls,
                           particle_sps=particle_sps, particle_wall_velocity=particle_wall_velocity,
                           particle_wall_pressure=particle_wall_pressure, particle_mdbc=particle_mdbc,
                           particle_wall_force=particle_wall_force,
                           probe=probe, sensor_moments=sensor_moments, free_surface=free_surface, wet_walls=wet_walls,
                           named_jit=j,
                           unpack=unpack)
