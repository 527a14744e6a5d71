"""Compile every CUDA kernel shoal launches for a real GPU, on a machine without one.

Numba's CUDA simulator runs the kernels as Python, so it cannot catch a kernel that Numba's CUDA
compiler rejects (a construct the CUDA target does not support, a type that only real typing
fails to unify, a float64 literal that turns a float32 kernel's arithmetic double). Two steps:

1. `record(path)`, in a simulator process (the child of ``tests/test_cuda_parity.py``): every
   kernel launch of the session is logged with its argument types -- the loop kernels
   (`shoal.backends.loops`) by their scheme specialisation and name, the others (cell grid and
   radix sort, reductions, MPI row kernels) by their qualified name.
2. `compile_logged(path, cc)`, in a process without the simulator and without a GPU: each logged
   kernel is built again from the same source and compiled by NVVM to PTX for compute capability
   `cc` (``numba.cuda.compile_ptx``), for its logged argument types; the physics loops
   (`shoal.backends.loops.PHYSICS_LOOPS`) also for the scheme specialisations of the built-in cases
   (the argument types of a loop depend on the precision only).

3. `float64_in_pair_loops(ptx)`: the double-precision instructions inside the innermost loops of
   a compiled kernel (in `rates`, the loops over a particle's neighbours), other than the ones
   meant to be there: positions are float64 in every precision, so a float32 pair loop loads the
   neighbour's coordinates as float64, subtracts and rounds the difference to float32
   (``ld.global.f64``, ``sub.f64``, ``cvt.rn.f32.f64``), with a periodic axis or a symmetry plane
   shifts or mirrors it first (``add.f64``, ``selp.f64``), and nothing else.

NVVM comes from the CUDA toolkit wheels of ``numba-cuda[cu13]`` (the test extra); no driver is
needed: the device functions' compile asks for the current device's compute capability, which is
answered with `cc` while compiling.
"""

from __future__ import annotations

import contextlib
import pickle
from types import SimpleNamespace

import numpy as np

# -- step 1: recording launches under the simulator


def _describe(value):
    """A picklable description of one kernel argument's Numba type."""
    from numba.cuda.simulator.cudadrv.devicearray import FakeCUDAArray

    if isinstance(value, FakeCUDAArray):
        t = value._numba_type_
        return ("array", value._ary.dtype, t.ndim, t.layout)
    if isinstance(value, tuple):
        return ("tuple", tuple(_describe(v) for v in value))
    if isinstance(value, (bool, np.bool_)):
        return ("scalar", "bool")
    if isinstance(value, int):
        return ("scalar", "<i8")
    if isinstance(value, float):
        return ("scalar", "<f8")
    if isinstance(value, np.generic):
        return ("scalar", value.dtype.str)
    raise TypeError(f"cannot describe a kernel argument of type {type(value).__name__}")


def record(path):
    """Log every kernel launch of this (simulator) process to `path` (a pickle, written at exit)."""
    import atexit

    from numba.cuda.simulator import kernel as simk

    import shoal.backends.cuda as bc

    loops = {}  # id of a loop kernel's Python function -> (spec, loop name, the function: kept alive, so
    #             that its id is not reused by a later function)
    seen = set()
    log = []

    init = bc.CUDABackend.__init__

    def tracking_init(self, spec):
        init(self, spec)
        for name, run in vars(self).items():
            kernel = getattr(run, "kernel", None)
            if isinstance(kernel, simk.FakeCUDAKernel):  # a loop of `make_for_each`
                loops[id(kernel.fn)] = (spec, name, kernel.fn)

    call = simk.FakeCUDAKernel.__call__

    def logging_call(self, *args):
        if not self._device and not simk._kernel_context:
            fn = self.fn
            key = ("loop",) + loops[id(fn)][:2] if id(fn) in loops else ("fn", fn.__module__, fn.__qualname__)
            entry = (key, tuple(_describe(a) for a in args))
            if entry not in seen:
                seen.add(entry)
                log.append(entry)
        return call(self, *args)

    bc.CUDABackend.__init__ = tracking_init
    simk.FakeCUDAKernel.__call__ = logging_call

    def dump():
        with open(path, "wb") as f:
            pickle.dump(log, f)

    atexit.register(dump)


# -- step 2: compiling the logged kernels for a GPU


def _numba_type(desc):
    from numba import types
    from numba.np import numpy_support

    kind = desc[0]
    if kind == "array":
        _, dtype, ndim, layout = desc
        return types.Array(numpy_support.from_dtype(dtype), ndim, layout)
    if kind == "tuple":
        return types.BaseTuple.from_types([_numba_type(d) for d in desc[1]])
    if desc[1] == "bool":
        return types.boolean
    return numpy_support.from_dtype(np.dtype(desc[1]))


@contextlib.contextmanager
def _device_cc(cc):
    """Answer 'the current device' with compute capability `cc` while compiling (no driver here)."""
    import numba.cuda.dispatcher as dispatcher

    saved = dispatcher.get_current_device
    dispatcher.get_current_device = lambda: SimpleNamespace(compute_capability=tuple(cc))
    try:
        yield
    finally:
        dispatcher.get_current_device = saved


def _fixed_kernels():
    """{qualified name: dispatcher} of the kernels outside the loops, as a GPU run builds them."""
    import shoal.backends.cuda as bc
    import shoal.neighbours.cuda_grid as grid

    out = {}
    rows = [k for pair in bc._row_kernels().values() for k in pair]
    for k in (*grid._kernels(grid.DEFAULT_BLOCK).values(), *bc._reductions()[:2], *rows, *bc._body_kernels()):
        out[k.py_func.__qualname__] = k
    return out


def case_spec(case):
    """The `SchemeSpec` a `Case` runs with (as `shoal.runner.build_model` sets it up), without
    generating its particles."""
    from shoal.physics.spec import SchemeSpec

    symmetry = 0
    if case.symmetry_planes:
        symmetry = 1 if case.symmetry_planes[0].normal[1] < 0 else 2
    return SchemeSpec.from_options(case.options, case.dim, tuple(case.domain.periodic) if case.domain else (),
                                   repulsive=any(s.boundary == "repulsive" for s in case.solids),
                                   planes=bool(case.planes), symmetry=symmetry)


BUILTIN_VARIANTS = {"tidal-bore": [dict(dim=2), dict(half=True)], "tidal-bore-piers": [dict(half=True)],
                    "rip-current": [dict(boundary="repulsive")]}
"""Keyword variants of the built-in cases that change their scheme specialisation."""


def builtin_specs():
    """The scheme specialisations of the built-in cases (default options, and `BUILTIN_VARIANTS`)."""
    from shoal.cases import CASES

    specs = set()
    for name, factory in CASES.items():
        for kwargs in [{}] + BUILTIN_VARIANTS.get(name, []):
            specs.add(case_spec(factory(**kwargs)))
    return sorted(specs, key=repr)


def compile_logged(path, cc=(9, 0), extra_specs=(), extra_loops=None, one_per_loop=False):
    """Compile every kernel logged in `path` (and each loop for `extra_specs`: those named in
    `extra_loops`, default all) to PTX for `cc`. With `one_per_loop`, a physics loop other than
    `rates` logged for several scheme specialisations is compiled for the first of each precision
    and dimension only (every loop's source compiled at least once per precision and dimension;
    every `rates`, the kernels outside the loops and the `extra_specs` loops all compiled).

    Returns
    -------
    done : list of (str, float)
        (kernel, compile seconds) of each compile, in order.
    missing : list of str
        Physics loops of `extra_specs` whose argument types were never logged for their precision
        (not compiled: a parity test in that precision should launch them).
    rates_ptx : dict of str to (SchemeSpec, str)
        The PTX of each `rates` kernel compiled, by its label in `done`.
    """
    import time

    from numba import cuda

    from shoal.backends.cuda import cuda_device_jit, make_for_each
    from shoal.backends.loops import attach_loops

    with open(path, "rb") as f:
        log = pickle.load(f)
    # the argument types of each loop by precision, from any logged specialisation
    loop_types = {}
    for key, args in log:
        if key[0] == "loop":
            loop_types.setdefault((key[1].precision, key[2]), args)
    jobs, seen = {}, set()
    for key, args in log:
        if one_per_loop and key[0] == "loop" and key[2] != "rates":
            kind = (key[2], key[1].precision, key[1].dim)
            if kind in seen:
                continue
            seen.add(kind)
        jobs[(key, args)] = None
    from shoal.backends.loops import PHYSICS_LOOPS

    missing = []
    for spec in extra_specs:
        for name in PHYSICS_LOOPS:  # the update loops depend on the precision and dimension only
            if extra_loops is not None and name not in extra_loops:
                continue
            args = loop_types.get((spec.precision, name))
            if args is None:
                missing.append(f"{name} [{spec.dim}D {spec.precision}]")
            else:
                jobs[(("loop", spec, name), args)] = None
    backends, fixed = {}, None
    done, rates_ptx = [], {}
    with _device_cc(cc):
        for key, args in jobs:
            if key[0] == "loop":
                spec, name = key[1], key[2]
                if spec not in backends:
                    backends[spec] = SimpleNamespace()
                    attach_loops(backends[spec], cuda_device_jit, make_for_each, spec, "cuda")
                fn = getattr(backends[spec], name).kernel.py_func
                label = f"{name} [{spec.dim}D {spec.precision}, {_spec_flags(spec)}]"
            else:
                if fixed is None:
                    fixed = _fixed_kernels()
                fn = fixed[key[2]].py_func
                label = key[2]
            sig = tuple(_numba_type(a) for a in args)
            t0 = time.perf_counter()
            ptx, _ = cuda.compile_ptx(fn, sig, cc=tuple(cc))
            if key[0] == "loop" and key[2] == "rates":  # the hot kernel: to machine code, for its resources
                label += " " + machine_code_resources(ptx, cc)
                rates_ptx[label] = (key[1], ptx)
            done.append((label, time.perf_counter() - t0))
    return done, sorted(set(missing)), rates_ptx


POSITION_F64 = frozenset({"ld.global.f64", "sub.f64", "cvt.rn.f32.f64"})
"""The double-precision instructions a float32 pair loop is meant to have: the float64 positions'
difference, rounded to float32 (`shoal.physics` takes pair distances that way)."""
IMAGE_F64 = frozenset({"add.f64", "selp.f64"})
"""And with a periodic axis or a symmetry plane: the neighbour's image position, shifted by the
period or mirrored in the plane, in float64 like every position (adds and selects, no products)."""


def allowed_f64(spec):
    """The double-precision instructions a float32 pair loop of scheme `spec` may hold."""
    return POSITION_F64 | IMAGE_F64 if (spec.periodic or spec.symmetry) else POSITION_F64


def float64_in_pair_loops(ptx, allowed=POSITION_F64):
    """{opcode: count} of the double-precision instructions (opcodes with ``.f64``) in the innermost
    loops of `ptx` that are not in `allowed`, and the number of innermost loops.

    A loop is a backward branch (``bra`` to a label above it); innermost loops contain no other
    loop. In a `rates` kernel these are the walks over a particle's neighbour candidates: what runs
    once per pair.
    """
    import collections
    import re

    lines = ptx.splitlines()
    labels = {}
    for k, line in enumerate(lines):
        m = re.match(r"^(\$L__BB\d+_\d+):", line)
        if m:
            labels[m.group(1)] = k
    loops = []
    for k, line in enumerate(lines):
        m = re.search(r"\bbra(?:\.uni)?\s+(\$L__BB\d+_\d+);", line)
        if m and labels.get(m.group(1), len(lines)) < k:
            loops.append((labels[m.group(1)], k))
    inner = [a for a in loops if not any(b != a and a[0] <= b[0] and b[1] <= a[1] for b in loops)]
    extra = collections.Counter()
    for a, b in inner:
        for line in lines[a:b + 1]:
            m = re.match(r"\s*(?:@!?%p\d+\s+)?([a-z][\w.]*)\s", line)
            if m and ".f64" in m.group(1) and m.group(1) not in allowed:
                extra[m.group(1)] += 1
    return dict(extra), len(inner)


def machine_code_resources(ptx, cc):
    """Assemble `ptx` to machine code for `cc` with nvJitLink (no driver needed) and return
    ptxas's summary: registers per thread, spill stores / loads, stack."""
    r = resources(ptx, cc)
    return (f"({r['registers']} registers, {r['spill_stores']} B spill stores, {r['spill_loads']} B spill loads, "
            f"{r['stack']} B stack)")


def resources(ptx, cc, max_registers=None):
    """ptxas's resources of the kernel in `ptx` assembled for `cc` by nvJitLink (no driver needed), as the
    CUDA backend links it (`max_registers`: the register cap the backend passes, ``SHOAL_CUDA_MAX_REGISTERS``):
    dict of registers a thread, spill stores and loads [bytes], stack frame [bytes]."""
    import re

    from cuda.core import Linker, LinkerOptions, ObjectCode

    options = LinkerOptions(arch=f"sm_{cc[0]}{cc[1]}", verbose=True, max_register_count=max_registers)
    linker = Linker(ObjectCode.from_ptx(ptx.encode()), options=options)
    linker.link("cubin")
    info = linker.get_info_log()
    regs = re.search(r"Used (\d+) registers", info)
    spill = re.search(r"(\d+) bytes stack frame, (\d+) bytes spill stores, (\d+) bytes spill loads", info)
    if not regs or not spill:
        raise RuntimeError(f"no resource summary in the ptxas log: {info[-500:]}")
    return dict(registers=int(regs.group(1)), spill_stores=int(spill.group(2)), spill_loads=int(spill.group(3)),
                stack=int(spill.group(1)))


def occupancy(registers, threads=128, sm_registers=65536, sm_threads=2048, sm_blocks=32):
    """The share of an SM's threads that blocks of `threads` threads using `registers` registers each keep
    resident, by registers alone (shared memory unused): registers are allocated to a warp in multiples of
    256 (8 a thread) on compute capability 7.0-9.0."""
    per_warp = -(-registers * 32 // 256) * 256
    warps = -(-threads // 32)
    blocks = min(sm_registers // (per_warp * warps), sm_threads // threads, sm_blocks)
    return blocks * threads / sm_threads


def _spec_flags(spec):
    flags = [f"kernel {spec.kernel}", f"viscosity {spec.viscosity}", f"diffusion {spec.diffusion}"]
    for name in ("tensile", "xsph", "sps", "repulsive", "planes", "no_slip", "wall_pressure"):
        if getattr(spec, name):
            flags.append(name)
    if spec.periodic:
        flags.append(f"periodic {spec.periodic}")
    if spec.symmetry:
        flags.append(f"symmetry {spec.symmetry}")
    return ", ".join(flags)
