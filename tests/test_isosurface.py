"""The free-surface mesh (`shoal.output.isosurface`, `shoal post --isosurface`)."""

import numpy as np
import pytest

import shoal
from shoal.cases import dam_break_2d, still_water_3d
from shoal.cli import main
from shoal.model import Model
from shoal.output.isosurface import enclosed_volume, surface_mesh
from shoal.runner import build_model


def _ball(dim, dp=0.01, R=0.1):
    """A lattice ball (disc in 2D) of fluid particles of radius R = 10 dp round (0.5, 0.5, 0.5), no walls."""
    ax = (np.arange(-12, 12) + 0.5) * dp
    g = np.stack(np.meshgrid(*[ax] * dim, indexing="ij"), -1).reshape(-1, dim)
    g = g[np.linalg.norm(g, axis=1) <= R] + 0.5
    pos = g if dim == 3 else np.column_stack([g[:, 0], np.zeros(len(g)), g[:, 1]])
    lo, hi = (0.2, 0.2 if dim == 3 else 0.0, 0.2), (0.8, 0.8 if dim == 3 else 0.0, 0.8)
    m = Model(pos, np.zeros(len(pos), np.int8), dp=dp, dim=dim, domain=(lo, hi), u_max=1.0)
    m.sort()
    return m, len(pos)


@pytest.mark.parametrize("dim", [3, 2])
def test_a_ball_of_particles_gives_a_sphere(dim):
    """The kernel-sum level 1/2 round a lattice ball of particles: every vertex lies within 0.15 dp of the
    sphere (circle) holding the particles' volume N dp^dim (measured 3D: mean -0.086 dp, spread 0.064 dp;
    2D: -0.028 / 0.13 dp), the mesh is closed (its enclosed volume is that of its mean radius within
    0.5 %) and its normals point out of the water (3D; 2D: anticlockwise in x-z)."""
    m, n = _ball(dim)
    dp = m.dp
    pts, (kind, conn) = surface_mesh(m)
    assert kind == ("triangle" if dim == 3 else "line")
    c = np.array([0.5, 0.5 if dim == 3 else 0.0, 0.5])
    r = np.linalg.norm(pts - c, axis=1)
    Vp = n * dp**dim
    R_eff = (3 * Vp / (4 * np.pi)) ** (1 / 3) if dim == 3 else np.sqrt(Vp / np.pi)
    assert np.max(np.abs(r - R_eff)) < 0.3 * dp and abs(r.mean() - R_eff) < 0.15 * dp and r.std() < 0.15 * dp
    V = enclosed_volume(pts, (kind, conn), dim)
    V_r = 4 / 3 * np.pi * r.mean() ** 3 if dim == 3 else np.pi * r.mean() ** 2
    assert V == pytest.approx(V_r, rel=0.005)
    if dim == 3:
        a, b, d = pts[conn[:, 0]], pts[conn[:, 1]], pts[conn[:, 2]]
        normal = np.cross(b - a, d - a)
        assert np.all(np.einsum("ij,ij->i", normal, (a + b + d) / 3 - c) > 0)


def test_still_water_surface_is_the_still_water_level():
    """A 3D tank of still water on its lattice: the mesh's top, away from the walls, is the still-water
    level within 0.05 dp (measured 0.002 dp below), as a wave gauge must read it (within 0.5 dp); the
    whole water body is closed round by the mesh along the walls: its volume is the particles' within 4 %
    (measured -2.7 %: the edges and corners are rounded over a kernel radius)."""
    case = still_water_3d(dp=0.02)
    m = build_model(case)
    m.sort()
    pts, cells = surface_mesh(m)
    pos, kinds, _ = m.owned_particles()
    fl = pos[kinds == 0]
    level = case.fluid.surface_level
    inner = (np.abs(pts[:, 0] - fl[:, 0].mean()) < 0.25 * np.ptp(fl[:, 0])) & \
            (np.abs(pts[:, 1] - fl[:, 1].mean()) < 0.25 * np.ptp(fl[:, 1])) & (pts[:, 2] > level - 3 * case.dp)
    assert inner.sum() > 50
    assert np.max(np.abs(pts[inner, 2] - level)) < 0.05 * case.dp
    assert enclosed_volume(pts, cells, 3) == pytest.approx(len(fl) * case.dp**3, rel=0.04)


def test_bad_level_and_spacing_are_input_errors():
    m, _ = _ball(2)
    with pytest.raises(shoal.errors.InputError, match="allowed 0 < level < 1"):
        surface_mesh(m, level=1.0)
    with pytest.raises(shoal.errors.InputError, match="allowed > 0"):
        surface_mesh(m, spacing=0.0)


@pytest.fixture(scope="module")
def dam_run(tmp_path_factory):
    """A 2D dam break (dp = a/12, 1,000 fluid particles) to t = 0.2 s (T = t sqrt(2g/a) = 2.3), 5 snapshots."""
    out = tmp_path_factory.mktemp("iso") / "run"
    case = dam_break_2d(dp=0.146 / 12, end_time=0.2, output_interval=0.05)
    shoal.run_case(case, out, plot=False, progress=False)
    return case, out


def test_post_isosurface_writes_a_mesh_series_that_keeps_the_water(dam_run, capsys):
    """`shoal post RUN --isosurface`: one .vtu per snapshot and a .pvd, only those (no PNGs); each a set
    of closed polylines in the x-z plane whose enclosed area is the water's, N dp^2, within 3 % at every
    snapshot of the collapsing column (the surface follows the water, none is lost or made)."""
    import meshio

    from shoal.output import read_pvd

    case, run = dam_run
    rc = main(["post", str(run), "--isosurface", "--out", str(run / "p")])
    out = capsys.readouterr().out
    assert rc == 0
    assert out.splitlines()[0] == "shoal: wrote 0 PNG(s) and 6 iso-surface file(s):"
    entries = read_pvd(run / "p" / "isosurface" / "dam-break-2d_surface.pvd")
    assert [t for t, _ in entries] == pytest.approx([0.0, 0.05, 0.1, 0.15, 0.2])
    area0 = case.n_fluid * case.dp**2
    for _, name in entries:
        mesh = meshio.read(run / "p" / "isosurface" / name)
        lines = mesh.cells_dict["line"]
        assert np.all(mesh.points[:, 1] == 0.0)
        assert enclosed_volume(mesh.points, ("line", lines), 2) == pytest.approx(area0, rel=0.03)
    assert sorted(p.name for p in (run / "p").iterdir()) == ["isosurface"]


@pytest.mark.parametrize("args, message", [
    (["--isosurface", "--iso-level", "1.5"], "allowed 0 < level < 1"),
    (["--isosurface", "--iso-spacing", "-1"], "--iso-spacing"),
    (["--isosurface", "--backend", "tpu"], "tpu"),
    (["--isosurface", "--iso-spacing", "1e-7"], "give a larger spacing"),  # refused at the first snapshot
])
def test_post_isosurface_bad_input_is_one_line(dam_run, tmp_path, capsys, args, message):
    _, run = dam_run
    rc = main(["post", str(run), "--out", str(tmp_path / "o"), *args])
    err = capsys.readouterr().err
    assert rc == 2 and err.startswith("shoal: error: ") and err.count("\n") == 1 and message in err, err
    assert not (tmp_path / "o").exists() or not any((tmp_path / "o").rglob("*.vtu"))
    assert not (tmp_path / "o").exists() or not any((tmp_path / "o").rglob("*.pvd"))  # no empty collection
