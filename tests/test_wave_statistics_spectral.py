"""Spectral and zero-crossing statistics of irregular-wave records (`shoal.analysis.spectral`,
`shoal.analysis.zero_crossing`) on synthetic records whose answers are known: exactly for sinusoids,
within a derived statistical tolerance for Gaussian seas."""

import numpy as np
import pytest

from shoal.analysis import (Spectrum, band_ratios, wave_spectrum, wave_statistics, zero_crossing_statistics)
from shoal.analysis.spectral import welch_dof
from shoal.errors import InputError


def jonswap(f, fp=1.0, gamma=3.3, hm0=0.1):
    """JONSWAP variance density [m^2/Hz] (Hasselmann et al. 1973; sigma 0.07 / 0.09), scaled to Hm0 by
    integrating the shape numerically."""
    def shape(x):
        x = np.asarray(x, float)
        out = np.zeros_like(x)
        m = x > 0
        sig = np.where(x[m] <= fp, 0.07, 0.09)
        peak = gamma ** np.exp(-(x[m] / fp - 1) ** 2 / (2 * sig ** 2))
        out[m] = x[m] ** -5 * np.exp(-1.25 * (x[m] / fp) ** -4) * peak
        return out

    grid = np.linspace(1e-3, 30 * fp, 300001)
    return shape(f) * (hm0 / 4) ** 2 / np.trapezoid(shape(grid), grid)


def gaussian_record(S, n, dt, seed):
    """A Gaussian sea of one-sided density S(f): a sum of n/2 cosines at f_k = k / (n dt) with complex
    Gaussian amplitudes, E|A_k|^2 = 2 S(f_k) df (random amplitudes and phases; Tucker et al. 1984)."""
    rng = np.random.default_rng(seed)
    f = np.fft.rfftfreq(n, dt)
    A = np.sqrt(S(f) * f[1]) * (rng.standard_normal(f.size) + 1j * rng.standard_normal(f.size))
    A[0] = A[-1] = 0
    return np.arange(n) * dt, np.fft.irfft(A * n / 2, n)


def taper_weights(n, L, window="hann"):
    """a_n: the weight Welch's average gives each sample's square (segments of L, half overlap), sum 1."""
    from scipy.signal import get_window

    w2 = np.asarray(get_window(window, L)) ** 2
    D = L // 2
    K = 1 + (n - L) // D
    a = np.zeros(n)
    for m in range(K):
        a[m * D:m * D + L] += w2 / (K * w2.sum())
    return a


# ---------------------------------------------------------------------------------------------- spectra

@pytest.mark.parametrize("offset", np.linspace(0.0, 0.5, 6))
def test_a_sinusoid_gives_half_its_amplitude_squared_and_its_frequency(offset):
    """m0 = a^2 / 2 with the taper corrected for: the errors are the segments' means removed (at most
    2 / (pi n)^2 of m0 for n periods a segment, 2e-5 here) and the taper-weighted mean of cos(2 w t),
    far smaller; the peak from the parabola through ln S lies within 0.02 df of the frequency at every
    offset from the bins (a property of the Hann window's main lobe)."""
    dt, a = 0.05, 0.1
    t = np.arange(0.0, 409.6, dt)
    f0 = (100 + offset) / 102.4  # 100 bins up: about 100 periods a segment
    s = wave_spectrum(t, 0.3 + a * np.cos(2 * np.pi * f0 * t + 0.4), segment=102.4)
    assert s.segments == 7 and s.df == pytest.approx(1 / 102.4) and not s.resampled
    assert s.m0 == pytest.approx(a * a / 2, rel=1e-4)
    assert s.Hm0 == pytest.approx(4 * np.sqrt(a * a / 2), rel=1e-4)
    assert abs(s.peak_frequency() - f0) < 0.02 * s.df
    assert s.Tp == pytest.approx(1 / s.peak_frequency())
    assert abs(s.peak_frequency("bin") - f0) <= 0.5 * s.df + 1e-12
    assert abs(s.peak_frequency("s4") - f0) < 0.5 * s.df


def test_two_sinusoids_on_bins_give_the_exact_mean_periods():
    """Two sinusoids on bins of the periodic Hann taper fill three bins each, with 1/6, 2/3, 1/6 of
    their variance: m0 and m1 are exact, m2 gains (a^2/2) df^2/3 per sinusoid and m_-1 its neighbours'
    1/(f -/+ df), so Tm01 equals m0/m1 of the two lines to rounding and Tm02, Tm-10 equal the
    three-bin sums to rounding and the lines' values within (df/f)^2 / 3 = 2e-4."""
    dt, L = 0.05, 2048
    df = 1 / (L * dt)
    t = np.arange(8 * L) * dt
    (a1, f1), (a2, f2) = (0.05, 100 * df), (0.02, 180 * df)
    eta = a1 * np.cos(2 * np.pi * f1 * t + 0.3) + a2 * np.sin(2 * np.pi * f2 * t - 1.1)
    s = wave_spectrum(t, eta, segment=L * dt)
    v1, v2 = a1 ** 2 / 2, a2 ** 2 / 2
    assert s.m0 == pytest.approx(v1 + v2, rel=1e-12)
    assert s.Tm01 == pytest.approx((v1 + v2) / (v1 * f1 + v2 * f2), rel=1e-12)
    m2 = v1 * (f1 ** 2 + df ** 2 / 3) + v2 * (f2 ** 2 + df ** 2 / 3)
    assert s.Tm02 == pytest.approx(np.sqrt((v1 + v2) / m2), rel=1e-12)

    def inv(v, f):
        return v * (2 / 3 / f + 1 / 6 / (f - df) + 1 / 6 / (f + df))

    assert s.Tm_10 == pytest.approx((inv(v1, f1) + inv(v2, f2)) / (v1 + v2), rel=1e-12)
    assert s.Tm02 == pytest.approx(np.sqrt((v1 + v2) / (v1 * f1 ** 2 + v2 * f2 ** 2)), rel=2e-4)
    assert s.Tm_10 == pytest.approx((v1 / f1 + v2 / f2) / (v1 + v2), rel=2e-4)
    # a band holds one line; the moments of a band are those of its bins
    assert s.band(f_max=140 * df).m0 == pytest.approx(v1, rel=1e-12)
    assert s.moment(1, f_min=140 * df) == pytest.approx(v2 * f2, rel=1e-12)
    assert s.band(140 * df).Tp == pytest.approx(1 / f2, rel=1e-12)


def test_welch_degrees_of_freedom():
    """Hann at half overlap: nu = 36 K^2 / (19 K - 1) (Percival & Walden 1993); no overlap: 2K."""
    for K in (2, 7, 31):
        assert welch_dof("hann", 256, 128, K) == pytest.approx(36 * K * K / (19 * K - 1), rel=1e-12)
        assert welch_dof("hann", 256, 0, K) == 2 * K


@pytest.mark.parametrize("overlap", [0.0, 0.75])
def test_white_noise_bins_scatter_as_chi_square_with_the_stated_degrees_of_freedom(overlap):
    """Unit white noise has S = 2 dt; each bin's estimate over S is chi-square with nu degrees of freedom
    over nu: mean 1, variance 2 / nu. Over the 2047 interior bins of 30 seeds the bins' mean scatters
    by 0.4 % and their variance times nu / 2 by 4 %; the tolerances are four of those. At 75 % overlap
    nu (263) is half of 2K (506): the check tells the two apart."""
    dt, n = 0.1, 2 ** 18
    t = np.arange(n) * dt
    x = np.random.default_rng(7).standard_normal(n)
    s = wave_spectrum(t, x, segment=409.6, overlap=overlap)
    r = s.S[1:-1] / (2 * dt)
    assert r.mean() == pytest.approx(1.0, abs=0.016)
    assert r.var() * s.dof / 2 == pytest.approx(1.0, abs=0.16)
    assert s.dof == (128.0 if overlap == 0 else pytest.approx(263.44, abs=0.01))


def test_hm0_of_a_gaussian_sea_within_its_sampling_error():
    """A Gaussian JONSWAP sea (Hm0 0.1 m, Tp 1 s, gamma 3.3) of 6554 s. Welch's m0 is the weighted mean
    square sum_n a_n eta_n^2 (weights a_n from the tapers, sum 1); for a Gaussian record its variance is
    (sum a_n^2 / dt) int S^2 df (Isserlis), i.e. m0 is chi-square over nu0 = 2 m0^2 dt / (sum a_n^2
    int S^2 df) degrees of freedom: nu0 = 7,200 here, so Hm0 scatters by 1 / sqrt(2 nu0) = 0.83 %
    (200 seeds: 0.86 %). The tolerance is four of those."""
    dt, n = 0.05, 2 ** 17
    t, eta = gaussian_record(jonswap, n, dt, seed=11)
    s = wave_spectrum(t, eta)
    grid = np.linspace(1e-3, 10, 200001)
    m0 = (0.1 / 4) ** 2
    a = taper_weights(n, n // 4)
    nu0 = 2 * m0 ** 2 * dt / (np.sum(a ** 2) * np.trapezoid(jonswap(grid) ** 2, grid))
    sigma = 1 / np.sqrt(2 * nu0)
    assert sigma == pytest.approx(0.0083, abs=1e-4)
    assert s.Hm0 == pytest.approx(0.1, rel=4 * sigma)
    assert s.Tp == pytest.approx(1.0, rel=0.05)  # the peak of the estimate scatters by a few bins of 0.006 Hz
    assert s.peak_period("s4") == pytest.approx(1.0, rel=0.02)
    # the mean periods of the target, from its moments
    mom = {k: np.trapezoid(grid ** k * jonswap(grid), grid) for k in (-1, 0, 1, 2)}
    assert s.Tm01 == pytest.approx(mom[0] / mom[1], rel=0.02)
    assert s.Tm02 == pytest.approx(np.sqrt(mom[0] / mom[2]), rel=0.02)
    assert s.Tm_10 == pytest.approx(mom[-1] / mom[0], rel=0.02)


def test_parseval_m0_is_the_record_variance():
    """sum_j S_j df over every bin is the taper-weighted variance of the segments, to rounding; m0 (bins
    f > 0) differs from the record's plain variance by sum_n (a_n - 1/N) eta_n^2, a Gaussian record's
    sampling difference of standard deviation sqrt(sum (a_n - 1/N)^2 / dt int S^2 df): 0.67 % of m0 here
    (plus the zero bin, 1e-5 of m0). The tolerance is four of those."""
    from scipy.signal import get_window

    dt, n = 0.05, 2 ** 17
    t, eta = gaussian_record(jonswap, n, dt, seed=5)
    s = wave_spectrum(t, eta)
    L, D = n // 4, n // 8
    w = np.asarray(get_window("hann", L))
    x = eta - eta.mean()
    seg = [x[m * D:m * D + L] - x[m * D:m * D + L].mean() for m in range(s.segments)]
    assert np.sum(s.S) * s.df == pytest.approx(np.mean([np.sum((w * v) ** 2) / np.sum(w * w) for v in seg]), rel=1e-12)
    a = taper_weights(n, L)
    grid = np.linspace(1e-3, 10, 200001)
    sigma = np.sqrt(np.sum((a - 1 / n) ** 2) / dt * np.trapezoid(jonswap(grid) ** 2, grid)) / np.var(eta)
    assert sigma == pytest.approx(0.0067, abs=2e-4)
    assert s.m0 == pytest.approx(np.var(eta), rel=4 * sigma)


def test_band_ratios_are_exact_for_the_target_and_scatter_as_derived_for_a_gaussian_sea():
    """A spectrum equal to the target gives ratios of 1, whatever the bins straddle; one scaled by 1.1 in
    [0.9, 1.0] fp gives 1.1 in that band and part of it in the bands a bin straddles. A Gaussian
    JONSWAP sea of 6554 s: each band's energy scatters by sqrt(c int_band S^2 df / T) / int_band S df
    (c = N sum a_n^2 = 1.19): 4.3 to 4.6 % (200 seeds: 3.9 to 4.5 %); the tolerance is four of those."""
    df = 0.0123
    f = np.arange(0, 400) * df
    S = jonswap(f)
    exact = Spectrum(f=f, S=S, df=df, segments=7, dof=13.36, dt=0.05)
    assert np.allclose(band_ratios(exact, jonswap, 1.0), 1.0, rtol=1e-12)
    assert np.allclose(band_ratios(exact, S, 1.0, edges=[0.5, 0.75, 2.0]), 1.0, rtol=1e-12)
    bump = Spectrum(f=f, S=np.where((f > 0.9 + df / 2) & (f < 1.0 - df / 2), 1.1, 1.0) * S, df=df, segments=7,
                    dof=13.36, dt=0.05)
    r = band_ratios(bump, jonswap, 1.0)
    assert r[2] > 1.05 and np.allclose(r[[0, 5, 6, 7]], 1.0, rtol=1e-12)

    dt, n = 0.05, 2 ** 17
    t, eta = gaussian_record(jonswap, n, dt, seed=3)
    s = wave_spectrum(t, eta)
    r = band_ratios(s, jonswap, 1.0)
    c = n * np.sum(taper_weights(n, n // 4) ** 2)
    edges = np.arange(0.7, 1.51, 0.1)
    sig = []
    for lo, hi in zip(edges[:-1], edges[1:]):
        g = np.linspace(lo, hi, 2001)
        sig.append(np.sqrt(c * np.trapezoid(jonswap(g) ** 2, g) / (n * dt)) / np.trapezoid(jonswap(g), g))
    sig = np.array(sig)
    assert np.all((sig > 0.042) & (sig < 0.047))
    assert np.all(np.abs(r - 1) < 4 * sig)


def test_a_record_with_uneven_steps_is_resampled_and_says_so():
    """A record with one sample missing is interpolated onto its median step (one sample interpolated
    linearly: m0 changes by O(1/N)); rounding of the times (a CSV file's 6 digits) is not unevenness."""
    dt, a = 0.05, 0.1
    t = np.arange(0.0, 409.6, dt)
    eta = a * np.cos(2 * np.pi * 0.8 * t)
    s = wave_spectrum(np.round(t, 6), eta)
    assert not s.resampled and s.dt == pytest.approx(dt, rel=1e-9)
    keep = np.ones(t.size, bool)
    keep[1000] = False
    s = wave_spectrum(t[keep], eta[keep])
    assert s.resampled and s.dt == pytest.approx(dt, rel=1e-9)
    assert s.m0 == pytest.approx(a * a / 2, rel=1e-3)


def one_line(excinfo):
    return "\n" not in str(excinfo.value)


def test_bad_records_are_refused_in_one_line():
    t = np.arange(0.0, 100.0, 0.05)
    eta = np.sin(t)
    cases = [
        (lambda: wave_spectrum(t, eta, segment=70.0), "at least 2 are needed"),
        (lambda: wave_spectrum(t[:10], eta[:10]), "at least 16"),
        (lambda: wave_spectrum(t, np.where(t > 50, np.nan, eta)), "non-finite value"),
        (lambda: wave_spectrum(t[::-1], eta), "increase strictly"),
        (lambda: wave_spectrum(t, eta[:-1]), "same length"),
        (lambda: wave_spectrum(t, eta, overlap=1.0), "overlap"),
        (lambda: wave_spectrum(t, eta, window="nonsense"), "unknown spectral window"),
        (lambda: wave_spectrum(t, eta, segment=0.2), "at least 8"),
        (lambda: wave_spectrum(t, eta).moment(0, f_min=50.0), "holds no frequency bin"),
        (lambda: wave_spectrum(t, eta).peak_frequency("max"), "unknown peak method"),
        (lambda: band_ratios(wave_spectrum(t, eta), jonswap, 0.3), "narrower than"),
        (lambda: band_ratios(wave_spectrum(t, eta, segment=50.0), jonswap, 20.0), "outside the spectrum"),
        (lambda: band_ratios(wave_spectrum(t, eta, segment=50.0), jonswap, 1.0, edges=[2, 1]), "increasing"),
        (lambda: band_ratios(wave_spectrum(t, eta, segment=50.0), np.ones(3), 1.0), "holds 3 values"),
        (lambda: zero_crossing_statistics(t, np.where(t > 50, np.inf, eta)), "non-finite value"),
        (lambda: zero_crossing_statistics(t[::-1], eta), "increase strictly"),
        (lambda: zero_crossing_statistics(t, eta, 0.0, 3.0), "no whole wave"),
        (lambda: zero_crossing_statistics(t, eta, 0.0, 0.2), "at least 8"),
        (lambda: zero_crossing_statistics(t, eta, 0.0, 20.0).H1_10, "at least 10 waves"),
    ]
    for call, message in cases:
        with pytest.raises(InputError, match=message) as excinfo:
            call()
        assert one_line(excinfo), message


# ------------------------------------------------------------------------------------------ zero crossing

def test_zero_crossing_statistics_match_wave_statistics():
    """The same waves as the regular-wave analysis, on a regular and on an irregular record."""
    dt = 0.025
    t = np.arange(0.0, 60.0, dt)
    regular = 0.4 + 0.025 * np.sin(2 * np.pi * t / 1.2 + 0.3) + 0.003 * np.cos(4 * np.pi * t / 1.2)
    _, irregular = gaussian_record(jonswap, t.size, dt, seed=2)
    for eta in (regular, irregular):
        a = wave_statistics(t, eta, 5.0, 55.0)
        b = zero_crossing_statistics(t, eta, 5.0, 55.0)
        assert np.array_equal(a.heights, b.heights) and np.array_equal(a.periods, b.periods)
        assert np.array_equal(a.crossings, b.crossings) and a.mean_level == b.mean_level
        assert b.height == a.height and b.Tz == a.period and b.Hmean == a.height


def test_highest_waves_of_a_known_sequence():
    """Whole sine waves of amplitudes 1..6 cm and periods 1.0..1.5 s, each sampled at its crest and
    trough: heights 2..12 cm, H1/3 the mean of the two highest, T1/3 their mean period."""
    amps = np.array([0.03, 0.01, 0.06, 0.02, 0.05, 0.04])
    pers = np.array([1.2, 1.0, 1.5, 1.1, 1.4, 1.3])
    t, eta, t_now = [], [], 0.0
    for a, T in zip(amps, pers):
        s = np.arange(40) / 40
        t.extend(t_now + s * T)
        eta.extend(a * np.sin(2 * np.pi * s))
        t_now += T
    t, eta = np.array(t + [t_now]), np.array(eta + [0.0])
    t, eta = np.concatenate([[-0.01], t]), np.concatenate([[-1e-3], eta])
    z = zero_crossing_statistics(t, eta - np.mean(eta) + 0.7)
    assert z.waves == 6
    assert np.allclose(z.heights, 2 * amps, rtol=0, atol=1e-12)
    assert z.H1_3 == pytest.approx(0.11, abs=1e-4)
    assert z.T1_3 == pytest.approx(1.45, abs=1e-3)
    assert z.Hmax == pytest.approx(0.12, abs=1e-4) and z.THmax == pytest.approx(1.5, abs=1e-3)
    assert z.Hrms == pytest.approx(np.sqrt(np.mean((2 * amps) ** 2)), abs=1e-4)
    assert z.highest(2) == pytest.approx(0.10, abs=1e-4)


def test_narrow_band_heights_follow_the_rayleigh_distribution():
    """A Gaussian sea of Gaussian spectrum (fp 1 Hz, sigma 0.05 Hz), 13,000 waves sampled at T/40.
    Longuet-Higgins (1952): H1/3 = 4.004 sqrt(m0), Hrms = sqrt(8 m0), Hmean = sqrt(2 pi m0), H1/10 =
    5.090 sqrt(m0); Rice: Tz = sqrt(m0 / m2) = 1 / sqrt(fp^2 + sigma^2). Biases: the spectrum's width
    lowers the heights by about sqrt((1 - r(T/2)) / 2) = 0.997 (Tayfun 1981; r the autocorrelation),
    the samples miss the crests by 0.1 % on average. Scatter of the ratios to the record's own m0 over
    100 seeds: 0.26 % (H1/3), 0.05 % (Hrms), 0.25 % (Hmean), 0.66 % (H1/10), 0.11 % (Tz); means 0.9965,
    0.9974, 0.9991, 0.9957, 0.9986 of the theory. Each tolerance is the 0.4 % bias plus four standard
    deviations."""
    dt, n = 1 / 40, 2 ** 19
    t, eta = gaussian_record(lambda f: np.exp(-0.5 * ((f - 1.0) / 0.05) ** 2), n, dt, seed=4)
    z = zero_crossing_statistics(t, eta)
    m0 = np.var(eta)
    assert 12900 < z.waves < 13300
    assert z.H1_3 == pytest.approx(4.004 * np.sqrt(m0), rel=0.015)
    assert z.Hrms == pytest.approx(np.sqrt(8 * m0), rel=0.006)
    assert z.Hmean == pytest.approx(np.sqrt(2 * np.pi * m0), rel=0.014)
    assert z.H1_10 == pytest.approx(5.090 * np.sqrt(m0), rel=0.031)
    assert z.Tz == pytest.approx(1 / np.sqrt(1 + 0.05 ** 2), rel=0.0085)
    assert z.T1_3 == pytest.approx(1.0, rel=0.01)
    assert z.Hmax > z.H1_10 > z.H1_3 > z.Hmean
