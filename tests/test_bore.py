"""Bore relations: the Belanger state satisfies mass and momentum conservation across the front."""

import math

import numpy as np
import pytest

from shoal.analysis import arrival_time, bore_from_inflow, celerity
from shoal.errors import InputError


@pytest.mark.parametrize("U", [0.3, 0.7, 1.5])
def test_belanger_state_conserves_mass_and_momentum(U):
    """In the bore's frame water arrives at U + c with depth d0 and leaves at c with depth d1:
    (U + c) d0 = c d1 and (U + c)^2 d0 + g d0^2/2 = c^2 d1 + g d1^2/2 (per unit width)."""
    g, d0 = 9.81, 0.1
    c, d1, fr = bore_from_inflow(U, d0, g)
    assert (U + c) * d0 == pytest.approx(c * d1, rel=1e-9)
    assert (U + c) ** 2 * d0 + g * d0**2 / 2 == pytest.approx(c**2 * d1 + g * d1**2 / 2, rel=1e-9)
    assert fr == pytest.approx((U + c) / math.sqrt(g * d0), rel=1e-12)
    assert d1 > d0 and c > 0


def test_tidal_bore_paper_regimes():
    """U = 0.3 m/s gives an undular bore (Fr < ~1.3) and 0.7 m/s a breaking one (Fr > 1.5)
    (the paper quotes Fr = 1.19 and 1.63 from its measurements)."""
    assert bore_from_inflow(0.3, 0.1)[2] == pytest.approx(1.24, abs=0.01)
    assert bore_from_inflow(0.7, 0.1)[2] == pytest.approx(1.59, abs=0.01)


def test_celerity_from_gauge_arrivals():
    c = 0.93
    xs = np.array([0.5, 1.0, 1.5])
    t = np.linspace(0, 3, 3001)
    arrivals = []
    for x in xs:
        level = 0.1 + 0.03 * (t > x / c)
        arrivals.append(arrival_time(t, level, 0.115))
    assert celerity(xs, arrivals) == pytest.approx(c, rel=2e-3)
    assert math.isnan(arrival_time(t, np.zeros_like(t), 0.1))


def test_undulations_count_secondary_waves_not_noise():
    """A front followed by decaying secondary waves (period 0.5 s) has crests, the first above d1;
    a smooth rise to d1 with 0.5 % noise has none."""
    from shoal.analysis import undulations

    rng = np.random.default_rng(0)
    d0, d1 = 0.1, 0.13
    t = np.linspace(0, 3, 601)
    ta = 1.0
    s = np.clip((t - ta) / 0.1, 0, 1)
    und = d0 + (d1 - d0) * s + 0.012 * s * np.exp(-(t - ta) / 1.5) * np.sin(2 * np.pi * (t - ta) / 0.5)
    n, first = undulations(t, und, ta, d1)
    assert n >= 2 and first > 0.05
    smooth = d0 + (d1 - d0) * 0.5 * (1 + np.tanh((t - ta) / 0.05)) + 0.0005 * rng.standard_normal(len(t))
    n, first = undulations(t, smooth, ta, d1)
    assert n == 0 and abs(first) < 0.03


def test_crest_speed_ratio_of_a_linear_wave_is_ka_coth_kd():
    """Under a linear progressive wave eta = a cos(kx) (Airy), u = a w cosh(k z) / sinh(k d) cos(kx) with
    z from the bed: the crest's surface particle at z = d + a moves at a w cosh(k (d + a)) / sinh(k d), so
    the index is that over c = w / k; particles below the mid level d0 + (d1 - d0)/2 are ignored, and a
    wave travelling towards -x is measured along -x."""
    from shoal.analysis import crest_speed_ratio
    from shoal.motions import wavenumber

    T, d, a = 1.2, 0.4, 0.03
    k = wavenumber(T, d)
    w = 2 * np.pi / T
    x = np.linspace(0, 2 * np.pi / k, 201)
    zs = np.linspace(0, 1, 21)
    X, S = np.meshgrid(x, zs)
    Z = S * (d + a * np.cos(k * X))  # columns from the bed to the surface
    U = a * w * np.cosh(k * Z) / np.sinh(k * d) * np.cos(k * X)
    pos = np.column_stack([X.ravel(), 0 * X.ravel(), Z.ravel()])
    vel = np.column_stack([U.ravel(), 0 * X.ravel(), 0 * X.ravel()])
    expected = a * w * np.cosh(k * (d + a)) / np.sinh(k * d) / (w / k)
    # d0 = d - a, d1 = d + a: the raised water is the top half of the wave
    assert crest_speed_ratio(pos, vel, d - a, d + a, w / k) == pytest.approx(expected, rel=1e-12)
    assert expected == pytest.approx(0.123, abs=1e-3)  # ka coth(kd) = 0.113, times cosh(k(d+a))/cosh(kd): far from breaking
    back = vel * -1
    assert crest_speed_ratio(pos, back, d - a, d + a, w / k, direction=-1.0) == pytest.approx(expected, rel=1e-12)
    assert crest_speed_ratio(pos, vel, d + 2 * a, d + 3 * a, w / k) == 0.0  # nothing above the mid level
    with pytest.raises(InputError, match="celerity"):
        crest_speed_ratio(pos, vel, d - a, d + a, 0.0)


@pytest.mark.parametrize("dim", [2, 3])
def test_volume_depth_of_a_lattice_is_its_depth(dim):
    """Water d = 0.18 m deep on a lattice of spacing dp, with hydrostatic densities: sum m / rho per unit
    area is d (particle volumes tile the column) to the compression, rho / rho0 - 1 below 1e-3, in 2D and
    in a 3D flume 0.15 m wide; a window of any length gives the same depth; disordering the particles
    inside the window leaves it unchanged (a volume, not a surface)."""
    from shoal.analysis import volume_depth

    dp, d, B = 0.005, 0.18, 0.15
    xs = (np.arange(200) + 0.5) * dp
    zs = (np.arange(int(round(d / dp))) + 0.5) * dp
    ys = (np.arange(int(round(B / dp))) + 0.5) * dp if dim == 3 else np.array([0.0])
    X, Y, Z = np.meshgrid(xs, ys, zs, indexing="ij")
    pos = np.c_[X.ravel(), Y.ravel(), Z.ravel()]
    rho0, B_tait = 1000.0, 1.6e5
    rho = rho0 * (1 + rho0 * 9.81 * (d - pos[:, 2]) / B_tait) ** (1 / 7)
    mass = rho0 * dp**dim
    w = None if dim == 2 else B
    for half in (0.05, 0.1):
        got = volume_depth(pos, rho, mass, 0.5, half, width=w)
        assert got == pytest.approx(d, rel=1.5e-3)
        assert got < d  # compressed water takes less room
    rng = np.random.default_rng(3)
    inside = np.abs(pos[:, 0] - 0.5) < 0.1 - dp
    shaken = pos.copy()
    shaken[inside, 2] += rng.uniform(-0.4 * dp, 0.4 * dp, inside.sum())
    assert volume_depth(shaken, rho, mass, 0.5, 0.1, width=w) == volume_depth(pos, rho, mass, 0.5, 0.1, width=w)
    with pytest.raises(InputError):
        volume_depth(pos, rho, mass, 0.5, 0.0)


def test_front_position_of_a_moving_step_gives_its_celerity():
    """A bore as a step on a hydrostatic lattice (dp = 5 mm): depth d1 = 0.18 m for x < x_f, d0 = 0.1 m
    beyond. The front found at level (d0 + d1) / 2 on 5 cm bins is within 0.09 bin of the step (the interpolation inside the bin that
    holds it, derived in `front_position`), whatever the step's place in its bin; the step moved at c = 0.873 m/s over 1 s gives c back within 0.5 %; a spray particle
    ahead of the front (one particle's volume, 0.5 % of a bin's) does not move it; a profile below the
    level everywhere gives NaN."""
    from shoal.analysis import celerity, front_position

    dp, d0, d1, b, c = 0.005, 0.1, 0.18, 0.05, 0.873
    xs = (np.arange(1000) + 0.5) * dp

    def lattice(xf):
        cols = [(x, z) for x in xs for z in (np.arange(int(round((d1 if x < xf else d0) / dp))) + 0.5) * dp]
        pos = np.array([(x, 0.0, z) for x, z in cols])
        top = np.where(pos[:, 0] < xf, d1, d0)
        return pos, 1000.0 * (1 + 1000.0 * 9.81 * (top - pos[:, 2]) / 1.6e5) ** (1 / 7)

    times = np.linspace(0.0, 1.0, 11)
    fronts = []
    for t in times:
        xf = 1.0 + c * t
        pos, rho = lattice(xf)
        got = front_position(pos, rho, 1000.0 * dp**2, 0.5 * (d0 + d1), 4.5, b)
        xf_lattice = xs[np.searchsorted(xs, xf)] - 0.5 * dp  # the step falls between particle columns
        assert abs(got - xf_lattice) < 0.09 * b, (t, got, xf_lattice)  # measured: 0.084 b at most
        fronts.append(got)
    assert celerity(fronts, times) == pytest.approx(c, rel=5e-3)
    spray = np.r_[pos, [[4.0, 0.0, 0.3]]]
    assert front_position(spray, np.r_[rho, 1000.0], 1000.0 * dp**2, 0.5 * (d0 + d1), 4.5, b) == got
    assert np.isnan(front_position(pos, rho, 1000.0 * dp**2, 0.2, 4.5, b))
    with pytest.raises(InputError):
        front_position(pos, rho, 1000.0 * dp**2, 0.14, 4.5, 0.0)
