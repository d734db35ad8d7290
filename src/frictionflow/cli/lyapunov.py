"""``frictionflow lyapunov``: both Lyapunov exponents of the stick-slip flow, forced or not."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any, Optional

from ..analysis.lyapunov import lyapunov_exponents
from ..io import check_output_path
from ._app import app
from .options import CONFIG_OPTION, command_config, parameter_names, start_state, with_dimensional, with_parameters
from .output import FLOW_MAP, print_summary, provenance, write_json
from .vocabulary import PARAMETER_DEFAULTS, option, parameter_help

MODEL = parameter_names(("oscillator", "law"), run=("x0", "v0", "t_end", "friction", "dimensional"))
#: (its own numbers, --t-transient, --steps-per-period and --block, are checked by their vocabulary terms)


#: the command list's line (click would cut the docstring); cli.SHORT_HELP may name it too
SHORT_HELP = "Lyapunov exponents of the stick-slip flow, forced or not."
OUT_FORMATS = (".json",)


@app.command(short_help=SHORT_HELP)
@with_parameters(MODEL, parameter_help("lyapunov", MODEL))
def lyapunov(
    params: dict[str, Any],
    t_transient: float = option("--t-transient"),
    steps_per_period: int = option("--steps-per-period"),
    block: Optional[float] = option("--block"),
    as_json: bool = option("--json"),
    out: Optional[Path] = option("--out", "Here: the JSON object, .json."),
    config: Optional[Path] = CONFIG_OPTION,
) -> None:
    """Lyapunov exponents of the stick-slip flow (switches located, saltation matrices, QR once per forcing period)."""
    if out is not None:
        check_output_path(out, OUT_FORMATS, "--out")
    cfg = command_config("lyapunov", config, params, config_only=("max_memory",))
    model, law, _ = cfg.build()
    x0, v0 = start_state(cfg, model, law)
    t_end = cfg.given.get("t_end", PARAMETER_DEFAULTS["lyapunov", "t_end"][0])
    result = lyapunov_exponents(model, law, x0=x0, v0=v0, t_transient=t_transient, t_end=t_end,
                                steps_per_block=steps_per_period, block=block, max_memory=cfg.max_memory)
    report = with_dimensional(result.as_dict(), cfg)
    if out is not None:
        write_json(out, report)
    if as_json:
        print(json.dumps(report, allow_nan=False))
    else:
        print_summary(result, provenance(law, FLOW_MAP, cfg.dimensional))
