"""Mean-flow analysis against analytic fields."""

import numpy as np
import pytest
import xarray as xr

from shoal.analysis import depth_average, mse, period_average, rmse, set_up, vorticity
from shoal.errors import InputError


def test_period_average_of_a_wave_is_its_mean():
    T = 1.5
    t = np.linspace(0, 10, 2001)
    eta = 0.02 + 0.1 * np.sin(2 * np.pi * t / T + 0.3) + 0.03 * np.sin(4 * np.pi * t / T)
    da = xr.DataArray(eta, coords={"time": t}, dims="time")
    for start in (1.0, 3.3):
        assert float(period_average(da, T, start, n_periods=2)) == pytest.approx(0.02, abs=1e-5)
    assert set_up(eta, t, T, 2.0, still_water_level=0.0) == pytest.approx(0.02, abs=1e-5)
    with pytest.raises(InputError, match="window"):
        period_average(da, T, 9.0, n_periods=2)


def test_depth_average_over_the_wet_nodes():
    """u = a z on the wet nodes (kernel sum >= 1/2 below a surface varying in x): the depth average is
    a times the mean wet node height and the flux is a sum(z) dz."""
    x = np.linspace(0, 1, 6)
    y = np.linspace(0, 0.5, 3)
    z = np.linspace(0.01, 0.39, 20)
    dz = z[1] - z[0]
    surf = 0.2 + 0.1 * x  # (x,)
    Z, Y, X = np.meshgrid(z, y, x, indexing="ij")
    wet = Z <= (0.2 + 0.1 * X)
    a = 2.0
    u = np.where(wet, a * Z, np.nan)
    ks = np.where(wet, 1.0, 0.0)
    ds = xr.Dataset({"u": (("z", "y", "x"), u), "v": (("z", "y", "x"), np.zeros_like(u)),
                     "kernel_sum": (("z", "y", "x"), ks)}, coords={"z": z, "y": y, "x": x})
    out = depth_average(ds)
    for i, xi in enumerate(x):
        zw = z[z <= surf[i]]
        assert float(out["depth"].isel(y=0, x=i)) == pytest.approx(len(zw) * dz)
        assert float(out["u"].isel(y=1, x=i)) == pytest.approx(a * zw.mean())
        assert float(out["u_flux"].isel(y=2, x=i)) == pytest.approx(a * zw.sum() * dz)


def test_vorticity_of_a_solid_rotation_and_a_shear():
    x = np.linspace(-1, 1, 21)
    y = np.linspace(-1, 1, 11)
    Y, X = np.meshgrid(y, x, indexing="ij")
    w = 0.3
    # solid-body rotation U = -w y, V = w x: Omega = 2 w everywhere (exact for centred differences)
    np.testing.assert_allclose(vorticity(-w * Y, w * X, x, y), 2 * w, atol=1e-12)
    # a shear U = s y: Omega = -s
    np.testing.assert_allclose(vorticity(0.5 * Y, 0 * X, x, y), -0.5, atol=1e-12)


def test_error_measures():
    assert rmse([1, 2, 3], [1, 2, 5]) == pytest.approx(np.sqrt(4 / 3))
    assert mse([1, 2, np.nan], [1, 4, 0]) == pytest.approx(2.0)
