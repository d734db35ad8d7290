"""The typer application the command modules register their commands on.

Apart from :mod:`frictionflow.cli` so that the command modules import it from
here, not from the package that imports them.
"""

from __future__ import annotations

import _thread
import signal
import sys
import threading
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
def sigterm_as_interrupt() -> Iterator[threading.Event]:
    """SIGTERM handled like Ctrl-C, so that ``kill`` ends a command as Ctrl-C does (a sweep's lock released too).

    Yields an event set once a C callback has dropped an interrupt (see ``swallowed``): a failure after one is the
    interrupt's doing (numba's kernel left without its compiled object), not the command's.
    """

    def interrupt(signum, frame):  # noqa: ANN001
        raise KeyboardInterrupt

    hook = sys.unraisablehook
    dropped = threading.Event()
    on_its_way = threading.Lock()  # held while an interrupt raised again has not reached the main thread's flags

    def raise_again() -> None:
        try:
            _thread.interrupt_main(signal.SIGTERM)
        finally:
            on_its_way.release()

    def swallowed(args):  # noqa: ANN001
        # A signal that lands in Python code called back from C (llvmlite's hooks while numba loads or links
        # kernels) raises there, and the callback's caller prints and drops it: the command would run on and
        # exit 0.  Raise it again from another thread, so that the main thread takes it where it is next
        # checked -- outside this hook, whose own exceptions are dropped too.  Once for a burst of drops (a
        # callback called again and again): the main thread's flag is one.
        if isinstance(args.exc_value, KeyboardInterrupt):
            dropped.set()
            if on_its_way.acquire(blocking=False):
                _thread.start_new_thread(raise_again, ())
        else:
            hook(args)

    try:
        previous = signal.signal(signal.SIGTERM, interrupt)
    except ValueError:  # not the main thread: leave signals alone
        yield dropped
        return
    sys.unraisablehook = swallowed
    try:
        yield dropped
    finally:
        if dropped.is_set():  # the interrupt raised again may still be on its way: let it come while SIGTERM is
            signal.signal(signal.SIGTERM, signal.SIG_IGN)  # ignored (it then does nothing), not under the handler
            if on_its_way.acquire(timeout=5.0):  # in place after us
                on_its_way.release()
        sys.unraisablehook = hook
        signal.signal(signal.SIGTERM, previous)


class PanelledCommand(typer.core.TyperCommand):
    """A command whose --help lists its options in panels (``rich_help_panel``) as plain text sections, and that
    ends on Ctrl-C or SIGTERM with :class:`Interrupted` (typer would return exit code 130 and print nothing).

    Plain text, not rich boxes: help texts keep their ``[default]`` brackets and read the same in any terminal.
    """

    def invoke(self, ctx: click.Context) -> Any:
        with sigterm_as_interrupt() as dropped:
            try:
                return super().invoke(ctx)
            except KeyboardInterrupt:
                raise Interrupted(INTERRUPTED) from None
            except Interrupted:  # the command's own words for it (what a sweep kept)
                raise
            except Exception:
                if dropped.is_set():  # what the dropped interrupt broke (a kernel half-compiled): the command was interrupted
                    raise Interrupted(INTERRUPTED) from None
                raise

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
