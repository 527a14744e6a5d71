"""Periodic run-up on a plane beach: the standing wave of Carrier & Greenspan (1958).

The flume (`periodic_runup_flume`): a 2D beach of slope 1:cot from a piston paddle at x = 0, where the
still water is d deep, to above the run-up; the still-water shoreline is at x = d cot. The paddle moves
with the standing wave's velocity at its face (`shoal.analysis.beach_standing_wave`) and the fluid starts
from the wave's state at t = 0 (`start_from_solution`): a flat surface at the hydrostatic density and the
solution's velocity field, so the flume has no start-up transient to wait out. A run-up gauge follows
the tip of the water that still interacts with the body (any particle, dry stretches up to the kernel
support bridged) and is read from its value at t = 0, the still-water shoreline, as a laboratory run-up
gauge is zeroed in still water.
"""

from __future__ import annotations

import math
import tempfile
import time
from pathlib import Path

import numpy as np

from . import runs
from .core import Metric, ValidationCase, figure, save_png


def periodic_runup_flume(wave, depth, cot, dp, options, end_time, folder, interval=None):
    """The case of the flume for `wave` (a `BeachStandingWave`), the paddle's displacement written to
    `folder` as a time series from one period before t = 0 (the spline's clamped start stays off the
    run).

    Returns
    -------
    Case
        With the run-up gauge ``tip`` and a wave gauge ``offshore`` (halfway to the paddle in sigma, or
        at J0's first extremum sigma = 3.83 when the paddle lies beyond it).
    """
    from ..case import Case, Fluid, FluidRegion, Output, Solid
    from ..geometry.shapes import Box, Slope, Tank
    from ..motions import TimeSeriesMotion
    from ..probes import RunupGauge, WaveGauge

    d, s = float(depth), 1.0 / cot
    shore = d * cot
    T = wave.period
    t = np.arange(-T, end_time + T, T / 400)
    path = Path(folder) / "paddle.txt"
    path.parent.mkdir(parents=True, exist_ok=True)
    np.savetxt(path, np.column_stack([t, wave.paddle_stroke(shore) * np.sin(wave.omega * t)]),
               header="t [s], x [m]: the paddle of the Carrier & Greenspan standing wave")
    top = d + 3 * wave.amplitude + 4 * dp
    x_end = top * cot
    solids = [Solid(name="paddle", shape=Box(lo=(-4 * dp, 0.0, 0.0), hi=(0.0, 0.0, top)), motion="paddle"),
              Solid(name="beach", shape=Slope(x0=0.0, z0=0.0, gradient=s)),
              Solid(name="flume", shape=Tank(lo=(-6 * dp, 0.0, 0.0), hi=(x_end, 0.0, top)))]
    interval = interval or T / 200
    sigma_L = float(wave.sigma(shore))
    sigma_g = 3.8317 if sigma_L > 4.3 else 0.5 * sigma_L
    X_g = (sigma_g / (2 * wave.omega)) ** 2 * wave.g * s
    support = 2 * options.coef_h * math.sqrt(2) * dp
    probes = [WaveGauge(name="offshore", x=shore - X_g, z0=0.0, z1=top, interval=interval),
              RunupGauge(name="tip", x0=shore - 3 * wave.amplitude * cot, x1=x_end, min_depth=dp, max_gap=support,
                         interval=interval)]
    return Case(name="periodic-runup", dim=2, dp=dp, end_time=end_time, fluid=Fluid(depth=d, surface_level=d),
                options=options, solids=solids, fluids=[FluidRegion(shape=Box(lo=(0, 0, 0), hi=(x_end, 0, d)))],
                motions=[TimeSeriesMotion(name="paddle", file=str(path))], probes=probes,
                output=Output(interval=end_time))


def start_from_solution(model, wave, shore):
    """Give the fluid particles the wave's velocity at t = 0: u, and w that keeps the flow on the bed
    and divergence-free (the surface is flat then, so positions and density are the still water's)."""
    fluid = model.host(model.kind) == 0
    p = model.world_positions()[fluid]
    X = shore - p[:, 0]
    height = np.maximum(p[:, 2] - wave.slope * p[:, 0], 0.0)
    vel = model.host(model.vel)
    vel[fluid, 0] = wave.velocity(X, 0.0)
    vel[fluid, 1] = wave.vertical_velocity(X, height, 0.0)
    model.backend.copy_into(model.vel, vel.astype(model.dtype), model.n)


def run_periodic_runup(wave, depth, cot, dp, options, periods, folder, backend="cpu"):
    """Run the flume for `periods` periods; returns dict(t, shoreline [m above the still level, from
    the gauge's t = 0 reading], zero [m, that reading less the still level], offshore [m], X_offshore,
    steps, particles, seconds)."""
    from ..probes import make_recorder
    from ..runner import build_model
    from ..simulation import Simulation, TimeInterval

    t0 = time.perf_counter()
    end = periods * wave.period
    case = periodic_runup_flume(wave, depth, cot, dp, options, end, folder)
    model = build_model(case, backend)
    start_from_solution(model, wave, depth * cot)
    sim = Simulation(model, end)
    recs = [make_recorder(p, folder, dp, model) for p in case.probes]
    for r in recs:
        sim.add_callback(r, TimeInterval(r.spec.interval), name=f"probe {r.spec.name}")
    try:
        sim.run()
    finally:
        for r in recs:
            r.close()
    gauge, tip = (np.array(r.rows, float) for r in recs)
    zero = float(tip[0, 1]) - depth
    return dict(t=tip[:, 0], shoreline=tip[:, 1] - depth - zero, zero=zero, offshore_t=gauge[:, 0],
                offshore=gauge[:, 1] - depth, X_offshore=float(depth * cot - case.probes[0].x),
                steps=sim.step_count, particles=case.n_particles, seconds=time.perf_counter() - t0)


def excursions(t, z, period):
    """Per whole period from t = 0: (highest, lowest) of z (NaNs left out)."""
    out = []
    k = 0
    while (k + 1) * period <= t[-1] + 1e-9:
        m = (t >= k * period) & (t < (k + 1) * period) & np.isfinite(z)
        if m.sum() > 10:
            out.append((float(np.max(z[m])), float(np.min(z[m]))))
        k += 1
    return out


class PeriodicRunup(ValidationCase):
    """The Carrier & Greenspan standing wave on a 1:10 beach: the shoreline's excursion against +-A.

    Parameters
    ----------
    tolerance : float
        Largest |half the shoreline's excursion in a period / A - 1| that passes (0.10, issue 28).
    """

    name = "periodic-runup"
    title = "Periodic run-up on a plane beach (Carrier & Greenspan 1958)"
    cost = 120.0
    setup = ("2D beach of slope 1:10 from a piston paddle where the still water is d = 0.1 m deep; the "
             "standing long wave of shoreline amplitude A = 0.222 d, breaking parameter epsilon = "
             "A omega^2 / (g s^2) = 0.5, k d = 0.15 at the paddle (sigma_L = 3, below the closed basin's "
             "first natural mode 3.83). The paddle moves with the solution's velocity at its face and the "
             "fluid starts from the solution at t = 0 (flat surface, hydrostatic density, the solution's "
             "velocity field), so there is no start-up transient. Run-up gauge: the tip of the water that "
             "still interacts with the body (`min_depth = dp`, `max_gap = 2h`), zeroed at t = 0 (the "
             "still-water shoreline). The wave flumes' scheme (laminar viscosity, coef_h = 1.5), Adami "
             "walls, float32. `--quick`: d/dp = 10, 1 period; `--full`: d/dp = 20, 3 periods.")
    reference = ("Analytic: the linear standing wave eta = A J0(sigma) sin(omega t), sigma = 2 omega "
                 "sqrt(X / (g s)) (Lamb 1932, section 186); the nonlinear solution of Carrier & Greenspan "
                 "(1958, J. Fluid Mech. 4, 97-109) keeps the shoreline's extremes at +A and -A below "
                 "breaking (epsilon < 1), distorting only their timing.")
    tolerance_text = ("Half the shoreline's excursion in each period within 10 % of A (issue 28, item 3), "
                      "in the quick run (A = 2.2 dp) as in the full one.")

    def __init__(self, tolerance=0.10):
        self.tol = float(tolerance)

    def params(self, quick):
        if quick:
            return dict(ddp=10.0, periods=1.0)
        return dict(ddp=20.0, periods=3.0)

    def wave(self):
        from ..analysis.beach_standing_wave import BeachStandingWave

        return BeachStandingWave.for_flume(depth=0.1, slope=0.1, sigma_paddle=3.0, breaking=0.5)

    def run(self, quick, backend, out):
        from ..cases.wave_flume import WAVE_OPTIONS
        from ..options import SPHOptions

        res = self.new_result(quick, backend, out)
        p = self.params(quick)
        d, cot = 0.1, 10.0
        dp = d / p["ddp"]
        wave = self.wave()
        options = SPHOptions(**WAVE_OPTIONS[2])

        def simulate():
            with tempfile.TemporaryDirectory() as tmp:  # the paddle's file and the gauges' CSVs
                return run_periodic_runup(wave, d, cot, dp, options, p["periods"], tmp, backend)

        key = ("periodic-runup", tuple(p.items()), backend)
        res.data = {**runs.memo(key, simulate), **p, "A": wave.amplitude, "T": wave.period, "d": d,
                    "tol": self.tol}
        res.run_seconds = res.data["seconds"]
        res.resolution = (f"dp = d/{p['ddp']:g} (A = {wave.amplitude / dp:.1f} dp), {p['periods']:g} "
                          f"period{'s' if p['periods'] != 1 else ''}")
        res.particles = f"{res.data['particles']:,}"
        return res

    def compare(self, result):
        d = result.data
        A, T = d["A"], d["T"]
        per = excursions(np.asarray(d["t"]), np.asarray(d["shoreline"]), T)
        exc = [(hi - lo) / (2 * A) for hi, lo in per]
        worst = max(abs(e - 1) for e in exc) if exc else float("nan")
        result.metrics = [
            Metric("half the shoreline's excursion per period / A, worst |error|", worst, d["tol"],
                   note=", ".join(f"{e:.3f}" for e in exc)),
            Metric("highest shoreline per period / A (theory 1)", float(np.mean([hi for hi, _ in per])) / A - 1,
                   note=", ".join(f"{hi / A:+.2f}" for hi, _ in per)),
            Metric("lowest shoreline per period / A (theory -1)", -float(np.mean([lo for _, lo in per])) / A - 1,
                   note=", ".join(f"{lo / A:+.2f}" for _, lo in per)),
        ]
        from ..analysis.beach_standing_wave import BeachStandingWave

        wave = BeachStandingWave(amplitude=A, slope=0.1, omega=2 * math.pi / T)
        z = np.asarray(d["shoreline"])
        ok = np.isfinite(z)
        rms = float(np.sqrt(np.mean((z[ok] - wave.shoreline(np.asarray(d["t"])[ok])) ** 2))) / A
        result.metrics.append(Metric("rms of the shoreline less A sin(omega t), over A", rms,
                                     note="the timing; the nonlinear wave's shoreline is not a sine"))
        result.notes.append(f"{d['steps']:,} steps; the gauge's still-water zero is {d['zero'] / A:+.2f} A "
                            "from the still level (the last particle sits on the bed below the surface).")
        fig = figure(8.0, 3.0)
        ax = fig.add_subplot(1, 1, 1)
        t = np.asarray(d["t"])
        ax.plot(t / T, np.asarray(d["shoreline"]) / A, "-", lw=1.0, color="tab:blue", label="shoal: run-up gauge")
        ax.plot(t / T, wave.shoreline(t) / A, "k--", lw=1.0, label="linear theory: A sin(omega t)")
        for s in (-1, 1):
            ax.axhline(s, color="0.6", lw=0.6)
        ax.set_xlabel("t / T")
        ax.set_ylabel("shoreline elevation / A")
        ax.legend(fontsize=8, loc="lower right")
        path = save_png(fig, result.out / f"{self.name}.png")
        passed = all(m.passed for m in result.metrics if m.passed is not None)
        return [path], passed
