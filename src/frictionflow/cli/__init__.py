"""The ``frictionflow`` command: a thin layer over the Python API.

A failure prints one line ``error: ...`` on stderr (not a traceback) and
exits with one of the codes of :data:`EXIT_CODES` (the README's table):
0 done; 1 a failure that is not the command line's fault (a full disk, an
I/O error, a scheduler that does not answer, a lost Dask worker, an output in
use by another run, a damaged output found by ``--verify``, an interruption,
a run that could not finish), after which the same command succeeds once the
cause is gone -- a sweep's store resumes; 2 bad input (values, options,
configs, and paths that cannot be written: a missing or read-only directory,
a directory in the way), refused before anything is computed or written.
"""

from __future__ import annotations

import importlib
import os
import signal
import sys
import warnings

import typer

from .._interrupt import abandoned
from ..io import PATH_ERRNOS
from ._app import INTERRUPTED, Interrupted, PanelledCommand, app
from .vocabulary import rewrite

#: what typer's ``main`` returns, without a word, for a KeyboardInterrupt outside a command's run (in the run,
#: ``PanelledCommand`` raises :class:`~frictionflow.cli._app.Interrupted` first)
TYPER_INTERRUPTED = 130
#: the exit codes of every command (documented in the README's "Exit codes")
EXIT_CODES = {0: "done", 1: "failed, not for the command line's fault: run it again once the cause is gone", 2: "bad input"}

#: the module that registers each command, imported when the command runs (all of them for the command
#: list): a command pays only for what it uses (``simulate`` does not load scipy.optimize or xarray).
#: A plugin table, not a hidden import: the layer test reads it as the CLI's import edges.
COMMAND_MODULES = {
    "simulate": "simulate",
    "reproduce": "reproduce",
    "sweep": "sweep",
    "orbit": "orbit",
    "continue": "orbit",
    "basins": "basins",
    "response": "response",
    "lyapunov": "lyapunov",
    "forced-orbit": "forced_orbit",
    "forced-continue": "forced_orbit",
    "map": "map",
    "stability": "stability",
}

#: one line per command for the command list (click would cut the docstring at its first period)
SHORT_HELP = {
    "simulate": "Simulate one run: steady state, power flow and TR_B.",
    "reproduce": "Reproduce Figs. 2-6 of the paper, with a report.",
    "sweep": "Sweep parameters over a grid (resumable, local or Dask).",
    "orbit": "Find a periodic orbit and its Floquet multipliers.",
    "continue": "Continue equilibria and periodic orbits in one parameter.",
    "response": "Frequency response of the forced oscillator (swept up and down).",
    "lyapunov": "Lyapunov exponents of the stick-slip flow, forced or not.",
    "forced-orbit": "Periodic orbit of the forced oscillator and its Floquet multipliers.",
    "forced-continue": "Continue forced periodic orbits in Omega or F_ex, with bifurcations.",
    "map": "Stability chart in two parameters: Hopf, grazing, fold (and forced: period-doubling) curves.",
    "stability": "Eigenvalues of a structure's steady sliding along one model entry: flutter and negative damping.",
}


def load_commands(argv: list[str] | None = None) -> None:
    """Register the command named in ``argv`` (its module only), or every command when none is named.

    A name that is not a command loads them all, so that the error can suggest the right one.
    """
    words = [a for a in (argv or []) if not a.startswith("-")]
    only_version = not words and argv is not None and "--version" in argv
    if only_version:
        return
    name = words[0] if words else None
    modules = {COMMAND_MODULES[name]} if name in COMMAND_MODULES else set(COMMAND_MODULES.values())
    for module in sorted(modules):
        importlib.import_module(f"{__name__}.{module}")
    _set_short_help()


def _set_short_help() -> None:
    """Give every registered command its line of :data:`SHORT_HELP` (without editing the command modules)."""
    for info in app.registered_commands:
        name = info.name or info.callback.__name__.replace("_", "-")
        info.short_help = SHORT_HELP.get(name, info.short_help)
        info.cls = PanelledCommand  # its options listed by help panel


def _one_line_warning(message, category, filename, lineno, file=None, line=None):  # noqa: ANN001
    print(f"warning: {message}", file=sys.stderr)


def main(argv: list[str] | None = None) -> int:
    """Entry point; returns the exit code (0 ok, 1 failure, 2 bad input).

    Spellings of earlier releases are rewritten first; each says so in one line on stderr, after the run (bad input
    keeps its one line: the error).
    """
    deprecations: list[str] = []
    code = _main(argv, deprecations)
    if code != 2:
        for line in deprecations:
            print(f"warning: {line}", file=sys.stderr)
    return code


def _main(argv: list[str] | None, deprecations: list[str]) -> int:
    warnings.showwarning = _one_line_warning
    argv = sys.argv[1:] if argv is None else list(argv)
    try:
        load_commands(argv)  # a command's modules: a Ctrl-C while they load is an interrupt like any other
    except KeyboardInterrupt:
        print(f"error: {INTERRUPTED}", file=sys.stderr)
        return 1
    command = typer.main.get_command(app)
    try:
        argv, lines = rewrite(argv)
        deprecations.extend(lines)
        returned = command.main(args=argv, prog_name="frictionflow", standalone_mode=False)
        if returned == TYPER_INTERRUPTED:  # a Ctrl-C outside a command's run (reading its options)
            raise Interrupted(INTERRUPTED)
    except typer.Exit as e:
        return e.exit_code
    except typer.Abort:
        print("aborted", file=sys.stderr)
        return 1
    except ValueError as e:
        print(f"error: {e}", file=sys.stderr)
        return 2
    except RuntimeError as e:  # a run that could not finish (the adaptive step cap, a full disk, ...)
        print(f"error: {e}", file=sys.stderr)
        return 1
    except OSError as e:  # the system's error where no writer put it into words: still one line
        where = f": {e.filename!r}" if e.filename else ""
        print(f"error: {e.strerror or e}{where}", file=sys.stderr)
        return 2 if e.errno in PATH_ERRNOS else 1
    except Exception as e:
        # Usage errors of click (vendored by recent typer): unknown options, bad types.
        if hasattr(e, "format_message") and hasattr(e, "exit_code"):
            if type(e).__name__ == "NoArgsIsHelpError":
                print(e.format_message(), file=sys.stderr)
            elif type(e).__name__ == "MissingParameter" and len(missing := _missing(e, argv)) > 1:
                print(f"error: missing options {', '.join(missing)}", file=sys.stderr)
            else:
                print(f"error: {e.format_message()}", file=sys.stderr)
            return int(e.exit_code)
        raise
    return 0


def _missing(error: Exception, argv: list[str]) -> list[str]:
    """Every required option of the failed command that ``argv`` does not give (click names only the first)."""
    ctx = getattr(error, "ctx", None)
    if ctx is None:
        return []
    given = {word.split("=")[0] for word in argv}
    return [p.opts[0] for p in ctx.command.params
            if p.param_type_name == "option" and p.required and not given & set(p.opts)]


def run() -> None:  # pragma: no cover - console script
    code = main()
    for sig in (signal.SIGINT, signal.SIGTERM):  # the command has ended: a signal now would only hide its code
        signal.signal(sig, signal.SIG_IGN)
    if abandoned():  # an interrupted run's thread is still at work: end without finalising under it
        sys.stdout.flush()
        sys.stderr.flush()
        os._exit(code)
    # CPython marks a KeyboardInterrupt that leaves an exec() of a string as unhandled even when it is caught
    # later (numba runs generated code so, and Ctrl-C or SIGTERM can land there): the process would end by
    # SIGINT (130), not with main's code.  The next exec() of a string clears that mark.
    exec("pass")
    if code != 0:  # its one line is said; an interrupt can leave objects half built (llvmlite's, while numba
        sys.unraisablehook = _quiet  # loads a kernel), whose finalisers would print a traceback after it
    sys.exit(code)


def _quiet(unraisable: object) -> None:
    """Say nothing of an exception raised where it cannot be (a finaliser's, at exit)."""
