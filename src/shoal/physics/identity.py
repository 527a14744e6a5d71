"""Content identities of the compiled per-particle functions, and one compiled copy of each per process.

A scheme (`SchemeSpec`) has some twenty loop kernels, but most of them read few of its fields: the
equation of state's ``pr2`` loop depends on the precision only, the integrators' updates on the
precision, the dimension, XSPH and the wall condition. Named after the whole scheme, every kernel
would be compiled once per scheme: the fifty-odd schemes of the test suite compiled ``pr2`` 52 times
and the symplectic updates 26 times, a third of the suite's CPU time going to Numba.

A compiled function is instead named by what its compiled code is made of, read from the Python
function being compiled rather than from a list of the scheme fields it is believed to read (such a
list goes stale silently, and a kernel wrongly shared between two schemes gives one of them wrong
physics):

* its code: module, qualified name, first line, bytecode, constants and names, and those of the
  functions defined inside it;
* the values it captures (its closure cells) and its default arguments: numbers, booleans,
  strings, NumPy scalars and types, tuples of these, and other compiled functions, which enter
  by their own identity (so a function's identity changes when anything it calls changes);
* the values of the module globals it reads (a scalar by value, a module, class or function by
  its qualified name, the compiled code of which the source hash covers);
* the hash of the kernel sources (`source_hash`) and the target ("cpu", "cuda").

A scheme field reaches a compiled function only through these: a factory reads ``spec`` and
either picks one of several definitions (a different code) or captures a value derived from it (a
different closure). Two schemes that give a function the same code, captures and globals give it
the same compiled code, and share it; any difference in what the compiler sees separates them. A
captured value of any other type (an array, a plain Python function, the spec itself used inside
a kernel) is refused with a `TypeError` rather than keyed approximately.

`named` memoises the compiled functions by identity for the whole process, so that schemes sharing
a function share one dispatcher (compiled, or loaded from Numba's disk cache, once), and
`shared_loop` does the same for the loop kernels around them; the identity is also the
dispatcher's ``_uuid``, which names it in Numba's on-disk cache key and (through
`shoal.backends.cpu.cache_name`) the loop kernel's cache file.
"""

from __future__ import annotations

import hashlib
import types
from pathlib import Path

import numpy as np

_SOURCE = None

_COMPILED = {}
"""(decorator, identity) -> compiled function: every function `named` has compiled in this process."""

_LOOPS = {}
"""(loop builder, identity of the per-particle function) -> loop kernel (`shared_loop`)."""


def source_hash():
    """Hash of the kernel source files (physics, neighbours, timestepping, backends).

    Part of every compiled function's identity, so that editing any module a kernel inlines (not
    only the file that defines the outer loop, which is all Numba's cache checks) recompiles
    instead of loading a stale kernel. Computed once per process."""
    global _SOURCE
    if _SOURCE is None:
        root = Path(__file__).resolve().parent.parent
        files = [f for d in ("physics", "neighbours", "timestepping", "backends") for f in (root / d).rglob("*.py")]
        h = hashlib.sha1()
        for f in sorted(files):
            h.update(f.relative_to(root).as_posix().encode())
            h.update(f.read_bytes())
        _SOURCE = h.hexdigest()[:12]
    return _SOURCE


def identity_of(compiled):
    """The identity `named` gave `compiled`, or None for a function it did not compile."""
    return getattr(compiled, "_shoal_identity", None)


def _describe_value(value, where):
    """A deterministic text naming a value a function captures (closure cell or default argument).

    Raises TypeError for a value that cannot be named exactly (see the module docstring)."""
    ident = identity_of(value)
    if ident is not None:
        return f"fn[{ident}]"
    if isinstance(value, np.generic):  # before float: np.float64 is a float
        return f"np.{value.dtype.str}:{value.tobytes().hex()}"
    if value is None or isinstance(value, (bool, int, float, complex, str, bytes)):
        # repr of a Python float round-trips exactly
        return f"{type(value).__name__}:{value!r}"
    if isinstance(value, np.dtype):
        return f"dtype:{value.descr!r}"
    if isinstance(value, tuple):
        return "(" + ",".join(_describe_value(v, where) for v in value) + ")"
    if isinstance(value, type):
        return f"type:{value.__module__}.{value.__qualname__}"
    raise TypeError(f"{where}: cannot give a compiled function an identity when it captures a value of type "
                    f"{type(value).__module__}.{type(value).__qualname__}; capture a number, a boolean, a NumPy "
                    "scalar or type, a tuple of these, or a function compiled by shoal.physics.identity.named")


def _describe_global(value, where):
    """A deterministic text naming a module global a compiled function reads.

    Scalars and other compiled functions as captured values; modules, classes and module-level
    functions by their qualified name (their code is part of the source hash, or of a library)."""
    try:
        return _describe_value(value, where)
    except TypeError:
        pass
    if isinstance(value, types.ModuleType):
        return f"module:{value.__name__}"
    name = getattr(value, "__qualname__", None) or getattr(value, "__name__", None)
    module = getattr(value, "__module__", None) or type(value).__module__
    if name is None:
        # an intrinsic or a library object without a qualified name: its type and registered name
        name = getattr(value, "_name", None)
    if name is None:
        raise TypeError(f"{where}: cannot name the global of type {type(value).__qualname__} it reads")
    return f"{type(value).__qualname__}:{module}.{name}"


def _describe_constant(c):
    if isinstance(c, types.CodeType):
        return "code[" + _describe_code(c) + "]"
    if isinstance(c, tuple):
        return "(" + ",".join(_describe_constant(x) for x in c) + ")"
    if isinstance(c, frozenset):  # iteration order of a set of strings varies between processes
        return "frozenset{" + ",".join(sorted(_describe_constant(x) for x in c)) + "}"
    return f"{type(c).__name__}:{c!r}"


def _describe_code(code):
    """The code object's bytecode, constants (nested functions' code included) and names."""
    return "|".join([code.co_qualname if hasattr(code, "co_qualname") else code.co_name, str(code.co_firstlineno),
                     hashlib.sha256(code.co_code).hexdigest(),
                     ",".join(_describe_constant(c) for c in code.co_consts),
                     ",".join(code.co_names), ",".join(code.co_varnames), ",".join(code.co_freevars),
                     ",".join(code.co_cellvars)])


def _global_names(code):
    names = set(code.co_names)
    for c in code.co_consts:
        if isinstance(c, types.CodeType):
            names |= _global_names(c)
    return names


def fingerprint(fn, target):
    """The identity of a Python function compiled for a target.

    Parameters
    ----------
    fn : function
        The Python function about to be compiled (not yet decorated).
    target : str
        The compilation target ("cpu", "cuda"): the same source compiles to different code.

    Returns
    -------
    str
        ``shoal:<source hash>:<target>:<module>.<qualname>:<32 hex digits>``, the digits the start
        of a SHA-256 of everything the compiler sees of `fn` (see the module docstring): equal for
        two functions exactly when they compile to the same code.

    Raises
    ------
    TypeError
        When `fn` captures a value, or reads a global, that cannot be named exactly.
    """
    code = fn.__code__
    where = f"{fn.__module__}.{fn.__qualname__}"
    parts = [source_hash(), target, where, _describe_code(code)]
    for name, cell in zip(code.co_freevars, fn.__closure__ or ()):
        try:
            value = cell.cell_contents
        except ValueError:  # an empty cell: a function that refers to itself by its closure name
            raise TypeError(f"{where}: the closure variable {name!r} is not bound yet") from None
        parts.append(f"{name}={_describe_value(value, where)}")
    parts.append("defaults=" + _describe_value(tuple(fn.__defaults__ or ()), where))
    kw = fn.__kwdefaults__ or {}
    parts.append("kwdefaults=" + ",".join(f"{k}={_describe_value(kw[k], where)}" for k in sorted(kw)))
    glob = fn.__globals__
    for name in sorted(_global_names(code)):
        if name in glob:
            parts.append(f"global {name}={_describe_global(glob[name], where)}")
    digest = hashlib.sha256("\n".join(parts).encode()).hexdigest()[:32]
    return f"shoal:{source_hash()}:{target}:{where}:{digest}"


def named(jit, target):
    """Wrap a compiling decorator so that each function gets its content identity and is compiled
    once per process.

    Parameters
    ----------
    jit : callable
        The backend's decorator (`shoal.backends.cpu.cpu_jit`, `shoal.backends.cuda.cuda_device_jit`).
    target : str
        Names the target in the identity ("cpu", "cuda").

    Returns
    -------
    callable
        A decorator, with a method ``verify()`` to call once the factories have returned (see
        below). It takes the function's `fingerprint` first: a function of the same identity
        compiled before with `jit` (for another scheme, or another backend instance) is returned as
        it is, so its compiled code and its disk-cache load are shared; otherwise `jit` compiles it
        and the identity becomes its ``_uuid`` where the compiled object has one (Numba's CPU
        dispatchers: the on-disk cache key pickles the functions a kernel captures with their uuid,
        random by default, which must be the same in every process for the cache to hit).
    """

    decorated = []  # (function, identity) of every function decorated, for `verify`

    def deco(fn):
        ident = fingerprint(fn, target)
        decorated.append((fn, ident))
        key = (jit, ident)
        found = _COMPILED.get(key)
        if found is not None:
            return found
        d = jit(fn)
        if hasattr(d, "_set_uuid"):
            d._set_uuid(ident)
        d._shoal_identity = ident
        return _COMPILED.setdefault(key, d)

    def verify():
        """Raise RuntimeError if a function decorated so far now has another identity.

        Numba compiles at the first call, from the closure cells as they are then; a factory that
        assigned a captured variable again after decorating a function would compile it with a
        value its identity does not name. Called once the factories have returned (their cells are
        then final)."""
        for fn, ident in decorated:
            if fingerprint(fn, target) != ident:
                raise RuntimeError(f"{fn.__module__}.{fn.__qualname__}: a value it captures changed after it was "
                                   "decorated; its identity would not name the code compiled")
        decorated.clear()

    deco.verify = verify
    return deco


def shared_loop(fn, build):
    """The loop kernel around a per-particle function, built once per process and identity.

    Parameters
    ----------
    fn : compiled function
        The per-particle function the loop calls (compiled by `named`).
    build : callable
        The backend's loop builder, ``build(fn) -> run(n, args)``.

    Returns
    -------
    callable
        ``build(fn)``, or the loop built before for the same `build` and the same identity of `fn`:
        schemes whose `fn` is the same compiled function share one loop kernel. A function without
        an identity (not compiled by `named`) gets a loop of its own.
    """
    ident = identity_of(fn)
    if ident is None:
        return build(fn)
    key = (build, ident)
    found = _LOOPS.get(key)
    if found is None:
        found = _LOOPS.setdefault(key, build(fn))
    return found
