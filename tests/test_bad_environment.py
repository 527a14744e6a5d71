"""The environment and the terminal a command meets (issue 30, class 6): Numba settings it cannot start
with, and a reader that stops reading.

Numba reads its variables when ``import shoal`` first imports it: a thread count of 0 ended that import in
a traceback from inside Numba, an unreadable count was dropped with a warning, ``NUMBA_DISABLE_JIT`` left
the kernels uncompiled (a traceback at the first call). Each is now one line and exit 2 from ``shoal``, an
`InputError` from ``import shoal``. ``shoal cases | head -1`` printed a traceback for the broken pipe; it
now ends quietly, as a writer killed by SIGPIPE does (status 141).
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

SRC = Path(__file__).resolve().parents[1] / "src"


def _env(**extra):
    env = {k: v for k, v in os.environ.items() if not k.startswith("NUMBA_")}
    env.update(PYTHONPATH=str(SRC), **extra)
    return env


@pytest.mark.parametrize("name,value,fragment", [
    ("NUMBA_NUM_THREADS", "0", "give a whole number of threads >= 1"),
    ("NUMBA_NUM_THREADS", "-3", "give a whole number of threads >= 1"),
    ("NUMBA_NUM_THREADS", "two", "NUMBA_NUM_THREADS = 'two'"),
    ("NUMBA_THREADING_LAYER", "bogus", "allowed: default, safe, forksafe"),
    ("NUMBA_DISABLE_JIT", "1", "run only compiled"),
])
def test_a_numba_setting_shoal_cannot_run_with_is_one_line(name, value, fragment, tmp_path):
    out = subprocess.run([sys.executable, "-m", "shoal", "check", "still-water-2d"], capture_output=True, text=True,
                         env=_env(**{name: value}), cwd=tmp_path, timeout=300)
    assert out.returncode == 2, out
    assert "Traceback" not in out.stderr and "Warning" not in out.stderr, out.stderr
    lines = out.stderr.splitlines()
    assert len(lines) == 1 and lines[0].startswith("shoal: error: ") and fragment in lines[0], out.stderr
    assert not out.stdout and not list(tmp_path.iterdir())
    # in Python, the same line as an InputError from the import
    code = "import shoal"
    py = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=_env(**{name: value}),
                        timeout=300)
    assert py.returncode == 1 and py.stderr.splitlines()[-1].startswith("shoal.errors.InputError: ")
    assert fragment in py.stderr.splitlines()[-1]


def test_a_reader_that_stops_reading_ends_the_command_quietly():
    """``shoal cases | head -0``: the reader has gone before the list is written (its end of the pipe is
    closed at once; the command takes a second to start), so every write meets a broken pipe: no traceback,
    nothing on stderr, status 141."""
    p = subprocess.Popen([sys.executable, "-m", "shoal", "cases"], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                         env=_env())
    p.stdout.close()
    err = p.stderr.read().decode()
    rc = p.wait(timeout=300)
    assert rc == 141 and err == "", (rc, err)


def test_ctrl_c_while_the_command_starts_is_one_line():
    """Ctrl-C while ``shoal`` is still importing NumPy, SciPy and Numba (it takes a second or more; the
    signal comes 0.3 s after the start): one line, status 130, no traceback, nothing written."""
    import signal
    import time

    p = subprocess.Popen([sys.executable, "-m", "shoal", "cases"], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                         env=_env())
    time.sleep(0.3)
    p.send_signal(signal.SIGINT)
    out, err = p.communicate(timeout=300)
    assert p.returncode == 130, (p.returncode, out, err)
    assert err.decode() == "shoal: interrupted while starting; nothing was written\n" and out == b""
