"""The ``frictionflow`` console script: a Ctrl-C or SIGTERM while the package loads ends in one line, exit 1.

Importing :mod:`frictionflow` takes most of a second (numpy, numba, the
kernels' registries), and the command line's own handling of an interrupt
(``frictionflow.cli``: one ``error:`` line, exit code 1) exists only once it is
loaded: a Ctrl-C in that second printed a traceback of the import, and a
SIGTERM ended the process with no word.  This module sits outside the package
so that it runs before any of it and holds both signals while the package
loads.  Ctrl-C is given back before the command line starts (it raises the
KeyboardInterrupt the commands handle: ``frictionflow.cli.main`` while a
command's modules load, the command itself while it runs); SIGTERM stays
here until a command maps it to Ctrl-C for its run, and returns here after.
A signal the caller ignores (a shell's background job) stays ignored.
"""

from __future__ import annotations

import os
import signal
import sys

#: the command line's own line for an interrupted command (``frictionflow.cli._app.PanelledCommand``)
INTERRUPTED = "error: interrupted (Ctrl-C or SIGTERM)"
SIGNALS = (signal.SIGINT, signal.SIGTERM)


def _interrupted(signum: int, frame: object) -> None:
    """End at once: nothing has run or been written yet."""
    sys.stderr.write(INTERRUPTED + "\n")
    sys.stderr.flush()
    os._exit(1)


_held = {sig: signal.getsignal(sig) for sig in SIGNALS}
for _sig, _previous in _held.items():
    if _previous is not signal.SIG_IGN:
        signal.signal(_sig, _interrupted)

from frictionflow.cli import run  # noqa: E402  (the slow import the handlers above cover)

signal.signal(signal.SIGINT, _held[signal.SIGINT])

__all__ = ["run"]

if __name__ == "__main__":
    run()
