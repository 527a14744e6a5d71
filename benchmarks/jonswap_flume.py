"""A JONSWAP sea in a 2D flume for a whole repeat period of its components (issue 31, must-show 1).

An `irregular` piston paddle with active absorption makes a JONSWAP sea (Hs, Tp, gamma = 3.3) in water of
depth d; a still-water relaxation zone one peak wavelength long absorbs it at the far end. The components'
amplitudes are deterministic (a_n = sqrt(2 S(f_n) df)) and their frequencies multiples of df, so the linear
elevation repeats itself after 1/df: over exactly one repeat period, a gauge's periodogram (a boxcar window,
no averaging) puts each component in its own frequency bin, and linear theory says it is the target spectrum
bin for bin. Gauges at 1, 1.25, 1.5, 1.75 and 2 peak wavelengths from the paddle record from the time the
slowest component has reached the last gauge for one repeat period (`--components` 512 over 0.5-3 fp: 205 Tp).

The analysis (`shoal.analysis.spectral`): Hm0 = 4 sqrt(m0), Tp of the periodogram, and the variance in bands
of 0.1 fp from 0.7 to 1.5 fp against the target's.

    python benchmarks/jonswap_flume.py --dp 0.05 --out /tmp/jonswap       # d/dp = 10 (Hs = dp)
    python benchmarks/jonswap_flume.py --dp 0.05 --out /tmp/jonswap --analyse-only

Cost: 3,000 particles at dp = 0.05 m, about 680,000 steps to the end of the window (c0 = 44 m/s); measured
here at 19 ms a step on one shared core of the 2-core machine, 3.6 hours: a GPU run.
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "src"))


def build(dp, depth=0.5, hs=0.05, tp=1.5, gamma=3.3, components=512, seed=1, awas=True, interval=0.05):
    """The case and its facts (gauges, the analysis window)."""
    from shoal.active_absorption import ActiveAbsorption
    from shoal.case import Case, Checkpointing, Fluid, FluidRegion, Output, Solid
    from shoal.cases.wave_flume import WAVE_OPTIONS
    from shoal.geometry.shapes import Box, Tank
    from shoal.motions import IrregularWaves
    from shoal.options import SPHOptions
    from shoal.probes import WaveGauge
    from shoal.relaxation import RelaxationZone
    from shoal.waves import JonswapSpectrum, group_velocity, wavenumber

    spec = JonswapSpectrum(hs=hs, tp=tp, gamma=gamma)
    paddle = IrregularWaves(name="paddle", depth=depth, spectrum=spec, components=components, seed=seed,
                            absorption=ActiveAbsorption() if awas else None)
    lp = 2.0 * math.pi / wavenumber(tp, depth)
    gauges = [round(f * lp, 3) for f in (1.0, 1.25, 1.5, 1.75, 2.0)]
    zone = (gauges[-1] + 0.5 * lp, gauges[-1] + 1.5 * lp)
    top = depth + 4.0 * hs
    back = paddle.max_displacement + 4 * dp + 0.1
    w = paddle.wave_components
    slowest = float(np.min(group_velocity(w.wavenumbers[w.amplitudes > 0], depth)))
    t0 = paddle.ramp + gauges[-1] / slowest
    window = (t0, t0 + w.repeat_period)
    case = Case(name="jonswap-flume", dim=2, dp=float(dp), end_time=float(window[1] + 2 * interval),
                description=f"JONSWAP Hs = {hs:g} m, Tp = {tp:g} s, gamma = {gamma:g} in d = {depth:g} m, "
                            f"{components} components, a piston with active absorption",
                fluid=Fluid(depth=depth, surface_level=depth), options=SPHOptions(**WAVE_OPTIONS[2]),
                solids=[Solid(name="paddle", shape=Box(lo=(-4 * dp, 0, 0), hi=(0, 0, top)), motion="paddle"),
                        Solid(name="flume", shape=Tank(lo=(-back, 0, 0), hi=(zone[1], 0, top)))],
                fluids=[FluidRegion(shape=Box(lo=(0, 0, 0), hi=(zone[1], 0, depth)))],
                motions=[paddle], relaxation=[RelaxationZone(start=zone[0], end=zone[1])],
                probes=[WaveGauge(name=f"x{x:g}", x=x, z0=depth - 4 * hs, z1=top, interval=interval)
                        for x in gauges],
                output=Output(interval=float(window[1])), checkpoint=Checkpointing(wall_interval=600.0))
    info = dict(dp=dp, depth=depth, hs=hs, tp=tp, gamma=gamma, components=components, seed=seed,
                peak_wavelength=lp, gauges=gauges, zone=zone, window=window, repeat_period=w.repeat_period,
                particles=case.n_particles, interval=interval)
    return case, info, paddle


def analyse(out, info, paddle):
    """Hm0, Tp and the 0.1 fp bands of each gauge over the window, against the target components'."""
    w = paddle.wave_components
    fp = 1.0 / info["tp"]
    target_m0 = float(np.sum(0.5 * w.amplitudes**2))
    rows = {}
    for x in info["gauges"]:
        d = np.loadtxt(Path(out) / f"gauge_x{x:g}.csv", delimiter=",", skiprows=1, ndmin=2)
        t, eta = d[:, 0], d[:, 1] - info["depth"]
        a, b = info["window"]
        dt = info["interval"]
        n = int(round((b - a) / dt))
        # the samples themselves (the gauges record at multiples of the interval): interpolating between them
        # would filter the short components
        ts = math.ceil(a / dt - 1e-9) * dt + dt * np.arange(n)
        e = np.interp(ts, t, eta)
        e = e - e.mean()
        spec = np.fft.rfft(e) / n
        f = np.fft.rfftfreq(n, info["interval"])
        var = 2.0 * np.abs(spec) ** 2  # the variance of each bin (one-sided)
        var[0] = 0.0
        m0 = float(np.sum(var))
        k = int(np.argmax(var))
        bands = []
        for lo in np.arange(0.7, 1.5 - 1e-9, 0.1):
            sel = (f >= lo * fp - 1e-12) & (f < (lo + 0.1) * fp - 1e-12)
            tsel = (w.frequencies >= lo * fp - 1e-12) & (w.frequencies < (lo + 0.1) * fp - 1e-12)
            bands.append(float(np.sum(var[sel]) / np.sum(0.5 * w.amplitudes[tsel] ** 2)) - 1.0)
        rows[f"{x:g}"] = dict(hm0=4.0 * math.sqrt(m0), hm0_error=math.sqrt(m0 / target_m0) - 1.0,
                              tp=1.0 / f[k], tp_error=(1.0 / f[k]) / info["tp"] - 1.0, band_errors=bands)
    return dict(target_hm0=4.0 * math.sqrt(target_m0), gauges=rows)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--dp", type=float, default=0.05)
    ap.add_argument("--components", type=int, default=512)
    ap.add_argument("--no-awas", action="store_true")
    ap.add_argument("--out", type=Path, required=True)
    ap.add_argument("--analyse-only", action="store_true")
    a = ap.parse_args(argv)
    case, info, paddle = build(a.dp, components=a.components, awas=not a.no_awas)
    print(json.dumps(info, indent=1, default=float), flush=True)
    if not a.analyse_only:
        from shoal.runner import run_case

        t0 = time.perf_counter()
        run_case(case, a.out, plot=False, overwrite=True)
        info["wall_s"] = time.perf_counter() - t0
    info.update(analyse(a.out, info, paddle))
    (a.out / "jonswap_summary.json").write_text(json.dumps(info, indent=2, default=float) + "\n")
    print(json.dumps(info, indent=2, default=float))


if __name__ == "__main__":
    main()
