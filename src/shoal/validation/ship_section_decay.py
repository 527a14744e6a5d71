"""Heave and roll decay of a 2D ship section against a published experiment (issue 32, must-show 3).

The section of Sundsdal, Greco, Hanssen & Lugni (2025): a rectangle B = 0.40 m wide and D = 0.256 m high with
bilges rounded to r = 0.0512 m, floating at the draft d = 0.20 m in water 1.0 m deep, its centre of gravity
KG = 0.106 m above the keel (their heel test), its roll radius of gyration 0.36 B. In their NTNU flume the
model spans the width, so its motions are two-dimensional; decay tests gave the natural periods kept in
``src/shoal/data/shipSection_Sundsdal2025_decay.csv`` (heave 1.17 s; roll 1.28 s with sway restricted, 1.26 s
with sway free on the rig's soft springs). Here the same section, as a polygon with its bilge arcs, floats at
the middle of a tank 1.0 m deep with damping zones at both ends (`ship_section_case`):

- heave: released at rest `offset` above its floating level, free in heave only;
- roll: started upright at the angular velocity `spin` about its centre of gravity, sway held (the
  experiment's scenario C), heave free.

Its damped periods (the mean zero-crossing period of the first cycles, `shoal.validation.heave_decay.
decay_period_and_damping`) are compared with the measured periods. The section's own hydrostatics check its
numbers: its metacentric height from its geometry, GM = KB + I_wp / A - KG, is the published 0.0629 m within
1 % (`section_hydrostatics`).

The mass per metre is that which floats the section at its draft in water of 1000 kg/m^3, rho A (78.9 kg/m;
the published displacement, 46.8 kg over the model's 0.586 m, is 79.9 kg/m, the heave rig included); the
inertia is M (0.36 B)^2 about the centre of gravity. The rig's sway damping (8.7 N s/m, "assumed similar in
heave") and its extra sway mass are left out: they move the periods by well under 1 %.

References
----------
K. R. Sundsdal, M. Greco, F.-C. Hanssen, C. Lugni, "An experimental investigation of drift forces and
coupled-motion effects for a 2D ship cross-section in regular waves", preprint, 2025; data and set-up:
https://github.com/KRSundsdal1/2D-ship-cross-section-in-regular-waves (CC0 1.0).
"""

from __future__ import annotations

import math
import tempfile
from pathlib import Path

import numpy as np

from .core import Metric, ValidationCase, figure, save_png
from .heave_decay import decay_period_and_damping, run_decay

RHO, G = 1000.0, 9.81
BEAM = 0.40
"""B [m]."""
HEIGHT = 0.256
"""D, keel to deck [m]."""
DRAFT = 0.20
"""d [m]."""
BILGE = 0.0512
"""Bilge radius [m]."""
KG = 0.106
"""Centre of gravity above the keel [m] (the heel test's; planned 0.108)."""
GYRATION = 0.36 * BEAM
"""Roll radius of gyration [m]."""
WATER = 1.0
"""Still-water depth [m]."""
PUBLISHED_GM = 0.0629
"""GM_roll [m] of the published model table."""

DATA_FILE = "shipSection_Sundsdal2025_decay.csv"
"""The measured natural periods (in ``src/shoal/data/``), with their source lines."""


def section_vertices(xc, keel, arc=8):
    """The section's outline in the x-z plane, counter-clockwise from the deck's left corner: the keel at height
    `keel` [m], the centre line at x = `xc` [m], each bilge arc in `arc` segments."""
    v = [(xc - BEAM / 2, keel + HEIGHT)]
    for k in range(arc + 1):
        a = math.pi + 0.5 * math.pi * k / arc  # the left bilge, from the side to the bottom
        v.append((xc - BEAM / 2 + BILGE + BILGE * math.cos(a), keel + BILGE + BILGE * math.sin(a)))
    for k in range(arc + 1):
        a = 1.5 * math.pi + 0.5 * math.pi * k / arc  # the right bilge, from the bottom to the side
        v.append((xc + BEAM / 2 - BILGE + BILGE * math.cos(a), keel + BILGE + BILGE * math.sin(a)))
    v.append((xc + BEAM / 2, keel + HEIGHT))
    return v


def section_hydrostatics(draft=DRAFT, kg=KG):
    """The upright section's hydrostatics at `draft` [m]: dict of the submerged area A [m^2], KB [m] (centroid
    above the keel), BM = B^3 / (12 A) [m] and GM = KB + BM - KG [m] (exact: the rectangle less the two corner
    pieces r^2 (1 - pi/4) the bilges cut, centroid of each r (10 - 3 pi) / (12 - 3 pi) above the keel)."""
    corner = BILGE * BILGE * (1 - math.pi / 4)
    zc = BILGE * (10 - 3 * math.pi) / (12 - 3 * math.pi)  # the piece between a quarter circle and its square
    area = BEAM * draft - 2 * corner
    kb = (BEAM * draft * draft / 2 - 2 * corner * zc) / area
    bm = BEAM ** 3 / (12 * area)
    return dict(area=area, kb=kb, bm=bm, gm=kb + bm - kg)


MASS = RHO * section_hydrostatics()["area"]
"""M = rho A [kg/m]: the mass that floats the section at its draft."""
INERTIA = MASS * GYRATION ** 2
"""I = M (0.36 B)^2 [kg m^2/m] about the centre of gravity."""


def measured_periods(path=None):
    """The decay tests' natural periods [s]: {"heave", "roll_sway_restricted", "roll_sway_free"}."""
    import csv

    text = Path(path or Path(__file__).resolve().parent.parent / "data" / DATA_FILE).read_text()
    rows = list(csv.DictReader(ln for ln in text.splitlines() if ln.strip() and not ln.startswith("#")))
    table = {(r["mode"], r["rig"]): float(r["period_s"]) for r in rows}
    return {"heave": table[("heave", "scenario B")],
            "roll_sway_restricted": table[("roll", "scenario C (sway restricted)")],
            "roll_sway_free": table[("roll", "scenario B (sway free)")]}


def ship_section_case(mode, dp=0.04, length=8.0, zone=2.0, end_time=6.0, offset=0.06, spin=0.3, interval=0.005,
                      options=None, precision="float32"):
    """The 2D case of `mode` "heave" or "roll": the section (mass `MASS`, inertia `INERTIA`, KG = 0.106 m) at the
    middle of a tank `length` [m] long with water 1.0 m deep, damping zones `zone` [m] long at both ends.
    "heave": released at rest with its keel `offset` [m] above the draft, free in heave only; "roll": upright
    at its draft, spun at `spin` [rad/s] about y, sway held. The wave flumes' scheme
    (`shoal.cases.wave_flume.WAVE_OPTIONS`) unless `options` are given."""
    from ..case import Case, DampingZone, Fluid, FluidRegion, Output, Solid
    from ..cases.wave_flume import WAVE_OPTIONS
    from ..floating import FloatingBody
    from ..geometry.shapes import Box, Prism, Tank

    if mode not in ("heave", "roll"):
        raise ValueError(f"mode {mode!r}: heave or roll")
    opts = dict(options if options is not None else WAVE_OPTIONS[2])
    opts["precision"] = precision
    xc = 0.5 * length
    keel = WATER - DRAFT + (offset if mode == "heave" else 0.0)
    common = dict(mass=MASS, centre_of_gravity=(xc, 0.0, keel + KG), inertia=(INERTIA, INERTIA, INERTIA),
                  interval=interval)
    floating = (FloatingBody(fixed=["x", "rx", "ry", "rz"], **common) if mode == "heave" else
                FloatingBody(fixed=["x"], angular_velocity=(0.0, spin, 0.0), **common))
    body = Solid(name="box", shape=Prism(vertices=section_vertices(xc, keel), axis="y"), floating=floating)
    return Case(name=f"ship-section-{mode}", dim=2, dp=dp, end_time=end_time,
                fluid=Fluid(depth=WATER, surface_level=WATER), options=opts, output=Output(interval=end_time),
                solids=[Solid(name="tank", shape=Tank(lo=(0, 0, 0), hi=(length, 0, 1.6 * WATER))), body],
                fluids=[FluidRegion(shape=Box(lo=(0, 0, 0), hi=(length, 0, WATER)))],
                damping=[DampingZone(start=(zone, 0, 0), end=(0, 0, 0)),
                         DampingZone(start=(length - zone, 0, 0), end=(length, 0, 0))])


TOLERANCE = 0.10
"""Issue 32, must-show 3: each natural period within 10 % of the experiment's."""


class ShipSectionDecay(ValidationCase):
    """Heave and roll decay of the NTNU ship section (Sundsdal et al. 2025) against its measured periods."""

    name = "ship-section-decay"
    title = "Ship section: heave and roll decay against the NTNU experiment"
    cost = 240.0
    setup = ("2D: the section of Sundsdal et al. (2025), a rectangle B = 0.40 m wide, 0.256 m high, bilges rounded "
             "to 0.0512 m, floating at d = 0.20 m (M = rho A = 78.9 kg/m, KG = 0.106 m, roll radius of gyration "
             "0.36 B: GM = 0.0629 m from the geometry, as published), at the middle of a tank 8 m long with "
             "water 1.0 m deep, damping zones 2 m long at both ends. Heave: released at rest 0.06 m above its "
             "draft, free in heave only. Roll: upright, spun at 0.3 rad/s (about 3 deg of roll), sway held "
             "(the experiment's scenario C), heave free. The wave flumes' scheme (laminar viscosity, coef_h = "
             "1.5), float32. Damped period (mean zero-crossing period) and damping ratio (log decrement) over "
             "the first 2 full cycles after the first extremum. `--quick`: dp = 0.04 m (B = 10 dp, d = 5 dp), "
             "6 s; `--full`: dp = 0.02 m (B = 20 dp).")
    reference = ("Decay tests of the model in the NTNU flume (1.0 m deep, 0.6 m wide, the model spanning it): heave "
                 "1.17 s; roll 1.28 s with sway restricted (1.26 s free in sway on soft springs). K. R. Sundsdal, "
                 "M. Greco, F.-C. Hanssen, C. Lugni (2025), data and set-up at github.com/KRSundsdal1/"
                 "2D-ship-cross-section-in-regular-waves (CC0). Table: `src/shoal/data/" + DATA_FILE + "`.")
    tolerance_text = ("Issue 32, must-show 3: each damped period within 10 % of the measured natural period. The "
                      "damping ratios are reported: the experiment gives none.")

    @staticmethod
    def params(quick):
        """Arguments of `ship_section_case` (both modes) and the cycles analysed."""
        if quick:
            return dict(dp=0.04, end_time=6.0, cycles=2)
        return dict(dp=0.02, end_time=6.0, cycles=2)

    def run(self, quick, backend, out):
        res = self.new_result(quick, backend, out)
        p = dict(self.params(quick))
        cycles = p.pop("cycles")
        data, wall = {}, 0.0
        with tempfile.TemporaryDirectory(prefix="shoal-validate-") as tmp:
            for mode, column in (("heave", "z"), ("roll", "pitch")):
                t, rec, seconds, n_fluid = run_decay(ship_section_case(mode, **p), Path(tmp) / mode, column, backend)
                data[mode] = dict(t=t.tolist(), record=rec.tolist())
                wall += seconds
        res.run_seconds = wall
        res.data = dict(data, cycles=cycles, dp=p["dp"])
        res.resolution = f"dp = {p['dp']} m (B = {BEAM / p['dp']:.0f} dp, d = {DRAFT / p['dp']:.0f} dp)"
        res.particles = f"{n_fluid} fluid"
        return res

    def compare(self, result):
        ref = measured_periods()
        fig = figure(height=5.0)
        result.metrics, measured = [], {}
        for k, (mode, key, unit, scale) in enumerate((("heave", "heave", "heave / d", DRAFT),
                                                      ("roll", "roll_sway_restricted", "roll [deg]", 1.0))):
            t, rec = np.array(result.data[mode]["t"]), np.array(result.data[mode]["record"])
            m = decay_period_and_damping(t, rec, cycles=result.data["cycles"])
            measured[mode] = {q: v for q, v in m.items() if q != "extrema"}
            result.metrics.append(Metric(f"damped {mode} period against the experiment", m["period_d"] / ref[key] - 1,
                                         TOLERANCE, note=f"{m['period_d']:.4f} s against {ref[key]:.2f} s"))
            result.metrics.append(Metric(f"{mode} damping ratio (reported)", m["zeta"], None, unit="",
                                         note="no measured damping to compare with"))
            ax = fig.add_subplot(2, 1, k + 1)
            ax.plot(t, (rec - m["level"]) / scale, "k-", lw=1, label=f"SPH, {result.resolution}")
            te, ze = m["extrema"]
            ax.plot(te, (np.array(ze) - m["level"]) / scale, "bo", ms=3, label="extrema analysed")
            t0 = te[0]
            ax.plot(t0 + np.array([0.0, ref[key]]), [0.0, 0.0], "r-", lw=3,
                    label=f"the measured period, {ref[key]:.2f} s")
            ax.set_ylabel(unit)
            ax.legend(fontsize=7)
        ax.set_xlabel("t [s]")
        result.data["measured"] = measured
        result.data["reference"] = ref
        path = save_png(fig, Path(result.out) / "ship_section_decay.png")
        return [path], all(x.passed for x in result.metrics if x.tolerance is not None)
