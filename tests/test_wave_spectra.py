"""Linear wave theory of the paddles (`shoal.waves`): dispersion, transfer functions, spectra (issue 31).

Each physical statement is checked against something computed another way: the dispersion relation itself,
the shallow- and deep-water limits of the transfer functions and their Taylor series, a numerical quadrature
of the wavemaker projection integral, the spectra's variance by a trapezoidal sum independent of the
normalising quadrature, and Goda's formula written out by hand.
"""

from __future__ import annotations

import ast
import math
from pathlib import Path

import numpy as np
import pytest
from pydantic import ValidationError

from shoal.errors import InputError
from shoal.waves import (FileSpectrum, JonswapSpectrum, PiersonMoskowitzSpectrum, flap_height_to_stroke,
                         group_velocity, piston_height_to_stroke, wavenumber, wavenumbers)

G = 9.81
SRC = Path(__file__).resolve().parents[1] / "src" / "shoal"


def test_the_waves_package_imports_only_numpy_scipy_pydantic_and_the_specs():
    """`shoal.waves` sits below `shoal.motions`: it may use numpy, scipy, pydantic, raschii (the nonlinear regular
    waves of `shoal.waves.nonlinear`), a few standard modules, `shoal.errors` and the spec types of
    `shoal.geometry.shapes`, and its own modules, nothing else of shoal."""
    allowed = {"shoal.errors", "shoal.geometry.shapes"}
    found = set()
    for path in (SRC / "waves").glob("*.py"):
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.ImportFrom):
                if node.level == 1:
                    continue  # the package's own modules
                if node.level == 2:
                    found.add("shoal." + (node.module or ""))
                elif (node.module or "").split(".")[0] not in ("__future__", "numpy", "scipy", "pydantic", "math",
                                                               "functools", "pathlib", "typing", "dataclasses",
                                                               "raschii"):
                    found.add(node.module)
            elif isinstance(node, ast.Import):
                found.update(a.name for a in node.names if a.name.split(".")[0] not in ("numpy", "math",
                                                                                        "functools", "re",
                                                                                        "raschii"))
    assert found <= allowed, found - allowed


# ------------------------------------------------------------------ dispersion
@pytest.mark.parametrize("depth", [0.05, 0.5, 3.0, 1e4])
def test_wavenumbers_solve_the_dispersion_relation_and_match_the_scalar_solver(depth):
    omega = np.linspace(0.0, 40.0, 401)
    k = wavenumbers(omega, depth)
    # omega^2 = g k tanh(kd) to the Newton tolerance (relative 1e-12, checked where omega > 0)
    np.testing.assert_allclose(G * k[1:] * np.tanh(k[1:] * depth), omega[1:] ** 2, rtol=1e-12)
    assert k[0] == 0.0
    scalar = [wavenumber(2 * math.pi / w, depth) for w in omega[1:]]
    np.testing.assert_allclose(k[1:], scalar, rtol=1e-13)


def test_group_velocity_is_d_omega_d_k_with_its_limits():
    """c_g = d omega / dk (central difference, step 1e-6 k: error ~1e-12 relative); sqrt(g d) in shallow
    water, omega / 2k = sqrt(g / k) / 2 in deep water (no overflow at kd = 1e6)."""
    d = 0.7
    for k in (0.05, 0.8, 3.0, 12.0):
        h = 1e-6 * k
        omega = lambda q: math.sqrt(G * q * math.tanh(q * d))  # noqa: E731
        assert group_velocity(k, d) == pytest.approx((omega(k + h) - omega(k - h)) / (2 * h), rel=1e-8)
    assert group_velocity(0.0, d) == pytest.approx(math.sqrt(G * d), rel=1e-15)
    assert group_velocity(1e-7, d) == pytest.approx(math.sqrt(G * d), rel=1e-12)
    assert group_velocity(1e6, 1.0) == pytest.approx(0.5 * math.sqrt(G / 1e6), rel=1e-15)
    np.testing.assert_allclose(group_velocity(np.array([0.05, 1e6]), d),
                               [group_velocity(0.05, d), group_velocity(1e6, d)], rtol=0)


# ------------------------------------------------------------------ transfer functions
def test_piston_limits_and_its_array_form():
    """H/S = kd (1 + O(kd^4)) in shallow water (4 sinh^2 x / (sinh 2x + 2x) = x (1 + x^2/3 + ...) /
    (1 + x^2/3 + ...)), 2 in deep water; an array gives each element exactly as the scalar does."""
    for kd in (1e-3, 1e-2, 3e-2):
        assert piston_height_to_stroke(kd, 1.0) == pytest.approx(kd, rel=kd**4)
    for kd in (30.0, 1e3, 1e300):
        assert piston_height_to_stroke(kd, 1.0) == 2.0
    ks = np.array([1e-3, 0.3, 1.0, 2.5, 24.9, 25.1, 1e6])
    assert np.array_equal(piston_height_to_stroke(ks, 1.0), [piston_height_to_stroke(float(k), 1.0) for k in ks])


def test_flap_on_the_bed_is_dean_and_dalrymple_6_23_with_its_limits():
    """Hinged at the bed: H/S = 4 (sinh kd / kd) (kd sinh kd - cosh kd + 1) / (sinh 2kd + 2kd) (D&D 6.23,
    written out here); shallow water kd/2 (1 + (kd)^2/12 + O(kd^4)), from the Taylor series of each factor;
    deep water 2 (1 - 1/kd) up to exp(-kd) terms, computed without overflow up to kd = 1e300."""
    for kd in (0.1, 0.5, 1.0, 3.0, 10.0, 19.0):
        direct = 4 * math.sinh(kd) / kd * (kd * math.sinh(kd) - math.cosh(kd) + 1) / (math.sinh(2 * kd) + 2 * kd)
        assert flap_height_to_stroke(kd, 1.0) == pytest.approx(direct, rel=1e-12)
    for kd in (1e-4, 1e-3, 1e-2):
        assert flap_height_to_stroke(kd, 1.0) == pytest.approx(0.5 * kd * (1 + kd**2 / 12), rel=kd**4)
    for kd in (50.0, 1e3, 1e6):
        assert flap_height_to_stroke(kd, 1.0) == pytest.approx(2.0 * (1.0 - 1.0 / kd), rel=1e-14)
    assert flap_height_to_stroke(1e300, 1.0) == 2.0
    # the two forms meet at kd = 20 (the plain one below, the one scaled by exp(-2kd) above)
    assert flap_height_to_stroke(20.0 - 1e-12, 1.0) == pytest.approx(flap_height_to_stroke(20.0 + 1e-12, 1.0),
                                                                      rel=1e-12)


@pytest.mark.parametrize("hinge", [-0.5, 0.0, 0.3, 0.7, 0.95])
@pytest.mark.parametrize("kd", [0.2, 1.0, 4.0, 25.0])
def test_hinged_flap_is_the_projection_of_its_displacement_on_the_progressive_mode(hinge, kd):
    """H/S = 4 sinh(kd) I / (sinh 2kd + 2kd), I = k int_0^d (X(s)/X(d)) cosh(ks) ds with X(s) = (s - l)/(d - l)
    above max(l, 0) and 0 below (s the height above the bed), by adaptive quadrature (relative 1e-12).
    The integral is computed scaled by exp(-kd) so that kd = 25 does not overflow."""
    from scipy.integrate import quad

    d = 1.0
    k = kd / d
    lo = max(hinge, 0.0)
    scaled, _ = quad(lambda s: (s - hinge) / (d - hinge) * 0.5 * (math.exp(k * (s - d)) + math.exp(-k * (s + d))),
                     lo, d, epsabs=0, epsrel=1e-13)
    i_scaled = k * scaled                                 # I exp(-kd)
    sinh_scaled = 0.5 * (1 - math.exp(-2 * kd))           # sinh(kd) exp(-kd)
    den_scaled = 0.5 * (1 - math.exp(-4 * kd)) + 2 * kd * math.exp(-2 * kd)   # (sinh 2kd + 2kd) exp(-2kd)
    assert flap_height_to_stroke(k, d, hinge) == pytest.approx(4 * sinh_scaled * i_scaled / den_scaled, rel=1e-10)


def test_a_flap_hinged_far_below_the_bed_is_a_piston_and_a_hinge_above_the_water_is_refused():
    """As l -> -inf the flap's displacement over the depth tends to uniform: H/S -> the piston's (1e6 depths
    below: the displacement varies by 1e-6 over the water column)."""
    for kd in (0.3, 1.0, 3.0, 40.0):
        assert flap_height_to_stroke(kd, 1.0, hinge=-1e6) == pytest.approx(piston_height_to_stroke(kd, 1.0),
                                                                           rel=2e-6)
    ks = np.array([0.01, 0.5, 19.9, 20.1, 300.0])
    assert np.array_equal(flap_height_to_stroke(ks, 1.0, 0.3), [flap_height_to_stroke(float(k), 1.0, 0.3)
                                                                for k in ks])
    with pytest.raises(ValueError, match="hinge = 1 m is not below the still-water level"):
        flap_height_to_stroke(1.0, 1.0, hinge=1.0)


# ------------------------------------------------------------------ spectra
def _m0_by_trapezoid(spectrum, tp):
    """m0 by a trapezoidal sum over 0 < f < 40 fp on 400,001 points (the peak at 1/tp is resolved by ~10^4
    points: error ~1e-9), plus the f^-5 tail above 40 fp in closed form, beta' Hs^2 Tp^-4 / (4 f^4) with the
    exponential factors equal to 1 to 1e-6 there (its share of m0 is ~1e-7)."""
    f = np.linspace(0.0, 40.0 / tp, 400_001)
    s = spectrum.density(f)
    tail = s[-1] * f[-1] / 4.0   # int_F^inf C f^-5 df = C F^-4 / 4 = S(F) F / 4
    return float(np.trapezoid(s, f)) + tail


@pytest.mark.parametrize("gamma", [1.0, 2.0, 3.3, 7.0, 20.0])
def test_jonswap_variance_is_hs_squared_over_16(gamma):
    """m0 = Hs^2/16 to 1e-6: the trapezoidal sum, independent of the quadrature that normalised beta."""
    hs, tp = 0.05, 1.5
    j = JonswapSpectrum(hs=hs, tp=tp, gamma=gamma)
    assert _m0_by_trapezoid(j, tp) == pytest.approx(hs**2 / 16, rel=1e-6)
    assert j.m0 == pytest.approx(hs**2 / 16, rel=1e-12)
    assert j.hm0 == pytest.approx(hs, rel=1e-12)


def test_pierson_moskowitz_variance_is_hs_squared_over_16_and_jonswap_of_gamma_1_is_it():
    hs, tp = 0.12, 2.2
    pm = PiersonMoskowitzSpectrum(hs=hs, tp=tp)
    assert _m0_by_trapezoid(pm, tp) == pytest.approx(hs**2 / 16, rel=1e-6)
    assert pm.m0 == pytest.approx(hs**2 / 16, rel=1e-13)
    j1 = JonswapSpectrum(hs=hs, tp=tp, gamma=1.0)
    assert j1.beta == pytest.approx(5.0 / 16.0, rel=1e-12)
    f = np.linspace(0.0, 10.0 / tp, 2001)
    np.testing.assert_allclose(j1.density(f), pm.density(f), rtol=1e-12, atol=0)
    for n in (1, 2, 3):
        assert j1.moment(n) == pytest.approx(pm.moment(n), rel=1e-12)


@pytest.mark.parametrize("spectrum", [JonswapSpectrum(hs=0.05, tp=1.5), JonswapSpectrum(hs=0.05, tp=1.5, gamma=7.0),
                                      PiersonMoskowitzSpectrum(hs=0.05, tp=1.5)], ids=["gamma3.3", "gamma7", "pm"])
def test_the_spectra_peak_at_fp(spectrum):
    """x^-5 exp(-1.25 x^-4) is largest at x = 1 (its derivative is 5 x^-10 (1 - x^4) exp(...)), and the peak
    enhancement too: the largest S of a fine grid is at fp, to its spacing."""
    fp = spectrum.peak_frequency
    f = np.linspace(0.2 * fp, 5 * fp, 480_001)
    assert f[np.argmax(spectrum.density(f))] == pytest.approx(fp, abs=1e-5 * fp)
    s0 = spectrum.density(fp)
    assert spectrum.density(fp * (1 - 1e-4)) < s0 and spectrum.density(fp * (1 + 1e-4)) < s0


def test_jonswap_is_godas_formula_by_hand():
    """S(f) = beta Hs^2 Tp^-4 f^-5 exp(-1.25 (Tp f)^-4) gamma^exp(-(Tp f - 1)^2 / (2 sigma^2)) written out at
    three frequencies, both sides of the peak (sigma_a below, sigma_b above); Goda's beta_J by hand, and how
    far it is from the beta that makes m0 = Hs^2/16 (the factors quoted in docs/waves.md)."""
    hs, tp, gamma = 0.05, 1.5, 3.3
    j = JonswapSpectrum(hs=hs, tp=tp, gamma=gamma)
    for f, sigma in ((0.8 / tp, 0.07), (1.0 / tp, 0.07), (1.3 / tp, 0.09)):
        by_hand = (j.beta * hs**2 * tp**-4 * f**-5 * math.exp(-1.25 * (tp * f) ** -4)
                   * gamma ** math.exp(-((tp * f - 1) ** 2) / (2 * sigma**2)))
        assert float(j.density(f)) == pytest.approx(by_hand, rel=1e-13)
    beta_j = 0.0624 / (0.230 + 0.0336 * 3.3 - 0.185 / (1.9 + 3.3)) * (1.094 - 0.01915 * math.log(3.3))
    assert j.goda_beta == pytest.approx(beta_j, rel=1e-15)
    assert beta_j == pytest.approx(0.21893, abs=1e-5)
    factors = {g: JonswapSpectrum(hs=hs, tp=tp, gamma=g).goda_beta / JonswapSpectrum(hs=hs, tp=tp, gamma=g).beta
               for g in (1.0, 3.3, 7.0)}
    assert [round(v, 3) for v in factors.values()] == [1.093, 1.068, 1.057]


def test_moments_against_the_trapezoid_and_the_band_shares_quoted_in_the_docs():
    """m1, m2 by quadrature against a trapezoidal sum over 0 .. 60 fp plus the f^-5 tail above in closed form,
    int_F^inf f^n C f^-5 df = S(F) F^(n+1) / (4 - n) (the exponential factors are 1 to 1e-7 there); m4 over
    all frequencies diverges (S ~ f^-5); the variance above 3 fp, which the default band leaves out, is
    1.0 % of a JONSWAP (gamma = 3.3) and 1.5 % of a Pierson-Moskowitz spectrum."""
    j = JonswapSpectrum(hs=0.05, tp=1.5)
    f = np.linspace(0.0, 60 / 1.5, 600_001)
    for n in (1, 2):
        tail = float(j.density(f[-1])) * f[-1] ** (n + 1) / (4 - n)
        assert j.moment(n) == pytest.approx(np.trapezoid(f**n * j.density(f), f) + tail, rel=1e-7)
    assert j.moment(4) == math.inf and math.isfinite(j.moment(4, 0.0, 10.0))
    assert j.moment(0, 0.3, 0.9) == pytest.approx(np.trapezoid(j.density(f[(f >= 0.3) & (f <= 0.9)]),
                                                               f[(f >= 0.3) & (f <= 0.9)]), rel=1e-8)
    assert round(j.moment(0, 3 / 1.5) / j.m0, 3) == 0.010
    pm = PiersonMoskowitzSpectrum(hs=0.05, tp=1.5)
    assert round(pm.moment(0, 3 / 1.5) / pm.m0, 3) == 0.015
    assert j.moment(0, 0.0, 0.5 / 1.5) / j.m0 < 1e-8  # (what lies below the default band)


def test_spectrum_specs_refuse_bad_values():
    for bad in (dict(hs=0.0, tp=1.0), dict(hs=0.05, tp=-1.0), dict(hs=0.05, tp=1.0, gamma=0.9),
                dict(hs=0.05, tp=1.0, gamma=21.0), dict(hs=math.nan, tp=1.0), dict(hs=0.05, tp=1.0, sigma_a=0.0),
                dict(hs="0.05", tp=1.0), dict(hs=0.05, tp=1.0, extra=1)):
        with pytest.raises(ValidationError):
            JonswapSpectrum(**bad)


# ------------------------------------------------------------------ a spectrum from a file
def test_file_spectrum_reads_a_table_and_integrates_its_lines(tmp_path):
    """A Pierson-Moskowitz spectrum tabulated with a header and comments: S is linear between the rows
    (checked midway), m0 the trapezoidal sum of the table, fp its largest row; m1 the exact integral of
    f times the linear S (Gauss-Legendre, checked against a trapezoid on a 100x finer grid of the lines)."""
    pm = PiersonMoskowitzSpectrum(hs=0.05, tp=1.5)
    f = np.linspace(0.2, 3.0, 141)
    s = pm.density(f)
    rows = "".join(f"{float(a)!r}, {float(b)!r}  # row\n" for a, b in zip(f, s))
    text = "# a spectrum\nf [Hz], S [m^2/Hz]\n" + rows + "\n"
    (tmp_path / "s.csv").write_text(text)
    fs = FileSpectrum(file=str(tmp_path / "s.csv"))
    assert np.array_equal(fs.table[0], f) and np.array_equal(fs.table[1], s)
    assert fs.m0 == pytest.approx(float(np.trapezoid(s, f)), rel=1e-13)
    assert fs.hm0 == pytest.approx(0.05, rel=2e-2)  # the table misses the tail above 3 Hz and its sampling
    assert fs.peak_frequency == f[np.argmax(s)]
    assert float(fs.density(0.5 * (f[10] + f[11]))) == pytest.approx(0.5 * (s[10] + s[11]), rel=1e-14)
    assert float(fs.density(0.1)) == 0.0 and float(fs.density(3.5)) == 0.0
    fine = np.linspace(f[0], f[-1], 100 * (len(f) - 1) + 1)
    assert fs.moment(1) == pytest.approx(np.trapezoid(fine * fs.density(fine), fine), rel=1e-6)
    assert fs.moment(0, 0.5, 1.0) == pytest.approx(np.trapezoid(fs.density(fine[(fine >= 0.5) & (fine <= 1.0)]),
                                                                fine[(fine >= 0.5) & (fine <= 1.0)]), rel=1e-7)


BAD_FILES = {
    "not-there": (None, "not found"),
    "empty": ("", "0 rows of numbers, fewer than 2"),
    "one-row": ("0.5 0.1\n", "1 row of numbers, fewer than 2"),
    "three-columns": ("0.5 0.1 3\n0.6 0.2 4\n", "line 1 ('0.5 0.1 3') is not two numbers"),
    "a-word-in-the-middle": ("f S\n0.5 0.1\nabc 0.2\n", "line 3 ('abc 0.2') is not two numbers"),
    "nan": ("0.5 0.1\n0.6 nan\n", "line 2 ('0.6 nan') holds a value that is not finite"),
    "decreasing": ("0.6 0.1\n0.5 0.2\n", "the frequencies do not increase strictly"),
    "repeated-frequency": ("0.5 0.1\n0.5 0.2\n", "the frequencies do not increase strictly"),
    "negative-frequency": ("-0.5 0.1\n0.5 0.2\n", "the frequency -0.5 Hz is negative"),
    "negative-density": ("0.5 0.1\n0.6 -0.2\n", "S = -0.2 m^2/Hz is negative"),
    "all-zero": ("0.5 0\n0.6 0\n", "S is zero at every frequency"),
    "binary": (b"\xff\xfe\x00\x01", "not a text file (UTF-8)"),
}


@pytest.mark.parametrize("name", list(BAD_FILES))
def test_a_bad_spectrum_file_is_one_line_naming_the_file_and_the_form(name, tmp_path):
    content, fragment = BAD_FILES[name]
    path = tmp_path / f"{name}.txt"
    if isinstance(content, bytes):
        path.write_bytes(content)
    elif content is not None:
        path.write_text(content)
    with pytest.raises(InputError) as err:
        FileSpectrum(file=str(path)).density(1.0)
    message = str(err.value)
    assert "\n" not in message
    assert message.startswith(f"spectrum file {str(path)!r}: ")
    assert fragment in message, message
    assert "give two columns, f [Hz] and S [m^2/Hz]" in message


def test_a_directory_is_not_a_spectrum_file(tmp_path):
    with pytest.raises(InputError, match="not a file"):
        FileSpectrum(file=str(tmp_path)).m0
