"""What a time step does after the integrator, as stages run in a stated order.

`Simulation.step` advances the particles with the integrator, then runs its
`stages`, each ``stage(sim, dt)``, in list order:

1. `Damping`: the damping zones relax the velocity in their strip
   (``sim.damping``, the case's ``[[damping]]``; `Model.apply_damping`);
2. `Relaxation`: the relaxation zones relax the velocity toward their
   targets at the step's end time (``sim.relaxation``, the case's
   ``[[relaxation]]`` resolved by `Case.relaxation_terms`;
   `Model.apply_relaxation`). After the damping (the two act on separate
   strips, so their order matters only where a case overlaps them) and
   before the density filter, which does not touch the velocity;
3. `Shifting` (only with ``options.shifting`` other than "none"): the
   fluid particles are moved toward a more regular distribution, their
   normal part removed at the free surface (`Model.apply_shifting`,
   `shoal.physics.shifting`). After the velocity stages, which read the
   positions of the step's end, and before the density filter, so that
   the filter's density is that of the shifted positions;
4. `DensityFilter`: every ``shepard_every`` steps the Shepard filter, or
   every ``mls_every`` steps the MLS filter, re-initialises the density
   (`Model.apply_filter`), and the integrator forgets its density history
   (Verlet's previous density) so the filtered field is not undone;
5. `OpenBoundaryExchange` (only with open boundaries): the buffers' state imposed, particles
   converted, created and removed (`shoal.particle_buffers.BufferZones.exchange`). After the
   density filter, so that the buffers keep their imposed density;
6. `StabilityCheck`: every ``check_every`` steps the particles are checked
   for NaN, a density outside its band or a particle gone wild
   (`Model.check`, `InstabilityError` naming where and why).

A new per-step treatment is a stage put in this list at its place
(``sim.stages.insert(k, stage)``), not a branch inside the step.
"""

from __future__ import annotations


class Damping:
    """Relax the velocity in the damping zones of ``sim.damping`` (none: nothing)."""

    name = "damping"

    def __call__(self, sim, dt):
        if sim.damping:
            sim.model.apply_damping(sim.damping, dt)


class Relaxation:
    """Relax the velocity in the relaxation zones of ``sim.relaxation`` toward their targets at ``sim.time``,
    the end of the step (none: nothing)."""

    name = "relaxation"

    def __call__(self, sim, dt):
        zones = getattr(sim, "relaxation", None)
        if zones:
            sim.model.apply_relaxation(zones, sim.time, dt)


class Shifting:
    """Particle shifting (`Model.apply_shifting`, the scheme's ``shifting``): positions only."""

    name = "shifting"

    def __call__(self, sim, dt):
        sim.model.apply_shifting()


class DensityFilter:
    """The Shepard (every `shepard_every` steps) or MLS (every `mls_every` steps) density filter;
    0 turns a filter off, and Shepard is applied where both are due."""

    name = "density filter"

    def __init__(self, shepard_every=0, mls_every=0):
        self.shepard_every = int(shepard_every or 0)
        self.mls_every = int(mls_every or 0)

    def __call__(self, sim, dt):
        n = sim.step_count
        if self.shepard_every and n % self.shepard_every == 0:
            kind = "shepard"
        elif self.mls_every and n % self.mls_every == 0:
            kind = "mls"
        else:
            return
        sim.model.apply_filter(kind)
        sim.integrator.reset_density_history()


class OpenBoundaryExchange:
    """The open boundaries' step (``sim.model.buffers``, `shoal.particle_buffers`)."""

    name = "open boundaries"

    def __call__(self, sim, dt):
        sim.model.buffers.exchange(dt, sim.time)


class StabilityCheck:
    """`Model.check` every `every` steps: the run stops with the step, the time and the reason."""

    name = "stability check"

    def __init__(self, every=1):
        self.every = max(1, int(every))

    def __call__(self, sim, dt):
        if sim.step_count % self.every == 0:
            sim.model.check(sim.step_count, sim.time)


def default_stages(options, check_every=1, open_boundaries=False):
    """The stages of a step for `options`, in their order: damping, relaxation, shifting (when the options
    ask for it: an option that is off adds no stage), density filter, the open boundaries' exchange (with
    `open_boundaries`), stability check."""
    shifting = [Shifting()] if getattr(options, "shifting", "none") != "none" else []
    exchange = [OpenBoundaryExchange()] if open_boundaries else []
    return [Damping(), Relaxation(), *shifting, DensityFilter(options.shepard_every, options.mls_every),
            *exchange, StabilityCheck(check_every)]
