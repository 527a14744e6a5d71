"""Tests for shoal.output.plot_case: the PNG of a case's initial geometry."""

from pathlib import Path

import numpy as np
import pytest
from matplotlib.image import imread

from shoal.errors import InputError
from shoal.output.plot_case import _subsample, plot_case

PNG_MAGIC = b"\x89PNG\r\n\x1a\n"
BLUE = np.array([0x1F, 0x77, 0xB4]) / 255.0      # tab:blue, the fluid
ORANGE = np.array([0xFF, 0x7F, 0x0E]) / 255.0    # tab:orange, a moving boundary


def _case(dim, length=1.0, width=0.3, height=0.5, depth=0.3, dp=0.02):
    """Fluid box, bottom/side/end walls (body 0) and a moving wall (body 1)."""
    xs = np.arange(0.0, length, dp)
    ys = np.arange(0.0, width, dp) if dim == 3 else np.zeros(1)
    zs = np.arange(0.0, height, dp)
    grid = np.stack(np.meshgrid(xs, ys, zs, indexing="ij"), axis=-1).reshape(-1, 3)
    x, y, z = grid.T
    side = (y < 2 * dp) | (y > width - 2 * dp) if dim == 3 else np.zeros(len(grid), bool)
    wall = (z < 2 * dp) | (x > length - 2 * dp) | side
    paddle = ~wall & (x > 0.1) & (x < 0.1 + 2 * dp)
    fluid = ~wall & (x > 0.2) & (z < depth)
    sel = wall | paddle | fluid
    kinds = np.select([fluid, wall, paddle], [0, 1, 2])[sel]
    body = np.select([fluid, wall, paddle], [-1, 0, 1])[sel]
    return grid[sel], kinds, body


def _read_png(path):
    path = Path(path)
    assert path.is_file()
    assert path.read_bytes()[:8] == PNG_MAGIC
    img = imread(path)
    assert img.ndim == 3 and img.shape[2] in (3, 4)
    return img


def _n_colours(img):
    rgb = np.round(img[..., :3] * 255).astype(np.int32).reshape(-1, 3)
    return len(np.unique(rgb[:, 0] * 65536 + rgb[:, 1] * 256 + rgb[:, 2]))


def _fraction_near(img, colour, tol=0.03):
    return float(np.mean(np.all(np.abs(img[..., :3] - colour) < tol, axis=-1)))


def test_plot_case_2d(tmp_path):
    pos, kinds, _ = _case(2, length=0.73, height=0.44, depth=0.3, dp=0.01)
    out = plot_case(tmp_path / "case2d.png", pos, kinds, dim=2, title="2D tank", dp=0.01)
    assert out == tmp_path / "case2d.png"
    img = _read_png(out)
    h, w = img.shape[:2]
    assert 800 <= w <= 2400 and 400 <= h <= 2000
    assert _n_colours(img) > 3
    assert _fraction_near(img, BLUE) > 0.02      # the fluid is visible
    assert _fraction_near(img, ORANGE) > 0.0     # and the moving wall
    assert not (tmp_path / "case2d.png.tmp").exists()


def test_plot_case_3d_with_bodies(tmp_path):
    pos, kinds, body = _case(3, length=3.0, width=0.3, height=0.5, depth=0.3, dp=0.02)
    out = plot_case(tmp_path / "sub" / "case3d.png", pos, kinds, body=body,
                    body_names=["flume", "paddle"], dim=3, title="3D flume", dp=0.02)
    img = _read_png(out)
    h, w = img.shape[:2]
    assert w > h > 300                           # a long flume gives a wide figure
    assert _n_colours(img) > 3
    # Fluid is drawn over the side walls in the side view: plenty of blue.
    assert _fraction_near(img, BLUE) > 0.02
    assert _fraction_near(img, ORANGE) > 0.0


def test_plot_case_3d_without_dp_or_body(tmp_path):
    pos, kinds, _ = _case(3, length=1.0, width=1.0, height=1.0, depth=0.5, dp=0.05)
    img = _read_png(plot_case(str(tmp_path / "cube.png"), pos, kinds, dim=3))
    assert _n_colours(img) > 3


def test_plot_case_subsample(tmp_path):
    pos, kinds, body = _case(2, dp=0.01)
    n = len(pos)
    out = plot_case(tmp_path / "sub.png", pos, kinds, body=body, dim=2, title="t",
                    dp=0.01, max_points=300)
    assert _n_colours(_read_png(out)) > 3

    idx, note = _subsample(n, 300)
    assert len(idx) == 300 and len(np.unique(idx)) == 300
    assert np.all(np.diff(idx) > 0) and idx[-1] < n
    np.testing.assert_array_equal(idx, _subsample(n, 300)[0])   # fixed seed
    assert f"300 of {n:,}" in note
    idx, note = _subsample(n, n)
    assert len(idx) == n and note == ""


@pytest.mark.parametrize("change", [
    "kinds_short", "body_short", "empty", "positions_2col", "bad_kind", "nan", "bad_dim",
    "bad_dp", "bad_max_points",
])
def test_plot_case_bad_input(tmp_path, change):
    pos, kinds, body = _case(2, dp=0.05)
    args = dict(positions=pos, kinds=kinds, body=body, dim=2, dp=0.05, max_points=1000)
    if change == "kinds_short":
        args["kinds"] = kinds[:-1]
    elif change == "body_short":
        args["body"] = body[1:]
    elif change == "empty":
        args.update(positions=np.zeros((0, 3)), kinds=np.zeros(0, int), body=None)
    elif change == "positions_2col":
        args["positions"] = pos[:, :2]
    elif change == "bad_kind":
        args["kinds"] = np.where(kinds == 2, 5, kinds)
    elif change == "nan":
        args["positions"] = pos.copy()
        args["positions"][3, 0] = np.nan
    elif change == "bad_dim":
        args["dim"] = 1
    elif change == "bad_dp":
        args["dp"] = -0.01
    elif change == "bad_max_points":
        args["max_points"] = 0
    with pytest.raises(InputError) as err:
        plot_case(tmp_path / "bad.png", **args)
    assert "\n" not in str(err.value)
    assert not (tmp_path / "bad.png").exists()
