"""`shoal check` reports what a checkpoint will take on disk.

The estimate (`shoal.simulation.checkpoint.checkpoint_bytes`) is compared
with checkpoint files actually written (`capture` + `write_checkpoint` of a
freshly built model, which is what the run writes, minus the probes'
records) for 2D and 3D, every integrator, both precisions, moving bodies
and the per-particle arrays that only some options allocate (XSPH, SPS
stress, no-slip wall velocity). No time step is taken, so nothing is
compiled.
"""

from __future__ import annotations

import re

import numpy as np
import pytest

from shoal.casefile import dumps_case
from shoal.cases import get_case
from shoal.cli import main
from shoal.runner import build_model
from shoal.simulation import Simulation
from shoal.simulation.checkpoint import CHECKPOINT_OVERHEAD, capture, checkpoint_bytes, write_checkpoint

CONFIGS = {
    "2d-symplectic-float32": ("still-water-2d", dict(dp=0.05), {}),
    "3d-verlet-float32": ("dam-break-3d", dict(dp=0.0365), dict(integrator="verlet")),
    "2d-moving-float64": ("wave-flume-2d", dict(dp=0.04), dict(precision="float64")),
    "2d-pc-xsph-sps-noslip": ("tidal-bore", dict(dp=0.02, dim=2), dict(no_slip=True)),
    "3d-symplectic-float64-xsph": ("still-water-3d", dict(dp=0.05), dict(precision="float64", xsph=0.5)),
}


def _case(name):
    base, kwargs, options = CONFIGS[name]
    case = get_case(base, **kwargs)
    return case.with_options(**options) if options else case


@pytest.mark.parametrize("name", list(CONFIGS))
def test_checkpoint_size_estimate_matches_a_written_checkpoint(name, tmp_path, shared_backends):
    case = _case(name)
    model = build_model(case)
    sim = Simulation(model, case.end_time)  # allocates the integrator's arrays
    path = tmp_path / "ckpt_000000.h5"
    toml = dumps_case(case, file_name="case.toml")
    write_checkpoint(path, capture(sim, toml))
    size = path.stat().st_size
    moving = bool(np.any(case.particles().kinds == 2))
    est = checkpoint_bytes(model.n_total, case.dim, case.options, moving, case_bytes=len(toml.encode()))
    print(f"\n{name}: {model.n_total} particles, written {size} B, estimated {est} B "
          f"({(est - CHECKPOINT_OVERHEAD - len(toml)) / model.n_total:.1f} B/particle)")
    assert abs(est - size) <= 0.002 * size + 2048, (est, size)


def test_3d_verlet_float32_is_85_bytes_a_particle():
    """The figure the README gave (86 B/particle measured with the file's overhead; now in
    benchmarks/results/notes/README.md, Checkpoints and restart)."""
    case = _case("3d-verlet-float32")
    per = (checkpoint_bytes(10**6, 3, case.options, case_bytes=0) - CHECKPOINT_OVERHEAD) / 10**6
    assert per == 85


def test_shoal_check_reports_the_checkpoint_size(capsys):
    assert main(["check", "dam-break-3d", "--dp", "0.0365", "--integrator", "verlet"]) == 0
    out = capsys.readouterr().out
    line = next(line for line in out.splitlines() if line.strip().startswith("checkpoints:"))
    print("\n" + line)
    case = _case("3d-verlet-float32")
    n = case.n_particles
    mib = checkpoint_bytes(n, 3, case.options, case_bytes=len(dumps_case(case, file_name="case.toml"))) / 2**20
    m = re.match(r"\s*checkpoints: ([0-9.]+) MiB each \((\d+) B/particle\), every 900 s of wall-clock time, "
                 r"at the end; the newest 2 kept: up to ([0-9.]+) MiB", line)
    assert m, line
    assert float(m.group(1)) == pytest.approx(mib, rel=5e-3)
    assert int(m.group(2)) == 85
    assert float(m.group(3)) == pytest.approx(2 * mib, rel=5e-3)


def test_shoal_check_counts_the_probe_records_in_the_checkpoints(tmp_path, capsys):
    """A test-point grid keeps every sample (for its NetCDF file) and each checkpoint holds them: the check
    line gives the size the checkpoints grow to by the end of the run."""
    text = dumps_case(get_case("still-water-2d", dp=0.05, end_time=10.0), commented=False).replace("probes = []\n", "")
    text += ('\n[[probes]]\ntype = "grid"\nname = "g"\nlo = [0.1, 0.0, 0.05]\nhi = [0.9, 0.0, 0.45]\n'
             'counts = [50, 1, 40]\ninterval = 0.01\n')
    (tmp_path / "case.toml").write_text(text)
    assert main(["check", str(tmp_path / "case.toml"), "--end-time", "10"]) == 0
    out = capsys.readouterr().out
    line = next(line for line in out.splitlines() if line.strip().startswith("checkpoints:"))
    print("\n" + line)
    samples = 1001
    records = 6 * 50 * 40 * samples  # u, v, w, p, rho, kernel sum per node and sample, float64 in the checkpoint
    m = re.search(r"; ([0-9.]+) MiB by the end with the probes' records\)", line)
    assert m, line
    assert float(m.group(1)) == pytest.approx(8 * records / 2**20, rel=0.01)
