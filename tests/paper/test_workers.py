"""``reproduce(workers=N)``: any positive count is accepted, and the pool never holds more processes than there
are independent computations (a huge count once crashed the process pool with an OverflowError)."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time

import pytest

from frictionflow.cli._app import sigterm_as_interrupt
from frictionflow.paper import Settings, pipeline
from tests.cli.processes import SRC


class _Sized(Exception):
    """Raised by the stand-in executor with the pool size it was asked for."""


def _record(workers: int):
    raise _Sized(workers)


@pytest.mark.parametrize("workers", [3, 10**20])
def test_the_pool_has_at_most_one_process_per_computation(workers, tmp_path, monkeypatch):
    monkeypatch.setattr(pipeline, "_executor", _record)
    monkeypatch.setattr(pipeline, "_warm_up", lambda settings: None)
    jobs = len(pipeline.compute_jobs(Settings.quick()))
    with pytest.raises(_Sized) as sized:
        pipeline.reproduce(tmp_path / "out", Settings.quick(), workers=workers)
    assert sized.value.args[0] == min(workers, jobs)
    assert 1 < jobs < 10**3


def test_a_killed_worker_ends_reproduce_in_one_line_with_exit_1(tmp_path):
    """SIGKILL one pool process mid-run: one ``error:`` line, exit 1 (the documented code), no traceback."""
    psutil = pytest.importorskip("psutil")
    run = subprocess.Popen([sys.executable, "-m", "frictionflow", "reproduce", "--quick", "--workers", "2",
                            "--out", str(tmp_path / "out")], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                           env=dict(os.environ, PYTHONPATH=os.pathsep.join(filter(None, [SRC, os.environ.get("PYTHONPATH")]))))
    parent, deadline, killed = psutil.Process(run.pid), time.monotonic() + 120, False
    while not killed and run.poll() is None and time.monotonic() < deadline:
        # the pool's processes are forked: their command line is the parent's (a compiling helper's is not)
        workers = [c for c in parent.children() if c.cmdline() == parent.cmdline()]
        if workers:
            time.sleep(0.5)
            workers[0].send_signal(signal.SIGKILL)
            killed = True
        time.sleep(0.05)
    out, err = run.communicate(timeout=300)
    if not killed:
        pytest.skip("the run ended before a pool process was seen")
    lines = err.strip().splitlines()
    assert run.returncode == 1 and len(lines) == 1 and lines[0].startswith("error: "), err
    assert "Traceback" not in err and out == ""


def _takes_sigterm_by_default() -> bool:
    return signal.getsignal(signal.SIGTERM) == signal.SIG_DFL


def test_a_pool_process_takes_sigterm_by_its_default_action():
    """A forked pool process inherited the command's SIGTERM handler (SIGTERM as Ctrl-C): when one worker was killed
    and the pool terminated the others, the handler raised KeyboardInterrupt inside them, and their tracebacks joined
    the one error line on the shared stderr (the killed-worker test above failed so, now and then)."""
    with sigterm_as_interrupt():
        assert signal.getsignal(signal.SIGTERM) != signal.SIG_DFL
        pool = pipeline._executor(2)
        try:
            assert pool.submit(_takes_sigterm_by_default).result(timeout=60)
        finally:
            pool.shutdown()
