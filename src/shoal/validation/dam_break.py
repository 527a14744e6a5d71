"""2D dam break: the surge front against Martin & Moyce (1952) and Koshizuka & Oka (1996)."""

from __future__ import annotations

import time

import numpy as np

from . import runs
from .core import Metric, ValidationCase, figure, save_png


class DamBreak2D(ValidationCase):
    """`dam-break-2d`: front Z = x/a against T = t sqrt(2 g / a).

    Parameters
    ----------
    tolerance : float
        Largest mean relative error against Martin & Moyce over 0.8 <= T <= 3 that passes (0.07).
    band_tolerance : float
        Largest distance of the front outside the band between the two experiments, relative to
        the band's lower edge, at T = 0.8, 1.0, ..., 3.0 (0.07).
    """

    name = "dam-break-2d"
    title = "2D dam break: surge front"
    cost = 60.0
    setup = ("`dam-break-2d`: a water column a = 0.146 m wide and 2a high at the left wall of a tank 5a "
             "long, released at t = 0; the front is the largest x of the fluid particles, recorded every "
             "dT = 0.05 to T = 3.3. Wendland kernel, alpha = 0.1, Fourtakas delta = 0.1, symplectic, "
             "float32, 3 layers of wall particles with the pressure extrapolated from the fluid (Adami et "
             "al. 2012) (the defaults).")
    reference = ("Martin & Moyce (1952), Phil. Trans. R. Soc. A 244, Table 2 (n^2 = 2, a = 2.25 in), typed "
                 "by the Ocellaris author; Koshizuka & Oka (1996), Nucl. Sci. Eng. 123, experimental front "
                 "digitised by the PySPH authors. Both ship in `src/shoal/data/` with their source lines "
                 "(`shoal.analysis.load_reference`).")
    tolerance_text = ("mean relative error vs Martin & Moyce over 0.8 <= T <= 3 <= 7 %, and the front within "
                      "7 % of the band between the two experiments at T = 0.8 ... 3.0: the two experiments "
                      "differ from each other by about 6 % near T = 2.3 (gate opening, bed friction and the "
                      "turbulent tip, which no 2D inviscid-limit scheme models), so a closer match is not "
                      "meaningful; T < 0.8 is left out because the gate's removal dominates there.")

    def __init__(self, tolerance=0.07, band_tolerance=0.07):
        self.tol = float(tolerance)
        self.band_tol = float(band_tolerance)

    @staticmethod
    def n_per_a(quick):
        """Particles across the column width a."""
        return 18.0 if quick else 36.5

    def run(self, quick, backend, out):
        res = self.new_result(quick, backend, out)
        n = self.n_per_a(quick)
        t0 = time.perf_counter()
        reused = runs.cached(("dam-break-2d", float(n), backend, 3.3))
        r = runs.dam_break_front(n, backend)
        res.run_seconds = r["seconds"] if reused else time.perf_counter() - t0
        res.shared = reused
        if reused:
            res.notes.append("run shared with another case of this session")
        res.resolution = f"dp = a/{n:g} = {r['dp'] * 1e3:.2f} mm"
        res.particles = f"{r['particles']:,} ({r['fluid']:,} fluid)"
        res.data = dict(r, n_per_a=n)
        return res

    def compare(self, result):
        from ..analysis import load_reference, mean_relative_error, outside_band

        d = result.data
        T, Z = d["T"], d["Z"]
        Tm, Zm = load_reference("martin_moyce_front")
        Tk, Zk = load_reference("koshizuka_oka_front")
        err_mm = mean_relative_error(T, Z, Tm, Zm, 0.8, 3.0)
        err_ko = mean_relative_error(T, Z, Tk, Zk, 0.8, 3.0)
        band = outside_band(T, Z, (Tm, Zm), (Tk, Zk), np.arange(0.8, 3.001, 0.2))
        result.metrics = [
            Metric("front, mean relative error vs Martin & Moyce, 0.8 <= T <= 3", err_mm, self.tol),
            Metric("front, mean relative error vs Koshizuka & Oka, 0.8 <= T <= 3", err_ko,
                   note="for information"),
            Metric("front, largest distance outside the band of the two experiments, T = 0.8 ... 3.0",
                   band, self.band_tol),
            Metric("fluid particles lost", 0.0 if d["mass_conserved"] else 1.0, 0.0, unit="particles"),
        ]
        result.notes.append(f"{d['steps']:,} steps.")
        fig = figure(8.0, 3.2)
        ax1, ax2 = fig.add_subplot(1, 2, 1), fig.add_subplot(1, 2, 2)
        ax1.plot(T, Z, "-", color="tab:blue", label=f"shoal, dp = a/{d['n_per_a']:g}")
        ax1.plot(Tm, Zm, "ks", ms=4, mfc="none", label="Martin & Moyce 1952")
        ax1.plot(Tk, Zk, "r^", ms=4, mfc="none", label="Koshizuka & Oka 1996")
        ax1.axvspan(0.8, 3.0, color="0.93")
        ax1.set_xlabel(r"$T = t\sqrt{2g/a}$")
        ax1.set_ylabel("Z = x / a")
        ax1.set_xlim(0, 3.4)
        ax1.legend(fontsize=8)
        ax1.set_title("surge front (shaded: compared range)", fontsize=9)
        for Tr, Zr, mk, lab in ((Tm, Zm, "ks", "vs Martin & Moyce"), (Tk, Zk, "r^", "vs Koshizuka & Oka")):
            sel = (Tr >= 0.8) & (Tr <= 3.0)
            ax2.plot(Tr[sel], 100 * (np.interp(Tr[sel], T, Z) - Zr[sel]) / Zr[sel], mk + "-", ms=4, mfc="none",
                     lw=0.8, label=lab)
        ax2.axhline(0, color="k", lw=0.6)
        for s in (-1, 1):
            ax2.axhline(100 * s * self.tol, color="k", ls="--", lw=0.8)
        ax2.set_xlabel("T")
        ax2.set_ylabel("(Z_shoal - Z_exp) / Z_exp [%]")
        ax2.set_title("relative error (dashed: tolerance on the mean)", fontsize=9)
        ax2.legend(fontsize=8)
        path = save_png(fig, result.out / "dam-break-2d.png")
        return [path], all(m.passed for m in result.metrics if m.passed is not None)
