"""Tidal bores in the flume of the tidal-bore paper, 2D section (x-z): the bore made by stopping an
inflow U against a closed gate travels upstream with the celerity and leaves the conjugate depth
that mass and momentum conservation across the front give.

Bore relations (derived in `shoal.analysis.bore`): in the bore's frame water arrives at U + c with
depth d0 and leaves at c with depth d1, so per unit width

    (U + c) d0 = c d1                                   (mass)
    (U + c)^2 d0 + g d0^2 / 2 = c^2 d1 + g d1^2 / 2     (momentum, hydrostatic pressure)

giving Belanger's d1 / d0 = (sqrt(1 + 8 Fr^2) - 1) / 2 with Fr = (U + c) / sqrt(g d0). For
d0 = 0.1 m: U = 0.3 m/s gives c = 0.928 m/s, d1 = 0.1323 m, Fr = 1.24 (undular: Fr < ~1.3,
Favre 1935, Chanson 2009); U = 0.7 m/s gives c = 0.873 m/s, d1 = 0.180 m, Fr = 1.59 (breaking).

Measured: the celerity is the least-squares slope of gauge position (0.5, 1.0, 1.5 m from the gate)
against the arrival time of the level half-way between d0 and d1; the level behind the front is the
mean of the 0.5 m gauge from 0.15 s after the arrival to the end of the run (across the undulations).

The scheme is the paper's (cubic spline, predictor-corrector, XSPH 0.5, MLS filter every 30 steps,
SPS, artificial viscosity alpha = 0.1) with the walls free-slip for the viscous term
(visco_bound_factor = 0, as the built-in tidal-bore cases): with alpha = 0.1 on the bed the
artificial viscosity (alpha h c0 / 8, about 1700 times water's) is a bed friction that took a third
of the inflow's speed within 0.8 s and made the undular bore 7.5 % slow at dp = 5 mm; the bore
relations are frictionless and so, over 1.6 s and 3 m, is water on a smooth bed (its boundary layer
is sqrt(nu t) ~ 1 mm thick).
"""

import numpy as np
import pytest

import shoal
from shoal.analysis import arrival_time, bore_from_inflow, celerity, crest_speed_ratio, level_behind, undulations
from shoal.cases import tidal_bore
from shoal.cases.tidal_bore import PAPER_OPTIONS
from shoal.options import SPHOptions
from shoal.output.vtu import read_vtu
from shoal.physics.spec import FLUID

D0 = 0.1


LOW_ALPHA = dict(PAPER_OPTIONS, alpha=0.02)
"""The paper's scheme with alpha = 0.02 (the paper gives no alpha; the built-in cases use 0.1): with 0.1
the 2D front of the U = 0.7 m/s bore is smoothed and never breaks (crest water at most 0.27 c at
dp = d0/10), with 0.02 it breaks."""


def run_bore(U, dp, end_time, tmp_path, options=None, breaking=False):
    """Run the 2D bore; with `breaking`, snapshots every 0.05 s give the kinematic breaking index."""
    opts = SPHOptions(**options) if options else None
    every = 0.05 if breaking else end_time
    case = tidal_bore(dp=dp, inflow_speed=U, dim=2, end_time=end_time, output_interval=every, options=opts)
    c, d1, fr = bore_from_inflow(U, D0)
    res = shoal.run_case(case, tmp_path / f"bore_{U}", plot=False)
    assert res.escaped == 0
    xs, arrivals, records = [], [], {}
    for name, x in (("x0.5", 0.5), ("x1.0", 1.0), ("x1.5", 1.5)):
        data = np.loadtxt(tmp_path / f"bore_{U}" / f"gauge_{name}.csv", delimiter=",", skiprows=1)
        t, z = data[:, 0], data[:, 1]
        ta = arrival_time(t, z, D0 + 0.5 * (d1 - D0))
        xs.append(x)
        arrivals.append(ta)
        records[x] = (t, z, ta)
    cm = celerity(xs, arrivals)
    t, z, ta = records[0.5]
    level = level_behind(t, z, ta)
    n_crests, first = undulations(t, z, ta, d1)
    print(f"U = {U} m/s, dp = {dp} m: celerity {cm:.4f} m/s vs {c:.4f} ({(cm - c) / c:+.2%}), level behind the "
          f"front {level:.4f} m vs d1 = {d1:.4f} ({(level - d1) / d1:+.2%}); first crest {first:+.2%} over d1, "
          f"{n_crests} crest(s); {res.steps} steps, {res.wall_seconds:.0f} s")
    index = float("nan")
    if breaking:
        series = []
        for f in sorted((tmp_path / f"bore_{U}").glob("tidal-bore_*.vtu")):
            pts, data = read_vtu(f)
            fluid = data["kind"] == FLUID
            series.append(crest_speed_ratio(pts[fluid], data["velocity"][fluid], D0, d1, c))
        index = max(series)
        print(f"  breaking index max(u_crest) / c every 0.05 s: {' '.join(f'{b:.2f}' for b in series)}")
    return (cm - c) / c, (level - d1) / d1, n_crests, first, index


@pytest.mark.parametrize("U,end_time", [(0.3, 1.3), (0.7, 1.6)])
def test_bore_undular_or_breaking_quick(U, end_time, tmp_path):
    """Issue 5 item 2 with one scheme (`LOW_ALPHA`) at dp = d0/10: both bores within 3 % of the
    Belanger celerity and conjugate depth; the U = 0.3 m/s bore (Fr 1.24) undular -- secondary crests,
    the first above d1, its water far slower than the front (breaking index B = max u_crest / c well
    below 1) -- and the U = 0.7 m/s bore (Fr 1.59) breaking: its crest water overtakes the front (B >= 1,
    the kinematic breaking criterion; `shoal.analysis.crest_speed_ratio`).

    Measured (2026-12-02, d0/10): U = 0.3 m/s: celerity -1.8 %, level +1.2 %, first crest 8.5 % above d1,
    B = 0.24 at most; U = 0.7 m/s: celerity -2.2 %, level -1.4 %, B above 1 from t = 1.2 s, up to 1.78.
    With alpha = 0.1 (the built-in default; U = 0.3 m/s at d0/10: celerity -0.8 %, level +1.1 %, first
    crest 6.5 % above d1, and at d0/20 in `test_bore_celerity_and_conjugate_depth`) the U = 0.7 m/s bore
    has B <= 0.27: it never breaks. At d0/20 (2026-12-02, 34 min on a loaded thread) the same scheme breaks
    earlier and harder (B > 1 from t = 0.55 s, up to 1.94; level -1.1 %) but the front, timed between the
    0.5 and 1.0 m gauges only (the 1.5 m gauge is reached after 1.6 s), runs 24 % fast while the breaking
    bore forms (0.08 s late at 0.5 m, 0.03 s early at 1.0 m): not asserted here. In a 5 m flume at d0/10
    (`tidal_bore(length=5.0, gauges_x=...)`, to 3.4 s) the breaking front's speed pulsates from gauge to
    gauge (-1.8, +9.5, +4.1, +1.3 % over 0.5 m spans) and averages +3.8 % over 0.5-2.5 m (+2.7 % over
    1.5-2.5 m), level -2.9 % at 1 m: the 3 % holds on this test's gauges, not yet over a longer run.
    At d0/20 in the 5 m flume (`benchmarks/breaking_bore.py --dp 0.005 --length 5`, 51 min on 2 threads)
    the settled front's celerity over 1.0-2.5 m is +0.7 % and the level behind it -3.0 to -6.5 %: the
    inflow ahead of the bore slows near the bed (to 0.28 m/s in the lowest 2 cm by t = 2.5 s); without
    the MLS filter the level is within 3 % at d0/10 but still -3.2 to -5.3 % at d0/20 (README, Validation)."""
    dc, dl, n, first, index = run_bore(U, 0.01, end_time, tmp_path, options=LOW_ALPHA, breaking=True)
    assert abs(dc) < 0.03 and abs(dl) < 0.03
    if U < 0.5:
        assert n >= 1 and first > 0.03 and index < 0.5
    else:
        assert index >= 1.0


@pytest.mark.validation
@pytest.mark.parametrize("U", [0.3, 0.7])
def test_bore_celerity_and_conjugate_depth(U, tmp_path):
    """dp = d0/20 = 5 mm, the paper's resolution, to t = 1.6 s: celerity and conjugate depth within
    3 % of the bore relations, and the U = 0.3 m/s bore undular.

    Measured (2026-11-23): U = 0.3 m/s: celerity -2.6 %, level +0.7 %, first crest 9.1 % above d1,
    2 crests; U = 0.7 m/s: celerity +0.6 %, level -0.1 % (69 min on a loaded 2-core machine). The
    U = 0.7 m/s bore does NOT break in this 2D section: its front overshoots d1 by 18.8 % with
    secondary crests, and near the front no particle moves faster than a quarter of the bore's
    celerity (no overturning, the kinematic breaking criterion; checked at dp = d0/10), so breaking
    is not asserted -- an open item (the paper's breaking bore is 3D, with SPS)."""
    dc, dl, n, first, _ = run_bore(U, 0.005, 1.6, tmp_path)
    assert abs(dc) < 0.03 and abs(dl) < 0.03
    if U < 0.5:
        assert n >= 1 and first > 0.03
