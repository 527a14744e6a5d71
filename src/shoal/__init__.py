"""shoal: weakly-compressible SPH for free-surface coastal and hydraulic flows.

The public API:

* `Case` (with `Domain`, `Fluid`, `Solid`, `FluidRegion`, `SymmetryPlane`,
  `Output`), the shapes of `shoal.geometry`, the motions of `shoal.motions`,
  the built-in cases in `shoal.cases`, and TOML case files (`load_case`,
  `write_case`);
* `SPHOptions` (kernel, viscosity, density diffusion, filters, integrator);
* `Model` (particles + scheme + backend) and `Simulation` (time loop with
  scheduled callbacks: `TimeInterval`, `IterationInterval`, `WallTimeInterval`);
* `run_case`, which runs a case end to end and writes VTU snapshots and
  checkpoints, and `resume_run`, which continues one from its last checkpoint;
* errors `InputError` and `InstabilityError`.
"""

import os as _os

# GNU OpenMP (Numba's usual threading layer on Linux) spins 300k iterations
# after each parallel loop; with ~20 parallel loops per step, a shoal run that
# shares its cores with another process became ~100x slower (measured). A
# short spin keeps idle-machine speed and removes that collapse.
_os.environ.setdefault("GOMP_SPINCOUNT", "3000")

import sys as _sys  # noqa: E402

from .environment import interrupted_while_starting as _interrupted_while_starting  # noqa: E402
from .environment import numba_environment_error as _numba_environment_error  # noqa: E402
from .environment import on_command_line as _on_command_line  # noqa: E402

# `shoal.cli.main` puts Python's own SIGINT handler back before it does anything
if _on_command_line(_sys.argv):
    import signal as _signal

    _signal.signal(_signal.SIGINT, _interrupted_while_starting)

# Numba reads its variables on import (below): a setting it cannot start with is one line, not a traceback
# from inside Numba -- on the command line (`shoal`, `python -m shoal`) an exit with status 2, in Python an
# InputError from `import shoal`.
_bad = _numba_environment_error(_os.environ)
if _bad:
    from .errors import InputError as _InputError

    if _on_command_line(_sys.argv):
        _sys.stderr.write(f"shoal: error: {_bad}\n")
        raise SystemExit(2)
    raise _InputError(_bad)

from .cpu_features import install as _install_cpu_features  # noqa: E402

# 512-bit vectors where the CPU has AVX-512, before Numba compiles anything (shoal.cpu_features)
_install_cpu_features()

import numpy as _np  # noqa: E402

# numba-cuda (0.30.4 and earlier) registers an overload of numpy.row_stack when
# numba.cuda is first imported; NumPy 2.5 removed row_stack (deprecated in 2.0
# as an alias of vstack), so `from numba import cuda` fails there with an
# AttributeError (seen on a GPU machine with NumPy 2.5.2). Restore the alias.
if not hasattr(_np, "row_stack"):
    _np.row_stack = _np.vstack

from .cache_lock import install as _install_cache_lock  # noqa: E402

# Processes that share Numba's on-disk cache (MPI ranks, sweeps, test workers)
# must not interleave their writes of one cache index (shoal.cache_lock).
_install_cache_lock()

from . import cases, geometry, motions  # noqa: E402
from .version import __version__  # noqa: E402
from .case import Case, Domain, Fluid, FluidRegion, Output, Solid, SymmetryPlane  # noqa: E402
from .casefile import load_case, write_case  # noqa: E402
from .errors import InputError, InstabilityError, ShoalError  # noqa: E402
from .model import Model  # noqa: E402
from .options import SPHOptions  # noqa: E402
from .runner import RunResult, resume_run, run_case  # noqa: E402
from .simulation import IterationInterval, Simulation, TimeInterval, WallTimeInterval  # noqa: E402

__all__ = ["Case", "Domain", "Fluid", "FluidRegion", "Output", "Solid", "SymmetryPlane", "load_case", "write_case",
           "geometry", "motions", "SPHOptions", "Model", "Simulation", "TimeInterval", "IterationInterval",
           "WallTimeInterval", "run_case", "resume_run", "RunResult", "cases", "InputError", "InstabilityError",
           "ShoalError", "__version__"]
