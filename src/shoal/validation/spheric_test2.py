"""SPHERIC Test 2: the 3D dam break with a box obstacle (Kleefsman et al. 2005), against the official
MARIN record of water heights H1-H4 and pressures P1-P8.

The case is built here with the Python API (`spheric_test2_case`): tank 3.22 x 1 x 1 m (open roof),
water column x 1.992..3.22 m, 0.55 m deep, the box 0.161 x 0.403 x 0.161 m at x 0.6635..0.8245 m,
y 0.2955..0.6985 m; water-height gauges (``type = "gauge"``) at the four H positions and pressure
probes (``type = "points"``) at P1-P8. A probe on a wall face sits half a particle spacing off the
face, inside the fluid: the SPH interpolation at the face itself would average over the wall
particles' side, where there is no fluid.

The label mapping of the official file (its gauge labels do not match the positions listed with the
geometry; `shared/validation-data/README.md`, section 2) is worked out from the arrival times in
`height_label_mapping` and documented in ``validation/spheric-test2/README.md``.
"""

from __future__ import annotations

import tempfile
import time
from pathlib import Path

import numpy as np

from .core import Metric, ValidationCase, figure, find_validation_dir, read_csv_with_comments, save_png

RHO0, G, H0 = 1000.0, 9.81, 0.55
TANK = (3.22, 1.0, 1.0)
COLUMN_X0 = 1.992
BOX_LO, BOX_HI = (0.6635, 0.2955, 0.0), (0.8245, 0.6985, 0.161)
GAUGE_X = {"x0.496": 0.496, "x0.992": 0.992, "x1.488": 1.488, "x2.638": 2.638}
GAUGE_Y = 0.5   # the tank's centre line (the positions list x only)
P_FACE = {"P1": 0.021, "P2": 0.061, "P3": 0.101, "P4": 0.141}      # z on the face x = 0.8245, y = 0.471
P_TOP = {"P5": 0.8035, "P6": 0.7635, "P7": 0.7235, "P8": 0.6835}   # x on the top z = 0.161, y = 0.471
P_Y = 0.471
REFERENCE_FILE = "SPHERIC_Test2_Kleefsman2005_pressure_waterheight.csv"
WALLS = dict(wall_pressure="adami", visco_bound_factor=0.0)
"""The validation's walls: pressure extrapolated from the fluid (Adami et al. 2012) and free-slip for the
viscous term. With the dynamic (DBC) wall pressure the surge slid over a dragging bed: at dp = 0.05 m the
heights were 15.4 / 12.7 / 13.0 / 11.1 % RMSE and P1 peaked 0.13 s late at 2.7 times the measured
pressure; free-slip DBC walls alone gave 14.1 / 11.8 / 13.0 / 8.4 % and 0.12 s; with these walls
9.1 / 6.6 / 6.2 / 6.6 %, 0.051 s and +21 % (the same drag that slowed the tidal bore's inflow,
`benchmarks/bed_drag.py`)."""
PEAK_SMOOTH = 0.01
"""Running mean [s] applied to both pressure records before their peaks are taken (10 samples of each:
the pressure probes are sampled every 1 ms, as the experiment's record)."""
PRESSURE_INTERVAL = 0.001
"""Sampling interval [s] of the pressure probes: the experiment's. At 5 ms, the computed impact (a spike
one or two samples wide) had its time quantised to +-5 ms, a tenth of the 0.05 s tolerance."""


def probe_points(dp):
    """{name: (x, y, z)} of P1-P8, each half a spacing off its wall face, into the fluid."""
    pts = {k: (BOX_HI[0] + 0.5 * dp, P_Y, z) for k, z in P_FACE.items()}
    pts.update({k: (x, P_Y, BOX_HI[2] + 0.5 * dp) for k, x in P_TOP.items()})
    return pts


def spheric_test2_case(dp=0.05, end_time=6.0, interval=0.005, options=None, pressure_interval=PRESSURE_INTERVAL):
    """The SPHERIC Test 2 set-up as a `shoal.Case` (default scheme: the case defaults, as `dam-break-3d`);
    the wave gauges sample every `interval` s, the pressure probes every `pressure_interval` s."""
    from ..case import Case, Fluid, FluidRegion, Output, Solid
    from ..geometry.shapes import Box, Tank
    from ..options import SPHOptions
    from ..probes import PointProbes, WaveGauge

    Lx, Ly, Lz = TANK
    pts = probe_points(dp)
    probes = [WaveGauge(name=k, x=x, y=GAUGE_Y, z0=0.0, z1=Lz, interval=interval) for k, x in GAUGE_X.items()]
    probes.append(PointProbes(name="pressure", points=[list(p) for p in pts.values()],
                              interval=pressure_interval))
    return Case(name="spheric-test2", dim=3, dp=float(dp), end_time=float(end_time),
                description="SPHERIC Test 2: 3D dam break with a box obstacle (Kleefsman et al. 2005)",
                fluid=Fluid(depth=H0, surface_level=H0), options=options or SPHOptions(),
                solids=[Solid(name="tank", shape=Tank(lo=(0, 0, 0), hi=(Lx, Ly, Lz), open=["top"])),
                        Solid(name="box", shape=Box(lo=BOX_LO, hi=BOX_HI))],
                fluids=[FluidRegion(shape=Box(lo=(COLUMN_X0, 0, 0), hi=(Lx, Ly, H0)))],
                probes=probes, output=Output(interval=float(end_time)),
                parameters=dict(dp=dp))


def height_label_mapping(t, heights, first_water=0.01):
    """Which gauge position each H column of the official file belongs to, from the arrival times.

    The gauge nearest the reservoir is reached first, the one behind the box last, and the reservoir
    gauge starts wet. Returns {label: x} (the positions of `GAUGE_X`) and {label: arrival time}.
    """
    arrivals = {}
    for label, h in heights.items():
        wet = np.flatnonzero(np.asarray(h) > first_water)
        arrivals[label] = float(t[wet[0]]) if len(wet) else float("inf")
    order = sorted(arrivals, key=arrivals.get)  # reservoir (t = 0) first, then downstream in order
    xs = sorted(GAUGE_X.values(), reverse=True)  # 2.638 (reservoir), 1.488, 0.992, 0.496
    return {label: x for label, x in zip(order, xs)}, arrivals


def load_reference(path=None):
    """The official record: dict t, P1..P8 [Pa], and heights {x: h [m]} (labels mapped by arrival)."""
    path = Path(path) if path else find_validation_dir() / "spheric-test2" / REFERENCE_FILE
    if not path.is_file():
        raise FileNotFoundError(f"reference data not found: {path}")
    header, data = read_csv_with_comments(path)
    col = {h.split("_")[0]: data[:, k] for k, h in enumerate(header)}
    t = col["time"]
    labels = {k: col[k] for k in ("H1", "H2", "H3", "H4")}
    mapping, arrivals = height_label_mapping(t, labels)
    return dict(t=t, pressure={k: col[k] for k in (*P_FACE, *P_TOP)},
                heights={mapping[k]: v for k, v in labels.items()}, mapping=mapping, arrivals=arrivals)


def height_rmse(t, h, t_ref, h_ref, t0=0.0, t1=6.0, scale=H0):
    """RMSE of h(t) against the reference on the reference's samples in [t0, t1], over `scale`."""
    t, h = np.asarray(t, float), np.nan_to_num(np.asarray(h, float), nan=0.0)
    sel = (t_ref >= max(t0, t[0])) & (t_ref <= min(t1, t[-1]))
    return float(np.sqrt(np.mean((np.interp(t_ref[sel], t, h) - h_ref[sel]) ** 2)) / scale)


def pressure_peak(t, p, t0=0.0, t1=1.0, smooth=0.0):
    """(time, value) of the largest pressure in [t0, t1] (after a running mean over `smooth` s); a dry
    probe (NaN: no fluid within its support) counts as 0."""
    t, p = np.asarray(t, float), np.nan_to_num(np.asarray(p, float), nan=0.0)
    sel = (t >= t0) & (t <= t1)
    ts, ps = t[sel], p[sel]
    if smooth > 0 and len(ts) > 2:
        n = max(1, int(round(smooth / np.median(np.diff(ts)))))
        if n > 1:
            ps = np.convolve(ps, np.ones(n) / n, mode="same")
    k = int(np.nanargmax(ps))
    return float(ts[k]), float(ps[k])


class SphericTest2(ValidationCase):
    """Water heights H1-H4 and the pressure P1 on the box against Kleefsman et al. (2005).

    Parameters
    ----------
    tolerance : float
        Largest water-height RMSE over 0 <= t <= `t_end`, normalised by H0 = 0.55 m (0.1).
    peak_time_tolerance : float
        Largest error of the time of P1's first peak [s] (0.05).
    peak_tolerance : float
        Largest relative error of P1's first-peak pressure (0.5).
    dp : float
        The --full spacing [m] (0.05: dp = 0.04 m does not fit 30 minutes on one thread, see the README).
    end_time : float
        End of the run and of the compared window [s] (4).
    options : SPHOptions, optional
        The scheme (default: the case defaults, as `dam-break-3d`, with the walls of `WALLS`).
    """

    name = "spheric-test2"
    title = "3D dam break with a box (SPHERIC Test 2, Kleefsman et al. 2005)"
    cost = 2400.0
    full_only = True
    setup = ("Tank 3.22 x 1 x 1 m (open roof); water column x = 1.992-3.22 m, 0.55 m deep, the full width; "
             "box 0.161 x 0.403 x 0.161 m at x = 0.6635-0.8245, y = 0.2955-0.6985 m. Built with the Python API "
             "(`shoal.validation.spheric_test2.spheric_test2_case`), the default scheme (Wendland, alpha = 0.1, "
             "Fourtakas delta = 0.1, symplectic, float32, c0 = 20 sqrt(g 0.55)) with the walls' pressure "
             "extrapolated from the fluid (Adami et al. 2012, `wall_pressure = \"adami\"`) and free-slip for "
             "the viscous term (`visco_bound_factor = 0`): with the dynamic (DBC) wall pressure the surge is "
             "dragged by the bed (heights 11-15 % RMSE, P1 0.13 s late), 3 layers of "
             "boundary particles). Water-height gauges (`type = \"gauge\"`, kernel-sum surface, dry = 0) at "
             "x = 0.496, 0.992, 1.488, 2.638 m on the centre line y = 0.5 m; pressure probes "
             "(`type = \"points\"`, Shepard-normalised) at P1-P4 on the box face x = 0.8245 m (y = 0.471, "
             "z = 0.021/0.061/0.101/0.141 m) and P5-P8 on its top, each moved half a spacing off the face into "
             "the fluid (an interpolation on the face itself would average over the wall side, where there "
             "is no fluid); gauges every 5 ms, pressure every 1 ms (the experiment's sampling). Run to "
             "t = 4 s (not 6 s: see the tolerance); dp = 0.05 m (dp = 0.04 m, "
             "35,308 particles and 20,000 steps to 6 s, is 80+ minutes on one thread here). --full only.")
    reference = ("Official SPHERIC Test 2 record of the MARIN experiment (Kleefsman et al. 2005, J. Comput. "
                 "Phys. 206, 363-393; Issa & Violeau 2006): P1-P8 and H1-H4 at about 1 ms, 0-7.39 s, CSV export "
                 "from TNL-Project/TNL-SPH @0c3d51fc, copied with its source lines into "
                 "`validation/spheric-test2/`. The file's H labels do not match the positions: by arrival "
                 "time (water > 1 cm) H1 is the gauge at x = 1.488 m (0.19 s), H2 at 0.992 m (0.36 s), H3 at "
                 "0.496 m behind the box (0.92 s) and H4 the reservoir gauge at 2.638 m (wet at t = 0), as "
                 "TNL-SPH and AQUAgpusph read them.")
    tolerance_text = ("water-height RMSE over 0 <= t <= 4 s within 10 % of H0 = 0.55 m at each gauge, P1's first "
                      "peak within 0.05 s of the measured time (0.42 s) and its pressure within 50 % (both "
                      "records smoothed over 10 ms). At dp = 0.05 m the 0.161 m box is 3 spacings "
                      "high, P1 (z = 0.021 m) lies within the first particle layer, and a weakly compressible "
                      "impact peak depends on c0 and on the kernel average over 2h = 0.17 m, so only the time and "
                      "the order of magnitude of the peak are meaningful; published SPH results at dp ~ 0.01-0.02 m "
                      "reach heights within a few cm and the P1 peak within ~20-30 %. The window ends at 4 s, not "
                      "6 s, for the run time on one shared core: it holds the first wave at all four gauges, the "
                      "impact on the box, the run-up at the far wall and the reflected wave's return past every "
                      "gauge (x = 2.638 m at about 2.75 s); the second return (4.5-5 s) is left out.")

    def __init__(self, tolerance=0.10, peak_time_tolerance=0.05, peak_tolerance=0.5, dp=0.05, end_time=4.0,
                 options=None):
        self.tol = float(tolerance)
        from ..options import SPHOptions

        self.options = options if options is not None else SPHOptions(**WALLS)
        self.peak_time_tol = float(peak_time_tolerance)
        self.peak_tol = float(peak_tolerance)
        self.dp = float(dp)
        self.end_time = float(end_time)

    def run(self, quick, backend, out):
        res = self.new_result(quick, backend, out)
        if quick:
            res.status = "not run"
            res.reason = ("full only (`shoal validate spheric-test2 --full`): the 3D run to t = 4 s takes 10,700 steps "
                          "of 21,612 particles at dp = 0.05 m, about an hour on one shared core")
            return res
        import shoal

        case = spheric_test2_case(dp=self.dp, end_time=self.end_time, options=self.options)
        names = list(probe_points(self.dp))
        t0 = time.perf_counter()
        with tempfile.TemporaryDirectory(prefix="shoal-validate-") as tmp:
            run = shoal.run_case(case, Path(tmp) / "run", backend=backend, plot=False, handle_signals=False)
            gauges = {}
            for k, x in GAUGE_X.items():
                d = np.loadtxt(Path(tmp) / "run" / f"gauge_{k}.csv", delimiter=",", skiprows=1, ndmin=2)
                gauges[x] = (d[:, 0], d[:, 1])
            d = np.loadtxt(Path(tmp) / "run" / "probe_pressure.csv", delimiter=",", skiprows=1, ndmin=2)
            pressure = {n: d[:, 1 + 5 * k + 3] for k, n in enumerate(names)}
            tp = d[:, 0]
        res.run_seconds = time.perf_counter() - t0
        res.resolution = f"dp = {self.dp:g} m (H0/{H0 / self.dp:.0f}), to t = {self.end_time:g} s"
        res.particles = f"{case.n_particles:,} ({case.n_fluid:,} fluid)"
        res.data = dict(gauges=gauges, tp=tp, pressure=pressure, dp=self.dp, steps=run.steps, escaped=run.escaped,
                        end_time=self.end_time)
        res.notes.append(f"{run.steps:,} steps" + (f", {run.escaped} particles left the domain" if run.escaped else "")
                         + ".")
        self._save(res)
        return res

    def _save(self, res):
        """The simulated records as CSV beside the figures (to compare again without rerunning)."""
        d = res.data
        tg = d["gauges"][GAUGE_X["x0.496"]][0]
        cols = [tg] + [np.interp(tg, *d["gauges"][x]) for x in GAUGE_X.values()]
        np.savetxt(res.out / "spheric-test2_heights.csv", np.column_stack(cols), delimiter=",", fmt="%.6g",
                   header="time_s," + ",".join(f"h_{k}_m" for k in GAUGE_X), comments="")
        np.savetxt(res.out / "spheric-test2_pressure.csv",
                   np.column_stack([d["tp"]] + [d["pressure"][k] for k in d["pressure"]]), delimiter=",",
                   fmt="%.6g", header="time_s," + ",".join(f"{k}_Pa" for k in d["pressure"]), comments="")

    def load_saved(self, folder):
        """The `run` data from the records `_save` wrote in `folder` (None when they are not there)."""
        folder = Path(folder)
        fh, fp = folder / "spheric-test2_heights.csv", folder / "spheric-test2_pressure.csv"
        if not (fh.is_file() and fp.is_file()):
            return None
        h = np.genfromtxt(fh, delimiter=",", names=True)
        p = np.genfromtxt(fp, delimiter=",", names=True)
        gauges = {x: (h["time_s"], h[f"h_{k}_m".replace(".", "")]) for k, x in GAUGE_X.items()}
        pressure = {k: p[f"{k}_Pa"] for k in (*P_FACE, *P_TOP) if f"{k}_Pa" in p.dtype.names}
        return dict(gauges=gauges, tp=p["time_s"], pressure=pressure, dp=self.dp, end_time=float(h["time_s"][-1]))

    def compare(self, result, reference=None):
        ref = reference or load_reference()
        d = result.data
        t1 = min(self.end_time, d.get("end_time", self.end_time))
        result.metrics = []
        for x in sorted(GAUGE_X.values()):
            label = next(k for k, v in ref["mapping"].items() if v == x)
            t, h = d["gauges"][x]
            e = height_rmse(t, h, ref["t"], ref["heights"][x], 0.0, t1)
            hs = np.nan_to_num(np.asarray(h, float), nan=0.0)
            sel = (ref["t"] >= 0.0) & (ref["t"] <= t1)
            bias = float(np.mean(np.interp(ref["t"][sel], t, hs) - ref["heights"][x][sel]))
            if x < max(GAUGE_X.values()):  # the first water (> 1 cm) at a gauge downstream of the column
                wet = np.flatnonzero(hs > 0.01)
                t_arr = float(t[wet[0]]) if len(wet) else float("nan")
                arrival = f"water > 1 cm at {t_arr:.2f} s (experiment {ref['arrivals'][label]:.2f} s); "
            else:
                arrival = ""
            result.metrics.append(Metric(f"water height at x = {x:g} m (file label {label}), RMSE / H0, "
                                         f"0 <= t <= {t1:g} s", e, self.tol,
                                         note=f"{arrival}mean h - h_exp = {100 * bias:+.1f} cm"))
        tr, pr = pressure_peak(ref["t"], ref["pressure"]["P1"], 0.0, 1.0, smooth=PEAK_SMOOTH)
        ts, ps = pressure_peak(d["tp"], d["pressure"]["P1"], 0.0, 1.0, smooth=PEAK_SMOOTH)
        result.metrics.append(Metric("P1: time of the first pressure peak (t < 1 s)", ts - tr, self.peak_time_tol,
                                     unit="s", note=f"shoal {ts:.3f} s, experiment {tr:.3f} s"))
        result.metrics.append(Metric("P1: first pressure peak", (ps - pr) / pr, self.peak_tol,
                                     note=f"shoal {ps:.0f} Pa, experiment {pr:.0f} Pa"))
        if "P3" in d["pressure"]:
            tr3, pr3 = pressure_peak(ref["t"], ref["pressure"]["P3"], 0.0, 1.0, smooth=PEAK_SMOOTH)
            ts3, ps3 = pressure_peak(d["tp"], d["pressure"]["P3"], 0.0, 1.0, smooth=PEAK_SMOOTH)
            result.metrics.append(Metric("P3: first pressure peak (for information)", (ps3 - pr3) / pr3, None,
                                         note=f"shoal {ps3:.0f} Pa at {ts3:.3f} s, experiment {pr3:.0f} Pa at "
                                              f"{tr3:.3f} s"))
        if any(m.passed is False for m in result.metrics if m.name.startswith("water height")):
            result.notes.append(
                "What the height FAIL says: the metric notes give the arrival times and the mean offsets. "
                "A front that arrives late and a layer that stands higher than measured downstream while the "
                "reservoir drains more slowly are the signature of a flow slowed by the walls: with the dynamic "
                "(DBC) wall pressure the bed drags the surge (at dp = 0.05 m 11-15 % RMSE), with the walls of "
                "`WALLS` (the default here) 6-9 %. The first water (> 1 cm) at x = 1.488 m comes 0.08-0.1 s "
                "late at dp = 0.04-0.05 m with either wall: a tip thinner than a particle spacing, which the "
                "kernel-sum surface cannot show; that part is resolution (a GPU run).")
        result.notes.append(
            "About P1: the computed impact is a spike a few ms wide, the acoustic peak of a weakly "
            "compressible impact; its height depends on c0 and on the kernel average over 2h = 0.17 m, as "
            "tall as the box, and its time moves by a few ms with the sampling and the resolution. Measured "
            "with the walls of `WALLS` at dp = 0.05 m: +0.048 s / +19 % on 1 ms samples (+0.051 s / +21 % "
            "on 5 ms samples, then a FAIL by 1 ms); +0.026 s / +101 % at dp = 0.04 m (5 ms samples); DBC "
            "walls at 0.05 m: +0.13 s / +173 %.")
        fig = figure(8.0, 6.4)
        for k, x in enumerate(sorted(GAUGE_X.values())):
            ax = fig.add_subplot(3, 2, k + 1)
            label = next(lb for lb, v in ref["mapping"].items() if v == x)
            ax.plot(ref["t"], ref["heights"][x], "k-", lw=0.8, label=f"experiment ({label})")
            t, h = d["gauges"][x]
            ax.plot(t, np.nan_to_num(h, nan=0.0), "-", color="tab:blue", lw=1, label=f"shoal, dp = {d['dp']:g} m")
            ax.set_xlim(0, t1)
            ax.set_title(f"water height at x = {x:g} m", fontsize=8)
            ax.set_ylabel("h [m]", fontsize=8)
            ax.tick_params(labelsize=7)
            if k == 0:
                ax.legend(fontsize=7)
        for k, name in enumerate(("P1", "P3")):
            if name not in d["pressure"]:
                continue
            ax = fig.add_subplot(3, 2, 5 + k)
            ax.plot(ref["t"], ref["pressure"][name] / 1e3, "k-", lw=0.6, label="experiment")
            ax.plot(d["tp"], d["pressure"][name] / 1e3, "-", color="tab:red", lw=0.8, label="shoal")
            ax.set_xlim(0, t1)
            ax.set_title(f"pressure {name}", fontsize=8)
            ax.set_ylabel("p [kPa]", fontsize=8)
            ax.set_xlabel("t [s]", fontsize=8)
            ax.tick_params(labelsize=7)
            ax.legend(fontsize=7)
        path = save_png(fig, result.out / "spheric-test2.png")
        return [path], all(m.passed for m in result.metrics if m.passed is not None)
