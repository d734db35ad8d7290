"""A compiled call that Ctrl-C and SIGTERM can interrupt: run on a thread of its own while the caller waits.

A compiled kernel never returns to Python before its end, and Python handles
a signal only between its own bytecodes, so an interrupt waited for a long
run.  :func:`interruptible` runs the call on a daemon thread (the kernels
release the GIL) and raises the interrupt in the waiting thread at once.  The
abandoned call goes on: :func:`abandoned` says so, and the interpreter's exit
waits for it (finalising under a running kernel crashed the process), while
the CLI ends at once (``frictionflow.cli.run``).
"""

from __future__ import annotations

import atexit
import threading
from typing import Any, Callable, TypeVar

T = TypeVar("T")
#: seconds between the waiting thread's checks for a signal
POLL = 0.05
#: the name of a run's thread (:func:`interruptible`)
RUN_THREAD = "frictionflow-run"
#: one event per call at work, set when it returns (not the thread's liveness: an interrupted ``join`` marks
#: the thread stopped while it runs on, CPython's bpo-45274)
_RUNNING: set[threading.Event] = set()


def interruptible(call: Callable[[], T]) -> T:
    """``call()`` on a daemon thread while this one waits: the structure kernels release the GIL (``nogil``), so
    this thread's signal handlers run at once and a KeyboardInterrupt (Ctrl-C, or SIGTERM as the CLI maps it)
    is raised here.  The abandoned run goes on until its end; ``call``'s own exception is raised here as it was
    raised there."""
    box: dict[str, Any] = {}
    done = threading.Event()

    def target() -> None:
        try:
            box["value"] = call()
        except BaseException as exc:  # noqa: BLE001 - handed to the waiting thread, which raises it
            box["error"] = exc
        finally:
            _RUNNING.discard(done)
            done.set()

    _RUNNING.add(done)
    threading.Thread(target=target, name=RUN_THREAD, daemon=True).start()
    while not done.wait(POLL):
        pass
    if "error" in box:
        raise box["error"]
    return box["value"]


def abandoned() -> bool:
    """Whether a call an interrupt left behind (:func:`interruptible`) is still at work."""
    return bool(_RUNNING)


@atexit.register
def _finish_abandoned() -> None:
    """At the interpreter's exit, wait for the calls an interrupt left behind: finalisation tears down what a
    compiled run still uses, and about one exit in ten crashed (SIGSEGV).  The CLI ends at once instead
    (``frictionflow.cli.run``: nothing of the process is needed after its last line)."""
    for done in list(_RUNNING):
        done.wait()
