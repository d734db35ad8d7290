"""The typer application the command modules register their commands on.

Apart from :mod:`frictionflow.cli` so that the command modules import it from
here, not from the package that imports them.
"""

from __future__ import annotations

import _thread
import signal
import sys
from contextlib import contextmanager
from typing import TYPE_CHECKING, Any, Iterator

import typer
import typer.core

if TYPE_CHECKING:  # annotations only: recent typer vendors click and no longer installs it
    import click

from .._version import __version__
from .vocabulary import PANELS


#: what an interrupted command says (after ``error:``), where nothing was kept to name
INTERRUPTED = "interrupted (Ctrl-C or SIGTERM)"


class Interrupted(RuntimeError):
    """Ctrl-C or SIGTERM during a command: exit code 1 with one ``error:`` line (what was kept, where it matters)."""


@contextmanager
def sigterm_as_interrupt() -> Iterator[None]:
    """SIGTERM handled like Ctrl-C, so that ``kill`` ends a command as Ctrl-C does (a sweep's lock released too)."""

    def interrupt(signum, frame):  # noqa: ANN001
        raise KeyboardInterrupt

    hook = sys.unraisablehook

    def swallowed(args):  # noqa: ANN001
        # A signal that lands in Python code called back from C (llvmlite's hooks while numba loads or links
        # kernels) raises there, and the callback's caller prints and drops it: the command would run on and
        # exit 0.  Raise it again from another thread, so that the main thread takes it where it is next
        # checked -- outside this hook, whose own exceptions are dropped too.
        if isinstance(args.exc_value, KeyboardInterrupt):
            _thread.start_new_thread(_thread.interrupt_main, (signal.SIGTERM,))
        else:
            hook(args)

    try:
        previous = signal.signal(signal.SIGTERM, interrupt)
    except ValueError:  # not the main thread: leave signals alone
        yield
        return
    sys.unraisablehook = swallowed
    try:
        yield
    finally:
        sys.unraisablehook = hook
        signal.signal(signal.SIGTERM, previous)


class PanelledCommand(typer.core.TyperCommand):
    """A command whose --help lists its options in panels (``rich_help_panel``) as plain text sections, and that
    ends on Ctrl-C or SIGTERM with :class:`Interrupted` (typer would return exit code 130 and print nothing).

    Plain text, not rich boxes: help texts keep their ``[default]`` brackets and read the same in any terminal.
    """

    def invoke(self, ctx: click.Context) -> Any:
        with sigterm_as_interrupt():
            try:
                return super().invoke(ctx)
            except KeyboardInterrupt:
                raise Interrupted(INTERRUPTED) from None

    def format_options(self, ctx: click.Context, formatter: click.HelpFormatter) -> None:
        groups: dict[str, list[tuple[str, str]]] = {}
        for param in self.get_params(ctx):
            record = param.get_help_record(ctx)
            if record is not None:
                panel = "Arguments" if param.param_type_name == "argument" else getattr(param, "rich_help_panel", None)
                groups.setdefault(panel or "Options", []).append(record)
        order = ("Arguments", *PANELS)
        for panel in sorted(groups, key=lambda p: order.index(p) if p in order else len(order)):
            with formatter.section(panel):
                formatter.write_dl(groups[panel])

app = typer.Typer(
    name="frictionflow",
    help="Dynamics and vibration power flow of dry-friction (mass-on-belt) oscillators.",
    no_args_is_help=True,
    add_completion=True,  # --install-completion / --show-completion (see the README)
    pretty_exceptions_enable=False,
    rich_markup_mode=None,
)


def _print_version(value: bool) -> None:
    """Eager ``--version``: print and stop before any command is needed."""
    if value:
        print(f"frictionflow {__version__}")
        raise typer.Exit(0)


@app.callback()
def _root(
    version: bool = typer.Option(False, "--version", help="Print the version and exit.",
                                 callback=_print_version, is_eager=True),
) -> None:
    """Dynamics and vibration power flow of dry-friction (mass-on-belt) oscillators."""
