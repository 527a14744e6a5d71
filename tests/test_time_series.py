"""`shoal.time_series.TimeSeries`: a value given as a table, a file or a function, linear between the given
times and held beyond them, with one-line errors for what cannot be one."""

from __future__ import annotations

import math

import pytest

from shoal.errors import InputError
from shoal.time_series import TimeSeries, value_at, value_bounds


def test_a_table_is_linear_between_its_times_and_held_beyond():
    s = TimeSeries(t=[0.0, 2.0, 10.0], value=[0.0, 0.3, 0.1])
    assert s(-1.0) == 0.0 and s(20.0) == 0.1
    assert s(1.0) == pytest.approx(0.15)
    assert s(6.0) == pytest.approx(0.2)
    assert s.bounds(0.0, 1.0) == pytest.approx((0.0, 0.15))
    assert s.bounds(1.0, 10.0) == pytest.approx((0.1, 0.3))  # the peak at t = 2 inside the window


def test_a_file_with_a_header_and_comments_reads_as_its_table(tmp_path):
    f = tmp_path / "tide.csv"
    f.write_text("# a tide\nt,level\n0,0.2\n3,0.25\n6,0.2\n")
    s = TimeSeries(file=str(f), scale=2.0)
    assert s(1.5) == pytest.approx(0.45)
    assert s.bounds(0.0, 6.0) == pytest.approx((0.4, 0.5))
    w = tmp_path / "q.txt"
    w.write_text("0 1\n1 3\n")
    assert TimeSeries(file=str(w))(0.25) == pytest.approx(1.5)


def test_a_function_is_called_and_its_extremes_sampled():
    s = TimeSeries(function=lambda t: 0.2 + 0.05 * math.sin(t))
    assert s(math.pi / 2) == pytest.approx(0.25)
    lo, hi = s.bounds(0.0, 2 * math.pi)
    assert lo == pytest.approx(0.15, abs=1e-5) and hi == pytest.approx(0.25, abs=1e-5)
    assert "function" not in s.model_dump()  # a case file is data: the function is not written to one


def test_numbers_and_series_read_alike():
    assert value_at(0.3, 5.0) == 0.3 and value_at(None, 1.0) is None
    assert value_at(TimeSeries(t=[0, 1], value=[0, 1]), 0.5) == 0.5
    assert value_bounds(0.3, 0.0, 1.0) == (0.3, 0.3)


@pytest.mark.parametrize("given, message", [
    (dict(t=[0.0, 1.0], value=[1.0]), "give one value per time"),
    (dict(t=[0.0], value=[1.0]), "at least two"),
    (dict(t=[0.0, 0.0], value=[1.0, 2.0]), "must increase"),
    (dict(t=[0.0, 1.0]), "needs both t and value"),
    (dict(), "got none"),
    (dict(t=[0.0, 1.0], value=[0.0, 1.0], file="x.csv"), "got t and value, file"),
    (dict(function="lambda t: t"), "Python-API only"),
])
def test_a_bad_series_is_one_clear_error(given, message):
    with pytest.raises(ValueError, match=message):
        TimeSeries(**given)


@pytest.mark.parametrize("text, message", [
    (None, "not found"),
    ("0,1,2\n1,2,3\n", "two columns"),
    ("t,v\n0,1\n", "holds 1 rows of numbers"),
    ("0,1\n2,2\n1,3\n", "must increase"),
])
def test_a_bad_file_is_one_clear_error(tmp_path, text, message):
    f = tmp_path / "s.csv"
    if text is not None:
        f.write_text(text)
    with pytest.raises(InputError, match=message):
        TimeSeries(file=str(f))(0.0)
