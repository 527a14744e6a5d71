"""Schemes share a compiled kernel exactly when they build it alike (`shoal.physics.identity`).

A compiled function is named by its code, the values it captures and the compiled functions it
calls, so two schemes (`SchemeSpec`) that differ only in fields a kernel does not read get the same
compiled loop object (compiled, or loaded from Numba's cache, once per process), and a field it
reads, directly or through a function it calls, separates them. Building a backend compiles
nothing (Numba compiles on the first call), so these checks are quick.
"""

from dataclasses import replace

import numba
import numpy as np
import pytest

from shoal.backends.cpu import CPUBackend, cache_name
from shoal.options import SPHOptions
from shoal.physics.identity import fingerprint, identity_of, named
from shoal.physics.spec import DIFF_IDS, KERNEL_IDS, VISC_IDS, WALL_IDS, SchemeSpec

BASE = SchemeSpec(dim=3, precision="float32", kernel=KERNEL_IDS["wendland"], viscosity=VISC_IDS["artificial"],
                  diffusion=DIFF_IDS["fourtakas"], tensile=False, xsph=False, cells_per_support=2)


def _loops(spec):
    return CPUBackend(spec)


def _compiled(loop):
    """The compiled loop kernel of a backend's kernel: the CPU's rates a pair at a time
    (`shoal.backends.cpu.MutualRates`) wrap theirs with the work arrays of one model."""
    return getattr(loop, "kernel", loop)


def test_pr2_is_shared_across_kernel_viscosity_and_dimension_but_not_precision():
    """p / rho^2 reads the equation of state only, whose constants are in the working precision."""
    a = _loops(BASE)
    others = [replace(BASE, kernel=KERNEL_IDS["cubic"]), replace(BASE, viscosity=VISC_IDS["laminar"]),
              replace(BASE, dim=2), replace(BASE, diffusion=DIFF_IDS["none"], xsph=True, sps=True, riemann=True)]
    for spec in others:
        assert _loops(spec).pr2 is a.pr2, spec
    assert _loops(replace(BASE, precision="float64")).pr2 is not a.pr2


def test_rates_are_separated_by_every_choice_they_compile_in():
    """The rates read the viscosity through the `viscous` function they call, the kernel through
    `w` and `grad_factor`: a change in a called function separates the caller."""
    a = _loops(BASE)
    assert _compiled(_loops(BASE).rates) is _compiled(a.rates)  # the same scheme: the same loop
    for change in (dict(viscosity=VISC_IDS["laminar"]), dict(kernel=KERNEL_IDS["cubic"]),
                   dict(diffusion=DIFF_IDS["molteni"]), dict(tensile=True), dict(xsph=True), dict(cells_per_support=1),
                   dict(periodic=1), dict(symmetry=1), dict(sps=True), dict(no_slip=True), dict(riemann=True),
                   dict(repulsive=True), dict(planes=True), dict(wall_pressure=WALL_IDS["adami"]),
                   dict(precision="float64"), dict(dim=2)):
        assert _compiled(_loops(replace(BASE, **change)).rates) is not _compiled(a.rates), change


def test_updates_depend_on_precision_dimension_xsph_and_wall_condition_only():
    a = _loops(BASE)
    same = _loops(replace(BASE, kernel=KERNEL_IDS["cubic"], viscosity=VISC_IDS["laminar"], diffusion=DIFF_IDS["none"],
                          sps=True))
    for name in ("verlet", "half_step", "symplectic_correct", "pc_correct", "save_state"):
        assert getattr(same, name) is getattr(a, name), name
    for change in (dict(xsph=True), dict(wall_pressure=WALL_IDS["adami"]), dict(dim=2), dict(precision="float64")):
        assert _loops(replace(BASE, **change)).symplectic_correct is not a.symplectic_correct, change
    # save_state copies the state: the dimension only
    assert _loops(replace(BASE, xsph=True, precision="float64")).save_state is a.save_state
    assert _loops(replace(BASE, dim=2)).save_state is not a.save_state


def test_shared_loops_have_one_cache_name_and_distinct_loops_distinct_names():
    """A loop's on-disk cache name follows its identity: kernels that differ never share an index file."""
    specs = [BASE, replace(BASE, precision="float64"), replace(BASE, dim=2), replace(BASE, viscosity=1),
             replace(BASE, kernel=1), replace(BASE, xsph=True)]
    names = {}
    for spec in specs:
        b = _loops(spec)
        for k in ("rates", "pr2", "verlet", "wall_pressure", "shepard"):
            loop = _compiled(getattr(b, k))
            names.setdefault(loop.py_func.__qualname__, set()).add(id(loop))
    assert all(len(ids) == 1 for ids in names.values())  # one name: one loop kernel


def test_a_shared_loop_gives_the_same_numbers():
    """The pr2 loop that the cubic-kernel scheme reuses from the Wendland one computes what it
    computes for the Wendland one (the equation of state, in float32)."""
    from shoal.physics.spec import make_params, params_array

    spec = replace(BASE, kernel=KERNEL_IDS["cubic"])
    b = _loops(spec)
    opts = SPHOptions(precision="float32", kernel="cubic", wall_pressure="dynamic")
    P = make_params(spec, dp=0.01, h=0.013, rho0=1000.0, c0=20.0, gamma=7.0, gravity=(0, 0, -9.81),
                    options=opts, mass_f=1e-3, mass_b=1e-3, grid_lo=(0.0, 0.0, 0.0), inv_cs=1.0)
    rho = np.array([990.0, 1000.0, 1012.5], np.float32)
    pr2 = np.zeros(3, np.float32)
    b.pr2(3, (rho, pr2, params_array(spec, P)))
    r = rho.astype(np.float64)
    expect = P.B * ((r / 1000.0) ** 7 - 1.0) / (r * r)
    np.testing.assert_allclose(pr2, expect, rtol=1e-4, atol=1e-7)


# -- the identity itself


def _factory(jit, c, with_g=True):
    @jit
    def g(x):
        return x * c

    if not with_g:
        return g

    @jit
    def f(x):
        return g(x) + 1.0

    return f


def test_identity_follows_captured_values_and_called_functions():
    jit = named(numba.njit, "test")
    f1, f1b, f2 = _factory(jit, 2.0), _factory(jit, 2.0), _factory(jit, 3.0)
    assert f1 is f1b  # built alike: one compiled function
    assert f1 is not f2  # f captures nothing that differs, but the g it calls does
    assert identity_of(f1) != identity_of(f2)
    assert f1(1.0) == 3.0 and f2(1.0) == 4.0
    # a float32 and a float64 constant of equal value are different code
    assert _factory(jit, np.float32(0.5)) is not _factory(jit, np.float64(0.5))
    assert _factory(jit, 1) is not _factory(jit, 1.0)
    # the identity is also the dispatcher's uuid (the disk cache's key) and names its loop's cache file
    assert f1._uuid == identity_of(f1)
    assert cache_name(f1) != cache_name(f2)


def test_identity_refuses_what_it_cannot_name():
    """A captured value that has no exact name (an array, a plain Python function, the spec used
    inside a kernel) is refused: an approximate key could let two different kernels share code."""
    def capturing(value):
        def fn(x):
            return value

        return fn

    for value in (np.zeros(3), lambda x: x, numba.njit(lambda x: x), BASE, [1.0]):
        with pytest.raises(TypeError, match="cannot give a compiled function an identity"):
            fingerprint(capturing(value), "cpu")


def test_identity_sees_the_code_and_the_globals_read():
    """Two definitions of one name with the same captures differ by their code; a scalar global
    read by a kernel enters by value."""
    def make(kind):
        if kind:
            def fn(x):
                return x + 1.0
        else:
            def fn(x):
                return x - 1.0
        return fn

    assert fingerprint(make(True), "cpu") != fingerprint(make(False), "cpu")
    assert fingerprint(make(True), "cpu") != fingerprint(make(True), "cuda")
    g = {"LIMIT": 1.0}
    exec("def h(x):\n    return min(x, LIMIT)\n", g)
    before = fingerprint(g["h"], "cpu")
    g["LIMIT"] = 2.0
    assert fingerprint(g["h"], "cpu") != before


def test_a_capture_assigned_again_after_decorating_is_refused():
    """Numba compiles at the first call, from the closure as it is then: a factory that assigns a
    captured variable again after decorating would compile code its identity does not name."""
    jit = named(numba.njit, "test-verify")
    _factory(jit, 5.0)
    jit.verify()  # nothing assigned again: fine
    c = 1.0

    @jit
    def f(x):
        return x * c

    c = 2.0
    with pytest.raises(RuntimeError, match="changed after it was decorated"):
        jit.verify()
