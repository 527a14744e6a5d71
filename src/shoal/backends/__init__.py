"""Backends decide how per-particle loops run; the physics is shared."""

from .cpu import CPUBackend

BACKENDS = ("cpu",)


def check_backend(name):
    """Raise InputError unless backend `name` can run here."""
    from ..errors import InputError

    if name == "cuda":
        raise InputError("backend 'cuda' is not available in this version of shoal yet; allowed: 'cpu'")
    if name not in BACKENDS:
        raise InputError(f"unknown backend {name!r}; allowed: {', '.join(map(repr, BACKENDS))}")


def get_backend(name, spec):
    """Return the backend called `name` compiled for `spec`."""
    check_backend(name)
    return CPUBackend(spec)
