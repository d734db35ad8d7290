"""Ctrl-C or SIGTERM during any command: exit code 1 and one ``error:`` line (the README's exit codes).

typer ends a command interrupted by Ctrl-C with code 130 and prints nothing, and ``frictionflow.cli.main`` passed
that on as 0 (a script took the interrupted run for a success); SIGTERM killed every command but the sweeps
silently with 143.
"""

from __future__ import annotations

import ctypes
import ctypes.util
import importlib
import importlib.metadata
import os
import signal
import subprocess
import sys
import time
import tomllib
from pathlib import Path

import pytest
import typer
import typer.main

import frictionflow.cli as frictionflow_cli
from frictionflow.cli import simulate as simulate_cli, sweep as sweep_cli
from frictionflow.cli._app import INTERRUPTED, Interrupted, PanelledCommand, sigterm_as_interrupt

from .processes import SRC, default_signals, in_process, one_line

SIMULATE = ("simulate", "--friction", "coulomb", "--fd", "0.02", "--fs", "0.04", "--zeta", "0.05", "--t-end", "50")


def _interrupt_by(how: str):
    def stop(*args, **kwargs):
        if how == "sigterm":
            signal.raise_signal(signal.SIGTERM)  # the handler the command installed turns it into Ctrl-C
        raise KeyboardInterrupt
    return stop


@pytest.mark.parametrize("how", ["ctrl-c", "sigterm"])
def test_an_interrupted_simulate_exits_1_with_one_line_and_prints_no_result(monkeypatch, how):
    before = signal.getsignal(signal.SIGTERM)
    monkeypatch.setattr(simulate_cli, "run_simulation", _interrupt_by(how))
    code, out, err, _ = in_process(*SIMULATE, "--json")
    assert code == 1 and out == ""
    one_line(err, "interrupted (Ctrl-C or SIGTERM)")
    assert signal.getsignal(signal.SIGTERM) == before  # restored once the command ends


def test_an_interrupted_sweep_says_what_its_store_keeps(monkeypatch, tmp_path):
    config = tmp_path / "s.toml"
    config.write_text('friction = "coulomb"\nfd = 0.02\nfs = 0.04\nt_end = 50.0\n[grid]\nvb = [0.01, 0.02]\n')
    interrupt = _interrupt_by("ctrl-c")

    def stop(*args, **kwargs):  # once the store exists (before it, the line names no store)
        (tmp_path / "r.zarr").mkdir()
        interrupt()

    monkeypatch.setattr(sweep_cli, "run_sweep", stop)
    code, out, err, _ = in_process("sweep", str(config), "--out", str(tmp_path / "r.zarr"))
    assert code == 1 and out == ""
    one_line(err, "interrupted:", "r.zarr keeps the chunks finished so far; run the same command to resume")


@pytest.mark.skipif(sys.platform == "win32", reason="POSIX signals")
@pytest.mark.parametrize("sig", [signal.SIGINT, signal.SIGTERM])
def test_a_signal_to_a_running_command_ends_it_with_exit_code_1(sig):
    """A real signal to a long fixed-step run, once the command has started (its first words on stderr: the
    coarse-step warning)."""
    env = dict(os.environ, PYTHONPATH=str(SRC))
    argv = [sys.executable, "-m", "frictionflow", "simulate", "--solver", "rk4", "--dt", "0.002", "--friction",
            "karnopp", "--fd", "0.02", "--t-end", "1e5", "--json"]
    p = subprocess.Popen(argv, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env,
                         preexec_fn=default_signals)
    first = p.stderr.readline()  # the run has begun: the warning is written just before it
    assert "warning" in first, first
    time.sleep(0.5)
    p.send_signal(sig)
    out, err = p.communicate(timeout=120)
    assert p.returncode == 1 and out == ""
    one_line(err, "interrupted (Ctrl-C or SIGTERM)")


def drop_an_interrupt() -> None:
    """A KeyboardInterrupt raised in Python code that C calls back, as a signal landing in llvmlite's hooks while
    numba loads kernels raises it: libc's qsort calls back a comparator that raises, and the caller drops it."""
    compare = ctypes.CFUNCTYPE(ctypes.c_int, ctypes.POINTER(ctypes.c_int), ctypes.POINTER(ctypes.c_int))

    def interrupted(a, b):
        raise KeyboardInterrupt

    libc = ctypes.CDLL(ctypes.util.find_library("c"))
    values = (ctypes.c_int * 3)(3, 2, 1)
    libc.qsort(values, 3, ctypes.sizeof(ctypes.c_int), compare(interrupted))


def test_an_interrupt_dropped_in_a_callback_from_c_is_raised_again():
    """The caller of the callback prints the KeyboardInterrupt and drops it, and the command ran on to exit 0 with
    its output."""
    dropped = []
    hook = sys.unraisablehook
    sys.unraisablehook = lambda args: dropped.append(args.exc_type)  # the context keeps it as the one to pass on
    try:
        with pytest.raises(KeyboardInterrupt):
            with sigterm_as_interrupt():
                drop_an_interrupt()
                time.sleep(5.0)  # the command's further work: the interrupt ends it
    finally:
        sys.unraisablehook = hook
    assert dropped == [] and sys.unraisablehook is hook


@pytest.mark.skipif(sys.platform == "win32", reason="POSIX signals")
@pytest.mark.parametrize("failure, says", [
    (RuntimeError("no compiled object yet for <Library '_sample'>"), INTERRUPTED),  # what numba raised next
    (Interrupted("interrupted: r.zarr keeps the chunks finished so far"), "r.zarr keeps"),  # a sweep's own words
])
def test_a_failure_after_a_dropped_interrupt_is_the_interrupt_and_nothing_follows_it(failure, says):
    """A SIGTERM dropped in numba's object-cache hook left the kernel without its compiled object: numba raised
    "no compiled object yet for <Library '_sample'>", the command printed that as its error, and the interrupt
    raised again then reached the handler outside the command, which wrote a second line (found by signalling
    a first run on an empty cache 12 s after its start, under load).  The command now ends as interrupted
    (keeping a command's own words for it), and the interrupt on its way is taken inside it: the handler in place
    afterwards sees no signal."""
    app = typer.Typer()

    @app.command(cls=PanelledCommand)
    def fail() -> None:
        drop_an_interrupt()
        raise failure

    after: list[int] = []
    previous = signal.signal(signal.SIGTERM, lambda signum, frame: after.append(signum))
    try:
        with pytest.raises(Interrupted) as raised:
            typer.main.get_command(app).main(args=[], standalone_mode=False)
        time.sleep(0.5)  # time for a signal still on its way
    finally:
        signal.signal(signal.SIGTERM, previous)
    assert says in str(raised.value) and after == []


def test_an_interrupt_caught_after_it_left_generated_code_exits_1(tmp_path):
    """CPython marks a KeyboardInterrupt that leaves an exec() of a string as unhandled even once caught, and
    then ends ``python -m`` by SIGINT (130) whatever its exit code: under load a signal landed in numba's
    generated code and ``simulate`` printed its one line and ended with -2 instead of 1."""
    (tmp_path / "entry.py").write_text(
        "import frictionflow.cli as cli\n"
        "def main():\n"
        "    try:\n"
        "        exec('raise KeyboardInterrupt')\n"
        "    except KeyboardInterrupt:\n"
        "        return 1\n"
        "cli.main = main\n"
        "cli.run()\n")
    env = dict(os.environ, PYTHONPATH=os.pathsep.join([str(SRC), str(tmp_path)]))
    done = subprocess.run([sys.executable, "-m", "entry"], env=env, capture_output=True, text=True, timeout=120)
    assert done.returncode == 1, done.stderr


@pytest.mark.skipif(sys.platform == "win32", reason="POSIX signals")
@pytest.mark.parametrize("sig", [signal.SIGINT, signal.SIGTERM])
def test_a_signal_at_any_moment_of_the_start_ends_in_one_line(sig):
    """Before, a Ctrl-C in the first second (the package loading, a command's modules, its options read) printed
    a 20-40 line traceback (exit by SIGINT) or ended with exit code 0 and no output (typer returned its 130 for
    an interrupt outside the command's run, and it was dropped); SIGTERM then ended the process with no word.
    The console script (``_frictionflow_launch``, outside the package) holds both signals while the package
    loads.  Signals sent from 0.1 s to 2 s after the start of a run that would take minutes: each ends with exit
    code 1 and the one line."""
    env = dict(os.environ, PYTHONPATH=str(SRC))
    # the child says when the interpreter's own start-up (site) is over: a signal before it is no program's.  Its
    # run is 1e10 RK4 steps (minutes, 5e5 samples, no warning): the default solver settles ``--t-end 1e7`` in 3
    # switches, and a warm run ended before a signal sent at 2 s (exit 0, its result on stdout)
    command = ['simulate', '--solver', 'rk4', '--dt', '1e-5', '--t-end', '1e5', '--record-every', '100000', '--json']
    start = (f"import runpy, sys; sys.argv[1:] = {command!r}; print('started', "
             "file=sys.stderr, flush=True); runpy.run_module('_frictionflow_launch', run_name='__main__')")
    for delay in (0.1, 0.4, 0.7, 1.0, 1.5, 2.0):  # (runpy reads the launcher in the first ms)
        p = subprocess.Popen([sys.executable, "-c", start], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                             text=True, env=env, preexec_fn=default_signals)
        assert p.stderr.readline() == "started\n"
        time.sleep(delay)
        assert p.poll() is None, (delay, "the run ended before the signal", p.communicate())
        p.send_signal(sig)
        out, err = p.communicate(timeout=120)
        assert p.returncode == 1 and out == "", (delay, p.returncode, err)
        one_line(err, "interrupted (Ctrl-C or SIGTERM)")


def test_the_console_script_is_the_launcher():
    """The installed ``frictionflow`` command starts in the module that holds the signals, not in the package."""
    with open(Path(__file__).resolve().parents[2] / "pyproject.toml", "rb") as f:
        scripts = tomllib.load(f)["project"]["scripts"]
    assert scripts == {"frictionflow": "_frictionflow_launch:run"}
    installed = importlib.metadata.entry_points(group="console_scripts", name="frictionflow")
    assert [e.value for e in installed] == ["_frictionflow_launch:run"]  # what pip made of it
    launcher = importlib.import_module("_frictionflow_launch")
    assert launcher.run is frictionflow_cli.run
