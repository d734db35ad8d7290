"""The command line in its own process, for tests of what a user sees: exit code, stdout, stderr, time.

:func:`in_process` runs the same entry point in the test's process: the kernels compiled there are reused, with no
interpreter start-up. Tests of a command's results and of its one-line refusals use it; tests whose claim is about the
process itself (a signal, the interpreter's exit, time to refuse) keep :func:`cli`.
"""

from __future__ import annotations

import contextlib
import io
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import frictionflow
from frictionflow.cli import main

#: the source tree under test, put first on the child's path (the installed package may be another tree)
SRC = str(Path(frictionflow.__file__).resolve().parents[1])


def default_signals() -> None:
    """A child's ``preexec_fn``: Ctrl-C and SIGTERM with their default actions, as a terminal starts a command.  A
    test worker may ignore either (and an ignored signal stays ignored across exec: the launcher then keeps it so,
    as a shell's background job does), so a test that signals its child sets them first."""
    for sig in (signal.SIGINT, signal.SIGTERM):
        signal.signal(sig, signal.SIG_DFL)


def cli(*argv: str, cwd: Path | None = None, timeout: float = 300) -> tuple[int, str, str, float]:
    """``python -m frictionflow ARGV`` in its own process, on this tree: (exit code, stdout, stderr, seconds)."""
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(filter(None, [SRC, os.environ.get("PYTHONPATH")])))
    t0 = time.monotonic()
    done = subprocess.run([sys.executable, "-m", "frictionflow", *argv], capture_output=True, text=True, env=env,
                          cwd=cwd, timeout=timeout, check=False)
    return done.returncode, done.stdout, done.stderr, time.monotonic() - t0


def in_process(*argv: str, cwd: Path | None = None) -> tuple[int, str, str, float]:
    """:func:`cli`'s ``(exit code, stdout, stderr, seconds)`` from ``frictionflow.cli.main(ARGV)`` in this process."""
    out, err = io.StringIO(), io.StringIO()
    here = os.getcwd()
    t0 = time.monotonic()
    try:
        if cwd is not None:
            os.chdir(cwd)
        with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
            code = main(list(argv))
    finally:
        os.chdir(here)
    return code, out.getvalue(), err.getvalue(), time.monotonic() - t0


def one_line(err: str, *words: str) -> str:
    """The single ``error:`` line of ``err``, holding ``words``; no traceback, no ignored exception."""
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: "), err
    assert all(w in lines[0] for w in words), err
    return lines[0]
