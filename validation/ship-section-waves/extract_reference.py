"""Extract the regular-wave responses of the NTNU ship section from its public records (issue 32, must-show 4).

Reads the scenario B records (model free in sway, heave and roll; files ``3PPH_R.csv``) and the calibrated
waves without the model (``1PPH.csv`` before the campaign, ``1PPH_1.csv`` after) of Sundsdal, Greco, Hanssen &
Lugni (2025), https://github.com/KRSundsdal1/2D-ship-cross-section-in-regular-waves (CC0 1.0; sensors and
set-up in its docs/experimental_setup.md and data/*/README.md), and writes
``src/shoal/data/shipSection_Sundsdal2025_waves.csv``: for each record, the first-harmonic amplitudes of the
model's sway, heave and roll, and of the incident wave at the model (the mean of probes 4 and 6, 1.5 m either
side of it, in the calibration runs of the same wave), over the same steady window.

The window: the model stands 7.0 m from the flap, whose first motion (5 % of its largest stroke) starts the
clock t_s; the wave train's front reaches the model at t_s + 7.0 / c_g, its 5-period ramp has passed 6
periods later, and waves reflected by the model reach it again, via the flap, after the published reflection
time (model-wavemaker-model at c_g): the window is [t_s + 7.0 / c_g + 6 T, t_s + 7.0 / c_g + t_refl], used
when it holds at least 3 periods (the longest, T = 1.516 s, holds one: left out, as the authors note), and
a record whose motions are zero (markers not tracked) is left out. An
amplitude is that of the least-squares fit a cos(omega t) + b sin(omega t) + c + d t over the window (the
trend takes the slow sway drift).

    python validation/ship-section-waves/extract_reference.py FOLDER

FOLDER holds the records (any depth below it), e.g. a clone of the repository above.
"""

from __future__ import annotations

import math
import sys
from pathlib import Path

import numpy as np

# the published wave table (data/3PPH/README.md): index -> (xi_B, omega [rad/s], T [s], k [rad/m], c_g [m/s],
# reflection time [s])
WAVES = {1: (0.350, 4.143, 1.516, 1.750, 1.184, 10.137), 2: (0.500, 4.952, 1.269, 2.500, 0.990, 12.116),
         3: (0.525, 5.075, 1.238, 2.625, 0.967, 12.415), 4: (0.550, 5.194, 1.210, 2.750, 0.944, 12.707),
         5: (0.575, 5.311, 1.183, 2.875, 0.924, 12.993), 6: (0.600, 5.425, 1.158, 3.000, 0.904, 13.272),
         7: (0.650, 5.646, 1.113, 3.250, 0.869, 13.814), 8: (0.700, 5.860, 1.072, 3.500, 0.837, 14.335),
         9: (0.750, 6.065, 1.036, 3.750, 0.809, 14.839), 10: (1.000, 7.004, 0.897, 5.000, 0.700, 17.134),
         11: (1.250, 7.830, 0.802, 6.250, 0.626, 19.157), 12: (1.500, 8.578, 0.733, 7.500, 0.572, 20.985),
         13: (1.750, 9.265, 0.678, 8.750, 0.529, 22.666), 14: (2.000, 9.905, 0.634, 10.000, 0.495, 24.231)}
HEIGHTS = {1: 0.024, 2: 0.04}
MODEL_X = 7.0
OUT = Path(__file__).resolve().parents[2] / "src" / "shoal" / "data" / "shipSection_Sundsdal2025_waves.csv"


def load(path):
    """{column name without its unit: array} of one record."""
    with open(path) as f:
        head = [h.split(" [")[0].strip() for h in f.readline().strip().split(",")]
    a = np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)
    return {h: a[:, k] for k, h in enumerate(head) if h}


def amplitude(t, y, omega, t0, t1):
    """First-harmonic amplitude of y over [t0, t1] (fit with a constant and a trend)."""
    m = (t >= t0) & (t <= t1)
    tt = t[m] - t0
    a = np.column_stack([np.cos(omega * tt), np.sin(omega * tt), np.ones_like(tt), tt])
    c, *_ = np.linalg.lstsq(a, y[m], rcond=None)
    return float(math.hypot(c[0], c[1]))


def window(rec, index):
    """(t_s, t0, t1): the flap's start and the steady window (module docstring)."""
    _, _, period, _, cg, refl = WAVES[index]
    wm = rec["WM_Position"]
    ts = float(rec["Time"][np.argmax(np.abs(wm - wm[0]) > 0.05 * np.abs(wm - wm[0]).max())])
    arrive = ts + MODEL_X / cg
    return ts, arrive + 6 * period, arrive + refl


def main(folder):
    files = {p.stem: p for p in Path(folder).rglob("*.csv")}
    rows = []
    for name in sorted(n for n in files if n.startswith("3") and len(n) >= 4):
        index, h = int(name[1:3]), int(name[3])
        if h not in HEIGHTS:
            continue
        xi, omega, period, k, cg, refl = WAVES[index]
        rec = load(files[name])
        ts, t0, t1 = window(rec, index)
        if t1 - t0 < 3 * period or t1 > rec["Time"][-1]:
            continue
        calib = []
        for cname in (f"1{index:02d}{h}", f"1{index:02d}{h}_1"):
            if cname in files:
                c = load(files[cname])
                cts, c0, c1 = window(c, index)
                calib += [amplitude(c["Time"], c[p], omega, c0, c1) for p in ("WP_4", "WP_6")]
        if not calib:
            continue
        zeta = float(np.mean(calib))
        resp = {q: amplitude(rec["Time"], rec[q], omega, t0, t1) for q in ("Sway", "Heave", "Roll")}
        if min(resp.values()) < 1e-6:
            continue  # the markers were not tracked: the record's motions are zero
        rows.append((xi, omega, period, k, HEIGHTS[h], name, len(calib) // 2, t0 - ts, t1 - ts, zeta,
                     resp["Sway"], resp["Heave"], resp["Roll"], resp["Sway"] / zeta, resp["Heave"] / zeta,
                     resp["Roll"] / (k * zeta)))
    head = [
        "# Regular-wave responses of the 2D ship section of Sundsdal, Greco, Hanssen & Lugni (2025) in the NTNU",
        "# flume (water 1.0 m deep; flap hinged 0.1 m above the bed; the model's centre 7.0 m from the flap), free",
        "# in sway (soft springs, 59-61 N/m, through the centre of gravity), heave and roll (scenario B), B = 0.40 m,",
        "# d = 0.20 m, KG = 0.106 m, r_roll = 0.36 B. Source: https://github.com/KRSundsdal1/2D-ship-cross-",
        "# section-in-regular-waves (CC0 1.0), records data/3PPH/<model_file>.csv (Sway [m], Heave [m], Roll [rad]",
        "# from visual markers at 20 frames/s, resampled to 200 Hz; the authors note their timing may be slightly",
        "# off in phase: amplitudes only are kept) and the calibrated waves without the model data/1PPH/1PPH.csv and",
        "# 1PPH_1.csv (probes 4 and 6 at 5.5 m and 8.5 m from the flap).",
        "# Extracted by validation/ship-section-waves/extract_reference.py (its docstring gives the steady window",
        "# and the fit): first-harmonic amplitudes over [window_start, window_end] s after the flap's start;",
        "# incident_amplitude: the mean over probes 4 and 6 of the calibration runs (calibration_runs of them);",
        "# sway_rao = sway / incident, heave_rao = heave / incident, roll_rao = roll / (k incident).",
        "xi_B,omega,period,k,wave_height,model_file,calibration_runs,window_start,window_end,incident_amplitude,"
        "sway_amplitude,heave_amplitude,roll_amplitude,sway_rao,heave_rao,roll_rao",
    ]
    lines = [",".join([f"{r[0]:.3f}", f"{r[1]:.3f}", f"{r[2]:.3f}", f"{r[3]:.3f}", f"{r[4]:.3f}", r[5], str(r[6]),
                       f"{r[7]:.2f}", f"{r[8]:.2f}"] + [f"{v:.6g}" for v in r[9:]]) for r in rows]
    OUT.write_text("\n".join(head + lines) + "\n")
    print(f"wrote {OUT} ({len(rows)} records)")


if __name__ == "__main__":
    if len(sys.argv) != 2:
        raise SystemExit("usage: extract_reference.py FOLDER")
    main(sys.argv[1])
