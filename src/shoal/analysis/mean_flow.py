"""Mean-flow analysis of the rip-current paper: period and depth averaging,
set-up, vorticity of the mean current, and error measures.

These work on what the probes write: a test-point grid as an xarray
Dataset (`shoal.probes.TestPoints`, dims time, z, y, x; variables u, v, w,
p, rho, kernel_sum) and gauge time series.

* Period average over n whole wave periods from `start`:
  <A> = (1 / nT) int_start^{start+nT} A dt  (trapezoidal in time).
* Depth average between the bed and the free surface, the wet nodes being
  those with kernel sum >= 1/2 (the probes' water criterion):
  U = (1/h) int u dz over the wet nodes, h their total height; the depth
  integral (volume flux per unit width) is q = U h.
* Set-up: the period-averaged water level minus the still-water level.
* Vertical vorticity of the mean current (paper: Omega = v_x - u_y):
  Omega = dV/dx - dU/dy (centred differences on the grid).
* Errors: RMSE, MSE and mean relative error, as both papers report.
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError


def period_average(ds, period, start, n_periods=1):
    """Average of a Dataset (or DataArray) with a `time` coordinate over
    [start, start + n_periods * period] (trapezoidal rule on the samples).

    Raises InputError when the samples do not cover the window.
    """
    t = np.asarray(ds["time"].values, float)
    t1 = start + n_periods * period
    if t.size < 2 or t[0] > start + 1e-9 or t[-1] < t1 - 1e-9:
        raise InputError(f"the samples cover t = [{t[0]:.4g}, {t[-1]:.4g}] s, not the averaging window "
                         f"[{start:.4g}, {t1:.4g}] s")
    w = ds.sel(time=slice(start - 1e-9, t1 + 1e-9))
    tw = np.asarray(w["time"].values, float)
    if tw.size < 2:
        raise InputError("fewer than two samples in the averaging window; sample more often")
    return w.integrate("time") / (tw[-1] - tw[0])


def depth_average(ds, variables=("u", "v"), wet_threshold=0.5):
    """Depth average and depth integral over the wet nodes of each (y, x) column.

    Returns a Dataset with, for each variable V, `V` (depth average) and
    `V_flux` (depth integral, m^2/s for a velocity), and `depth` (height of
    the wet nodes, uniform z spacing assumed, each node standing for dz).
    """
    if "kernel_sum" not in ds:
        raise InputError("depth averaging needs the test points' kernel_sum (the water criterion)")
    z = np.asarray(ds["z"].values, float)
    if z.size < 2:
        raise InputError("depth averaging needs at least two z levels")
    dz = float(np.mean(np.diff(z)))
    wet = ds["kernel_sum"] >= wet_threshold
    depth = wet.sum("z") * dz
    out = {"depth": depth}
    for v in variables:
        flux = ds[v].where(wet, 0.0).sum("z") * dz
        out[f"{v}_flux"] = flux
        out[v] = flux / depth.where(depth > 0)
    import xarray as xr

    return xr.Dataset(out)


def set_up(levels, times, period, start, still_water_level, n_periods=1):
    """Period-mean water level minus the still-water level [m] from a gauge series."""
    import xarray as xr

    da = xr.DataArray(np.asarray(levels, float), coords={"time": np.asarray(times, float)}, dims="time")
    return float(period_average(da, period, start, n_periods)) - float(still_water_level)


def vorticity(U, V, x, y):
    """Omega = dV/dx - dU/dy [1/s] of a horizontal field U(y, x), V(y, x) on a grid."""
    U = np.asarray(U, float)
    V = np.asarray(V, float)
    return np.gradient(V, np.asarray(x, float), axis=-1) - np.gradient(U, np.asarray(y, float), axis=-2)


def rmse(sim, ref):
    """Root-mean-square error sqrt(mean((sim - ref)^2)), NaNs ignored."""
    d = np.asarray(sim, float) - np.asarray(ref, float)
    return float(np.sqrt(np.nanmean(d * d)))


def mse(sim, ref):
    """Mean-square error mean((sim - ref)^2), NaNs ignored (the rip-current paper's measure)."""
    d = np.asarray(sim, float) - np.asarray(ref, float)
    return float(np.nanmean(d * d))
