"""Every built-in case builds its particles and runs a few steps on the CPU."""

import json

import numpy as np
import pytest

from shoal.cases import CASES, get_case
from shoal.check import check_case, solver_bytes
from shoal.errors import InputError
from shoal.runner import build_model
from shoal.simulation import Simulation

COARSE = {
    "dam-break-2d": dict(dp=0.01), "dam-break-3d": dict(dp=0.03), "dam-break-dualsphysics": dict(dp=0.03),
    "spheric-benchmark": dict(dp=0.04), "still-water-2d": dict(dp=0.05), "still-water-3d": dict(dp=0.06), "wave-flume-2d": dict(dp=0.04),
    "wave-basin-2d": dict(dp=0.04, length=4.5), "wave-flume-3d": dict(dp=0.08, width=0.4), "tidal-bore": dict(dp=0.025), "tidal-bore-piers": dict(dp=0.025),
    "rip-current": dict(dp=0.075), "floating-box-2d": dict(dp=0.025), "moored-box-3d": dict(dp=0.05),
    "open-channel-2d": dict(dp=0.04), "open-channel-3d": dict(dp=0.05, length=0.6, gauges_x=[0.3]),
    "sluice-gate-2d": dict(dp=0.015), "weir-2d": dict(dp=0.02),
}


def test_every_case_has_a_coarse_setting():
    assert set(COARSE) == set(CASES)


@pytest.mark.parametrize("name", sorted(CASES))
def test_case_builds_and_runs_a_few_steps(name):
    case = get_case(name, **COARSE[name])
    p = case.particles()
    assert p.n_fluid > 0 and len(p) == len(p.kinds)
    lines = check_case(case)
    assert any("particles:" in s for s in lines)
    model = build_model(case)
    n0 = model.n_total
    sim = Simulation(model, end_time=1.0).run(max_steps=3)
    assert sim.step_count == 3 and sim.time > 0
    assert model.n == n0  # nothing left the domain in 3 steps
    assert np.all(np.isfinite(model.world_positions()))
    # solver_bytes is what the model holds once the integrator has its state
    moving = bool(np.any(p.kinds == 2))
    floating = any(s.floating is not None for s in case.solids)
    # the rows held: the particles, and with open boundaries room for a buffer's worth of copies
    assert solver_bytes(model.capacity, case.dim, case.options, model.grid.ncell, moving, floating,
                        open_boundaries=bool(case.open_boundaries)) == model.nbytes()
    mem_line = next(s for s in lines if s.strip().startswith("memory:"))
    assert f"{model.nbytes() / 2**20:,.1f} MiB" in mem_line  # shoal check's estimate is what the run holds


def test_half_width_and_repulsive_variants_run():
    half = get_case("tidal-bore", dp=0.025, half=True)
    full = get_case("tidal-bore", dp=0.025)
    assert half.particles().n_fluid * 2 == full.particles().n_fluid
    m = build_model(half)
    assert m.spec.symmetry == 1
    Simulation(m, 1.0).run(max_steps=3)
    assert m.n == m.n_total
    rep = get_case("rip-current", dp=0.075, boundary="repulsive")
    assert np.all(rep.particles().spacing[rep.particles().kinds != 0] == 0.075 / 2)
    model = build_model(rep)
    kinds = model.host(model.kind)
    assert set(np.unique(kinds)) == {0, 3, 4}  # fluid, repulsive fixed, repulsive moving (the paddle)
    Simulation(model, 1.0).run(max_steps=3)
    assert model.n == model.n_total


def test_unknown_case_parameter_is_named():
    with pytest.raises(InputError, match="no parameter 'speed'.*inflow_speed"):
        get_case("tidal-bore", speed=0.3)


def test_run_writes_a_resolved_case_that_runs_again(tmp_path):
    from shoal import Simulation, load_case, run_case

    case = get_case("still-water-2d", dp=0.05, end_time=0.01)
    res = run_case(case, tmp_path / "a", plot=False, max_steps=2)
    again = load_case(tmp_path / "a" / "case.toml")
    # the same case; the built-in case's parameters are a comment in that file (and a table in resolved.json)
    assert again.resolved() == case.model_copy(update={"parameters": {}}).resolved()
    assert json.loads((tmp_path / "a" / "resolved.json").read_text())["parameters"] == case.parameters
    np.testing.assert_array_equal(again.particles().positions, case.particles().positions)
    sim = Simulation(again).run(max_steps=2)  # a Case runs directly, to its own end_time
    assert sim.end_time == case.end_time and sim.step_count == 2 == res.steps


def test_tidal_bore_2d_section():
    case = get_case("tidal-bore", dp=0.01, dim=2, inflow_speed=0.7)
    p = case.particles()
    assert case.dim == 2 and p.counts()["fluid"] == 300 * 10
    assert "breaking" in case.description
    m = build_model(case)
    Simulation(m, 1.0).run(max_steps=3)
    with pytest.raises(InputError, match="2D"):
        get_case("tidal-bore", dp=0.01, dim=2, half=True)


def test_tidal_bore_length_and_gauges():
    """A longer flume holds length / dp fluid columns; gauges go where asked, inside the flume only."""
    case = get_case("tidal-bore", dp=0.01, dim=2, length=6.0, gauges_x=[1.0, 4.5])
    assert case.particles().counts()["fluid"] == 600 * 10
    assert [(pr.name, pr.x) for pr in case.probes] == [("x1", 1.0), ("x4.5", 4.5)]
    with pytest.raises(InputError, match="gauges_x = 7 m lies outside"):
        get_case("tidal-bore", dp=0.01, dim=2, length=6.0, gauges_x=[7.0])
    with pytest.raises(InputError, match="length"):
        get_case("tidal-bore", dp=0.01, dim=2, length=-1.0)


@pytest.mark.parametrize("layers,tol", [(1, 0.01), (3, 0.03)])
def test_dualsphysics_dam_break_count_estimate_is_the_generated_count(layers, tol):
    """The memory check of the benchmark case counts its water and walls, not the tank's volume."""
    from shoal.cases.dam_break import dam_break_dualsphysics, dualsphysics_particle_estimate

    n = len(dam_break_dualsphysics(dp=0.01, layers=layers).particles().positions)
    assert abs(dualsphysics_particle_estimate(0.01, layers) / n - 1) < tol, n


def test_memory_check_admits_what_fits_and_refuses_what_does_not(monkeypatch):
    """On a 24 GiB machine the 20.8M-particle benchmark (dp = 1.6 mm; measured on the GPU machine: 205
    host bytes a particle at the peak) is admitted; the tank's volume was counted before, 5.7 times too
    many, and refused it. Half that dp (166M particles, 8 times the memory) is refused in one line."""
    from shoal import memory
    from shoal.cases.dam_break import dam_break_dualsphysics

    monkeypatch.setattr(memory, "physical_memory", lambda: 24 * 2**30)
    dam_break_dualsphysics(dp=0.0016)
    with pytest.raises(InputError, match=r"about 1\.6\de\+08 particles would be generated.*use a larger dp") as err:
        dam_break_dualsphysics(dp=0.0008)
    assert "\n" not in str(err.value)


@pytest.mark.parametrize("dp,layers", [(0.008, 3), (0.005, 3), (0.008, 1)])
def test_dam_break_3d_count_estimate_is_the_generated_count(monkeypatch, dp, layers):
    """The memory check of `dam_break_3d` counts the water and the tank's shell (open top), within 2 %
    of the generated count; it counted the tank's volume, up to 3.4 times too many here."""
    import shoal.cases.dam_break as db

    seen = []
    monkeypatch.setattr(db, "check_count", lambda n, dim: seen.append(n))
    n = len(db.dam_break_3d(dp=dp, layers=layers).particles().positions)
    assert len(seen) == 1 and abs(seen[0] / n - 1) < 0.02, (seen, n)


def test_a_built_in_case_run_from_its_name_resumes(tmp_path, capsys):
    """The checkpoint holds the case with its parameters; the case.toml the run writes has them as a comment
    only: they are a record, not the case, and the resume goes on."""
    from shoal.cli import main

    out = str(tmp_path / "sw")
    common = ["--no-progress", "--no-plot"]
    assert main(["run", "still-water-2d", "--dp", "0.05", "--end-time", "0.02", "--checkpoint-interval", "0.01",
                 "--out", out, *common]) == 0
    assert main(["run", "--resume", out, "--end-time", "0.03", *common]) == 0
    assert "resumed from" in capsys.readouterr().out
