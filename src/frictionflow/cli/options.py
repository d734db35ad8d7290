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
import re
import typing
from pathlib import Path
from typing import Any, Callable, Optional

import typer

from ..config import RunConfig
from ..estimate import Limits, limited
from ..friction import FrictionLaw
from ..io import OutputError, check_input_path, read_config
from ..orbits.parameters import parameter_names as varied_names
from ..params import BeltOscillator, DimensionalParams
from ..parameters import Param, declared, dimensional_parameters
from .vocabulary import PATH_METAVAR, check_law, default_law, option, panel_of, path_text  # noqa: F401 (re-exported)

#: the run's parameters every model command takes (the others are command-specific)
MODEL_RUN = ("x0", "v0", "t_end", "friction", "solver", "dimensional")

_TYPES = {"real": float, "int": int, "choice": str, "text": str}


def parameter_names(owners: tuple[str, ...], run: tuple[str, ...] = ()) -> tuple[str, ...]:
    """Declared parameters of ``owners``, plus the run parameters named in ``run``."""
    return tuple(n for n, p in declared().items() if p.owner in owners or n in run)


def _option(p: Param, help_override: dict[str, str]) -> inspect.Parameter:
    annotation = Optional[_TYPES[p.kind]]
    given = typer.Option(None, p.flag, help=help_override.get(p.name, p.help()), rich_help_panel=panel_of(p))
    return inspect.Parameter(p.name, inspect.Parameter.KEYWORD_ONLY, default=given, annotation=annotation)


def with_parameters(names: tuple[str, ...], help_override: dict[str, str] | None = None) -> Callable:
    """Decorator: give a command one option per parameter in ``names``, passed to it as ``params``, and
    :func:`bounded`'s ``--no-limit``."""
    params = declared()
    extra = [_option(params[n], help_override or {}) for n in names]
    return lambda fn: bounded(_gathered(fn, extra, "params", lambda given: given))


#: the option that lifts the limits of :mod:`frictionflow.estimate` (the same on every command)
NO_LIMIT = "--no-limit"
NO_LIMIT_OPTION = option(NO_LIMIT)


def bounded(fn: Callable) -> Callable:
    """Decorator: run the command within the limits of :mod:`frictionflow.estimate`; its option ``--no-limit``
    lifts them (the estimate is still shown by the progress bars)."""
    signature = inspect.signature(fn, eval_str=True)

    @functools.wraps(fn)
    def command(*args: Any, no_limit: bool = False, **kwargs: Any) -> Any:
        with limited(None if no_limit else Limits(lift=NO_LIMIT)):
            return fn(*args, **kwargs)

    extra = inspect.Parameter("no_limit", inspect.Parameter.KEYWORD_ONLY, default=NO_LIMIT_OPTION, annotation=bool)
    command.__signature__ = signature.replace(parameters=[*signature.parameters.values(), extra])  # type: ignore[attr-defined]
    command.__annotations__ = {}
    del command.__wrapped__
    return command


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


def command_config(command: str, config: Optional[Path], params: dict[str, Any],
                   config_only: tuple[str, ...] = ()) -> RunConfig:
    """The run's settings on ``command``: the config file's, overridden by the options given, with the command's
    default law (:func:`~.vocabulary.default_law`) unless one is chosen; a law it cannot use refused in one line.
    A config key is one of ``params`` (the command's options) or of ``config_only`` (the settings the command reads
    from a config without an option); any other is refused."""
    file_values: dict[str, Any] = {}
    if config is not None:
        check_input_path(config, "--config")  # before reading it, naming the option
        file_values = read_config(config)
        unused = [key for key in file_values if key not in params and key not in config_only]
        if unused:  # a key this command takes no option for would be ignored without a word
            raise ValueError(f"--config: key {unused[0]!r} is not used by {command} (a config holds the model's "
                             f"options -- the system, its law and solver -- not the command's own: "
                             f"frictionflow {command} --help)")
    given = dict(params)
    if given.get("friction") is None and "friction" not in file_values:
        given["friction"] = default_law(command)
    cfg = merged_config(config, given)
    check_law(command, cfg.friction)
    return cfg


def with_dimensional(report: dict[str, Any], cfg: RunConfig) -> dict[str, Any]:
    """``report`` with the dimensional table the run was given and its omega0 (``dimensional``), if any: the
    results are non-dimensional, and these convert them back (time by omega0, length by l_0)."""
    if cfg.dimensional is not None:
        report["dimensional"] = cfg.dimensional | {"omega0": DimensionalParams.from_table(cfg.dimensional).omega0}
    return report


def start_state(cfg: RunConfig, model: BeltOscillator, law: FrictionLaw) -> tuple[float, float]:
    """(x0, v0) as given, else the law's default start (:meth:`FrictionLaw.start`) -- of every command that takes one."""
    return law.start(model.vb, cfg.x0, cfg.v0)


CONFIG_OPTION = option("--config")
#: every command that writes a figure takes this one --dpi
DPI_OPTION = option("--dpi")


def refuse_fixed(parameter: str, flag: str, where: str, config: Optional[Path], params: dict[str, Any]) -> None:
    """Refuse a value of ``parameter`` given besides ``flag`` that varies it (on the command line or in the config):
    the study sets it ``where`` ("along the branch"), so the value would be silently ignored."""
    option_name = f"--{parameter.replace('_', '-')}"
    if params.get(parameter) is not None:
        raise ValueError(f"{option_name} {params[parameter]:g} conflicts with {flag} {parameter}=FROM:TO, which sets "
                         f"{parameter} {where}: give one of them")
    values = read_config(config, "--config") if config is not None else {}
    if parameter in values:
        raise ValueError(f"--config: {parameter} = {values[parameter]!r} conflicts with {flag} {parameter}=FROM:TO, "
                         f"which sets {parameter} {where}: remove it from {str(config)!r}")
    table = params.get("dimensional") or values.get("dimensional")
    table = declared()["dimensional"].parse(table) if isinstance(table, str) else table
    keys = _dimensional_keys(parameter, table)
    if keys:  # the range is non-dimensional: the table's value would be dropped, or the range read in its units
        given = ", ".join(f"{k}={table[k]:g}" for k in keys)
        raise ValueError(f"{flag} {parameter}: the dimensional table sets {parameter} ({given}), and "
                         f"{flag} gives non-dimensional values {where}: give the model without the dimensional table"
                         f"{'' if parameter in REQUIRED_BY_TABLE else f' or leave {keys[0]} out of it'}")


#: the non-dimensional parameters a dimensional table always sets (from its required m, c, k, v_b)
REQUIRED_BY_TABLE = ("zeta", "vb")


def _dimensional_keys(parameter: str, table: Any) -> list[str]:
    """The keys of a dimensional ``table`` (None: none given) that set the non-dimensional ``parameter``."""
    if not table:
        return []
    known = {key: p.name for key, p in dimensional_parameters().items()}
    return [k for k in table if known.get(k) == parameter or (parameter == "zeta" and k == "c")]


def check_option(flag: str, param: Param, value: Any) -> Any:
    """``param.check(value)`` in a line naming the command-line option ``flag`` (not the API's argument)."""
    return dataclasses.replace(param, name=flag).check(value)


def check_varied(flag: str, name: str, law: FrictionLaw) -> None:
    """Refuse, naming ``flag``, a parameter ``name`` that a continuation cannot vary with ``law`` (the API's check
    would name its argument, ``param``)."""
    allowed = varied_names(law)
    if name not in allowed:
        raise ValueError(f"{flag}: NAME must be one of {', '.join(allowed)} for friction={law.name}, got {name!r}")


def renamed(error: Exception, old: str, new: str, *, everywhere: bool = False) -> Exception:
    """``error`` with the API's name ``old`` at the head of its message (``everywhere``: wherever it stands as a
    word; for a name no sentence uses otherwise, such as ``sweep_out``) replaced by the option ``new``: the same
    type, and for an :class:`~frictionflow.io.OutputError` the same errno; ``error`` itself otherwise."""
    text = str(error)
    if everywhere:
        new_text = re.sub(rf"(?<![\w-]){re.escape(old)}(?![\w-])", new, text)
    else:
        head = next((h for h in (f"{old}: ", f"{old} ") if text.startswith(h)), None)
        new_text = text if head is None else new + text[len(old):]
    if new_text == text:
        return error
    if isinstance(error, OutputError):
        return OutputError(new_text, error.errno)
    try:
        return type(error)(new_text)
    except TypeError:  # an error that takes other arguments: left as it is
        return error
