"""Backends decide how per-particle loops run; the physics is shared."""

from .cpu import CPUBackend

BACKENDS = ("cpu",)


def get_backend(name, spec):
    """Return the backend called `name` compiled for `spec`."""
    from ..errors import InputError

    if name == "cpu":
        return CPUBackend(spec)
    if name == "cuda":
        raise InputError("backend 'cuda' is not available in this version of shoal yet; allowed: 'cpu'")
    raise InputError(f"unknown backend {name!r}; allowed: {', '.join(map(repr, BACKENDS))}")
