"""``shoal post``: plots of a finished run, and the mean-flow pipeline behind them."""

import csv

import numpy as np
import pytest
import xarray as xr

import shoal
from shoal.cases import still_water_2d
from shoal.cli import main
from shoal.errors import InputError
from shoal.post import mean_flow, parse_plane, plot_plane, plot_tracks, post, run_info, surface_levels
from shoal.probes import FlowGauge, ForceGauge, MaxZGauge, PointProbes, RunupGauge, TestPoints, Tracker, WaveGauge

PNG = b"\x89PNG\r\n\x1a\n"


def _is_png(path):
    data = path.read_bytes()
    return data[:8] == PNG and len(data) > 5000


@pytest.fixture(scope="module")
def run_dir(tmp_path_factory):
    """A real 2D still-water run (0.1 s, dp = 0.04 m) with a probe of every type."""
    case = still_water_2d(dp=0.04, depth=0.4, length=0.8, end_time=0.1, output_interval=0.05)
    case = case.model_copy(update={"probes": [
        PointProbes(name="mid", points=[(0.4, 0, 0.1), (0.4, 0, 0.2)], interval=0.01),
        WaveGauge(name="g1", x=0.4, z0=0.2, z1=0.6, interval=0.01),
        MaxZGauge(name="m", x=0.4, radius=0.05, interval=0.01),
        RunupGauge(name="r", x0=0.0, x1=0.8, interval=0.01),
        TestPoints(name="tank", lo=(0.1, 0, 0.02), hi=(0.7, 0, 0.5), counts=(7, 1, 13), interval=0.01),
        Tracker(name="t", start=[(0.4, 0, 0.2), (0.1, 0, 0.1)], interval=0.01),
        FlowGauge(name="f", at=0.4, interval=0.01), ForceGauge(name="bed", solid="tank", interval=0.01)]})
    out = tmp_path_factory.mktemp("post") / "run"
    shoal.run_case(case, out, plot=False)
    return out


def _run(args, capsys):
    rc = main(args)
    cap = capsys.readouterr()
    return rc, cap.out, cap.err


def test_post_without_selector_makes_every_plot(run_dir, tmp_path, capsys):
    rc, out, err = _run(["post", str(run_dir), "--out", str(tmp_path / "all")], capsys)
    assert rc == 0, err
    names = sorted(p.name for p in (tmp_path / "all").iterdir())
    assert names == sorted(["gauge_g1.png", "maxz_m.png", "runup_r.png", "probe_mid.png", "track_t.png", "flow_f.png", "force_bed.png",
                            "meanflow_tank_section.png", "meanflow_tank_setup.png", "meanflow_tank_profiles.png",
                            "plane_y0_t0.1.png"])
    assert all(_is_png(tmp_path / "all" / n) for n in names)
    listed = [line.strip() for line in out.splitlines()[1:]]
    assert sorted(listed) == sorted(str(tmp_path / "all" / n) for n in names)  # the list printed
    assert out.splitlines()[0] == f"shoal: wrote {len(names)} PNG(s):"


@pytest.mark.parametrize("selector, expect", [
    (["--gauges"], {"gauge_g1.png", "maxz_m.png", "runup_r.png", "probe_mid.png", "flow_f.png", "force_bed.png"}),
    (["--mean-flow", "--start", "0.02"], {"meanflow_tank_section.png", "meanflow_tank_setup.png",
                                          "meanflow_tank_profiles.png"}),
    (["--tracks"], {"track_t.png"}),
    (["--plane", "z=0.2"], {"plane_z0.2_t0.1.png"}),
    (["--plane", "x=0.4", "--time", "0.04"], {"plane_x0.4_t0.05.png"}),  # the nearest snapshot
])
def test_each_selector_writes_only_its_plots(run_dir, tmp_path, capsys, selector, expect):
    rc, _, err = _run(["post", str(run_dir), "--out", str(tmp_path)] + selector, capsys)
    assert rc == 0, err
    assert {p.name for p in tmp_path.iterdir()} == expect
    assert all(_is_png(tmp_path / n) for n in expect)


def test_post_defaults_to_the_post_folder(run_dir):
    written = post(run_dir, gauges=True)
    assert written and all(p.parent == run_dir / "post" and _is_png(p) for p in written)


@pytest.mark.parametrize("args, message", [
    (["/nonexistent/run"], "not a directory"),
    (["{empty}"], "holds no shoal run output"),
    (["{run}", "--plane", "q=1"], "--plane 'q=1': must be AXIS=VALUE"),
    (["{run}", "--plane", "z=abc"], "must be AXIS=VALUE"),
    (["{run}", "--plane", "z=5"], "no fluid particle within dp = 0.04 m of the plane z = 5 m"),
    (["{run}", "--mean-flow", "--period", "0.3"], "shorter than one period"),
    (["{run}", "--mean-flow", "--period", "0.04", "--periods", "3"], "holds 2 complete period"),
    (["{run}", "--mean-flow", "--periods", "0"], "--periods = 0"),
    (["{run}", "--plane", "mid", "--time", "-1"], "--time = -1.0"),
    (["{empty}", "--tracks"], "holds no shoal run output"),
    (["{run}", "--dp", "1"], "unrecognized arguments"),
])
def test_bad_input_is_one_line_and_exit_2(run_dir, tmp_path, capsys, args, message):
    (tmp_path / "empty").mkdir()
    args = [a.format(empty=tmp_path / "empty", run=run_dir) for a in args]
    rc, out, err = _run(["post"] + args + ["--out", str(tmp_path / "o")], capsys)
    assert rc == 2
    assert err.startswith("shoal: error: ") and err.count("\n") == 1 and message in err, err


def test_a_selector_without_its_files_is_an_error(tmp_path):
    run = tmp_path / "run"
    run.mkdir()
    (run / "gauge_a.csv").write_text("time,level\n0,0.4\n0.1,0.41\n")
    with pytest.raises(InputError, match="no track_"):
        post(run, tracks=True)
    assert [p.name for p in post(run)] == ["gauge_a.png"]  # no case.toml needed


# ------------------------------------------------------------------ mean flow on a known field
T, OMEGA, A_WAVE, AMP, XC, YC = 1.0, 0.2, 0.05, 0.01, 0.5, 0.3


def _rotation_dataset():
    """A 3D test-point record with a known mean flow.

    A steady solid-body rotation U = -Omega (y - yc), V = Omega (x - xc), plus a progressive wave of
    period T: level eta = 0.2 + 0.01 x + a cos(w t - k x), wave velocity A cos(w t - k x) in u. The
    kernel sum is 1/2 + (eta - z) / 0.08 (clipped to [0, 1], so linear across the surface) above a bed
    z_b = 0.05 + 0.05 x (0 below it); velocities are NaN where the kernel sum is 0 (Shepard's empty
    support). Sampled 20 times per period over three periods.
    """
    x = np.linspace(0.0, 1.0, 11)
    y = np.linspace(0.0, 0.6, 7)
    z = np.linspace(0.01, 0.39, 20)
    t = np.arange(61) * T / 20
    k = 2 * np.pi
    Tt, Z, Y, X = np.meshgrid(t, z, y, x, indexing="ij")
    phase = 2 * np.pi * Tt / T - k * X
    eta = 0.2 + 0.01 * X + AMP * np.cos(phase)
    ks = np.clip(0.5 + (eta - Z) / 0.08, 0.0, 1.0)
    ks = np.where(Z < 0.05 + 0.05 * X, 0.0, ks)
    u = -OMEGA * (Y - YC) + A_WAVE * np.cos(phase)
    v = OMEGA * (X - XC) + 0 * Tt
    w = 0.02 * np.cos(phase)
    dry = ks == 0
    data = {n: (("time", "z", "y", "x"), np.where(dry, np.nan, f)) for n, f in (("u", u), ("v", v), ("w", w))}
    data["kernel_sum"] = (("time", "z", "y", "x"), ks)
    data["p"] = (("time", "z", "y", "x"), 1000 * 9.81 * np.maximum(eta - Z, 0))
    data["rho"] = (("time", "z", "y", "x"), np.full_like(ks, 1000.0))
    return xr.Dataset(data, coords={"time": t, "z": z, "y": y, "x": x})


def test_mean_flow_of_a_rotation_plus_a_wave():
    """Period-mean, depth-averaged: the vorticity is 2 Omega and the arrows are the rotation.

    The wave's velocity averages out over whole periods except for its correlation with the wet depth
    (the mean current is <q>/<h>, q the depth integral over the wet nodes): that Stokes drift depends on
    x only, so it leaves dU/dy and the vorticity exact (to rounding: the grid derivatives of linear fields
    are exact). It points the way the wave runs (u in phase with the crest) and is A a / (2 <h>) for a
    continuous depth; the wet depth is counted in nodes, off by up to dz, so it lies in
    (0, A (a/2 + dz) / <h>]. V is steady: exact. The mean level is exact where the kernel sum is
    linear across the surface (the trapezoidal rule integrates the sampled cosine over whole periods
    exactly), and always-wet nodes average the wave velocity to zero."""
    ds = _rotation_dataset()
    mf = mean_flow(ds, period=T, still_water_level=0.19)
    assert (mf.attrs["t_start"], mf.attrs["t_end"], mf.attrs["periods"]) == (0.0, 3.0, 3)
    x, y, z = ds["x"].values, ds["y"].values, ds["z"].values
    Y, X = np.meshgrid(y, x, indexing="ij")
    om = mf["vorticity"].transpose("y", "x").values
    np.testing.assert_allclose(om, 2 * OMEGA, rtol=1e-9)
    U, V = mf["U"].transpose("y", "x").values, mf["V"].transpose("y", "x").values
    np.testing.assert_allclose(V, OMEGA * (X - XC), atol=1e-12)
    drift = U - (-OMEGA * (Y - YC))
    np.testing.assert_allclose(drift, drift[:1].repeat(len(y), 0), atol=1e-12)  # a function of x only
    h = mf["depth"].isel(y=0).values
    assert np.all(drift[0] > 0) and np.all(drift[0] <= A_WAVE * (AMP / 2 + 0.02) / h)
    np.testing.assert_allclose(mf["level"].transpose("y", "x").values, 0.2 + 0.01 * X, atol=1e-9)
    np.testing.assert_allclose(mf["setup"].transpose("y", "x").values, 0.01 + 0.01 * X, atol=1e-9)
    # the bed: the first node above z_b
    bed = np.array([z[np.argmax(z >= 0.05 + 0.05 * xi)] for xi in x])
    np.testing.assert_allclose(mf["bed"].isel(y=0).values, bed)
    # node means: an always-wet node (z = 0.13 m, above the bed everywhere, below every trough)
    um = mf["u_mean"].sel(z=z[6]).transpose("y", "x").values
    np.testing.assert_allclose(um, -OMEGA * (Y - YC), atol=1e-9)
    assert np.isnan(mf["u_mean"].sel(z=z[-1])).all()  # dry all the time
    # the last two periods only
    assert mean_flow(ds, period=T, periods=2).attrs["t_start"] == 1.0
    with pytest.raises(InputError, match="holds 3 complete"):
        mean_flow(ds, period=T, periods=4)


def test_surface_levels_match_the_gauge_rule():
    from shoal.probes import surface_level

    rng = np.random.default_rng(0)
    z = np.linspace(0, 1, 12)
    ks = np.sort(rng.uniform(0, 1, (5, 12)), axis=1)[:, ::-1]
    ks[0] = 0.0
    ks[1] = 1.0
    got = surface_levels(ks, z)
    want = [surface_level(z, s) for s in ks]
    np.testing.assert_allclose(got, want, equal_nan=True)


def _synthetic_run(tmp_path, with_case=True):
    run = tmp_path / "synth"
    run.mkdir()
    _rotation_dataset().to_netcdf(run / "testpoints_rot.nc", engine="scipy")
    if with_case:
        (run / "case.toml").write_text('name = "synthetic"\ndim = 3\ndp = 0.02\n[fluid]\nsurface_level = 0.19\n'
                                       '[[motions]]\ntype = "piston"\nname = "p"\nperiod = 1.0\n')
    return run


def test_mean_flow_plots_of_a_3d_grid(tmp_path):
    run = _synthetic_run(tmp_path)
    assert run_info(run)["period"] == 1.0 and run_info(run)["surface_level"] == 0.19
    written = post(run, mean_flow=True, periods=2)
    assert sorted(p.name for p in written) == ["meanflow_rot_current.png", "meanflow_rot_profiles.png",
                                               "meanflow_rot_setup.png"]
    assert all(_is_png(p) for p in written)


def test_mean_flow_without_a_period_averages_the_whole_record(tmp_path):
    run = _synthetic_run(tmp_path, with_case=False)
    assert run_info(run)["period"] is None
    with pytest.raises(InputError, match="--periods 2: the record holds 1 complete"):
        post(run, mean_flow=True, periods=2)  # one "period": the whole record
    assert len(post(run, mean_flow=True, start=1.0)) == 3


# ------------------------------------------------------------------ 3D tracks and planes
def test_tracks_and_planes_of_a_3d_run(tmp_path):
    from shoal.output.pvd import PVDWriter
    from shoal.output.vtu import write_vtu

    run = tmp_path / "run3"
    run.mkdir()
    (run / "case.toml").write_text('name = "box"\ndim = 3\ndp = 0.05\n')
    g = np.arange(0.025, 0.5, 0.05)
    X, Y, Z = np.meshgrid(g, g, g[:6], indexing="ij")
    pos = np.column_stack([X.ravel(), Y.ravel(), Z.ravel()])
    vel = np.column_stack([-(pos[:, 1] - 0.25), pos[:, 0] - 0.25, np.zeros(len(pos))])
    kind = np.where(pos[:, 2] < 0.05, 1, 0)
    pvd = PVDWriter(run, "box")
    for k, t in enumerate((0.0, 0.5)):
        write_vtu(run / f"box_{k:04d}.vtu", pos, {"velocity": vel, "kind": kind}, time=t)
        pvd.add(t, f"box_{k:04d}.vtu")
    with open(run / "track_a.csv", "w", newline="") as f:
        wr = csv.writer(f)
        wr.writerow(["time", "x_1", "y_1", "z_1", "x_2", "y_2", "z_2"])
        for t in np.linspace(0, 1, 11):
            wr.writerow([t, 0.25 + 0.1 * np.cos(t), 0.25 + 0.1 * np.sin(t), 0.1, 0.1, 0.1 + 0.1 * t, 0.2])
    assert [p.name for p in plot_tracks(run, tmp_path / "o")] == ["track_a.png"]
    assert [p.name for p in plot_plane(run, tmp_path / "o", "z=0.12")] == ["plane_z0.12_t0.5.png"]
    assert [p.name for p in plot_plane(run, tmp_path / "o", "mid", time=0.1)] == ["plane_y0.25_t0.png"]
    assert all(_is_png(p) for p in (tmp_path / "o").iterdir())
    with pytest.raises(InputError, match="no fluid particle"):
        plot_plane(run, tmp_path / "o", "z=0.02")  # only wall particles there


def test_parse_plane():
    assert parse_plane("z=0.05") == (2, 0.05)
    assert parse_plane(" Y = -1e-2 ") == (1, -0.01)
    assert parse_plane("mid") == (None, None)
    for bad in ("z", "w=1", "z=nan", "z=1=2", ""):
        with pytest.raises(InputError, match="AXIS=VALUE"):
            parse_plane(bad)
