"""Hostile case files and command lines never give a traceback (issue 30, must-show 3).

Two properties, each over inputs built by Hypothesis:

* **TOML documents, as text.** A case file that ``shoal new`` writes (small
  built-in cases), mutated where a person or a tool would damage it: a value
  replaced by numbers at the float limits (1.7976931348623157e308, 5e-324,
  -0.0, nan, +inf, -inf), integers beyond int64 or beyond the 4300 digits
  Python reads, 1_000-style underscores, hex/octal/binary integers, strings
  with control characters, escapes, unicode or 100,000 characters,
  datetimes; tables and inline tables or arrays nested up to thousands
  deep; keys inserted, duplicated, dotted; table headers repeated; lines
  deleted; characters inserted, deleted, the text cut off; and, at the byte
  level, a BOM, NUL bytes, CRLF or CR line ends, bytes that are not UTF-8,
  UTF-16. Each document is written to a file and read by
  `shoal.casefile.load_case`, which must give a `Case` or an `InputError` of
  one line, and given to ``shoal check FILE`` (`shoal.cli.main`, in this
  process), which must exit 0 or 2 and, on 2, print exactly that error as
  its one line ``shoal: error: ...``.
* **Command lines.** Argument lists whose subcommands and options are read
  from the real parser (`shoal.cli.build_parser`), with values drawn from
  the valid ones and from junk: unknown flags, missing values, values of the
  wrong type ('0_05', 'nan', '-1', '1e309'), ``--param``/``--option``
  KEY=VALUE items with unknown keys and values of every TOML kind, paths to
  missing files, to a directory, to /dev/null, empty and 5000-character
  strings, '-', unicode and the undecodable bytes a shell can pass
  (surrogate escapes). Each runs through `shoal.cli.main` in a fresh folder
  and must exit 0 or 2 (argparse's own errors included: the project prints
  them as one line too), with no traceback; on 2 exactly one line
  ``shoal: error: ...`` and no file in the folder changed or created; and
  nothing outside the folder created or changed. (Before the error line,
  and on 0, standard error holds only ``shoal: warning: ...`` lines: a
  resume warns of each damaged checkpoint it skips.)

Why: the project's rule for bad input is one line naming what is wrong and
what is allowed, exit status 2, nothing of the user's overwritten; the
corpora of `test_bad_inputs` hold the cases someone thought of, and
`test_bad_inputs_property` mutates parsed dictionaries, which never meet the
TOML reader or the argument parser.

Standard output is a strict UTF-8 stream, as under a UTF-8 locale such as
en_US.UTF-8 (a character it cannot encode, a surrogate escape from an
undecodable argument, is an error there); standard error replaces such a
character, as Python's does.

Two things are not run, so that each example takes milliseconds:

* the time loop of ``shoal run`` (`shoal.runner._steps`: compiling the
  kernels of one scheme takes 6-15 s, and the numerics are tested
  elsewhere): everything before it runs for real (the case and its options
  are validated, the memory is checked, the output directory is prepared
  and locked, an earlier run's files are cleared), and a stand-in returns
  the result of a run of no step; likewise `shoal.validation.run_validation`
  behind ``shoal validate`` (the validation runs take minutes to hours);
* a valid mutant document whose lattice is large is only validated and
  measured against the guard that refuses a case too big for the memory
  (as in `test_bad_inputs_property`); the command-line property pretends
  to run on a machine of 256 MiB, so that a ``--dp`` or ``--param`` that
  scales a case up meets that same guard (`shoal.memory.check_count`)
  instead of generating millions of particles.

Derandomized (the same examples on every run); no deadline (the first
example imports scipy and matplotlib).
"""

from __future__ import annotations

import argparse
import contextlib
import hashlib
import io
import os
import re
import stat
import tempfile
from dataclasses import fields
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest
from hypothesis import HealthCheck, event, example, given, settings
from hypothesis import strategies as st

from shoal import cli
from shoal.case import Case
from shoal.casefile import dumps_case, load_case
from shoal.cases import case_parameters, get_case
from shoal.errors import InputError
from shoal.memory import check_generation_size
from shoal.options import SPHOptions
from shoal.validation import VALIDATION_CASES
from test_bad_inputs import _cli, _one_error_line
from test_bad_inputs_property import BASES, MAX_NODES, _nodes, _one_line

REPO = Path(__file__).resolve().parents[1]
# (the strategies hold strings of thousands of characters; Hypothesis warns when it shows one)
pytestmark = pytest.mark.filterwarnings("ignore:Generating overly large repr")

# the case files `shoal new` writes for the small built-in cases of test_bad_inputs_property (commented, as a
# person would start from them)
BASE_TEXTS = {name: dumps_case(get_case(name, **kw), commented=True) for name, kw in BASES.items()}

# ----------------------------------------------------------------------------- TOML values, as text

FLOAT_LIMITS = ["1.7976931348623157e308", "-1.7976931348623157e308", "1.7976931348623159e308", "1e309", "-1e309",
                "5e-324", "-5e-324", "4.9e-324", "2.2250738585072014e-308", "1e-400", "-0.0", "+0.0", "0.0",
                "nan", "+nan", "-nan", "inf", "+inf", "-inf", "1e+300", "1E-300", "6.02214076e23"]
INTEGERS = ["0", "-0", "+1", "9223372036854775807", "9223372036854775808", "-9223372036854775809",
            "18446744073709551616", "1" + "0" * 40, "9" * 4300, "9" * 4301, "-" + "9" * 5000, "1_000",
            "1_000.000_1", "0x7FFF_FFFF", "0xdead_beef", "0x" + "f" * 17, "0x" + "f" * 4000, "0x" + "f" * 5000,
            "0o755", "0b1010", "0b" + "1" * 200]
# not TOML numbers: the reader must refuse them in one line
BAD_NUMBERS = ["1__0", "_1", "1_", "01", ".5", "5.", "1e", "0x", "0xG", "0o8", "0b2", "1.e5", "--1", "+-1",
               "NaN", "Inf", "infinity", "1,5", "0x-1", "\u0661", "1e1_0", "0.0.0"]
DATETIMES = ["1979-05-27T07:32:00Z", "1979-05-27T00:32:00.999999-07:00", "1979-05-27 07:32:00", "1979-05-27",
             "07:32:00", "00:32:00.999999", "1979-02-30", "9999-12-31T23:59:59Z", "0000-01-01",
             "1979-05-27T07:32:00+24:00", "1979-05-27T25:00:00"]
STRING_LITERALS = ['""', "''", '"\\x41"', '"\\uD800"', '"\\U00110000"', '"\\U0010FFFF"', "'C:\\path\\no escapes'",
                   '"""multi\nline"""', "'''raw\nmulti'''", '"unterminated', '"\\u001b[31mred\\u0007"',
                   '"a\\u0000b"', '"\\u2028\\u0085\\u200f"', '"x' + "x" * 100_000 + '"', '"\\u00e9\U0001f30a"',
                   '"../../etc/passwd"', '"/dev/null"', '"."', '".."', '"tank\\nname"', '"\\t"', "'\t'",
                   '"a" "b"', "'it''s'"]
KEYWORDS = ["true", "false", "True", "null", "none", "[]", "{}", "[,]", "{,}", "[1,]", "{a = 1,}"]


def _basic_string(text, raw_controls):
    """`text` as a TOML basic string; control characters escaped, or left raw (not TOML: refused)."""
    out = []
    for ch in text:
        if ch in '"\\':
            out.append("\\" + ch)
        elif (ord(ch) < 0x20 or ch == "\x7f") and not raw_controls:
            out.append(f"\\u{ord(ch):04X}")
        else:
            out.append(ch)
    return '"' + "".join(out) + '"'


numbers = (st.sampled_from(FLOAT_LIMITS) | st.sampled_from(INTEGERS) | st.sampled_from(BAD_NUMBERS)
           | st.floats().map(repr) | st.integers(-(2**80), 2**80).map(str))
strings = (st.builds(_basic_string, st.text(max_size=12), st.booleans()) | st.sampled_from(STRING_LITERALS)
           | st.builds(_basic_string, st.text(st.characters(codec="utf-8"), min_size=200, max_size=600),
                       st.just(False)))
bare_keys = st.sampled_from(["a", "dp", "type", "name", "lo", "hi", "x", "1", "-", "_", "\u00e9", '"quoted key"',
                             "'literal key'", '""', '"\\u0000"', "a.b", "fluid.depth", "a b", "=", "[x]",
                             ".".join(["k"] * 500)])
scalars = numbers | strings | st.sampled_from(DATETIMES) | st.sampled_from(KEYWORDS)
values = st.recursive(scalars, lambda inner: st.lists(inner, max_size=4).map(lambda xs: "[" + ", ".join(xs) + "]")
                      | st.lists(st.tuples(bare_keys, inner), max_size=3).map(
                          lambda kv: "{" + ", ".join(f"{k} = {v}" for k, v in kv) + "}"), max_leaves=8)


def _deep(kind, depth, leaf):
    """`leaf` nested `depth` deep in arrays, inline tables or both by turns."""
    if kind == "array":
        return "[" * depth + leaf + "]" * depth
    if kind == "inline":
        return "{a = " * depth + leaf + "}" * depth
    opens = "".join("[" if k % 2 else "{a = " for k in range(depth))
    return opens + leaf + "".join("]" if k % 2 else "}" for k in reversed(range(depth)))


deep_values = st.builds(_deep, st.sampled_from(["array", "inline", "mixed"]),
                        st.sampled_from([2, 30, 150, 300, 400, 1000, 5000]), scalars)
any_value = values | deep_values
HEADERS = ["[fluid]", "[[solids]]", "[options]", "[domain]", "[output]", "[[probes]]", "[[fluid]]", "[ fluid . x ]",
           "[]", "[[]]", "[fluid", "[a]]", "[" + ".".join(["t"] * 300) + "]", '["\\u0000"]', "[[solids.shape]]",
           "[solids]", "[checkpoint.interval]"]
# tables a case file may add (shapes that read files, motions, probes, a domain, planes), each "{S}" a string
# and each "{N}" a number drawn anew: file names and names of every kind, numbers at the limits
TABLES = [
    '[[solids]]\nname = {S}\nshape = { type = "mesh", file = {S} }',
    '[[solids]]\nname = {S}\nshape = { type = "bathymetry", file = {S}, base = {N} }',
    '[[solids]]\nname = {S}\nmotion = {S}\nshape = { type = "box", lo = [{N}, {N}, {N}], hi = [{N}, {N}, {N}] }',
    '[[solids]]\nshape = { type = "cylinder", axis = {S}, center = [{N}, {N}], radius = {N} }',
    '[[motions]]\ntype = "time_series"\nname = {S}\nfile = {S}',
    '[[motions]]\ntype = "piston"\nname = "p"\nheight = {N}\nperiod = {N}\ndepth = {N}',
    '[[motions]]\ntype = "solitary"\nname = "s"\nheight = {N}\ndepth = {N}',
    '[[motions]]\ntype = "constant_velocity"\nname = {S}\nvelocity = [{N}, {N}, {N}]\nstart = {N}',
    '[[probes]]\ntype = "gauge"\nname = {S}\nx = {N}\nz0 = {N}\nz1 = {N}\ninterval = {N}',
    '[[probes]]\ntype = "grid"\nname = "g"\nlo = [{N}, 0.0, {N}]\nhi = [{N}, 0.0, {N}]\ncounts = [{N}, 1, {N}]\n'
    'interval = 0.01',
    '[[probes]]\ntype = "points"\nname = "p"\npoints = [[{N}, {N}, {N}]]\ninterval = {N}',
    '[[probes]]\ntype = "tracker"\nname = "t"\nids = [{N}]\ninterval = {N}',
    '[[probes]]\ntype = "force"\nname = "f"\nsolid = {S}\ninterval = {N}',
    '[[probes]]\ntype = "pressure"\nname = {S}\npoints = [[{N}, 0.0, {N}]]\nmethod = {S}\ninterval = {N}',
    '[domain]\nlo = [{N}, {N}, {N}]\nhi = [{N}, {N}, {N}]\nperiodic = [{S}]',
    '[[damping]]\nstart = [{N}, 0.0, 0.0]\nend = [{N}, 0.0, 0.0]\nrate = {N}',
    '[[relaxation]]\nstart = {N}\nend = {N}\ntime_scale = {N}\ntarget = { type = {S}, height = {N}, period = {N}, '
    'depth = {N} }',
    '[[relaxation]]\nstart = {N}\nend = {N}\nlevel = {N}\ntarget = { type = "motion", motion = {S}, origin = {N} }',
    '[[planes]]\npoint = [{N}, {N}, {N}]\nnormal = [{N}, {N}, {N}]',
    '[[symmetry_planes]]\npoint = [{N}, {N}, {N}]\nnormal = [{N}, {N}, {N}]',
    '[[fluids]]\nvelocity = [{N}, {N}, {N}]\nshape = { type = "box", lo = [{N}, {N}, {N}], hi = [{N}, {N}, {N}] }',
]
# names and numbers that fit, so that an added table is often valid but for one part
FITTING_STRINGS = ['"p"', '"s"', '"tank"', '"x"', '"y"', '"z"', '"case.toml"', '"."', '"/dev/null"', '"bed.csv"',
                   '"rock.stl"', '"linear"', '"still"']
FITTING_NUMBERS = ["0.0", "0.1", "0.3", "0.5", "1.0", "2", "3", "0.01"]
KEY_VALUE = re.compile(r"^(\s*[A-Za-z_][\w.-]*\s*=\s*)(.*)$")
NUMBER = re.compile(r"(?<![\w.])-?\d+(?:\.\d+)?(?:e[+-]?\d+)?(?![\w.])")


def _mutate_text(draw, text):
    """One mutation of the TOML `text`, at the level of its lines or characters."""
    lines = text.split("\n")
    op = draw(st.sampled_from(["value", "number", "number", "insert", "dotted", "table", "append", "append",
                               "duplicate", "delete", "char", "truncate", "deep"]), label="op")
    at = draw(st.integers(0, len(lines)), label="line")
    rows = [k for k, line in enumerate(lines) if KEY_VALUE.match(line)]
    found = list(NUMBER.finditer(text))
    if (op in ("value", "deep") and not rows) or (op == "number" and not found):
        op = "insert"  # (the text was cut before any key or number)
    if op in ("value", "deep"):
        k = draw(st.sampled_from(rows), label="key line")
        lines[k] = KEY_VALUE.match(lines[k]).group(1) + draw(deep_values if op == "deep" else any_value, label="v")
    elif op == "number":  # a number anywhere, an inline table's or an array's included
        m = found[draw(st.integers(0, len(found) - 1), label="number")]
        return text[:m.start()] + draw(numbers | numbers | any_value, label="new number") + text[m.end():]
    elif op == "insert":  # a key of the document again (a duplicate) or another
        known = sorted({m.group(1).split("=")[0].strip() for line in lines if (m := KEY_VALUE.match(line))})
        key = draw(st.sampled_from(known) | bare_keys if known else bare_keys, label="key")
        lines.insert(at, f"{key} = {draw(any_value, label='value')}")
    elif op == "dotted":  # a table's key set from the top level, or from inside another table
        key = draw(st.sampled_from(["fluid.depth", "options.alpha", "output.interval", "domain.lo", "solids.name",
                                    "fluid.depth.x", "a.b.c"]), label="dotted key")
        lines.insert(draw(st.sampled_from([0, at]), label="where"), f"{key} = {draw(any_value, label='value')}")
    elif op == "table":
        lines.insert(at, draw(st.sampled_from(HEADERS), label="header"))
    elif op == "append":  # a whole table at the end (an empty `motions = []` of the same name goes)
        table = draw(st.sampled_from(TABLES), label="table")
        name = table.split("]")[0].strip("[")
        lines = [line for line in lines if line != f"{name} = []"]
        parts = re.split(r"(\{[SN]\})", table)
        for k, part in enumerate(parts):
            if part == "{S}":
                parts[k] = draw(st.sampled_from(FITTING_STRINGS) | strings, label="string")
            elif part == "{N}":
                parts[k] = draw(st.sampled_from(FITTING_NUMBERS) | numbers, label="number")
        lines += ["", "".join(parts)]
    elif op == "duplicate":
        lines.insert(at, lines[draw(st.integers(0, len(lines) - 1), label="copied")])
    elif op == "delete":
        del lines[min(at, len(lines) - 1)]
    elif op == "char":
        pos = draw(st.integers(0, len(text)), label="position")
        ch = draw(st.sampled_from(list("[]{}\"'=#\\\n., \t") + ["\r", "\x00", "\x7f", "\u2028", "\ufeff"]),
                  label="char")
        return text[:pos] + ch + text[pos + draw(st.integers(0, 1), label="replace"):]
    else:
        return text[:draw(st.integers(0, len(text)), label="cut")]
    return "\n".join(lines)


def _encode(draw, text):
    """The bytes of the file: UTF-8, or with a BOM, CR/CRLF line ends, a NUL or a byte that is not UTF-8,
    Latin-1 or UTF-16."""
    how = draw(st.sampled_from(["utf-8"] * 6 + ["bom", "crlf", "cr", "nul", "invalid", "latin-1", "utf-16"]),
               label="encoding")
    if how == "bom":
        return b"\xef\xbb\xbf" + text.encode("utf-8")
    if how in ("crlf", "cr"):
        return text.replace("\n", "\r\n" if how == "crlf" else "\r").encode("utf-8")
    if how in ("nul", "invalid"):
        data = text.encode("utf-8")
        pos = draw(st.integers(0, len(data)), label="byte position")
        return data[:pos] + (b"\x00" if how == "nul" else b"\xff\xfe") + data[pos:]
    if how == "latin-1":
        return text.encode("latin-1", "replace")
    if how == "utf-16":
        return text.encode("utf-16")
    return text.encode("utf-8")


def _doc(*subs, base="still-water-2d", append=""):
    """The case file of `base` with each (old, new) replaced once, plus `append`, as UTF-8 bytes: the
    documents the fuzzing found (explicit examples below)."""
    text = BASE_TEXTS[base]
    for old, new in subs:  # at the start of a line: a key, not the parameters' record in the header comment
        m = re.search("(?m)^" + re.escape(old), text)
        assert m, old
        text = text[:m.start()] + new + text[m.end():]
    return (text + append).encode("utf-8")


HEX_4000 = "0x" + "f" * 4000  # an integer TOML reads, whose 4817 decimal digits str() refuses to write
GRID_BILLIONS = ('\n[[probes]]\ntype = "grid"\nname = "g"\nlo = [0.1, 0.0, 0.1]\nhi = [0.5, 0.0, 0.3]\n'
                 'counts = [2, 1, 0xdead_beef]\ninterval = 0.01\n')  # 3.7 billion nodes along z
GAUGE_FLOATS = ('\n[[probes]]\ntype = "gauge"\nname = "g"\nx = 0.3\nz0 = -1.7976931348623157e308\n'
                'z1 = 1.7976931348623157e308\ninterval = 0.01\n')  # z1 - z0 = inf
SOLITARY_DEEP = '\n[[motions]]\ntype = "solitary"\nname = "s"\nheight = 0.1\ndepth = 1e200\n'
PISTON_DEEP = '\n[[motions]]\ntype = "piston"\nname = "p"\nheight = 0.05\nperiod = 1.2\ndepth = 1e10\n'


@st.composite
def documents(draw):
    """A case file as bytes: the text `shoal new` writes, mutated 1-3 times, then encoded."""
    text = BASE_TEXTS[draw(st.sampled_from(sorted(BASE_TEXTS)), label="base")]
    for _ in range(draw(st.sampled_from([1, 1, 1, 2, 3]), label="mutations")):
        text = _mutate_text(draw, text)
    return _encode(draw, text)


@contextlib.contextmanager
def _terminal():
    """Standard output and error as under a UTF-8 locale; yields a namespace whose ``out`` and ``err`` are
    what was written (set when the block ends)."""
    out = io.TextIOWrapper(io.BytesIO(), encoding="utf-8", errors="strict", newline="\n", write_through=True)
    err = io.TextIOWrapper(io.BytesIO(), encoding="utf-8", errors="backslashreplace", newline="\n",
                           write_through=True)
    got = SimpleNamespace(out="", err="")
    try:
        with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
            yield got
    finally:
        got.out = out.buffer.getvalue().decode("utf-8")
        got.err = err.buffer.getvalue().decode("utf-8")


def _error_line(err):
    """The one line ``shoal: error: ...`` that ends `err`, after any ``shoal: warning: ...`` lines (the
    project's rule: a resume warns of each damaged checkpoint it skips, then refuses in one line)."""
    lines = err.splitlines()
    assert all(line.startswith("shoal: warning: ") for line in lines[:-1]), err
    return _one_error_line(lines[-1] if lines else err)


def _main(argv):
    """`_cli(argv)` with the terminal of `_terminal`: (status, stdout, stderr)."""
    with _terminal() as got:
        status = _cli(argv)
    assert "Traceback" not in got.out + got.err, got.err
    return status, got.out, got.err


@pytest.fixture(scope="module")
def doc_dir(tmp_path_factory):
    return tmp_path_factory.mktemp("documents")


@settings(max_examples=600, deadline=None, derandomize=True, database=None,
          suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large, HealthCheck.large_base_example])
@given(doc=documents())
# what the fuzzing found (each gave a traceback before its fix; see test_found_by_fuzzing below)
@example(doc=_doc(("dp = 0.05", "dp = " + "9" * 4301)))  # tomllib: int()'s 4300-digit limit, a ValueError
@example(doc=_doc(append="\n[parameters]\nx = " + "[" * 300 + "1" + "]" * 300 + "\n"))
@example(doc=_doc(("dim = 2", f"dim = {HEX_4000}")))  # the error message's repr of the value failed
@example(doc=_doc(("keep = 2", f"keep = {HEX_4000}")))  # loaded, then could not be written back (check)
@example(doc=_doc(append=f"\n[parameters]\ndepth = {HEX_4000}\n"))  # the same, in [parameters]
@example(doc=_doc(("motions = []\n", ""), append=PISTON_DEEP))  # cosh(2kd) overflowed in deep water
@example(doc=_doc(("dp = 0.0365", "dp = 5e-324"), base="dam-break-3d"))  # the memory guard's lattice overflowed
@example(doc=_doc(("lattice_origin = [0.0", "lattice_origin = [1.7976931348623157e308"), base="dam-break-3d"))
@example(doc=b"\xef\xbb\xbf" + _doc())  # a BOM: was "not valid TOML ... line 1, column 1"; now read
@example(doc=_doc(("probes = []\n", ""), append=GRID_BILLIONS))  # placing it allocated 28 GiB (MemoryError)
@example(doc=_doc(("probes = []\n", ""), append=GAUGE_FLOATS))  # its sample points: int(inf)
@example(doc=_doc(("motions = []\n", ""), append=SOLITARY_DEEP))  # depth**3 overflowed (check: its stroke)
def test_hostile_toml_documents_give_a_case_or_one_line(doc, doc_dir):
    """A case file gives a `Case` or one line of `InputError`; ``shoal check`` prints that same line and exits
    2, or checks the case and exits 0 (or refuses it in one line: a probe outside the domain ...)."""
    path = doc_dir / "case.toml"
    path.write_bytes(doc)
    try:
        case = load_case(path)
    except InputError as err:
        msg = _one_line(err)
        event("refused as it loads: " + ("not TOML" if "valid TOML" in msg else "TOML, not a case"))
        assert msg.startswith(f"{path}: ") or msg.startswith(f"case file {str(path)!r}"), msg
        status, out, err_text = _main(["check", str(path)])
        assert status == 2, (status, err_text)
        assert _error_line(err_text) == f"shoal: error: {cli._printable(msg)}"  # the same, from the command line
        assert out == ""
        return
    assert isinstance(case, Case)
    try:
        with np.errstate(over="ignore"):  # (coordinates at the float limits: an infinite count is large)
            large = _nodes(case) > MAX_NODES
    except (InputError, OSError):  # no box to measure (a mesh file not there, its name too long for the
        large = False  # system ...): `shoal check` says so at once, in one line
    if large:  # a large lattice: only the guard that refuses, before generating, what cannot fit
        try:
            check_generation_size(case, *case._generation_box())
        except InputError as err:
            _one_line(err)  # (`shoal check` would refuse it the same way: not generated here either)
            event("a case, too big for the memory")
            return
        event("a case with a large lattice: only loaded")
        return
    status, out, err_text = _main(["check", str(path)])
    assert status in (0, 2), (status, err_text)
    event(f"a case, shoal check exits {status}")
    if status == 2:
        _error_line(err_text)
    else:
        assert all(line.startswith("shoal: warning: ") for line in err_text.splitlines()), err_text
        assert "particles:" in out, out


# ----------------------------------------------------------------------------- command lines

PARSER = cli.build_parser()
SUBPARSERS = next(a for a in PARSER._actions if isinstance(a, argparse._SubParsersAction)).choices
# built-in cases that `check` and `plot-case` take in well under a second (rip-current: 4 million particles, 12 s)
CHEAP_CASES = ["still-water-2d", "dam-break-2d", "still-water-3d", "wave-flume-2d", "dam-break-3d", "tidal-bore"]
COMMAND_WEIGHTS = ["check"] * 5 + ["run"] * 5 + ["new"] * 3 + ["post"] * 2 + ["validate"] * 2 + [
    "plot-case", "cases", "info", None]
assert set(COMMAND_WEIGHTS) - {None} == set(SUBPARSERS)  # every command of the parser, and no other
PARAM_KEYS = sorted({k for name in CHEAP_CASES for k in case_parameters(name)} | {"options", "half"})
OPTION_KEYS = [f.name for f in fields(SPHOptions)]
SMALL_MACHINE = 256 * 2**20  # bytes: about 350,000 particles (`shoal.memory.BYTES_PER_PARTICLE`)
JUNK = ["--frobnicate", "--dp=0.05", "--dp=", "-x", "--", "-", "", " ", "\u00e9", "\x1b[31m", "x" * 5000, "--help",
        "--version", "\udcff", "--DP", "--end", "--para", "\t", "a b", "\U0001f30a", "-o", "--out", "---", "-1",
        "--no-such=1", "@args.txt"]
# (valid, junk) values of each kind; a value is drawn from the valid ones two times in three, so that most
# command lines get past the parser and meet the command's own checks with one or two bad parts
NUMBERS = (["0.02", "0.025", "0.05", "0.1", "1", "3", "1e300", "٣"],  # (float() reads an Arabic-Indic digit)
           ["1e-300", "5e-324", "1.7976931348623157e308", "1e309", "0_05", "1_000", "nan", "-nan", "-1", "0",
            "-0.0", "inf", "-inf", "abc", "", " 0.05 ", "0x10", "1,5", "\u00bd", "1e", "+.5", "1/2", "10" * 300])
PARAMS = (["layers=2", "depth=0.3", "end_time=0.5", "half=true", "dim=2", "inflow_speed=0.5", "wave_height=0.03",
           "period=1.5", "output_interval=0.5", "a=0.1", "gauges_x=[1.0, 2.5]", "length=1.5"],
          # and junk of `_key_value`, with values of the wrong kind for these keys
          ["layers=2.5", "options=5", "options={alpha = 1e309}", "dim=[2]", "half=2", "length=" + "1" * 5000,
           "gauges_x=[nan]", "gauges_x=[]", "gauges_x=1", "gauges_x=[[1]]", "tank_length=-1", "width=1e-300",
           "dp=1e-300", "end_time=-0.0", "output_interval=1e-300", "depth=1979-05-27", "layers=99999999999999999999",
           "depth=0x" + "f" * 4000])
OPTIONS = (["alpha=0.02", "kernel=cubic", "wall_pressure=dynamic", "cfl=0.1", "xsph=0.5", "shepard_every=10",
            "precision=float64", "density_diffusion=none", "fixed_dt=1e-5", "riemann=true", "coef_h=1.2"],
           ["cfl=2", "alpha=nan", "fixed_dt=1e-300", "shepard_every=2.5", "cells_per_support=4", "kernel=1",
            "precision=float16", "nu=-1e-6", "verlet_euler_every=true", "mls_every=" + "9" * 5000])
TOML_VALUES = ["0.7", "1e300", "-1", "0", "nan", "inf", "-inf", "true", "false", "[1, 2]", "[]", "{a = 1}", "{}",
               '"x"', "x", "", "1_0", "0x10", "0b1", "1" * 5000, "1979-05-27", "2", "cubic", "a=b", " 1 ", "1e-300",
               "5e-324", "1.7976931348623157e308", "\udcff", "\u00e9", "[[[[1]]]]", "{options = {alpha = 1}}",
               '"\\u0000"', "'", "float64", "adami", "99999999999999999999", "[" * 200 + "]" * 200, "0x" + "f" * 4000]
PATHS_IN = (["case.toml", "run/case.toml", "\u00e9/case.toml", "\udcff/case.toml"],
            ["bad.toml", "empty.toml", "binary.bin", "missing.toml", "adir", "adir/", "run", "/dev/null", "-", "",
             ".", "x" * 300, "x" * 5000 + ".toml", "a\nb.toml", "case.toml/x", "{outside}", "{outside}/keep.txt",
             "{outside}/missing.toml", "\udcff.toml"])
DIRS_IN = (["run", "adir"], PATHS_IN[0] + PATHS_IN[1])
PATHS_OUT = (["out", "out.toml", "out.png", "\u00e9.toml", "\udcff.toml", "sub/dir/out", "a\nb", "\x1b[31m.toml"],
             ["adir", "case.toml", "run", "/dev/null", "", "-", ".", "x" * 300, "x" * 5000, "case.toml/x",
              "nested/" * 40 + "o"])
CASE_NAMES = (CHEAP_CASES, ["dam-brake-2d", "rip-current --dp 1", "nope", "", "-", "\udcff", "DAM-BREAK-2D"])
VALUE_POOLS = {
    "backend": (["cpu"], ["cuda", "tpu", "", "CPU"]),
    "plane": (["z=0.05", "y=mid", "y=0.15"], ["x=", "q=1", "z=nan", "z=1e308", "mid", "", "z", "=0.1"]),
    "cases": (list(VALIDATION_CASES), ["nope", "", "\udcff"]),
    "run_dir": DIRS_IN, "resume": DIRS_IN, "sources": DIRS_IN,
    "out": PATHS_OUT, "output": PATHS_OUT,
}


def _pick(valid, junk):
    """A valid value two times in three, else junk."""
    return st.sampled_from(valid) | st.sampled_from(valid) | st.sampled_from(junk)


def _key_value(valid, hostile, keys):
    """KEY=VALUE items: valid ones, or values of the wrong kind for real keys, or a real or junk key with a
    value of any TOML kind, or no KEY=VALUE at all."""
    keys = st.sampled_from(keys) | st.sampled_from(["", "1a", "a b", "\u00e9", "__class__"])
    junk = (st.tuples(keys, st.sampled_from(TOML_VALUES)).map(lambda kv: f"{kv[0]}={kv[1]}")
            | st.sampled_from(hostile) | st.sampled_from(["depth", "=0.3", "a=b=c", "", "="]))
    return st.sampled_from(valid) | st.sampled_from(valid) | junk


def _value_for(action):
    """Values for the option or positional `action`: its valid ones and junk of its kind (numbers for a
    number, KEY=VALUE items for --param, paths for a path ...)."""
    dest = action.dest
    if action.choices:
        return _pick(list(action.choices), ["float16", "", "CUBIC", "rk4"])
    if dest == "param":
        return _key_value(*PARAMS, PARAM_KEYS)
    if dest == "option":
        return _key_value(*OPTIONS, OPTION_KEYS)
    if action.type is not None:
        return _pick(*NUMBERS)
    if dest == "case":
        return _pick(CASE_NAMES[0] + PATHS_IN[0], CASE_NAMES[1] + PATHS_IN[1])
    if dest == "name":
        return _pick(*CASE_NAMES)
    if dest in VALUE_POOLS:
        return _pick(*VALUE_POOLS[dest])
    return st.sampled_from(JUNK)


@st.composite
def command_lines(draw):
    """An argument list: rarely a top-level flag, a subcommand of the real parser (or junk), then a few
    tokens: mostly its options, with a value; now and then one without its value, an extra positional, junk."""
    top = draw(st.sampled_from(["--version", "--help", "-h", "--frobnicate", "-"] + [None] * 45), label="top")
    argv = [top] if top else []
    # the commands with inputs most often (plot-case, the slowest, least); 1 in 20 no command at all
    name = draw(st.sampled_from(COMMAND_WEIGHTS), label="command")
    if name is None:
        name = draw(st.sampled_from(["simulate", "", "RUN", "chek", "--dp"]), label="junk command")
    argv.append(name)
    sub = SUBPARSERS.get(name)
    if sub is None:
        return argv
    actions = [a for a in sub._actions if not isinstance(a, argparse._HelpAction)]
    positionals = [a for a in actions if not a.option_strings]
    options = [a for a in actions if a.option_strings]
    for a in positionals:  # usually given, sometimes not (a missing positional)
        if draw(st.integers(0, 9), label="skip positional"):
            argv.append(draw(_value_for(a), label=a.dest))
    for _ in range(draw(st.integers(0, 4), label="tokens")):
        kind = draw(st.sampled_from(["option"] * 12 + ["positional", "junk", "no value"]), label="token")
        if kind == "option" and options:
            a = draw(st.sampled_from(options), label="option")
            argv.append(draw(st.sampled_from(a.option_strings), label="flag"))
            if a.nargs != 0:
                argv.append(draw(_value_for(a), label=a.dest))
        elif kind == "no value" and options:  # an option that takes a value, at the end without one
            argv.append(draw(st.sampled_from([s for a in options for s in a.option_strings]), label="flag"))
        elif kind == "positional" and positionals:
            argv.append(draw(_value_for(draw(st.sampled_from(positionals), label="which")), label="extra"))
        else:
            argv.append(draw(st.sampled_from(JUNK), label="junk"))
    return argv


def _files(d):
    """{relative path: (kind, sha256 of a file's bytes)} of everything under `d`."""
    out = {}
    for root, dirs, names in os.walk(d):
        for n in dirs + names:
            p = Path(root) / n
            st_ = os.lstat(p)
            digest = hashlib.sha256(p.read_bytes()).hexdigest() if stat.S_ISREG(st_.st_mode) else ""
            out[str(p.relative_to(d))] = (stat.S_IFMT(st_.st_mode), digest)
    return out


def _seed(cwd):
    """The user's files in the folder a command runs in: case files (valid, malformed, empty, binary), a
    directory, and a run directory of junk (a run's names, contents that are not a run's)."""
    (cwd / "case.toml").write_text(BASE_TEXTS["still-water-2d"], encoding="utf-8")
    (cwd / "bad.toml").write_text("dp = \n", encoding="utf-8")
    (cwd / "empty.toml").write_text("", encoding="utf-8")
    (cwd / "binary.bin").write_bytes(bytes(range(256)))
    (cwd / "adir").mkdir()
    for odd in ("\u00e9", "\udcff"):  # a folder named in unicode, one named by a byte that is not UTF-8
        (cwd / odd).mkdir()
        (cwd / odd / "case.toml").write_text(BASE_TEXTS["still-water-2d"], encoding="utf-8")
    run = cwd / "run"
    run.mkdir()
    (run / "case.toml").write_text(BASE_TEXTS["still-water-2d"], encoding="utf-8")
    (run / "resolved.json").write_text("{}", encoding="utf-8")
    (run / "results.json").write_text('{"cases": 5}', encoding="utf-8")
    (run / "gauge_g.csv").write_text("time,level\n0,abc\nnan,1e309\n", encoding="utf-8")
    (run / "ckpt_000001.h5").write_bytes(b"\x89HDF\r\n\x1a\n" + bytes(32))
    (run / "still-water-2d.pvd").write_text("<VTKFile>", encoding="utf-8")


def _no_steps(case, out_dir, procs, model, point, backend, progress, plot, max_steps, handle_signals, log, state):
    """Stands in for `shoal.runner._steps` (the time loop and its output): a run of no step."""
    from shoal.simulation.run_log import close_run_log

    if log is not None:
        close_run_log(log)
    return SimpleNamespace(steps=0, time=0.0, wall_seconds=0.0, compile_seconds=0.0, particle_steps_per_second=0.0,
                           snapshots=0, out_dir=out_dir, escaped=0,
                           resumed_from=point.path if point.ck is not None else None)


@pytest.fixture(scope="module")
def cli_dirs(tmp_path_factory):
    """(base, outside): the base folder of each example's folder, and a folder outside them that the
    examples name as an input (and must leave as it is)."""
    base = tmp_path_factory.mktemp("command-lines")
    outside = base / "outside"
    outside.mkdir()
    (outside / "keep.txt").write_text("the user's\n", encoding="utf-8")
    return base, outside


@settings(max_examples=1000, deadline=None, derandomize=True, database=None,
          suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])
@given(argv=command_lines())
# what the fuzzing found (each gave a traceback, or an error of two lines, before its fix)
@example(argv=["run", "--resume", "a\nb.toml"])  # a newline of a file name split the error line
@example(argv=["plot-case", "still-water-2d", "-o", "\udcff.png"])  # printing an undecodable byte of argv
@example(argv=["new", "still-water-2d", "-o", "\udcff.toml"])  # writing it into the case file's header
@example(argv=["new", "still-water-2d", "--param", "layers=2.5"])  # `new` let pydantic's error through
@example(argv=["check", "still-water-2d", "--param", "length=" + "1" * 5000])  # int()'s 4300-digit limit
@example(argv=["check", "still-water-2d", "--param", f"layers={HEX_4000}"])  # could not be written back
@example(argv=["check", "wave-flume-2d", "--end-time", "1.7976931348623157e308"])  # a gauge's samples: int(inf)
@example(argv=["check", "dam-break-2d", "--param", "tank_length=cubic"])  # float('cubic') in the case function
@example(argv=["check", "tidal-bore", "--param", "half=\udcff"])  # a string parameter the case file cannot hold
@example(argv=["run", "--resume", "run"])  # (not a bug: a warning for the damaged checkpoint, then the error)
def test_hostile_command_lines_exit_0_or_2_in_one_line(argv, cli_dirs):
    """An argument list exits 0 or 2, in one line ``shoal: error: ...`` on 2, leaving the user's files as they
    were, and writes nothing outside its folder (see the module docstring)."""
    base, outside = cli_dirs
    argv = [a.replace("{outside}", str(outside)) for a in argv]
    cwd = Path(tempfile.mkdtemp(dir=base))
    _seed(cwd)
    before, outside_before, base_before = _files(cwd), _files(outside), sorted(os.listdir(base))
    repo_before = set(os.listdir(REPO))
    old = os.getcwd()
    os.chdir(cwd)
    try:
        with pytest.MonkeyPatch.context() as mp:
            mp.setattr("shoal.runner._steps", _no_steps)
            mp.setattr("shoal.validation.run_validation", lambda *a, **k: [])
            mp.setattr("shoal.memory.physical_memory", lambda: SMALL_MACHINE)
            mp.setattr("shoal.memory.available_memory", lambda: SMALL_MACHINE)
            mp.setattr("shoal.check.physical_memory", lambda: SMALL_MACHINE)
            status, out, err = _main(argv)
    finally:
        os.chdir(old)
    assert status in (0, 2), (status, out, err)
    event(f"{next((a for a in argv if a in SUBPARSERS), 'no command')} exits {status}")
    if status == 2:
        _error_line(err)
        assert _files(cwd) == before  # a refused command leaves the user's files as they were
    else:
        assert all(line.startswith("shoal: warning: ") for line in err.splitlines()), err
    # nothing outside the folder created or changed: the folder named as an input, the folders beside this
    # one, /dev/null; and in the checkout (where pytest started: other tests may write there meanwhile), nothing
    # of the names this command could write (its relative paths, its default outputs)
    assert _files(outside) == outside_before
    assert sorted(os.listdir(base)) == base_before
    assert stat.S_ISCHR(os.stat("/dev/null").st_mode)
    named = {a.split("/")[0] for a in argv if a and not a.startswith(("-", "/"))} | {"runs"}
    assert not {n for n in set(os.listdir(REPO)) - repo_before if any(n.startswith(m) for m in named)}


# ----------------------------------------------------------------------------- what the fuzzing found

@pytest.mark.parametrize("files,argv,fragments", [
    pytest.param({"case.toml": _doc(("dp = 0.05", "dp = " + "9" * 4301))}, None,
                 ["case.toml: an integer has more than 4300 digits"], id="toml-integer-of-4301-digits"),
    pytest.param({"case.toml": _doc(("dim = 2", f"dim = {HEX_4000}"))}, None,
                 ["dim is an integer beyond 64 bits", "from -2^63 to 2^63 - 1"], id="toml-hex-integer-4817-digits"),
    pytest.param({"case.toml": _doc(("keep = 2", "keep = 18446744073709551616"))}, None,
                 ["checkpoint.keep is an integer beyond 64 bits"], id="toml-integer-beyond-64-bits"),
    pytest.param({"case.toml": _doc(append="\n[parameters]\nx = " + "[" * 300 + "1" + "]" * 300 + "\n")},
                 None, ["parameters: x[0][0]", "nested more than 100 deep"], id="toml-parameter-nested-300-deep"),
    pytest.param({"case.toml": _doc(("dp = 0.0365", "dp = 5e-324"), base="dam-break-3d")}, None,
                 ["would scan inf lattice nodes", "use a larger dp"], id="toml-dp-5e-324"),
    pytest.param({"case.toml": _doc(("lattice_origin = [0.0", "lattice_origin = [1.7976931348623157e308"),
                                    base="dam-break-3d")}, None,
                 ["lattice_origin.x = 1.798e+308 m", "more than 1e15 spacings", "give an origin near the case"],
                 id="toml-lattice-origin-at-the-float-limit"),
    pytest.param({"case.toml": _doc(("probes = []\n", ""), append=GRID_BILLIONS)}, None,
                 ["GiB for the probes", "probes[0] (grid 'g')", "fewer grid nodes"], id="toml-grid-of-billions"),
    pytest.param({"case.toml": _doc(("probes = []\n", ""), append=GAUGE_FLOATS)}, None,
                 ["the run needs inf GiB", "probes[0] (gauge 'g')", "a shorter z0 .. z1"], id="toml-gauge-line-inf"),
    pytest.param({"case.toml": _doc(("motions = []\n", ""), append=SOLITARY_DEEP)}, None,
                 ["motions[0]: height = 0.1 m in 1e+200 m of water gives no finite paddle stroke"],
                 id="toml-solitary-wave-in-1e200-m-of-water"),
    pytest.param({}, ["run", "--resume", "a\nb"], ["--resume a\\nb: no such run directory"],
                 id="cli-newline-in-a-path"),
    pytest.param({}, ["new", "still-water-2d", "--param", "layers=2.5", "-o", "x.toml"],
                 ["--param layers=2.5", "layers = 2.5: must be an integer"], id="cli-new-param-of-the-wrong-kind"),
    pytest.param({}, ["check", "still-water-2d", "--param", "length=" + "1" * 5000], ["length = '111", "positive"],
                 id="cli-param-integer-of-5000-digits"),
    pytest.param({}, ["check", "still-water-2d", "--param", f"layers={HEX_4000}"],
                 ["--param layers=...: an integer beyond 64 bits"], id="cli-param-hex-integer-4817-digits"),
    pytest.param({}, ["check", "dam-break-2d", "--param", "tank_length=cubic"],
                 ["a --param value has the wrong kind (tank_length='cubic')"], id="cli-param-string-for-a-float"),
    pytest.param({}, ["check", "tidal-bore", "--param", "half=\udcff"],
                 ["--param half=...: the value holds a byte that is not UTF-8"], id="cli-param-undecodable-byte"),
    pytest.param({}, ["check", "wave-flume-2d", "--end-time", "1.7976931348623157e308"],
                 ["the run needs inf GiB", "probes[0] (gauge 'x1')"], id="cli-end-time-at-the-float-limit"),
])
def test_found_by_fuzzing_is_one_line_and_exit_2(files, argv, fragments, tmp_path, monkeypatch, capsys):
    """Each input the two properties found to give a traceback (or an error of two lines): now one line
    naming what is wrong and what is allowed, exit status 2, nothing written."""
    monkeypatch.chdir(tmp_path)
    for name, data in files.items():
        (tmp_path / name).write_bytes(data)
    status = _cli(argv or ["check", "case.toml"])
    out, err = capsys.readouterr()
    line = _one_error_line(err)
    assert status == 2, (status, out, err)
    for part in fragments:
        assert part in line, (part, line)
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted(files)


def test_found_by_fuzzing_runs_now(tmp_path, monkeypatch):
    """Inputs that are valid, found to give a traceback: a piston in deep water (cosh 2kd overflowed),
    a case file that begins with a BOM (refused as 'not valid TOML' at line 1, column 1), a file name with
    a byte that is not UTF-8 (a surrogate escape in argv: its case file's header could not be encoded, nor
    the line that names it on a strict UTF-8 terminal)."""
    monkeypatch.chdir(tmp_path)
    (tmp_path / "deep.toml").write_bytes(_doc(("motions = []\n", ""), append=PISTON_DEEP))
    (tmp_path / "bom.toml").write_bytes(b"\xef\xbb\xbf" + _doc())
    assert load_case(tmp_path / "deep.toml").motions[0].stroke == pytest.approx(0.025)  # deep water: H/S = 2
    assert load_case(tmp_path / "bom.toml") == _load_bytes(_doc())
    status, out, err = _main(["new", "still-water-2d", "-o", "\udcff.toml"])
    assert status == 0 and err == "" and "wrote \\udcff.toml" in out, (status, out, err)
    assert b"\xff.toml" in os.listdir(os.fsencode(tmp_path))  # the file is named by the byte itself
    assert (tmp_path / "\udcff.toml").read_text(encoding="utf-8").count("shoal run ?.toml") == 1
    status, out, err = _main(["check", "\udcff.toml"])
    assert status == 0 and "particles:" in out, (status, out, err)


def _load_bytes(data):
    """The case of the case-file bytes `data` (through a file, as `shoal check` reads it)."""
    with tempfile.TemporaryDirectory() as d:
        path = Path(d) / "case.toml"
        path.write_bytes(data)
        return load_case(path)
