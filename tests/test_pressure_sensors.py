"""Pressure sensors on walls (`shoal.probes.PressureSensors`, `shoal.probes.pressure_sensors`)."""

import csv

import numpy as np
import pytest

import shoal
from shoal.cases import still_water_2d, still_water_3d
from shoal.errors import InputError
from shoal.options import SPHOptions
from shoal.probes import PressureSensors
from shoal.probes.pressure_sensors import fit_pressure, sensor_points
from shoal.runner import build_model

RHO0, G = 1000.0, 9.81


def _tank(dim, precision="float64"):
    o = SPHOptions(precision=precision)
    if dim == 2:
        return still_water_2d(dp=0.02, depth=0.4, length=0.8, options=o)
    return still_water_3d(dp=0.03, depth=0.3, length=0.3, width=0.3, options=o)


def _pressures(m, pts, method):
    return fit_pressure(m.sensor_moments(pts), m.dim, m.h, m.rho0, m.gravity, method)


@pytest.mark.parametrize("dim", [2, 3])
def test_sensors_on_the_walls_of_still_water_read_the_hydrostatic_pressure(dim):
    """The still-water tank starts with the hydrostatic density, a pressure linear in z: on the bed
    (half the kernel support empty) and on a side wall, the linear fit and the hydrostatic Shepard
    average read rho0 g (H - z) to round-off (float64); the plain Shepard average on the bed reads low
    by rho0 g times the height of the fluid's centroid in the support (3 % in 2D, 8 % in 3D here),
    which is what the fit removes."""
    case = _tank(dim)
    H = case.fluid.depth
    m = build_model(case)
    m.sort()
    c = 0.4 if dim == 2 else 0.15
    y = 0.0 if dim == 2 else 0.15
    pts = np.array([[c, y, 0.0], [c + 0.05, y, 0.0], [0.0, y, 0.1], [0.0, y, 0.2]])
    exact = RHO0 * G * (H - pts[:, 2])
    for method in ("linear", "hydrostatic"):
        np.testing.assert_allclose(_pressures(m, pts, method), exact, rtol=1e-9)
    shepard = _pressures(m, pts, "shepard")
    assert np.all(shepard[:2] < (1 - 0.02) * exact[:2])


def test_the_linear_fit_is_exact_for_a_pressure_gradient_along_the_wall_and_across_it():
    """A pressure field p = p0 + a x + b z (the fluid decelerating against the wall x = 0, say) set
    through the densities: the linear fit reads it exactly at the wall x = 0 and on the bed, the
    hydrostatic Shepard average does not (it knows gravity's gradient only)."""
    case = _tank(2)
    m = build_model(case)
    p0, a, b = 5000.0, -20000.0, -RHO0 * G
    pos = m.host(m.pos)
    p = p0 + a * pos[:, 0] + b * pos[:, 1]  # 2D stores (x, z)
    rho = m.rho0 * (1 + p / m.B) ** (1 / 7)
    fluid = m.host(m.kind) == 0
    m.rho[fluid] = rho[fluid].astype(m.dtype)
    m.sort()
    pts = np.array([[0.0, 0.0, 0.1], [0.0, 0.0, 0.25], [0.3, 0.0, 0.0]])
    exact = p0 + a * pts[:, 0] + b * pts[:, 2]
    np.testing.assert_allclose(_pressures(m, pts, "linear"), exact, rtol=1e-9)
    hydro = _pressures(m, pts, "hydrostatic")
    assert abs(hydro[0] - exact[0]) > 0.05 * abs(a) * m.h  # off by the x-gradient times the centroid's offset


@pytest.mark.parametrize("dim", [2, 3])
def test_a_sensor_with_a_normal_sees_only_the_fluid_in_front_of_its_face(dim):
    """With the wall's normal n, a sensor at x_s counts only the fluid particles in front of the wall's
    plane through it or less than half a spacing behind it, (x_j - x_s) . n >= -dp/2 (a transducer sees
    nothing behind its face: water over the wall's edge, or beyond a thin wall). Inside the water at rest,
    a quarter spacing off a lattice column (no particle within dp/4 of the cut): the kernel sum equals the
    Wendland sum sum_j m / rho_j W(|x_s - x_j|, h) over those particles computed here, which leaves out
    a part of the support, and each side's hydrostatic average still reads rho0 g (H - z)."""
    from shoal.physics.spec import kernel_normalisation

    case = _tank(dim)
    H, dp = case.fluid.depth, case.dp
    m = build_model(case)
    m.sort()
    y = 0.0 if dim == 2 else 0.15
    x = (20.25 if dim == 2 else 5.25) * dp
    pts = np.array([[x, y, 0.1], [x, y, 0.15]])
    full = m.sensor_moments(pts)
    pos = m.host(m.pos).astype(np.float64)
    fluid = m.host(m.kind) == 0
    world = pos if dim == 3 else np.column_stack([pos[:, 0], np.zeros(len(pos)), pos[:, 1]])
    vol = m.mass / m.host(m.rho).astype(np.float64)
    assert case.options.kernel == "wendland"
    aw = kernel_normalisation(m.spec.kernel, dim, m.h)
    for sign in (1.0, -2.0):
        normal = np.array([sign, 0.0, 0.0])
        mom = m.sensor_moments(pts, np.array([normal] * 2))
        for k, pt in enumerate(pts):
            q = np.linalg.norm(world - pt, axis=1) / m.h
            front = fluid & ((world - pt) @ normal / abs(sign) >= -0.5 * dp)
            t = np.clip(1 - 0.5 * q, 0, None)
            expected = np.sum(vol[front] * aw * t[front]**4 * (2 * q[front] + 1))
            assert mom[k, 0] == pytest.approx(expected, rel=1e-9)
            assert mom[k, 0] < 0.9 * full[k, 0]  # the cut leaves out a part of the support
        np.testing.assert_allclose(fit_pressure(mom, dim, m.h, m.rho0, m.gravity), RHO0 * G * (H - pts[:, 2]),
                                   rtol=1e-9)


def test_a_dry_sensor_reads_zero_and_a_thin_sheet_falls_back_to_the_hydrostatic_average():
    """No fluid within 2h, or a kernel sum below `kernel_sum_min`: 0 Pa (gauge pressure). One row of particles: the moment matrix is singular
    across the row, so the fit falls back to the hydrostatic Shepard average (finite, not a blow-up)."""
    s = 0.5
    dry = fit_pressure(np.zeros((1, 9)), 2, 0.01, RHO0, (0, 0, -G))
    assert dry[0] == 0.0
    # a row of particles along x at z = s h above the point, all at pressure 100 Pa
    x = np.linspace(-1.5, 1.5, 7)
    w = np.exp(-x**2)
    e = np.column_stack([x, np.full_like(x, s)])
    mom = [w.sum(), *(w @ e), (w * x * x).sum(), (w * x * s).sum(), (w * s * s).sum(), 100 * w.sum(),
           *(100 * w @ e)]
    p = fit_pressure(np.array([mom]), 2, 0.01, RHO0, (0, 0, -G), kernel_sum_min=0.0)
    assert p[0] == pytest.approx(100 + RHO0 * G * s * 0.01)
    assert w.sum() > 1  # the same moments with a kernel sum below the threshold: dry
    assert fit_pressure(np.array([mom]), 2, 0.01, RHO0, (0, 0, -G), kernel_sum_min=1.01 * w.sum())[0] == 0.0


def test_a_sensor_beyond_the_water_reads_dry():
    """The 2D dam break at t = 0: on the bed under the column the fit reads rho0 g 2a; a spacing and
    more beyond the column's face (kernel sum below 0.1) it reads 0, where the fit alone would carry
    the column's pressure out to the dry bed."""
    from shoal.cases import dam_break_2d

    case = dam_break_2d(dp=0.01, options=SPHOptions(precision="float64"))
    a, dp = case.parameters["a"], case.dp
    m = build_model(case)
    m.sort()
    pts = np.array([[0.5 * a, 0, 0.0], [a + 1.2 * dp, 0, 0.0], [a + 2 * dp, 0, 0.0]])
    p = _pressures(m, pts, "linear")
    assert p[0] == pytest.approx(RHO0 * G * 2 * a, rel=1e-6)
    assert p[1] == p[2] == 0.0
    mom = m.sensor_moments(pts)
    assert fit_pressure(mom, 2, m.h, m.rho0, m.gravity, kernel_sum_min=0.0)[1] > 0.5 * RHO0 * G * 2 * a


def test_sensor_area_points():
    """A disc of diameter D perpendicular to the normal (3D) or a segment along the wall (2D), centred
    on the sensor, spacing at most dp/4; diameter 0 is the point itself."""
    c = np.array([1.0, 0.5, 0.2])
    assert np.array_equal(sensor_points(c, None, 0.0, 0.01, 3), c[None])
    pts = sensor_points(c, (-2.0, 0.0, 0.0), 0.02, 0.01, 3)
    assert np.allclose(pts[:, 0], 1.0)                       # on the wall plane x = 1
    assert np.max(np.linalg.norm(pts - c, axis=1)) <= 0.01 + 1e-12
    assert np.allclose(pts.mean(axis=0), c)
    assert len(pts) > 40                                      # spacing <= dp/4 over a disc of 2 dp
    seg = sensor_points(c, (0.0, 0.0, 1.0), 0.02, 0.01, 2)
    assert np.allclose(seg[:, 2], 0.2) and np.allclose(seg[:, 1], 0.5)
    assert seg[:, 0].min() == pytest.approx(0.99) and seg[:, 0].max() == pytest.approx(1.01)


def test_case_file_errors_are_one_line():
    with pytest.raises(ValueError, match="normal"):
        PressureSensors(name="p", points=[[0, 0, 0]], interval=0.01, diameter=0.01)
    with pytest.raises(ValueError, match="no direction"):
        PressureSensors(name="p", points=[[0, 0, 0]], interval=0.01, normal=[0, 0, 0])
    with pytest.raises(ValueError):
        PressureSensors(name="p", points=[[0, 0, 0]], interval=0.01, method="kriging")


def test_a_sensor_outside_the_domain_is_refused_by_check():
    from shoal.check import check_probes

    case = _tank(2)
    case = case.model_copy(update={"probes": [PressureSensors(name="p", points=[[5.0, 0, 0]], interval=0.1)]})
    with pytest.raises(InputError, match="outside the domain"):
        check_probes(case, 10)


@pytest.mark.parametrize("dim", [2, 3])
def test_sensors_in_a_run_settle_on_the_hydrostatic_pressure(tmp_path, dim):
    """A short run of the still-water tank (float32, the default) with sensors on the bed and on a
    side wall, one of them of finite diameter: once the column's acoustic mode (period 4 H / c0 =
    0.04 s, excited by the start) has decayed (t >= 0.2 s), every sample lies within 2 % of rho0 g H
    of the hydrostatic pressure rho0 g (H - z), and so does the record's mean; the CSV has one column
    per sensor.

    Why 2 % and not less: the scheme's own water column at rest settles above the hydrostatic pressure
    (measured with these sensors: +1.2 to +1.3 % of rho0 g H on the bed and +0.87 % at z = H/4 in 2D, at
    H/dp = 20 and 40, with dynamic and Adami walls, in tanks 2 and 8 depths long; +0.9 % on the bed in
    3D; +0.6 % in 2D with coef_h = 1.5), a property of the scheme that issue 28 is to remove, not of the
    sensor: the sensor reads what the fluid holds, and its exact readings are tested at t = 0 above."""
    case = _tank(dim, "float32")
    H = case.fluid.depth
    y = 0.0 if dim == 2 else 0.15
    c = 0.4 if dim == 2 else 0.15
    pts = [[c, y, 0.0], [0.0, y, 0.1]]
    sensors = [PressureSensors(name="bed", points=pts, interval=0.01),
               PressureSensors(name="disc", points=[pts[0]], interval=0.01, normal=[0, 0, 1], diameter=0.05)]
    case = case.model_copy(update={"probes": sensors, "end_time": 0.3})
    shoal.run_case(case, tmp_path, progress=False, plot=False, overwrite=True)
    for name, zs in (("bed", [0.0, 0.1]), ("disc", [0.0])):
        rows = list(csv.reader(open(tmp_path / f"pressure_{name}.csv")))
        assert rows[0] == ["time"] + [f"p_{k}" for k in range(len(zs))]
        data = np.array([[float(v) for v in r] for r in rows[1:]])
        assert len(data) == 31
        exact = RHO0 * G * (H - np.array(zs))
        settled = data[data[:, 0] >= 0.2 - 1e-9, 1:]
        err = np.max(np.abs(settled - exact)) / (RHO0 * G * H)
        assert err < 0.02, (name, err)
        mean_err = np.max(np.abs(data[:, 1:].mean(axis=0) - exact)) / (RHO0 * G * H)
        assert mean_err < 0.02, (name, mean_err)


@pytest.mark.parametrize("bed", ["flat", "slope"])
def test_still_water_touches_its_bed_and_presses_on_it(bed):
    """Issue 28, item 1, on a flat bed and a 1:10 slope (2D, H/dp = 10, default options, dynamic walls):
    after 0.5 s at rest the water's lowest layer stays within 0.6 dp of the wall surface (the lattice
    puts it at 0.5 dp; over a slope the stair-steps put each spacing-wide bin's closest particle
    between 0 and 1 dp, 0.5 dp on average; measured 0.50 for both, `benchmarks/wall_gap.py`) and the
    bed sensors read rho0 g d within 2 % of rho0 g H (measured +1.25 % on the flat bed, +0.1 to
    +0.8 % on the slope: the scheme's steeper hydrostatic gradient, see
    `test_sensors_in_a_run_settle_on_the_hydrostatic_pressure`)."""
    import importlib.util
    from pathlib import Path

    spec = importlib.util.spec_from_file_location(
        "wall_gap", Path(__file__).resolve().parents[1] / "benchmarks" / "wall_gap.py")
    wall_gap = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(wall_gap)
    r = wall_gap.measure(bed, 0.02, 0.2, 0.5, "dynamic")
    assert r["gap"] <= 0.6, r
    assert r["gap_min"] >= 0.0, r  # no particle inside the wall
    assert np.max(np.abs(r["pressure_err"])) < 2.0, r
