"""Smoke tests of the scripts in benchmarks/ and validation/*/ (issue 29, item 7): each runs as its user
runs it (``python SCRIPT ...``, one Numba thread) on the smallest problem it accepts, for a few steps,
and what it prints or writes is parsed and checked, so that none of them rots unnoticed between the
long runs they are written for.

Covered elsewhere: ``benchmarks/bench_dambreak.py`` and ``benchmarks/regression.py``
(tests/test_benchmark_script.py), ``benchmarks/readme_tables.py`` (tests/test_docs_numbers.py),
``benchmarks/refcounts.py`` (tests/test_refcounts.py).

Cost: the scripts share a few compiled schemes (the 2D dam break's defaults, the wave flumes' options, the
tidal bore's paper scheme, the 3D dam breaks, SPHERIC Test 2's walls), most of which the rest of the suite
compiles too. Some scripts cannot show their figures in a few steps; there the run is checked for what it
writes, and the analysis is checked on synthetic records with a known answer (`--analyse-only`,
`--analyse`, the rip-current ``analyse.py``). ``benchmarks/bore_options.py`` has no option for a flume short
enough to reach two gauges in a short run, so its tiny run is checked to end in its one-line error after
reading the gauges.
"""

from __future__ import annotations

import json
import math
import os
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from test_mpi import mpiexec  # noqa: F401  (the fixture that starts 2 ranks: skips, or fails under CI)

ROOT = Path(__file__).resolve().parents[1]
BENCH = ROOT / "benchmarks"
RIP = ROOT / "validation" / "rip-current"


def run(script, *args, expect=0, timeout=600, env=None, cwd=None):
    """Run `script` (a path) with this Python, one Numba thread; assert its exit status; the result."""
    full = dict(os.environ, NUMBA_NUM_THREADS="1", MPLBACKEND="Agg", **(env or {}))
    full.pop("SHOAL_MPI", None)
    cmd = ([sys.executable] if str(script).endswith(".py") else ["bash"]) + [str(script), *map(str, args)]
    r = subprocess.run(cmd, capture_output=True, text=True, env=full, timeout=timeout, cwd=cwd)
    assert r.returncode == expect, f"exit {r.returncode}\n{r.stdout[-3000:]}\n{r.stderr[-3000:]}"
    return r


def rows(text, pattern):
    """The lines of `text` that match `pattern` (re.match), as match objects."""
    return [m for m in (re.match(pattern, s) for s in text.splitlines()) if m]


# --- benchmarks/ ---------------------------------------------------------------------------------------


def test_bed_drag(tmp_path):
    """A uniform stream over a dynamic bed, periodic in x: sampled at the asked times, it keeps its speed."""
    out = tmp_path / "bed.json"
    r = run(BENCH / "bed_drag.py", "--dp", 0.02, "--t-end", 0.02, "--every", 0.01, "--beds", "dynamic",
            "--json", out)
    res = json.loads(out.read_text())
    bed = res["beds"]["dynamic"]
    assert [s["t"] for s in bed["series"]] == [0.0, 0.01, 0.02] and bed["escaped"] == 0
    assert bed["steps"] > 10 and abs(bed["loss_mean"]) < 0.02, bed
    assert "dynamic bed: " in r.stdout and "speed lost by t = 0.02 s" in r.stdout


def test_bench_mpi(mpiexec):  # noqa: F811
    """2 ranks of the 3D dam break: one JSON object with each rank's particles and communication share,
    and the table."""
    r = run(BENCH / "bench_mpi.py", "--dp", 0.03, "--steps", 2, "--warmup", 1, "--only", "Rx1")
    res = json.loads(r.stdout.splitlines()[0])
    assert res["ranks"] == 2 and res["steps"] == 2 and res["threads"] == 1
    ranks = res["per_rank"]
    assert sum(p["owned"] for p in ranks) == res["particles"] and min(p["ghosts"] for p in ranks) > 0
    assert len(res["comm_share_per_rank"]) == 2 and all(0 <= s < 1 for s in res["comm_share_per_rank"])
    assert f"| 2 ranks x 1 thread | {res['particles']:,} |" in r.stdout


def test_bore_options_tiny_run_ends_in_its_one_line_error():
    """The undular bore to t = 0.02 s: the case runs and its gauges are read, and the bore has not reached
    two of them yet (the script has no shorter flume: it is being used for a study, and is left alone)."""
    r = run(BENCH / "bore_options.py", '{"dp": 0.02, "t_end": 0.02}', expect=2)
    assert r.stderr.strip().splitlines() == ["bore_options.py: the bore reached fewer than two gauges"], r.stderr
    r = run(BENCH / "bore_options.py", '{"no_such_option": 1}', expect=2)
    assert r.stderr.startswith("bore_options.py: ") and "no_such_option" in r.stderr


def test_breaking_bore(tmp_path):
    """A 1 m flume to t = 0.35 s with gauges every 0.1 m: the bore passes two of them at about Belanger's
    celerity, and the breaking index, front track and near-bed inflow have one entry per snapshot."""
    out = tmp_path / "bore.json"
    r = run(BENCH / "breaking_bore.py", "--dp", 0.02, "--length", 1, "--t-end", 0.35, "--gauge-every", 0.1,
            "--settled", 0.1, "--snap", 0.05, "--json", out)
    res = json.loads(out.read_text())
    assert json.loads(r.stdout) == res
    assert res["gauges"] == [0.1, 0.2] and all(np.isfinite(res["arrivals"]))
    assert 0.5 < res["celerity_all"] / res["belanger"]["c"] < 1.5, res["celerity_all"]
    n = len(res["breaking_index"]["times"])
    assert n == 8 and len(res["front_track"]["x"]) == n and len(res["inflow_near_bed"]["speed"]) == n
    assert res["inflow_near_bed"]["speed"][0] == pytest.approx(0.7, abs=1e-3)


def test_carrier_greenspan(tmp_path):
    """The standing wave on a 1:5 beach at d/dp = 5 from the rundown to 0.1 period: the shoreline and
    offshore records against the theory's, finite."""
    out = tmp_path / "cg.json"
    r = run(BENCH / "carrier_greenspan.py", "--cot", 5, "--ddp", 5, "--periods", 0.1, "--json", out)
    res = json.loads(out.read_text())
    s = res["series"]
    assert len(s["t"]) == len(s["shoreline"]) == len(s["theory"]) > 10
    assert s["t"][0] < 0 and s["t"][-1] == pytest.approx(0.1 * res["period"], rel=0.05)
    assert np.isfinite(res["shoreline_rms"]) and res["steps"] > 100 and res["particles"] > 100
    assert "Carrier-Greenspan standing wave on 1:5" in r.stdout and "shoreline rms" in r.stdout


def test_dam_break_front_walls(tmp_path):
    """The 2D dam-break surge at a/dp = 6 to T = 3: the front runs ahead (Z grows from 1) and its error
    against Martin & Moyce is finite."""
    out = tmp_path / "front.json"
    r = run(BENCH / "dam_break_front_walls.py", "--n", 6, "--wall", "dynamic", "--json", out)
    (res,) = json.loads(out.read_text())
    T, Z = np.array(res["T"]), np.array(res["Z"])
    assert res["wall"] == "dynamic" and T[-1] == pytest.approx(3.0, abs=0.06) and Z[0] == pytest.approx(1.0, abs=0.1)
    assert Z[-1] > 2.0 and np.all(np.diff(Z) >= -0.05)
    assert 0 <= res["mean_rel_err_mm"] < 0.5 and np.isfinite(res["band"])
    assert rows(r.stdout, r"\s+6 dynamic\s+\d+\s+[\d.]+%")


def _flume_records(folder, height=0.05, period=1.2, depth=0.4, reflection=0.2, end=8.0):
    """Gauge records gauge_x<X>.csv of a regular wave of `height` with a reflected wave `reflection`
    times as high, no decay."""
    from shoal.motions import wavenumber

    k, w = wavenumber(period, depth), 2 * math.pi / period
    t = np.arange(0.0, end + 1e-9, 0.02)
    for x in np.round(np.arange(0.5, 4.3 + 1e-9, 0.25), 3):
        eta = 0.5 * height * (np.cos(k * x - w * t) + reflection * np.cos(k * x + w * t + 0.7))
        np.savetxt(folder / f"gauge_x{x:g}.csv", np.c_[t, eta + depth], delimiter=",", header="time,level",
                   comments="")


def test_flume_reflection(tmp_path):
    """A 1.5 m flume for 0.1 s writes the gauges the analysis reads; the analysis, on synthetic records of
    a known incident and reflected wave, finds them in every window."""
    run_dir = tmp_path / "run"
    r = run(BENCH / "flume_reflection.py", "--dp", 0.04, "--depth", 0.2, "--period", 0.8, "--height", 0.02,
            "--length", 1.5, "--zone", 1.0, 1.5, "--end", 0.1, "--out", run_dir)
    assert rows(r.stdout, r"[\d,]+ particles, gauges 0.5-0.75 m")
    for x in ("0.5", "0.75"):
        head, *data = (run_dir / f"gauge_x{x}.csv").read_text().splitlines()
        assert head == "time,level" and len(data) >= 5 and float(data[0].split(",")[1]) == pytest.approx(0.2, abs=0.02)
    synthetic = tmp_path / "synthetic"
    synthetic.mkdir()
    _flume_records(synthetic)
    r = run(BENCH / "flume_reflection.py", "--analyse-only", synthetic)
    pct = r"([-+][\d.]+)%"
    windows = rows(r.stdout, rf"\s*([\d.]+)-\s*([\d.]+)\s+{pct} / {pct} / {pct}\s+([-\d.]+)\s+([\d.]+)")
    assert len(windows) == 3, r.stdout  # 3.0-5.4, 4.2-6.6, 5.4-7.8 s
    for m in windows:
        assert all(abs(float(v)) < 0.2 for v in m.groups()[2:5]), m.group(0)  # H_I / H - 1 [%]
        assert abs(float(m.group(6))) < 0.05 and float(m.group(7)) == pytest.approx(0.2, abs=0.002), m.group(0)


def test_impact_pressure(tmp_path):
    """SPHERIC Test 2 at dp = 0.1 m to 0.05 s: every sensor and way of measuring has a row and a JSON entry
    (no impact yet: the water has not reached the box)."""
    out = tmp_path / "impact.json"
    r = run(BENCH / "impact_pressure.py", "--dp", 0.1, "--end", 0.05, "--json", out)
    res = json.loads(out.read_text())
    assert sorted(res["sensors"]) == ["P1", "P2", "P3", "P4"] and res["end"] == 0.05
    for s in res["sensors"].values():
        assert sorted(s) == ["probe dp/2 off", "sensor hydro", "sensor linear", "sensor open"]
        assert all(m["smoothed"]["p"] == 0 for m in s.values())  # dry: no impact before 0.05 s
    assert len(rows(r.stdout, r"P\d\s+(probe|sensor)")) == 16


def test_jonswap_flume_analysis_of_the_linear_record(tmp_path):
    """`benchmarks/jonswap_flume.py --analyse-only` on gauge records written from the paddle's linear elevation
    (`WaveComponents.elevation` at each gauge): over exactly one repeat period the periodogram holds each
    component in its own bin, so Hm0 is the target's, Tp the peak component's period and every 0.1 fp band
    from 0.7 to 1.5 fp the target's variance, to round-off and the CSV's 9 digits."""
    sys.path.insert(0, str(BENCH))
    try:
        import jonswap_flume
    finally:
        sys.path.remove(str(BENCH))
    case, info, paddle = jonswap_flume.build(0.1, components=32)
    t = np.arange(0.0, info["window"][1] + 0.1, info["interval"])
    for x in info["gauges"]:
        eta = info["depth"] + paddle.elevation(x, t)
        np.savetxt(tmp_path / f"gauge_x{x:g}.csv", np.column_stack([t, eta]), delimiter=",", fmt="%.9f",
                   header="time,level", comments="")
    run(BENCH / "jonswap_flume.py", "--dp", 0.1, "--components", 32, "--analyse-only", "--out", tmp_path)
    out = json.loads((tmp_path / "jonswap_summary.json").read_text())
    peak = paddle.wave_components.frequencies[np.argmax(paddle.wave_components.amplitudes)]
    for g in out["gauges"].values():
        assert abs(g["hm0_error"]) < 1e-5
        assert g["tp"] == pytest.approx(1.0 / peak, rel=1e-9)
        assert max(abs(b) for b in g["band_errors"]) < 1e-4


def test_profile_phases():
    """The phases of a step of the 3D dam break: four timings that add up to 100 %."""
    r = run(BENCH / "profile_phases.py", "--dp", 0.03, "--steps", 2)
    m = re.search(r"(\d+) particles, float32, per step: sort ([\d.]+) ms \((\d+) %\), rates ([\d.]+) ms \((\d+) %\), "
                  r"dt ([\d.]+) ms \((\d+) %\), update ([\d.]+) ms \((\d+) %\)", r.stdout)
    assert m, r.stdout
    assert float(m.group(4)) > 0 and 97 <= sum(int(m.group(k)) for k in (3, 5, 7, 9)) <= 103


def test_solitary_runup(tmp_path):
    """The solitary-wave flume at d/dp = 5 to 0.1 s: the gauges are read (the wave is still at the paddle),
    the figures are written."""
    out = tmp_path / "sol.json"
    r = run(BENCH / "solitary_runup.py", "--ddp", 5, "--end", 0.1, "--json", out)
    res = json.loads(out.read_text())
    assert res["particles"] > 100 and res["runup_theory"] == pytest.approx(2.831 * math.sqrt(10) * 0.05**1.25)
    assert 0 <= res["H_2d"] < 0.05 and np.isfinite(res["tip_zero"])
    assert "to t = 0.10 s" in r.stdout and "run-up: theory" in r.stdout


def test_spheric_walls(tmp_path):
    """SPHERIC Test 2 at dp = 0.1 m to 0.05 s through the validation case: the height RMSEs, P1's peak, the
    comparison PNG and the records."""
    r = run(BENCH / "spheric_walls.py", tmp_path, '{"wall_pressure": "adami"}', "--dp", 0.1, "--end", 0.05)
    heights = rows(r.stdout, r"\s+water height at x = [\d.]+ m .*, 0 <= t <= 0.05 s: ([\d.e-]+)")
    assert len(heights) == 4 and all(float(m.group(1)) < 0.2 for m in heights), r.stdout
    assert "P1: first pressure peak" in r.stdout
    for f in ("spheric-test2.png", "spheric-test2_heights.csv", "spheric-test2_pressure.csv"):
        assert (tmp_path / f).stat().st_size > 100
    assert (tmp_path / "spheric-test2_heights.csv").read_text().startswith("time_s,h_x0.496_m,")


def test_wall_cost():
    """The cost of a rate evaluation of the 3D dam break: one JSON line, ratio 1 for the first scheme."""
    r = run(BENCH / "wall_cost.py", "--dp", 0.03, "--evals", 1, "--schemes", "dynamic")
    res = json.loads(r.stdout.splitlines()[-1])
    assert res["evals"] == 1 and res["particles"] > 1000 and 0.5 < res["wall_fraction"] < 1
    assert res["schemes"]["dynamic"]["ratio"] == 1.0 and all(v > 0 for v in res["schemes"]["dynamic"]["ms"])


def test_wall_gap():
    """Still water over a flat bed (H/dp = 5, 0.05 s) and the dam-break surge (a/20): a gap of about half a
    spacing over the flat bed, the bed pressures within a few % of hydrostatic, the surge's front ahead."""
    r = run(BENCH / "wall_gap.py", "--bed", "flat", "surge", "--wall", "dynamic", "--dp", 0.04, "--end", 0.05,
            "--surge-dp", 0.0073)
    (flat,) = rows(r.stdout, r"flat\s+dynamic\s+\d+\s+([\d.]+)\s+([\d.]+)\s+([-+][\d.]+) ([-+][\d.]+) ([-+][\d.]+)")
    assert 0.3 < float(flat.group(1)) < 1.0 and all(abs(float(v)) < 5 for v in flat.groups()[2:]), flat.group(0)
    (surge,) = rows(r.stdout, r"surge\s+dynamic\s+\d+\s+([\d.]+)\s+([\d.]+)\s+\(dp = .*front at x = ([\d.]+) a\)")
    assert float(surge.group(1)) > 0 and 1.5 < float(surge.group(3)) < 3.5, surge.group(0)


def test_wall_impact_2d():
    """The 2D dam break against its far wall (a/dp = 10, to T = 4.5): every sensor and method has a row,
    the water reaches the wall at about t = 0.36 s."""
    r = run(BENCH / "wall_impact_2d.py", "--dp", 0.0146, "--T", 4.5, "--interval", 0.002, "--wall", "dynamic")
    table = rows(r.stdout, r"\s+(0\.\d\d) (hydrostatic|linear)\s+(\S+)\s+(\S+)\s+(\S+)")
    assert [(m.group(1), m.group(2)) for m in table] == [(z, m) for z in ("0.05", "0.25", "0.50")
                                                         for m in ("hydrostatic", "linear")]
    contact = [float(m.group(3)) for m in table if np.isfinite(float(m.group(3)))]
    assert contact and all(0.3 < t < 0.5 for t in contact), r.stdout


def test_wave_decay(tmp_path):
    """A standing wave in a 0.2 m deep periodic channel for one period: the energy series and the fit of
    its peaks; the period comes out within 10 %."""
    csv = tmp_path / "energy.csv"
    r = run(BENCH / "wave_decay.py", "--dp", 0.05, "--depth", 0.2, "--period", 0.8, "--periods", 1, "--csv", csv)
    res = json.loads(r.stdout)
    assert abs(res["period_error_percent"]) < 10 and 0.5 < res["E0_over_linear"] < 1.5, res
    assert res["kinetic_energy_peaks_over_first"][0] == 1.0 and len(res["kinetic_energy_peaks_over_first"]) >= 3
    head, *data = csv.read_text().splitlines()
    assert head == "time,E_above_rest,KE,mode_coefficient,KE_mode,E_with_elastic" and len(data) >= 40


# --- benchmarks/device/ --------------------------------------------------------------------------------


def test_device_scripts_parse():
    """The GPU session's shell scripts are valid bash (fetch_wheels.sh downloads wheels into the
    checkout: only parsed here)."""
    for name in ("check.sh", "fetch_wheels.sh"):
        subprocess.run(["bash", "-n", str(BENCH / "device" / name)], check=True)


def test_device_check_info_stage_on_the_simulator(tmp_path):
    """check.sh's `info` stage without a GPU, on Numba's CUDA simulator (its smoke kernel runs there as
    Python; nvidia-smi is missing): the versions, the kernel, and `shoal info`, in $OUT/info.txt. An
    unknown stage is one line and exit status 2."""
    r = run(BENCH / "device" / "check.sh", "nope", expect=2, cwd=tmp_path)
    assert r.stderr.strip() == "check.sh: unknown stage 'nope'; allowed: info bench tests seed par cpu spheric regs rip"
    out = tmp_path / "out"
    run(BENCH / "device" / "check.sh", "info", cwd=tmp_path, timeout=300,
        env=dict(OUT=str(out), PY=sys.executable, NUMBA_ENABLE_CUDASIM="1", DEADLINE="240"))
    info = (out / "info.txt").read_text()
    assert "SMOKE OK" in info and "smoke: default NVVM works" in info, info
    assert re.search(r"^numba \S+ numba-cuda \S+ numpy \S+$", info, re.M) and "\nshoal " in info, info


# --- validation/rip-current/ ---------------------------------------------------------------------------


def test_rip_current_run_check():
    """run.py --check at the coarsest spacing: the validation run's case (moved paddle, shortened basin,
    test-point grid and gauges) builds and is checked, without running."""
    r = run(RIP / "run.py", "--out", "unused", "--dp", 0.075, "--check")
    assert "paddle at x = 4.5 m (validation run)" in r.stdout, r.stdout
    assert re.search(r"time step: [\d.]+ s .*steps to t = 16.5 s", r.stdout), r.stdout
    assert "3D, dp = 0.075 m" in r.stdout and ", verlet, float32" in r.stdout, r.stdout  # OPTION_CHANGES applied
    m = re.search(r"particles: ([\d,]+) = ([\d,]+) fluid", r.stdout)
    assert m and 50_000 < int(m.group(1).replace(",", "")) < 200_000, r.stdout
    assert "for the probes' samples" in r.stdout  # the test-point grid and the gauges


def test_rip_current_transects(tmp_path):
    """transects.py --check builds both 2D transects; --analyse, on synthetic gauge records whose set-up
    is 5 mm over the bar and 2 mm in the channel (after a still-water offset of 1 mm) and whose waves are
    0.1 m high, finds those in its table and transects.json."""
    r = run(RIP / "transects.py", "--out", tmp_path, "--dp", 0.075, "--check")
    assert r.stdout.count("time step: ") == 2, r.stdout
    assert "along y = 2.5 m (bar)" in r.stdout and "along y = 0.5 m (channel)" in r.stdout
    t = np.arange(0.0, 16.5 + 1e-9, 0.05)
    for which, setup in (("bar", 0.005), ("channel", 0.002)):
        d = tmp_path / f"{which}_dp0.075"
        d.mkdir()
        level = 0.5 + 0.001 + np.where(t >= 2.0, setup + 0.05 * np.sin(2 * np.pi * t / 1.5), 0.0)
        for g in ("offshore", "toe", "crest", "trough", "inshore"):
            np.savetxt(d / f"gauge_{g}.csv", np.c_[t, level], delimiter=",", header="time,level", comments="")
    r = run(RIP / "transects.py", "--out", tmp_path, "--dp", 0.075, "--analyse")
    res = json.loads((tmp_path / "transects.json").read_text())["0.075"]
    for g in ("offshore", "toe", "crest", "trough", "inshore"):
        assert res["bar"][g]["setup_mm"] == pytest.approx(5.0, abs=0.1)
        assert res["channel"][g]["setup_mm"] == pytest.approx(2.0, abs=0.1)
        assert res["bar_minus_channel_mm"][g] == pytest.approx(3.0, abs=0.1)
        assert res["bar"][g]["wave_height_m"] == pytest.approx(0.1, abs=0.002)
    assert len(rows(r.stdout, r"\| 0.075 \| \w+ \| [\d.]+ \| \+5.0 \| \+2.0 \| \+3.0 \|")) == 5, r.stdout


def _rip_run_dir(d):
    """A synthetic run directory of the rip-current run: case.toml (still-water level, piston period),
    run.log, the test-point grid `bar` and the gauges. From t = 2 s: waves 4 cm high, a set-up of
    10 mm over the bar (y > 1 m) and 2 mm in the channel, a mean current of -0.1 m/s (offshore) in the
    channel and +0.05 m/s over the bar."""
    import xarray as xr

    swl, T = 0.517, 1.5
    (d / "case.toml").write_text(f'name = "rip-current"\ndim = 3\ndp = 0.075\n\n[fluid]\ndepth = {swl}\n'
                                 f'surface_level = {swl}\n\n[[motions]]\ntype = "piston"\nname = "piston"\n'
                                 f"period = {T}\n")
    (d / "run.log").write_text(
        "2026-12-05 10:00:00,000 INFO particles 1000 (fluid 600), dp 0.075 m, h 0.13 m\n"
        "2026-12-05 10:01:00,000 INFO done: 10 steps to t = 6 s in 60.0 s wall (1.0 s compile), "
        "1.67e+02 particle-steps/s, 0 particles escaped\n")

    def level(t, y):
        return swl + np.where(t >= 2.0, np.where(y > 1.0, 0.010, 0.002) + 0.02 * np.sin(2 * np.pi * t / T), 0.0)

    t = np.round(np.arange(0.0, 6.0 + 1e-9, T / 10), 6)
    x, y, z = np.linspace(8.0, 18.0, 21), np.linspace(0.15, 3.85, 9), np.linspace(0.08, 0.757, 15)
    tt, zz, yy, xx = np.meshgrid(t, z, y, x, indexing="ij")
    dz = z[1] - z[0]
    ks = np.clip(0.5 + (level(tt, yy) - zz) / (2 * dz), 0.0, 1.0)  # linear through 1/2 at the level
    u = np.where(tt >= 2.0, np.where(yy < 1.0, -0.1, 0.05), 0.0)
    dims = ("time", "z", "y", "x")
    ds = xr.Dataset({"u": (dims, u), "v": (dims, 0 * u), "w": (dims, 0 * u), "p": (dims, 0 * u),
                     "rho": (dims, 1000 + 0 * u), "kernel_sum": (dims, ks)},
                    coords={"time": t, "x": x, "y": y, "z": z})
    ds.to_netcdf(d / "testpoints_bar.nc", engine="scipy")
    tg = np.round(np.arange(0.0, 6.0 + 1e-9, T / 30), 6)
    for name, yg in (("crest_bar", 2.5), ("crest_channel", 0.5), ("offshore", 2.0)):
        np.savetxt(d / f"gauge_{name}.csv", np.c_[tg, level(tg, yg)], delimiter=",", header="time,level",
                   comments="")


def test_rip_current_analyse(tmp_path):
    """analyse.py on a synthetic run (`_rip_run_dir`): the set-up over the bar and in the channel (grid and
    gauges), the offshore channel current, the run's statistics, results.json and the two PNGs."""
    run_dir, out = tmp_path / "run", tmp_path / "out"
    run_dir.mkdir()
    _rip_run_dir(run_dir)
    r = run(RIP / "analyse.py", run_dir, "--out", out)
    res = json.loads((out / "results.json").read_text())
    assert res["period_s"] == 1.5 and res["window_s"] == pytest.approx([4.5, 6.0])
    assert res["run"]["particles"] == 1000 and res["run"]["steps"] == 10 and res["run"]["finished"]
    grid = res["setup_grid_mm"]
    assert grid["crest_bar"] == pytest.approx(10.0, abs=0.5) and grid["crest_channel"] == pytest.approx(2.0, abs=0.5)
    assert res["setup_gauges_mm"]["crest_bar_minus_channel"] == pytest.approx(8.0, abs=0.5)
    assert res["gauges"]["crest_bar"]["wave_height_m"] == pytest.approx(0.04, abs=0.002)
    cur = res["channel_current"]
    assert cur["direction"] == "offshore" and cur["U_mean_m_s"] == pytest.approx(-0.1, abs=1e-3)
    assert res["checks"]["setup_bar_above_channel_at_crest_grid"] and res["checks"]["channel_current_offshore"]
    assert sorted(res["pngs"]) == ["meanflow_current.png", "meanflow_setup.png"]
    assert all((out / name).stat().st_size > 1000 for name in res["pngs"])
    assert "channel mean cross-shore current U = -0.1000 m/s (offshore)" in r.stdout


def test_control_options_tiny_run_ends_in_its_one_line_error():
    """The weir at dp = 0.02 m to t = 0.02 s: the case runs with the options given and stops with its one-line
    error (the validation's window, 5-8 s, not reached); an unknown option and an unknown case are refused in
    one line."""
    r = run(BENCH / "control_options.py", "weir", '{"dp": 0.02, "end_time": 0.02, "coef_h": 1.0}', expect=2)
    assert r.stderr.strip().splitlines() == [
        "control_options.py: the run ended at t = 0.02 s, before the end of the window analysed (5-8 s)"], r.stderr
    r = run(BENCH / "control_options.py", "weir", '{"no_such_option": 1}', expect=2)
    assert r.stderr.startswith("control_options.py: ") and "no_such_option" in r.stderr
    r = run(BENCH / "control_options.py", "dam", expect=2)
    assert "give the case: weir or sluice-gate" in r.stderr


def test_peer_sitting_with_a_stand_in_peer(tmp_path):
    """The sitting's order (peer, float32, float64, float64, float32, peer) and its ratios, with a stand-in for
    DualSPHysics's run.sh that prints a fixed JSON line after a line of other output (the real one needs the
    build in ../shared/peers); a missing peer is refused in one line."""
    peer = tmp_path / "run.sh"
    line = json.dumps({"build": "stand-in", "particles": 1000, "particle_steps_per_second": 1e5})
    peer.write_text(f"echo 'DualSPHysics says hello'\necho '{line}'\n")
    out = tmp_path / "sitting.json"
    r = run(BENCH / "peer_sitting.py", "--peer", peer, "--dp", 0.03, "--steps", 2, "--warmup", 1, "--threads", 1,
            "--json", out)
    d = json.loads(out.read_text())
    assert [x.get("precision", x["code"]) for x in d["runs"]] == [
        "DualSPHysics", "float32", "float64", "float64", "float32", "DualSPHysics"]
    for ratio in d["ratios"]:
        mine = sum(x["particle_steps_per_second"] for x in d["runs"] if x.get("precision") == ratio["precision"])
        assert ratio["shoal_over_peer"] == pytest.approx(mine / 2e5, rel=1e-12)
        assert f"shoal {ratio['precision']} / DualSPHysics: {ratio['shoal_over_peer']:.2f}" in r.stdout
    assert all(x["particles"] == 6366 for x in d["runs"] if x["code"] == "shoal")
    r = run(BENCH / "peer_sitting.py", "--peer", tmp_path / "none.sh", expect=2)
    assert r.stderr.strip().count("\n") == 0 and "is not a file" in r.stderr


def test_thread_scaling(tmp_path):
    """Thread counts alternated in one process: a time a step per count and round, and the speed-ups over the
    first count (here 1 and 1 thread: the smoke tests run one Numba thread); a count beyond Numba's pool is
    refused in one line."""
    out = tmp_path / "scaling.json"
    r = run(BENCH / "thread_scaling.py", "--dp", 0.03, "--threads", 1, 1, "--rounds", 2, "--steps", 1, "--json", out)
    d = json.loads(out.read_text())
    assert d["particles"] == 6366 and len(d["seconds_per_step"]["1"]) == 4  # two rounds of the count 1, twice
    assert d["speedup"]["1"] == pytest.approx(1.0)
    assert len(rows(r.stdout, r"round \d: 1 threads [\d.]+ ms, 1 threads [\d.]+ ms$")) == 2
    r = run(BENCH / "thread_scaling.py", "--threads", 1, 2, expect=2)
    assert r.stderr.strip() == ("thread_scaling.py: error: --threads must be between 1 and 1 (Numba's thread pool; "
                                "NUMBA_NUM_THREADS sets it)")


# --- validation/sluice-gate/ ---------------------------------------------------------------------------


def test_sluice_gate_one_run_refuses_a_coarse_dp_in_one_line():
    """one_run.py (the runs beyond `shoal validate sluice-gate --full`) passes the case's own check: a dp too
    coarse for the opening is one line, exit 2, before anything runs. Its run is the validation's
    (`run_sluice_gate`, run by `pytest -m validation tests/test_sluice_gate_and_weir.py`)."""
    r = run(ROOT / "validation" / "sluice-gate" / "one_run.py", "--dp", 0.05, "--out", "x", expect=2)
    assert r.stderr.count("\n") == 1 and "the gate opening is 0.06 m" in r.stderr
