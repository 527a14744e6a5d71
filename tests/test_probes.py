"""Probes and wave gauges: SPH interpolation at fixed points (rip-current paper, Eq. 11)."""

import csv

import numpy as np
import pytest

import shoal
from shoal.cases import still_water_2d, still_water_3d
from shoal.probes import PointProbes, WaveGauge, surface_level
from shoal.runner import build_model

G = 9.81


def _ready(case):
    m = build_model(case)
    m.sort()
    return m


@pytest.mark.parametrize("dim", [2, 3])
def test_probe_pressure_is_hydrostatic_at_rest(dim):
    """Fluid starts with the hydrostatic density: interpolated pressure = rho0 g (H - z) within
    0.5 % of rho0 g H away from walls and surface (Shepard interpolation of a linear field)."""
    H = 0.4
    case = still_water_2d(dp=0.02, depth=H, length=0.8) if dim == 2 else still_water_3d(dp=0.03, depth=0.3,
                                                                                           length=0.3, width=0.3)
    H = case.fluid.depth
    m = _ready(case)
    zs = np.linspace(0.25 * H, 0.75 * H, 5)
    pts = np.column_stack([np.full(5, 0.15 if dim == 3 else 0.4), np.full(5, 0.15 if dim == 3 else 0.0), zs])
    r = m.sample(pts)
    err = np.max(np.abs(r["pressure"] - 1000 * G * (H - zs))) / (1000 * G * H)
    assert err < 0.005, err
    np.testing.assert_allclose(r["kernel_sum"], 1.0, atol=0.01)  # inside the fluid the kernel sum is 1
    assert np.all(np.abs(r["velocity"]) == 0)


def test_shepard_removes_the_free_surface_bias_of_the_plain_sum():
    """At the free surface the kernel sum is about 1/2: the plain interpolation of the density
    is about half of rho0 there, the Shepard one stays at rho0."""
    case = still_water_2d(dp=0.02, depth=0.4, length=0.8)
    m = _ready(case)
    pts = np.array([[0.4, 0.0, 0.4]])  # on the surface
    plain, shep = m.sample(pts, shepard=False), m.sample(pts)
    assert 0.4 < plain["kernel_sum"][0] < 0.6
    assert plain["density"][0] == pytest.approx(1000.0 * plain["kernel_sum"][0], rel=1e-3)
    assert shep["density"][0] == pytest.approx(1000.0, rel=1e-3)


def test_linear_velocity_field_is_interpolated():
    case = still_water_2d(dp=0.02, depth=0.4, length=0.8)
    dp = case.dp
    p = case.particles()
    vel = np.zeros_like(p.positions)
    vel[:, 0] = 0.1 + 0.5 * p.positions[:, 0] - 0.3 * p.positions[:, 2]
    vel[p.kinds != 0] = 0
    m = build_model(case)
    m.vel[:, :] = vel[:, [0, 2]].astype(m.dtype)
    m.sort()
    rng = np.random.default_rng(1)
    pts = np.column_stack([rng.uniform(0.2, 0.6, 20), np.zeros(20), rng.uniform(0.1, 0.3, 20)])
    r = m.sample(pts)
    exact = 0.1 + 0.5 * pts[:, 0] - 0.3 * pts[:, 2]
    # Shepard interpolation is exact for constants; for a linear field its error is the kernel's
    # first moment at the point (a fraction of dp) times the gradient
    assert np.max(np.abs(r["velocity"][:, 0] - exact)) < 0.05 * dp * 0.6


@pytest.mark.parametrize("dim", [2, 3])
def test_wave_gauge_reads_the_still_water_level(dim):
    """The kernel-sum threshold S = 1/2 finds the surface of still water within dp/10."""
    case = still_water_2d(dp=0.02, depth=0.4, length=0.8) if dim == 2 else still_water_3d(
        dp=0.03, depth=0.3, length=0.3, width=0.3)
    H, dp = case.fluid.depth, case.dp
    m = _ready(case)
    z = np.linspace(0.5 * H, 1.5 * H, 201)
    x, y = (0.4, 0.0) if dim == 2 else (0.15, 0.15)
    s = m.sample(np.column_stack([np.full_like(z, x), np.full_like(z, y), z]), shepard=False)["kernel_sum"]
    level = surface_level(z, s)
    assert abs(level - H) < 0.1 * dp, (level, H)


def test_surface_level_helper():
    z = np.array([0.0, 1.0, 2.0, 3.0])
    assert surface_level(z, np.array([1.0, 0.9, 0.3, 0.0])) == pytest.approx(1.0 + 0.4 / 0.6)
    assert np.isnan(surface_level(z, np.zeros(4)))
    assert surface_level(z, np.ones(4)) == 3.0


def test_probes_and_gauges_in_a_run_write_csv(tmp_path):
    case = still_water_2d(dp=0.04, depth=0.4, length=0.8, end_time=0.05)
    case = case.model_copy(update={"probes": [
        PointProbes(name="mid", points=[(0.4, 0, 0.1), (0.4, 0, 0.2)], interval=0.01),
        WaveGauge(name="g1", x=0.4, z0=0.2, z1=0.6, interval=0.01)]})
    # the TOML round trip keeps them
    shoal.write_case(case, tmp_path / "c.toml")
    assert shoal.load_case(tmp_path / "c.toml").probes == case.probes
    shoal.run_case(case, tmp_path / "run", plot=False)
    rows = list(csv.reader(open(tmp_path / "run" / "gauge_g1.csv")))
    assert rows[0] == ["time", "level"] and len(rows) == 1 + 6  # t = 0, 0.01, ..., 0.05
    levels = np.array([float(r[1]) for r in rows[1:]])
    assert np.all(np.abs(levels - 0.4) < 0.1 * 0.04)
    rows = list(csv.reader(open(tmp_path / "run" / "probe_mid.csv")))
    assert len(rows[0]) == 1 + 2 * 5 and len(rows) == 7
    p = np.array([[float(r[4]), float(r[9])] for r in rows[1:]])
    np.testing.assert_allclose(p, [[1000 * G * 0.3, 1000 * G * 0.2]] * 6, rtol=0.03)


def test_test_point_grid_and_tracker_in_a_run(tmp_path):
    import xarray as xr

    from shoal.probes import TestPoints, Tracker

    case = still_water_2d(dp=0.04, depth=0.4, length=0.8, end_time=0.04)
    case = case.model_copy(update={"probes": [
        TestPoints(name="tank", lo=(0.2, 0, 0.05), hi=(0.6, 0, 0.35), counts=(5, 1, 4), interval=0.02),
        Tracker(name="t", start=[(0.4, 0, 0.2), (0.1, 0, 0.1)], ids=[3], interval=0.01)]})
    shoal.write_case(case, tmp_path / "c.toml")
    assert shoal.load_case(tmp_path / "c.toml").probes == case.probes
    shoal.run_case(case, tmp_path / "run", plot=False)
    ds = xr.open_dataset(tmp_path / "run" / "testpoints_tank.nc", engine="scipy")
    assert dict(ds.sizes) == {"time": 3, "z": 4, "y": 1, "x": 5}
    assert ds["p"].attrs["units"] == "Pa" and ds["x"].attrs["units"] == "m" and ds["time"].attrs["units"] == "s"
    z = ds["z"].values
    p = ds["p"].isel(time=-1, y=0).values  # (z, x)
    expect = 1000 * G * (0.4 - z)[:, None]
    assert np.max(np.abs(p - expect)) / (1000 * G * 0.4) < 0.03
    rows = list(csv.reader(open(tmp_path / "run" / "track_t.csv")))
    assert len(rows[0]) == 1 + 3 * 3 and len(rows) == 1 + 5
    first = np.array([float(v) for v in rows[1][1:]]).reshape(3, 3)
    # the particles nearest to the start points, and id 3
    assert np.linalg.norm(first[1] - [0.4, 0, 0.2]) < 0.04 and np.linalg.norm(first[2] - [0.1, 0, 0.1]) < 0.04
    np.testing.assert_allclose(first[0], case.particles().positions[3], atol=1e-6)


def test_probes_run_offline_over_snapshots_give_the_run_values(tmp_path):
    """A gauge sampled during the run and the same gauge run offline over the saved snapshots agree
    at the snapshot times (same kernels, same particles; float32 snapshots of float64 positions)."""
    from shoal.probes.offline import run_probes_offline

    case = still_water_2d(dp=0.04, depth=0.4, length=0.8, end_time=0.04, output_interval=0.02)
    gauge = WaveGauge(name="g", x=0.4, z0=0.2, z1=0.6, interval=0.02)
    probe = PointProbes(name="p", points=[(0.4, 0, 0.2)], interval=0.02)
    case = case.model_copy(update={"probes": [gauge, probe]})
    shoal.run_case(case, tmp_path / "run", plot=False)
    recs = run_probes_offline(tmp_path / "run", [gauge, probe])
    online_g = [[float(v) for v in r] for r in list(csv.reader(open(tmp_path / "run" / "gauge_g.csv")))[1:]]
    online_p = [[float(v) for v in r] for r in list(csv.reader(open(tmp_path / "run" / "probe_p.csv")))[1:]]
    assert [r[0] for r in recs[0].rows] == pytest.approx([r[0] for r in online_g])
    np.testing.assert_allclose([r[1] for r in recs[0].rows], [r[1] for r in online_g], atol=1e-4)
    np.testing.assert_allclose(np.array(recs[1].rows)[:, 4], np.array(online_p)[:, 4], rtol=1e-4)  # pressure


def test_probes_offline_over_a_damaged_collection_is_one_input_error(tmp_path):
    """A run directory whose .pvd is cut off: one InputError naming the file (it was a ValueError
    traceback about resuming), and the snapshots are left as they were."""
    from shoal.errors import InputError
    from shoal.probes.offline import run_probes_offline

    case = still_water_2d(dp=0.04, depth=0.4, length=0.8, end_time=0.02, output_interval=0.02)
    shoal.run_case(case, tmp_path / "run", plot=False)
    pvd = next((tmp_path / "run").glob("*.pvd"))
    pvd.write_text(pvd.read_text()[:80])
    before = sorted(p.name for p in (tmp_path / "run").iterdir())
    gauge = WaveGauge(name="g", x=0.4, z0=0.2, z1=0.6, interval=0.02)
    with pytest.raises(InputError, match=f"cannot read the snapshot collection .*{pvd.name}") as info:
        run_probes_offline(tmp_path / "run", [gauge])
    assert "\n" not in str(info.value)
    assert sorted(p.name for p in (tmp_path / "run").iterdir()) == before


def test_only_probes_buried_in_fixed_walls_are_refused():
    """A gauge whose whole column lies in a fixed block, or a probe point inside it, is refused; one
    on the block's face, one whose column rises above the block, and one in a moving block are not
    (the moving block can leave, the others see water)."""
    from shoal.case import Case
    from shoal.errors import InputError
    from shoal.motions import ConstantVelocity
    from shoal.probes import PointProbes, WaveGauge
    from shoal.probes.placement import check_buried_probes

    base = Case.model_validate({
        "name": "t", "dim": 2, "dp": 0.05, "end_time": 0.01, "fluid": {"depth": 0.3, "surface_level": 0.3},
        "solids": [{"name": "tank", "shape": {"type": "tank", "lo": [0, 0, 0], "hi": [1.2, 0, 0.6]}},
                   {"name": "block", "shape": {"type": "box", "lo": [0.6, 0, 0], "hi": [0.9, 0, 0.5]}}],
        "fluids": [{"shape": {"type": "box", "lo": [0, 0, 0], "hi": [0.6, 0, 0.3]}}]})

    def with_probes(*probes, case=base):
        return case.model_copy(update={"probes": list(probes)})

    with pytest.raises(InputError, match=r"probes\[0\] \(gauge 'g'\).*inside solids\[1\] \(block\)"):
        check_buried_probes(with_probes(WaveGauge(name="g", x=0.75, z0=0.05, z1=0.4, interval=0.01)))
    with pytest.raises(InputError, match=r"points\[1\] = \[0.7, 0.0, 0.2\] lies inside solids\[1\]"):
        check_buried_probes(with_probes(PointProbes(name="p", points=[(0.3, 0, 0.1), (0.7, 0, 0.2)], interval=0.01)))
    for ok in (WaveGauge(name="g", x=0.6, z0=0.05, z1=0.4, interval=0.01),  # on the face
               WaveGauge(name="g", x=0.75, z0=0.05, z1=0.55, interval=0.01),  # over the top
               PointProbes(name="p", points=[(0.9, 0, 0.2), (0.75, 0, 0.5)], interval=0.01)):
        check_buried_probes(with_probes(ok))
    moving = base.model_copy(update={
        "motions": [ConstantVelocity(name="m", velocity=(0.0, 0.0, 0.1))],
        "solids": [base.solids[0], base.solids[1].model_copy(update={"motion": "m"})]})
    check_buried_probes(with_probes(WaveGauge(name="g", x=0.75, z0=0.05, z1=0.4, interval=0.01), case=moving))
