"""``frictionflow forced-orbit`` and ``frictionflow forced-continue``: periodic orbits of the forced oscillator.

Registered by importing this module in :mod:`frictionflow.cli` (``from . import forced_orbit``).
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any, Optional

import numpy as np
import typer

from .._json import jsonable
from ..core import forced_map as fm
from .._display import spoken
from ..friction.registry import SWITCH_LAW, tangent_law_names
from ..io import check_input_path, check_output_path, read_config, write_figure
from ..orbits.forced import DEFAULT_STEPS, PARAMETERS, check_parameter, continue_forced, find_forced_orbit, stroboscopic_sweep, switch_period_doubling
from ..orbits.forced_plot import plot_forced_branches
from ..parameters import Param
from ..plotting import FIGURE_FORMATS
from ..solvers.base import kernel_params
from ._app import app
from .options import CONFIG_OPTION, PATH_METAVAR, merged_config, parameter_names, path_text, with_parameters

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
    plot: Optional[Path] = typer.Option(None, "--plot", parser=path_text, metavar=PATH_METAVAR, help="Draw the orbit's phase portrait and time history (.png, .pdf, .svg)."),
    config: Optional[Path] = CONFIG_OPTION,
) -> None:
    """Newton shooting for the orbit of period m 2 pi / Omega: state at tau = 0, multipliers, power and TR_B."""
    _check(m=m, transient=transient, steps=steps)
    if plot is not None:
        check_output_path(plot, FIGURE_FORMATS, "--plot")
    cfg, model, law = _build(config, params)
    orbit = find_forced_orbit(model, law, m=m, x0=cfg.x0, v0=cfg.v0, transient_periods=transient, steps=steps)
    if plot is not None:
        _plot_orbit(orbit, plot)
    if as_json:
        print(json.dumps(orbit.as_dict(), allow_nan=False))
    else:
        print(orbit.summary())


def _plot_orbit(orbit, path: Path) -> None:
    """Phase portrait and X(tau) over one orbit period, sampled by runs of the flow map from tau = 0."""
    import matplotlib

    matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt

    n = 200 * orbit.m
    ts = np.linspace(0.0, orbit.period, n + 1)[1:]
    pts = np.array([orbit.state, *(_state_at(orbit, t, DEFAULT_STEPS) for t in ts)])
    tt = np.concatenate([[0.0], ts])
    fig, ax = plt.subplots(1, 2, figsize=(10, 4))
    ax[0].plot(pts[:, 0], pts[:, 1], lw=1.2)
    ax[0].plot([orbit.state[0]], [orbit.state[1]], "ko", mfc="none", label=r"$\tau = 0$")
    ax[0].axhline(orbit.model.vb, color="0.6", lw=0.8, ls=":")
    ax[0].set(xlabel="X", ylabel="X'", title=f"orbit, m={orbit.m} ({orbit.stability})")
    ax[0].legend(fontsize=8)
    ax[1].plot(tt, pts[:, 0], label="X")
    ax[1].plot(tt, pts[:, 1], label="X'")
    ax[1].set(xlabel=r"$\tau$", title="one period")
    ax[1].legend(fontsize=8)
    fig.tight_layout()
    write_figure(fig, path, "--plot")


def _state_at(orbit, t: float, steps: int) -> np.ndarray:
    """The orbit's state at time t (< its period), by the flow map over [0, t] (t need not be whole periods)."""
    model = orbit.model
    p = kernel_params(model, orbit.friction)
    out = fm.map_out()
    n = max(4, int(np.ceil(steps * t / model.forcing_period)))
    fm.flow_map(float(orbit.state[0]), float(orbit.state[1]), model.zeta, model.vb, p, float(t), n, out)
    return out.end.copy()


@app.command("forced-continue", short_help=SHORT_HELP_CONTINUE)
@with_parameters(MODEL, HELP)
def forced_continue(
    params: dict[str, Any],
    parameter: str = typer.Option("omega", "--parameter", help="The continuation parameter: omega or fex."),
    start: float = typer.Option(..., "--from", help="Start value of the parameter (the first orbit is found there)."),
    stop: float = typer.Option(..., "--to", help="End value of the parameter."),
    m: int = typer.Option(1, "--m", help="Period in forcing periods."),
    steps: int = typer.Option(512, "--steps", help="RK4 steps per forcing period."),
    max_points: int = typer.Option(400, "--max-points", help="Most points on the branch."),
    switch_pd: bool = typer.Option(False, "--switch-pd", help="Also continue the 2m branch born at the first period doubling."),
    sweep: int = typer.Option(0, "--sweep", help="Brute-force overlay: this many parameter values swept up (0: none)."),
    as_json: bool = typer.Option(False, "--json", help="Print one JSON object with the branch(es) to stdout."),
    plot: Optional[Path] = typer.Option(None, "--plot", parser=path_text, metavar=PATH_METAVAR, help="Draw the bifurcation diagram (.png, .pdf, .svg)."),
    config: Optional[Path] = CONFIG_OPTION,
) -> None:
    """Pseudo-arclength continuation in Omega or F_ex: folds, period doublings, Neimark-Sacker, grazings."""
    if parameter not in PARAMETERS:
        raise ValueError(f"--parameter must be omega or fex, got {parameter!r}")
    for flag, value in (("--from", start), ("--to", stop)):
        check_parameter(parameter, value, flag)  # both ends by the parameter's declaration, as the API checks them
    if start == stop:
        raise ValueError(f"--to must differ from --from ({start!r})")
    _check(m=m, steps=steps, max_points=max_points, sweep=sweep)
    if plot is not None:
        check_output_path(plot, FIGURE_FORMATS, "--plot")
    cfg, model, law = _build(config, params)
    branch = continue_forced(model, law, parameter, start, stop, m=m, x0=cfg.x0, v0=cfg.v0, steps=steps,
                             max_points=max_points)
    branches = [branch]
    if switch_pd and branch.events_of("period_doubling"):
        branches.append(switch_period_doubling(branch))
    brute = None
    if sweep:
        values = np.linspace(min(start, stop), max(start, stop), sweep)
        brute = stroboscopic_sweep(branch.model, law, parameter, values, x0=float(branch.points[0].state[0]) if start < stop else 0.0,
                                   v0=float(branch.points[0].state[1]) if start < stop else 0.0)
    if plot is not None:
        plot_forced_branches(branches, plot, sweep=brute, name="--plot")
    if as_json:
        out: dict[str, Any] = {"branches": [b.as_dict() for b in branches]}
        if brute is not None:
            out["brute_force"] = jsonable({"values": brute.values, "X": brute.x, "V": brute.v})
        print(json.dumps(out, allow_nan=False))
    else:
        for b in branches:
            print(b.summary())
