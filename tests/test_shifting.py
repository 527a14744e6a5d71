"""Particle shifting (``shifting = "delta_plus"``: Sun, Colagrossi, Marrone & Zhang 2017,
`shoal.physics.shifting`): a regular lattice stays put, a disordered one becomes more regular, the free
surface of still water does not move along its normal, and the option goes through a case file (the CUDA
kernels against the CPU's: `tests/test_cuda_parity.py::test_particle_shifting_matches_cpu`).

Small 2D tanks (dp = 20 mm, a few hundred particles), so the module runs in well under a minute on one
core once Numba's cache is warm.
"""

import numpy as np
import pytest

from shoal.cases import still_water_2d
from shoal.errors import InputError
from shoal.options import SPHOptions
from shoal.runner import build_model
from shoal.simulation import Simulation

DP = 0.02


def _tank(shifting="delta_plus", precision="float32", backend="cpu", depth=0.2, length=0.4):
    case = still_water_2d(dp=DP, depth=depth, length=length, end_time=10.0,
                          options=SPHOptions(shifting=shifting, precision=precision))
    return case, build_model(case, backend)


def _by_id(m, a):
    out = np.zeros((m.n_total,) + m.host(a).shape[1:], m.host(a).dtype)
    out[m.host(m.idp)] = m.host(a)
    return out


def _set_rows(m, name, values):
    """Set a per-particle array of `m` (in its current row order) on either backend."""
    a = getattr(m, name)
    if m.backend.host_memory:
        a[:m.n] = values
    else:
        a.copy_to_device(np.ascontiguousarray(values, dtype=a.dtype))


def test_regular_lattice_is_not_moved():
    """A tank's lattice at uniform density (walls, corners and free surface included): every term of the
    sum cancels with its mirror, and the free-surface rows keep only their (zero) tangential part. Shift
    below 1e-6 dp (float32 sums of terms of order 1: round-off)."""
    _, m = _tank()
    m.sort()
    _set_rows(m, "rho", np.full(m.n, m.rho0))
    p0 = _by_id(m, m.pos)
    m.apply_shifting()
    moved = np.abs(_by_id(m, m.pos) - p0).max() / m.dp
    print(f"largest shift on a lattice: {moved:.2e} dp")
    assert moved < 1e-6


def _interior(m, pos, kind, surface_z, margin):
    """Fluid particles farther than `margin` from the walls and below the surface."""
    x, z = pos[:, 0], pos[:, 1]
    fluid = kind == 0
    xs, zs = pos[fluid, 0], pos[fluid, 1]
    return fluid & (x > xs.min() + margin) & (x < xs.max() - margin) & (z > zs.min() + margin) & (
        z < surface_z - margin)


def _nn_spread(pos, rows):
    """Standard deviation of the nearest-neighbour distance over `rows` (all particles as neighbours)."""
    from scipy.spatial import cKDTree

    d, _ = cKDTree(pos).query(pos[rows], k=2)
    return float(np.std(d[:, 1]))


def test_perturbed_lattice_becomes_more_regular():
    """The lattice of a tank, each fluid particle displaced at random by up to 0.15 dp along each axis
    (uniform density, no flow: the shifting alone, 60 passes with a re-sort before each, as 60 steps'
    stages would): the spread of the nearest-neighbour distance of the submerged particles (more than 2h
    from the walls and the surface) falls by at least a factor 2."""
    _, m = _tank()
    rng = np.random.default_rng(3)
    kind = m.host(m.kind).copy()
    pos = m.host(m.pos).copy()
    fluid = kind == 0
    top = pos[fluid, 1].max()
    pos[fluid] += 0.15 * m.dp * rng.uniform(-1, 1, size=(int(fluid.sum()), 2))
    _set_rows(m, "pos", pos)
    rows = _interior(m, pos, kind, top, 2 * m.h)
    ids = m.host(m.idp).copy()
    before = _nn_spread(pos, rows)
    for _ in range(60):
        m.sort()
        _set_rows(m, "rho", np.full(m.n, m.rho0))
        m.apply_shifting()
    after_pos = _by_id(m, m.pos)[ids]
    after = _nn_spread(after_pos, rows)
    print(f"nearest-neighbour distance spread: {before / m.dp:.4f} dp -> {after / m.dp:.4f} dp "
          f"({before / after:.2f} times less) over {int(rows.sum())} submerged particles")
    assert after < before / 2


def _surface_level(case, m, steps):
    """Mean height of the particles of the initial top layer after `steps` steps."""
    p = case.particles()
    fluid = p.kinds == 0
    top_ids = np.flatnonzero(fluid & np.isclose(p.positions[:, 2], p.positions[fluid, 2].max()))
    Simulation(m, 10.0).run(max_steps=steps)
    return float(_by_id(m, m.pos)[top_ids, 1].mean()), top_ids


def test_free_surface_of_still_water_is_not_moved_along_its_normal():
    """A free-surface particle keeps only the tangential part of its shift: in one pass over the
    hydrostatic tank (density rising with depth, so the interior particles do shift) the top layer's
    heights change by round-off only (below 1e-7 dp: the projection in float32 of a shift capped at
    0.1 dp leaves a few float32 ulps of it, 0.1 x 6e-8 x a few; the interior's vertical shifts are
    two orders above); and after 300 steps of the still tank the top layer's mean
    height with shifting is within 0.02 dp of that without."""
    case, m = _tank()
    m.sort()
    p0 = _by_id(m, m.pos)
    m.apply_shifting()
    p1 = _by_id(m, m.pos)
    fluid = case.particles().kinds == 0
    z = case.particles().positions[:, 2]
    top = fluid & np.isclose(z, z[fluid].max())
    dz_top = np.abs(p1[top, 1] - p0[top, 1]).max() / m.dp
    dz_inside = np.abs(p1[fluid & ~top, 1] - p0[fluid & ~top, 1]).max() / m.dp
    print(f"one pass: top layer's |dz| <= {dz_top:.1e} dp, the interior's up to {dz_inside:.1e} dp")
    assert dz_top < 1e-7 and dz_inside > 1e-6
    levels = {}
    for shifting in ("none", "delta_plus"):
        case, m = _tank(shifting)
        levels[shifting], _ = _surface_level(case, m, 300)
    diff = abs(levels["delta_plus"] - levels["none"]) / DP
    print(f"top layer's mean height after 300 steps: {levels['none']:.6f} m without, "
          f"{levels['delta_plus']:.6f} m with shifting ({diff:.4f} dp apart)")
    assert diff < 0.02


def test_option_round_trips_through_a_case_file_and_a_bad_value_is_one_line(tmp_path):
    from shoal.casefile import load_case, write_case

    case = still_water_2d(dp=DP, depth=0.2, length=0.4,
                          options=SPHOptions(shifting="delta_plus", shifting_coef=0.5))
    path = tmp_path / "case.toml"
    write_case(case, path)
    back = load_case(path)
    assert back.options.shifting == "delta_plus" and back.options.shifting_coef == 0.5
    assert SPHOptions().shifting == "none"  # off unless asked for
    text = path.read_text()
    bad = tmp_path / "bad.toml"
    bad.write_text(text.replace('shifting = "delta_plus"', 'shifting = "lind"'))
    assert 'shifting = "lind"' in bad.read_text()
    with pytest.raises(InputError) as info:
        load_case(bad)
    msg = str(info.value)
    assert "\n" not in msg and "shifting" in msg and "'delta_plus'" in msg, msg
    for value, words in (("bogus", ["'bogus'", "'none'"]), (0.0, ["shifting_coef", "> 0"])):
        key = "shifting" if isinstance(value, str) else "shifting_coef"
        with pytest.raises(InputError) as info:
            SPHOptions(**{key: value})
        assert "\n" not in str(info.value) and all(w in str(info.value) for w in words)
