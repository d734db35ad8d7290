"""``frictionflow lyapunov``: both Lyapunov exponents of the stick-slip flow, forced or not."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any, Optional

import typer

from ..analysis.lyapunov import lyapunov_exponents
from .._display import spoken
from ..friction.registry import SWITCH_LAW, tangent_law_names
from ..io import check_input_path, read_config
from ..parameters import Param
from ._app import app
from .options import CONFIG_OPTION, merged_config, parameter_names, with_parameters

MODEL = parameter_names(("oscillator", "law"), run=("x0", "v0", "t_end", "friction", "dimensional"))
HELP = {
    "x0": "Start X [0].",
    "v0": "Start X' [0].",
    "t_end": "End of the averaging, transient included (rounded up to whole blocks) [6000].",
    "friction": f"Friction law with Coulomb's stick rule: {spoken(tangent_law_names())} [{SWITCH_LAW}].",
}
#: the command's own settings, with their ranges (bounded: the cost grows with them)
COMMAND_PARAMETERS = {p.name: p for p in (
    Param("t_transient", "", "transient before averaging", "run", 1000.0, lower=0.0, upper=1e9),
    Param("steps", "", "RK4 steps per block", "run", 512, kind="int", lower=4, upper=1_000_000),
    Param("block", "", "renormalisation interval of an unforced run", "run", None, lower=0.0, lower_open=True, upper=1e6),
)}


#: the command list's line (click would cut the docstring); cli.SHORT_HELP may name it too
SHORT_HELP = "Lyapunov exponents of the stick-slip flow, forced or not."


@app.command(short_help=SHORT_HELP)
@with_parameters(MODEL, HELP)
def lyapunov(
    params: dict[str, Any],
    t_transient: float = typer.Option(1000.0, "--t-transient", help="Time before the averaging starts (rounded up to whole blocks)."),
    steps: int = typer.Option(512, "--steps", help="RK4 steps per block (forcing period); switches are located whatever it is."),
    block: Optional[float] = typer.Option(None, "--block", help="Renormalisation interval when unforced [2 pi]; forced: the forcing period."),
    as_json: bool = typer.Option(False, "--json", help="Print one JSON object with the results to stdout (-inf as null)."),
    config: Optional[Path] = CONFIG_OPTION,
) -> None:
    """Lyapunov exponents of the stick-slip flow (switches located, saltation matrices, QR once per forcing period)."""
    file_values: dict[str, Any] = {}
    if config is not None:
        check_input_path(config, "--config")
        file_values = read_config(config)
    for name, value in (("t_transient", t_transient), ("steps", steps), ("block", block)):
        if value is not None:
            COMMAND_PARAMETERS[name].check(value)
    given = dict(params)
    if given.get("friction") is None and "friction" not in file_values:
        given["friction"] = SWITCH_LAW
    cfg = merged_config(config, given)
    model, law, _ = cfg.build()
    t_end = cfg.given.get("t_end", 6000.0)
    result = lyapunov_exponents(model, law, x0=cfg.x0 if cfg.x0 is not None else 0.0,
                                v0=cfg.v0 if cfg.v0 is not None else 0.0, t_transient=t_transient, t_end=t_end,
                                steps_per_block=steps, block=block, max_memory=cfg.max_memory)
    if as_json:
        print(json.dumps(result.as_dict(), allow_nan=False))
    else:
        print(result.summary())
