"""The SPHERIC Test 2 case of the cross-code GPU benchmark (`shoal.cases.spheric_benchmark`, issue 34): the same
particles and scheme as the benchmark's DualSPHysics definition, whose run logs give the figures compared with.

DualSPHysics 5.2's log of the benchmark on an H100 NVL at dp = 6 mm (``tomashalada/sph-benchmarks``,
``results/results_dambreak3D-NVIDIA-H100-NVL/dualSPHysics_0.006_1.out``): CaseNp=4989696, CaseNbound=1975146,
CaseNfluid=3014550, KernelH=0.012000 (H/Dp=2), Cs0=45.77571510910561, CteB=299345.2, Visco=0.02,
ViscoBoundFactor=0, DensityDiffusionValue=0.1, VerletSteps=40, CFLnumber=0.2."""

from __future__ import annotations

import math

from shoal.cases import spheric_benchmark
from shoal.runner import build_model

DS_FLUID, DS_BOUND, DS_TOTAL = 3_014_550, 1_975_146, 4_989_696
DS_C0, DS_B = 45.77571510910561, 299345.2


def test_at_6_mm_the_fluid_is_dualsphysics_particles_and_the_walls_within_a_quarter_per_cent():
    """The fluid is DualSPHysics's lattice block, 203 x 165 x 90 particles; the walls differ where the box meets
    the floor (DualSPHysics's box walls run two spacings into the floor, which stops short of them)."""
    p = spheric_benchmark(dp=0.006).particles()
    fluid = int((p.kinds == 0).sum())
    assert fluid == DS_FLUID
    assert abs((len(p) - fluid) / DS_BOUND - 1) < 0.0025
    assert abs(len(p) / DS_TOTAL - 1) < 0.001


def test_the_scheme_is_the_benchmark_definitions():
    """h = 2 dp, c0 = 20 sqrt(g h_swl) with DualSPHysics's h_swl, B = c0^2 rho0 / 7: the values of its log."""
    case = spheric_benchmark(dp=0.04)
    o = case.options
    assert (o.kernel, o.viscosity, o.density_diffusion, o.wall_pressure, o.integrator) == (
        "wendland", "artificial", "molteni", "dynamic", "verlet")
    assert (o.alpha, o.visco_bound_factor, o.delta, o.verlet_euler_every, o.cfl, o.shifting) == (
        0.02, 0.0, 0.1, 40, 0.2, "none")
    model = build_model(case)
    assert math.isclose(model.h, 2 * 0.04, rel_tol=1e-12)
    assert math.isclose(model.c0, DS_C0, rel_tol=2e-6)
    assert math.isclose(float(model.params.B), DS_B, rel_tol=1e-6)  # float32 parameters: 6e-8
