"""Random case dictionaries never give a traceback (issue 7, item 4).

Property: a case dictionary -- the parsed TOML of a built-in case, mutated
at random (keys deleted, values replaced by JSON-like values of other
types, unknown keys inserted, numbers replaced by 0, negatives, inf, nan,
huge values) -- gives either a valid `Case` or `shoal.errors.InputError`
with a one-line message; nothing else. A valid mutant is then taken
through what ``shoal check`` does (the particles, the memory and
checkpoint estimates, the probe and motion checks), but only where its
lattice is small (a mutant with a tiny dp is only validated: generating
millions of particles here would prove nothing more: it only meets the
guard that refuses a case too big for the memory before generating it),
and written back as a case file that loads to the same case.

Derandomized (the same examples on every run, so CI is stable);
``max_examples`` 200, no deadline (a first particle generation imports
scipy).
"""

from __future__ import annotations

import math
import tomllib

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from shoal.case import Case
from shoal.casefile import case_from_dict, dumps_case
from shoal.cases import get_case
from shoal.errors import InputError

# small built-in cases covering every table: tanks, boxes, a slope, a piston and gauges (wave flume),
# a 3D tank and column, a moving inflow wall (tidal bore 2D section)
BASES = {
    "still-water-2d": dict(dp=0.05),
    "wave-flume-2d": dict(dp=0.04),
    "dam-break-3d": dict(dp=0.0365),
    "tidal-bore": dict(dp=0.02, dim=2),
}
MAX_NODES = 60_000  # generate particles only below this many lattice nodes (about 0.1 s)


def _base(name):
    return tomllib.loads(dumps_case(get_case(name, **BASES[name]), commented=False))


BASE_DICTS = {name: _base(name) for name in BASES}

SPECIAL_NUMBERS = [0, 0.0, -0.0, -1, -1.5, 1e-300, 1e-12, 1e12, 1e300, -1e300, math.inf, -math.inf, math.nan,
                   2**63, -(2**63), 10**30, 3, 2, 1, 0.5, True, False]

scalars = (st.none() | st.booleans() | st.integers(min_value=-(2**70), max_value=2**70)
           | st.floats(allow_nan=True, allow_infinity=True) | st.sampled_from(SPECIAL_NUMBERS)
           | st.text(max_size=8) | st.sampled_from(["box", "tank", "piston", "x", "top", "float16", ""]))
values = st.recursive(scalars, lambda inner: st.lists(inner, max_size=4)
                      | st.dictionaries(st.text(max_size=6), inner, max_size=3), max_leaves=8)


def _containers(obj, path=()):
    """Every (path, dict-or-list) inside `obj`, `obj` included."""
    out = [(path, obj)]
    items = obj.items() if isinstance(obj, dict) else enumerate(obj) if isinstance(obj, list) else ()
    for k, v in items:
        if isinstance(v, (dict, list)):
            out += _containers(v, path + (k,))
    return out


def _mutate(data, d):
    """Apply one random mutation to the nested dict `d` in place."""
    conts = _containers(d)
    path, c = conts[data.draw(st.integers(0, len(conts) - 1), label="container")]
    keys = list(c) if isinstance(c, dict) else list(range(len(c)))
    op = data.draw(st.sampled_from(["delete", "replace", "number", "unknown", "retype"]), label="op")
    if op == "unknown" and isinstance(c, dict):
        c[data.draw(st.text(min_size=1, max_size=8), label="new key")] = data.draw(values, label="value")
        return
    if not keys:
        return
    k = data.draw(st.sampled_from(keys), label="key")
    if op == "delete":
        del c[k]
    elif op == "number":
        c[k] = data.draw(st.sampled_from(SPECIAL_NUMBERS), label="number")
    elif op == "retype":  # the same value wrapped in a list / made a string / a table
        v = c[k]
        c[k] = data.draw(st.sampled_from([[v], str(v), {"value": v}]), label="retyped")
    else:
        c[k] = data.draw(values, label="value")


def _nodes(case):
    lo, hi = case._generation_box()
    axes = (0, 2) if case.dim == 2 else (0, 1, 2)
    return math.prod(max(1.0, (hi[a] - lo[a]) / case.dp + 1) for a in axes)


def _one_line(err):
    msg = str(err)
    assert msg and "\n" not in msg and "\r" not in msg, repr(msg)
    assert "Traceback" not in msg
    return msg


def _exercise(case):
    """What `shoal check` does, where the lattice is small; and the round trip of the case file."""
    from shoal.check import check_case

    text = dumps_case(case, commented=True)
    again = case_from_dict(tomllib.loads(text))
    # the commented file records the parameters as comments only, the uncommented one as a table
    assert dumps_case(again) == dumps_case(case.model_copy(update={"parameters": {}}))
    resolved = dumps_case(case, commented=False)
    assert dumps_case(case_from_dict(tomllib.loads(resolved)), commented=False) == resolved  # (text: nan)
    if _nodes(case) <= MAX_NODES:
        lines = check_case(case)
        assert any("particles:" in line for line in lines)
    else:  # only the guard that refuses, before generating, what cannot fit (it may pass: the case is valid)
        from shoal.memory import check_generation_size

        check_generation_size(case, *case._generation_box())


@settings(max_examples=200, deadline=None, derandomize=True, database=None,
          suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])
@given(data=st.data(), base=st.sampled_from(sorted(BASES)), n=st.integers(1, 4))
def test_random_case_dicts_give_a_case_or_one_line_input_error(data, base, n):
    d = _copy(BASE_DICTS[base])
    for _ in range(n):
        _mutate(data, d)
    try:
        case = case_from_dict(d, source="case.toml")
    except InputError as err:
        msg = _one_line(err)
        assert msg.startswith("case.toml: "), msg
        return
    assert isinstance(case, Case)
    try:
        _exercise(case)
    except InputError as err:
        _one_line(err)


def _copy(obj):
    if isinstance(obj, dict):
        return {k: _copy(v) for k, v in obj.items()}
    if isinstance(obj, list):
        return [_copy(v) for v in obj]
    return obj


@pytest.mark.parametrize("base", sorted(BASES))
def test_unmutated_bases_are_valid_and_cheap(base):
    """The starting points themselves load, check and round-trip (so the property exercises mutants of
    valid cases, and valid mutants are taken through `shoal check`)."""
    case = case_from_dict(_copy(BASE_DICTS[base]))
    assert _nodes(case) <= MAX_NODES
    _exercise(case)
    assert np.count_nonzero(case.particles().kinds == 0) > 0
