"""Impact pressure on walls: a 2D dam break's surge on the far wall and SPHERIC Test 2's box (issue 28, item 4).

Both impacts run with the scheme the user guide gives for the pressure water puts on a wall
(`IMPACT_OPTIONS`: the Riemann terms of Zhang, Hu & Adams 2017 in place of artificial viscosity and density
diffusion, over walls whose pressure is extrapolated from the fluid, Adami et al. 2012, free-slip for the
viscous term). Adding the delta-plus particle shifting (``shifting = "delta_plus"``) brought the 2D wall's
bottom sensor from 39 % to 14-15 % at H/dp = 120 but to 14 % or 19 % at 60 depending on a 7e-5 change of the
lattice (`benchmarks/results/issue28-shifting/`): too near the 20 % asked for a test that runs on every
machine's round-off, so it is not in `IMPACT_OPTIONS` yet.

* **2D** (`impact_2d`): `dam-break-2d` (a column a x 2a, a = 0.146 m, in a tank 5a long) with wall pressure
  sensors (``type = "pressure"``, the fluid's pressure extrapolated to the wall's surface) on the far wall at
  z = 0.05 a, 0.25 a and 0.5 a, sampled every 0.2 ms and not filtered. Judged at the bottom of the wall
  (z = 0.05 a), as issue 28 asks: the ringing after the first impact (`ringing`), the largest departure of
  the record from its own running mean over 5 ms, from 5 ms to 100 ms after the peak, over the peak, at
  most 20 %. The two higher sensors' ringing is reported, not judged: there the water runs up the wall
  rather than hits it, the "peak" is the largest sample of a slow rise (0.4 rho0 g H at 0.5 a, against
  7 at the bottom), and the ratio is the particles' pressure noise over it, which moves with round-off:
  at H/dp = 60 the same code read 14.7 and 16.2 % on one 2-core machine and 18.1 and 22.0 % on another
  (AMD EPYC, no AVX-512), where the bottom sensor read 16.3 % on both.
* **3D** (`spheric_impact`): SPHERIC Test 2 (`shoal.validation.spheric_test2.spheric_test2_case`) to
  t = 0.7 s with wall pressure sensors on the box's face at P1-P4 (x = 0.8245 m, y = 0.471 m), every 1 ms as
  the MARIN record. Judged against that record (`first_peak`): the first peak's time (within 0.02 s) and
  pressure (within 30 %), both records averaged over 10 ms as the `spheric-test2` case does, and the lowest
  pressure in the quarter second after the measured impact, not below -0.5 rho0 g H0 (all three issue 28's).
"""

from __future__ import annotations

import math
import tempfile
import time
from pathlib import Path

import numpy as np

from . import runs
from .core import Metric, ValidationCase, figure, save_png
from .spheric_test2 import BOX_HI, H0, P_FACE, P_Y, PEAK_SMOOTH, RHO0, WALLS, load_reference, pressure_peak

G = 9.81
A = 0.146
"""The 2D column's width [m] (Koshizuka & Oka 1996); its height is 2a."""
IMPACT_OPTIONS = dict(WALLS, riemann=True, alpha=0.0, density_diffusion="none")
"""The scheme for impacts (`docs/physics.md`, "Impact pressure and the Riemann terms")."""
HEIGHTS_2D = (0.05, 0.25, 0.5)
"""Heights of the 2D sensors on the far wall, over a."""
JUDGED_2D = 0.05
"""The 2D sensor whose ringing is judged: the bottom of the wall (issue 28, item 4)."""
INTERVAL_2D = 2e-4
"""The 2D sensors' sampling interval [s]."""
T_END_2D = 5.5
"""The 2D run's end, T = t sqrt(2 g / a): the surge has hit the far wall (T = 2.6) and climbed it."""
RING_START, RING_END, RING_MEAN = 0.005, 0.1, 0.005
"""Ringing: from `RING_START` to `RING_END` s after the peak, against a running mean over `RING_MEAN` s."""
IMPACT_END = 0.7
"""The 3D run's end [s]: the measured impact on the box is at 0.42 s; its quarter second follows."""
AFTER_IMPACT = 0.25
"""The window [s] after the measured impact in which the lowest pressure is judged."""


def running_mean(t, p, width):
    """`p` averaged over a centred window of `width` s (the samples' median spacing sets its length)."""
    p = np.asarray(p, float)
    n = max(1, int(round(width / np.median(np.diff(t)))))
    return np.convolve(p, np.ones(n) / n, mode="same") if n > 1 else p


def ringing(t, p, start=RING_START, end=RING_END, mean=RING_MEAN):
    """The impact's ringing in an unfiltered wall-pressure record.

    With k the sample of the largest pressure, the largest |p - running mean of p over `mean` s| from
    ``t[k] + start`` to ``t[k] + end``, over p[k]. Also returns the first contact (first nonzero sample),
    the peak's time and value and the lowest pressure after the contact, as a dict.
    """
    t, p = np.asarray(t, float), np.asarray(p, float)
    wet = np.flatnonzero(p != 0)
    if not len(wet):
        return dict(t_contact=math.nan, t_peak=math.nan, peak=math.nan, min=math.nan, ringing=math.nan)
    k = int(np.argmax(p))
    after = (t >= t[k] + start) & (t <= t[k] + end)
    ring = np.abs(p - running_mean(t, p, mean))[after]
    return dict(t_contact=float(t[wet[0]]), t_peak=float(t[k]), peak=float(p[k]), min=float(p[wet[0]:].min()),
                ringing=float(ring.max() / p[k]) if ring.size else math.nan)


def first_peak(t, p, t_ref, p_ref, window=(0.0, 1.0), smooth=PEAK_SMOOTH, after=AFTER_IMPACT):
    """A pressure record against the experiment's around the first impact.

    Returns a dict: ``smoothed`` and ``raw``, each the first peak (largest value in `window` after a
    running mean over `smooth` s, or none) of both records, with ``dt`` (s) and ``rel`` (fraction) the
    differences; ``min_after`` the record's lowest value from 0.02 s before the experiment's smoothed peak
    to `after` s after it, over rho0 g H0; ``ringing`` as `ringing` (5 ms to 0.25 s after the raw peak,
    against a 10 ms running mean). A dry sensor (NaN) counts as 0.
    """
    t, p = np.asarray(t, float), np.nan_to_num(np.asarray(p, float))
    out = {}
    for label, width in (("smoothed", smooth), ("raw", 0.0)):
        tp, pp = pressure_peak(t, p, *window, smooth=width)
        tr, pr = pressure_peak(t_ref, p_ref, *window, smooth=width)
        out[label] = dict(t=tp, p=pp, t_ref=tr, p_ref=pr, dt=tp - tr, rel=(pp - pr) / pr)
    t_imp = out["smoothed"]["t_ref"]
    sel = (t >= t_imp - 0.02) & (t <= t_imp + after)
    out["min_after"] = float(np.min(p[sel])) / (RHO0 * G * H0) if sel.any() else math.nan
    out["ringing"] = ringing(t, p, end=after, mean=smooth)["ringing"]
    return out


def impact_2d(dp, options, backend="cpu", interval=INTERVAL_2D, t_end=T_END_2D, method="hydrostatic"):
    """Run the 2D dam break on the far wall; return its sensors' records (t, {z/a: p [Pa]}) and its counts."""
    import shoal
    from ..cases import dam_break_2d
    from ..options import SPHOptions
    from ..probes import PressureSensors

    case = dam_break_2d(dp=dp, a=A, end_time=t_end / math.sqrt(2 * G / A), options=SPHOptions(**options))
    sensors = PressureSensors(name="wall", points=[[5 * A, 0.0, f * A] for f in HEIGHTS_2D], normal=[-1, 0, 0],
                              interval=interval, method=method)
    case = case.model_copy(update={"probes": [sensors],
                                   "output": case.output.model_copy(update={"interval": case.end_time})})
    t0 = time.perf_counter()
    with tempfile.TemporaryDirectory(prefix="shoal-validate-") as tmp:
        run = shoal.run_case(case, Path(tmp) / "run", backend=backend, plot=False, handle_signals=False)
        d = np.loadtxt(Path(tmp) / "run" / "pressure_wall.csv", delimiter=",", skiprows=1, ndmin=2)
    return dict(t=d[:, 0], p={f: d[:, 1 + k] for k, f in enumerate(HEIGHTS_2D)}, particles=case.n_particles,
                fluid=case.n_fluid, steps=run.steps, seconds=time.perf_counter() - t0, dp=dp)


def spheric_impact(dp, options, backend="cpu", end_time=IMPACT_END, method="hydrostatic"):
    """Run SPHERIC Test 2 to `end_time` with wall pressure sensors at P1-P4; return their records, the
    validation's probes half a spacing off the face (for comparison) and the run's counts."""
    import shoal
    from ..options import SPHOptions
    from ..probes import PressureSensors
    from .spheric_test2 import spheric_test2_case

    case = spheric_test2_case(dp=dp, end_time=end_time, options=SPHOptions(**options))
    face = PressureSensors(name="face", points=[[BOX_HI[0], P_Y, z] for z in P_FACE.values()],
                           normal=[1.0, 0.0, 0.0], interval=0.001, method=method)
    case = case.model_copy(update={"probes": [*case.probes, face]})
    t0 = time.perf_counter()
    with tempfile.TemporaryDirectory(prefix="shoal-validate-") as tmp:
        run = shoal.run_case(case, Path(tmp) / "run", backend=backend, plot=False, handle_signals=False)
        s = np.loadtxt(Path(tmp) / "run" / "pressure_face.csv", delimiter=",", skiprows=1, ndmin=2)
        q = np.loadtxt(Path(tmp) / "run" / "probe_pressure.csv", delimiter=",", skiprows=1, ndmin=2)
    return dict(t=s[:, 0], sensor={k: s[:, 1 + i] for i, k in enumerate(P_FACE)},
                probe={k: np.nan_to_num(q[:, 1 + 5 * i + 3]) for i, k in enumerate(P_FACE)},
                particles=case.n_particles, fluid=case.n_fluid, steps=run.steps,
                seconds=time.perf_counter() - t0, dp=dp)


class WallImpact(ValidationCase):
    """The pressure of water hitting a wall: the 2D dam break's ringing on the far wall and SPHERIC Test 2's
    P1-P4 on the box (issue 28, item 4).

    Parameters
    ----------
    ringing_tolerance : float
        Largest ringing after 5 ms, over the peak, at the bottom of the 2D wall (0.20).
    peak_time_tolerance : float
        Largest |first peak's time - the experiment's| [s] at P1-P4 (0.02).
    peak_tolerance : float
        Largest |first peak / the experiment's - 1| at P1-P4 (0.30).
    lowest : float
        The lowest pressure allowed in the quarter second after the impact, over rho0 g H0 (-0.5).
    spheric_dp : float
        The --full run's spacing for SPHERIC Test 2 [m].
    """

    name = "wall-impact"
    title = "Impact pressure on walls: a 2D dam break on a wall, SPHERIC Test 2's box"
    cost = 90.0
    setup = ("Both with `riemann = true`, `alpha = 0`, `density_diffusion = \"none\"`, Adami walls, free-slip "
             "viscous term (`IMPACT_OPTIONS`), Wendland, symplectic, float32. **2D**: `dam-break-2d` (column "
             "a = 0.146 m wide, 2a high, tank 5a) to T = t sqrt(2g/a) = 5.5, wall pressure sensors "
             "(`type = \"pressure\"`, hydrostatic-corrected Shepard extrapolation to the wall surface) on the "
             "far wall at z = 0.05, 0.25, 0.5 a, every 0.2 ms, unfiltered; H/dp = 60 (`--quick`) and 120 "
             "(`--full`). **3D** (`--full` only): SPHERIC Test 2 to t = 0.7 s with the same sensors on the box's "
             "face at P1-P4 (x = 0.8245 m, y = 0.471 m, z = 0.021/0.061/0.101/0.141 m), every 1 ms.")
    reference = ("2D: the criterion itself (issue 28: oscillations after 5 ms at most 20 % of the peak). 3D: the "
                 "official SPHERIC Test 2 record of the MARIN experiment (Kleefsman et al. 2005, J. Comput. Phys. "
                 "206, 363-393), `validation/spheric-test2/` with its source lines.")
    tolerance_text = ("2D: at the bottom of the wall (z = 0.05 a), the largest |p - its 5 ms running mean| from 5 ms "
                      "to 100 ms after the peak at most 20 % of the peak (the sensors higher up are reported, not "
                      "judged). 3D, at each of P1-P4: the first peak (t < 1 s; both records "
                      "averaged over 10 ms, as in `spheric-test2`) within 0.02 s and 30 % of the experiment's, and "
                      "no pressure below -0.5 rho0 g H0 from 0.02 s before the measured peak to 0.25 s after it "
                      "(issue 28, item 4).")

    def __init__(self, ringing_tolerance=0.20, peak_time_tolerance=0.02, peak_tolerance=0.30, lowest=-0.5,
                 spheric_dp=0.02):
        self.ring_tol = float(ringing_tolerance)
        self.peak_time_tol = float(peak_time_tolerance)
        self.peak_tol = float(peak_tolerance)
        self.lowest = float(lowest)
        self.spheric_dp = float(spheric_dp)

    @staticmethod
    def h_over_dp(quick):
        """The 2D column's height over the spacing."""
        return 60.0 if quick else 120.0

    def run(self, quick, backend, out):
        res = self.new_result(quick, backend, out)
        n = self.h_over_dp(quick)
        key = ("wall-impact-2d", n, backend)
        two = runs.memo(key, lambda: impact_2d(2 * A / n, IMPACT_OPTIONS, backend))
        res.data = dict(two=two, H_over_dp=n)
        res.run_seconds = two["seconds"]
        res.resolution = f"2D: H/dp = {n:g}"
        res.particles = f"2D: {two['particles']:,} ({two['fluid']:,} fluid)"
        if not quick:
            three = runs.memo(("wall-impact-3d", self.spheric_dp, backend),
                              lambda: spheric_impact(self.spheric_dp, IMPACT_OPTIONS, backend))
            res.data["three"] = three
            res.run_seconds += three["seconds"]
            res.resolution += f"; SPHERIC Test 2: dp = {self.spheric_dp:g} m (H0/{H0 / self.spheric_dp:.1f}), to t = {IMPACT_END:g} s"
            res.particles += f"; 3D: {three['particles']:,} ({three['fluid']:,} fluid)"
        return res

    def compare(self, result, reference=None):
        d = result.data
        two = d["two"]
        scale = RHO0 * G * 2 * A
        result.metrics = []
        for f in HEIGHTS_2D:
            r = ringing(two["t"], two["p"][f])
            judged = f == JUDGED_2D
            result.metrics.append(Metric(
                f"2D wall, z = {f:g} a: ringing 5-100 ms after the peak, over the peak", r["ringing"],
                self.ring_tol if judged else None,
                note=f"peak {r['peak'] / scale:.2f} rho0 g H at {r['t_peak']:.4f} s, lowest "
                     f"{r['min'] / scale:+.2f} rho0 g H" + ("" if judged else "; not judged (run-up, not impact)")))
        figs = [self._plot_2d(result)]
        if "three" in d:
            ref = reference or load_reference()
            three = d["three"]
            for k in P_FACE:
                m = first_peak(three["t"], three["sensor"][k], ref["t"], ref["pressure"][k])
                s, raw = m["smoothed"], m["raw"]
                result.metrics.append(Metric(f"{k}: time of the first peak (t < 1 s)", s["dt"], self.peak_time_tol,
                                             unit="s", note=f"shoal {s['t']:.3f} s, experiment {s['t_ref']:.3f} s"))
                result.metrics.append(Metric(f"{k}: first peak", s["rel"], self.peak_tol,
                                             note=f"shoal {s['p']:.0f} Pa, experiment {s['p_ref']:.0f} Pa; "
                                                  f"unaveraged {raw['rel']:+.0%} at {raw['dt']:+.3f} s"))
                result.metrics.append(Metric(f"{k}: lowest pressure in the quarter second after the impact, over "
                                             "rho0 g H0", m["min_after"], None, passed=m["min_after"] >= self.lowest,
                                             unit="", note=f"not below {self.lowest:g}"))
                q = first_peak(three["t"], three["probe"][k], ref["t"], ref["pressure"][k])["smoothed"]
                result.notes.append(f"{k} read by a probe half a spacing off the face (the `spheric-test2` case's): "
                                    f"{q['dt']:+.3f} s, {q['rel']:+.1%}.")
            figs.append(self._plot_3d(result, ref))
        passed = all(m.passed for m in result.metrics if m.passed is not None)
        return figs, passed

    def _plot_2d(self, result):
        two = result.data["two"]
        scale = RHO0 * G * 2 * A
        fig = figure(8.0, 3.0)
        ax = fig.add_subplot(1, 1, 1)
        for f in HEIGHTS_2D:
            ax.plot(two["t"], two["p"][f] / scale, lw=0.7, label=f"z = {f:g} a")
        contact = min(ringing(two["t"], two["p"][f])["t_contact"] for f in HEIGHTS_2D)
        if math.isfinite(contact):
            ax.set_xlim(contact - 0.01, two["t"][-1])
        ax.set_xlabel("t [s]")
        ax.set_ylabel("p / (rho0 g H)")
        ax.set_title(f"2D dam break on the far wall, H/dp = {result.data['H_over_dp']:g}, every 0.2 ms", fontsize=9)
        ax.legend(fontsize=8)
        return save_png(fig, result.out / f"{self.name}-2d.png")

    def _plot_3d(self, result, ref):
        three = result.data["three"]
        fig = figure(8.0, 6.0)
        for i, k in enumerate(P_FACE):
            ax = fig.add_subplot(2, 2, i + 1)
            sel = ref["t"] <= IMPACT_END
            ax.plot(ref["t"][sel], ref["pressure"][k][sel] / 1e3, "k-", lw=0.7, label="MARIN experiment")
            ax.plot(three["t"], np.nan_to_num(three["sensor"][k]) / 1e3, "-", lw=0.7, color="tab:blue",
                    label="shoal: wall sensor")
            ax.set_xlim(0.3, IMPACT_END)
            ax.set_title(f"{k} (z = {P_FACE[k]:g} m)", fontsize=9)
            ax.set_xlabel("t [s]")
            ax.set_ylabel("p [kPa]")
            if i == 0:
                ax.legend(fontsize=7)
        fig.tight_layout()
        return save_png(fig, result.out / f"{self.name}-3d.png")
