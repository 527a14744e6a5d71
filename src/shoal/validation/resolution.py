"""Resolution study: the dam-break front error and the bore celerity error against dp."""

from __future__ import annotations

import numpy as np

from . import runs
from .core import Metric, ValidationCase, figure, save_png


class ResolutionStudy(ValidationCase):
    """Dam-break front at three resolutions and the undular bore's celerity at two (quick) or three.

    Parameters
    ----------
    tolerance : float
        Largest celerity error of the bore at the finest resolution that passes (0.03).
    """

    name = "resolution-study"
    title = "Resolution study: dam-break front and bore celerity against dp"
    cost = 150.0
    setup = ("The `dam-break-2d` front (as in that case) at dp = a/9, a/18, a/36.5 (quick) or a/18, a/36.5, "
             "a/73 (full), and the U = 0.3 m/s `tidal-bores` run (as in that case) at dp = 0.02 and 0.01 m "
             "to t = 1.3 s (quick) or 0.02, 0.01 and 0.005 m to t = 1.6 s (full). Runs already made by "
             "the other cases in the same session are reused.")
    reference = ("Martin & Moyce (1952) for the front (mean relative error over 0.8 <= T <= 3); Belanger for "
                 "the celerity (0.928 m/s). Self-convergence of the front: the mean |Z(dp) - Z(dp/2)| over "
                 "0.8 <= T <= 3 between successive resolutions, relative to the finer one.")
    tolerance_text = ("convergence, not a match: the change of the dam-break front between successive "
                      "resolutions must shrink (the SPH solution converges; it converges towards a nearly "
                      "inviscid front that leads the experiment, so the error against Martin & Moyce need not "
                      "fall, see the README), and the bore celerity at the finest resolution must be within "
                      "the 3 % of `tidal-bores`.")

    def __init__(self, tolerance=0.03):
        self.tol = float(tolerance)

    @staticmethod
    def plan(quick):
        if quick:
            return dict(dam=(9.0, 18.0, 36.5), bore_dp=(0.02, 0.01), bore_t=1.3)
        return dict(dam=(18.0, 36.5, 73.0), bore_dp=(0.02, 0.01, 0.005), bore_t=1.6)

    def run(self, quick, backend, out):
        res = self.new_result(quick, backend, out)
        p = self.plan(quick)
        reused = [f"dam break a/{n:g}" for n in p["dam"] if runs.cached(("dam-break-2d", n, backend, 3.3))]
        reused += [f"bore dp = {dp:g}" for dp in p["bore_dp"]
                   if runs.cached(("tidal-bore", 0.3, dp, p["bore_t"], backend))]
        dam = {n: runs.dam_break_front(n, backend) for n in p["dam"]}
        bore = {dp: runs.bore(0.3, dp, p["bore_t"], backend) for dp in p["bore_dp"]}
        res.run_seconds = sum(r["seconds"] for r in [*dam.values(), *bore.values()])
        res.shared = bool(reused)
        if reused:
            res.notes.append("reused from other cases of this session: " + ", ".join(reused))
        res.resolution = ("dam break dp = " + ", ".join(f"a/{n:g}" for n in p["dam"]) + "; bore dp = "
                          + ", ".join(f"{dp:g}" for dp in p["bore_dp"]) + " m")
        res.particles = ("dam break " + " / ".join(f"{r['particles']:,}" for r in dam.values()) + "; bore "
                         + " / ".join(f"{r['particles']:,}" for r in bore.values()))
        res.data = dict(dam=dam, bore=bore)
        return res

    def compare(self, result):
        from ..analysis import load_reference, mean_relative_error

        Tm, Zm = load_reference("martin_moyce_front")
        dam, bore = result.data["dam"], result.data["bore"]
        ns = sorted(dam)
        errs = [mean_relative_error(dam[n]["T"], dam[n]["Z"], Tm, Zm, 0.8, 3.0) for n in ns]
        t = np.linspace(0.8, 3.0, 23)
        zs = {n: np.interp(t, dam[n]["T"], dam[n]["Z"]) for n in ns}
        diffs = [float(np.mean(np.abs(zs[a] - zs[b]) / zs[b])) for a, b in zip(ns[:-1], ns[1:])]
        dps = sorted(bore, reverse=True)
        bm = {dp: runs.bore_measures(bore[dp]) for dp in dps}
        cerr = [(bm[dp]["c"] - bm[dp]["c_ref"]) / bm[dp]["c_ref"] for dp in dps]
        result.metrics = [Metric(f"dam break a/{n:g}: front error vs Martin & Moyce", e, note="for information")
                          for n, e in zip(ns, errs)]
        result.metrics.append(Metric(
            "dam break: change between successive resolutions shrinks",
            diffs[-1] / diffs[0] if diffs[0] > 0 else float("nan"), None, unit="x",
            passed=bool(all(b < a for a, b in zip(diffs[:-1], diffs[1:]))),
            note="ratio of the last to the first; mean |Z(dp) - Z(finer)| / Z(finer) = "
            + ", ".join(f"{100 * v:.2f} %" for v in diffs)))
        result.metrics += [Metric(f"bore U = 0.3 m/s, dp = {dp:g} m: celerity vs Belanger", e,
                                  self.tol if dp == dps[-1] else None,
                                  note="" if dp == dps[-1] else "for information")
                           for dp, e in zip(dps, cerr)]
        fig = figure(8.0, 3.2)
        ax1, ax2 = fig.add_subplot(1, 2, 1), fig.add_subplot(1, 2, 2)
        inv = [1 / n for n in ns]
        ax1.plot(inv, [100 * e for e in errs], "o-", color="tab:blue", label="error vs Martin & Moyce")
        ax1.plot([np.sqrt(inv[k] * inv[k + 1]) for k in range(len(diffs))], [100 * v for v in diffs], "s--",
                 color="tab:purple", label="mean |Z(dp) - Z(next finer)| / Z")
        ax1.set_xscale("log")
        ax1.set_xlabel("dp / a")
        ax1.set_ylabel("%")
        ax1.set_title("2D dam-break front, 0.8 <= T <= 3", fontsize=9)
        ax1.set_ylim(0, 1.45 * max(100 * max(errs), 100 * max(diffs)))  # room for the legend above the points
        ax1.legend(fontsize=7, loc="upper center")
        ax2.plot([dp / 0.1 for dp in dps], [100 * e for e in cerr], "o-", color="tab:green",
                 label="celerity error")
        ax2.plot([dp / 0.1 for dp in dps], [100 * (bm[dp]["d1"] - bm[dp]["d1_ref"]) / bm[dp]["d1_ref"] for dp in dps],
                 "s--", color="tab:orange", label="level behind the front")
        for s in (-1, 1):
            ax2.axhline(100 * s * self.tol, color="k", ls="--", lw=0.8)
        ax2.axhline(0, color="k", lw=0.5)
        ax2.set_xscale("log")
        ax2.set_xlabel("dp / d0")
        ax2.set_ylabel("error vs Belanger [%]")
        ax2.set_title("undular bore U = 0.3 m/s (dashed: 3 %)", fontsize=9)
        ax2.legend(fontsize=7, loc="lower right")
        path = save_png(fig, result.out / "resolution-study.png")
        return [path], all(m.passed for m in result.metrics if m.passed is not None)
