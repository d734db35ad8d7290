"""Write the command-line reference from the command definitions, at every build.

Typer's own Markdown generator (``typer.cli.get_docs_for_click``, what ``typer
MODULE utils docs`` runs) walks the click command built from the application:
every command, every option with its help and default.  Nothing here is written
by hand, so the reference cannot drift from the program.  The page is
``generated/cli.md`` (a build product, ignored by git), included by ``cli.rst``.
"""

from __future__ import annotations

from pathlib import Path

import typer
import typer.cli

from frictionflow.cli import COMMAND_MODULES, app, load_commands

INTRO = """\
Every command and every option of the ``frictionflow`` program, generated from
the command definitions when this documentation is built (the same text as
``frictionflow COMMAND --help``).  Bad input prints one line naming the option
and its allowed range and exits with code 2 before anything is computed or
written; a run that cannot finish exits with code 1.
"""


def click_command():
    """The click command of the whole program, its subcommands in the order of :data:`COMMAND_MODULES`."""
    load_commands(None)
    command = typer.main.get_command(app)
    order = {name: i for i, name in enumerate(COMMAND_MODULES)}
    command.commands = dict(sorted(command.commands.items(), key=lambda kv: order.get(kv[0], len(order))))
    return command


def markdown() -> str:
    """The reference as Markdown: a title, :data:`INTRO`, then typer's pages of the program and each command."""
    command = click_command()
    ctx = typer.Context(command, info_name="frictionflow")
    text = typer.cli.get_docs_for_click(obj=command, ctx=ctx, name="frictionflow", title="Command-line reference")
    title, _, rest = text.strip().partition("\n")
    return f"{title}\n\n{INTRO.replace('``', '`')}\n{rest.strip()}\n"


def write(app_) -> None:  # noqa: ANN001 - Sphinx's application
    """``builder-inited``: write ``generated/cli.md`` in the source tree."""
    out = Path(app_.srcdir) / "generated" / "cli.md"
    out.parent.mkdir(parents=True, exist_ok=True)
    text = markdown()
    if not out.is_file() or out.read_text() != text:  # unchanged: keep the file's time (no rebuild)
        out.write_text(text)


def setup(app_):  # noqa: ANN001, ANN201
    app_.connect("builder-inited", write)
    return {"parallel_read_safe": True, "parallel_write_safe": True}
