"""Tidal bores (2D flume section): celerity and conjugate depth against the Belanger relations,
and the undular bore's first-wave amplitude against Favre (1935)."""

from __future__ import annotations

import time

import numpy as np

from . import runs
from .core import Metric, ValidationCase, figure, find_validation_dir, read_csv_with_comments, save_png

BORE_SETUP = ("`tidal-bore` with `dim = 2`: the x-z section of the 3 m x 0.4 m flume of Liu et al., water "
              "d0 = 0.1 m deep flowing at U towards the closed gate at x = 0 (the inflow made by a wall pushed "
              "at U from x = 3 m); the bore travels upstream. Wave gauges at x = 0.5, 1.0 and 1.5 m every "
              "0.01 s (kernel-sum surface). The paper's scheme: cubic spline, predictor-corrector, XSPH 0.5, "
              "MLS filter every 30 steps, SPS turbulence, alpha = 0.1, walls free-slip for the viscous term "
              "(`visco_bound_factor = 0`), float32.")


def _quick_params(quick):
    return (0.01, 1.3) if quick else (0.005, 1.6)


class TidalBores(ValidationCase):
    """The undular (U = 0.3 m/s) and breaking (U = 0.7 m/s) bores against the Belanger relations.

    Parameters
    ----------
    tolerance : float
        Largest relative error of the celerity and of the level behind the front that passes (0.03).
    speeds : tuple of float
        Inflow speeds U [m/s].
    """

    name = "tidal-bores"
    title = "Tidal bores: celerity and conjugate depth (2D section)"
    cost = 300.0
    setup = BORE_SETUP + (" The celerity is the least-squares slope of gauge position against the arrival "
                          "time of the level half-way between d0 and d1; the level behind the front is the "
                          "mean of the 0.5 m gauge from 0.15 s after the arrival to the end of the run.")
    reference = ("Rankine-Hugoniot (Belanger) state of a flow of depth d0 and speed U stopped by a gate: "
                 "(U + c) d0 = c d1 and d1/d0 = (sqrt(1 + 8 Fr^2) - 1)/2 with Fr = (U + c)/sqrt(g d0) "
                 "(`shoal.analysis.bore_from_inflow`): U = 0.3 m/s gives c = 0.928 m/s, d1 = 0.1323 m, "
                 "Fr = 1.24 (undular); U = 0.7 m/s gives c = 0.873 m/s, d1 = 0.180 m, Fr = 1.59 (breaking).")
    tolerance_text = ("celerity and level behind the front within 3 % of Belanger (issue 8): the relations "
                      "are exact for a frictionless channel with hydrostatic pressure far from the front, and "
                      "the tidal-bore paper reports 0.72 % (undular) and 2.08 % (breaking) against them; the "
                      "gauges' kernel-sum surface resolves the level to about dp/4 (2.5 % of d0 at "
                      "dp = 0.01 m). The first crest over d1 is shown for information.")

    def __init__(self, tolerance=0.03, speeds=(0.3, 0.7)):
        self.tol = float(tolerance)
        self.speeds = tuple(float(u) for u in speeds)

    def run(self, quick, backend, out):
        res = self.new_result(quick, backend, out)
        dp, t_end = _quick_params(quick)
        t0 = time.perf_counter()
        res.data = {"runs": {U: runs.bore(U, dp, t_end, backend) for U in self.speeds}, "dp": dp, "t_end": t_end}
        res.run_seconds = time.perf_counter() - t0
        res.resolution = f"dp = {dp:g} m = d0/{0.1 / dp:.0f}, to t = {t_end:g} s"
        res.particles = ", ".join(f"U = {U:g}: {r['particles']:,} ({r['fluid']:,} fluid)"
                                  for U, r in res.data["runs"].items())
        return res

    def compare(self, result):
        d = result.data
        result.metrics = []
        fig = figure(8.0, 3.2 * len(d["runs"]) / 1.6)
        for k, (U, r) in enumerate(d["runs"].items()):
            m = runs.bore_measures(r)
            dc = (m["c"] - m["c_ref"]) / m["c_ref"]
            dl = (m["d1"] - m["d1_ref"]) / m["d1_ref"]
            result.metrics += [
                Metric(f"U = {U:g} m/s: celerity vs Belanger ({m['c_ref']:.3f} m/s)", dc, self.tol,
                       note=f"measured {m['c']:.4f} m/s"),
                Metric(f"U = {U:g} m/s: level behind the front vs d1 = {m['d1_ref']:.4f} m", dl, self.tol,
                       note=f"measured {m['d1']:.4f} m"),
            ]
            undular = m["fr_ref"] < 1.3
            shape_ok = bool(m["first"] > 0.03) if undular else bool(m["first"] < 0.03)
            result.metrics.append(Metric(
                f"U = {U:g} m/s: first crest over d1 at x = 0.5 m", m["first"], None,
                note=("for information (the amplitude is judged in `undular-bore-amplitude`); "
                      + ("undular as expected" if undular and shape_ok else
                         "breaking as expected (no crest 3 % above d1)" if shape_ok else
                         "expected an undular front (> 3 % above d1)" if undular else
                         "overshoots d1 by more than the 3 % a breaking front should (the test suite checks "
                         "this at dp = 0.005 m)")
                      + f"; {m['crests']} crest(s) within 1 s")))
            if r["escaped"]:
                result.notes.append(f"U = {U:g} m/s: {r['escaped']} particles left the domain.")
            result.notes.append(f"U = {U:g} m/s: {r['steps']:,} steps, {r['seconds']:.0f} s.")
            ax = fig.add_subplot(len(d["runs"]), 1, k + 1)
            for (x, (t, z)), col in zip(sorted(r["gauges"].items()), ("tab:blue", "tab:orange", "tab:green")):
                ax.plot(t, z, "-", color=col, lw=1, label=f"gauge x = {x:g} m")
                if x / m["c_ref"] <= t[-1]:
                    ax.plot([x / m["c_ref"]] * 2, [0.1, m["d1_ref"]], ":", color=col, lw=1)
            ax.axhline(m["d1_ref"], color="k", ls="--", lw=0.8, label="Belanger d1")
            ax.axhline(0.1, color="0.5", lw=0.6)
            ax.set_ylabel("level [m]")
            ax.set_title(f"U = {U:g} m/s (Fr = {m['fr_ref']:.2f}): dotted = arrival at the Belanger celerity; "
                         f"celerity {100 * dc:+.1f} %, level {100 * dl:+.1f} %", fontsize=9)
            ax.legend(fontsize=7, loc="upper left", ncol=4)
        ax.set_xlabel("t [s]")
        path = save_png(fig, result.out / "tidal-bores.png")
        return [path], all(mt.passed for mt in result.metrics if mt.passed is not None)


class UndularAmplitude(ValidationCase):
    """First-wave amplitude of undular bores, a_max / h0 against the Froude number, vs Favre (1935).

    Parameters
    ----------
    tolerance : float
        Largest relative error of a_max / h0 that passes (0.15).
    """

    name = "undular-bore-amplitude"
    title = "Undular bore: first-wave amplitude vs Froude number (Favre 1935)"
    cost = 150.0
    setup = BORE_SETUP + (" a_max = (z_max - d0) / d0 with z_max the highest level (smoothed over 5 samples) "
                          "within 1 s of the bore's arrival, at the gauge giving the largest value among those "
                          "with 0.3 s of record after the arrival; Fr = (U + c) / sqrt(g d0) with the measured "
                          "celerity c. Quick: the U = 0.3 m/s bore of `tidal-bores` (one point); full: also "
                          "U = 0.15 and 0.2 m/s (Fr 1.12 and 1.16).")
    reference = ("Favre (1935), maximum amplitude of the first undulation a_max/h0 = (h_max - h0)/h0 against "
                 "Fr = |u0 - sigma| / sqrt(g h0), laboratory series h0 = 100 (units not stated, presumably mm), "
                 "digitised in ranocha/2024_serre_green_naghdi (MIT), `validation/undular-bore-amplitude/`; "
                 "the series h0 = 200 is drawn for comparison and used where Fr is beyond the h0 = 100 "
                 "series (Fr > 1.206).")
    tolerance_text = ("a_max/h0 within 15 % of Favre's at the measured Fr (linear interpolation): the two "
                      "digitised series (h0 = 100 and 200) differ by up to 5 % at equal Fr, a_max still grows "
                      "with the distance the bore has travelled (Favre's channel was longer than this 3 m "
                      "flume) and the data are digitised from a figure (quality C).")

    def __init__(self, tolerance=0.15):
        self.tol = float(tolerance)

    @staticmethod
    def speeds(quick):
        return (0.3,) if quick else (0.15, 0.2, 0.3)

    def run(self, quick, backend, out):
        res = self.new_result(quick, backend, out)
        dp, t_end = _quick_params(quick)
        t0 = time.perf_counter()
        speeds = self.speeds(quick)
        reused = [U for U in speeds if runs.cached(("tidal-bore", U, dp, t_end, backend))]
        res.data = {"runs": {U: runs.bore(U, dp, t_end, backend) for U in speeds}, "dp": dp}
        res.run_seconds = sum(r["seconds"] for r in res.data["runs"].values())
        res.shared = bool(reused)
        if reused:
            res.notes.append("runs shared with `tidal-bores`: U = " + ", ".join(f"{u:g}" for u in reused) + " m/s")
        res.resolution = f"dp = {dp:g} m = d0/{0.1 / dp:.0f}, to t = {t_end:g} s"
        res.particles = ", ".join(f"U = {U:g}: {r['particles']:,}" for U, r in res.data["runs"].items())
        return res

    def reference_data(self):
        """{h0: (Fr, a_max/h0)} of the Favre series shipped in ``validation/undular-bore-amplitude/``."""
        folder = find_validation_dir() / self.name
        out = {}
        for h0 in (100, 200):
            path = folder / f"undularBore_Favre_amax_vs_Fr_h0_{h0}.csv"
            if not path.is_file():
                raise FileNotFoundError(f"reference data not found: {path}")
            _, data = read_csv_with_comments(path)
            out[h0] = (data[:, 0], data[:, 1])
        return out

    @staticmethod
    def reference_at(ref, fr):
        """(a_max/h0, series) of Favre at `fr`: the h0 = 100 series, else h0 = 200, else NaN."""
        for h0 in (100, 200):
            F, a = ref[h0]
            if F.min() <= fr <= F.max():
                return float(np.interp(fr, F, a)), h0
        return float("nan"), None

    def compare(self, result):
        ref = self.reference_data()
        pts = []
        result.metrics = []
        for U, r in result.data["runs"].items():
            m = runs.bore_measures(r)
            a_ref, series = self.reference_at(ref, m["fr"])
            err = (m["amax"] - a_ref) / a_ref if np.isfinite(a_ref) else float("nan")
            pts.append((U, m["fr"], m["amax"], a_ref))
            crest_dp = (runs.BORE_DEPTH * (1 + m["amax"]) - m["d1_ref"]) / result.data["dp"]
            note = (f"Fr = {m['fr']:.3f}, a_max/h0 = {m['amax']:.3f} (gauge x = {m['amax_gauge']} m) vs "
                    f"{a_ref:.3f} (Favre, h0 = {series})" if series else
                    f"Fr = {m['fr']:.3f} is outside the Favre data (1.06-1.37)")
            result.metrics.append(Metric(f"U = {U:g} m/s: a_max/h0 vs Favre", err, self.tol, note=note))
        if any(m.passed is False for m in result.metrics):
            far = max(x for _, x in runs.BORE_GAUGES)
            result.notes.append(
                f"What the FAIL says: the computed first wave is {'lower' if err < 0 else 'higher'} than Favre's "
                f"at the same Froude number. At dp = d0/{0.1 / result.data['dp']:.0f} the first crest stands "
                f"{crest_dp:.1f} particle spacing(s) above d1, so the crest is barely resolved. It is not the "
                f"distance the bore has travelled (the gauges are 0.5-{far:g} m from the gate): in a 10 m flume "
                "at dp = d0/10 a_max/h0 stays at 0.37-0.42 from 0.5 to 6 m (README, Validation). It is the "
                "resolution and the scheme's dissipation: alpha = 0.01 instead of 0.1 raises a_max/h0 from 0.41 "
                "to 0.44 at d0/10, a wider kernel (coef_h = 1.5) does not change it "
                "(`benchmarks/bore_options.py`), and the error falls as dp does: for U = 0.3 m/s -30.9 % at "
                "d0/10 (quick) and -22.6 % at d0/20 (--full, 2026-12-03), where the weakest bore (U = 0.15 m/s, "
                "Fr 1.09, a first wave 0.2 h0 high) is within 2 % and U = 0.2 m/s (Fr 1.13) is at -19.7 %: the "
                "taller the first wave, the more of it the particles smooth away. The next check is d0/40 "
                "(8 times the d0/20 cost: a GPU run).")
        fig = figure(6.0, 3.4)
        ax = fig.add_subplot(1, 1, 1)
        for (h0, (F, a)), mk in zip(ref.items(), ("ks", "kD")):
            ax.plot(F, a, mk, ms=4, mfc="none" if h0 == 200 else "k", label=f"Favre 1935, h0 = {h0}")
        P = np.array(pts)
        ax.plot(P[:, 1], P[:, 2], "o", color="tab:red", ms=6, label=f"shoal, dp = {result.data['dp']:g} m")
        for U, fr, a, _ in pts:
            ax.annotate(f"U = {U:g}", (fr, a), textcoords="offset points", xytext=(5, -10), fontsize=7)
        ax.set_xlabel(r"Fr = $(U + c)/\sqrt{g d_0}$")
        ax.set_ylabel(r"$a_{max}/h_0$")
        ax.set_title("first-wave amplitude of undular bores", fontsize=9)
        ax.legend(fontsize=8)
        path = save_png(fig, result.out / "undular-bore-amplitude.png")
        return [path], all(mt.passed for mt in result.metrics if mt.passed is not None)
