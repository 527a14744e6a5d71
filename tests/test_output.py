"""Tests for shoal.output: VTU snapshots, PVD collection and PNG plots."""

import xml.etree.ElementTree as ET

import meshio
import numpy as np
import pytest

from shoal.output import PVDWriter, plot_particles, read_vtu, write_vtu

PNG_MAGIC = b"\x89PNG\r\n\x1a\n"


def _particles(n, dtype, seed=0):
    rng = np.random.default_rng(seed)
    points = rng.random((n, 3)).astype(dtype)
    points[:, 1] = 0.0
    data = {
        "velocity": rng.normal(size=(n, 3)).astype(dtype),
        "density": (1000.0 + rng.normal(size=n)).astype(dtype),
        "pressure": rng.normal(scale=1e4, size=n).astype(dtype),
        "id": rng.permutation(n).astype(np.int64),
        "id32": np.arange(n, dtype=np.int32),
        "kind": rng.integers(0, 3, size=n).astype(np.int8),
        "kind_u8": rng.integers(0, 3, size=n).astype(np.uint8),
    }
    return points, data


@pytest.mark.parametrize("dtype", [np.float32, np.float64])
def test_vtu_roundtrip_exact(tmp_path, dtype):
    points, data = _particles(50, dtype)
    path = tmp_path / "snap_000001.vtu"
    write_vtu(path, points, data, time=0.125)

    pts, pdata = read_vtu(path)
    assert pts.dtype == dtype
    np.testing.assert_array_equal(pts, points)
    assert set(pdata) == set(data)
    for name in ("velocity", "density", "pressure"):
        assert pdata[name].dtype == dtype
        assert pdata[name].shape == data[name].shape
        np.testing.assert_array_equal(pdata[name], data[name])
    assert pdata["id"].dtype == np.int64
    assert pdata["id32"].dtype == np.int32
    np.testing.assert_array_equal(pdata["id"], data["id"])
    np.testing.assert_array_equal(pdata["id32"], data["id32"])
    # int8/uint8 are widened to int32 for ParaView, values unchanged.
    for name in ("kind", "kind_u8"):
        assert pdata[name].dtype == np.int32
        np.testing.assert_array_equal(pdata[name], data[name].astype(np.int32))

    # One vertex cell per particle, and the time as TimeValue field data.
    mesh = meshio.read(path)
    assert [block.type for block in mesh.cells] == ["vertex"]
    np.testing.assert_array_equal(mesh.cells[0].data.ravel(), np.arange(50))
    np.testing.assert_array_equal(mesh.field_data["TimeValue"], [0.125])


def test_vtu_is_valid_vtk_xml(tmp_path):
    points, data = _particles(50, np.float64)
    path = tmp_path / "snap.vtu"
    write_vtu(path, points, data, time=2.5)

    text = path.read_text()
    assert '<VTKFile type="UnstructuredGrid"' in text
    root = ET.parse(path).getroot()
    assert root.tag == "VTKFile"
    assert root.get("type") == "UnstructuredGrid"
    assert root.get("compressor") == "vtkZLibDataCompressor"
    piece = root.find("UnstructuredGrid/Piece")
    assert piece.get("NumberOfPoints") == "50"
    assert piece.get("NumberOfCells") == "50"
    names = {da.get("Name") for da in piece.iterfind("PointData/DataArray")}
    assert names == set(data)
    velocity = piece.find("PointData/DataArray[@Name='velocity']")
    assert velocity.get("NumberOfComponents") == "3"
    time = root.find("UnstructuredGrid/FieldData/DataArray[@Name='TimeValue']")
    assert float(time.text) == 2.5
    # No temporary files left behind.
    assert sorted(p.name for p in tmp_path.iterdir()) == ["snap.vtu"]


def test_vtu_without_time_and_overwrite(tmp_path):
    path = tmp_path / "snap.vtu"
    points, data = _particles(10, np.float64, seed=1)
    write_vtu(path, points, data, time=1.0)
    points2, data2 = _particles(20, np.float64, seed=2)
    write_vtu(str(path), points2, {"density": data2["density"]})

    pts, pdata = read_vtu(path)
    np.testing.assert_array_equal(pts, points2)
    assert list(pdata) == ["density"]
    np.testing.assert_array_equal(pdata["density"], data2["density"])
    assert "TimeValue" not in meshio.read(path).field_data
    assert sorted(p.name for p in tmp_path.iterdir()) == ["snap.vtu"]


def test_vtu_empty(tmp_path):
    path = tmp_path / "empty.vtu"
    write_vtu(path, np.zeros((0, 3)), {"velocity": np.zeros((0, 3)),
                                      "kind": np.zeros(0, np.int8)}, time=0.0)
    pts, pdata = read_vtu(path)
    assert pts.shape == (0, 3)
    assert pdata["velocity"].shape == (0, 3)
    assert pdata["kind"].shape == (0,)
    assert pdata["kind"].dtype == np.int32


def test_vtu_rejects_bad_shapes(tmp_path):
    points, data = _particles(5, np.float64)
    with pytest.raises(ValueError):
        write_vtu(tmp_path / "a.vtu", points[:, :2], data)
    with pytest.raises(ValueError):
        write_vtu(tmp_path / "a.vtu", points, {"density": np.zeros(4)})
    assert list(tmp_path.iterdir()) == []


def _parse_pvd(path):
    root = ET.parse(path).getroot()
    assert root.tag == "VTKFile"
    assert root.get("type") == "Collection"
    datasets = root.findall("Collection/DataSet")
    for ds in datasets:
        assert ds.get("group") == ""
        assert ds.get("part") == "0"
    return [(float(ds.get("timestep")), ds.get("file")) for ds in datasets]


def test_pvd_lists_entries_in_order(tmp_path):
    writer = PVDWriter(tmp_path, "run")
    pvd = tmp_path / "run.pvd"
    assert pvd.exists()
    assert _parse_pvd(pvd) == []

    times = [0.0, 0.1, 0.30000000000000004, 1.0 / 3.0, 12.5]
    for i, t in enumerate(times):
        writer.add(t, f"run_{i:06d}.vtu")
        # Rewritten after every add, so a crash keeps everything so far.
        assert _parse_pvd(pvd) == [(tt, f"run_{j:06d}.vtu")
                                   for j, tt in enumerate(times[: i + 1])]
    assert writer.entries() == [(t, f"run_{i:06d}.vtu") for i, t in enumerate(times)]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["run.pvd"]


def test_pvd_absolute_filename_made_relative(tmp_path):
    writer = PVDWriter(tmp_path, "run")
    writer.add(0.5, tmp_path / "vtu" / "run_000000.vtu")
    assert _parse_pvd(tmp_path / "run.pvd") == [(0.5, "vtu/run_000000.vtu")]


def test_pvd_resume_keeps_entries(tmp_path):
    first = PVDWriter(tmp_path, "run")
    first.add(0.0, "a.vtu")
    first.add(0.25, "b.vtu")

    resumed = PVDWriter(tmp_path, "run", resume=True)
    assert resumed.entries() == [(0.0, "a.vtu"), (0.25, "b.vtu")]
    resumed.add(0.5, "c.vtu")
    assert _parse_pvd(tmp_path / "run.pvd") == [
        (0.0, "a.vtu"), (0.25, "b.vtu"), (0.5, "c.vtu")]

    resumed.truncate(0.25)
    assert _parse_pvd(tmp_path / "run.pvd") == [(0.0, "a.vtu"), (0.25, "b.vtu")]

    fresh = PVDWriter(tmp_path, "run")  # resume=False starts over
    assert fresh.entries() == []
    assert _parse_pvd(tmp_path / "run.pvd") == []


def test_pvd_resume_without_file_and_bad_file(tmp_path):
    writer = PVDWriter(tmp_path / "new", "run", resume=True)
    assert writer.entries() == []
    assert _parse_pvd(tmp_path / "new" / "run.pvd") == []

    (tmp_path / "bad.pvd").write_text("<VTKFile type='Collection'><Coll")
    with pytest.raises(ValueError):
        PVDWriter(tmp_path, "bad", resume=True)
    with pytest.raises(ValueError):
        writer.add(float("nan"), "x.vtu")


@pytest.mark.parametrize("dim", [2, 3])
def test_plot_particles_writes_png(tmp_path, dim):
    rng = np.random.default_rng(3)
    n = 500
    points = rng.random((n, 3))
    if dim == 2:
        points[:, 1] = 0.0
    kind = (points[:, 0] < 0.1).astype(np.int8)
    speed = np.linalg.norm(rng.normal(size=(n, 3)), axis=1)
    path = tmp_path / "frame.png"
    plot_particles(path, points, speed, kind=kind, title="t = 0.5 s",
                   value_label="|u| [m/s]", dim=dim)

    raw = path.read_bytes()
    assert raw[:8] == PNG_MAGIC
    assert len(raw) > 1000
    # Image is not blank: several distinct colours (boundary grey + colormap).
    import matplotlib.image as mpimg

    img = mpimg.imread(path)
    assert img.ndim == 3 and img.shape[0] > 100 and img.shape[1] > 100
    colours = np.unique(img.reshape(-1, img.shape[2]).round(2), axis=0)
    assert len(colours) > 20
    assert sorted(p.name for p in tmp_path.iterdir()) == ["frame.png"]


def test_plot_particles_all_fluid_and_bad_dim(tmp_path):
    points = np.random.default_rng(4).random((100, 3))
    plot_particles(tmp_path / "a.png", points, points[:, 2])
    assert (tmp_path / "a.png").read_bytes()[:8] == PNG_MAGIC
    with pytest.raises(ValueError):
        plot_particles(tmp_path / "b.png", points, points[:, 2], dim=1)
