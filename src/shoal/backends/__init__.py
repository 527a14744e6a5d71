"""Backends decide how per-particle loops run; the physics is shared."""

from .cpu import CPUBackend

BACKENDS = ("cpu", "cuda")


def check_backend(name):
    """Raise InputError unless backend `name` can run here."""
    from ..errors import InputError

    if name == "cuda":
        from .cuda import cuda_status

        ok, why = cuda_status()
        if not ok:
            raise InputError(f"backend 'cuda' is not available here: {why}; use --backend cpu")
        return
    if name not in BACKENDS:
        raise InputError(f"unknown backend {name!r}; allowed: {', '.join(map(repr, BACKENDS))}")


def get_backend(name, spec):
    """Return the backend called `name` compiled for `spec`."""
    check_backend(name)
    if name == "cuda":
        from .cuda import CUDABackend

        return CUDABackend(spec)
    return CPUBackend(spec)
