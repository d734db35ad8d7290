"""``frictionflow forced-orbit`` and ``frictionflow forced-continue``: periodic orbits of the forced oscillator.

Registered by importing this module in :mod:`frictionflow.cli` (``from . import forced_orbit``).
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Optional

import numpy as np
import typer

from .._json import jsonable
from .._display import spoken
from ..friction.registry import SWITCH_LAW, tangent_law_names
from ..io import check_input_path, check_output_path, read_config
from ..orbits.forced import PARAMETERS, check_parameter, continue_forced, find_forced_orbit, stroboscopic_sweep, switch_period_doubling
from ..orbits.forced_plot import plot_forced_branches, plot_forced_orbit
from ..parameters import Param
from ..plotting import FIGURE_FORMATS
from ._app import app
from .options import CONFIG_OPTION, DPI_OPTION, PATH_METAVAR, merged_config, parameter_names, path_text, with_options, with_parameters

MODEL = parameter_names(("oscillator", "law"), run=("x0", "v0", "friction", "dimensional"))
HELP = {
    "x0": "Start X at tau = 0 [0].",
    "v0": "Start X' at tau = 0 [0].",
    "friction": f"Friction law with Coulomb's stick rule: {spoken(tangent_law_names())} [{SWITCH_LAW}].",
}
COMMAND_PARAMETERS = {p.name: p for p in (
    Param("m", "", "period in forcing periods", "run", 1, kind="int", lower=1, upper=1000),
    Param("steps", "", "RK4 steps per forcing period", "run", 512, kind="int", lower=4, upper=1_000_000),
    Param("transient", "", "forcing periods before shooting", "run", 200, kind="int", lower=0, upper=10_000_000),
    Param("max_points", "", "points of the branch", "run", 400, kind="int", lower=2, upper=100_000),
    Param("sweep", "", "brute-force parameter values", "run", 0, kind="int", lower=0, upper=10_000),
)}
SHORT_HELP_ORBIT = "Periodic orbit of the forced oscillator and its Floquet multipliers."
SHORT_HELP_CONTINUE = "Continue forced periodic orbits in Omega or F_ex, with bifurcations."


def _check(**values: Any) -> None:
    for name, value in values.items():
        if value is not None:
            COMMAND_PARAMETERS[name].check(value)


def _build(config: Optional[Path], params: dict[str, Any]):
    file_values: dict[str, Any] = {}
    if config is not None:
        check_input_path(config, "--config")
        file_values = read_config(config)
    given = dict(params)
    if given.get("friction") is None and "friction" not in file_values:
        given["friction"] = SWITCH_LAW
    cfg = merged_config(config, given)
    model, law, _ = cfg.build()
    return cfg, model, law


@app.command("forced-orbit", short_help=SHORT_HELP_ORBIT)
@with_parameters(MODEL, HELP)
def forced_orbit(
    params: dict[str, Any],
    m: int = typer.Option(1, "--m", help="Period in forcing periods (1 harmonic, > 1 subharmonic)."),
    transient: int = typer.Option(200, "--transient", help="Forcing periods run from (x0, v0) before shooting (0: shoot from them)."),
    steps: int = typer.Option(512, "--steps", help="RK4 steps per forcing period (switches are located whatever it is)."),
    as_json: bool = typer.Option(False, "--json", help="Print one JSON object with the results to stdout."),
    plot: Optional[Path] = typer.Option(None, "--plot", parser=path_text, metavar=PATH_METAVAR, help="Draw the orbit's phase portrait and time history (.png, .pdf, .svg, .eps)."),
    dpi: float = DPI_OPTION,
    config: Optional[Path] = CONFIG_OPTION,
) -> None:
    """Newton shooting for the orbit of period m 2 pi / Omega: state at tau = 0, multipliers, power and TR_B."""
    _check(m=m, transient=transient, steps=steps)
    if plot is not None:
        check_output_path(plot, FIGURE_FORMATS, "--plot")
    cfg, model, law = _build(config, params)
    orbit = find_forced_orbit(model, law, m=m, x0=cfg.x0, v0=cfg.v0, transient_periods=transient, steps=steps)
    if plot is not None:
        plot_forced_orbit(orbit, plot, name="--plot", dpi=dpi)
    if as_json:
        print(json.dumps(orbit.as_dict(), allow_nan=False))
    else:
        print(orbit.summary())


@dataclass(frozen=True)
class ForcedContinueOptions:
    """The forced-continue command's own options (the model's come as ``params``), each with its typer option."""

    parameter: str = typer.Option("omega", "--parameter", help="The continuation parameter: omega or fex.")
    start: float = typer.Option(..., "--from", help="Start value of the parameter (the first orbit is found there).")
    stop: float = typer.Option(..., "--to", help="End value of the parameter.")
    m: int = typer.Option(1, "--m", help="Period in forcing periods.")
    steps: int = typer.Option(512, "--steps", help="RK4 steps per forcing period.")
    max_points: int = typer.Option(400, "--max-points", help="Most points on the branch.")
    switch_pd: bool = typer.Option(False, "--switch-pd", help="Also continue the 2m branch born at the first period doubling.")
    sweep: int = typer.Option(0, "--sweep", help="Brute-force overlay: this many parameter values swept up (0: none).")
    as_json: bool = typer.Option(False, "--json", help="Print one JSON object with the branch(es) to stdout.")
    plot: Optional[Path] = typer.Option(None, "--plot", parser=path_text, metavar=PATH_METAVAR, help="Draw the bifurcation diagram (.png, .pdf, .svg, .eps).")
    dpi: float = DPI_OPTION
    config: Optional[Path] = CONFIG_OPTION


@app.command("forced-continue", short_help=SHORT_HELP_CONTINUE)
@with_parameters(MODEL, HELP)
@with_options(ForcedContinueOptions)
def forced_continue(params: dict[str, Any], opts: ForcedContinueOptions) -> None:
    """Pseudo-arclength continuation in Omega or F_ex: folds, period doublings, Neimark-Sacker, grazings."""
    if opts.parameter not in PARAMETERS:
        raise ValueError(f"--parameter must be omega or fex, got {opts.parameter!r}")
    for flag, value in (("--from", opts.start), ("--to", opts.stop)):
        check_parameter(opts.parameter, value, flag)  # both ends by the parameter's declaration, as the API checks them
    if opts.start == opts.stop:
        raise ValueError(f"--to must differ from --from ({opts.start!r})")
    _check(m=opts.m, steps=opts.steps, max_points=opts.max_points, sweep=opts.sweep)
    if opts.plot is not None:
        check_output_path(opts.plot, FIGURE_FORMATS, "--plot")
    cfg, model, law = _build(opts.config, params)
    branch = continue_forced(model, law, opts.parameter, opts.start, opts.stop, m=opts.m, x0=cfg.x0, v0=cfg.v0,
                             steps=opts.steps, max_points=opts.max_points)
    branches = [branch]
    if opts.switch_pd and branch.events_of("period_doubling"):
        branches.append(switch_period_doubling(branch))
    brute = None
    if opts.sweep:
        values = np.linspace(min(opts.start, opts.stop), max(opts.start, opts.stop), opts.sweep)
        up = opts.start < opts.stop
        brute = stroboscopic_sweep(branch.model, law, opts.parameter, values, x0=float(branch.points[0].state[0]) if up else 0.0,
                                   v0=float(branch.points[0].state[1]) if up else 0.0)
    if opts.plot is not None:
        plot_forced_branches(branches, opts.plot, sweep=brute, name="--plot", dpi=opts.dpi)
    if opts.as_json:
        out: dict[str, Any] = {"branches": [b.as_dict() for b in branches]}
        if brute is not None:
            out["brute_force"] = jsonable({"values": brute.values, "X": brute.x, "V": brute.v})
        print(json.dumps(out, allow_nan=False))
    else:
        for b in branches:
            print(b.summary())
