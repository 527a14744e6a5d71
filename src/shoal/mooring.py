"""Mooring lines of floating bodies, computed by MoorDyn v2 and coupled through their fairlead points.

MoorDyn (Hall & Goupee 2015, "Validation of a lumped-mass mooring line model with DeepCwind semisubmersible
model test data", Ocean Engineering 104, 590-603; https://moordyn.readthedocs.io) discretises each line
into N segments between N + 1 lumped-mass nodes, with axial stiffness and internal damping per segment,
weight and buoyancy, Morison drag and added mass per node and a penalty seabed; shoal drives it through
the `moordyn` package (MoorDyn-C's Python wrapper) and keeps the rigid-body dynamics to itself.

What is coupled
    Each fairlead is a MoorDyn point of type ``Coupled`` (or ``Vessel``): 3 degrees of freedom whose
    position and velocity shoal imposes. Fairlead k belongs to body b_k and is the body point that was at
    x0_k at t = 0, so at a body state (c, R, v, omega) (`shoal.rigid_body.BodyState`)

        x_k = c + R (x0_k - c0),   u_k = v + omega x (x_k - c)

    (`shoal.body_loads.body_point`). Coupled MoorDyn bodies and rods are refused: shoal, not MoorDyn,
    integrates the bodies.

One step (`Mooring.loads`)
    ``moordyn.Step(x^n, u^n, t, dt)`` moves the fairlead points from x^n along u^n over [t, t + dt]
    (MoorDyn's own sub-steps of its ``dtM`` interpolate them linearly) and advances the lines to t + dt;
    it returns F_k, the force the lines pull fairlead k with at t + dt: the tension of each attached line's
    end segment plus what MoorDyn lumps into its end node (half a segment's weight, buoyancy, drag) and
    the point's own weight and drag when the input gives it a mass, volume or CdA. The force and torque on
    body b (world frame, torque about its centre of gravity c) are

        F_b = sum_{k: b_k = b} F_k,   T_b = sum_{k: b_k = b} (x_k^n - c^n) x F_k.

    The coupling is explicit (a loose coupling, as MoorDyn's own drivers: the force at the end of a step
    from the motion at its start); its lag of one step is negligible when the body's time step, set by the
    fluid, is far below the lines' and the body's periods.

Files
    MoorDyn writes ``<name>.out`` (and, as its input asks, ``<name>_Line<k>.out`` and ``<name>.log``) next
    to the input file it reads. shoal gives it a private directory instead: a copy of the input file, with
    ``1 disableOutTime`` first among its options (else MoorDyn prints the time to the console at every
    step; a setting later in the file wins), and links to everything else in the input file's directory,
    so that the files the input names by relative path (``fileIC``, a seabed file, wave grids) are found.
    At `Mooring.close`, MoorDyn's files move to `moordyn_dir` when one is given, else they are deleted.
    shoal writes its own CSV files (`MooringRecorder`).

Checkpoints
    `Mooring.checkpoint_state` holds MoorDyn's serialised system (``moordyn.Serialize``: every line node's
    position and velocity, the time integrator's state) with the fairleads' last kinematics and forces;
    `Mooring.restore_state` sets them back (``moordyn.Init_NoIC`` then ``moordyn.Deserialize``), and the run
    continues bitwise as if it had not stopped.

Frames
    MoorDyn's frame has z = 0 at the still water level and the seabed at z = -WtrDpth; a shoal case often
    has its bed at z = 0. `Mooring`'s `origin` is the point of shoal's frame that is MoorDyn's origin (a
    flume with its bed at z = 0 and still-water depth d: origin = (0, 0, d)); the fairleads go to MoorDyn at
    x - origin, and the node positions come back at x_MoorDyn + origin. The axes are the same (z up).

Units: SI. A 2D body is per unit width: MoorDyn's forces are in N, not N/m, so a 2D model needs them divided by its width.
"""

from __future__ import annotations

import contextlib
import csv
import ctypes
import io
import os
import re
import shutil
import sys
import tempfile
import warnings
from pathlib import Path

import numpy as np

from .body_loads import body_point
from .rigid_body import cross3
from .errors import InputError, InstabilityError

_CHECKPOINT_VERSION = 1


def _flush_c_streams():
    """fflush(NULL): MoorDyn writes through C++'s std::cout/cerr, which share C's stdio buffers; what they
    hold must reach the redirected descriptors before these are put back."""
    try:
        ctypes.CDLL(None).fflush(None)
    except (OSError, AttributeError):  # no C library to call (not on Linux/macOS): nothing buffered to lose
        pass


@contextlib.contextmanager
def _captured_console():
    """Redirect the process's stdout and stderr (file descriptors 1 and 2, which MoorDyn's C++ writes to)
    into a temporary file for the block; yields a list that holds the captured text afterwards.

    Why: MoorDyn prints a banner and its progress at creation and initialisation, and its errors only as
    text on stderr (the wrapper raises a bare ``RuntimeError('MoorDyn_Create() failed')``); capturing them
    keeps the console quiet and lets `Mooring` say what was wrong in one line."""
    out = []
    sys.stdout.flush()
    sys.stderr.flush()
    try:
        saved = [os.dup(1), os.dup(2)]
    except OSError:  # no console to capture (descriptors closed): nothing to keep quiet
        yield out
        out.append("")
        return
    with tempfile.TemporaryFile(mode="w+b") as sink:
        try:
            os.dup2(sink.fileno(), 1)
            os.dup2(sink.fileno(), 2)
            try:
                yield out
            finally:
                _flush_c_streams()
        finally:
            os.dup2(saved[0], 1)
            os.dup2(saved[1], 2)
            os.close(saved[0])
            os.close(saved[1])
            sink.seek(0)
            out.append(sink.read().decode("utf-8", errors="replace"))


_PREFIX = re.compile(r"^(ERR|WRN|MSG|DBG)\s+\S+:\d+\s+\S+\(\)\s*:\s*")


def _messages(text, level):
    """MoorDyn's log lines of `level` ("ERR" or "WRN") in `text`, without their source-location prefix
    ("ERR /project/source/X.cpp:12 f(): "), and the lines that follow them (MoorDyn continues a message
    on the next lines)."""
    lines, keep = [], False
    for raw in text.replace("\r", "\n").splitlines():
        line = raw.strip()
        m = _PREFIX.match(line)
        if m:
            keep = m.group(1) == level
            line = line[m.end():]
        elif line.startswith(("ERR ", "WRN ", "MSG ", "DBG ")):
            keep = line.startswith(level)
            line = line[4:]
        elif level == "ERR" and line.startswith("Error ("):
            keep = True
        if keep and line:
            lines.append(line.rstrip(":"))
    return lines


def _with_quiet_console(text):
    """The input file's text with ``1 disableOutTime`` first among its OPTIONS (module docstring); the text
    unchanged when it has no OPTIONS section (MoorDyn will refuse it anyway)."""
    lines = text.splitlines(keepends=True)
    for i, line in enumerate(lines):
        if "---" in line and "OPTIONS" in line.upper():
            newline = "\r\n" if line.endswith("\r\n") else "\n"
            if not line.endswith("\n"):
                lines[i] = line + newline
            lines.insert(i + 1, "1             disableOutTime   (set by shoal: no time print per step)" + newline)
            return "".join(lines)
    return text


class Mooring:
    """Mooring lines computed by MoorDyn, pulling at fairlead points of shoal's rigid bodies (module
    docstring for the coupling).

    Parameters
    ----------
    input_file : str or path-like
        A MoorDyn v2 input file. Its POINTS of type ``Coupled`` (or ``Vessel``) are the fairleads; it may
        have no coupled bodies or rods.
    fairleads : sequence of (int, array_like)
        One ``(body_index, x0)`` per coupled point, in the order of the POINTS section: the index of the
        body (in the lists given to `initialise` and `loads`) and where the fairlead, a point of that body,
        was at t = 0 [m].
    moordyn_dir : str or path-like, optional
        Where MoorDyn's own output files go at `close` (created if missing); by default they are deleted.
    origin : array_like, optional
        [m], the point of shoal's frame that is the origin of MoorDyn's (on the still water level; module
        docstring, Frames). Default (0, 0, 0): the frames are the same.

    Raises
    ------
    shoal.errors.InputError
        A missing or unreadable file, one MoorDyn refuses (its message), coupled bodies or rods, or a
        number of fairleads other than the number of coupled points.

    Notes
    -----
    Usable as a context manager: ``with Mooring(...) as m:`` closes MoorDyn at the end.
    """

    def __init__(self, input_file, fairleads, moordyn_dir=None, origin=(0.0, 0.0, 0.0)):
        self.input_file = Path(input_file)
        try:
            self.origin = np.array(origin, float).reshape(3)
        except (TypeError, ValueError):
            raise InputError(f"mooring origin {origin!r}: not a point [x, y, z]") from None
        if not np.all(np.isfinite(self.origin)):
            raise InputError(f"mooring origin {self.origin.tolist()}: not finite")
        self.moordyn_dir = None if moordyn_dir is None else Path(moordyn_dir)
        self._system = None
        self._workdir = None
        self._initialised = False
        self.fairleads = self._checked_fairleads(fairleads)
        name = self.input_file
        if not name.exists():
            raise InputError(f"mooring input file {name}: not found")
        try:
            text = name.read_bytes().decode("utf-8", errors="surrogateescape")
        except OSError as e:
            raise InputError(f"mooring input file {name}: cannot be read ({e.strerror or e})") from None
        self._workdir = Path(tempfile.mkdtemp(prefix="shoal-moordyn-"))
        try:
            self._prepare_workdir(text)
            try:
                import moordyn  # deferred: shoal runs without MoorDyn until a case is moored
            except ImportError:
                raise InputError(f"mooring input file {name}: mooring lines need the moordyn package "
                                 "(pip install moordyn)") from None
            self._moordyn = moordyn
            with _captured_console() as console:
                try:
                    self._system = moordyn.Create(str(self._workdir / name.name))
                except RuntimeError:
                    self._system = None
            if self._system is None:
                raise InputError(self._refusal("refused by MoorDyn", console[0]))
            moordyn.SetVerbosity(self._system, moordyn.LEVEL_WRN)
            moordyn.SetLogLevel(self._system, moordyn.LEVEL_WRN)
            self._check_model()
        except BaseException:
            self._discard()
            raise

    # ------------------------------------------------------------ construction
    def _checked_fairleads(self, fairleads):
        out = []
        for k, item in enumerate(fairleads):
            try:
                b, x0 = item
                x0 = np.array(x0, float).reshape(3)
            except (TypeError, ValueError):
                raise InputError(f"mooring fairlead {k}: {item!r} is not (body_index, [x, y, z])") from None
            if isinstance(b, bool) or not isinstance(b, (int, np.integer)) or b < 0:
                raise InputError(f"mooring fairlead {k}: body index {b!r} is not an integer >= 0")
            if not np.all(np.isfinite(x0)):
                raise InputError(f"mooring fairlead {k}: position {x0.tolist()} is not finite")
            out.append((int(b), x0))
        return out

    def _prepare_workdir(self, text):
        """The private directory MoorDyn reads from and writes to (module docstring, Files)."""
        src = self.input_file.resolve().parent
        stem = self.input_file.stem
        for entry in os.scandir(src):
            name = entry.name
            # not the input, and not the files MoorDyn will write: through a link it would overwrite them
            # (the output of an earlier MoorDyn run beside the input)
            if name != self.input_file.name and not (
                    name.startswith(stem) and name.endswith((".out", ".log", ".vtu", ".vtm"))):
                with contextlib.suppress(OSError):  # links are a convenience; a file named by a path still works
                    os.symlink(entry.path, self._workdir / entry.name)
        (self._workdir / self.input_file.name).write_bytes(
            _with_quiet_console(text).encode("utf-8", errors="surrogateescape"))

    def _refusal(self, what, console):
        errors = [e.replace(str(self._workdir / self.input_file.name), str(self.input_file))
                  for e in _messages(console, "ERR")]
        # MoorDyn's own message first; its generic trailer ("Error (-3) during the Mooring System creation",
        # "Exception while reading the input file") only when there is nothing else
        specific = [e for e in errors if not e.startswith(("Error (", "Exception while"))]
        errors = specific or errors
        detail = "; ".join(dict.fromkeys(errors)) if errors else "MoorDyn gave no reason"
        return f"mooring input file {self.input_file}: {what}: {detail}"

    def _check_model(self):
        md, s = self._moordyn, self._system
        self.n_lines = int(md.GetNumberLines(s))
        if self.n_lines == 0:
            raise InputError(f"mooring input file {self.input_file}: no lines (is it a MoorDyn v2 input file, "
                             "with a LINES section?)")
        points = [md.GetPoint(s, i) for i in range(1, int(md.GetNumberPoints(s)) + 1)]
        self._coupled = [p for p in points if md.GetPointType(p) == md.POINT_TYPE_COUPLED]
        ndof = int(md.NCoupledDOF(s))
        if ndof != 3 * len(self._coupled):
            raise InputError(f"mooring input file {self.input_file}: it couples bodies or rods "
                             f"({ndof} coupled degrees of freedom, {len(self._coupled)} coupled points); shoal "
                             "integrates the bodies itself: attach the lines to points of type Coupled")
        if len(self.fairleads) != len(self._coupled):
            raise InputError(f"mooring input file {self.input_file}: {len(self._coupled)} coupled points, "
                             f"{len(self.fairleads)} fairleads given: give one (body_index, x0) per coupled "
                             "point, in the order of the POINTS section")
        self._lines = [md.GetLine(s, k) for k in range(1, self.n_lines + 1)]
        self.forces = np.zeros((len(self.fairleads), 3))
        self._x = np.zeros((len(self.fairleads), 3))
        self._u = np.zeros((len(self.fairleads), 3))

    # ------------------------------------------------------------ coupling
    @property
    def n_fairleads(self):
        """The number of fairleads (MoorDyn's coupled points)."""
        return len(self.fairleads)

    def fairlead_kinematics(self, bodies, states):
        """(x, u): the fairleads' positions [m] (shoal's frame) and velocities [m/s], arrays (n_fairleads, 3),
        at the bodies' `states`: x = c + R (x0 - c0), u = v + omega x (x - c)."""
        if len(bodies) != len(states):
            raise ValueError(f"{len(bodies)} bodies and {len(states)} states")
        x, u = np.empty((self.n_fairleads, 3)), np.empty((self.n_fairleads, 3))
        for k, (b, x0) in enumerate(self.fairleads):
            if b >= len(bodies):
                raise InputError(f"mooring fairlead {k}: body index {b}, but there are {len(bodies)} bodies")
            x[k], u[k] = body_point(bodies[b], states[b], x0)
        return x, u

    def initialise(self, bodies, states):
        """Place the fairleads at the bodies' `states` and run ``moordyn.Init``: MoorDyn's initial condition
        (its static solve or dynamic relaxation, as the input's options ask) with the fairleads held there.
        Sets `forces` to the lines' pull on the fairleads in that state.

        Raises
        ------
        shoal.errors.InputError
            MoorDyn failed to initialise (its message).
        """
        self._x, self._u = self.fairlead_kinematics(bodies, states)
        md = self._moordyn
        with _captured_console() as console:
            try:
                err = md.Init(self._system, (self._x - self.origin).ravel().tolist(), self._u.ravel().tolist())
            except RuntimeError:
                err = -255
        self._warn(console[0])
        if err != md.ERRCODE_SUCCESS:
            raise InputError(self._refusal(f"MoorDyn's initialisation failed (error {err})", console[0]))
        self._initialised = True
        # dt = 0: no step, only the forces of the state just found
        self.forces = np.asarray(md.Step(self._system, (self._x - self.origin).ravel().tolist(),
                                         self._u.ravel().tolist(), 0.0, 0.0), float).reshape(-1, 3)

    def _warn(self, console):
        for msg in dict.fromkeys(_messages(console, "WRN")):
            warnings.warn(f"MoorDyn ({self.input_file}): {msg}", RuntimeWarning, stacklevel=3)

    def loads(self, bodies, states, t, dt):
        """Advance the lines from t to t + dt with the fairleads moving from the bodies' `states` (at t)
        along their velocities, and return the lines' loads on every body.

        Parameters
        ----------
        bodies : sequence of shoal.rigid_body.RigidBody
        states : sequence of shoal.rigid_body.BodyState
            The bodies' states at t.
        t, dt : float
            The step's start and length [s].

        Returns
        -------
        list of (numpy.ndarray, numpy.ndarray)
            (F [N], T [N m]) per body, world frame, T about the body's centre of gravity
            ``states[b].position``: F_b = sum F_k, T_b = sum (x_k - c) x F_k over the body's fairleads k,
            F_k the lines' pull on fairlead k at t + dt (module docstring). Zero for unmoored bodies.
            `forces` keeps the F_k, (n_fairleads, 3).

        Raises
        ------
        shoal.errors.InstabilityError
            MoorDyn failed in the step (NaN in the lines: a time step ``dtM`` too long for the lines'
            stiffness, or a fairlead moved impossibly far).
        """
        if not self._initialised:
            raise RuntimeError("Mooring.initialise (or restore_state) must come before loads")
        x, u = self.fairlead_kinematics(bodies, states)
        try:
            f = self._moordyn.Step(self._system, (x - self.origin).ravel().tolist(), u.ravel().tolist(),
                                   float(t), float(dt))
        except RuntimeError as e:
            raise InstabilityError(f"MoorDyn ({self.input_file}) failed in the step from t = {t:g} s "
                                   f"(dt = {dt:g} s): {e}; its message is above") from None
        f = np.asarray(f, float).reshape(-1, 3)
        if not np.all(np.isfinite(f)):
            raise InstabilityError(f"MoorDyn ({self.input_file}): a fairlead force is not finite after the step "
                                   f"from t = {t:g} s; try a smaller dtM (or CFL) in its OPTIONS")
        self._x, self._u, self.forces = x, u, f
        out = [(np.zeros(3), np.zeros(3)) for _ in bodies]
        for k, (b, _) in enumerate(self.fairleads):
            arm = x[k] - states[b].position
            out[b] = (out[b][0] + f[k], out[b][1] + cross3(arm, f[k]))
        return out

    def body_load(self, body_index):
        """``load(body, state, t) -> (F, T)`` (`shoal.body_loads`): the fairlead forces of the last `loads`
        call held, applied at the fairleads of body `body_index` where `state` puts them,
        T = sum (x_k(state) - c) x F_k. For the integrator's stages within one step, which MoorDyn advances
        once."""
        mine = [k for k, (b, _) in enumerate(self.fairleads) if b == body_index]

        def load(body, state, t):
            f, tq = np.zeros(3), np.zeros(3)
            for k in mine:
                x, _ = body_point(body, state, self.fairleads[k][1])
                f = f + self.forces[k]
                tq = tq + cross3(x - state.position, self.forces[k])
            return f, tq

        return load

    # ------------------------------------------------------------ line data
    def line_end_forces(self, line):
        """(F_A, F_B) [N]: the force line `line` (0-based) pulls its end points with, at its anchor end A
        (node 0) and its fairlead end B (node N): each end segment's tension plus what MoorDyn lumps into the
        end node (half a segment's weight and buoyancy, drag, seabed contact). Their magnitudes are the end
        tensions `MooringRecorder` writes."""
        md, ln = self._moordyn, self._lines[line]
        n = int(md.GetLineN(ln))
        return np.array(md.GetLineNodeForce(ln, 0), float), np.array(md.GetLineNodeForce(ln, n), float)

    def line_nodes(self, line):
        """The positions [m] (shoal's frame) of line `line`'s (0-based) N + 1 nodes, (N + 1, 3), from end A
        to end B."""
        md, ln = self._moordyn, self._lines[line]
        return np.array([md.GetLineNodePos(ln, i) for i in range(int(md.GetLineN(ln)) + 1)], float) + self.origin

    # ------------------------------------------------------------ checkpoints
    def checkpoint_state(self):
        """The state a checkpoint keeps, as bytes (an ``.npz`` archive): MoorDyn's serialised system
        (``moordyn.Serialize``) with the fairleads' last positions, velocities and forces."""
        if not self._initialised:
            raise RuntimeError("nothing to checkpoint before Mooring.initialise")
        buf = io.BytesIO()
        blob = self._moordyn.Serialize(self._system)
        np.savez(buf, version=np.int64(_CHECKPOINT_VERSION), positions=self._x, velocities=self._u,
                 forces=self.forces, n_lines=np.int64(self.n_lines),
                 moordyn=np.frombuffer(bytes(blob), dtype=np.uint8))
        return buf.getvalue()

    def restore_state(self, data):
        """Set the state a `checkpoint_state` call returned, in place of `initialise` (or after it): the run
        continues bitwise. The mooring must be built from the same input file.

        Raises
        ------
        shoal.errors.InputError
            `data` is not a mooring checkpoint, or it does not fit this input file.
        """
        try:
            with np.load(io.BytesIO(bytes(data))) as z:
                version, x, u, f = int(z["version"]), z["positions"], z["velocities"], z["forces"]
                n_lines, blob = int(z["n_lines"]), z["moordyn"].tobytes()
        except (OSError, ValueError, KeyError, TypeError, EOFError) as e:
            raise InputError(f"mooring checkpoint: not one of shoal's ({e})") from None
        if version != _CHECKPOINT_VERSION:
            raise InputError(f"mooring checkpoint: version {version}, this shoal reads {_CHECKPOINT_VERSION}")
        if x.shape != (self.n_fairleads, 3) or n_lines != self.n_lines:
            raise InputError(f"mooring checkpoint: {x.shape[0]} fairleads and {n_lines} lines, but "
                             f"{self.input_file} has {self.n_fairleads} and {self.n_lines}")
        md = self._moordyn
        with _captured_console() as console:
            try:
                if not self._initialised:
                    err = md.Init_NoIC(self._system, (x - self.origin).ravel().tolist(), u.ravel().tolist())
                    if err != md.ERRCODE_SUCCESS:
                        raise RuntimeError(f"error {err}")
                md.Deserialize(self._system, blob)
                ok = True
            except RuntimeError:
                ok = False
        if not ok:
            raise InputError(self._refusal("the checkpoint does not fit it", console[0]))
        self._initialised = True
        self._x, self._u, self.forces = np.array(x), np.array(u), np.array(f)

    # ------------------------------------------------------------ closing
    def _discard(self):
        """Close MoorDyn, move its files to `moordyn_dir` (or drop them) and remove the private directory."""
        if self._system is not None:
            with _captured_console():
                self._moordyn.Close(self._system)
            self._system = None
        if self._workdir is None:
            return
        own = self._workdir / self.input_file.name
        for entry in os.scandir(self._workdir):
            p = Path(entry.path)
            if entry.is_symlink() or p == own:
                p.unlink()
            elif self.moordyn_dir is not None and entry.is_file(follow_symlinks=False):
                self.moordyn_dir.mkdir(parents=True, exist_ok=True)
                shutil.move(p, self.moordyn_dir / entry.name)
        shutil.rmtree(self._workdir, ignore_errors=True)
        self._workdir = None

    def close(self):
        """Close MoorDyn (idempotent); its output files go to `moordyn_dir` or are deleted."""
        self._discard()
        self._initialised = False

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()
        return False

    def __del__(self):
        with contextlib.suppress(Exception):
            self.close()


TENSION_HEADER = ["time [s]", "fairlead_tension [N]", "anchor_tension [N]"]
"""The header of a line's tension CSV (`MooringRecorder`)."""


def nodes_header(mooring, line):
    """The header of the node-position CSV of line `line` (0-based) of `mooring`."""
    n_nodes = len(mooring.line_nodes(line))
    return ["time [s]"] + [f"{q}{i} [m]" for i in range(n_nodes) for q in ("x", "y", "z")]


def tension_row(mooring, line, t):
    """A row of line `line`'s tension CSV at time `t` [s]: t, |F_B|, |F_A| (`Mooring.line_end_forces`), as text."""
    fa, fb = mooring.line_end_forces(line)
    return [f"{t:.9g}", f"{np.linalg.norm(fb):.9g}", f"{np.linalg.norm(fa):.9g}"]


def nodes_row(mooring, line, t):
    """A row of line `line`'s node-position CSV at time `t` [s], as text."""
    return [f"{t:.9g}"] + [f"{v:.9g}" for v in mooring.line_nodes(line).ravel()]


class MooringRecorder:
    """CSV files of a `Mooring`'s lines, one row per `record` call.

    For each line k (1-based, MoorDyn's numbering), in `directory`:

    * ``mooring_line<k>.csv``: ``time [s], fairlead_tension [N], anchor_tension [N]``: the magnitudes of
      the line's pull on its end points B (fairlead) and A (anchor) (`Mooring.line_end_forces`);
    * ``mooring_line<k>_nodes.csv``: ``time [s]``, then ``x<i> [m], y<i> [m], z<i> [m]`` of each node i
      from end A (i = 0) to end B (i = N).

    Parameters
    ----------
    mooring : Mooring
    directory : str or path-like
        Created if missing.
    resume_time : float, optional
        Continue files written before a checkpoint at this time [s]: their rows after it are dropped, and
        the next rows are appended. By default the files start anew.
    """

    def __init__(self, mooring, directory, resume_time=None):
        self.mooring = mooring
        self.directory = Path(directory)
        self.directory.mkdir(parents=True, exist_ok=True)
        self.paths, self._files, self._writers = [], [], []
        for k in range(1, mooring.n_lines + 1):
            for path, header in ((self.directory / f"mooring_line{k}.csv", TENSION_HEADER),
                                 (self.directory / f"mooring_line{k}_nodes.csv", nodes_header(mooring, k - 1))):
                self.paths.append(path)
                if resume_time is not None and path.exists():
                    _truncate_after(path, float(resume_time))
                    fh = open(path, "a", newline="")
                else:
                    fh = open(path, "w", newline="")
                    csv.writer(fh).writerow(header)
                self._files.append(fh)
                self._writers.append(csv.writer(fh))

    def record(self, t):
        """Append one row per file: the lines as they are now (after the last `Mooring.loads`, that is at
        its t + dt), at time `t` [s]."""
        for k in range(self.mooring.n_lines):
            self._writers[2 * k].writerow(tension_row(self.mooring, k, t))
            self._writers[2 * k + 1].writerow(nodes_row(self.mooring, k, t))
        for fh in self._files:
            fh.flush()

    def close(self):
        for fh in self._files:
            fh.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()
        return False


def _truncate_after(path, t):
    """Keep the header of the CSV file `path` and its rows up to time `t` (first column) [s]."""
    with open(path, newline="") as fh:
        rows = list(csv.reader(fh))
    t = float(f"{t:.9g}")  # as `MooringRecorder.record` wrote it
    kept = rows[:1] + [r for r in rows[1:] if r and float(r[0]) <= t]
    with open(path, "w", newline="") as fh:
        csv.writer(fh).writerows(kept)
