"""Variance density spectra S(f) [m^2/Hz] of the surface elevation, as case-file specs.

A spectrum is a table with a ``type``, e.g. ``spectrum = {type = "jonswap", hs = 0.05, tp = 1.5}``:

* `JonswapSpectrum` (``"jonswap"``): JONSWAP (Hasselmann et al. 1973) of significant height Hs, peak period Tp
  and peak enhancement gamma, in Goda's (1988) form;
* `PiersonMoskowitzSpectrum` (``"pierson_moskowitz"``): a fully developed sea (Pierson & Moskowitz 1964), the
  JONSWAP of gamma = 1;
* `FileSpectrum` (``"file"``): a spectrum tabulated in a text file.

Hs is the spectral significant height Hm0 = 4 sqrt(m0) throughout, m0 the variance of the elevation (the
zeroth moment of S): the parametric spectra are normalised so that m0 = Hs^2 / 16 over 0 < f < inf.
"""

from __future__ import annotations

import functools
import math
from pathlib import Path
from typing import Annotated, Literal, Union

import numpy as np
from pydantic import Field, PrivateAttr

from ..geometry.shapes import CasePath, PositiveReal, Spec

_X_MIN = 0.05
"""f / fp below which the parametric spectra are 0: exp(-1.25 (fp / f)^4) < exp(-200000) underflows to 0 there
anyway, and x^-5 would overflow for f / fp < 1e-62."""


class Spectrum(Spec):
    """Base of the variance density spectra S(f) [m^2/Hz] (abstract)."""

    def density(self, f):
        """S(f) [m^2/Hz] at the frequencies `f` [Hz] (array_like; 0 for f <= 0)."""
        raise NotImplementedError

    @property
    def peak_frequency(self):
        """fp [Hz], where S is largest."""
        raise NotImplementedError

    def moment(self, n, f_min=0.0, f_max=math.inf):
        """The spectral moment m_n = int_{f_min}^{f_max} f^n S(f) df [m^2 Hz^n] (n = 0: the variance [m^2])."""
        raise NotImplementedError

    @property
    def m0(self):
        """The variance m0 = int S(f) df [m^2] of the elevation."""
        return self.moment(0)

    @property
    def hm0(self):
        """The spectral significant height Hm0 = 4 sqrt(m0) [m]."""
        return 4.0 * math.sqrt(self.m0)


def _shape_moment(n, x_lo, x_hi, gamma, sigma_a, sigma_b):
    """int_{x_lo}^{x_hi} x^n x^-5 exp(-1.25 x^-4) gamma^r(x) dx, r the JONSWAP peak enhancement's exponent,
    integrated in u = 1.25 x^-4 (dx x^-5 = -du / 5): (1/5) int x(u)^n exp(-u) gamma^r(x(u)) du, a smooth
    integrand but for the factor u^(-n/4) at u = 0 (f -> inf, integrable for n < 4)."""
    from scipy.integrate import quad

    if x_hi == math.inf and n >= 4:
        return math.inf
    u_lo = 0.0 if x_hi == math.inf else 1.25 / x_hi**4
    u_hi = math.inf if x_lo <= 0 else 1.25 / x_lo**4
    if not u_lo < u_hi:
        return 0.0

    def integrand(u):
        x = (1.25 / u) ** 0.25
        s = sigma_a if x <= 1.0 else sigma_b
        return x**n * math.exp(-u) * gamma ** math.exp(-((x - 1.0) ** 2) / (2.0 * s * s))

    total = 0.0
    # the peak (x = 1, u = 1.25) and its enhancement, a few sigma wide, split off so that quad samples them
    cuts = [u_lo] + [c for c in (1.25 / 1.5**4, 1.25, 1.25 / 0.7**4, 60.0) if u_lo < c < u_hi] + [u_hi]
    for a, b in zip(cuts[:-1], cuts[1:]):
        total += quad(integrand, a, b, epsabs=0.0, epsrel=1e-13, limit=200)[0]
    return total / 5.0


@functools.lru_cache(maxsize=64)
def _jonswap_beta(gamma, sigma_a, sigma_b):
    return 1.0 / (16.0 * _shape_moment(0, 0.0, math.inf, gamma, sigma_a, sigma_b))


class JonswapSpectrum(Spectrum):
    """JONSWAP spectrum (Hasselmann et al. 1973) in Goda's (1988) form, of significant height `hs` Hs [m],
    peak period `tp` Tp [s] and peak enhancement `gamma`:

        S(f) = beta Hs^2 Tp^-4 f^-5 exp(-1.25 (Tp f)^-4) gamma^exp(-(Tp f - 1)^2 / (2 sigma^2)),

    sigma = `sigma_a` for f <= fp = 1 / Tp, `sigma_b` above. Goda's approximation of the constant,
    beta_J = 0.0624 (1.094 - 0.01915 ln gamma) / (0.230 + 0.0336 gamma - 0.185 / (1.9 + gamma)) (`goda_beta`),
    is written for the significant height H_1/3 of a zero-crossing analysis (taken as Hm0 it gives m0 = 1.057
    to 1.093 Hs^2 / 16 for 1 <= gamma <= 7); here Hs is Hm0 = 4 sqrt(m0), so `beta` is computed instead, by
    quadrature, such that m0 = Hs^2 / 16 over 0 < f < inf exactly (to the quadrature's 1e-13):
    beta = 1 / (16 int x^-5 exp(-1.25 x^-4) gamma^r dx), x = f Tp, r the exponent of gamma above.
    gamma = 1 gives beta = 5/16, the Pierson-Moskowitz spectrum. S is largest at fp.
    """

    type: Literal["jonswap"] = "jonswap"
    hs: PositiveReal
    tp: PositiveReal
    gamma: Annotated[float, Field(ge=1.0, le=20.0, allow_inf_nan=False, strict=True)] = 3.3
    sigma_a: Annotated[float, Field(gt=0.0, le=1.0, allow_inf_nan=False, strict=True)] = 0.07
    sigma_b: Annotated[float, Field(gt=0.0, le=1.0, allow_inf_nan=False, strict=True)] = 0.09

    @property
    def peak_frequency(self):
        """fp = 1 / Tp [Hz]."""
        return 1.0 / self.tp

    @property
    def beta(self):
        """The constant beta of the formula that makes m0 = Hs^2 / 16 (by quadrature; 5/16 for gamma = 1)."""
        return _jonswap_beta(float(self.gamma), float(self.sigma_a), float(self.sigma_b))

    @property
    def goda_beta(self):
        """Goda's (1988) approximation beta_J = 0.0624 (1.094 - 0.01915 ln gamma) / (0.230 + 0.0336 gamma
        - 0.185 / (1.9 + gamma)), for H_1/3 (not used: `beta` is)."""
        g = self.gamma
        return 0.0624 / (0.230 + 0.0336 * g - 0.185 / (1.9 + g)) * (1.094 - 0.01915 * math.log(g))

    def density(self, f):
        """S(f) [m^2/Hz] at `f` [Hz] (array_like; 0 for f <= 0.05 fp, where it underflows to 0)."""
        x = np.asarray(f, float) * self.tp
        xs = np.maximum(x, _X_MIN)
        s = np.where(xs <= 1.0, self.sigma_a, self.sigma_b)
        shape = xs**-5 * np.exp(-1.25 * xs**-4) * self.gamma ** np.exp(-((xs - 1.0) ** 2) / (2.0 * s * s))
        return np.where(x > _X_MIN, self.beta * self.hs**2 * self.tp * shape, 0.0)

    def moment(self, n, f_min=0.0, f_max=math.inf):
        """m_n = int_{f_min}^{f_max} f^n S(f) df by quadrature (in u = 1.25 (fp / f)^4); inf for n >= 4 up to
        f = inf (S ~ f^-5)."""
        integral = _shape_moment(n, f_min * self.tp, f_max * self.tp, float(self.gamma), float(self.sigma_a),
                                 float(self.sigma_b))
        return self.beta * self.hs**2 * self.tp**-n * integral


class PiersonMoskowitzSpectrum(Spectrum):
    """Pierson-Moskowitz spectrum (Pierson & Moskowitz 1964) of a fully developed sea, of significant height
    `hs` Hs [m] and peak period `tp` Tp [s], in the form of Bretschneider (1959) and Goda (1988):

        S(f) = (5/16) Hs^2 fp^4 f^-5 exp(-1.25 (fp / f)^4),   fp = 1 / Tp,

    whose m0 is Hs^2 / 16 exactly (int_0^inf x^-5 exp(-1.25 x^-4) dx = 1/5). The JONSWAP spectrum of
    gamma = 1.
    """

    type: Literal["pierson_moskowitz"] = "pierson_moskowitz"
    hs: PositiveReal
    tp: PositiveReal

    @property
    def peak_frequency(self):
        """fp = 1 / Tp [Hz]."""
        return 1.0 / self.tp

    def density(self, f):
        """S(f) [m^2/Hz] at `f` [Hz] (array_like; 0 for f <= 0.05 fp, where it underflows to 0)."""
        x = np.asarray(f, float) * self.tp
        xs = np.maximum(x, _X_MIN)
        return np.where(x > _X_MIN, 0.3125 * self.hs**2 * self.tp * xs**-5 * np.exp(-1.25 * xs**-4), 0.0)

    def moment(self, n, f_min=0.0, f_max=math.inf):
        """m_n = int_{f_min}^{f_max} f^n S(f) df by quadrature; m0 = Hs^2 / 16 over the whole axis; inf for
        n >= 4 up to f = inf."""
        integral = _shape_moment(n, f_min * self.tp, f_max * self.tp, 1.0, 0.07, 0.09)
        return 0.3125 * self.hs**2 * self.tp**-n * integral


_FILE_FORM = ("give two columns, f [Hz] and S [m^2/Hz], one row per frequency, the frequencies increasing; "
              "'#' comments and one header row allowed")


class FileSpectrum(Spectrum):
    """A spectrum tabulated in the text file `file`: two columns, frequency f [Hz] (non-negative, increasing
    strictly) and S [m^2/Hz] (non-negative, not all zero), separated by spaces, tabs or commas; '#' starts a
    comment, and the first row may be a header. S(f) is the straight line between rows and 0 outside the
    table, so its moments are those of the piecewise-linear S (m0 the trapezoidal sum of the table), Hm0 =
    4 sqrt(m0), and fp is the frequency of the largest S in the table. A relative path in a case file is
    relative to the case file; in Python, to the working directory. A bad file is a `shoal.errors.InputError`
    (when the spectrum is first used).
    """

    type: Literal["file"] = "file"
    file: CasePath
    _table: tuple | None = PrivateAttr(default=None)

    def _fail(self, problem):
        from ..errors import InputError

        return InputError(f"spectrum file {self.file!r}: {problem}; {_FILE_FORM}")

    def _load(self):
        p = Path(self.file)
        if not p.is_file():
            raise self._fail("not found" if not p.exists() else "not a file")
        try:
            text = p.read_text(encoding="utf-8-sig")
        except UnicodeDecodeError:
            raise self._fail("not a text file (UTF-8)") from None
        except OSError as exc:
            raise self._fail(f"could not be read ({exc.strerror or exc})") from None
        rows, header_seen = [], False
        for number, line in enumerate(text.split("\n"), start=1):
            line = line.split("#", 1)[0].replace(",", " ").strip()
            if not line:
                continue
            parts = line.split()
            try:
                values = [float(v) for v in parts]
            except ValueError:
                values = None
            if values is None and not rows and not header_seen:
                header_seen = True  # a header row, before the first row of numbers
                continue
            shown = line if len(line) <= 40 else line[:37] + "..."
            if values is None or len(values) != 2:
                raise self._fail(f"line {number} ({shown!r}) is not two numbers")
            if not all(math.isfinite(v) for v in values):
                raise self._fail(f"line {number} ({shown!r}) holds a value that is not finite")
            rows.append(values)
        if len(rows) < 2:
            raise self._fail(f"{len(rows)} row{'' if len(rows) == 1 else 's'} of numbers, fewer than 2")
        a = np.array(rows)
        f, s = a[:, 0], a[:, 1]
        if f[0] < 0:
            raise self._fail(f"the frequency {f[0]:g} Hz is negative")
        if np.any(np.diff(f) <= 0):
            raise self._fail("the frequencies do not increase strictly")
        if np.any(s < 0):
            raise self._fail(f"S = {s[s < 0][0]:g} m^2/Hz is negative")
        if not np.any(s > 0):
            raise self._fail("S is zero at every frequency")
        self._table = (f, s)
        return self._table

    @property
    def table(self):
        """(f [Hz], S [m^2/Hz]): the file's rows, as arrays."""
        return self._table or self._load()

    @property
    def peak_frequency(self):
        """The frequency [Hz] of the table's largest S (the first, if several are equal)."""
        f, s = self.table
        return float(f[np.argmax(s)])

    def density(self, f):
        """S(f) [m^2/Hz] at `f` [Hz]: linear between the table's rows, 0 outside them."""
        fs, ss = self.table
        return np.interp(np.asarray(f, float), fs, ss, left=0.0, right=0.0)

    def moment(self, n, f_min=0.0, f_max=math.inf):
        """m_n of the piecewise-linear S over [f_min, f_max], by 8-point Gauss-Legendre quadrature on each
        piece (exact for integer 0 <= n <= 14; m0 is the trapezoidal sum)."""
        fs, ss = self.table
        lo, hi = max(f_min, fs[0]), min(f_max, fs[-1])
        if not lo < hi:
            return 0.0
        knots = np.concatenate([[lo], fs[(fs > lo) & (fs < hi)], [hi]])
        x, w = np.polynomial.legendre.leggauss(8)
        a, b = knots[:-1, None], knots[1:, None]
        f = 0.5 * (b - a) * x + 0.5 * (a + b)
        return float(np.sum(0.5 * (b - a) * w * f**n * self.density(f)))


AnySpectrum = Annotated[Union[JonswapSpectrum, PiersonMoskowitzSpectrum, FileSpectrum], Field(discriminator="type")]
"""A spectrum of any type, chosen by its ``type``."""

SPECTRA = {"jonswap": JonswapSpectrum, "pierson_moskowitz": PiersonMoskowitzSpectrum, "file": FileSpectrum}
"""The spectrum classes by their ``type``."""
