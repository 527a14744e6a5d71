"""Periodic run-up on a plane beach: the standing wave of Carrier & Greenspan (1958).

The flume (`periodic_runup_flume`): a 2D beach of slope 1:cot from a piston paddle at x = 0, where the
still water is d deep, to above the run-up; the still-water shoreline is at x = d cot. The flume starts
from the nonlinear wave's moment of rest (`shoal.analysis.beach_standing_wave`): at the lowest rundown,
t = -T/4, every particle is still, the surface is the solution's (`BeachStandingWave.rundown_surface`)
and the density is hydrostatic under it (`start_at_rest`). The paddle then moves as the water column at
its face does in the nonlinear solution (`BeachStandingWave.column_path`), so the flume is driven and
started in the nonlinear wave's own state and has no transient to wait out. A run-up gauge follows the
tip of the water that still interacts with the body (any particle, dry stretches up to the kernel
support bridged); its offset from the true shoreline is read at the start, where the shoreline is at -A.
"""

from __future__ import annotations

import math
import tempfile
import time
from pathlib import Path

import numpy as np

from ..physics.spec import FLUID
from . import runs
from .core import Metric, ValidationCase, figure, save_png


def periodic_runup_flume(wave, depth, cot, dp, options, end_time, folder, interval=None, fit_surface=True):
    """The case of the flume for `wave` (a `BeachStandingWave`), started at the solution's rundown
    (run time 0 is the solution's t = -T/4); the paddle's displacement is written to `folder` as a time
    series from one period before the start (the spline's clamped start stays off the run). With
    `fit_surface` (default) the beach's wall particles lie on layers parallel to it
    (`shoal.geometry.surface_fit`) instead of the lattice's staircase.

    Returns
    -------
    Case
        With the run-up gauge ``tip`` and a wave gauge ``offshore`` (halfway to the paddle in sigma, or
        at J0's first extremum sigma = 3.83 when the paddle lies beyond it).
    """
    from ..case import Case, Fluid, FluidRegion, Output, Solid
    from ..geometry.shapes import Box, Prism, Slope, Tank
    from ..motions import TimeSeriesMotion
    from ..probes import RunupGauge, WaveGauge

    d, s = float(depth), 1.0 / cot
    shore = d * cot
    T, t0 = wave.period, wave.rundown_time
    t = np.arange(-T, end_time + T, T / 400)
    path = Path(folder) / "paddle.txt"
    path.parent.mkdir(parents=True, exist_ok=True)
    np.savetxt(path, np.column_stack([t, shore - wave.column_path(shore, t0, t0 + t)]),
               header="t [s], x [m]: the paddle of the Carrier & Greenspan standing wave, the water column "
                      "at its face")
    top = d + 3 * wave.amplitude + 4 * dp
    x_end = top * cot
    # the water at rest under the rundown surface, from the paddle's face to the shoreline (the beach
    # solid holds the lattice nodes below its surface)
    X = np.linspace(wave.amplitude / s, shore, 2001)
    surface = [(float(shore - Xk), float(d + zk)) for Xk, zk in zip(X[::-1], wave.rundown_surface(X[::-1]))]
    water = Prism(axis="y", vertices=[(0.0, 0.0)] + surface + [(shore - X[0], 0.0)])
    solids = [Solid(name="paddle", shape=Box(lo=(-4 * dp, 0.0, 0.0), hi=(0.0, 0.0, top)), motion="paddle"),
              Solid(name="beach", shape=Slope(x0=0.0, z0=0.0, gradient=s), fit_surface=fit_surface),
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
                options=options, solids=solids, fluids=[FluidRegion(shape=water)],
                motions=[TimeSeriesMotion(name="paddle", file=str(path))], probes=probes,
                output=Output(interval=end_time))


def start_at_rest(model, wave, depth, shore):
    """Give the fluid particles the hydrostatic density under the rundown surface, rho0 (1 + rho0 g
    (z_s - z) / B)^(1/7) with z_s = depth + `wave.rundown_surface` at their offshore distance (the
    model's initial density is that of a flat surface at `depth`); they are at rest as the wave is."""
    from ..physics.eos import density_of

    fluid = model.host(model.kind) == FLUID
    p = model.world_positions()[fluid]
    z_s = depth + np.nan_to_num(wave.rundown_surface(shore - p[:, 0]), nan=-np.inf)
    rho = model.host(model.rho)
    under = np.clip(z_s - p[:, 2], 0.0, None)
    g = float(np.linalg.norm(model.gravity))
    rho[fluid] = density_of(model.rho0 * g * under, model.rho0, model.B)
    model.backend.copy_into(model.rho, rho.astype(model.dtype), model.n)


def run_periodic_runup(wave, depth, cot, dp, options, periods, folder, backend="cpu", fit_surface=True):
    """Run the flume from the rundown for `periods` periods of the solution's time t >= 0 (a quarter
    period more: run time = t + T/4).

    Returns
    -------
    dict
        t [s, the solution's time], shoreline [m above the still level: the gauge's reading less its
        offset at the start, where the shoreline is at -A], zero [m, that offset: the gauge's reading
        less the true shoreline], offshore [m, the wave gauge less the still level] at offshore_t,
        X_offshore [m], steps, particles, seconds.
    """
    from ..probes import make_recorder
    from ..build import build_model
    from ..simulation import Simulation, TimeInterval

    t0 = time.perf_counter()
    end = (periods + 0.25) * wave.period
    shore = depth * cot
    case = periodic_runup_flume(wave, depth, cot, dp, options, end, folder, fit_surface=fit_surface)
    model = build_model(case, backend)
    start_at_rest(model, wave, depth, shore)
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
    zero = float(tip[0, 1]) - (depth - wave.amplitude)
    return dict(t=tip[:, 0] + wave.rundown_time, shoreline=tip[:, 1] - depth - zero, zero=zero,
                offshore_t=gauge[:, 0] + wave.rundown_time, offshore=gauge[:, 1] - depth,
                X_offshore=float(shore - case.probes[0].x), steps=sim.step_count, particles=case.n_particles,
                seconds=time.perf_counter() - t0)


def excursions(t, z, period):
    """Per whole period from t = 0: (highest, lowest) of z (NaNs and t < 0 left out)."""
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
             "first natural mode 3.83). The flume starts from the nonlinear solution's moment of rest, "
             "the lowest rundown (its surface, hydrostatic density, no motion), and the paddle moves as the "
             "solution's water column at its face, so there is no start-up transient. The beach's wall particles "
             "lie on layers parallel to it (`fit_surface = true`). Run-up gauge: the tip "
             "of the water that still interacts with the body (`min_depth = dp`, `max_gap = 2h`), its offset "
             "from the shoreline read at the start (shoreline at -A). The wave flumes' scheme (laminar "
             "viscosity, coef_h = 1.5), Adami walls, float32. `--quick`: d/dp = 10, 1 period; `--full`: "
             "d/dp = 20, 3 periods (each after the first quarter period).")
    reference = ("Analytic: the nonlinear standing wave of Carrier & Greenspan (1958, J. Fluid Mech. 4, "
                 "97-109) by their hodograph transformation, whose shoreline reaches exactly +A and -A below "
                 "breaking (epsilon < 1); its linear limit eta = A J0(sigma) sin(omega t), sigma = 2 omega "
                 "sqrt(X / (g s)) (Lamb 1932, section 186).")
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
        t = np.asarray(d["t"])
        z = np.asarray(d["shoreline"])
        ok = np.isfinite(z) & (t >= 0)
        rms = float(np.sqrt(np.mean((z[ok] - wave.nonlinear_shoreline(t[ok])) ** 2))) / A
        result.metrics.append(Metric("rms of the shoreline less the nonlinear solution's, over A", rms,
                                     note="the shape and timing of the run-up and rundown"))
        if "offshore" in d:
            tg, zg = np.asarray(d["offshore_t"]), np.asarray(d["offshore"])
            eta = wave.nonlinear(d["X_offshore"], tg)[0]
            on = (tg >= 0) & np.isfinite(zg) & np.isfinite(eta)
            scale = 0.5 * (np.nanmax(eta) - np.nanmin(eta))
            result.metrics.append(Metric(
                f"offshore surface (X = {d['X_offshore']:.2f} m) less the nonlinear solution's, rms over its "
                "amplitude", float(np.sqrt(np.mean((zg[on] - eta[on]) ** 2))) / scale,
                note="the standing wave the paddle keeps up"))
        result.notes.append(f"{d['steps']:,} steps; the gauge reads {d['zero'] / A:+.2f} A from the true "
                            "shoreline at the start (the last particle sits on the bed below the surface).")
        fig = figure(8.0, 3.0)
        ax = fig.add_subplot(1, 1, 1)
        ax.plot(t / T, z / A, "-", lw=1.0, color="tab:blue", label="shoal: run-up gauge")
        tt = np.linspace(t[0], t[-1], 2000)
        ax.plot(tt / T, wave.nonlinear_shoreline(tt) / A, "k--", lw=1.0,
                label="Carrier & Greenspan (nonlinear shallow water)")
        ax.axvline(0.0, color="0.6", lw=0.6, ls=":")
        for sgn in (-1, 1):
            ax.axhline(sgn, color="0.6", lw=0.6)
        ax.set_xlabel("t / T (the run starts at rest at -T/4)")
        ax.set_ylabel("shoreline elevation / A")
        ax.legend(fontsize=8, loc="lower right")
        path = save_png(fig, result.out / f"{self.name}.png")
        passed = all(m.passed for m in result.metrics if m.passed is not None)
        return [path], passed
