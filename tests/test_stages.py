"""The stages of a time step (`shoal.simulation.stages`): their order and their schedules."""

from __future__ import annotations

from types import SimpleNamespace

from shoal.options import SPHOptions
from shoal.simulation.stages import DensityFilter, StabilityCheck, default_stages


class _Model:
    def __init__(self):
        self.calls = []

    def apply_damping(self, zones, dt):
        self.calls.append(("damping", len(zones), dt))

    def apply_relaxation(self, zones, t, dt):
        self.calls.append(("relaxation", len(zones), t, dt))

    def apply_filter(self, kind):
        self.calls.append(("filter", kind))

    def check(self, step, time):
        self.calls.append(("check", step))


def _sim(damping=(), relaxation=()):
    model = _Model()
    integrator = SimpleNamespace(resets=0)
    integrator.reset_density_history = lambda: setattr(integrator, "resets", integrator.resets + 1)
    return SimpleNamespace(model=model, integrator=integrator, damping=list(damping), relaxation=list(relaxation),
                           step_count=0, time=0.0)


def _steps(sim, stages, n, dt=0.1):
    for _ in range(n):
        sim.step_count += 1
        sim.time += dt
        for stage in stages:
            stage(sim, dt)


def test_default_order_is_damping_then_relaxation_then_filter_then_check():
    stages = default_stages(SPHOptions(shepard_every=2), check_every=1)
    assert [s.name for s in stages] == ["damping", "relaxation", "density filter", "stability check"]
    sim = _sim(damping=[object()], relaxation=[object(), object()])
    _steps(sim, stages, 2)
    # the relaxation's targets are those of the step's end time
    assert sim.model.calls == [("damping", 1, 0.1), ("relaxation", 2, 0.1, 0.1), ("check", 1), ("damping", 1, 0.1),
                               ("relaxation", 2, 0.2, 0.1), ("filter", "shepard"), ("check", 2)]
    assert sim.integrator.resets == 1  # the filtered density is not undone by the integrator's history


def test_density_filter_schedule_shepard_wins_a_tie():
    sim = _sim()
    _steps(sim, [DensityFilter(shepard_every=3, mls_every=2)], 6)
    assert [c[1] for c in sim.model.calls] == ["mls", "shepard", "mls", "shepard"]  # steps 2, 3, 4, 6
    assert sim.integrator.resets == 4


def test_no_damping_zones_and_sparse_checks_do_nothing_between():
    sim = _sim()
    _steps(sim, default_stages(SPHOptions(), check_every=3), 7)
    assert sim.model.calls == [("check", 3), ("check", 6)]
    assert StabilityCheck(0).every == 1
