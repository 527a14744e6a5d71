"""CUDA backend parity with the CPU backend (same physics source, two targets).

On a machine with a GPU these run on it; elsewhere `test_simulator_run` runs
them under Numba's CUDA simulator in a child process (slowly, so the cases
are tiny: a 2D dam break of a few hundred particles). Tolerances: float64
rates agree to 1e-9 relative (only summation order and fused multiply-adds
differ); float32 to 1e-4 relative; a 50-step float32 run (10 steps under
the simulator, where a step of these few hundred particles takes seconds) to
1e-5 m in position (dp = 37 mm) and 1e-3 relative in density.
"""

import math

import numpy as np
import pytest
from cuda_support import SIMULATOR, needs_cuda, run_module_under_simulator

from shoal.cases import dam_break_2d
from shoal.options import SPHOptions
from shoal.runner import build_model
from shoal.simulation import Simulation

A = 0.146
# steps of the multi-step runs: fewer under the simulator (it runs every GPU thread as Python)
STEPS = 10 if SIMULATOR else 50


def _compile_check(log, extra_loops, one_per_loop=False):
    import cuda_kernels

    try:
        from numba.cuda.cudadrv.nvvm import NVVM

        NVVM()
    except Exception as exc:  # the toolkit wheels of numba-cuda[cu13] (the test extra) are missing
        pytest.skip(f"NVVM not found, the PTX compile check is skipped: {exc}")
    specs = cuda_kernels.builtin_specs()
    done, missing, rates_ptx = cuda_kernels.compile_logged(log, (9, 0), extra_specs=specs,
                                                           extra_loops=extra_loops, one_per_loop=one_per_loop)
    print(f"compiled {len(done)} kernels to PTX for sm_90 in {sum(t for _, t in done):.1f} s "
          f"({len(specs)} built-in specialisations); the rates kernels in machine code:")
    for label, _ in done:
        if "registers" in label:
            print("  " + label)
    assert not missing, f"loops never launched in their precision by this module: {missing}"
    # float32 on the GPU means float32 arithmetic per pair: no float64 literal or promotion in the
    # neighbour loops, only the float64 positions' difference (the float64 kernels show the check bites)
    n32 = 0
    for label, (spec, ptx) in rates_ptx.items():
        extra, loops = cuda_kernels.float64_in_pair_loops(ptx, cuda_kernels.allowed_f64(spec))
        assert loops >= 1, label
        if spec.precision == "float32":
            n32 += 1
            assert not extra, f"float64 arithmetic per pair in {label}: {extra}"
        else:
            assert extra.get("fma.rn.f64", 0) + extra.get("mul.f64", 0) + extra.get("mul.rn.f64", 0) > 10, label
    assert n32 >= 5
    print(f"{n32} float32 rates kernels: no float64 arithmetic per pair beyond the positions' difference")
    return done


def test_simulator_run(tmp_path):
    """Run this module under the CUDA simulator in a child process, logging its kernel launches; then
    compile to PTX for an H100/H200 (compute capability 9.0) with NVVM (`cuda_kernels`) each launched
    kernel outside the physics loops, each launched `rates` kernel, each other physics loop launched
    once per precision and dimension (its copies for the other scheme specialisations were compiled
    too until the kernels had run on an H200: 104 kernels in 48 s here, now 78 in 39 s), and the
    `rates` kernel of every built-in case's scheme specialisation: what the simulator cannot check, that the kernels compile
    for a real GPU (a packed float32 parameter record, whose float64 fields were unaligned, compiled
    for the simulator and not for a GPU). Every loop of every specialisation, logged or built-in:
    `test_every_builtin_loop_compiles_for_a_gpu` (-m validation)."""
    log = tmp_path / "kernels.pkl"
    run_module_under_simulator(__file__, "test_simulator_run", kernel_log=log)
    done = _compile_check(log, extra_loops=("rates",), one_per_loop=True)
    assert len(done) > 40


@pytest.mark.validation
def test_every_builtin_loop_compiles_for_a_gpu(tmp_path):
    """`test_simulator_run` with every physics loop (not only `rates`) of every built-in case's scheme
    specialisation compiled for sm_90: 201 kernels, about 100 s on 2 cores (kept out of CI's time)."""
    log = tmp_path / "kernels.pkl"
    run_module_under_simulator(__file__, "test_simulator_run", kernel_log=log)
    done = _compile_check(log, extra_loops=None)
    assert len(done) > 200


@needs_cuda
def test_models_of_one_scheme_share_their_compiled_kernels():
    """CUDA kernels are compiled at their first launch and not cached on disk, so a second model of the
    same scheme must reuse the first one's kernels (compiled once per process), and a model of a scheme
    whose kernels differ (here: the precision) must not."""
    case = dam_break_2d(dp=A / 6, a=A, layers=2, options=SPHOptions(precision="float32"))
    a, b = build_model(case, "cuda"), build_model(case, "cuda")
    other = build_model(dam_break_2d(dp=A / 6, a=A, layers=2, options=SPHOptions(precision="float64")), "cuda")
    for name in ("rates", "pr2", "verlet", "probe"):
        assert getattr(a.backend, name).kernel is getattr(b.backend, name).kernel
        assert getattr(a.backend, name).kernel is not getattr(other.backend, name).kernel
    assert a.backend is not b.backend and a.backend._bad is not b.backend._bad  # per-model device state


def _by_id(model, array):
    h = model.host(array)
    out = np.zeros_like(h)
    out[model.host(model.idp)] = h
    return out


def _pair(precision, ndp=6, integrator="verlet", **opts):
    case = dam_break_2d(dp=A / ndp, a=A, layers=2,
                        options=SPHOptions(precision=precision, integrator=integrator, **opts))
    return build_model(case, "cpu"), build_model(case, "cuda")


@needs_cuda
@pytest.mark.parametrize("precision,tol", [("float64", 1e-9), ("float32", 1e-4)])
def test_one_evaluation_of_rates_matches_cpu(precision, tol):
    cpu, gpu = _pair(precision, xsph=0.5)
    # a random velocity field on the fluid, so every term (viscosity, XSPH) is exercised
    rng = np.random.default_rng(1)
    v = (0.2 * rng.standard_normal(cpu.vel.shape)).astype(cpu.dtype)
    v[cpu.host(cpu.kind) != 0] = 0
    cpu.vel[:] = v
    gpu.vel.copy_to_device(v)
    for m in (cpu, gpu):
        m.sort()
        m.compute_rates()
    # same neighbour order: the sort is stable on both
    assert np.array_equal(cpu.host(cpu.idp), gpu.host(gpu.idp))
    assert np.array_equal(cpu.host(cpu.grid.cell_start, 0, cpu.grid.ncell + 2),
                          gpu.host(gpu.grid.cell_start, 0, gpu.grid.ncell + 2))
    for name in ("ace", "drho", "xsph"):
        a, b = _by_id(cpu, getattr(cpu, name)), _by_id(gpu, getattr(gpu, name))
        err = np.max(np.abs(a - b)) / np.max(np.abs(a))
        print(f"{precision} {name}: max relative difference {err:.2e}")
        assert err < tol
    dt_c, dt_g = cpu.time_step_limit(), gpu.time_step_limit()
    assert dt_g == pytest.approx(dt_c, rel=tol)


@needs_cuda
def test_fifty_step_dam_break_matches_cpu():
    cpu, gpu = _pair("float32", ndp=4)
    runs = [Simulation(m, 1.0).run(max_steps=STEPS) for m in (cpu, gpu)]
    assert runs[0].time == pytest.approx(runs[1].time, rel=1e-5)
    dpos = np.max(np.abs(_by_id(cpu, cpu.pos) - _by_id(gpu, gpu.pos)))
    drho = np.max(np.abs(_by_id(cpu, cpu.rho) - _by_id(gpu, gpu.rho))) / 1000.0
    print(f"{STEPS} steps, t = {runs[0].time:.4f} s: max |dx| {dpos:.2e} m, max |drho|/rho0 {drho:.2e}")
    # the particles did move (a comparison of two frozen states would prove nothing)
    assert np.max(np.abs(_by_id(cpu, cpu.vel))) > 0.01
    assert dpos < 1e-5
    assert drho < 1e-3


@needs_cuda
@pytest.mark.parametrize("integrator,opts", [
    ("symplectic", dict(turbulence="sps", xsph=0.5, shepard_every=2, wall_pressure="adami")),
    ("predictor_corrector", dict(kernel="cubic", tensile_correction=True, turbulence="sps", mls_every=2, no_slip=True)),
])
def test_float32_schemes_match_cpu(integrator, opts):
    """The float32 kernels of the other integrators, with SPS, XSPH, the density filters, Adami walls,
    the tensile correction and a damping zone, stay with the CPU's for a few steps (float32: the
    tolerances of `test_fifty_step_dam_break_matches_cpu`). Their argument types also feed the
    PTX compile check of `test_simulator_run` for the built-in cases' float32 specialisations."""
    from shoal.case import DampingZone

    cpu, gpu = _pair("float32", ndp=4, integrator=integrator, **opts)
    runs = []
    for m in (cpu, gpu):
        sim = Simulation(m, 1.0)
        sim.damping = [DampingZone(start=(0.5 * A, 0, 0), end=(A, 0, 0), rate=5.0)]
        runs.append(sim.run(max_steps=4))
    assert runs[0].time == pytest.approx(runs[1].time, rel=1e-5)
    dpos = np.max(np.abs(_by_id(cpu, cpu.pos) - _by_id(gpu, gpu.pos)))
    drho = np.max(np.abs(_by_id(cpu, cpu.rho) - _by_id(gpu, gpu.rho))) / 1000.0
    assert np.max(np.abs(_by_id(cpu, cpu.vel))) > 0.005
    assert dpos < 1e-5
    assert drho < 1e-3
    # a probe and the walls' forces in float32
    pts = np.array([[0.3 * A, 0.0, 0.2 * A], [0.6 * A, 0.0, 0.1 * A]])
    sc, sg = (m.sample(pts) for m in (cpu, gpu))
    assert np.all(np.isfinite(sc["pressure"])) and np.max(sc["pressure"]) > 0
    np.testing.assert_allclose(sg["pressure"], sc["pressure"], rtol=1e-3)
    np.testing.assert_allclose(sg["velocity"], sc["velocity"], atol=1e-4)
    forces = []
    for m in (cpu, gpu):
        f, ids = m.wall_forces()
        forces.append(f[np.argsort(ids)])
    assert np.max(np.abs(forces[0])) > 0
    assert np.max(np.abs(forces[0] - forces[1])) < 1e-3 * np.max(np.abs(forces[0]))


@needs_cuda
def test_moving_wall_inflow_matches_cpu():
    """A wall pushed at constant speed (the tidal-bore inflow) moves the same on both backends."""
    from shoal.case import Case, Fluid, FluidRegion, Solid
    from shoal.geometry.shapes import Box, Tank
    from shoal.motions import ConstantVelocity

    u = -0.3
    case = Case(name="wall", dim=2, dp=0.025, fluid=Fluid(depth=0.1, surface_level=0.1),
                options={"integrator": "predictor_corrector", "precision": "float32"},
                solids=[Solid(shape=Box(lo=(0.3, 0, 0), hi=(0.35, 0, 0.15)), motion="push", layers=2),
                        Solid(shape=Tank(lo=(0, 0, 0), hi=(0.35, 0, 0.15), open=["top", "xmax"]), layers=2)],
                fluids=[FluidRegion(shape=Box(lo=(0, 0, 0), hi=(0.3, 0, 0.1)), velocity=(u, 0, 0))],
                motions=[ConstantVelocity(name="push", velocity=(u, 0, 0))])
    cpu, gpu = build_model(case, "cpu"), build_model(case, "cuda")
    steps = 8 if SIMULATOR else 20
    runs = [Simulation(m, 1.0).run(max_steps=steps) for m in (cpu, gpu)]
    assert runs[0].time == pytest.approx(runs[1].time, rel=1e-5)
    kinds = case.particles().kinds
    pc, pg = _by_id(cpu, cpu.pos), _by_id(gpu, gpu.pos)
    moving = kinds == 2
    t = runs[0].time
    np.testing.assert_allclose(pc[moving], case.particles().positions[moving][:, [0, 2]] + [u * t, 0], atol=1e-12)
    dpos = np.max(np.abs(pc - pg))
    print(f"moving wall, {steps} steps, t = {t:.4f} s: max |dx| {dpos:.2e} m")
    assert np.max(np.abs(pc[moving] - pg[moving])) < 1e-9
    assert dpos < 1e-5


@needs_cuda
@pytest.mark.parametrize("precision,tol", [("float64", 1e-9), ("float32", 1e-4)])
def test_periodic_rates_match_cpu(precision, tol):
    """The wrapped (periodic) gather gives the CPU's rates on the CUDA backend, and three steps (the
    periodic wrap of the positions) the CPU's positions."""
    from shoal.model import Model

    rng = np.random.default_rng(5)
    dp = 0.01
    g = np.stack(np.meshgrid((np.arange(10) + 0.5) * dp, [0.0], (np.arange(6) + 0.5) * dp, indexing="ij"),
                 -1).reshape(-1, 3)
    g[:, [0, 2]] += 0.2 * dp * rng.standard_normal((len(g), 2))
    g[:, 0] %= 10 * dp
    v = np.zeros_like(g)
    v[:, [0, 2]] = 0.1 * rng.standard_normal((len(g), 2))
    common = dict(dp=dp, dim=2, options=SPHOptions(precision=precision), gravity=(0, 0, 0), u_max=1.0,
                  domain=((0, 0, -0.05), (10 * dp, 0, 0.11)), periodic=("x",), velocities=v)
    cpu = Model(g, np.zeros(len(g), np.int8), backend="cpu", **common)
    gpu = Model(g, np.zeros(len(g), np.int8), backend="cuda", **common)
    for m in (cpu, gpu):
        m.sort()
        m.compute_rates()
    for name in ("ace", "drho"):
        a, b = _by_id(cpu, getattr(cpu, name)), _by_id(gpu, getattr(gpu, name))
        assert np.max(np.abs(a - b)) <= tol * np.max(np.abs(a))
    for m in (cpu, gpu):
        Simulation(m, 1.0).run(max_steps=3)
    # positions are float64 in both precisions; float32 rates differ in the last bits
    assert np.max(np.abs(_by_id(cpu, cpu.pos) - _by_id(gpu, gpu.pos))) < (1e-12 if precision == "float64" else 1e-8)


@needs_cuda
@pytest.mark.parametrize("kind", ["shepard", "mls"])
def test_density_filters_and_damping_match_cpu(kind):
    """The Shepard and MLS density filters and a damping zone's velocity decay give the CPU's
    densities and velocities on the CUDA backend (float64: to round-off)."""
    from shoal.case import DampingZone

    cpu, gpu = _pair("float64")
    rng = np.random.default_rng(7)
    fluid = cpu.host(cpu.kind) == 0
    rho = cpu.host(cpu.rho).copy()
    rho[fluid] *= 1 + 0.01 * rng.standard_normal(int(fluid.sum()))  # a noisy field for the filter to smooth
    v = 0.2 * rng.standard_normal(cpu.vel.shape)
    v[~fluid] = 0
    zone = DampingZone(start=(0.5 * A, 0, 0), end=(A, 0, 0), rate=50.0)
    for m in (cpu, gpu):
        if m is cpu:
            m.rho[:] = rho
            m.vel[:] = v
        else:
            m.rho.copy_to_device(rho)
            m.vel.copy_to_device(v)
        m.sort()
        m.apply_filter(kind)
        m.apply_damping([zone], 0.01)
    a, b = _by_id(cpu, cpu.rho), _by_id(gpu, gpu.rho)
    assert np.max(np.abs(a[fluid] - rho[fluid])) > 1.0  # the filter did change the densities
    assert np.max(np.abs(a - b)) <= 1e-9 * 1000.0
    a, b = _by_id(cpu, cpu.vel), _by_id(gpu, gpu.vel)
    assert np.sum(np.any(a != v, axis=1)) > 0  # some particles are in the zone
    assert np.max(np.abs(a - b)) <= 1e-12


@needs_cuda
@pytest.mark.parametrize("precision,tol", [("float64", 1e-12), ("float32", 1e-5)])
def test_relaxation_zone_matches_cpu(precision, tol):
    """One relaxation stage (`Model.apply_relaxation`) toward an irregular sea of 16 components over half the
    dam-break tank gives the CPU's velocities on the CUDA backend (float64: to round-off; float32: 1e-5 m/s,
    the velocities being of order 0.1 m/s)."""
    from shoal.motions import IrregularWaves
    from shoal.relaxation import MotionTarget, RelaxationZone, resolve_zone
    from shoal.waves import JonswapSpectrum

    cpu, gpu = _pair(precision)
    sea = IrregularWaves(name="sea", spectrum=JonswapSpectrum(hs=0.02, tp=0.6), depth=0.6 * A, components=16,
                         ramp_time=0.6)
    terms = resolve_zone(RelaxationZone(start=0.4 * A, end=A, target=MotionTarget(motion="sea", origin=-0.2),
                                        time_scale=5e-4), [sea], surface_level=0.6 * A)
    rng = np.random.default_rng(11)
    fluid = cpu.host(cpu.kind) == 0
    v = (0.1 * rng.standard_normal(cpu.vel.shape)).astype(cpu.host(cpu.vel).dtype)
    v[~fluid] = 0
    for m in (cpu, gpu):
        if m is cpu:
            m.vel[:] = v
        else:
            m.vel.copy_to_device(v)
        m.sort()
        m.apply_relaxation([terms], 0.45, 2e-4)
        m.apply_relaxation([terms], 0.4502, 2e-4)  # the second step reuses the zone's device buffer
    a, b = _by_id(cpu, cpu.vel), _by_id(gpu, gpu.vel)
    assert np.sum(np.any(a != v, axis=1)) > 10  # particles in the zone were relaxed
    assert np.max(np.abs(a - b)) <= tol


@needs_cuda
def test_sps_rates_match_cpu():
    """SPS turbulence (stress pass + force term) gives the CPU's rates on the CUDA backend."""
    cpu, gpu = _pair("float64", turbulence="sps", sps_cs=0.5)
    rng = np.random.default_rng(2)
    v = 0.2 * rng.standard_normal(cpu.vel.shape)
    v[cpu.host(cpu.kind) != 0] = 0
    cpu.vel[:] = v
    gpu.vel.copy_to_device(v)
    for m in (cpu, gpu):
        m.sort()
        m.compute_rates()
    for name in ("tau", "ace"):
        a, b = _by_id(cpu, getattr(cpu, name)), _by_id(gpu, getattr(gpu, name))
        assert np.max(np.abs(a)) > 0
        assert np.max(np.abs(a - b)) <= 1e-9 * np.max(np.abs(a)), name


@needs_cuda
def test_no_slip_walls_match_cpu():
    """The no-slip wall-velocity pass (Adami et al. 2012) and the boundary viscosity factor give the
    CPU's rates on the CUDA backend."""
    cpu, gpu = _pair("float64", no_slip=True, visco_bound_factor=0.5)
    rng = np.random.default_rng(5)
    v = 0.2 * rng.standard_normal(cpu.vel.shape)
    v[cpu.host(cpu.kind) != 0] = 0
    cpu.vel[:] = v
    gpu.vel.copy_to_device(v)
    for m in (cpu, gpu):
        m.sort()
        m.compute_rates()
    for name in ("vwall", "ace", "drho"):
        a, b = _by_id(cpu, getattr(cpu, name)), _by_id(gpu, getattr(gpu, name))
        assert np.max(np.abs(a)) > 0
        assert np.max(np.abs(a - b)) <= 1e-9 * np.max(np.abs(a)), name


@needs_cuda
def test_adami_wall_pressure_matches_cpu():
    """The wall-pressure pass of Adami et al. (2012), with a wall accelerating (a piston at a quarter
    period, where its acceleration is largest), gives the CPU's wall densities and rates on the CUDA
    backend."""
    from shoal.case import Case, Fluid, FluidRegion, Solid
    from shoal.geometry.shapes import Box, Tank
    from shoal.motions import PistonWavemaker

    case = Case(name="paddle", dim=2, dp=0.025, fluid=Fluid(depth=0.1, surface_level=0.1),
                options={"precision": "float64", "wall_pressure": "adami"},
                solids=[Solid(shape=Box(lo=(-0.05, 0, 0), hi=(0.0, 0, 0.15)), motion="piston", layers=2),
                        Solid(shape=Tank(lo=(-0.05, 0, 0), hi=(0.35, 0, 0.15)), layers=2)],
                fluids=[FluidRegion(shape=Box(lo=(0, 0, 0), hi=(0.35, 0, 0.1)))],
                motions=[PistonWavemaker(name="piston", height=0.02, period=1.0, depth=0.1, ramp_periods=0.0)])
    cpu, gpu = build_model(case, "cpu"), build_model(case, "cuda")
    rng = np.random.default_rng(7)
    rho = cpu.host(cpu.rho).copy()
    fl = cpu.host(cpu.kind) == 0
    rho[fl] *= 1 + 2e-3 * rng.standard_normal(fl.sum())  # a non-hydrostatic fluid pressure to extrapolate
    cpu.rho[:] = rho
    gpu.rho.copy_to_device(rho)
    before = rho.copy()  # rows in id order before the first sort
    for m in (cpu, gpu):
        m.move_bodies(0.75)
        m.sort()
        m.compute_rates()
    walls = _by_id(cpu, cpu.kind) != 0
    a, b = _by_id(cpu, cpu.rho), _by_id(gpu, gpu.rho)
    assert np.max(np.abs(b[walls] - before[walls])) > 0.1  # the pass set the walls' densities on both
    assert np.max(np.abs(a - b)) <= 1e-9 * 1000.0
    for name in ("ace", "drho"):
        a, b = _by_id(cpu, getattr(cpu, name)), _by_id(gpu, getattr(gpu, name))
        assert np.max(np.abs(a - b)) <= 1e-9 * np.max(np.abs(a)), name


def _flap_pair(precision, wall_pressure):
    """CPU and CUDA models of a small 2D tank whose left wall is a flap hinged at the bed (a few hundred
    particles for the simulator)."""
    from shoal.case import Case, Fluid, FluidRegion, Solid
    from shoal.geometry.shapes import Box, Tank
    from shoal.motions import FlapWavemaker

    case = Case(name="flap", dim=2, dp=0.025, fluid=Fluid(depth=0.1, surface_level=0.1),
                options={"precision": precision, "wall_pressure": wall_pressure},
                solids=[Solid(shape=Box(lo=(-0.05, 0, 0), hi=(0.0, 0, 0.15)), motion="flap", layers=2),
                        Solid(shape=Tank(lo=(-0.15, 0, 0), hi=(0.35, 0, 0.15)), layers=2)],
                fluids=[FluidRegion(shape=Box(lo=(0, 0, 0), hi=(0.35, 0, 0.1)))],
                motions=[FlapWavemaker(name="flap", height=0.02, period=0.6, depth=0.1, ramp_periods=0.0)])
    return case, build_model(case, "cpu"), build_model(case, "cuda")


@needs_cuda
@pytest.mark.parametrize("precision,tol", [("float64", 1e-9), ("float32", 1e-4)])
def test_rotating_flap_and_its_adami_pressure_match_cpu(precision, tol):
    """A flap rotating about its hinge (`shoal.physics.body_motion`), at a time where its angular velocity
    and acceleration are both large: the same wall positions (1e-12 m, float64 on both backends) and
    velocities, and the Adami wall pressure with each particle's own acceleration a_d + alpha x r +
    omega x (omega x r), then the rates, on the CUDA backend as on the CPU."""
    case, cpu, gpu = _flap_pair(precision, "adami")
    rng = np.random.default_rng(5)
    rho = cpu.host(cpu.rho).astype(np.float64)
    fl = cpu.host(cpu.kind) == 0
    rho[fl] *= 1 + 2e-3 * rng.standard_normal(fl.sum())
    cpu.rho[:] = rho.astype(cpu.dtype)
    gpu.rho.copy_to_device(rho.astype(cpu.dtype))
    t = 0.2  # theta' and theta'' both a good part of their amplitude
    th, w, al = case.motions[0].angle(t)
    assert abs(w) > 0.3 and abs(al) > 2.0
    for m in (cpu, gpu):
        m.move_bodies(t)
        m.sort()
        m.compute_rates()
    moving = _by_id(cpu, cpu.kind) == 2
    pc, pg = _by_id(cpu, cpu.pos), _by_id(gpu, gpu.pos)
    assert np.max(np.abs(pc[moving] - pg[moving])) < 1e-12
    vc, vg = _by_id(cpu, cpu.vel), _by_id(gpu, gpu.vel)
    assert np.max(np.abs(vc[moving])) > 0.02
    assert np.max(np.abs(vc[moving] - vg[moving])) <= tol * np.max(np.abs(vc[moving]))
    walls = _by_id(cpu, cpu.kind) != 0
    a, b = _by_id(cpu, cpu.rho), _by_id(gpu, gpu.rho)
    assert np.max(np.abs(a[walls] - rho[walls])) > 0.1  # the pass set the walls' densities
    assert np.max(np.abs(a - b)) <= tol * 1000.0
    for name in ("ace", "drho"):
        a, b = _by_id(cpu, getattr(cpu, name)), _by_id(gpu, getattr(gpu, name))
        assert np.max(np.abs(a - b)) <= tol * np.max(np.abs(a)), name


@needs_cuda
@pytest.mark.parametrize("precision,tol", [("float64", 1e-9), ("float32", 1e-4)])
def test_rotating_flap_mdbc_ghost_vectors_match_cpu(precision, tol):
    """mDBC walls on a rotating flap: its ghost vectors turned by R(t) (`make_wall_vector_rotation`), the
    walls' densities and no-slip-free rates from them, the same on both backends."""
    case, cpu, gpu = _flap_pair(precision, "mdbc")
    n = cpu.ghost_of.shape[0]
    moving = np.flatnonzero(case.particles().kinds == 2) - cpu.ghost_id0
    g0 = cpu.host(cpu.ghost_of, 0, n)[moving].astype(np.float64)  # at t = 0 (R = I)
    for m in (cpu, gpu):
        m.move_bodies(0.2)
        m.sort()
        m.compute_rates()
    gc, gg = cpu.host(cpu.ghost_of, 0, n), gpu.host(gpu.ghost_of, 0, n)
    R = case.motions[0].rigid_kinematics(0.2).rotation[np.ix_([0, 2], [0, 2])]
    np.testing.assert_allclose(gc[moving], g0 @ R.T, rtol=0, atol=tol * 0.1 * cpu.dp)
    assert np.max(np.abs(gc - gg)) <= tol * cpu.dp
    for name in ("rho", "ace", "drho"):
        a, b = _by_id(cpu, getattr(cpu, name)), _by_id(gpu, getattr(gpu, name))
        assert np.max(np.abs(a - b)) <= tol * np.max(np.abs(a)), name


def _mdbc_pair(dim, precision):
    """CPU and CUDA models of a small tank with mDBC walls and no-slip (2D: the dam break of `_pair`;
    3D: a 0.1 x 0.06 x 0.1 m tank, dp = 0.02 m, a few hundred particles for the simulator)."""
    if dim == 2:
        return _pair(precision, wall_pressure="mdbc", no_slip=True)
    from shoal.case import Case, Fluid, FluidRegion, Solid
    from shoal.geometry.shapes import Box, Tank

    case = Case(name="tank", dim=3, dp=0.02, fluid=Fluid(depth=0.06, surface_level=0.06),
                options={"precision": precision, "wall_pressure": "mdbc", "no_slip": True},
                solids=[Solid(shape=Tank(lo=(0, 0, 0), hi=(0.1, 0.06, 0.1)), layers=2)],
                fluids=[FluidRegion(shape=Box(lo=(0, 0, 0), hi=(0.1, 0.06, 0.06)))])
    return build_model(case, "cpu"), build_model(case, "cuda")


@needs_cuda
@pytest.mark.parametrize("dim", [2, 3])
@pytest.mark.parametrize("precision,tol", [("float64", 1e-9), ("float32", 1e-4)])
def test_mdbc_walls_match_cpu(dim, precision, tol):
    """mDBC walls (`shoal.physics.mdbc`) with no-slip: the walls' densities from their ghost nodes, their
    no-slip velocities and the rates they give the fluid are the CPU's on the CUDA backend, with a random
    fluid density and velocity (so that the first-order fit and the mirrored velocity are exercised)."""
    cpu, gpu = _mdbc_pair(dim, precision)
    rng = np.random.default_rng(11)
    fl = cpu.host(cpu.kind) == 0
    v = 0.2 * rng.standard_normal(cpu.vel.shape)
    v[~fl] = 0
    cpu.vel[:] = v.astype(cpu.dtype)
    gpu.vel.copy_to_device(v.astype(cpu.dtype))
    rho = cpu.host(cpu.rho).astype(np.float64)
    rho[fl] *= 1 + 2e-3 * rng.standard_normal(fl.sum())
    cpu.rho[:] = rho.astype(cpu.dtype)
    gpu.rho.copy_to_device(rho.astype(cpu.dtype))
    for m in (cpu, gpu):
        m.sort()
        m.compute_rates()
    walls = _by_id(cpu, cpu.kind) != 0
    a, b = _by_id(cpu, cpu.rho), _by_id(gpu, gpu.rho)
    assert np.any(a[walls] > 1000.0 * (1 + 1e-3))  # the walls took the fluid's density
    assert np.max(np.abs(a - b)) <= tol * 1000.0
    for name in ("vwall", "ace", "drho"):
        a, b = _by_id(cpu, getattr(cpu, name)), _by_id(gpu, getattr(gpu, name))
        assert np.max(np.abs(a)) > 0, name
        assert np.max(np.abs(a - b)) <= tol * np.max(np.abs(a)), name


@needs_cuda
@pytest.mark.parametrize("paddle", ["piston", "flap"])
def test_active_absorption_measures_and_moves_the_paddle_as_on_the_cpu(paddle):
    """An absorbing paddle (`shoal.active_absorption`) in a small 2D tank with a wave on its surface (the
    fluid's heights raised by a sine): the elevation it measures in front of itself (the probe kernel's
    kernel sums on the CUDA backend), the correction it computes from it, and the walls it then places are
    the CPU's (float64: the kernel sums to round-off, the paddle's particles to 1e-12 m)."""
    from shoal.active_absorption import ActiveAbsorption
    from shoal.case import Case, Fluid, FluidRegion, Solid
    from shoal.geometry.shapes import Box, Tank
    from shoal.motions import FlapWavemaker, PistonWavemaker

    kind = PistonWavemaker if paddle == "piston" else FlapWavemaker
    motion = kind(name="p", height=0.01, period=0.6, depth=0.1, ramp_periods=0.5,
                  absorption=ActiveAbsorption(start=0.0))
    case = Case(name="awas", dim=2, dp=0.0125, fluid=Fluid(depth=0.1, surface_level=0.1),
                options={"precision": "float64"},
                solids=[Solid(shape=Box(lo=(-0.05, 0, 0), hi=(0.0, 0, 0.15)), motion="p", layers=2),
                        Solid(shape=Tank(lo=(-0.15, 0, 0), hi=(0.35, 0, 0.15)), layers=2)],
                fluids=[FluidRegion(shape=Box(lo=(0, 0, 0), hi=(0.35, 0, 0.1)))], motions=[motion])

    class Sim:
        def __init__(self, model):
            self.model, self.time, self.step_count = model, 0.0, 0

    states = []
    for backend in ("cpu", "cuda"):
        m = build_model(case, backend)
        pos = m.host(m.pos).astype(np.float64)
        fl = m.host(m.kind) == 0
        pos[fl, -1] *= 1.0 + 0.15 * np.sin(2 * np.pi * pos[fl, 0] / 0.35)  # a surface that is no still water
        m.backend.copy_into(m.pos, pos, m.n)
        m.sort()
        sim, c = Sim(m), m.motions[0]
        seen = []
        for k in range(1, 4):
            sim.time, sim.step_count = 0.01 * k, k
            c(sim)
            m.move_bodies(sim.time + 0.005)
            seen.append((c.measured, c.u_c))
        states.append((seen, _by_id(m, m.pos)[_by_id(m, m.kind) == 2]))
    (a, pa), (b, pb) = states
    assert all(math.isfinite(x[0]) for x in a) and abs(a[-1][1]) > 1e-4  # measured, and corrected
    np.testing.assert_allclose(np.array(b), np.array(a), rtol=1e-9, atol=1e-12)
    assert np.max(np.abs(pa - pb)) < 1e-12


@needs_cuda
def test_floating_body_matches_cpu():
    """A floating box (`shoal.body_coupling`) released one spacing above its draft in a small 2D tank, and a
    dense block sliding on the bed with friction: the fluid's force and torque summed over their particles
    (atomic adds on the device), the bed's contact force on the block (`shoal.physics.contact`), the bodies'
    states after three steps, and the particles they place, are the CPU's (float64: to round-off)."""
    from shoal.case import Case, Fluid, FluidRegion, Solid
    from shoal.floating import FloatingBody
    from shoal.geometry.shapes import Box, Tank

    dp = 0.0125
    case = Case(name="float", dim=2, dp=dp, fluid=Fluid(depth=0.1, surface_level=0.1),
                options={"precision": "float64"},
                solids=[Solid(shape=Tank(lo=(0, 0, 0), hi=(0.3, 0, 0.2)), layers=2),
                        Solid(name="box", shape=Box(lo=(0.125, 0, 0.075 + dp), hi=(0.175, 0, 0.125 + dp)), layers=2,
                              floating=FloatingBody(density=500.0)),
                        Solid(name="block", shape=Box(lo=(0.025, 0, 0.0), hi=(0.075, 0, 0.025)), layers=2,
                              floating=FloatingBody(density=2000.0, friction=0.5, velocity=(0.2, 0.0, 0.0)))],
                fluids=[FluidRegion(shape=Box(lo=(0, 0, 0), hi=(0.3, 0, 0.1)))])
    out = []
    for backend in ("cpu", "cuda"):
        sim = Simulation(case, end_time=1.0, backend=backend)
        loads = []
        for _ in range(3):
            sim.step()
            loads.append(np.concatenate([sim.model.floating.fluid.ravel(), sim.model.floating.contact.ravel()]))
        m = sim.model
        s = np.concatenate([np.concatenate([b.state.position, b.state.velocity, b.state.rotation.ravel(),
                                            b.state.angular_velocity]) for b in m.floating.bodies])
        out.append((np.array(loads), s, _by_id(m, m.pos)[_by_id(m, m.kind) == 2]))
    (la, sa, pa), (lb, sb, pb) = out
    assert abs(la[-1, 2]) > 0 and abs(sa[5]) > 0  # loaded, and moving
    assert la[-1, 12 + 6 + 2] > 0  # the bed pushes the block up
    assert la[-1, 12 + 6] < 0  # and its friction holds back the block sliding along +x
    np.testing.assert_allclose(lb, la, rtol=1e-9, atol=1e-9 * np.abs(la).max())
    np.testing.assert_allclose(sb, sa, rtol=1e-9, atol=1e-12)
    assert np.max(np.abs(pa - pb)) < 1e-12


@needs_cuda
def test_particle_shifting_matches_cpu():
    """One particle-shifting pass (`Model.apply_shifting`, delta-plus-SPH) over the dam-break tank with its
    fluid perturbed by up to 0.1 dp gives the CPU's positions on the CUDA backend (float64: 1e-12 m)."""
    cpu, gpu = _pair("float64", shifting="delta_plus")
    rng = np.random.default_rng(5)
    pos = cpu.host(cpu.pos).astype(np.float64)
    fluid = cpu.host(cpu.kind) == 0
    pos[fluid] += 0.1 * cpu.dp * rng.uniform(-1, 1, size=(int(fluid.sum()), pos.shape[1]))
    out = []
    for m in (cpu, gpu):
        m.backend.copy_into(m.pos, pos, m.n)
        m.sort()
        m.apply_shifting()
        out.append(_by_id(m, m.pos))
    assert np.max(np.abs(out[0] - pos)) > 1e-4 * cpu.dp  # the perturbed particles shifted
    assert np.max(np.abs(out[0] - out[1])) <= 1e-12


@needs_cuda
def test_repulsive_walls_and_planes_match_cpu():
    """Monaghan-Kajtar walls and a wall plane: the same motion on the CUDA backend (8 steps of a small tank)."""
    from shoal.case import Case, Fluid, FluidRegion, Solid, WallPlane
    from shoal.geometry.shapes import Box, Tank

    case = Case(name="mk", dim=2, dp=0.04, fluid=Fluid(depth=0.2, surface_level=0.2),
                options={"precision": "float64"},
                solids=[Solid(shape=Tank(lo=(0, 0, 0), hi=(0.4, 0, 0.3)), boundary="repulsive")],
                planes=[WallPlane(point=(0.3, 0, 0), normal=(-1, 0, 0.2))],
                fluids=[FluidRegion(shape=Box(lo=(0, 0, 0), hi=(0.2, 0, 0.2)))])
    cpu, gpu = build_model(case, "cpu"), build_model(case, "cuda")
    for m in (cpu, gpu):
        Simulation(m, 1.0).run(max_steps=8)
    dpos = np.max(np.abs(_by_id(cpu, cpu.pos) - _by_id(gpu, gpu.pos)))
    assert np.max(np.abs(_by_id(cpu, cpu.vel))) > 1e-3
    assert dpos < 1e-9


@needs_cuda
def test_symmetry_plane_rates_match_cpu():
    """The mirror scan of a symmetry plane gives the CPU's rates on the CUDA backend."""
    from shoal.model import Model

    rng = np.random.default_rng(7)
    dp = 0.02
    g = np.stack(np.meshgrid((np.arange(6) + 0.5) * dp, (np.arange(4) + 0.5) * dp, (np.arange(5) + 0.5) * dp,
                             indexing="ij"), -1).reshape(-1, 3)
    g += 0.1 * dp * rng.standard_normal(g.shape)
    g[:, 1] = np.minimum(g[:, 1], 4 * dp - 1e-4)
    v = 0.1 * rng.standard_normal(g.shape)
    common = dict(dp=dp, dim=3, options=SPHOptions(precision="float64"), gravity=(0, 0, -9.81), fluid_height=0.1,
                  domain=((-0.05, -0.05, -0.05), (0.17, 4 * dp + 0.05, 0.15)), symmetry_y=(4 * dp, -1.0),
                  velocities=v)
    cpu = Model(g, np.zeros(len(g), np.int8), backend="cpu", **common)
    gpu = Model(g, np.zeros(len(g), np.int8), backend="cuda", **common)
    for m in (cpu, gpu):
        m.sort()
        m.compute_rates()
    for name in ("ace", "drho"):
        a, b = _by_id(cpu, getattr(cpu, name)), _by_id(gpu, getattr(gpu, name))
        assert np.max(np.abs(a - b)) <= 1e-9 * np.max(np.abs(a))


def _random_fluid_velocity(cpu, gpu, seed):
    """The same random velocity field (0.2 m/s rms) on the fluid of both models; returns the generator."""
    rng = np.random.default_rng(seed)
    v = 0.2 * rng.standard_normal(cpu.vel.shape)
    v[cpu.host(cpu.kind) != 0] = 0
    cpu.vel[:] = v
    gpu.vel.copy_to_device(v)
    return rng


@needs_cuda
def test_probes_match_cpu():
    """Probe interpolation (kernel sum, pressure, velocity) gives the CPU's values on the CUDA backend."""
    cpu, gpu = _pair("float64")
    rng = _random_fluid_velocity(cpu, gpu, 4)
    pts = np.column_stack([rng.uniform(0.0, 0.2, 12), np.zeros(12), rng.uniform(0.0, 0.35, 12)])
    out = []
    for m in (cpu, gpu):
        m.sort()
        out.append(m.sample(pts, shepard=False))
    for k in ("kernel_sum", "pressure", "velocity"):
        a, b = out[0][k], out[1][k]
        assert np.max(np.abs(a)) > 0
        assert np.max(np.abs(a - b)) <= 1e-9 * np.max(np.abs(a)), k


@needs_cuda
@pytest.mark.parametrize("precision", ["float64", "float32"])
def test_pressure_sensor_moments_match_cpu(precision):
    """The fluid's moments around wall pressure sensors (`Model.sensor_moments`) and the pressure fitted
    from them are the CPU's on the CUDA backend: float64 to 1e-9 relative, float32 to 1e-4."""
    from shoal.probes.pressure_sensors import fit_pressure

    cpu, gpu = _pair(precision)
    rng = np.random.default_rng(5)
    rho = cpu.host(cpu.rho).copy()
    fluid = cpu.host(cpu.kind) == 0
    rho[fluid] *= 1 + 0.005 * rng.standard_normal(fluid.sum())  # a pressure field that is not smooth
    cpu.rho[:] = rho
    gpu.rho.copy_to_device(rho)
    pts = np.column_stack([rng.uniform(0.0, 0.2, 8), np.zeros(8), rng.uniform(0.0, 0.35, 8)])
    pts[:3, 2] = 0.0  # on the bed
    moms = []
    for m in (cpu, gpu):
        m.sort()
        moms.append(m.sensor_moments(pts))
    tol = 1e-9 if precision == "float64" else 1e-4
    assert np.max(np.abs(moms[0])) > 0
    assert np.max(np.abs(moms[0] - moms[1])) <= tol * np.max(np.abs(moms[0]))
    for method in ("hydrostatic", "linear"):
        p = [fit_pressure(mo, 2, cpu.h, cpu.rho0, cpu.gravity, method) for mo in moms]
        assert np.max(np.abs(p[0] - p[1])) <= 10 * tol * np.max(np.abs(p[0])), method


@needs_cuda
def test_flow_gauge_matches_cpu():
    """A flow gauge (`shoal.probes.FlowGauge`) reads the CUDA backend's particles as the CPU's: the same
    particles counted through the section after a displacement, the same slab flow rate."""
    from shoal.probes import FlowGauge

    cpu, gpu = _pair("float64")
    _random_fluid_velocity(cpu, gpu, 5)
    spec = FlowGauge(name="f", at=0.07, interval=1.0)
    out = []
    for m in (cpu, gpu):
        m.sort()
        prev, _, q, _ = m.flow_sample(spec, None)
        prev = prev - 0.5 * A * (np.arange(len(prev)) % 3 == 0)  # a third of the particles came from upstream
        _, crossed, _, _ = m.flow_sample(spec, prev)
        out.append((crossed, q))
    assert out[0][0] > 0 and out[0][1] != 0
    assert out[0][0] == out[1][0] and abs(out[0][1] - out[1][1]) <= 1e-12 * abs(out[0][1])


@needs_cuda
@pytest.mark.parametrize("opts", ([] if SIMULATOR else [{}]) + [{"no_slip": True, "viscosity": "laminar", "nu": 1e-3}])
def test_wall_forces_match_cpu(opts):
    """The fluid's force on each boundary particle (`shoal.physics.forces`, a force gauge's sum) is the
    CPU's on the CUDA backend, with the artificial viscosity and with no-slip walls and laminar
    viscosity, within 1e-9 of the largest (under the simulator the second only: it takes every term the
    first does but the artificial viscosity, which the rates' parity tests cover)."""
    cpu, gpu = _pair("float64", **opts)
    _random_fluid_velocity(cpu, gpu, 6)
    out = []
    for m in (cpu, gpu):
        m.sort()
        if m.spec.no_slip:
            b = m.backend
            b.timed(b.wall_velocity, m.n, (m.pos, m.vel, m.kind, m.grid.cell, m.grid.cell_start, m.grid.gdims_arr,
                                           m.P, m.vwall))
        f, ids = m.wall_forces()
        o = np.zeros((m.n_total, 3))
        o[ids] = f
        out.append(o)
    assert np.max(np.abs(out[0])) > 0
    assert np.max(np.abs(out[0] - out[1])) <= 1e-9 * np.max(np.abs(out[0]))
    assert np.allclose(cpu.body_force(0), out[0].sum(axis=0))


@needs_cuda
def test_isosurface_matches_cpu():
    """The free-surface mesh (`shoal.output.isosurface.surface_mesh`) from the CUDA backend's kernel sums
    is the CPU's: the same segments, vertices within 1e-9 m."""
    from shoal.output.isosurface import surface_mesh

    cpu, gpu = _pair("float64")
    out = []
    for m in (cpu, gpu):
        m.sort()
        out.append(surface_mesh(m, spacing=m.dp))
    (pa, (ka, ca)), (pb, (kb, cb)) = out
    assert ka == kb == "line" and len(ca) > 20 and np.array_equal(ca, cb)
    assert np.max(np.abs(pa - pb)) <= 1e-9


@needs_cuda
def test_free_surface_flags_match_cpu():
    cpu, gpu = _pair("float64")
    out = []
    for m in (cpu, gpu):
        m.sort()
        f = m.free_surface()
        o = np.zeros(m.n_total, np.int8)
        o[m.host(m.idp)] = f
        out.append(o)
    assert out[0].sum() > 0
    np.testing.assert_array_equal(out[0], out[1])


@needs_cuda
def test_growing_the_device_arrays_mid_run_changes_nothing():
    """Device arrays cannot grow in place: `ParticleStore.resize` allocates new ones, copies the active
    rows and re-points every reference (the model's, ``scratch``, the integrator's, the grid's). A CUDA
    run whose arrays grew between two steps goes on bitwise as one whose arrays did not."""
    case = dam_break_2d(dp=A / 4, a=A, layers=2, end_time=1.0,
                        options=SPHOptions(precision="float32", integrator="symplectic", xsph=0.5))
    kept, grown = build_model(case, "cuda"), build_model(case, "cuda")
    runs = [Simulation(m, 1.0).run(max_steps=3) for m in (kept, grown)]
    old = {id(a) for a in grown.per_particle_arrays()}
    grown.store.resize(2 * grown.capacity)
    arrays = grown.per_particle_arrays()
    assert all(a.shape[0] == grown.capacity for a in arrays) and not old & {id(a) for a in arrays}
    integ = runs[1].integrator
    assert all(getattr(integ, k) is a for k, a in zip(("pos_n", "vel_n", "rho_n"), grown.extra_arrays))
    assert grown.grid.capacity == grown.capacity
    for sim in runs:
        sim.run(max_steps=3)
    assert np.max(np.abs(_by_id(kept, kept.vel))) > 0.01
    for name in ("pos", "vel", "rho"):
        assert np.array_equal(_by_id(kept, getattr(kept, name)), _by_id(grown, getattr(grown, name))), name


@needs_cuda
def test_resume_from_checkpoint_is_bitwise_on_cuda(tmp_path):
    """A CUDA run stopped after 5 steps (checkpoint) and resumed for 3 more ends bitwise equal to an
    uninterrupted 8-step CUDA run (device arrays saved and restored in their sorted order; the Verlet
    scheme's Euler step every 4 steps falls on both sides of the restart)."""
    from shoal.runner import resume_run, run_case

    ndp = 4 if SIMULATOR else 6
    case = dam_break_2d(dp=A / ndp, a=A, layers=2, end_time=1.0, output_interval=1.0,
                        options=SPHOptions(precision="float32", integrator="verlet", verlet_euler_every=4))
    run_case(case, tmp_path / "a", backend="cuda", plot=False, max_steps=5, handle_signals=False)
    resumed = resume_run(tmp_path / "a", backend="cuda", plot=False, max_steps=3, handle_signals=False)
    whole = run_case(case, tmp_path / "b", backend="cuda", plot=False, max_steps=8, handle_signals=False)
    assert resumed.steps == whole.steps == 8
    for name in ("pos", "vel", "rho"):
        a, b = _by_id(resumed.model, getattr(resumed.model, name)), _by_id(whole.model, getattr(whole.model, name))
        assert np.array_equal(a, b), name


@needs_cuda
@pytest.mark.parametrize("precision,tol", [("float64", 1e-9), ("float32", 1e-4)])
def test_riemann_rates_and_wall_forces_match_cpu(precision, tol):
    """With the Riemann pair terms (`shoal.physics.riemann`) over Adami walls, one evaluation of the
    rates and the walls' forces give the CPU's values on the CUDA backend, under a random velocity field
    (closing pairs exercise the limiter) and a perturbed density (the acoustic term)."""
    cpu, gpu = _pair(precision, riemann=True, alpha=0.0, density_diffusion="none")
    rng = np.random.default_rng(11)
    fl = cpu.host(cpu.kind) == 0
    v = (0.2 * rng.standard_normal(cpu.vel.shape)).astype(cpu.dtype)
    v[~fl] = 0
    cpu.vel[:] = v
    gpu.vel.copy_to_device(v)
    rho = cpu.host(cpu.rho).copy()
    rho[fl] *= (1 + 2e-3 * rng.standard_normal(fl.sum())).astype(cpu.dtype)
    cpu.rho[:] = rho
    gpu.rho.copy_to_device(rho)
    forces = []
    for m in (cpu, gpu):
        m.sort()
        m.compute_rates()
        f, ids = m.wall_forces()
        o = np.zeros((m.n_total, 3))
        o[ids] = f
        forces.append(o)
    for name in ("ace", "drho"):
        a, b = _by_id(cpu, getattr(cpu, name)), _by_id(gpu, getattr(gpu, name))
        assert np.max(np.abs(a - b)) <= tol * np.max(np.abs(a)), name
    assert np.max(np.abs(forces[0])) > 0
    assert np.max(np.abs(forces[0] - forces[1])) <= tol * np.max(np.abs(forces[0]))


def _rows_by_id(model, *arrays):
    """`arrays` (host copies of the active rows) in the order of the particles' ids, and the sorted ids."""
    ids = model.host(model.idp)
    order = np.argsort(ids)
    return ids[order], [model.host(a)[order] for a in arrays]


@needs_cuda
def test_open_boundaries_match_cpu():
    """Open boundaries on the CUDA backend (`shoal.particle_buffers`, on host mirrors of the device arrays,
    and the rate-holding kernel `shoal.physics.buffer_hold`) do what they do on the CPU: in a channel whose
    water is moved 0.6 dp downstream (the inlet's first column crosses its plane, the last column of the
    domain the outlet's) and whose inlet level jumps from 0.2 to 0.3 m (two rows lifted into its buffer), one
    exchange converts, creates and removes the same particles with the same ids, and imposes the same
    velocities and densities (the outlet's from the water at the mirror images); then a few steps end with
    the same particles within 1e-9 m (float64), the fluid's shifted (``shifting = "delta_plus"``) and the
    buffers' not (the ``hold_shift`` kernel)."""
    from shoal.case import Case, Fluid, FluidRegion, Solid
    from shoal.geometry.shapes import Box
    from shoal.open_boundary import OpenBoundary
    from shoal.time_series import TimeSeries

    dp, depth, length = 0.04, 0.2, 0.4
    level = TimeSeries(t=[0.0, 1e-5], value=[depth, 0.3])
    case = Case(name="channel", dim=2, dp=dp, fluid=Fluid(depth=depth, surface_level=depth),
                options={"precision": "float64", "wall_pressure": "adami", "visco_bound_factor": 0.0,
                         "shifting": "delta_plus"},
                solids=[Solid(name="bed", shape=Box(lo=(-0.2, 0, -3 * dp), hi=(length + 0.2, 0, 0)), layers=3)],
                fluids=[FluidRegion(shape=Box(lo=(0, 0, 0), hi=(length, 0, depth)), velocity=(0.2, 0, 0))],
                open_boundaries=[
                    OpenBoundary(name="in", point=(0, 0, 0), normal=(1, 0, 0), lo=(0, 0, 0), hi=(0, 0, 0.4),
                                 velocity=0.2, level=level),
                    OpenBoundary(name="out", point=(length, 0, 0), normal=(-1, 0, 0), lo=(length, 0, 0),
                                 hi=(length, 0, 0.4), level=depth)])
    cpu, gpu = build_model(case, "cpu"), build_model(case, "cuda")
    done = []
    for m in (cpu, gpu):
        m.sort()
        pos = m.host(m.pos).copy()
        pos[m.host(m.kind) == 0, 0] += 0.6 * dp
        m.backend.copy_into(m.pos, pos, m.n)
        done.append(m.buffers.exchange(0.0, 1.0))
    (s, r), (sg, rg) = done
    assert s > 0 and r > 0 and (s, r) == (sg, rg)
    assert cpu.buffers.created > s  # the lifted rows besides the copies
    assert (cpu.n, cpu.buffers.created, cpu.buffers.removed, cpu.buffers.next_id) == \
        (gpu.n, gpu.buffers.created, gpu.buffers.removed, gpu.buffers.next_id)
    ids_c, rows_c = _rows_by_id(cpu, cpu.pos, cpu.vel, cpu.rho, cpu.buffers.zone)
    ids_g, rows_g = _rows_by_id(gpu, gpu.pos, gpu.vel, gpu.rho, gpu.buffers.zone)
    assert np.array_equal(ids_c, ids_g)
    for a, b, name in zip(rows_c, rows_g, ("pos", "vel", "rho", "zone")):
        assert np.allclose(a, b, rtol=1e-12, atol=1e-12), name
    steps = 3 if SIMULATOR else 20
    for m in (cpu, gpu):
        Simulation(m, 1.0).run(max_steps=steps)
    ids_c, (pc, vc) = _rows_by_id(cpu, cpu.pos, cpu.vel)
    ids_g, (pg, vg) = _rows_by_id(gpu, gpu.pos, gpu.vel)
    assert np.array_equal(ids_c, ids_g)
    dpos = np.max(np.abs(pc - pg))
    print(f"open boundaries, {steps} steps: max |dx| {dpos:.2e} m, created {cpu.buffers.created}, "
          f"removed {cpu.buffers.removed}")
    assert np.max(np.abs(vc)) > 0.1
    assert dpos < 1e-9
