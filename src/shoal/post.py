"""``shoal post RUN_DIR``: the standard plots of a finished run, as PNGs.

Each plotting function reads a run directory (what `shoal.run_case`
writes) and writes PNGs (matplotlib's Agg canvas: no display, no pyplot
state) to an output folder, returning the paths written:

* `plot_gauges`: time series of every ``gauge_*.csv``, ``maxz_*.csv``,
  ``runup_*.csv`` and ``probe_*.csv`` (one figure per file, one panel per
  quantity: levels [m], positions [m], velocities [m/s], pressure [Pa],
  density [kg/m^3]);
* `plot_mean_flow`: from each ``testpoints_*.nc`` grid, the period-mean
  current (`mean_flow`): a plan view of the depth-averaged mean-current
  arrows over the bed contours, coloured by the vertical vorticity of the
  mean current (the rip-current paper's Fig. 7/10), the mean water level
  (set-up) in plan (Fig. 8), and vertical profiles of the mean u at a few
  columns (Fig. 11); a 2D grid (ny = 1) gets an x-z section of the mean
  (u, w) instead of the plan views;
* `plot_spectra`: the variance density spectrum of every ``gauge_*.csv``
  (Welch's method, `shoal.analysis.wave_spectrum`) against the target
  spectrum of the case's ``irregular`` or ``focused`` paddle, with Hm0, Tp,
  Tm01 and Tm02 (also written to ``spectra.json``);
* `plot_tracks`: particle trajectories from ``track_*.csv`` (plan view x-y
  in 3D, x-z in 2D; Fig. 12);
* `plot_plane`: the velocity magnitude of the fluid particles within dp of
  a plane (``z=0.05``, ``y=0.15``, ``x=1.0`` or ``mid``) in the last (or a
  chosen) snapshot (the tidal-bore paper's Fig. 9/17/18).

`post` runs the ones asked for, or every one that applies to the files
present. Bad input raises `InputError` (one line; the command line exits
with status 2).
"""

from __future__ import annotations

import csv
import json
import math
import re
import tomllib
from pathlib import Path

import numpy as np

from .errors import InputError
from .output.atomic import replace_file

__all__ = ["post", "plot_gauges", "plot_spectra", "plot_mean_flow", "plot_tracks", "plot_plane", "mean_flow",
           "parse_plane", "surface_levels", "run_info", "spectral_paddle"]

GAUGE_PATTERNS = ("gauge_*.csv", "maxz_*.csv", "runup_*.csv", "probe_*.csv", "flow_*.csv", "force_*.csv",
                  "pressure_*.csv")
_UNITS = {"level": "free-surface elevation [m]", "zmax": "highest fluid particle z [m]",
          "velocity": "velocity [m/s]", "p": "pressure [Pa]", "rho": "density [kg/m$^3$]",
          "position": "position of the highest particle [m]"}


# ------------------------------------------------------------------ the run
def run_info(run_dir):
    """What the plots need to know about a run, from its ``case.toml`` and
    ``resolved.json`` (read as plain data, not validated: a run directory
    of an older or newer shoal still plots).

    Parameters
    ----------
    run_dir : str or os.PathLike
        A run directory.

    Returns
    -------
    dict
        ``dim`` (2, 3 or None), ``dp`` [m] or None, ``surface_level`` [m] or
        None (the still-water level), ``period`` [s] or None (the first
        piston motion's period), ``name`` and ``probes`` (the raw probe
        tables, for legends).

    Raises
    ------
    InputError
        If `run_dir` is not a directory.
    """
    run_dir = Path(run_dir)
    if not run_dir.is_dir():
        raise InputError(f"{str(run_dir)!r} is not a directory (give the output directory of a shoal run)")
    case, resolved = {}, {}
    if (run_dir / "case.toml").is_file():
        try:
            case = tomllib.loads((run_dir / "case.toml").read_text(encoding="utf-8"))
        except (tomllib.TOMLDecodeError, UnicodeDecodeError) as exc:
            raise InputError(f"{run_dir / 'case.toml'}: not a valid case file: {exc}") from None
    if (run_dir / "resolved.json").is_file():
        try:
            resolved = json.loads((run_dir / "resolved.json").read_text(encoding="utf-8"))
        except (json.JSONDecodeError, UnicodeDecodeError):
            resolved = {}
    fluid = case.get("fluid", {}) if isinstance(case.get("fluid"), dict) else {}
    period = None
    for m in case.get("motions", []) or []:
        if isinstance(m, dict) and m.get("type") == "piston" and isinstance(m.get("period"), (int, float)):
            period = float(m["period"])
            break
    surface = fluid.get("surface_level", fluid.get("depth"))
    return {"dim": case.get("dim", resolved.get("dim")), "dp": case.get("dp", resolved.get("dp")),
            "surface_level": float(surface) if isinstance(surface, (int, float)) else None,
            "period": period, "name": case.get("name", resolved.get("name", run_dir.name)),
            "probes": {p.get("name"): p for p in case.get("probes", []) or [] if isinstance(p, dict)}}


def _figure(width, height):
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=(width, height), dpi=120)
    FigureCanvasAgg(fig)
    return fig


def _save(fig, path):
    return replace_file(path, lambda tmp: fig.savefig(tmp, format="png"))


def _read_csv(path):
    """Header and float rows of a probe CSV (an empty file gives no rows)."""
    try:
        with open(path, newline="", encoding="utf-8") as f:
            rows = list(csv.reader(f))
    except UnicodeDecodeError:
        raise InputError(f"{path} is not a probe CSV written by shoal (not UTF-8 text)") from None
    if not rows:
        return [], np.zeros((0, 0))
    try:
        data = np.array([[float(v) for v in r] for r in rows[1:] if r], float)
    except ValueError:
        raise InputError(f"{path}: not a shoal probe file (a non-numeric value)") from None
    if data.size == 0:
        data = np.zeros((0, len(rows[0])))
    if data.shape[1] != len(rows[0]):
        raise InputError(f"{path}: rows have {data.shape[1]} values, the header {len(rows[0])}")
    return rows[0], data


# ------------------------------------------------------------------ gauges
def _groups(kind, header, spec, dim=None):
    """Panels of one probe file: (label, [(column index, legend)])."""
    cols = {name: i for i, name in enumerate(header)}
    if kind == "gauge":
        return [(_UNITS["level"], [(cols["level"], "level")])] if "level" in cols else []
    if kind == "maxz":
        return [(_UNITS["zmax"], [(cols["zmax"], "zmax")])] if "zmax" in cols else []
    if kind == "runup":
        out = []
        if "zmax" in cols:
            out.append(("run-up elevation [m]", [(cols["zmax"], "highest fluid particle z")]))
        pos = [(cols[c], c) for c in ("x", "y") if c in cols and not (c == "y" and dim == 2)]
        if pos:
            out.append((_UNITS["position"], pos))
        return out
    if kind == "force":
        unit = "N/m (per metre of width)" if dim == 2 else "N"
        comps = [(cols[c], c) for c in ("fx", "fy", "fz") if c in cols and not (c == "fy" and dim == 2)]
        return [(f"force on {(spec or {}).get('solid', 'the solid')} [{unit}]", comps)] if comps else []
    if kind == "flow":
        per = " per metre of width" if dim == 2 else ""
        vol, rate = ("m$^2$", "m$^2$/s") if dim == 2 else ("m$^3$", "m$^3$/s")
        out = []
        if "volume" in cols:
            out.append((f"volume passed{per} [{vol}]", [(cols["volume"], "net volume through the section")]))
        rates = [(cols[c], leg) for c, leg in (("rate", "mean since the last sample (count)"),
                                               ("rate_slab", "instantaneous (slab 2 dp)")) if c in cols]
        if rates:
            out.append((f"flow rate{per} [{rate}]", rates))
        if "area_slab" in cols:
            area = "m" if dim == 2 else "m$^2$"
            out.append((f"{'depth (wetted area per metre)' if dim == 2 else 'wetted area'} [{area}]",
                        [(cols["area_slab"], "slab 2 dp")]))
        return out
    points = (spec or {}).get("points") or []
    panels = {"velocity": [], "p": [], "rho": []}
    for name, i in cols.items():
        m = re.fullmatch(r"([uvw]|p|rho)_(\d+)", name)
        if not m:
            continue
        q, k = m.group(1), int(m.group(2))
        where = f" at ({', '.join(f'{c:g}' for c in points[k])})" if k < len(points) else f" point {k}"
        panels["velocity" if q in "uvw" else q].append((i, f"{q}{where}"))
    return [(_UNITS[k], v) for k, v in panels.items() if v]


def plot_gauges(run_dir, out):
    """Time series of the run's gauge, max-z, run-up and point-probe files.

    One PNG per file (``<file stem>.png``), one panel per quantity with its
    unit; the still-water level (from ``case.toml``) is drawn on elevation
    panels. A probe file with no sample yet is skipped.

    Parameters
    ----------
    run_dir : str or os.PathLike
        The run directory holding ``gauge_*.csv``, ``maxz_*.csv``,
        ``runup_*.csv`` and ``probe_*.csv``.
    out : str or os.PathLike
        Folder for the PNGs (created if missing).

    Returns
    -------
    list of pathlib.Path
        The PNGs written.
    """
    run_dir, out = Path(run_dir), Path(out)
    info = run_info(run_dir)
    written = []
    for pattern in GAUGE_PATTERNS:
        for path in sorted(run_dir.glob(pattern)):
            kind, _, name = path.stem.partition("_")
            header, data = _read_csv(path)
            panels = _groups(kind, header, info["probes"].get(name), info["dim"])
            if len(data) == 0 or not panels or header[0] != "time":
                continue
            t = data[:, 0]
            fig = _figure(8.0, 1.0 + 2.2 * len(panels))
            axes = fig.subplots(len(panels), 1, sharex=True, squeeze=False)[:, 0]
            for ax, (label, columns) in zip(axes, panels):
                for i, legend in columns:
                    ax.plot(t, data[:, i], lw=1.0, label=legend)
                if "elevation" in label and info["surface_level"] is not None:
                    ax.axhline(info["surface_level"], color="0.5", ls="--", lw=0.8, label="still-water level")
                ax.set_ylabel(label)
                ax.grid(alpha=0.3)
                if len(columns) > 1 or "elevation" in label:
                    ax.legend(fontsize="small", ncol=min(3, len(columns) + 1))
            axes[-1].set_xlabel("time [s]")
            axes[0].set_title(f"{info['name']}: {path.name}")
            fig.tight_layout()
            written.append(_save(fig, out / f"{path.stem}.png"))
    return written


# ------------------------------------------------------------------ spectra
SPECTRAL_MOTIONS = ("irregular", "focused")
"""Motion types whose waves have a target spectrum (`shoal.motions.IrregularWaves`, `FocusedWaves`)."""

_MIN_SAMPLES = 32
"""Samples a record needs for Welch's default segments (a quarter of the record, 8 samples at least)."""


def spectral_paddle(run_dir):
    """The first ``irregular`` or ``focused`` motion of a run's ``case.toml``, built as its
    `shoal.motions` object, or None (no such motion, or one this shoal cannot build: a spectrum file
    that has moved, a newer case format)."""
    from pydantic import ValidationError

    from .casefile import MOTIONS

    run_dir = Path(run_dir)
    try:
        case = tomllib.loads((run_dir / "case.toml").read_text(encoding="utf-8"))
    except (OSError, tomllib.TOMLDecodeError, UnicodeDecodeError):
        return None
    for m in case.get("motions", []) or []:
        if isinstance(m, dict) and m.get("type") in SPECTRAL_MOTIONS:
            spec = dict(m)
            sp = spec.get("spectrum")
            if isinstance(sp, dict) and sp.get("type") == "file" and isinstance(sp.get("file"), str):
                spec["spectrum"] = dict(sp, file=str((run_dir / sp["file"]).resolve()))
            try:
                return MOTIONS[m["type"]].model_validate(spec)
            except (ValidationError, InputError, OSError, ValueError):
                return None
    return None


def plot_spectra(run_dir, out, start=None, segment=None):
    """Variance density spectra of the run's wave gauges against the target spectrum.

    For each ``gauge_*.csv`` the elevation record from `start` to its end is analysed by Welch's
    method (`shoal.analysis.wave_spectrum`: Hann-tapered segments of `segment` seconds overlapping by
    half) and drawn with the target density S(f) of the case's ``irregular`` or ``focused`` paddle
    (`spectral_paddle`), its measured Hm0 = 4 sqrt(m0), Tp, Tm01 = m0 / m1 and Tm02 = sqrt(m0 / m2)
    (IAHR 1989) in the legend. The same numbers go to ``spectra.json`` in `out`: per gauge ``Hm0``,
    ``Tp``, ``Tm01``, ``Tm02`` [m, s], the window ``t0``, ``t1`` [s], ``df`` [Hz] and the degrees of
    freedom ``dof``, and the target's ``Hs`` and ``Tp``.

    Parameters
    ----------
    run_dir : str or os.PathLike
        The run directory holding ``gauge_*.csv``.
    out : str or os.PathLike
        Folder for the PNGs and ``spectra.json`` (created if missing).
    start : float, optional
        Ignore the records before this time [s]. Default: the paddle's start-up ramp (its
        ``ramp_time``, two peak periods unless set), or 0 without a spectral paddle.
    segment : float, optional
        Welch segment length [s] (resolution 1 / segment); default a quarter of the window.

    Returns
    -------
    list of pathlib.Path
        The PNGs (``spectrum_<gauge>.png``) and ``spectra.json``; empty when no gauge file holds
        a record long enough for two segments after `start`.

    Raises
    ------
    InputError
        A record that cannot be analysed other than by being too short (NaN elevations, times that
        do not increase).
    """
    from .analysis import wave_spectrum

    run_dir, out = Path(run_dir), Path(out)
    info = run_info(run_dir)
    paddle = spectral_paddle(run_dir)
    target = paddle.spectrum if paddle is not None else None
    t_start = float(start) if start is not None else (paddle.ramp if paddle is not None else 0.0)
    written, table = [], {}
    for path in sorted(run_dir.glob("gauge_*.csv")):
        header, data = _read_csv(path)
        if len(data) == 0 or not header or header[0] != "time" or "level" not in header:
            continue
        t, z = data[:, 0], data[:, header.index("level")]
        keep = t >= t_start
        if np.count_nonzero(keep) < _MIN_SAMPLES:
            continue  # too short for Welch's default segments: nothing to plot yet
        try:
            sp = wave_spectrum(t[keep], z[keep], segment=segment)
        except InputError as exc:
            raise InputError(f"{path}: {exc}") from None
        name = path.stem.partition("_")[2]
        row = {"Hm0": sp.Hm0, "Tp": sp.Tp, "Tm01": sp.Tm01, "Tm02": sp.Tm02, "t0": float(t[keep][0]),
               "t1": float(t[keep][-1]), "df": sp.df, "dof": sp.dof}
        fig = _figure(8.0, 4.5)
        ax = fig.subplots()
        ax.plot(sp.f, sp.S, lw=1.2, label=f"measured: Hm0 = {sp.Hm0:.4g} m, Tp = {sp.Tp:.3g} s, "
                                          f"Tm01 = {sp.Tm01:.3g} s, Tm02 = {sp.Tm02:.3g} s")
        f_hi = float(sp.f[-1])
        if target is not None:
            fp = target.peak_frequency
            f_hi = min(f_hi, 3.5 * fp)
            f = np.linspace(0.0, f_hi, 800)[1:]
            ax.plot(f, target.density(f), "k--", lw=1.0,
                    label=f"target {target.type}: Hs = {target.hm0:.4g} m, Tp = {1.0 / fp:.3g} s")
            row.update(target_Hs=float(target.hm0), target_Tp=float(1.0 / fp))
        ax.set_xlim(0.0, f_hi)
        ax.set_xlabel("frequency [Hz]")
        ax.set_ylabel("S(f) [m$^2$/Hz]")
        ax.grid(alpha=0.3)
        ax.legend(fontsize="small")
        ax.set_title(f"{info['name']}: {path.name}, {row['t0']:.4g}-{row['t1']:.4g} s, "
                     f"{sp.segments} segments, df = {sp.df:.3g} Hz")
        fig.tight_layout()
        written.append(_save(fig, out / f"spectrum_{name}.png"))
        table[name] = row
    if table:
        text = json.dumps({"start": t_start, "gauges": table}, indent=2) + "\n"
        written.append(replace_file(out / "spectra.json", lambda tmp: Path(tmp).write_text(text, encoding="utf-8")))
    return written


# ------------------------------------------------------------------ mean flow
def surface_levels(kernel_sum, z, threshold=0.5):
    """Free-surface level of every column of a test-point grid.

    The highest z where the kernel sum is >= `threshold`, linearly
    interpolated to the crossing with the node above (as the wave gauges
    do, `shoal.probes.surface_level`), vectorised over the columns.

    Parameters
    ----------
    kernel_sum : ndarray, shape (..., nz)
        Kernel sums, z last.
    z : ndarray, shape (nz,)
        Node elevations [m], increasing.
    threshold : float
        The water criterion (1/2: the probes' free surface).

    Returns
    -------
    ndarray, shape (...)
        Levels [m]; NaN where a column is dry, z[-1] where it is wet to the top.
    """
    s = np.asarray(kernel_sum, float)
    z = np.asarray(z, float)
    wet = s >= threshold
    nz = z.size
    k = nz - 1 - np.argmax(wet[..., ::-1], axis=-1)  # highest wet node
    kp = np.minimum(k + 1, nz - 1)
    s0 = np.take_along_axis(s, k[..., None], -1)[..., 0]
    s1 = np.take_along_axis(s, kp[..., None], -1)[..., 0]
    with np.errstate(divide="ignore", invalid="ignore"):
        frac = np.where(kp > k, (s0 - threshold) / (s0 - s1), 0.0)
    level = z[k] + frac * (z[kp] - z[k])
    return np.where(wet.any(axis=-1), level, np.nan)


def _window(t, period, periods, start):
    """(window start, period, number of periods) of the averaging."""
    t = np.asarray(t, float)
    if t.size < 2:
        raise InputError(f"{t.size} time sample(s): averaging needs at least two")
    if start is not None and not (math.isfinite(start) and start >= 0):
        raise InputError(f"--start = {start}: must be a time >= 0 [s]")
    s = t[0] if start is None else max(float(start), t[0])
    if periods is not None and not (isinstance(periods, (int, np.integer)) and periods >= 1):
        raise InputError(f"--periods = {periods}: must be a whole number >= 1")
    span = t[-1] - s
    if span <= 0:
        raise InputError(f"no samples after --start = {start} s (the record ends at t = {t[-1]:.4g} s)")
    if period is None:  # the whole record is the one "period"
        if periods is not None and periods > 1:
            raise InputError(f"--periods {periods}: the record holds 1 complete period (no --period and no "
                             "piston motion in case.toml: the whole record after --start is averaged)")
        return s, span, 1
    if not (math.isfinite(period) and period > 0):
        raise InputError(f"--period = {period}: must be a positive time [s]")
    complete = int(math.floor(span / period + 1e-9))
    if periods is None:
        if complete < 1:
            raise InputError(f"the record after t = {s:.4g} s is {span:.4g} s long, shorter than one period "
                             f"T = {period:g} s; give a shorter --period or an earlier --start")
        periods = complete
    elif periods > complete:
        raise InputError(f"--periods {periods}: the record after t = {s:.4g} s holds {complete} complete "
                         f"period(s) of T = {period:g} s")
    return t[-1] - periods * period, float(period), int(periods)


def mean_flow(ds, period=None, periods=None, start=None, still_water_level=None, wet_threshold=0.5):
    """The period-mean flow of a test-point grid (the rip-current paper's analysis).

    The averaging window is the last `periods` whole periods of the record
    after `start` (default: every complete period after it; no `period`: the
    whole record after `start`), averaged with `shoal.analysis.period_average`.
    A node is wet when its kernel sum is >= 1/2.

    * Depth-averaged mean current: each sample is depth-integrated over its
      wet nodes (`shoal.analysis.depth_average`); U = <q_x> / <h>,
      V = <q_y> / <h> (mean volume flux over mean wet depth, so a wave's
      crest-trough flux is kept); `vorticity` Omega = dV/dx - dU/dy of it
      (`shoal.analysis.vorticity`, 3D grids only).
    * Node means u_mean, v_mean, w_mean: the mean over the times the node is
      wet, shown where it is wet at least half the time (`wet_fraction`).
    * Mean water level `level`: the period mean of each column's surface
      level (`surface_levels`); `setup` = level - `still_water_level`.
    * `bed`: the lowest node wet at some time in the window (an estimate of
      the bed elevation, within one node spacing above it).

    Parameters
    ----------
    ds : xarray.Dataset
        Test points: dims (time, z, y, x); variables u, v, w, kernel_sum.
    period : float, optional
        Averaging period T [s] (the wave period).
    periods : int, optional
        Number of periods to average over (the last ones of the record).
    start : float, optional
        Ignore the record before this time [s] (the start-up).
    still_water_level : float, optional
        [m], for the set-up.
    wet_threshold : float
        The water criterion on the kernel sum.

    Returns
    -------
    xarray.Dataset
        U, V, depth, (vorticity), level, (setup), bed on (y, x); u_mean,
        v_mean, w_mean, wet_fraction on (z, y, x); attributes t_start,
        t_end, period, periods.

    Raises
    ------
    InputError
        Missing variables, or a record too short for the window.
    """
    import xarray as xr

    from .analysis import depth_average, period_average, vorticity

    missing = [v for v in ("u", "v", "w", "kernel_sum") if v not in ds]
    if missing:
        raise InputError(f"the test points lack {', '.join(missing)}")
    t0, T, n = _window(ds["time"].values, period, periods, start)
    wet = ds["kernel_sum"] >= wet_threshold
    vel = xr.Dataset({v: ds[v].where(wet, 0.0) for v in ("u", "v", "w")})
    per_sample = depth_average(xr.Dataset({"u": vel["u"], "v": vel["v"], "kernel_sum": ds["kernel_sum"]}),
                               wet_threshold=wet_threshold)
    fluxes = period_average(per_sample[["u_flux", "v_flux", "depth"]], T, t0, n)
    h = fluxes["depth"]
    out = {"depth": h, "U": fluxes["u_flux"] / h.where(h > 0), "V": fluxes["v_flux"] / h.where(h > 0)}
    frac = period_average(wet.astype(float), T, t0, n)
    sums = period_average(vel, T, t0, n)
    with np.errstate(divide="ignore", invalid="ignore"):
        for v in ("u", "v", "w"):
            out[f"{v}_mean"] = (sums[v] / frac.where(frac > 0)).where(frac >= 0.5)
    out["wet_fraction"] = frac
    z = np.asarray(ds["z"].values, float)
    ks = ds["kernel_sum"].transpose("time", "y", "x", "z").values
    lev = xr.DataArray(surface_levels(ks, z, wet_threshold), dims=("time", "y", "x"),
                       coords={"time": ds["time"], "y": ds["y"], "x": ds["x"]})
    out["level"] = period_average(lev, T, t0, n)
    if still_water_level is not None:
        out["setup"] = out["level"] - float(still_water_level)
    window = wet.sel(time=slice(t0 - 1e-9, None)).any("time").transpose("y", "x", "z").values
    k = np.argmax(window, axis=-1)
    out["bed"] = xr.DataArray(np.where(window.any(axis=-1), z[k], np.nan), dims=("y", "x"),
                              coords={"y": ds["y"], "x": ds["x"]})
    res = xr.Dataset(out)
    if ds.sizes["y"] >= 2 and ds.sizes["x"] >= 2:
        res["vorticity"] = (("y", "x"), vorticity(res["U"].transpose("y", "x").values,
                                                   res["V"].transpose("y", "x").values,
                                                   ds["x"].values, ds["y"].values))
    res.attrs.update(t_start=float(t0), t_end=float(t0 + n * T), period=float(T), periods=int(n))
    units = {"U": "m s-1", "V": "m s-1", "depth": "m", "level": "m", "setup": "m", "bed": "m", "vorticity": "s-1",
             "u_mean": "m s-1", "v_mean": "m s-1", "w_mean": "m s-1", "wet_fraction": "1"}
    for k_, u in units.items():
        if k_ in res:
            res[k_].attrs["units"] = u
    return res


def _profile_columns(mf, count=4):
    """(y index, x index) of up to `count` columns, spread over x along the
    middle y row, among the columns with at least two wet mean nodes."""
    um = mf["u_mean"].transpose("z", "y", "x").values
    j = mf.sizes["y"] // 2
    wet_cols = np.flatnonzero(np.isfinite(um[:, j, :]).sum(axis=0) >= 2)
    if wet_cols.size == 0:
        return []
    picks = np.unique(wet_cols[np.round(np.linspace(0, wet_cols.size - 1, min(count, wet_cols.size))).astype(int)])
    return [(j, int(i)) for i in picks]


def _window_text(mf):
    a = mf.attrs
    return f"t = {a['t_start']:.3g}-{a['t_end']:.3g} s ({a['periods']} x {a['period']:.3g} s)"


def plot_mean_flow(run_dir, out, period=None, periods=None, start=None):
    """Plots of the period-mean flow of each ``testpoints_*.nc`` grid.

    For a 3D grid (ny >= 2): ``meanflow_<name>_current.png`` (plan view of
    the depth-averaged mean-current arrows, coloured by the vertical
    vorticity of the mean current, over contours of the bed), and
    ``meanflow_<name>_setup.png`` (filled contours of the set-up, or of the
    mean water level when the still-water level is unknown). For a 2D grid
    (ny = 1): ``meanflow_<name>_section.png`` (x-z section of the mean
    (u, w) arrows coloured by speed, with the mean water level and the bed)
    and ``meanflow_<name>_setup.png`` (set-up along x). Both:
    ``meanflow_<name>_profiles.png``, vertical profiles of the mean u at up
    to four columns.

    Parameters
    ----------
    run_dir : str or os.PathLike
        The run directory.
    out : str or os.PathLike
        Folder for the PNGs.
    period : float, optional
        Averaging period [s]; default: the case's piston period, else the
        whole record (after `start`).
    periods : int, optional
        Average over the last `periods` periods (default: every complete one
        after `start`).
    start : float, optional
        Ignore the record before this time [s].

    Returns
    -------
    list of pathlib.Path
        The PNGs written.

    Raises
    ------
    InputError
        A record too short for the window, or an unreadable dataset.
    """
    import xarray as xr

    run_dir, out = Path(run_dir), Path(out)
    info = run_info(run_dir)
    period = period if period is not None else info["period"]
    written = []
    for path in sorted(run_dir.glob("testpoints_*.nc")):
        name = path.stem.partition("_")[2]
        try:
            with xr.open_dataset(path, engine="scipy") as f:
                ds = f.load()
        except (OSError, ValueError, TypeError) as exc:
            raise InputError(f"{path}: not a readable test-point dataset ({exc})") from None
        try:
            mf = mean_flow(ds, period, periods, start, info["surface_level"])
        except InputError as err:
            raise InputError(f"{path.name}: {err}") from None
        if ds.sizes["y"] >= 2:
            written += _plan_plots(mf, out, name, info)
        else:
            written += _section_plots(mf, out, name, info)
        written.append(_profiles_plot(mf, out, name))
    return written


def _plan_plots(mf, out, name, info):
    from matplotlib.colors import TwoSlopeNorm

    x, y = mf["x"].values, mf["y"].values
    U, V = mf["U"].transpose("y", "x").values, mf["V"].transpose("y", "x").values
    bed = mf["bed"].transpose("y", "x").values
    aspect = float(np.clip((np.ptp(y) or 1.0) / (np.ptp(x) or 1.0), 0.25, 2.0))
    written = []

    fig = _figure(8.0, 1.6 + 6.0 * aspect)
    ax = fig.add_subplot()
    _bed_contours(ax, x, y, bed)
    om = mf["vorticity"].transpose("y", "x").values
    ok = np.isfinite(U) & np.isfinite(V)
    X, Y = np.meshgrid(x, y)
    lim = float(np.nanmax(np.abs(om[ok]))) if ok.any() and np.isfinite(om[ok]).any() else 1.0
    q = ax.quiver(X[ok], Y[ok], U[ok], V[ok], om[ok], cmap="RdBu_r",
                  norm=TwoSlopeNorm(0.0, -(lim or 1.0), lim or 1.0), pivot="mid")
    fig.colorbar(q, ax=ax, label=r"mean vertical vorticity $\Omega = \partial_x V - \partial_y U$ [1/s]")
    speed = np.hypot(U[ok], V[ok])
    ref = _nice(float(np.max(speed))) if speed.size and np.max(speed) > 0 else 0.1
    ax.quiverkey(q, 0.82, -0.1, ref, f"{ref:g} m/s", labelpos="E", coordinates="axes")
    ax.set(xlabel="x [m]", ylabel="y [m]", aspect="equal",
           title=f"{info['name']} {name}: depth-averaged mean current, {_window_text(mf)}")
    fig.tight_layout()
    written.append(_save(fig, out / f"meanflow_{name}_current.png"))

    fig = _figure(8.0, 1.6 + 6.0 * aspect)
    ax = fig.add_subplot()
    key = "setup" if "setup" in mf else "level"
    field = mf[key].transpose("y", "x").values
    label = "set-up: mean water level - still-water level [m]" if key == "setup" else "mean water level [m]"
    if np.isfinite(field).sum() >= 4 and np.nanmax(field) > np.nanmin(field):
        cf = ax.contourf(x, y, np.ma.masked_invalid(field), levels=12, cmap="viridis")
        fig.colorbar(cf, ax=ax, label=label)
    else:
        m = ax.pcolormesh(x, y, np.ma.masked_invalid(field), cmap="viridis", shading="nearest")
        fig.colorbar(m, ax=ax, label=label)
    _bed_contours(ax, x, y, bed)
    ax.set(xlabel="x [m]", ylabel="y [m]", aspect="equal", title=f"{info['name']} {name}: {_window_text(mf)}")
    fig.tight_layout()
    written.append(_save(fig, out / f"meanflow_{name}_setup.png"))
    return written


def _bed_contours(ax, x, y, bed):
    if np.isfinite(bed).sum() >= 4 and np.nanmax(bed) > np.nanmin(bed):
        cs = ax.contour(x, y, np.ma.masked_invalid(bed), levels=8, colors="0.3", linewidths=0.6)
        ax.clabel(cs, fontsize="x-small", fmt="%.3g")
        ax.plot([], [], color="0.3", lw=0.6, label="bed (lowest wet test point) [m]")
        ax.legend(loc="lower left", fontsize="x-small")


def _nice(v):
    """1, 2 or 5 times a power of ten, not above v."""
    e = 10.0 ** math.floor(math.log10(v))
    return max(m * e for m in (1, 2, 5) if m * e <= v)


def _section_plots(mf, out, name, info):
    x, z = mf["x"].values, mf["z"].values
    u = mf["u_mean"].isel(y=0).transpose("z", "x").values
    w = mf["w_mean"].isel(y=0).transpose("z", "x").values
    level = mf["level"].isel(y=0).values
    bed = mf["bed"].isel(y=0).values
    written = []
    fig = _figure(10.0, 4.5)
    ax = fig.add_subplot()
    X, Z = np.meshgrid(x, z)
    ok = np.isfinite(u) & np.isfinite(w)
    if ok.any():
        q = ax.quiver(X[ok], Z[ok], u[ok], w[ok], np.hypot(u[ok], w[ok]), cmap="viridis", pivot="mid")
        fig.colorbar(q, ax=ax, label="mean speed $\\sqrt{u^2 + w^2}$ [m/s]")
        sp = float(np.max(np.hypot(u[ok], w[ok])))
        if sp > 0:
            ref = _nice(sp)
            ax.quiverkey(q, 0.82, -0.14, ref, f"{ref:g} m/s", labelpos="E", coordinates="axes")
    ax.plot(x, level, color="tab:blue", lw=1.2, label="mean water level")
    if info["surface_level"] is not None:
        ax.axhline(info["surface_level"], color="0.5", ls="--", lw=0.8, label="still-water level")
    ax.plot(x, bed, color="0.3", lw=1.0, label="bed (lowest wet test point)")
    ax.set(xlabel="x [m]", ylabel="z [m]", title=f"{info['name']} {name}: mean (u, w), {_window_text(mf)}")
    ax.legend(fontsize="small", loc="lower left")
    fig.tight_layout()
    written.append(_save(fig, out / f"meanflow_{name}_section.png"))

    fig = _figure(8.0, 3.5)
    ax = fig.add_subplot()
    if "setup" in mf:
        ax.plot(x, mf["setup"].isel(y=0).values, marker=".", lw=1.0)
        ax.axhline(0.0, color="0.5", lw=0.6)
        ax.set_ylabel("set-up: mean level - still-water level [m]")
    else:
        ax.plot(x, level, marker=".", lw=1.0)
        ax.set_ylabel("mean water level [m]")
    ax.set(xlabel="x [m]", title=f"{info['name']} {name}: {_window_text(mf)}")
    ax.grid(alpha=0.3)
    fig.tight_layout()
    written.append(_save(fig, out / f"meanflow_{name}_setup.png"))
    return written


def _profiles_plot(mf, out, name):
    z = mf["z"].values
    fig = _figure(6.0, 5.0)
    ax = fig.add_subplot()
    cols = _profile_columns(mf)
    for j, i in cols:
        u = mf["u_mean"].isel(y=j, x=i).values
        ok = np.isfinite(u)
        ax.plot(u[ok], z[ok], marker=".", lw=1.0,
                label=f"x = {float(mf['x'][i]):.3g} m, y = {float(mf['y'][j]):.3g} m")
    ax.axvline(0.0, color="0.5", lw=0.6)
    ax.set(xlabel="mean u [m/s]", ylabel="z [m]", title=f"{name}: mean u profiles, {_window_text(mf)}")
    if cols:
        ax.legend(fontsize="small")
    else:
        ax.text(0.5, 0.5, "no column wet half the time", transform=ax.transAxes, ha="center")
    ax.grid(alpha=0.3)
    fig.tight_layout()
    return _save(fig, out / f"meanflow_{name}_profiles.png")


# ------------------------------------------------------------------ tracks
def plot_tracks(run_dir, out):
    """Trajectories of the tracked particles of each ``track_*.csv``.

    A plan view (x-y) for a 3D run, the x-z plane for a 2D run (from
    ``case.toml``; without it, a run whose y never changes is 2D); a dot
    marks each start. One PNG per file, ``track_<name>.png``.

    Parameters
    ----------
    run_dir : str or os.PathLike
        The run directory.
    out : str or os.PathLike
        Folder for the PNGs.

    Returns
    -------
    list of pathlib.Path
        The PNGs written.
    """
    run_dir, out = Path(run_dir), Path(out)
    info = run_info(run_dir)
    written = []
    for path in sorted(run_dir.glob("track_*.csv")):
        header, data = _read_csv(path)
        if len(data) == 0 or header[0] != "time" or (len(header) - 1) % 3:
            continue
        xyz = data[:, 1:].reshape(len(data), -1, 3)
        ids = [h[2:] for h in header[1::3]]
        dim = info["dim"] or (3 if np.nanmax(np.abs(xyz[:, :, 1] - xyz[:1, :, 1])) > 0 else 2)
        b = 1 if dim == 3 else 2
        fig = _figure(8.0, 6.0 if dim == 3 else 4.5)
        ax = fig.add_subplot()
        for k, pid in enumerate(ids):
            line, = ax.plot(xyz[:, k, 0], xyz[:, k, b], lw=1.0, label=f"id {pid}" if len(ids) <= 12 else None)
            ax.plot(xyz[0, k, 0], xyz[0, k, b], "o", ms=3, color=line.get_color())
        ax.set(xlabel="x [m]", ylabel="y [m]" if dim == 3 else "z [m]", aspect="equal",
               title=f"{info['name']}: trajectories {path.name}, t = {data[0, 0]:.3g}-{data[-1, 0]:.3g} s "
                     f"(dots: start)")
        if len(ids) <= 12:
            ax.legend(fontsize="small")
        ax.grid(alpha=0.3)
        fig.tight_layout()
        written.append(_save(fig, out / f"{path.stem}.png"))
    return written


# ------------------------------------------------------------------ plane
def parse_plane(spec):
    """``"z=0.05"`` -> (2, 0.05); ``"mid"`` -> (None, None) (the default plane).

    Raises
    ------
    InputError
        If `spec` is not AXIS=VALUE with AXIS x, y or z and a finite VALUE [m].
    """
    text = str(spec).strip()
    if text.lower() == "mid":
        return None, None
    m = re.fullmatch(r"([xyzXYZ])\s*=\s*(\S+)", text)
    value = None
    if m:
        try:
            value = float(m.group(2))
        except ValueError:
            value = None
    if value is None or not math.isfinite(value):
        raise InputError(f"--plane {text!r}: must be AXIS=VALUE with AXIS x, y or z and VALUE in metres "
                         "(e.g. --plane z=0.05, --plane y=0.15), or mid")
    return "xyz".index(m.group(1).lower()), value


def _snapshots(run_dir):
    from .output.pvd import read_pvd

    for pvd in sorted(run_dir.glob("*.pvd")):
        try:
            entries = read_pvd(pvd)
        except ValueError:
            continue
        entries = [(t, f) for t, f in entries if (run_dir / f).is_file()]
        if entries:
            return entries
    return []


def plot_plane(run_dir, out, plane="mid", time=None):
    """Velocity magnitude of the fluid particles on a plane, from one snapshot.

    The particles within dp of the plane (``x=``, ``y=`` or ``z=`` VALUE
    [m]) in the last snapshot, or the one nearest to `time`, drawn at their
    in-plane coordinates and coloured by |v|; boundary particles in the
    slab are grey. ``mid`` is the middle of the fluid's y extent in 3D and
    the x-z plane in 2D. In 2D a ``z=`` or ``x=`` plane is a line: |v| is
    plotted along it. Writes ``plane_<axis><value>_t<time>.png``.

    Parameters
    ----------
    run_dir : str or os.PathLike
        The run directory (``<case>.pvd`` and its ``.vtu`` snapshots).
    out : str or os.PathLike
        Folder for the PNG.
    plane : str
        ``"z=0.05"``, ``"y=0.15"``, ``"x=1.0"`` or ``"mid"``.
    time : float, optional
        Snapshot time [s] (the nearest snapshot is used); default the last.

    Returns
    -------
    list of pathlib.Path
        The PNG written.

    Raises
    ------
    InputError
        A bad plane, no snapshot, or no fluid particle near the plane.
    """
    from .output.vtu import read_vtu

    run_dir, out = Path(run_dir), Path(out)
    axis, value = parse_plane(plane)
    info = run_info(run_dir)
    entries = _snapshots(run_dir)
    if not entries:
        raise InputError(f"{run_dir} holds no snapshots (<case>.pvd and .vtu files) for --plane")
    times = np.array([t for t, _ in entries])
    if time is None:
        k = len(entries) - 1
    else:
        if not (math.isfinite(time) and time >= 0):
            raise InputError(f"--time = {time}: must be a time >= 0 [s]")
        k = int(np.argmin(np.abs(times - time)))
    t, name = entries[k]
    pos, data = read_vtu(run_dir / name)
    pos = np.asarray(pos, float)
    if "velocity" not in data or "kind" not in data:
        raise InputError(f"{run_dir / name}: no velocity or kind point data (not a shoal snapshot)")
    speed = np.linalg.norm(np.asarray(data["velocity"], float), axis=1)
    fluid = np.asarray(data["kind"]) == 0
    dim = info["dim"] or (3 if np.ptp(pos[:, 1]) > 0 else 2)
    dp = info["dp"]
    if dp is None:
        raise InputError(f"{run_dir} has no case.toml or resolved.json giving dp (the plane's thickness)")
    if axis is None:
        axis = 1
        value = 0.0 if dim == 2 else 0.5 * (pos[fluid, 1].min() + pos[fluid, 1].max())
    near = np.abs(pos[:, axis] - value) <= dp
    if not (near & fluid).any():
        lo, hi = pos[fluid, axis].min(), pos[fluid, axis].max()
        raise InputError(f"no fluid particle within dp = {dp:g} m of the plane {'xyz'[axis]} = {value:g} m at "
                         f"t = {t:.4g} s (the fluid spans {'xyz'[axis]} = {lo:.4g} to {hi:.4g} m)")
    in_plane = [a for a in (0, 1, 2) if a != axis and not (dim == 2 and a == 1)]
    labels = {0: "x [m]", 1: "y [m]", 2: "z [m]"}
    f = near & fluid
    wall = near & ~fluid
    plane_text = "the x-z plane" if dim == 2 and axis == 1 else f"{'xyz'[axis]} = {value:.4g} m"
    if len(in_plane) == 2:
        a, b = in_plane
        span_a = np.ptp(pos[near, a]) or 1.0
        span_b = np.ptp(pos[near, b]) or 1.0
        fig = _figure(9.0, float(np.clip(9.0 * span_b / span_a, 2.5, 9.0)) + 1.2)
        ax = fig.add_subplot()
        size = float(np.clip(3.0e4 / max(int(near.sum()), 1), 0.3, 25.0))
        if wall.any():
            ax.scatter(pos[wall, a], pos[wall, b], s=size, c="0.65", linewidths=0, rasterized=True)
        sc = ax.scatter(pos[f, a], pos[f, b], s=size, c=speed[f], cmap="viridis", linewidths=0, rasterized=True)
        fig.colorbar(sc, ax=ax, label="|v| [m/s]", shrink=0.8)
        ax.set(xlabel=labels[a], ylabel=labels[b], aspect="equal")
    else:
        a = in_plane[0]
        fig = _figure(8.0, 3.5)
        ax = fig.add_subplot()
        order = np.argsort(pos[f, a])
        ax.plot(pos[f, a][order], speed[f][order], ".", ms=3)
        ax.set(xlabel=labels[a], ylabel="|v| [m/s]")
        ax.grid(alpha=0.3)
    ax.set_title(f"{info['name']}: |v| of the fluid within dp of {plane_text}, t = {t:.4g} s", fontsize="medium")
    fig.tight_layout()
    tag = f"{'xyz'[axis]}{value:.4g}_t{t:.4g}"
    return [_save(fig, out / f"plane_{tag}.png")]


# ------------------------------------------------------------------ all
def post(run_dir, out=None, gauges=False, mean_flow=False, tracks=False, plane=None, time=None, period=None,
         periods=None, start=None, isosurface=False, iso_spacing=None, iso_level=0.5, backend="cpu", spectra=False,
         segment=None):
    """Make the standard plots of a finished run (``shoal post``).

    With no selector (`gauges`, `spectra`, `mean_flow`, `tracks`, `plane`), every
    plot that applies to the files present (the plane plot on the ``mid`` plane,
    the spectra when the case has an ``irregular`` or ``focused`` paddle).
    A selector whose files are missing is an error. The free-surface meshes
    (`isosurface`) are made only when asked for.

    Parameters
    ----------
    run_dir : str or os.PathLike
        The run directory.
    out : str or os.PathLike, optional
        Folder for the PNGs (default ``run_dir / "post"``).
    gauges, mean_flow, tracks : bool
        Select `plot_gauges`, `plot_mean_flow`, `plot_tracks`.
    spectra : bool
        Select `plot_spectra`.
    plane : str, optional
        Select `plot_plane` on this plane.
    time : float, optional
        Snapshot time for the plane plot [s].
    period, periods, start
        The mean-flow averaging window (`plot_mean_flow`); `start` also starts the spectra's window.
    segment : float, optional
        Welch segment length of the spectra [s] (`plot_spectra`).
    isosurface : bool
        Also write the free surface of every snapshot as a mesh
        (`shoal.output.isosurface.write_isosurfaces`: ``isosurface/`` in
        `out`, a .pvd and one .vtu per snapshot).
    iso_spacing, iso_level : float
        Its grid spacing [m] (default dp/2) and kernel-sum level (1/2).
    backend : str
        Compute backend of the iso-surface's kernel sums ("cpu" or "cuda").

    Returns
    -------
    list of pathlib.Path
        The files written (PNGs; with `isosurface`, then the .pvd and .vtu files).

    Raises
    ------
    InputError
        A missing directory, a directory holding no run, a selector with no
        files to plot, or bad options.
    """
    run_dir = Path(run_dir)
    run_info(run_dir)  # a directory?
    have = {"gauges": any(any(run_dir.glob(p)) for p in GAUGE_PATTERNS),
            "mean_flow": any(run_dir.glob("testpoints_*.nc")),
            "tracks": any(run_dir.glob("track_*.csv")),
            "plane": bool(_snapshots(run_dir))}
    have["spectra"] = any(run_dir.glob("gauge_*.csv"))
    if not any(have.values()):
        raise InputError(f"{run_dir} holds no shoal run output (gauge, probe, test-point, track or snapshot "
                         "files)")
    chosen = {"gauges": gauges, "mean_flow": mean_flow, "tracks": tracks, "plane": plane is not None,
              "spectra": spectra}
    if isosurface and not have["plane"]:
        raise InputError(f"{run_dir} holds no snapshots (.pvd + .vtu) for --isosurface")
    what = {"gauges": "gauge_*.csv, maxz_*.csv, runup_*.csv, probe_*.csv, flow_*.csv, force_*.csv or pressure_*.csv files",
            "mean_flow": "testpoints_*.nc test-point grids", "tracks": "track_*.csv files",
            "plane": "snapshots (.pvd + .vtu)", "spectra": "gauge_*.csv files"}
    if any(chosen.values()) or isosurface:  # selectors (--isosurface alone: the meshes only)
        for k, on in chosen.items():
            if on and not have[k]:
                raise InputError(f"{run_dir} holds no {what[k]} for --{k.replace('_', '-')}")
        todo = chosen
    else:
        todo = dict(have, spectra=have["spectra"] and spectral_paddle(run_dir) is not None)
    if plane is not None:
        parse_plane(plane)  # a bad spec fails before any plotting
    out = Path(out) if out is not None else run_dir / "post"
    written = []
    if todo["gauges"]:
        written += plot_gauges(run_dir, out)
    if todo["spectra"]:
        spectra_written = plot_spectra(run_dir, out, start, segment)
        if spectra and not spectra_written:
            after = f"t = {start:g} s" if start is not None else "the paddle's ramp"
            raise InputError(f"{run_dir}: no gauge record is long enough for a spectrum after {after} "
                             f"({_MIN_SAMPLES} samples at least); run longer or give an earlier --start")
        written += spectra_written
    if todo["mean_flow"]:
        written += plot_mean_flow(run_dir, out, period, periods, start)
    if todo["tracks"]:
        written += plot_tracks(run_dir, out)
    if todo["plane"]:
        written += plot_plane(run_dir, out, plane if plane is not None else "mid", time)
    if isosurface:
        from .output.isosurface import write_isosurfaces

        written += write_isosurfaces(run_dir, out / "isosurface", iso_spacing, iso_level, backend)
    return written
