"""``frictionflow simulate``."""

from __future__ import annotations

import json
import math
import sys
import warnings
from pathlib import Path
from typing import Any, Optional

from ..analysis import analyze, precompile
from ..estimate import enforce
from ..io import TRAJECTORY_FORMATS, check_output_path, trajectory_bytes, write_trajectory
from ..plotting import FIGURE_FORMATS, plot_run
from ..simulate import simulate as run_simulation
from ._app import app
from .options import CONFIG_OPTION, command_config, parameter_names, with_dimensional, with_parameters
from .output import provenance, show
from .structure import RTOL as MODEL_RTOL, T_END as MODEL_T_END, simulate_model
from .vocabulary import option, parameter_help

NAMES = parameter_names(("oscillator", "law", "solver", "run"))


@app.command()
@with_parameters(NAMES, parameter_help("simulate", NAMES, {
    "t_end": f"With --model: {MODEL_T_END:g} unless given.",
    "rtol": f"With --model: {MODEL_RTOL:g} unless given.",
    "dense_dt": "With --model: any step > 0 in the model's units of time."}))
def simulate(
    params: dict[str, Any],
    as_json: bool = option("--json"),
    out: Optional[Path] = option("--out", "Here: the trajectory, .csv, .nc or .zarr (with --model: .nc)."),
    plot: Optional[Path] = option("--plot", "Here: time history, phase portrait and power flow."),
    dpi: float = option("--dpi"),
    config: Optional[Path] = CONFIG_OPTION,
    model_file: Optional[Path] = option("--model"),
) -> None:
    """Simulate one run, find its steady state and report power flow and TR_B."""
    if model_file is not None:
        if config is not None:
            raise ValueError("--model describes the whole system: --config cannot be given with it")
        return simulate_model(model_file, params, as_json, {"out": out, "plot": plot, "dpi": dpi})
    # Every path is checked before any work, so a bad one costs nothing and writes nothing.
    cfg = command_config("simulate", config, params)
    if out is not None:
        check_output_path(out, TRAJECTORY_FORMATS, "--out")
    if plot is not None:
        check_output_path(plot, FIGURE_FORMATS, "--plot")

    if (out is not None or plot is not None) and cfg.dense_dt is None:
        cfg = cfg.replace(dense_dt=2 * math.pi / 200)  # files and figures want the curve, not just its switches
    if cfg.window is not None:
        # windows snap to samples: sample finely enough that a hand-set window lands within 1e-3
        cfg = cfg.replace(dense_dt=min(cfg.dense_dt or 1e-3, 1e-3))
    model, law, solv = cfg.build()
    samples = solv.sample_estimate(cfg.t_end, model)
    enforce(solv.cost(model, law, cfg.t_end).writing(out, 0 if out is None else trajectory_bytes(samples, out), "--out"))
    analysis_ready = precompile.in_background()  # a first run: the analysis compiles on another core meanwhile
    traj = run_simulation(model, law, solv, t_end=cfg.t_end, x0=cfg.x0, v0=cfg.v0, progress=sys.stderr.isatty(),
                          max_memory=cfg.max_memory)
    analysis_ready()
    result = analyze(traj, window=cfg.window, rtol=cfg.rtol)
    if result.steady_state.kind == "diverged":
        warnings.warn(f"the motion left the floating-point range at tau={result.steady_state.window[0]:.6g}: "
                      "steady state 'diverged', no averages")
    report = with_dimensional(result.to_dict(), cfg)
    if out is not None:
        write_trajectory(traj, out, name="--out")
    if plot is not None:
        plot_run(result, plot, name="--plot", dpi=dpi)
    if as_json:
        print(json.dumps(report))
    else:
        _print_summary(report, provenance(law, solv, cfg.dimensional))


def _print_summary(report: dict[str, Any], caption: str) -> None:
    from rich.console import Console
    from rich.table import Table

    ss = report["steady_state"]
    table = Table(title=f"steady state: {ss['kind']}  window {ss['window'][0]:.6g}..{ss['window'][1]:.6g}")
    table.add_column("quantity")
    table.add_column("value", justify="right")
    if ss["period"] is not None:
        table.add_row("period", f"{ss['period']:.10g}")
    if ss["decay_rate"] is not None:
        heading = f" (heading: {ss['heading']})" if ss["heading"] else ""  # only a run not settled heads somewhere
        table.add_row("decay rate", f"{ss['decay_rate']:.6g}{heading}")
    if ss.get("stability"):  # an equilibrium the run stayed on may be unstable (a start exactly on it)
        table.add_row("stability", ss["stability"])
    for k, v in report["averages"].items():
        table.add_row(k, "n/a" if v is None else f"{v:.6e}")
    table.add_row("TR_B", "n/a" if report["TR_B"] is None else f"{report['TR_B']:.6g}")
    for k, v in report["amplitude"].items():
        table.add_row(k, f"{v:.6g}")
    table.add_row("energy residual", f"{report['energy_residual']:.2e}")
    show(Console(), table, caption)
