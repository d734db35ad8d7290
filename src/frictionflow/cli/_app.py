"""The typer application the command modules register their commands on.

Apart from :mod:`frictionflow.cli` so that the command modules import it from
here, not from the package that imports them.
"""

from __future__ import annotations

import typer

from .._version import __version__

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
