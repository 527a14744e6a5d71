"""`TimeSeries`: a quantity that changes in time, given as a table, a file or (Python API) a function.

Open boundaries take one where a number would do (`shoal.open_boundary.OpenBoundary`: an inflow's velocity or
discharge following a hydrograph, a level following a tide). Between the given times the value is linear in
t (as DualSPHysics's inlet velocity and surface-level files); before the first time it holds the first value,
after the last the last.

In a case file::

    velocity = {t = [0.0, 2.0, 10.0], value = [0.0, 0.3, 0.3]}   # a ramp, then steady
    level = {file = "tide.csv"}                                  # columns t [s], value ('#' comments, header)
"""

from __future__ import annotations

from pathlib import Path
from typing import Annotated, Callable

import numpy as np
from pydantic import Field, PrivateAttr, field_validator, model_validator

from .errors import InputError
from .geometry.shapes import CasePath, Real, RealList, Spec, python_function

SAMPLES = 2001
"""Points at which a function's extremes over a run are looked for (`TimeSeries.bounds`), and of the table that
stands for it in a run (`TimeSeries.sampled`)."""


class TimeSeries(Spec):
    """A value v(t), piecewise linear between given times and held beyond them.

    Give exactly one of

    - `t` and `value`: the table (at least two times, increasing);
    - `file`: a text file of two columns t [s], value (.csv comma-separated, else whitespace; '#' comments and
      a header line allowed); a relative path is relative to the case file;
    - `function`: a Python callable v(t) of a float (Python API only: a case file is data and cannot hold code;
      a run samples it at `SAMPLES` times over [0, end_time] and runs and writes that table, so that what a
      run's ``case.toml`` holds is what ran and what a resume continues).

    Attributes
    ----------
    t, value : lists of floats
    file : str
    function : callable
    scale : float
        Multiplies every value (a file in other units, a hydrograph scaled to a model).
    """

    t: RealList | None = None
    value: RealList | None = None
    file: CasePath | None = None
    function: Annotated[Callable | None, Field(exclude=True)] = None
    scale: Real = 1.0
    _table: object = PrivateAttr(default=None)

    @field_validator("function", mode="before")
    @classmethod
    def _code(cls, v):
        return python_function(v, "give the series as t and value, or a file")

    @model_validator(mode="after")
    def _one(self):
        table = self.t is not None or self.value is not None
        given = [k for k, on in (("t and value", table), ("file", self.file is not None),
                                 ("function", self.function is not None)) if on]
        if len(given) != 1:
            raise ValueError("a time series is one of t and value (a table), file or function (got "
                             f"{', '.join(given) if given else 'none'})")
        if table:
            if self.t is None or self.value is None:
                raise ValueError("a table needs both t and value")
            if len(self.t) != len(self.value) or len(self.t) < 2:
                raise ValueError(f"t has {len(self.t)} values and value {len(self.value)}: give one value per time, "
                                 "at least two")
            if any(b <= a for a, b in zip(self.t, self.t[1:])):
                raise ValueError("the times t must increase from one to the next")
        return self

    def table(self):
        """(t, v) arrays of the table or the file (scaled), or None for a function; reads the file once.

        Raises
        ------
        InputError
            The file is missing or is not two columns of increasing times.
        """
        if self.function is not None:
            return None
        if self._table is None:
            if self.t is not None:
                t, v = np.asarray(self.t, float), np.asarray(self.value, float)
            else:
                t, v = _read(self.file)
            self._table = (t, v * float(self.scale))
        return self._table

    def __call__(self, t):
        """v(t) (a float)."""
        tab = self.table()
        if tab is None:
            v = float(self.function(float(t)))
            return v * float(self.scale)
        return float(np.interp(t, tab[0], tab[1]))

    def sampled(self, t0, t1, n=SAMPLES):
        """A function as a table of `n` points over [t0, t1] (scale applied); a table or a file as it is."""
        if self.function is None:
            return self
        t = np.linspace(t0, t1, n)
        return TimeSeries(t=t.tolist(), value=[self(x) for x in t])

    def bounds(self, t0, t1):
        """(smallest, largest) value over [t0, t1] [s]: at the table's times inside it and its ends, or a
        function sampled at `SAMPLES` points."""
        tab = self.table()
        if tab is None:
            vs = [self(t) for t in np.linspace(t0, t1, SAMPLES)]
        else:
            ts = np.concatenate([[t0, t1], tab[0][(tab[0] > t0) & (tab[0] < t1)]])
            vs = np.interp(ts, tab[0], tab[1])
        return float(np.min(vs)), float(np.max(vs))


def _read(path):
    """(t, v) of a two-column file (`TimeSeries`)."""
    p = Path(path)
    if not p.is_file():
        raise InputError(f"time-series file {str(path)!r} not found")
    try:
        a = np.genfromtxt(p, delimiter="," if p.suffix == ".csv" else None, comments="#")
    except ValueError as exc:
        raise InputError(f"time-series file {str(path)!r} could not be read: {' '.join(str(exc).split())}") from None
    a = np.atleast_2d(a)
    if a.ndim != 2 or a.shape[1] != 2:
        raise InputError(f"time-series file {str(path)!r} must hold two columns, t [s] and the value")
    a = a[np.all(np.isfinite(a), axis=1)]  # a header line reads as NaN
    if len(a) < 2:
        raise InputError(f"time-series file {str(path)!r} holds {len(a)} rows of numbers: give at least two")
    if np.any(np.diff(a[:, 0]) <= 0):
        raise InputError(f"time-series file {str(path)!r}: the times (first column) must increase from one row to "
                         "the next")
    return a[:, 0].copy(), a[:, 1].copy()


def value_at(x, t):
    """`x` at time t: x itself for a number, x(t) for a `TimeSeries`, None for None."""
    if x is None or not isinstance(x, TimeSeries):
        return x
    return x(t)


def value_bounds(x, t0, t1):
    """(smallest, largest) of `x` over [t0, t1]: (x, x) for a number."""
    if isinstance(x, TimeSeries):
        return x.bounds(t0, t1)
    return float(x), float(x)


__all__ = ["TimeSeries", "value_at", "value_bounds"]
