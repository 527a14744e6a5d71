"""TOML case files: read, validate, write.

A case file is the TOML form of a `shoal.Case`: each table maps onto one
constructor (``[fluid]`` -> `Fluid`, ``[[solids]]`` -> `Solid`, a
``shape = {type = "box", ...}`` -> `shoal.geometry.Box`, ...), with the
same names, units and defaults. Loading one never executes code: it is
parsed by `tomllib` and validated by the pydantic schema of those classes.
Every error is one line naming the file, the key with its path (e.g.
``solids[1].shape.lo``), the value given and what is allowed.
"""

from __future__ import annotations

import re
import sys
import tomllib
import typing
from dataclasses import fields as dc_fields
from dataclasses import is_dataclass
from pathlib import Path

from pydantic import BaseModel, ValidationError

from .case import Case
from .errors import InputError
from .geometry.shapes import SHAPES
from .motions import (ConstantVelocity, FlapWavemaker, FocusedWaves, IrregularWaves, PistonWavemaker,
                      RotationMotion, SolitaryPiston, TimeSeriesMotion)
from .waves.spectra import SPECTRA

MOTIONS = {"constant_velocity": ConstantVelocity, "piston": PistonWavemaker, "solitary": SolitaryPiston,
           "time_series": TimeSeriesMotion, "irregular": IrregularWaves, "focused": FocusedWaves,
           "flap": FlapWavemaker, "rotation": RotationMotion}
from .probes import (FlowGauge, ForceGauge, MaxZGauge, PointProbes, PressureSensors, RunupGauge, TestPoints, Tracker,
                     WaveGauge)

PROBES = {"points": PointProbes, "gauge": WaveGauge, "grid": TestPoints, "tracker": Tracker, "maxz": MaxZGauge,
          "runup": RunupGauge, "flow": FlowGauge, "force": ForceGauge,
          "pressure": PressureSensors}
_TAGGED = {"shape": SHAPES, "motions": MOTIONS, "probes": PROBES, "spectrum": SPECTRA}


# ------------------------------------------------------------------ loading
def load_case(path, overrides=None):
    """Read and validate the case file `path` (plus `overrides`, a dict of
    top-level values such as ``{"dp": 0.01}``); return a `Case`.

    Raises
    ------
    InputError
        One line: the file, the key, the value and what is allowed.
    """
    path = Path(path)
    if path.is_dir():
        raise InputError(f"case file {str(path)!r} is a directory; give a TOML case file")
    if not path.is_file():
        raise InputError(f"case file {str(path)!r} not found")
    try:
        # utf-8-sig: a byte-order mark, as some Windows editors write, is not read as part of the first key
        data = tomllib.loads(path.read_text(encoding="utf-8-sig"))
    except tomllib.TOMLDecodeError as exc:
        raise InputError(f"{path}: not valid TOML: {exc}") from None
    except UnicodeDecodeError:
        raise InputError(f"{path}: not a text file (a TOML case file is UTF-8 text)") from None
    except ValueError:  # tomllib lets int()'s own limit through: an integer of more than 4300 digits
        raise InputError(f"{path}: an integer has more than {sys.get_int_max_str_digits()} digits, the most "
                         "Python reads (no case value needs so many)") from None
    except RecursionError:
        raise InputError(f"{path}: tables or arrays nested too deeply to be a case file") from None
    big = wide_integer(data)
    if big is not None:  # (tomllib reads any size; one of thousands of digits could not even be written back)
        raise InputError(f"{path}: {big} is an integer beyond 64 bits; TOML integers are 64-bit, from -2^63 to "
                         "2^63 - 1")
    if overrides:
        data.update(overrides)
    return case_from_dict(data, source=str(path), base_dir=path.parent)


def wide_integer(data, where=""):
    """The key path (e.g. ``solids[0].layers``) of the first integer in the parsed TOML `data` outside the
    64-bit range of the TOML specification, or None."""
    if isinstance(data, int) and not isinstance(data, bool):
        return None if -2**63 <= data < 2**63 else where
    items = data.items() if isinstance(data, dict) else enumerate(data) if isinstance(data, list) else ()
    for k, v in items:
        found = wide_integer(v, f"{where}[{k}]" if isinstance(k, int) else f"{where}.{k}" if where else k)
        if found is not None:
            return found
    return None


def case_from_dict(data, source="case", base_dir=None):
    """Validate a plain dict (a parsed case file) into a `Case`."""
    try:
        return Case.model_validate(data, context={"base_dir": str(base_dir) if base_dir else None})
    except ValidationError as err:
        raise InputError(f"{source}: {format_validation_error(err)}") from None
    except InputError as err:
        raise InputError(f"{source}: {err}") from None


# ------------------------------------------------------------------ errors
def _path(loc):
    """('solids', 0, 'shape', 'box', 'lo') -> 'solids[0].shape.lo' (tags dropped)."""
    out = ""
    prev = None
    for k, item in enumerate(loc):
        if isinstance(item, int):
            out += f"[{item}]"
        else:
            parent = prev if not isinstance(prev, int) else (loc[k - 2] if k >= 2 else None)
            if parent in _TAGGED and item in _TAGGED[parent]:
                prev = item
                continue  # the union's tag pydantic puts in the path
            if item.startswith("function-") or item in ("tagged-union", "float", "TimeSeries"):
                continue  # pydantic's names of validators and of a union's branches (a number or a series)
            out += ("." if out else "") + item
        prev = item
    return out or "(top level)"


def _unwrap(ann):
    """The model / dataclass classes an annotation refers to."""
    origin = typing.get_origin(ann)
    if origin is typing.Annotated:
        return _unwrap(typing.get_args(ann)[0])
    if origin in (list, tuple, typing.Union) or str(origin) == "types.UnionType":
        out = []
        for a in typing.get_args(ann):
            out += _unwrap(a)
        return out
    if isinstance(ann, type) and (issubclass(ann, BaseModel) or is_dataclass(ann)):
        return [ann]
    import types

    if isinstance(ann, types.UnionType):
        out = []
        for a in typing.get_args(ann):
            out += _unwrap(a)
        return out
    return []


def _fields(cls):
    if isinstance(cls, type) and issubclass(cls, BaseModel):
        return {k: f.annotation for k, f in cls.model_fields.items()}
    hints = typing.get_type_hints(cls)
    return {f.name: hints.get(f.name) for f in dc_fields(cls)}


def _class_at(loc):
    """The model class of the table at `loc` (for listing its keys)."""
    cls = Case
    prev = None
    for k, item in enumerate(loc):
        if isinstance(item, int):
            prev = item
            continue
        parent = prev if not isinstance(prev, int) else (loc[k - 2] if k >= 2 else None)
        if parent in _TAGGED and item in _TAGGED[parent]:
            cls = _TAGGED[parent][item]
            prev = item
            continue
        f = _fields(cls).get(item)
        if f is None:
            return None
        found = _unwrap(f)
        if not found:
            return None
        cls = found[0]
        prev = item
    return cls


def _short(v, n=60):
    if isinstance(v, bool):
        return "true" if v else "false"
    if v is None:
        return "nothing"
    if hasattr(v, "isoformat"):
        return v.isoformat()
    try:
        r = repr(v)
    except ValueError:  # an integer of more digits than str() of an int gives (4300), or an array holding one
        what = "an integer" if isinstance(v, int) else "an array with an integer"
        return f"{what} of more than {sys.get_int_max_str_digits()} digits"
    return r if len(r) <= n else r[: n - 3] + "..."


_SCALAR_ERRORS = ("float_type", "int_type", "float_parsing", "int_parsing", "bool_type", "bool_parsing",
                  "string_type")
_TABLE_ERRORS = ("model_type", "model_attributes_type", "dict_type", "dataclass_type")


def _branch_errors(errors):
    """The errors of the branch of a union (a number or a table: `shoal.time_series.TimeSeries`) that the input
    was meant for: a table's errors when a table was given, a number's when a number or a string was."""
    out = [e for e in errors if not (isinstance(e.get("input"), dict) and e["type"] in _SCALAR_ERRORS)]
    if len(out) > 1:
        out = [e for e in out if not (e["type"] in _TABLE_ERRORS and not isinstance(e.get("input"), dict))] or out
    return out or errors


def format_validation_error(err):
    """One line for the first error of a pydantic ValidationError."""
    errors = _branch_errors(err.errors())
    e = errors[0]
    loc = tuple(e["loc"])
    path = _path(loc)
    typ = e["type"]
    msg = e["msg"]
    more = f" (and {len(errors) - 1} more problem{'s' if len(errors) > 2 else ''})" if len(errors) > 1 else ""
    if typ in ("extra_forbidden", "unexpected_keyword_argument"):
        parent_loc = loc[:-1]
        cls = _class_at(parent_loc)
        allowed = ", ".join(sorted(_fields(cls))) if cls is not None else "see the documentation"
        where = _path(parent_loc) if parent_loc else "the top level"
        return f"unknown key {loc[-1]!r} in {where}; allowed keys: {allowed}{more}"
    if typ == "missing" and loc and isinstance(loc[-1], int):
        return f"{_path(loc[:-1])} has too few values (a point or vector is an array of 3 numbers){more}"
    if typ == "missing":
        return f"missing required key {path}{more}"
    if typ == "union_tag_invalid":
        tags = e.get("ctx", {}).get("expected_tags", "")
        return f"{path}.type = {_short(e['input'].get('type') if isinstance(e['input'], dict) else e['input'])} " \
               f"is not a known type; allowed: {tags}{more}"
    if typ == "union_tag_not_found":
        parent = loc[-1] if loc and not isinstance(loc[-1], int) else (loc[-2] if len(loc) > 1 else "")
        tags = ", ".join(repr(t) for t in _TAGGED.get(parent, {})) or "see the documentation"
        return f"{path}: missing key 'type' (one of {tags}){more}"
    if typ in ("model_type", "dataclass_type", "model_attributes_type", "dict_type", "dataclass_exact_type"):
        return f"{path} = {_short(e.get('input'))} must be a table (key = value pairs){more}"
    if typ == "value_error":
        text = re.sub(r"^Value error, ", "", msg)
        if path == "(top level)" or text.startswith("unknown key"):
            return f"{text}{more}"
        if path == "options" and re.match(r"^[a-z_]+ = ", text):
            return f"options.{text}{more}"
        key = loc[-1] if loc else None
        if isinstance(key, str) and text.startswith(f"{key} = "):
            return f"{path}{text[len(key):]}{more}"
        return f"{path}: {text}{more}"
    if typ == "string_pattern_mismatch":
        return (f"{path} = {_short(e.get('input'))}: use letters, digits, '_', '.' and '-' only, and not dots "
                f"alone ('.' and '..' name folders){more}")
    if typ == "bool_parsing" or typ == "bool_type":
        return f"{path} = {_short(e.get('input'))}: must be true or false{more}"
    if typ in ("float_type", "int_type", "float_parsing", "int_parsing", "int_from_float", "literal_error") \
            and isinstance(e.get("input"), (bool, str)) and typ != "literal_error":
        what = "an integer" if typ.startswith("int") else "a number"
        return f"{path} = {_short(e.get('input'))}: must be {what}{more}"
    text = re.sub(r"^Input should be", "must be", msg)
    text = text.replace("a valid tuple", "an array").replace("a valid list", "an array")
    text = text.replace("a valid integer", "an integer").replace("a valid number", "a number")
    text = re.sub(r"^(Tuple|List|String) should have", "must have", text)
    text = text.replace(" items after validation", " values").replace(" item after validation", " value")
    text = text.replace("Input", "the value")
    return f"{path} = {_short(e.get('input'))}: {text}{more}"


# ------------------------------------------------------------------ writing
TABLE_DOCS = {
    ("solids", "name"): "a name for logs, plots and motions",
    ("solids", "velocity"): "[m/s]",
    ("fluids", "velocity"): "initial velocity [m/s]",
    ("motions", "velocity"): "wall velocity [m/s]",
    ("motions", "depth"): "water depth at the paddle [m]",
    ("fluid", "depth"): "reference depth H [m]: c0 = coef_sound * sqrt(g H)",
    ("", "name"): "case name (output file names)",
    ("probes", "interval"): "sampling interval [s]",
    ("probes", "x"): "gauge position [m]",
    ("probes", "y"): "gauge position [m]",
    ("probes", "z0"): "bottom of the gauge's search line [m]",
    ("probes", "z1"): "top of the gauge's search line [m]",
    ("probes", "shepard"): "Shepard-normalised interpolation (true) or the plain SPH sum",
    ("probes", "counts"): "grid nodes along x, y, z",
    ("probes", "radius"): "horizontal reach of the max-z gauge around (x, y) [m]",
    ("probes", "x0"): "start of the run-up gauge's x range [m]",
    ("probes", "x1"): "end of the run-up gauge's x range [m]",
    ("probes", "band"): "width in y of the run-up gauge's strip (3D) [m]",
    ("probes", "landward"): '"+x" or "-x": which way the beach rises',
    ("probes", "axis"): 'the flow gauge\'s section is the plane axis = at ("x", "y" or "z")',
    ("probes", "at"): "position of the flow gauge's section along its axis [m]",
    ("probes", "solid"): "name of the solid whose hydrodynamic force the force gauge measures",
    ("damping", "start"): "a point [m] on the plane where the damping starts (f = 0)",
    ("damping", "end"): "a point [m] on the plane where it is full (f = 1); f grows from start to end",
    ("damping", "rate"): "damping rate [1/s]: velocity x max(1 - dt rate f^2, 0)",
    ("motions", "start"): "start time [s]",
    ("relaxation", "start"): "x [m] of the zone's inner end (target weight 0)",
    ("relaxation", "end"): "x [m] of its outer end, at the boundary (target weight 1)",
    ("relaxation", "time_scale"): "tau [s]: the deviation from the target shrinks by (1 - w) every tau",
    ("relaxation", "ramp_time"): "start-up ramp of the target [s]",
    ("relaxation", "level"): "still-water level [m] (default: fluid.surface_level)",
    ("relaxation", "type"): '"still", "linear", "fenton", "stokes" or "motion"',
    ("relaxation", "order"): "order N of the stream-function (fenton) target",
    ("relaxation", "wavelength"): "wavelength [m] of the target wave (instead of its period)",
    ("motions", "duration"): "time [s] from which the paddle stops (a ramp down; omit: never)",
    ("motions", "order"): "1, or 2: add the second-order paddle correction (Schaffer 1996)",
    ("motions", "gain"): '"linear" (omega / (H/S)) or "shallow" (sqrt(g/d)): active absorption\'s gain',
    ("motions", "gauge_offset"): "distance [m] in front of the paddle where active absorption measures (default 2h)",
    ("motions", "drift_periods"): "active absorption's drift control time, in wave periods",
    ("relaxation", "depth"): "water depth of the target wave [m]",
    ("relaxation", "direction"): '"+x" or "-x": the way the target wave travels',
    ("relaxation", "phase"): "phase of the target wave [rad]",
    ("relaxation", "origin"): "x [m] the target's phases are measured from (a paddle's rest position)",
    ("relaxation", "motion"): "name of the irregular or focused motion whose sea is the target",
    ("checkpoint", "interval"): "simulated time between checkpoints [s] (0 = none)",
    ("checkpoint", "wall_interval"): "wall-clock time between checkpoints [s] (0 = none)",
    ("checkpoint", "keep"): "checkpoints kept (the newest)",
    ("", "max_escaped_fraction"): "stop when more than this fraction of the fluid has left the domain",
}
KEY_DOCS = {
    "dim": "2 (x-z plane) or 3",
    "dp": "particle spacing [m]",
    "end_time": "simulated time [s]",
    "description": "what the case is",
    "rho0": "reference density [kg/m^3]",
    "gravity": "[m/s^2], z up",
    "depth": "[m]",
    "u_max": "largest expected speed [m/s] (sets c0 = coef_sound * u_max)",
    "surface_level": "still free-surface level [m] (hydrostatic initial density)",
    "kernel": '"wendland" or "cubic"',
    "coef_h": "h = coef_h * sqrt(dim) * dp",
    "coef_sound": "c0 = coef_sound * sqrt(g depth) (or * u_max)",
    "viscosity": '"artificial" or "laminar"',
    "alpha": "artificial viscosity coefficient",
    "visco_bound_factor": "factor on the viscous term of fluid-wall pairs (0 = free-slip walls)",
    "no_slip": "no-slip wall velocity of Adami et al. (2012) in the viscous term",
    "wall_pressure": ('"adami" (default: extrapolated from the fluid), "dynamic" (wall particles integrate '
                      'continuity, DBC) or "mdbc" (from the fluid at their mirror images across the wall)'),
    "nu": "kinematic viscosity [m^2/s] (laminar)",
    "density_diffusion": '"fourtakas", "molteni" or "none"',
    "delta": "density diffusion coefficient",
    "riemann": "pair pressures and velocities from the Riemann solver of Zhang, Hu & Adams (2017)",
    "xsph": "XSPH epsilon (0 = off)",
    "tensile_correction": "Monaghan (2000) tensile correction",
    "turbulence": '"none" or "sps" (Smagorinsky sub-particle-scale stress)',
    "sps_cs": "Smagorinsky constant Cs",
    "sps_ci": "isotropic SPS coefficient C_I",
    "shepard_every": "Shepard density filter every N steps (0 = off)",
    "mls_every": "MLS density filter every N steps (0 = off)",
    "integrator": '"symplectic", "verlet" or "predictor_corrector"',
    "verlet_euler_every": "Euler step every N Verlet steps",
    "cfl": "CFL number of the variable time step",
    "fixed_dt": "fixed time step [s] (omit for variable)",
    "precision": '"float32" or "float64"',
    "cells_per_support": "neighbour cells per kernel support (1, 2 or 3)",
    "boundary": '"dynamic" (layers of particles) or "repulsive" (Monaghan-Kajtar, dp/2)',
    "layers": "layers of dynamic boundary particles (omit: as deep as the kernel support)",
    "motion": "name of a [[motions]] entry moving this solid",
    "velocity": "[m/s]",
    "interval": "time between snapshots [s]",
    "lattice_origin": "particles sit at origin + (i + 1/2) dp [m]",
    "height": "wave height [m]",
    "period": "wave period [s]",
    "ramp_periods": "start-up ramp length in wave periods",
    "start": "start time [s]",
}

HEADER = """\
# shoal case file (TOML). Units are SI: metres, seconds, kilograms.
# x along the flume (cross-shore), y lateral, z up; 2D cases use the x-z plane.
# Run it:          shoal run {file}
# Check it first:  shoal check {file}
# Shapes: box, tank, plane, slope, prism, cylinder, bathymetry, mesh (STL) -- see the README.
"""


def dumps_case(case, commented=True, file_name="case.toml"):
    """The TOML text of `case` (every default filled in); with `commented`,
    a header and a comment after known keys."""
    import tomli_w

    data = case.resolved()
    # order: scalars first, then tables, as a person would write it
    order = ["name", "description", "dim", "dp", "end_time", "max_escaped_fraction", "lattice_origin", "parameters",
             "domain", "fluid", "options", "output", "checkpoint", "motions", "solids", "fluids"]
    data = {k: data[k] for k in order if k in data} | {k: v for k, v in data.items() if k not in order}
    # a commented file is one a person edits: there the builder's parameters are a comment, since editing
    # them would change nothing (the tables are the case); the uncommented text (a checkpoint's copy) keeps them
    record = data.pop("parameters", None) if commented else None
    if not data.get("parameters"):
        data.pop("parameters", None)
    text = tomli_w.dumps(data, multiline_strings=False)
    # arrays of numbers on one line: lo = [0.0, 0.0, 0.0]
    text = re.sub(r"\[\n((?:    [^\n\[\]{}]*,\n)+)\]",
                  lambda m: "[" + ", ".join(x.strip().rstrip(",") for x in m.group(1).splitlines()) + "]", text)
    if not commented:
        return text
    lines = []
    table = ""
    # split on "\n" only: str.splitlines also breaks at \x85, \u2028, ... which a TOML string may hold
    for line in text.rstrip("\n").split("\n"):
        t = re.match(r"^\[\[?([A-Za-z_.]+)\]\]?$", line)
        if t:
            table = t.group(1).split(".")[0]
        m = re.match(r"^([A-Za-z_][A-Za-z0-9_]*) = ", line)
        doc = None
        if m:
            doc = TABLE_DOCS.get((table, m.group(1)), KEY_DOCS.get(m.group(1)))
        if doc and "#" not in line and len(line) < 100:
            line = f"{line}  # {doc}"
        lines.append(line)
    # the file's name in the header's comments: a newline in it would end the comment, an undecodable byte
    # (a surrogate escape) could not be written as UTF-8
    shown = "".join(ch if ch.isprintable() else "?" for ch in file_name)
    return HEADER.format(file=shown) + _parameters_record(record) + "\n" + "\n".join(lines) + "\n"


def _parameters_record(parameters):
    """Comment lines recording the built-in case's parameters (empty without any)."""
    import json
    import textwrap

    if not parameters:
        return ""

    def show(v):
        if isinstance(v, bool):
            return str(v).lower()
        if isinstance(v, (list, tuple)):
            return "[" + ", ".join(show(x) for x in v) + "]"
        return json.dumps(v) if isinstance(v, str) else repr(v)

    items = ", ".join(f"{k if k.isidentifier() else json.dumps(k)} = {show(v)}"
                      for k, v in parameters.items() if v is not None)
    body = textwrap.wrap(items, 96, break_long_words=True, break_on_hyphens=False)
    return ("# Built from these parameters of the built-in case (a record, not read back: the tables below\n"
            "# are the case; for other parameters, run shoal new again with --param KEY=VALUE):\n"
            + "".join(f"#   {line}\n" for line in body))


def write_case(case, path, commented=True):
    """Write `case` as a TOML case file to `path` (atomically)."""
    from .output.atomic import replace_file

    path = Path(path)
    text = dumps_case(case, commented=commented, file_name=path.name)
    return replace_file(path, lambda tmp: tmp.write_text(text, encoding="utf-8"))
