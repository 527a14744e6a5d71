"""Wave set-up along two 2D cross-shore transects of the rip-current basin: over the bar and in the
rip channel, at several particle spacings (a documented study, not a CI test).

Why: the 3D check of issue 6, item 5 (the mean water level over the bar stands above that in the
rip channel) fails at the coarse CPU resolution of ``run.py`` (dp = 0.075 m, two particles over
the bar crest), and ``README.md`` puts that down to resolution: the breaking over the bar and the
radiation-stress gradient that raises the mean level behind it are not resolved. The 3D run at
dp <= 0.03 m is a GPU run. These 2D transects cost a hundredth of it, so they can show on a CPU
whether the set-up difference between the bar's profile and the channel's appears as dp falls,
with the same scheme, waves, gauges and analysis as the 3D run.

Each transect is the bed profile of the 3D basin along one line (y = 2.5 m, the middle of the bar;
y = 0.5 m, the middle of the channel: `run.bed_level`), in the x-z plane, with the paddle, end
wall, options (`run.OPTIONS`), wave gauges (the 3D run's x positions) and averaging window (the
last 5 of 15 periods) of ``run.py``. A 2D transect has no alongshore flow: the water set up
behind the bar cannot escape through the channel, so the 2D difference bounds the 3D one from
above; what it shows is whether the set-up is resolved at a given dp.

    PYTHONPATH=src python validation/rip-current/transects.py --dp 0.075 0.0375 --out /tmp/shoal-transects
    PYTHONPATH=src python validation/rip-current/transects.py --dp 0.075 0.0375 --out /tmp/shoal-transects --analyse

The analysis writes ``transects.json`` in `--out` and prints the table of ``README.md``.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import run as rip  # noqa: E402  (this folder's run.py: the 3D run's settings)

import shoal  # noqa: E402
from shoal.case import Case, Fluid, FluidRegion, Output, Solid  # noqa: E402
from shoal.geometry.shapes import Bathymetry, Box, Profile, Tank  # noqa: E402
from shoal.motions import PistonWavemaker  # noqa: E402
from shoal.probes import WaveGauge  # noqa: E402

TRANSECTS = {"bar": 2.5, "channel": 0.5}  # y of each transect in the 3D basin [m]
GAUGE_X = {"offshore": 5.5, "toe": 9.0, "crest": rip.CREST_X, "trough": 14.0, "inshore": 16.0}
WAVE_HEIGHT = 0.19
STILL = (0.3, 1.8)  # s: the gauges' still-water reading (before the first wave arrives), as analyse.py
N_PERIODS = 5       # averaging window: the last 5 whole periods


def still_water_level():
    from shoal.cases.rip_current import rip_current_bed

    return rip_current_bed()[2] + 0.15  # 0.15 m of water over the crest


def transect_case(which, dp, end_time=rip.END_TIME, paddle_x=rip.PADDLE_X, basin_end=rip.BASIN_END):
    """The 2D case along transect `which` ('bar' or 'channel') at spacing `dp`."""
    from shoal.cases.rip_current import rip_current_bed

    y = TRANSECTS[which]
    xs = list(rip_current_bed()[0].x)
    profile = Profile(x=xs, z=[rip.bed_level(x, y) for x in xs])
    swl = still_water_level()
    piston = PistonWavemaker(name="piston", height=WAVE_HEIGHT, period=rip.PERIOD, depth=swl, ramp_periods=2.0)
    top = swl + 0.3
    paddle_t = 4 * dp
    x_back = paddle_x - 0.5 * piston.stroke - paddle_t - 2 * dp
    solids = [
        Solid(name="paddle", shape=Box(lo=(paddle_x - paddle_t, 0.0, 0.0), hi=(paddle_x, 0.0, top)), motion="piston"),
        Solid(name="bed", shape=Bathymetry(profile=profile)),
        Solid(name="basin", shape=Tank(lo=(x_back, 0.0, 0.0), hi=(basin_end, 0.0, top))),
    ]
    fluids = [FluidRegion(shape=Box(lo=(paddle_x, 0.0, 0.0), hi=(basin_end, 0.0, swl)))]
    gauges = [WaveGauge(name=name, x=x, y=0.0, z0=round(rip.bed_level(x, y) + dp, 4), z1=round(swl + 0.3, 4),
                        interval=rip.GAUGE_INTERVAL) for name, x in GAUGE_X.items()]
    return Case(name=f"rip-transect-{which}", dim=2, dp=float(dp), end_time=float(end_time),
                description=f"2D transect of the rip-current basin along y = {y:g} m ({which})",
                fluid=Fluid(depth=swl, surface_level=swl), options=shoal.SPHOptions(**rip.OPTIONS),
                solids=solids, fluids=fluids, motions=[piston], probes=gauges,
                output=Output(interval=rip.OUTPUT_INTERVAL),
                parameters=dict(transect=which, y=y, dp=dp, still_water_level=swl, paddle_x=paddle_x,
                                basin_end=basin_end, stroke=piston.stroke))


def run_dir(out, which, dp):
    return Path(out) / f"{which}_dp{dp:g}"


def analyse_run(path, swl, end_time=rip.END_TIME):
    """Set-up (mm, corrected by the gauge's still-water reading) and wave height of each gauge."""
    from shoal.analysis import set_up
    from shoal.post import _read_csv

    t0 = end_time - N_PERIODS * rip.PERIOD
    out = {}
    for name in GAUGE_X:
        header, data = _read_csv(path / f"gauge_{name}.csv")
        t, lev = data[:, 0], data[:, 1]
        ref = float(np.nanmean(lev[(t >= STILL[0]) & (t <= STILL[1])]))
        su = set_up(lev, t, rip.PERIOD, t0, swl, N_PERIODS)
        w = t >= t0 - 1e-9
        heights = [float(np.nanmax(lev[w & (t >= t0 + k * rip.PERIOD) & (t <= t0 + (k + 1) * rip.PERIOD)])
                         - np.nanmin(lev[w & (t >= t0 + k * rip.PERIOD) & (t <= t0 + (k + 1) * rip.PERIOD)]))
                   for k in range(N_PERIODS)]
        out[name] = {"setup_mm": 1e3 * (su + swl - ref), "setup_raw_mm": 1e3 * su,
                     "still_water_offset_mm": 1e3 * (ref - swl), "wave_height_m": float(np.mean(heights))}
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", required=True, help="folder for the runs (outside the repository)")
    ap.add_argument("--dp", type=float, nargs="+", default=[0.075, 0.0375])
    ap.add_argument("--transect", choices=sorted(TRANSECTS), nargs="+", default=sorted(TRANSECTS))
    ap.add_argument("--end-time", type=float, default=rip.END_TIME)
    ap.add_argument("--analyse", action="store_true", help="analyse finished runs, do not run")
    ap.add_argument("--check", action="store_true", help="print the counts and time step, do not run")
    a = ap.parse_args(argv)
    swl = still_water_level()
    if not a.analyse:
        for dp in a.dp:
            for which in a.transect:
                case = transect_case(which, dp, a.end_time)
                if a.check:
                    from shoal.check import check_case

                    print("\n".join(check_case(case)))
                    continue
                res = shoal.run_case(case, run_dir(a.out, which, dp), progress=False, plot=False, overwrite=True)
                print(f"{which} dp = {dp:g}: {res.steps} steps, {res.particles} particles, {res.wall_seconds:.0f} s "
                      f"wall, {res.particle_steps_per_second:.3g} particle-steps/s", flush=True)
        if a.check:
            return 0
    results = {}
    for dp in a.dp:
        r = {w: analyse_run(run_dir(a.out, w, dp), swl, a.end_time) for w in TRANSECTS}
        results[f"{dp:g}"] = dict(r, bar_minus_channel_mm={g: r["bar"][g]["setup_mm"] - r["channel"][g]["setup_mm"]
                                                          for g in GAUGE_X})
    (Path(a.out) / "transects.json").write_text(json.dumps(results, indent=1) + "\n")
    print("| dp [m] | gauge | x [m] | set-up bar [mm] | set-up channel [mm] | bar - channel [mm] | H bar / channel [m] |")
    print("|---|---|---|---|---|---|---|")
    for dp, r in results.items():
        for g, x in GAUGE_X.items():
            print(f"| {dp} | {g} | {x:g} | {r['bar'][g]['setup_mm']:+.1f} | {r['channel'][g]['setup_mm']:+.1f} | "
                  f"{r['bar_minus_channel_mm'][g]:+.1f} | {r['bar'][g]['wave_height_m']:.3f} / "
                  f"{r['channel'][g]['wave_height_m']:.3f} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
