"""Max-z and run-up gauges (`shoal.probes.MaxZGauge`, `RunupGauge`)."""

import csv
from types import SimpleNamespace

import numpy as np
import pytest

import shoal
from shoal.case import Output
from shoal.cases import still_water_2d
from shoal.errors import InputError
from shoal.geometry import Box, Slope, Tank
from shoal.probes import MaxZGauge, RunupGauge, highest_fluid, make_recorder


def _rows(path):
    rows = list(csv.reader(open(path)))
    return rows[0], np.array([[float(v) for v in r] for r in rows[1:]])


def test_highest_fluid_selects_the_gauge_region():
    """Hand-placed particles: the radius (horizontal distance in 3D, |dx| in 2D), the x range and the
    y band decide which particles count; walls never count; an empty region gives NaN."""
    pos = np.array([[0.0, 0.0, 1.0],    # fluid, at the gauge
                    [0.09, 0.0, 2.0],   # fluid, 0.09 from the gauge in x
                    [0.0, 0.09, 3.0],   # fluid, 0.09 in y (3D: 0.09 horizontal distance; 2D: ignored y)
                    [0.08, 0.08, 4.0],  # fluid, 0.113 horizontally (outside r = 0.1 in 3D, inside in 2D)
                    [0.0, 0.0, 9.0]])   # a wall particle above everything
    kinds = np.array([0, 0, 0, 0, 1])
    g = MaxZGauge(name="g", x=0.0, y=0.0, radius=0.1, interval=1.0)
    assert highest_fluid(pos, kinds, 3, g)[0] == 3.0
    assert highest_fluid(pos, kinds, 2, g)[0] == 4.0
    assert highest_fluid(pos, kinds, 2, g.model_copy(update={"radius": 0.075}))[0] == 3.0  # x = 0.08, 0.09 out
    far = g.model_copy(update={"x": 5.0})
    assert all(np.isnan(highest_fluid(pos, kinds, 3, far)))
    r = RunupGauge(name="r", x0=0.05, x1=0.2, interval=1.0)
    assert highest_fluid(pos, kinds, 3, r) == (4.0, 0.08, 0.08)
    banded = r.model_copy(update={"y": 0.0, "band": 0.1})  # |y| <= 0.05: the particle at y = 0.08 is out
    assert highest_fluid(pos, kinds, 3, banded) == (2.0, 0.09, 0.0)
    assert highest_fluid(pos, kinds, 2, banded) == (4.0, 0.08, 0.08)  # no band in 2D


def test_runup_position_is_the_landward_end_of_the_top_row():
    """Particles level within the tie tolerance: the run-up position is the most landward of them."""
    pos = np.array([[0.1, 0, 1.0], [0.3, 0, 1.0], [0.5, 0, 0.999], [0.7, 0, 0.97], [0.9, 0, 0.5]])
    kinds = np.zeros(5, int)
    r = RunupGauge(name="r", x0=0.0, x1=1.0, interval=1.0)
    assert highest_fluid(pos, kinds, 2, r) == (1.0, 0.3, 0.0)  # no tolerance: the exact ties only
    assert highest_fluid(pos, kinds, 2, r, tie=0.01) == (1.0, 0.5, 0.0)
    assert highest_fluid(pos, kinds, 2, r, tie=0.05) == (1.0, 0.7, 0.0)
    assert highest_fluid(pos, kinds, 2, r.model_copy(update={"landward": "-x"}), tie=0.05) == (1.0, 0.1, 0.0)


def test_gauge_specs_are_validated_and_round_trip(tmp_path):
    with pytest.raises(ValueError, match="x1"):
        RunupGauge(name="r", x0=1.0, x1=0.5, interval=0.1)
    with pytest.raises(ValueError):
        MaxZGauge(name="m", x=0.0, radius=0.0, interval=0.1)
    case = still_water_2d(dp=0.04, depth=0.4, length=0.8).model_copy(update={"probes": [
        MaxZGauge(name="m", x=0.4, radius=0.05, interval=0.01),
        RunupGauge(name="r", x0=0.1, x1=0.7, y=0.0, band=0.2, interval=0.01)]})
    shoal.write_case(case, tmp_path / "c.toml")
    assert shoal.load_case(tmp_path / "c.toml").probes == case.probes
    text = (tmp_path / "c.toml").read_text().replace("x1 = 0.7", "x1 = 0.05")
    (tmp_path / "bad.toml").write_text(text)
    with pytest.raises(InputError, match="x1"):
        shoal.load_case(tmp_path / "bad.toml")


def test_maxz_in_a_still_water_tank_reads_the_still_water_level(tmp_path):
    """Real run (2D tank, H = 0.4 m, dp = 0.04 m, 0.1 s): the highest particle centre under the gauge
    is the top lattice row, dp/2 below the still-water level H, and stays there (the hydrostatic
    start does not settle by more than a small fraction of dp). We assert |zmax - (H - dp/2)| < dp/10,
    hence |zmax - H| < dp."""
    H, dp = 0.4, 0.04
    case = still_water_2d(dp=dp, depth=H, length=0.8, end_time=0.1).model_copy(update={"probes": [
        MaxZGauge(name="mid", x=0.4, radius=dp, interval=0.02),
        RunupGauge(name="tank", x0=0.0, x1=0.8, interval=0.02)]})
    shoal.run_case(case, tmp_path / "run", plot=False)
    head, data = _rows(tmp_path / "run" / "maxz_mid.csv")
    assert head == ["time", "zmax"]
    np.testing.assert_allclose(data[:, 0], [0, 0.02, 0.04, 0.06, 0.08, 0.1], atol=1e-9)
    assert np.all(np.abs(data[:, 1] - (H - dp / 2)) < dp / 10), data
    head, data = _rows(tmp_path / "run" / "runup_tank.csv")
    assert head == ["time", "zmax", "x", "y"] and len(data) == 6
    assert np.all(np.abs(data[:, 1] - (H - dp / 2)) < dp / 10), data
    assert np.all(np.abs(data[:, 2] - (0.8 - dp / 2)) < dp / 10), data  # the top row's end at the +x wall


def _beach_case(end_time, dp=0.02, H=0.2, x0=0.5, gradient=0.5, probes=()):
    return shoal.Case(name="beach", dim=2, dp=dp, end_time=end_time,
                      fluid=shoal.Fluid(depth=H, surface_level=H),
                      solids=[shoal.Solid(name="beach", shape=Slope(x0=x0, z0=0.0, gradient=gradient)),
                              shoal.Solid(name="tank", shape=Tank(lo=(0, 0, 0), hi=(1.0, 0, 1.5 * H)))],
                      fluids=[shoal.FluidRegion(shape=Box(lo=(0, 0, 0), hi=(1.0, 0, H)))],
                      probes=list(probes), output=Output(interval=end_time))


def test_runup_on_a_sloping_beach_in_still_water_is_the_still_water_level(tmp_path):
    """Real run (2D, a 1:2 beach from x = 0.5 m, still water H = 0.2 m, dp = 0.02 m, 0.1 s): the run-up
    over the beach (x from its toe to beyond the shoreline at x_s = 0.9 m) is the top particle row, dp/2
    under H: |zmax - (H - dp/2)| < dp/10, so within dp of the still-water level. Its position is the
    landward end of that row: the bed reaches the row's height dp/2 below H at x_s - (dp/2)/gradient
    = 0.88 m, and the last lattice node before it is less than dp seaward (a dp/10 allowance for the
    particles' motion). A range wholly above the shoreline is dry (NaN)."""
    H, dp, gradient = 0.2, 0.02, 0.5
    x_row = 0.9 - 0.5 * dp / gradient
    case = _beach_case(0.1, dp=dp, H=H, probes=[RunupGauge(name="beach", x0=0.5, x1=1.0, interval=0.02),
                                                RunupGauge(name="dry", x0=0.95, x1=1.0, interval=0.05)])
    shoal.run_case(case, tmp_path / "run", plot=False)
    _, data = _rows(tmp_path / "run" / "runup_beach.csv")
    assert len(data) == 6
    assert np.all(np.abs(data[:, 1] - (H - dp / 2)) < dp / 10), data
    assert np.all((data[:, 2] > x_row - dp - dp / 10) & (data[:, 2] <= x_row + dp / 10)), data
    _, dry = _rows(tmp_path / "run" / "runup_dry.csv")
    assert np.all(np.isnan(dry[:, 1:]))


def test_maxz_recorder_runs_offline(tmp_path):
    """The recorder only needs host positions and kinds, so it also runs over saved snapshots."""
    from shoal.probes.offline import run_probes_offline

    case = still_water_2d(dp=0.04, depth=0.4, length=0.8, end_time=0.02, output_interval=0.01)
    shoal.run_case(case, tmp_path / "run", plot=False)
    recs = run_probes_offline(tmp_path / "run", [MaxZGauge(name="m", x=0.4, radius=0.04, interval=0.01)])
    assert [r[0] for r in recs[0].rows] == pytest.approx([0.0, 0.01, 0.02])
    assert np.all(np.abs(np.array(recs[0].rows)[:, 1] - 0.38) < 0.004)
    assert (tmp_path / "run" / "offline" / "maxz_m.csv").is_file()


def test_make_recorder_dispatches_the_new_gauges(tmp_path):
    from shoal.model import Model

    # the recorder asks the model (Model.highest_fluid), which reads its particles' positions and kinds
    model = SimpleNamespace(dim=2, owned_particles=lambda: (np.array([[0.5, 0.0, 0.3]]), np.array([0]), np.array([0])),
                            reduce=lambda value, op: value, gather=lambda value: [value])  # one process's hooks
    model.highest_fluid = lambda spec, tie: Model.highest_fluid(model, spec, tie)
    rec = make_recorder(RunupGauge(name="r", x0=0.0, x1=1.0, interval=0.1), tmp_path, 0.01, model)
    rec(SimpleNamespace(time=0.25, model=model))
    rec.close()
    assert (tmp_path / "runup_r.csv").read_text().splitlines() == ["time,zmax,x,y", "0.25,0.3,0.5,0"]


def _column(x, n, dp, z0=0.0, y=0.0):
    """n particles stacked at x from z0 + dp/2 (a water layer n dp thick over a bed at z0)."""
    return [[x, y, z0 + (k + 0.5) * dp] for k in range(n)]


def test_shoreline_follows_the_wet_tongue_not_a_film_or_a_splash():
    """Hand-placed particles (2D, dp = 0.01, columns from x0 = 0): a layer 3 particles thick over
    columns 0-4 on a bed rising 0.01 per column, 1 particle over columns 5-6 (a film), nothing over
    7-8 and a splash 4 particles high over column 9. With min_depth = 2 dp the shoreline is column 4
    (bed 0.04 m: zmax = its lowest particle centre - dp/2), with min_depth = dp it is column 6 (the
    film counts), never the splash; landward = "-x" reads the same range from the other end (the
    splash's own column, the first wet one from that side, then its run ends); a film-only range is
    dry (NaN)."""
    from shoal.probes import shoreline, shoreline_columns

    dp = 0.01
    pts = []
    for c in range(5):
        pts += _column((c + 0.5) * dp, 3, dp, z0=c * dp)
    for c in (5, 6):
        pts += _column((c + 0.5) * dp, 1, dp, z0=c * dp)
    pts += _column(9.5 * dp, 4, dp, z0=0.3)
    pos = np.array(pts)
    kinds = np.zeros(len(pos), int)
    kinds[-1] = 1  # a wall particle never counts
    g = RunupGauge(name="r", x0=0.0, x1=0.1, interval=0.1, min_depth=2 * dp)

    def read(spec):
        cols = shoreline_columns(pos, kinds, 2, spec, dp, (0.0, 0.0))
        return shoreline(*cols, 2, spec, dp, (0.0, 0.0))

    z, x, y = read(g)
    assert z == pytest.approx(0.04) and x == pytest.approx(0.045) and y == 0.0
    z, x, _ = read(g.model_copy(update={"min_depth": dp}))
    assert z == pytest.approx(0.06) and x == pytest.approx(0.065)
    z, x, _ = read(g.model_copy(update={"landward": "-x"}))
    assert z == pytest.approx(0.3) and x == pytest.approx(0.095)
    assert all(np.isnan(read(g.model_copy(update={"x0": 0.05, "x1": 0.09}))))
    # bridging dry stretches: 2 dry columns (7, 8) lie between the film and the splash
    z, x, _ = read(g.model_copy(update={"min_depth": dp, "max_gap": 1.5 * dp}))
    assert z == pytest.approx(0.06)  # one dry column bridged: not enough
    z, x, _ = read(g.model_copy(update={"min_depth": dp, "max_gap": 2 * dp}))
    assert z == pytest.approx(0.3) and x == pytest.approx(0.095)  # two: the splash joins the run
    with pytest.raises(ValueError, match="max_gap"):
        RunupGauge(name="r", x0=0.0, x1=0.1, interval=0.1, max_gap=dp)


def test_shoreline_in_3d_is_the_highest_over_the_rows():
    """Two rows of columns in y (dp = 0.01, band 0.02 around y = 0.01): the tongue reaches column 2 in
    the first row and column 4 in the second; the gauge reads the second row's shoreline and its y."""
    from shoal.probes import shoreline, shoreline_columns

    dp = 0.01
    pts = []
    for c in range(3):
        pts += _column((c + 0.5) * dp, 2, dp, z0=c * dp, y=0.005)
    for c in range(5):
        pts += _column((c + 0.5) * dp, 2, dp, z0=c * dp, y=0.015)
    pos = np.array(pts)
    g = RunupGauge(name="r", x0=0.0, x1=0.1, y=0.01, band=0.02, interval=0.1, min_depth=1.5 * dp)
    ylim = (0.0, 0.02)
    cols = shoreline_columns(pos, np.zeros(len(pos), int), 3, g, dp, ylim)
    z, x, y = shoreline(*cols, 3, g, dp, ylim)
    assert z == pytest.approx(0.04) and x == pytest.approx(0.045) and y == pytest.approx(0.015)


def test_shoreline_on_a_beach_in_still_water(tmp_path):
    """Real run (the 1:2 beach of `test_runup_on_a_sloping_beach_in_still_water_is_the_still_water_level`,
    H = 0.2 m, dp = 0.02 m, 0.1 s) with min_depth = 2 dp: the shoreline is where the still water is
    2 dp deep, the bed at H - 2 dp; the gauge reads the bed under the last column holding 2 particles,
    which the lattice puts within one column (dp wide, gradient dp = 0.01 m high) of it, so zmax lies in
    [H - 2 dp - gradient dp - dp/2, H - 2 dp + dp/2] (the dp/2: the bed estimated from the lowest
    particle centre on a stair-stepped bed), at every sample."""
    H, dp, gradient = 0.2, 0.02, 0.5
    case = _beach_case(0.1, dp=dp, H=H, probes=[RunupGauge(name="wet", x0=0.5, x1=1.0, interval=0.02,
                                                           min_depth=2 * dp)])
    shoal.run_case(case, tmp_path / "run", plot=False)
    _, data = _rows(tmp_path / "run" / "runup_wet.csv")
    assert len(data) == 6
    lo, hi = H - 2 * dp - gradient * dp - dp / 2, H - 2 * dp + dp / 2
    assert np.all((data[:, 1] >= lo) & (data[:, 1] <= hi)), (data, lo, hi)
    shore = 0.5 + (H - 2 * dp) / gradient  # where the still water is 2 dp deep
    assert np.all(np.abs(data[:, 2] - shore) <= 2 * dp), data
