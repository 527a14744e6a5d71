"""The files a run writes in its directory, by name.

A new run starts only in an empty or new directory or in one of shoal's own runs (``resolved.json``):
`foreign_clash` finds a file of the user's that a run would replace. ``--overwrite`` then removes the
earlier run's files -- and only those -- before the new run writes its own (`clear_run`), so no snapshot
or probe record of the earlier run is left to be read as the new one's.
"""

from __future__ import annotations

import re
import shutil
import tomllib
from pathlib import Path

from ..errors import InputError
from ..faults import reached

_FIXED = ("case.toml", "resolved.json", "run.log")
_PATTERN = re.compile(r"^(escaped(\.rank\d+)?\.csv|(gauge|probe|track|force|maxz|runup|flow|pressure)_[A-Za-z0-9_.\-]+"
                      r"\.csv(\.resume)?|testpoints_[A-Za-z0-9_.\-]+\.nc|ckpt_\d+\.(h5|mpi\.json|rank\d+\.h5)"
                      r"(\.tmp|\.bad)?)$")


def _snapshot_pattern(name):
    """The snapshot files of a run named `name`: ``name_NNNN.vtu`` / ``.pvtu`` (and the folder of an MPI
    snapshot's pieces), ``name.pvd``, ``name_final.png``, ``name_unstable.vtu``."""
    return re.compile(rf"^{re.escape(name)}(_\d+\.(vtu|pvtu)|_\d+|\.pvd|_final\.png|_unstable\.vtu)$")


def run_files(out_dir, names):
    """shoal's own files in `out_dir` for runs named `names` (sorted paths; none when it is no directory)."""
    out_dir = Path(out_dir)
    if not out_dir.is_dir():
        return []
    snaps = [_snapshot_pattern(n) for n in names]
    return sorted(p for p in out_dir.iterdir()
                  if p.name in _FIXED or _PATTERN.match(p.name) or any(s.match(p.name) for s in snaps))


def earlier_name(out_dir):
    """The case name of the run in `out_dir` (its ``case.toml``), or None."""
    try:
        return tomllib.loads((Path(out_dir) / "case.toml").read_text(encoding="utf-8")).get("name")
    except (OSError, ValueError, UnicodeDecodeError):
        return None


def foreign_clash(out_dir, case):
    """The first file of `out_dir` that a new run of `case` would write over although no shoal run made it
    (the directory holds no ``resolved.json``), or None."""
    out_dir = Path(out_dir)
    if (out_dir / "resolved.json").exists():
        return None
    found = run_files(out_dir, [case.name])
    return found[0] if found else None


def refuse_foreign_files(out_dir, case):
    """Raise `InputError` when a new run of `case` in `out_dir` would replace a file no shoal run made."""
    clash = foreign_clash(out_dir, case)
    if clash is not None:
        raise InputError(f"{out_dir} holds {clash.name}, which no shoal run wrote (there is no resolved.json): a "
                         "run there would replace it; choose another --out directory")


def dangling_link(out_dir):
    """`InputError` text when `out_dir` is a symbolic link that leads to no folder (a missing target or a
    loop of links), else None: creating the folder there fails with a bare "File exists"."""
    out_dir = Path(out_dir)
    if out_dir.is_symlink() and not out_dir.is_dir():
        return (f"the output directory {out_dir} is a symbolic link that leads to no folder (a missing target or "
                "a loop of links); choose another --out directory")
    return None


def clear_run(out_dir, case):
    """Remove the earlier run's files from `out_dir` (those of its case name and of `case`'s), before a new
    run of `case` starts there (``--overwrite``)."""
    names = {case.name}
    old = earlier_name(out_dir)
    if isinstance(old, str):
        names.add(old)
    # resolved.json last: while it is there the directory is known as a shoal run, so one killed in the middle
    # of this clearing is cleared by the next --overwrite, not refused as someone else's (`foreign_clash`)
    for p in sorted(run_files(out_dir, sorted(names)), key=lambda p: p.name == "resolved.json"):
        reached(f"remove:{p.name}")  # a test hook (shoal.faults)
        if p.is_dir() and not p.is_symlink():
            shutil.rmtree(p)
        else:
            p.unlink()
