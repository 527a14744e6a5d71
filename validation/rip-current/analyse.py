"""Analyse the rip-current validation run (issue 6, item 5; see README.md and run.py).

    PYTHONPATH=src python validation/rip-current/analyse.py runs/rip-0.05

Reads the run directory (``testpoints_bar.nc``, ``gauge_*.csv``, ``case.toml``, ``run.log``) and

* averages the test points over the last `--periods` whole wave periods of the record and over the
  wet depth with `shoal.analysis` (`period_average`, `depth_average`: U = <q_x> / <h>, the mean
  volume flux over the mean wet depth, as `shoal.post.mean_flow` does), and takes the vertical
  vorticity of that mean current (`shoal.analysis.vorticity`, Omega = dV/dx - dU/dy);
* measures the set-up (period-mean water level minus the still-water level) from the wave gauges
  (`shoal.analysis.set_up`) and from the test-point columns, over the bar and in the rip channel;
  both raw and relative to the level each gauge / column reads in still water at the start (the
  kernel-sum surface of a coarse lattice sits a fraction of dp off the nominal level, and the
  offset depends on the depth: over the crest the water is two or three particles deep);
* gives the sign of the mean cross-shore current in the channel (x points onshore: U < 0 is
  offshore) and the sense of rotation of the mean circulation over the bar and near the shore
  (circulation = the line integral of the mean current round a rectangle = the area integral of
  Omega; in these axes, x onshore and y from the channel wall to the bar wall, the paper's primary
  cell, onshore over the bar and offshore in the channel, has Omega < 0);
* writes ``results.json`` and makes the plan-view mean-current and mean-water-level PNGs with
  `shoal.post.plot_mean_flow`, copied here as ``meanflow_current.png`` and ``meanflow_setup.png``
  (or to `--out`; a `--preview DIR` of a run still going writes them to DIR unless `--out` says
  otherwise, so it never replaces the finished run's results kept here).
"""

from __future__ import annotations

import argparse
import json
import re
import shutil
import sys
import tempfile
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent

# regions (case coordinates, m): x onshore from the rest position of the case's paddle; the bar
# crest at x = 12.4, the bar from its toe at 8.89 to 13.69, the beach toe at 14.4, the shoreline at
# 17.9; the channel is y in [0, 1] (0.1 m wide transition at y = 1), the bar y in [1, 4]
CREST = (11.9, 12.9)           # the crest line +- 0.5 m
BAR_Y = (1.5, 4.0)             # over the bar, clear of the transition
CHANNEL_Y = (0.0, 0.75)        # in the channel, clear of the transition
CHANNEL_X = (9.0, 13.7)        # along the channel, from the bar toe to the bar's shoreward end
BAR_CELL = dict(x=(9.0, 14.0), y=(0.15, 3.85))       # the primary cell: over the bar and channel
NEARSHORE_CELL = dict(x=(14.0, 17.3), y=(0.15, 3.85))  # shoreward of the bar, in the surf zone
STILL = (0.3, 1.8)             # still-water reference window [s] (before the waves reach x >= 8 m)


MAX_PNG_BYTES = 200_000


def _shrink_png(path):
    """Re-save a PNG with a 256-colour palette (the plots have few colours) to keep it small."""
    from PIL import Image

    with Image.open(path) as im:
        small = im.convert("RGB").quantize(colors=256, method=Image.Quantize.MEDIANCUT)
    small.save(path, optimize=True)


def _sel(da, x=None, y=None):
    """The part of a (y, x) DataArray inside the ranges."""
    if x is not None:
        da = da.sel(x=slice(*x))
    if y is not None:
        da = da.sel(y=slice(*y))
    return da


def _mean(da):
    v = np.asarray(da.values, float)
    return float(np.nanmean(v)) if np.isfinite(v).any() else float("nan")


def circulation(U, V, x, y, box):
    """Line integral of (U, V) anticlockwise round the rectangle `box` (nearest grid lines), and
    the mean vorticity it implies (circulation / area) [m^2/s, 1/s]. NaN edges (dry) are skipped."""
    i0, i1 = (int(np.argmin(np.abs(x - v))) for v in box["x"])
    j0, j1 = (int(np.argmin(np.abs(y - v))) for v in box["y"])
    xs, ys = x[i0:i1 + 1], y[j0:j1 + 1]

    def line(vals, coord):
        ok = np.isfinite(vals)
        return float(np.trapezoid(np.where(ok, vals, 0.0), coord)), bool(ok.all())

    bottom, b_ok = line(U[j0, i0:i1 + 1], xs)        # y = y0, going +x
    right, r_ok = line(V[j0:j1 + 1, i1], ys)         # x = x1, going +y
    top, t_ok = line(U[j1, i0:i1 + 1], xs)           # y = y1, going -x
    left, l_ok = line(V[j0:j1 + 1, i0], ys)          # x = x0, going -y
    gamma = bottom + right - top - left
    area = (xs[-1] - xs[0]) * (ys[-1] - ys[0])
    return {"x": [float(xs[0]), float(xs[-1])], "y": [float(ys[0]), float(ys[-1])],
            "circulation_m2_s": gamma, "mean_vorticity_1_s": gamma / area,
            "edges_fully_wet": b_ok and r_ok and t_ok and l_ok,
            "edge_integrals_m2_s": {"bottom_+x": bottom, "right_+y": right, "top_+x": top, "left_+y": left}}


def preview_from_checkpoint(run_dir, dest):
    """A run still going has no ``testpoints_bar.nc`` yet (it is written at the end): rebuild it
    from the test-point samples held in the newest checkpoint (read only; the run is not
    touched) into `dest`, with copies of ``case.toml``, ``run.log`` and the gauge CSVs. Returns
    `dest` and the checkpoint's time."""
    from shoal.casefile import load_case
    from shoal.probes import GridRecorder, TestPoints
    from shoal.simulation.resume import latest_checkpoint

    dest.mkdir(parents=True, exist_ok=True)
    ck = latest_checkpoint(run_dir)
    for p in [run_dir / "case.toml", run_dir / "run.log", *sorted(run_dir.glob("gauge_*.csv"))]:
        shutil.copyfile(p, dest / p.name)
    case = load_case(run_dir / "case.toml")
    for k, cb in enumerate(ck.meta["callbacks"]):
        spec = next((q for q in case.probes if isinstance(q, TestPoints) and cb["name"] == f"probe {q.name}"), None)
        if spec is None:
            continue
        arrays = ck.callbacks.get(k, {})
        rec = GridRecorder(spec, dest)
        keys = cb.get("state", {}).get("sample_keys", [])
        rec.times = list(arrays["times"])
        rec.samples = [{key: arrays[f"samples/{key}"][i] for key in keys} for i in range(len(rec.times))]
        rec.close()
    return dest, ck.time


def run_stats(run_dir):
    """Steps, simulated time and wall time from run.log (the 'done' line, else the last step line)."""
    log = (run_dir / "run.log").read_text(encoding="utf-8", errors="replace") if (run_dir / "run.log").exists() else ""
    out = {}
    m = re.findall(r"particles (\d+) \(fluid (\d+)\)", log)
    if m:
        out["particles"], out["fluid_particles"] = int(m[-1][0]), int(m[-1][1])
    m = re.findall(r"particles \d+ \(fluid \d+\), dp ([\d.eE+-]+) m", log)
    if m:
        out["dp"] = float(m[-1])
    done = re.findall(r"done: (\d+) steps to t = ([\d.eE+-]+)(?: s)? in ([\d.]+) s wall \(([\d.]+) s compile\), "
                      r"([\d.eE+-]+) particle-steps/s", log)
    if done:
        s, t, w, c, r = done[-1]
        out.update(finished=True, steps=int(s), t_end=float(t), wall_seconds=float(w), compile_seconds=float(c),
                   particle_steps_per_second=float(r))
    else:
        steps = re.findall(r"step (\d+) t ([\d.eE+-]+) s", log)
        if steps:
            out.update(finished=False, steps=int(steps[-1][0]), t_end=float(steps[-1][1]))
    # the computing time from the log's clock: each process (the start and every --resume) is a segment
    # from its "particles ..." line to its last line; their sum counts a stopped process's work after its
    # last checkpoint, which the resumed process redid, twice (checkpoints came every 15 min)
    from datetime import datetime

    segments, start, last = [], None, None
    for line in log.splitlines():
        m = re.match(r"(\d{4}-\d\d-\d\d \d\d:\d\d:\d\d)", line)
        if not m:
            continue
        stamp = datetime.strptime(m.group(1), "%Y-%m-%d %H:%M:%S")
        if re.search(r"INFO particles \d+ \(fluid", line):
            if start is not None:
                segments.append((last - start).total_seconds())
            start = stamp
        last = stamp
    if start is not None:
        segments.append((last - start).total_seconds())
        out.update(processes=len(segments), log_compute_seconds=sum(segments))
        if out.get("steps") and out["log_compute_seconds"] > 0 and "particles" in out:
            out["log_particle_steps_per_second"] = out["particles"] * out["steps"] / out["log_compute_seconds"]
    return out


def gauge_analysis(run_dir, swl, period, t0, n):
    """Set-up, still-water reading and wave height of every gauge over the window."""
    from shoal.analysis import set_up
    from shoal.post import _read_csv

    out = {}
    for path in sorted(run_dir.glob("gauge_*.csv")):
        header, data = _read_csv(path)
        if len(data) < 2:
            continue
        t, lev = data[:, 0], data[:, 1]
        still = lev[(t >= STILL[0]) & (t <= STILL[1])]
        ref = float(np.nanmean(still)) if still.size else float("nan")
        try:
            su = set_up(lev, t, period, t0, swl, n)
        except Exception as err:  # a record too short
            out[path.stem[6:]] = {"error": str(err)}
            continue
        heights = []
        for k in range(n):
            w = (t >= t0 + k * period - 1e-9) & (t <= t0 + (k + 1) * period + 1e-9)
            if w.sum() > 3:
                heights.append(float(np.nanmax(lev[w]) - np.nanmin(lev[w])))
        out[path.stem[6:]] = {"still_water_reading_m": ref, "still_water_offset_mm": 1e3 * (ref - swl),
                              "setup_raw_mm": 1e3 * su, "setup_mm": 1e3 * (su + swl - ref),
                              "wave_height_m": float(np.mean(heights)) if heights else float("nan"),
                              "wave_height_per_period_m": heights}
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("run_dir")
    ap.add_argument("--period", type=float, default=None, help="wave period [s] (default: the case's)")
    ap.add_argument("--periods", type=int, default=1,
                    help="average over the last N periods (1: the paper averages over one wave period)")
    ap.add_argument("--out", default=None,
                    help="where results.json and the two PNGs go (default: this folder; with --preview, its DIR)")
    ap.add_argument("--preview", default=None, metavar="DIR",
                    help="the run is still going: analyse the newest checkpoint's test points (copied to DIR)")
    a = ap.parse_args(argv)
    # a preview must not replace the finished run's results kept here
    a.out = a.out or a.preview or str(HERE)

    import xarray as xr

    from shoal.analysis import depth_average, period_average, vorticity
    from shoal.post import _window, plot_mean_flow, run_info, surface_levels

    run_dir, out = Path(a.run_dir), Path(a.out)
    preview_time = None
    if a.preview:
        live = run_dir
        run_dir, preview_time = preview_from_checkpoint(live, Path(a.preview))
        print(f"preview of the run in {live}: test points up to the checkpoint at t = {preview_time:.4g} s")
    info = run_info(run_dir)
    swl, period = info["surface_level"], a.period or info["period"]
    with xr.open_dataset(run_dir / "testpoints_bar.nc", engine="scipy") as f:
        ds = f.load()
    t0, T, n = _window(ds["time"].values, period, a.periods, None)  # the last n whole periods
    x, y, z = (np.asarray(ds[c].values, float) for c in ("x", "y", "z"))

    # period- and depth-averaged current: U = <q_x> / <h> over the wet nodes (kernel sum >= 1/2)
    wet = ds["kernel_sum"] >= 0.5
    per_sample = depth_average(xr.Dataset({"u": ds["u"].where(wet, 0.0), "v": ds["v"].where(wet, 0.0),
                                           "kernel_sum": ds["kernel_sum"]}))
    mean = period_average(per_sample[["u_flux", "v_flux", "depth"]], T, t0, n)
    h = mean["depth"].where(mean["depth"] > 0)
    U = (mean["u_flux"] / h).transpose("y", "x")
    V = (mean["v_flux"] / h).transpose("y", "x")
    omega = xr.DataArray(vorticity(U.values, V.values, x, y), dims=("y", "x"), coords={"y": y, "x": x})

    # mean water level of each column (kernel-sum surface), its still-water reading, the set-up
    ks = ds["kernel_sum"].transpose("time", "y", "x", "z").values
    lev = xr.DataArray(surface_levels(ks, z), dims=("time", "y", "x"),
                       coords={"time": ds["time"], "y": y, "x": x})
    level = period_average(lev, T, t0, n)
    still = lev.sel(time=slice(*STILL)).mean("time")
    setup_raw = level - swl
    setup = level - still
    # columns wet at rest and wet all through the window (the swash zone's columns are not)
    always_wet = np.isfinite(lev.sel(time=slice(t0 - 1e-9, t0 + n * T + 1e-9))).all("time") & np.isfinite(still)
    setup_raw, setup = setup_raw.where(always_wet), setup.where(always_wet)

    def region(da, xr_, yr_):
        return _mean(_sel(da, xr_, yr_))

    crest_bar, crest_ch = region(setup, CREST, BAR_Y), region(setup, CREST, CHANNEL_Y)
    raw_bar, raw_ch = region(setup_raw, CREST, BAR_Y), region(setup_raw, CREST, CHANNEL_Y)
    bar_x = (9.0, 13.7)
    bar_all, ch_all = region(setup, bar_x, BAR_Y), region(setup, bar_x, CHANNEL_Y)
    U_ch = _sel(U, CHANNEL_X, CHANNEL_Y)
    U_channel = _mean(U_ch)
    along = U_ch.mean("y")
    gauges = gauge_analysis(run_dir, swl, T, t0, n)

    def g(name, key="setup_mm"):
        return gauges.get(name, {}).get(key, float("nan"))

    bar_cell = circulation(U.values, V.values, x, y, BAR_CELL)
    near_cell = circulation(U.values, V.values, x, y, NEARSHORE_CELL)
    om_bar = region(omega, BAR_CELL["x"], BAR_CELL["y"])
    om_near = region(omega, NEARSHORE_CELL["x"], NEARSHORE_CELL["y"])
    two_cells = bool(bar_cell["circulation_m2_s"] < 0 < near_cell["circulation_m2_s"])

    results = {
        "run_dir": str(run_dir), "run": run_stats(run_dir),
        "preview_of_unfinished_run_checkpoint_time_s": preview_time,
        "still_water_level_m": swl, "period_s": T,
        "window_s": [float(t0), float(t0 + n * T)], "periods_averaged": n,
        "test_points": {"counts_x_y_z": [len(x), len(y), len(z)], "x": [x[0], x[-1]], "y": [y[0], y[-1]],
                        "z": [z[0], z[-1]], "samples": int(ds.sizes["time"]),
                        "interval_s": float(np.median(np.diff(ds["time"].values)))},
        "regions": {"crest_x": CREST, "bar_y": BAR_Y, "channel_y": CHANNEL_Y, "channel_x": CHANNEL_X,
                    "bar_x": bar_x, "still_reference_s": STILL},
        "setup_grid_mm": {
            "crest_bar": 1e3 * crest_bar, "crest_channel": 1e3 * crest_ch,
            "crest_bar_minus_channel": 1e3 * (crest_bar - crest_ch),
            "crest_bar_raw": 1e3 * raw_bar, "crest_channel_raw": 1e3 * raw_ch,
            "crest_bar_minus_channel_raw": 1e3 * (raw_bar - raw_ch),
            "bar_region": 1e3 * bar_all, "channel_region": 1e3 * ch_all,
            "bar_region_minus_channel_region": 1e3 * (bar_all - ch_all),
            "still_offset_range_mm": [1e3 * float(np.nanmin(still.values - swl)),
                                      1e3 * float(np.nanmax(still.values - swl))]},
        "gauges": gauges,
        "setup_gauges_mm": {
            "crest_bar_minus_channel": g("crest_bar") - g("crest_channel"),
            "crest_bar_minus_channel_raw": g("crest_bar", "setup_raw_mm") - g("crest_channel", "setup_raw_mm"),
            "trough_bar_minus_channel": g("trough_bar") - g("trough_channel"),
            "inshore_bar_minus_channel": g("inshore_bar") - g("inshore_channel")},
        "channel_current": {
            "U_mean_m_s": U_channel, "direction": "offshore" if U_channel < 0 else "onshore",
            "U_min_m_s": float(np.nanmin(U_ch.values)), "U_max_m_s": float(np.nanmax(U_ch.values)),
            "fraction_of_channel_nodes_offshore": float(np.mean(U_ch.values[np.isfinite(U_ch.values)] < 0)),
            "along_channel": {f"{xx:.2f}": float(v) for xx, v in zip(along["x"].values, along.values)},
            "V_trough_into_channel_m_s": _mean(_sel(V, (13.7, 14.4), (1.0, 2.5))),
            "U_over_bar_m_s": _mean(_sel(U, (11.0, 13.7), BAR_Y))},
        "vorticity": {"bar_cell": bar_cell, "nearshore_cell": near_cell,
                      "area_mean_bar_cell_1_s": om_bar, "area_mean_nearshore_cell_1_s": om_near,
                      "convention": "Omega = dV/dx - dU/dy, x onshore, y from the channel wall (y = 0) to the bar "
                                    "wall (y = 4); the paper's primary cell (onshore over the bar, offshore in the "
                                    "channel) has Omega < 0 in these axes; the paper plots x the other way "
                                    "(waves from the right), where it shows it anticlockwise"},
        "checks": {"setup_bar_above_channel_at_crest_grid": bool(crest_bar > crest_ch),
                   "setup_bar_above_channel_at_crest_gauges": bool(g("crest_bar") > g("crest_channel")),
                   "channel_current_offshore": bool(U_channel < 0),
                   "two_counter_rotating_cells": two_cells},
    }

    out.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory() as tmp:
        written = plot_mean_flow(run_dir, tmp, period=T, periods=n)
        copies = {}
        for p in written:
            for kind in ("current", "setup"):
                if p.name.endswith(f"_{kind}.png"):
                    dest = out / f"meanflow_{kind}.png"
                    shutil.copyfile(p, dest)
                    if dest.stat().st_size > MAX_PNG_BYTES:
                        _shrink_png(dest)
                    copies[dest.name] = dest.stat().st_size
    results["pngs"] = copies
    (out / "results.json").write_text(json.dumps(results, indent=2, default=float) + "\n")

    r = results
    print(f"window t = {t0:.4g}-{t0 + n * T:.4g} s ({n} x {T:g} s), {ds.sizes['time']} test-point samples")
    print(f"set-up at the crest (grid, relative to still water at the start): bar {1e3 * crest_bar:.2f} mm, "
          f"channel {1e3 * crest_ch:.2f} mm, bar - channel {1e3 * (crest_bar - crest_ch):+.2f} mm "
          f"(raw: {1e3 * (raw_bar - raw_ch):+.2f} mm)")
    print(f"set-up at the crest (gauges): bar - channel {r['setup_gauges_mm']['crest_bar_minus_channel']:+.2f} mm "
          f"(raw {r['setup_gauges_mm']['crest_bar_minus_channel_raw']:+.2f} mm)")
    for name, gv in gauges.items():
        if "error" not in gv:
            print(f"  gauge {name:16s} H = {gv['wave_height_m']:.3f} m, set-up {gv['setup_mm']:+.2f} mm "
                  f"(raw {gv['setup_raw_mm']:+.2f}, still-water offset {gv['still_water_offset_mm']:+.2f} mm)")
    print(f"channel mean cross-shore current U = {U_channel:+.4f} m/s ({r['channel_current']['direction']}), "
          f"range {r['channel_current']['U_min_m_s']:+.3f} to {r['channel_current']['U_max_m_s']:+.3f} m/s")
    print(f"circulation: bar cell {bar_cell['circulation_m2_s']:+.4f} m^2/s (mean Omega "
          f"{bar_cell['mean_vorticity_1_s']:+.4f} 1/s), nearshore cell {near_cell['circulation_m2_s']:+.4f} m^2/s "
          f"(mean Omega {near_cell['mean_vorticity_1_s']:+.4f} 1/s); two counter-rotating cells: {two_cells}")
    print("checks:", r["checks"])
    print("PNGs:", copies)
    return 0


if __name__ == "__main__":
    sys.exit(main())
