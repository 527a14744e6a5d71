"""A corpus of bad inputs through the real command line (issue 7, item 4).

Each entry is run through ``shoal.cli.main`` in this process and must give
exit status 2 and exactly one line on stderr, ``shoal: error: ...``, naming
what is wrong (the fragments listed) -- never a traceback. A few go
through ``python -m shoal`` in a subprocess to prove the exit status and
the absence of a traceback end to end, and a refused ``shoal run`` must
leave a run directory that already holds a run exactly as it was.

Entries cover: malformed TOML (syntax errors, binary, empty, non-UTF-8),
wrong types, zero or negative sizes, geometry that leaves no fluid or puts
it outside the domain, unknown or missing motions, missing and malformed
files (case file, STL, bathymetry, time series), unwritable output
directories, unknown options and keys at several levels, unknown cases,
bad ``--param`` and flags, ``--resume`` without a checkpoint, cases too
large for this machine's memory (``check`` and ``run``), probes outside the
domain, periodic and symmetry set-ups that cannot work. Run with
``pytest -s`` to see every message.
"""

from __future__ import annotations

import hashlib
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from shoal.cli import main

SRC = Path(__file__).resolve().parents[1] / "src"

BASE = """\
name = "tank"
dim = 2
dp = 0.05
end_time = 0.01

[fluid]
depth = 0.3
surface_level = 0.3

[output]
interval = 0.005

[[solids]]
name = "tank"
shape = { type = "tank", lo = [0.0, 0.0, 0.0], hi = [0.6, 0.0, 0.5] }

[[fluids]]
shape = { type = "box", lo = [0.0, 0.0, 0.0], hi = [0.6, 0.0, 0.3] }
"""

BASE3D = (BASE.replace("dim = 2", "dim = 3").replace("hi = [0.6, 0.0, 0.5]", "hi = [0.6, 0.3, 0.5]")
          .replace("hi = [0.6, 0.0, 0.3]", "hi = [0.6, 0.3, 0.3]"))

# a bed and water over it, no side walls: for periodic domains and explicit domains
BED = """\
name = "bed"
dim = 2
dp = 0.05
end_time = 0.01

[fluid]
depth = 0.3

[[solids]]
name = "bed"
shape = { type = "box", lo = [0.0, 0.0, -0.2], hi = [1.0, 0.0, 0.0] }

[[fluids]]
shape = { type = "box", lo = [0.0, 0.0, 0.0], hi = [1.0, 0.0, 0.3] }
"""


def edit(*subs, append="", base=BASE):
    """`base` with each (old, new) replaced once (old must be there), plus `append`."""
    text = base
    for old, new in subs:
        assert old in text, old
        text = text.replace(old, new, 1)
    return text + append


def solid(shape, motion=None, base=BASE):
    extra = f'motion = "{motion}"\n' if motion else ""
    return edit(append=f'\n[[solids]]\nname = "extra"\n{extra}shape = {shape}\n', base=base)


def probe(table):
    return edit(append=f"\n[[probes]]\n{table}\n")


PISTON = '\n[[motions]]\ntype = "piston"\nname = "paddle"\nheight = 0.02\nperiod = 1.0\ndepth = 0.3\n'
STL_BAD = "solid rock\n facet normal 0 0 1\n  outer loop\n   vertex 0 0 0\n   vertex 1 0\n"  # cut off mid-facet


def _ascii_stl(faces):
    """ASCII STL text of the triangles `faces` (vertex triples)."""
    body = "".join("facet normal 0 0 0\nouter loop\n" + "".join(f"vertex {x} {y} {z}\n" for x, y, z in f)
                   + "endloop\nendfacet\n" for f in faces)
    return f"solid rock\n{body}endsolid rock\n"


_CUBE = [((0, 0, 0), (0, 0.1, 0), (0.1, 0.1, 0)), ((0, 0, 0), (0.1, 0.1, 0), (0.1, 0, 0)),  # bottom
         ((0, 0, 0), (0.1, 0, 0), (0.1, 0, 0.1)), ((0, 0, 0), (0.1, 0, 0.1), (0, 0, 0.1)),
         ((0.1, 0, 0), (0.1, 0.1, 0), (0.1, 0.1, 0.1)), ((0.1, 0, 0), (0.1, 0.1, 0.1), (0.1, 0, 0.1)),
         ((0.1, 0.1, 0), (0, 0.1, 0), (0, 0.1, 0.1)), ((0.1, 0.1, 0), (0, 0.1, 0.1), (0.1, 0.1, 0.1)),
         ((0, 0.1, 0), (0, 0, 0), (0, 0, 0.1)), ((0, 0.1, 0), (0, 0, 0.1), (0, 0.1, 0.1))]
STL_OPEN = _ascii_stl(_CUBE)  # a box of 0.1 m without its top face
STL_FLAT = _ascii_stl(_CUBE[:2] + [f[::-1] for f in _CUBE[:2]])  # a square and its back: closed, no volume


def _vtu_bytes():
    """A valid one-snapshot VTU of four particles, written by shoal."""
    import tempfile

    from shoal.output.vtu import write_vtu

    with tempfile.TemporaryDirectory() as d:
        path = Path(d) / "c_0000.vtu"
        write_vtu(path, np.zeros((4, 3)), {"rho": np.ones(4)}, time=0.0)
        return path.read_bytes()


_VTU = _vtu_bytes()
_PVD = ('<?xml version="1.0"?>\n<VTKFile type="Collection" version="0.1">\n<Collection>\n'
        '<DataSet timestep="0" file="c_0000.vtu"/>\n</Collection>\n</VTKFile>\n')
POST_PLANE = ["post", "{d}/run", "--plane", "z=0", "--out", "{d}/plots"]


def _damaged_run(vtu):
    """The files of a run directory whose only snapshot holds the bytes `vtu`."""
    return {"run/c.pvd": _PVD, "run/c_0000.vtu": vtu, "run/resolved.json": "{}"}

TS_DECREASING = "t,x\n0.0,0.0\n1.0,0.1\n0.5,0.2\n"

RUN = ["--out", "{d}/out", "--no-plot", "--no-progress"]
BLOCK_CASE = edit(('hi = [0.6, 0.0, 0.5] }', 'hi = [1.2, 0.0, 0.6] }'),
                  append='\n[[solids]]\nname = "block"\nshape = { type = "box", lo = [0.6, 0.0, 0.0], '
                         'hi = [0.9, 0.0, 0.5] }\n')
GAUGE = '\n[[probes]]\ntype = "gauge"\nname = "g"\nx = {x}\nz0 = 0.05\nz1 = 0.4\ninterval = 0.005\n'
PADDLE_BOX = '{ type = "box", lo = [0.1, 0.0, 0.0], hi = [0.15, 0.0, 0.4] }'
MOTION_CV = '\n[[motions]]\ntype = "constant_velocity"\nname = "m"\nvelocity = [{v}]\n'
MOTION_TS = '\n[[motions]]\ntype = "time_series"\nname = "m"\nfile = "paddle.csv"\n'

# (id, files {name: text or bytes} written into the test's directory, argv ({d}: that directory),
#  fragments the error line must hold)
PISTON_HT = '\n[[motions]]\ntype = "piston"\nname = "p"\nheight = {h}\nperiod = {t}\ndepth = 0.3\n'
BATHY_NPZ = '\n[[solids]]\nname = "bed"\nshape = { type = "bathymetry", file = "bed.npz", base = -0.2 }\n'


def _npz(x=(0.0, 0.6), y=(0.0, 1.0), z=((-0.1, -0.1), (-0.1, -0.1))):
    """The bytes of an .npz height map with arrays x, y and z."""
    import io

    buf = io.BytesIO()
    np.savez(buf, x=np.asarray(x, float), y=np.asarray(y, float), z=np.asarray(z, float))
    return buf.getvalue()


CORPUS = [
    # ------------------------------------------------------------ malformed TOML
    ("toml-missing-value", {"case.toml": edit(("dp = 0.05", "dp = "))}, None, ["not valid TOML", "line 3"]),
    ("toml-unclosed-string", {"case.toml": edit(('name = "tank"', 'name = "tank'))}, None, ["not valid TOML"]),
    ("toml-unclosed-array", {"case.toml": edit(("hi = [0.6, 0.0, 0.3] }", "hi = [0.6, 0.0, 0.3 }"))}, None,
     ["not valid TOML"]),
    ("toml-duplicate-key", {"case.toml": edit(("dp = 0.05", "dp = 0.05\ndp = 0.04"))}, None, ["not valid TOML"]),
    ("toml-table-twice", {"case.toml": edit(append="\n[fluid]\nrho0 = 1000.0\n")}, None, ["not valid TOML"]),
    ("toml-bare-word", {"case.toml": edit(('name = "tank"', "name = tank"))}, None, ["not valid TOML"]),
    ("binary-file", {"case.toml": bytes(range(256)) * 4}, None, ["not a text file", "UTF-8"]),
    ("empty-file", {"case.toml": ""}, None, ["case.toml", "missing required key name", "more problems"]),
    ("latin-1-file", {"case.toml": BASE.replace('"tank"', '"t\xe9nk"').encode("latin-1")}, None,
     ["not a text file"]),
    ("case-file-is-a-directory", {"dir.toml/x": ""}, ["check", "{d}/dir.toml"], ["is a directory"]),
    # ------------------------------------------------------------ wrong types
    ("string-for-number", {"case.toml": edit(("dp = 0.05", 'dp = "fine"'))}, None, ["dp = 'fine'", "must be a number"]),
    ("list-for-table", {"case.toml": edit(("end_time = 0.01", "end_time = 0.01\noutput = [1, 2]"),
                                          ("[output]\ninterval = 0.005\n", ""))}, None,
     ["output = [1, 2]", "must be a table"]),
    ("boolean-for-integer", {"case.toml": edit(('name = "tank"\nshape', 'name = "tank"\nlayers = true\nshape'))},
     None, ["solids[0].layers", "must be an integer"]),
    ("boolean-for-dim", {"case.toml": edit(("dim = 2", "dim = true"))}, None, ["dim = true", "2 or 3"]),
    ("table-for-array", {"case.toml": edit(("[[fluids]]\nshape", "[fluids]\nshape"))}, None,
     ["fluids", "must be an array"]),
    ("string-for-vector", {"case.toml": edit(("depth = 0.3\n", 'depth = 0.3\ngravity = "down"\n'))}, None,
     ["fluid.gravity = 'down'", "must be an array"]),
    # ------------------------------------------------------------ zero or negative sizes
    ("dp-zero", {"case.toml": edit(("dp = 0.05", "dp = 0"))}, None, ["dp = 0", "greater than 0"]),
    ("dp-negative", {"case.toml": edit(("dp = 0.05", "dp = -0.05"))}, None, ["dp = -0.05", "greater than 0"]),
    ("dp-nan", {"case.toml": edit(("dp = 0.05", "dp = nan"))}, None, ["dp = nan", "finite"]),
    ("end-time-zero", {"case.toml": edit(("end_time = 0.01", "end_time = 0"))}, None, ["end_time = 0", "greater than 0"]),
    ("output-interval-zero", {"case.toml": edit(("interval = 0.005", "interval = 0.0"))}, None,
     ["output.interval = 0.0", "greater than 0"]),
    ("box-hi-below-lo", {"case.toml": edit(("hi = [0.6, 0.0, 0.3]", "hi = [0.6, 0.0, -0.3]"))}, None,
     ["fluids[0].shape", "hi.z = -0.3 is below lo.z"]),
    ("cylinder-zero-radius", {"case.toml": solid('{ type = "cylinder", axis = "z", center = [0.3, 0.15], radius = 0.0 }',
                                                 base=BASE3D)}, None, ["solids[1].shape.radius = 0.0", "greater than 0"]),
    ("tank-without-interior", {"case.toml": edit(("hi = [0.6, 0.0, 0.5]", "hi = [0.0, 0.0, 0.5]"))}, None,
     ["solids[0].shape", "hi.x = 0.0 must be above lo.x = 0.0"]),
    ("cli-dp-negative", {}, ["run", "--dp", "-1"], ["--dp", "positive", "-1"]),
    ("cli-end-time-zero", {}, ["check", "still-water-2d", "--end-time", "0"], ["--end-time", "positive"]),
    # ------------------------------------------------------------ geometry
    ("solid-covers-the-fluid", {"case.toml": solid('{ type = "box", lo = [-0.1, 0.0, -0.1], hi = [0.7, 0.0, 0.4] }')},
     None, ["fluids[0] (box) holds no particle", "inside solids"]),
    ("fluid-thinner-than-dp", {"case.toml": edit(("hi = [0.6, 0.0, 0.3]", "hi = [0.6, 0.0, 0.02]"))}, None,
     ["fluids[0] (box) holds no particle", "thinner than dp = 0.05 m along z (0.02 m)"]),
    ("fluid-outside-the-domain", {"case.toml": edit(("lo = [0.0, 0.0, 0.0], hi = [1.0, 0.0, 0.3]",
                                                     "lo = [0.0, 0.0, 2.0], hi = [1.0, 0.0, 2.3]"),
                                                    append="\n[domain]\nlo = [-0.1, 0.0, -0.3]\nhi = [1.1, 0.0, 1.0]\n",
                                                    base=BED)},
     None, ["fluids[0] (box) holds no particle", "lies outside the domain [-0.1, 1.1] x [-0.3, 1] m"]),
    ("solid-outside-the-domain", {"case.toml": edit(append="\n[domain]\nlo = [0.0, 0.0, 0.0]\nhi = [0.3, 0.0, 0.2]\n")},
     None, ["solids[0] (tank)", "outside the domain", "enlarge the domain"]),
    ("domain-hi-below-lo", {"case.toml": edit(append="\n[domain]\nlo = [0.0, 0.0, 0.0]\nhi = [-1.0, 0.0, 1.0]\n")},
     None, ["domain", "hi.x = -1.0 must be above lo.x"]),
    ("no-gravity-no-u_max", {"case.toml": edit(("depth = 0.3\n", "depth = 0.3\ngravity = [0.0, 0.0, 0.0]\n"))}, None,
     ["fluid.gravity = [0.0, 0.0, 0.0]", "speed of sound", "u_max"]),
    ("shape-type-unknown", {"case.toml": edit(('type = "tank"', 'type = "bowl"'))}, None,
     ["solids[0].shape.type = 'bowl'", "allowed: 'box', 'tank'"]),
    # ------------------------------------------------------------ motions
    ("motion-name-unknown", {"case.toml": solid('{ type = "box", lo = [0.0, 0.0, 0.0], hi = [0.05, 0.0, 0.4] }',
                                                motion="wiggle").replace("\n[[solids]]", PISTON + "\n[[solids]]", 1)},
     None, ["solids[1].motion = 'wiggle'", "names no motion", "motions: paddle"]),
    ("solid-motion-missing", {"case.toml": solid('{ type = "box", lo = [0.0, 0.0, 0.0], hi = [0.05, 0.0, 0.4] }',
                                                 motion="paddle")}, None,
     ["solids[1].motion = 'paddle'", "names no motion", "none defined"]),
    ("motion-type-unknown", {"case.toml": edit(append=PISTON.replace('"piston"', '"wobble"', 1))}, None,
     ["motions[0].type = 'wobble'", "not a known type", "'piston'"]),
    # ------------------------------------------------------------ missing and malformed files
    ("case-file-missing", {}, ["check", "{d}/nope.toml"], ["nope.toml", "not found"]),
    ("case-file-missing-run", {}, ["run", "{d}/nope.toml", *RUN], ["nope.toml", "not found"]),
    ("stl-missing", {"case.toml": solid('{ type = "mesh", file = "rock.stl" }', base=BASE3D)}, None,
     ["rock.stl", "not found"]),
    ("stl-malformed", {"case.toml": solid('{ type = "mesh", file = "rock.stl" }', base=BASE3D), "rock.stl": STL_BAD},
     None, ["rock.stl", "no triangles"]),
    ("stl-binary-truncated", {"case.toml": solid('{ type = "mesh", file = "rock.stl" }', base=BASE3D),
                              "rock.stl": bytes(80) + (1000).to_bytes(4, "little") + bytes(100)},
     None, ["rock.stl", "is truncated", "1,000 triangles"]),
    ("bathymetry-file-missing", {"case.toml": solid('{ type = "bathymetry", file = "bed.csv" }')}, None,
     ["bathymetry file", "bed.csv", "not found"]),
    ("bathymetry-file-malformed", {"case.toml": solid('{ type = "bathymetry", file = "bed.csv" }'),
                                   "bed.csv": "x,y,z\n0,0,zero\n1,0\n"}, None, ["bathymetry file", "bed.csv"]),
    ("time-series-file-missing", {"case.toml": solid('{ type = "box", lo = [0.0, 0.0, 0.0], hi = [0.05, 0.0, 0.4] }',
                                                     motion="m").replace(
        "\n[[solids]]", '\n[[motions]]\ntype = "time_series"\nname = "m"\nfile = "paddle.csv"\n\n[[solids]]', 1)},
     None, ["motion 'm'", "paddle.csv", "not found"]),
    ("time-series-times-decrease", {"case.toml": solid('{ type = "box", lo = [0.0, 0.0, 0.0], hi = [0.05, 0.0, 0.4] }',
                                                       motion="m").replace(
        "\n[[solids]]", '\n[[motions]]\ntype = "time_series"\nname = "m"\nfile = "paddle.csv"\n\n[[solids]]', 1),
        "paddle.csv": TS_DECREASING}, None, ["motion 'm'", "must increase strictly"]),
    ("time-series-file-malformed", {"case.toml": solid('{ type = "box", lo = [0.0, 0.0, 0.0], hi = [0.05, 0.0, 0.4] }',
                                                       motion="m").replace(
        "\n[[solids]]", '\n[[motions]]\ntype = "time_series"\nname = "m"\nfile = "paddle.csv"\n\n[[solids]]', 1),
        "paddle.csv": "t,x\n0.0,0.0\n1.0\n2.0,0.1,0.2,0.3,0.4\n"}, None, ["motion 'm'", "paddle.csv"]),
    # ------------------------------------------------------------ output directory
    ("out-is-a-file", {"case.toml": BASE, "taken": "a file"},
     ["run", "{d}/case.toml", "--out", "{d}/taken", "--no-plot", "--no-progress"], ["taken", "is a file"]),
    # ------------------------------------------------------------ unknown options, keys, cases
    ("cli-unknown-option", {}, ["run", "--frobnicate"], ["unrecognized arguments", "--frobnicate"]),
    ("cli-unknown-command", {}, ["simulate"], ["invalid choice", "simulate"]),
    ("unknown-top-level-key", {"case.toml": edit(("dp = 0.05", "dp = 0.05\nresolution = 3"))}, None,
     ["unknown key 'resolution'", "top level", "allowed keys:", "dp"]),
    ("unknown-key-in-options", {"case.toml": edit(append="\n[options]\nkernal = \"cubic\"\n")}, None,
     ["'kernal'", "options", "allowed keys:", "kernel"]),
    ("unknown-key-in-shape", {"case.toml": edit(('type = "tank",', 'type = "tank", height = 1.0,'))}, None,
     ["unknown key 'height'", "solids[0].shape", "allowed keys: hi, lo, open, type"]),
    ("unknown-key-in-probe", {"case.toml": probe('type = "gauge"\nname = "g"\nx = 0.3\nz0 = 0.0\nz1 = 0.5\n'
                                                 'interval = 0.005\ncolour = "red"')}, None,
     ["unknown key 'colour'", "probes[0]", "allowed keys:", "z1"]),
    ("unknown-case", {}, ["check", "dam-brake-2d"], ["unknown case 'dam-brake-2d'", "dam-break-2d"]),
    ("param-unknown-key", {}, ["check", "still-water-2d", "--param", "depht=0.3"],
     ["has no parameter 'depht'", "depth"]),
    ("param-bad-value", {}, ["check", "still-water-2d", "--param", "depth=deep"], ["depth = 'deep'", "positive"]),
    ("param-wrong-kind", {}, ["check", "still-water-2d", "--param", "layers=2.5"],
     ["--param layers=2.5", "layers = 2.5", "must be an integer"]),
    ("param-not-key-value", {}, ["check", "still-water-2d", "--param", "depth"], ["--param 'depth'", "KEY=VALUE"]),
    ("param-with-case-file", {"case.toml": BASE}, ["check", "{d}/case.toml", "--param", "depth=0.2"],
     ["--param sets parameters of built-in cases"]),
    ("precision-float16", {}, ["run", "--precision", "float16"], ["float16", "float32", "float64"]),
    ("backend-tpu", {}, ["run", "still-water-2d", "--backend", "tpu"], ["unknown backend 'tpu'", "'cpu', 'cuda'"]),
    ("resume-empty-dir", {"empty/.keep": ""}, ["run", "--resume", "{d}/empty"], ["no run to resume"]),
    ("resume-no-checkpoint", {"old/case.toml": BASE, "old/resolved.json": "{}"}, ["run", "--resume", "{d}/old"],
     ["holds no checkpoint", "ckpt_NNNNNN.h5"]),
    ("resume-missing-dir", {}, ["run", "--resume", "{d}/nowhere"], ["--resume", "no such run directory"]),
    ("resume-with-a-case", {"old/case.toml": BASE}, ["run", "still-water-2d", "--resume", "{d}/old"],
     ["--resume", "cannot be given with it"]),
    # ------------------------------------------------------------ more than this machine's memory
    ("tiny-dp-case-file-check", {"case.toml": edit(("dp = 0.05", "dp = 1e-6"))}, None,
     ["particles would be generated", "GiB", "use a larger dp"]),
    ("tiny-dp-case-file-run", {"case.toml": edit(("dp = 0.05", "dp = 1e-6"))}, ["run", "{d}/case.toml", *RUN],
     ["particles would be generated", "use a larger dp"]),
    ("tiny-dp-builtin-check", {}, ["check", "rip-current", "--dp", "0.001"], ["particles would be generated", "GiB"]),
    ("tiny-dp-builtin-run", {}, ["run", "rip-current", "--dp", "0.001", *RUN], ["particles would be generated"]),
    ("huge-domain-3d", {"case.toml": edit(append="\n[domain]\nlo = [-1e5, -1e5, -1e5]\nhi = [1e5, 1e5, 1e5]\n",
                                          base=BASE3D)}, None, ["lattice nodes", "smaller domain"]),
    ("huge-probe-grid", {"case.toml": probe('type = "grid"\nname = "g"\nlo = [0.1, 0.0, 0.1]\nhi = [0.5, 0.0, 0.3]\n'
                                            'counts = [100000, 1, 100000]\ninterval = 0.001')}, None,
     ["GiB for the probes", "probes[0] (grid 'g')", "fewer grid nodes"]),
    ("huge-gauge-line", {"case.toml": probe('type = "gauge"\nname = "g"\nx = 0.3\nz0 = 0.0\nz1 = 1e9\n'
                                            'interval = 0.005')}, ["run", "{d}/case.toml", *RUN],
     ["GiB for the probes", "probes[0] (gauge 'g')", "a shorter z0 .. z1"]),
    # ------------------------------------------------------------ probes
    ("probe-point-outside", {"case.toml": probe('type = "points"\nname = "p"\npoints = [[5.0, 0.0, 0.1]]\n'
                                                'interval = 0.005')}, None,
     ["probes[0] (points 'p')", "points[0] = [5.0, 0.0, 0.1]", "outside the domain"]),
    ("gauge-outside", {"case.toml": probe('type = "gauge"\nname = "g"\nx = -3.0\nz0 = 0.0\nz1 = 0.5\n'
                                          'interval = 0.005')}, ["run", "{d}/case.toml", *RUN],
     ["probes[0] (gauge 'g')", "x = -3", "outside the domain"]),
    ("tracker-id-not-a-particle", {"case.toml": probe('type = "tracker"\nname = "t"\nids = [5, 100000]\n'
                                                      'interval = 0.005')}, ["run", "{d}/case.toml", *RUN],
     ["probes[0] (tracker 't')", "ids [100000] are no particles"]),
    ("pressure-sensor-outside", {"case.toml": probe('type = "pressure"\nname = "wall"\npoints = [[0.3, 0.0, -2.0]]\n'
                                                    'interval = 0.005')}, None,
     ["probes[0] (pressure 'wall')", "points[0] = [0.3, 0.0, -2.0]", "outside the domain"]),
    ("pressure-sensor-area-without-normal", {"case.toml": probe('type = "pressure"\nname = "wall"\n'
                                                                'points = [[0.3, 0.0, 0.0]]\ndiameter = 0.01\n'
                                                                'interval = 0.005')}, None,
     ["probes[0]", "diameter = 0.01 m needs the wall's normal"]),
    ("pressure-sensor-method", {"case.toml": probe('type = "pressure"\nname = "wall"\npoints = [[0.3, 0.0, 0.0]]\n'
                                                   'method = "kriging"\ninterval = 0.005')}, None,
     ["probes[0]", "method", "linear"]),
    ("probe-names-repeated", {"case.toml": probe('type = "maxz"\nname = "m"\nx = 0.3\nradius = 0.1\ninterval = 0.01')
                              + '\n[[probes]]\ntype = "maxz"\nname = "m"\nx = 0.2\nradius = 0.1\ninterval = 0.01\n'},
     None, ["probes[1]", "named 'm'", "same file"]),
    # ------------------------------------------------------------ periodic and symmetry set-ups
    ("periodic-length-not-whole", {"case.toml": edit(append='\n[domain]\nlo = [0.0, 0.0, -0.3]\nhi = [1.02, 0.0, 1.0]'
                                                            '\nperiodic = ["x"]\n', base=BED)}, None,
     ["domain.periodic = ['x']", "1.02 m long in x", "not a whole number", "make it 1 m"]),
    ("periodic-y-in-2d", {"case.toml": edit(append='\n[domain]\nlo = [0.0, 0.0, -0.3]\nhi = [1.0, 0.0, 1.0]'
                                                   '\nperiodic = ["y"]\n', base=BED)}, None,
     ["periodic = ['y']", "not allowed in 2D"]),
    ("symmetry-plane-in-2d", {"case.toml": edit(append="\n[[symmetry_planes]]\npoint = [0.0, 0.1, 0.0]\n"
                                                       "normal = [0.0, -1.0, 0.0]\n")}, None,
     ["symmetry_planes[0]", "3D case", "2D case"]),
    ("symmetry-plane-not-y", {"case.toml": edit(append="\n[[symmetry_planes]]\npoint = [0.3, 0.0, 0.0]\n"
                                                       "normal = [1.0, 0.0, 0.0]\n", base=BASE3D)}, None,
     ["symmetry_planes[0].normal = [1.0, 0.0, 0.0]", "y = const"]),
    ("wall-plane-without-depth", {"case.toml": edit(("depth = 0.3\n", "u_max = 1.0\n"),
                                                    append="\n[[planes]]\npoint = [0.0, 0.0, 0.0]\n"
                                                           "normal = [0.0, 0.0, 1.0]\n")}, None,
     ["wall planes", "need gravity and a fluid.depth"]),
    # issue 30, class 4: intervals and time steps far below the stable step (the run would never end, or
    # fill the disk with snapshots): refused before anything runs
    ("output-interval-1e-300", {"case.toml": edit(("interval = 0.005", "interval = 1e-300"))}, None,
     ["output.interval = 1e-300 s", "below a hundredth of the stable time step", "give at least"]),
    ("checkpoint-interval-tiny", {"case.toml": edit(append="\n[checkpoint]\ninterval = 1e-12\n")}, None,
     ["checkpoint.interval = 1e-12 s", "below a hundredth", "1e+10 steps"]),
    ("probe-interval-tiny", {"case.toml": edit(append='\n[[probes]]\ntype = "gauge"\nname = "g"\nx = 0.3\n'
                                                      "z0 = 0.0\nz1 = 0.4\ninterval = 1e-200\n")}, None,
     ["probes[0].interval = 1e-200 s", "below a hundredth"]),
    ("fixed-dt-1e-300", {"case.toml": edit(append="\n[options]\nfixed_dt = 1e-300\n")}, None,
     ["options.fixed_dt = 1e-300 s", "below a hundredth"]),
    ("fixed-dt-option-flag", {}, ["run", "still-water-2d", "--dp", "0.05", "--option", "fixed_dt=1e-300",
                                  "--out", "{d}/out"],
     ["options.fixed_dt = 1e-300 s", "give at least"]),
    # issue 30, classes 6 and 7: a height map whose grid is not increasing, misshapen, or has holes
    ("npz-bathymetry-with-nan", {"case.toml": edit(append=BATHY_NPZ), "bed.npz": _npz(z=[[0.0, np.nan], [0.1, 0.1]])},
     None, ["bed.npz", "NaN or infinite", "height at every node"]),
    ("npz-bathymetry-decreasing-x", {"case.toml": edit(append=BATHY_NPZ), "bed.npz": _npz(x=[1.0, 0.0])}, None,
     ["bed.npz", "x must be at least 2 finite, increasing values"]),
    ("npz-bathymetry-z-misshapen", {"case.toml": edit(append=BATHY_NPZ), "bed.npz": _npz(z=[[0.0, 0.1, 0.2]])}, None,
     ["bed.npz", "not (len(x), len(y)) = (2, 2)"]),
    # issue 30, class 6: inputs at the limits
    ("dp-1e-300-on-a-built-in-case", {}, ["check", "still-water-2d", "--dp", "1e-300"],
     ["dp = 1e-300 m", "a million times finer", "use dp >="]),
    ("case-file-nested-5000-deep", {"case.toml": "a = " + "[" * 5000 + "]" * 5000 + "\n"}, None,
     ["nested too deeply"]),
    ("post-a-probe-csv-that-is-not-utf8", {"run/gauge_g.csv": b"time,level\n\xff\xfe,1\n", "run/resolved.json": "{}"},
     ["post", "{d}/run", "--out", "{d}/plots"], ["gauge_g.csv", "not UTF-8 text"]),
    ("case-file-path-5000-characters", {}, ["check", "{d}/" + "x" * 5000 + ".toml"], ["..."]),
    # issue 30, classes 6 and 7: waves that cannot exist, paddles that cannot move
    ("piston-wave-above-miche", {"case.toml": edit(append=PISTON_HT.format(h=0.2, t=1.0))}, None,
     ["height = 0.2 m", "breaking limit", "Miche 1944", "0.171 m"]),
    ("piston-period-1e-300", {"case.toml": edit(append=PISTON_HT.format(h=0.05, t=1e-300))}, None,
     ["period = 1e-300 s", "no finite wavelength"]),
    ("piston-period-1e300", {"case.toml": edit(append=PISTON_HT.format(h=0.05, t=1e300))}, None,
     ["period = 1e+300 s", "more than 1000 times the depth"]),
    ("solitary-above-mccowan", {"case.toml": edit(append='\n[[motions]]\ntype = "solitary"\nname = "s"\n'
                                                          "height = 0.25\ndepth = 0.3\n")}, None,
     ["height = 0.25 m", "0.833 times the depth", "H / d = 0.78 (McCowan 1894)"]),
    # issue 30, class 5: walls driven faster than sound (they crossed the fluid in one step, and one
    # far from its binned cell read outside the neighbour grid: SIGSEGV); refused by check and by run
    ("wall-at-1e12-m-per-s", {"case.toml": solid(PADDLE_BOX, motion="m").replace(
        "\n[[solids]]", MOTION_CV.format(v="1e12, 0.0, 0.0") + "\n[[solids]]", 1)}, None,
     ["motion 'm' reaches 1e+12 m/s", "speed of sound c0 = 34.3 m/s", "below 0.1 c0 = 3.43 m/s"]),
    ("wall-at-minus-1e12-m-per-s-run", {"case.toml": solid(PADDLE_BOX, motion="m").replace(
        "\n[[solids]]", MOTION_CV.format(v="0.0, 0.0, -1e12") + "\n[[solids]]", 1)}, ["run", "{d}/case.toml", *RUN],
     ["motion 'm' reaches 1e+12 m/s", "not below the speed of sound"]),
    ("wall-driven-millions-of-metres", {"case.toml": solid(PADDLE_BOX, motion="m").replace(
        "\n[[solids]]", MOTION_TS + "\n[[solids]]", 1), "paddle.csv": "t,x\n0.0,0.0\n0.005,3e6\n0.01,-3e6\n"},
     None, ["motion 'm' reaches", "e+09 m/s", "check the motion's units"]),
    ("wall-time-series-in-mm-scaled-1e9-run", {"case.toml": solid(PADDLE_BOX, motion="m").replace(
        "\n[[solids]]", MOTION_TS + "scale = 1e9\n\n[[solids]]", 1), "paddle.csv": "t,x\n0.0,0.0\n1.0,20.0\n"},
     ["run", "{d}/case.toml", *RUN], ["motion 'm' reaches", "not below the speed of sound c0 = 34.3 m/s"]),
    ("wall-3d-at-1e6-m-per-s-sideways", {"case.toml": solid(PADDLE_BOX.replace("0.0, 0.4]", "0.3, 0.4]"), motion="m",
                                                             base=BASE3D).replace(
        "\n[[solids]]", MOTION_CV.format(v="0.0, 1e6, 0.0") + "\n[[solids]]", 1)}, None,
     ["motion 'm' reaches 1e+06 m/s", "options.coef_sound or fluid.u_max"]),
    # issue 30, class 7: numbers the float32 kernels cannot hold (the run stopped at step 0 as "unstable")
    ("rho0-1e300", {"case.toml": edit(("depth = 0.3", "depth = 0.3\nrho0 = 1e300"))}, None,
     ["fluid.rho0 = 1e+300 kg/m^3", "rho0^2 = inf", "outside what float32 holds", "water is rho0 = 1000"]),
    ("rho0-1e-300-run", {"case.toml": edit(("depth = 0.3", "depth = 0.3\nrho0 = 1e-300"))}, ["run", "{d}/case.toml",
                                                                                           *RUN],
     ["fluid.rho0 = 1e-300 kg/m^3", "rho0^2 = 0"]),
    ("rho0-1e20-fits-only-float64", {"case.toml": edit(("depth = 0.3", "depth = 0.3\nrho0 = 1e20"))}, None,
     ["rho0^2 = 1e+40", 'use options.precision = "float64"']),
    ("u-max-1e300", {"case.toml": edit(("depth = 0.3", "depth = 0.3\nu_max = 1e300"))}, None,
     ["c0 = 2e+301 m/s", "c0^2 = inf"]),
    ("depth-1e300", {"case.toml": edit(("depth = 0.3\n", "depth = 1e300\n"))}, None, ["c0^2 = 3.92e+303"]),
    ("fluid-velocity-1e300-run", {"case.toml": edit(("hi = [0.6, 0.0, 0.3] }", "hi = [0.6, 0.0, 0.3] }\n"
                                                                               "velocity = [1e300, 0.0, 0.0]"))},
     ["run", "{d}/case.toml", *RUN], ["fluids[0].velocity", "not below the speed of sound c0 = 34.3 m/s"]),
    # issue 30, class 7: probes buried in a fixed wall (they recorded NaN for the whole run)
    ("gauge-inside-a-block", {"case.toml": BLOCK_CASE + GAUGE.format(x=0.75)}, None,
     ["probes[0] (gauge 'g')", "x = 0.75 m, z = 0.05 .. 0.4 m", "inside solids[1] (block)", "move it into the water"]),
    ("gauge-inside-the-tank-wall-run", {"case.toml": BLOCK_CASE + GAUGE.format(x=-0.05)}, ["run", "{d}/case.toml", *RUN],
     ["x = -0.05 m", "inside solids[0] (tank)"]),
    ("probe-point-inside-a-block", {"case.toml": BLOCK_CASE + '\n[[probes]]\ntype = "points"\nname = "p"\n'
                                    "points = [[0.3, 0.0, 0.1], [0.75, 0.0, 0.2]]\ninterval = 0.005\n"}, None,
     ["probes[0] (points 'p'): points[1] = [0.75, 0.0, 0.2]", "inside solids[1] (block)"]),
    # issue 30, class 7: meshes that bound no solid (an open one classified lattice nodes at random)
    ("stl-open-box", {"case.toml": solid('{ type = "mesh", file = "rock.stl" }', base=BASE3D), "rock.stl": STL_OPEN},
     None, ["rock.stl' is open", "4 edges belong to one triangle only", "fill its holes"]),
    ("stl-flat", {"case.toml": solid('{ type = "mesh", file = "rock.stl" }', base=BASE3D), "rock.stl": STL_FLAT},
     None, ["rock.stl' encloses no volume", "flat"]),
    # issue 30, class 6: snapshots that meshio cannot parse (it printed its own message and exited 1)
    ("post-a-truncated-vtu", _damaged_run(_VTU[: len(_VTU) // 2]), POST_PLANE,
     ["c_0000.vtu is not a readable VTU snapshot", "truncated or damaged", "move it aside"]),
    ("post-an-empty-vtu", _damaged_run(b""), POST_PLANE, ["c_0000.vtu is not a readable VTU snapshot"]),
    ("post-a-binary-vtu", _damaged_run(bytes(range(256)) * 8), POST_PLANE, ["c_0000.vtu is not a readable VTU"]),
    # issue 30, class 8: a report merged from nothing
    ("validate-report-only-from-nothing", {}, ["validate", "--report-only", "--out", "{d}/out"],
     ["nothing to merge", "no results.json", "shoal validate --out DIR"]),
    # issue 30, classes 3 and 7: a run named after a folder, an endless name, a number with a typo
    ("case-name-dot-dot", {"case.toml": edit(('name = "tank"', 'name = ".."'))}, None,
     ["name = '..'", "not dots alone"]),
    ("case-name-dot", {"case.toml": edit(('name = "tank"', 'name = "."'))}, None, ["name = '.'", "not dots alone"]),
    ("case-name-300-characters", {"case.toml": edit(('name = "tank"', f'name = "{"x" * 300}"'))}, None,
     ["300 characters", "at most 100"]),
    ("dp-with-an-underscore", {}, ["check", "still-water-2d", "--dp", "0_05"], ["--dp must be a number", "'0_05'"]),
    ("end-time-with-an-underscore", {}, ["check", "still-water-2d", "--end-time", "1_0"],
     ["--end-time must be a number", "'1_0'"]),
    ("output-interval-flag-on-a-case-file", {"case.toml": BASE}, ["run", "{d}/case.toml", "--output-interval",
                                                                  "1e-300", "--out", "{d}/out"],
     ["output.interval = 1e-300 s", "below a hundredth"]),
]


def test_corpus_is_large_and_distinct():
    assert len(CORPUS) >= 40
    assert len({c[0] for c in CORPUS}) == len(CORPUS)


def _write(d, files):
    for name, content in files.items():
        p = d / name
        p.parent.mkdir(parents=True, exist_ok=True)
        if isinstance(content, bytes):
            p.write_bytes(content)
        else:
            p.write_text(content, encoding="utf-8")


def _cli(argv):
    """The CLI in this process: its exit status, returned or raised (argparse raises SystemExit)."""
    try:
        return main(argv)
    except SystemExit as exc:
        return exc.code


def _one_error_line(err):
    assert "Traceback" not in err, err
    lines = err.splitlines()
    assert len(lines) == 1, err
    assert lines[0].startswith("shoal: error: "), err
    return lines[0]


@pytest.mark.parametrize("files,argv,fragments", [pytest.param(*c[1:], id=c[0]) for c in CORPUS])
def test_bad_input_is_one_line_and_exit_2(files, argv, fragments, tmp_path, monkeypatch, capsys, request):
    monkeypatch.chdir(tmp_path)  # a refused run must not write runs/ anywhere either
    _write(tmp_path, files)
    argv = [a.replace("{d}", str(tmp_path)) for a in (argv or ["check", "{d}/case.toml"])]
    status = _cli(argv)
    out, err = capsys.readouterr()
    assert status == 2, (status, out, err)
    line = _one_error_line(err)
    print(f"\n[{request.node.callspec.id}] {line}")
    for part in fragments:
        assert part in line, (part, line)
    assert not (tmp_path / "out").exists() and not (tmp_path / "runs").exists()  # nothing was written


def test_unwritable_output_directory(tmp_path, capsys):
    """A run whose output directory cannot be created or written: one line, exit 2. As root, permissions
    do not stop writes, so the directory is put under a regular file (which stops root too)."""
    (tmp_path / "case.toml").write_text(BASE)
    if os.geteuid() == 0:
        (tmp_path / "plain-file").write_text("not a directory")
        out_dir = tmp_path / "plain-file" / "out"
    else:
        locked = tmp_path / "locked"
        locked.mkdir()
        locked.chmod(0o500)
        out_dir = locked / "out"
    try:
        status = _cli(["run", str(tmp_path / "case.toml"), "--out", str(out_dir), "--no-plot", "--no-progress"])
    finally:
        if os.geteuid() != 0:
            (tmp_path / "locked").chmod(0o700)
    line = _one_error_line(capsys.readouterr().err)
    print("\n" + line)
    assert status == 2
    assert "cannot write to the output directory" in line and str(out_dir) in line
    assert not out_dir.exists()


# ----------------------------------------------------------------------------- nothing already written is lost

def _snapshot(d):
    """{relative path: (size, mtime_ns, sha256)} of every file under `d`."""
    return {str(p.relative_to(d)): (p.stat().st_size, p.stat().st_mtime_ns, hashlib.sha256(p.read_bytes()).hexdigest())
            for p in sorted(d.rglob("*")) if p.is_file()}


@pytest.fixture
def previous_run(tmp_path):
    """A run directory holding a previous run's files (their content does not matter here)."""
    d = tmp_path / "runs" / "tank"
    d.mkdir(parents=True)
    for name, text in [("resolved.json", '{"name": "tank"}\n'), ("case.toml", BASE), ("run.log", "done\n"),
                       ("tank.pvd", "<VTKFile/>\n"), ("tank_0000.vtu", "vtu 0\n"), ("tank_0001.vtu", "vtu 1\n"),
                       ("gauge_g.csv", "time,level\n0,0.3\n"), ("escaped.csv", "id,kind,time,x,y,z,u,v,w\n")]:
        (d / name).write_text(text)
    (d / "ckpt_000010.h5").write_bytes(b"\x89HDF\r\n\x1a\n" + bytes(64))
    old = 1_600_000_000_000_000_000  # mtimes in the past, so a rewrite would show
    for p in d.iterdir():
        os.utime(p, ns=(old, old))
    return d


@pytest.mark.parametrize("what,text,extra", [
    ("already-a-run", BASE, []),
    ("bad-case-with-overwrite", edit(("dp = 0.05", "dp = -1")), ["--overwrite"]),
    ("probe-outside-with-overwrite", probe('type = "points"\nname = "p"\npoints = [[9.0, 0.0, 0.1]]\ninterval = 0.005'),
     ["--overwrite"]),
    ("too-big-with-overwrite", edit(("dp = 0.05", "dp = 1e-6")), ["--overwrite"]),
])
def test_refused_run_leaves_the_previous_run_untouched(what, text, extra, previous_run, tmp_path, capsys):
    case = tmp_path / "case.toml"
    case.write_text(text)
    before = _snapshot(previous_run)
    status = _cli(["run", str(case), "--out", str(previous_run), "--no-plot", "--no-progress", *extra])
    line = _one_error_line(capsys.readouterr().err)
    print(f"\n[{what}] {line}")
    assert status == 2
    assert _snapshot(previous_run) == before  # same files, same bytes, same mtimes
    if what == "already-a-run":
        assert "already holds a run" in line and "--overwrite" in line


# ----------------------------------------------------------------------------- end to end, in a subprocess

def _shoal(args, cwd):
    env = dict(os.environ)
    env["PYTHONPATH"] = str(SRC) + os.pathsep + env.get("PYTHONPATH", "")
    return subprocess.run([sys.executable, "-m", "shoal", *args], capture_output=True, text=True, env=env, cwd=cwd,
                          timeout=120)


@pytest.mark.parametrize("files,args,fragment", [
    pytest.param({"case.toml": bytes(range(256))}, ["check", "case.toml"], "not a text file", id="binary-file"),
    pytest.param({"case.toml": edit(("dp = 0.05", "dp = "))}, ["run", "case.toml", "--no-plot"], "not valid TOML",
                 id="malformed-toml-run"),
    pytest.param({"case.toml": edit(("dp = 0.05", "dp = 1e-6"))}, ["run", "case.toml", "--no-plot"],
                 "use a larger dp", id="too-big-run"),
    pytest.param({}, ["run", "--resume", "nowhere"], "no such run directory", id="resume-nowhere"),
    pytest.param({}, ["check", "still-water-2d", "--param", "layers=2.5"], "must be an integer",
                 id="param-wrong-kind"),
])
def test_subprocess_exit_2_without_traceback(files, args, fragment, tmp_path):
    _write(tmp_path, files)
    proc = _shoal(args, tmp_path)
    assert proc.returncode == 2, proc.stderr
    assert "Traceback" not in proc.stderr
    lines = proc.stderr.splitlines()
    assert len(lines) == 1 and lines[0].startswith("shoal: error: ") and fragment in lines[0], proc.stderr
    assert not (tmp_path / "runs").exists()  # nothing was written


def test_check_shows_a_description_without_its_control_characters(tmp_path, capsys):
    """An untrusted case file's description reaches the terminal with its escape sequences replaced."""
    text = BASE.replace('name = "tank"\n', 'name = "tank"\ndescription = "x\\u001b[31mred\\u0007"\n', 1)
    (tmp_path / "case.toml").write_text(text, encoding="utf-8")
    assert _cli(["check", str(tmp_path / "case.toml")]) == 0, capsys.readouterr().err
    out = capsys.readouterr().out
    assert "\x1b" not in out and "\x07" not in out and out.splitlines()[0] == "case tank: x?[31mred?"


def test_a_parameter_key_with_a_line_break_is_shown_escaped():
    """A key holding a control character (found by tests/test_bad_inputs_property.py: "\\r") is shown quoted
    with its escapes, so the error stays one line."""
    import shoal
    from shoal.geometry import Box

    with pytest.raises(ValueError) as err:
        shoal.Case(name="k", dim=2, dp=0.02, fluid=shoal.Fluid(depth=0.3), parameters={"\r": [None]},
                   fluids=[shoal.FluidRegion(shape=Box(lo=(0, 0, 0), hi=(1, 0, 0.3)))])
    msg = str(err.value).splitlines()[-1]
    assert "'\\r'[0] = nothing: a parameter is a number" in str(err.value)
    assert "\r" not in msg
