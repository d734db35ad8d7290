"""The CLI options of the declared parameters, in one place for every command.

:func:`with_parameters` adds an option for each declared parameter of the
chosen owners (:mod:`frictionflow.parameters`) to a command function, so that
a parameter added to a law, a solver or the oscillator appears on every
command that takes it, with its help text from the declaration.  The command
receives them as one mapping ``params`` (only those given: the rest is None).
:func:`with_options` does the same for a command's own options: one record
``opts`` instead of a parameter each.
"""

from __future__ import annotations

import dataclasses
import functools
import inspect
import typing
from pathlib import Path
from typing import Any, Callable, Optional

import typer

from ..config import RunConfig
from ..io import DEFAULT_DPI, DPI_RANGE, FIGURE_FORMATS, read_config
from ..parameters import Param, declared

#: the run's parameters every model command takes (the others are command-specific)
MODEL_RUN = ("x0", "v0", "t_end", "friction", "solver", "dimensional")

_TYPES = {"real": float, "int": int, "choice": str, "text": str}


def parameter_names(owners: tuple[str, ...], run: tuple[str, ...] = ()) -> tuple[str, ...]:
    """Declared parameters of ``owners``, plus the run parameters named in ``run``."""
    return tuple(n for n, p in declared().items() if p.owner in owners or n in run)


def _option(p: Param, help_override: dict[str, str]) -> inspect.Parameter:
    annotation = Optional[_TYPES[p.kind]]
    option = typer.Option(None, p.flag, help=help_override.get(p.name, p.help()))
    return inspect.Parameter(p.name, inspect.Parameter.KEYWORD_ONLY, default=option, annotation=annotation)


def with_parameters(names: tuple[str, ...], help_override: dict[str, str] | None = None) -> Callable:
    """Decorator: give a command one option per parameter in ``names``, passed to it as ``params``."""
    params = declared()
    extra = [_option(params[n], help_override or {}) for n in names]
    return lambda fn: _gathered(fn, extra, "params", lambda given: given)


def with_options(record: type) -> Callable:
    """Decorator: give a command the options declared by ``record`` (a dataclass whose fields default to their
    ``typer.Option``), passed to it as one ``record`` named ``opts``.

    A command with many options of its own keeps a short signature (a few
    parameters) while typer still sees one parameter per option, in the
    order of the fields.
    """
    hints = typing.get_type_hints(record)
    extra = [inspect.Parameter(f.name, inspect.Parameter.KEYWORD_ONLY, default=f.default, annotation=hints[f.name])
             for f in dataclasses.fields(record)]
    return lambda fn: _gathered(fn, extra, "opts", lambda given: record(**given))


def _gathered(fn: Callable, extra: list[inspect.Parameter], name: str, pack: Callable) -> Callable:
    """``fn`` as a command that takes the options ``extra`` (before its own) and passes them packed as ``name``."""
    own = [q for q in inspect.signature(fn, eval_str=True).parameters.values() if q.name != name]
    names = [q.name for q in extra]

    @functools.wraps(fn)
    def command(**kwargs: Any) -> Any:
        given = {n: kwargs.pop(n) for n in names}
        return fn(**{name: pack(given)}, **kwargs)

    # typer (and a decorator above this one) must read this signature (annotations evaluated), not the function's
    command.__signature__ = inspect.Signature([*extra, *(q.replace(kind=inspect.Parameter.KEYWORD_ONLY) for q in own)])  # type: ignore[attr-defined]
    command.__annotations__ = {}
    del command.__wrapped__
    return command


def merged_config(config: Optional[Path], options: dict[str, Any]) -> RunConfig:
    """Config file values, overridden by the options given on the command line."""
    values: dict[str, Any] = read_config(config) if config is not None else {}
    if config is not None:  # every value of the file checked, also those the options then override
        try:
            RunConfig.checked(values, source=str(config))
        except ValueError as e:
            said = str(e)  # (an unknown key already names the file)
            raise ValueError(said if said.startswith(f"{config}: ") else f"{config}: {said}") from None
    values.update({k: v for k, v in options.items() if v is not None})
    return RunConfig.from_mapping(values, source=str(config) if config else "options")


#: how a path option shows in --help (as typer shows a ``Path`` option without a parser)
PATH_METAVAR = "<path>"


def path_text(text: str | Path) -> Path:
    """A path option's value: refuses an empty one, which ``Path`` would turn into ``.`` (this directory) and an
    error would then quote as ``'.'``, not as what was typed."""
    if isinstance(text, Path):
        return text
    if text == "":
        raise typer.BadParameter("an empty path: give a file name")
    return Path(text)


CONFIG_OPTION = typer.Option(None, "--config", parser=path_text, metavar=PATH_METAVAR, help="TOML file with any of these options (names with underscores).")
#: the figure formats, as the --plot options' help says them
FIGURE_SUFFIXES = ", ".join(FIGURE_FORMATS)
#: every command that writes a figure takes this one --dpi
DPI_OPTION = typer.Option(DEFAULT_DPI, "--dpi", min=DPI_RANGE[0], max=DPI_RANGE[1], metavar="<float>", show_default=False,
                          help=f"Resolution of the figures in dots per inch [{DEFAULT_DPI:g}]; the --plot file's suffix "
                               f"sets the format ({FIGURE_SUFFIXES}).")
