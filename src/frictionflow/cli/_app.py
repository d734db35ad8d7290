"""The typer application the command modules register their commands on.

Apart from :mod:`frictionflow.cli` so that the command modules import it from
here, not from the package that imports them.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import typer
import typer.core

if TYPE_CHECKING:  # annotations only: recent typer vendors click and no longer installs it
    import click

from .._version import __version__
from .vocabulary import PANELS


class PanelledCommand(typer.core.TyperCommand):
    """A command whose --help lists its options in panels (``rich_help_panel``) as plain text sections.

    Plain text, not rich boxes: help texts keep their ``[default]`` brackets and read the same in any terminal.
    """

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
