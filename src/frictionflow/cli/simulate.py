"""``frictionflow simulate``."""

from __future__ import annotations

import json
import math
import sys
from pathlib import Path
from typing import Any, Optional

import typer

from ..analysis import analyze
from ..config import RunConfig, parse_dimensional
from ..io import TRAJECTORY_FORMATS, check_output_path, read_config, write_trajectory
from ..plotting import FIGURE_FORMATS
from ..simulate import simulate as run_simulation
from . import app


def merged_config(config: Optional[Path], options: dict[str, Any]) -> RunConfig:
    """Config file values, overridden by the options given on the command line."""
    values: dict[str, Any] = read_config(config) if config is not None else {}
    values.update({k: v for k, v in options.items() if v is not None})
    return RunConfig.from_mapping(values, source=str(config) if config else "options")


@app.command()
def simulate(
    fd: Optional[float] = typer.Option(None, "--fd", help="Kinetic friction F_d >= 0 [0.02]."),
    fs: Optional[float] = typer.Option(None, "--fs", help="Maximum static friction F_s >= F_d [F_d]."),
    vb: Optional[float] = typer.Option(None, "--vb", help="Belt speed V_b [0.01]."),
    zeta: Optional[float] = typer.Option(None, "--zeta", help="Damping ratio zeta >= 0 [0]."),
    vd: Optional[float] = typer.Option(None, "--vd", help="Karnopp band half-width V_d > 0 [1e-3]."),
    vs: Optional[float] = typer.Option(None, "--vs", help="Stribeck velocity V_s > 0 [0.01]."),
    delta: Optional[float] = typer.Option(None, "--delta", help="Stribeck exponent > 0 [2]."),
    viscous: Optional[float] = typer.Option(None, "--viscous", help="Viscous friction coefficient >= 0 (Stribeck) [0]."),
    dimensional: Optional[str] = typer.Option(
        None, "--dimensional", help="Dimensional input instead: 'm=..,c=..,k=..,v_b=..,f_d=..[,f_ms=..,v_d=..,l_0=..]'."
    ),
    x0: Optional[float] = typer.Option(None, "--x0", help="Initial X [F_d]."),
    v0: Optional[float] = typer.Option(None, "--v0", help="Initial X' [V_b]."),
    t_end: Optional[float] = typer.Option(None, "--t-end", help="End time tau > 0 [500]."),
    dt: Optional[float] = typer.Option(None, "--dt", help="RK4 step > 0 [1e-3]."),
    record_every: Optional[int] = typer.Option(None, "--record-every", help="Keep every k-th RK4 step."),
    dense_dt: Optional[float] = typer.Option(None, "--dense-dt", help="Exact/adaptive: also sample every DENSE_DT [2pi/200 with --out/--plot]."),
    ode_rtol: Optional[float] = typer.Option(None, "--ode-rtol", help="Adaptive solver's relative tolerance [1e-10]."),
    max_steps: Optional[int] = typer.Option(None, "--max-steps", help="Adaptive solver's step cap [1e7]."),
    solver: Optional[str] = typer.Option(None, "--solver", help="auto (exact for karnopp/coulomb, adaptive for stribeck), exact, adaptive or rk4 [auto]."),
    friction: Optional[str] = typer.Option(None, "--friction", help="Friction law: karnopp, coulomb or stribeck [karnopp]."),
    stick_force: Optional[str] = typer.Option(
        None, "--stick-force", help="Force held while sticking: resultant (X+2zeta X') or spring (X, the paper's) [resultant]."
    ),
    window: Optional[str] = typer.Option(None, "--window", help="Average over T0:T1 instead of the detected steady-state window."),
    rtol: Optional[float] = typer.Option(None, "--rtol", help="Steady-state convergence tolerance [rk4 1e-6, adaptive 1e-8, exact 1e-10]."),
    as_json: bool = typer.Option(False, "--json", help="Print one JSON object with the results to stdout."),
    out: Optional[Path] = typer.Option(None, "--out", help="Write the trajectory (.csv or .nc)."),
    plot: Optional[Path] = typer.Option(None, "--plot", help="Draw time history, phase portrait and power flow (.png, .pdf, .svg)."),
    config: Optional[Path] = typer.Option(None, "--config", help="TOML file with any of these options (names with underscores)."),
) -> None:
    """Simulate one run, find its steady state and report power flow and TR_B."""
    options = dict(
        fd=fd, fs=fs, vb=vb, zeta=zeta, vd=vd, vs=vs, delta=delta, viscous=viscous, x0=x0, v0=v0, t_end=t_end,
        dt=dt, record_every=record_every, dense_dt=dense_dt, ode_rtol=ode_rtol, max_steps=max_steps,
        solver=solver, friction=friction, stick_force=stick_force, window=window, rtol=rtol,
        dimensional=parse_dimensional(dimensional) if dimensional is not None else None,
    )
    cfg = merged_config(config, options)
    # Output paths are checked before any work so a bad one costs nothing.
    if out is not None:
        check_output_path(out, TRAJECTORY_FORMATS, "out")
    if plot is not None:
        check_output_path(plot, FIGURE_FORMATS, "plot")

    if (out is not None or plot is not None) and cfg.dense_dt is None:
        cfg.dense_dt = 2 * math.pi / 200  # files and figures want the curve, not just its switches
    if cfg.window is not None:
        # windows snap to samples: sample finely enough that a hand-set window lands within 1e-3
        cfg.dense_dt = min(cfg.dense_dt or 1e-3, 1e-3)
    model, law, solv = cfg.build()
    traj = run_simulation(model, law, solv, t_end=cfg.t_end, x0=cfg.x0, v0=cfg.v0, progress=sys.stderr.isatty())
    result = analyze(traj, window=cfg.window, rtol=cfg.rtol)
    report = result.to_dict()
    if cfg.dimensional is not None:
        report["dimensional"] = cfg.dimensional | {"omega0": model_omega0(cfg)}
    if out is not None:
        write_trajectory(traj, out)
    if plot is not None:
        from ..plotting import plot_run

        plot_run(result, plot)
    if as_json:
        print(json.dumps(report))
    else:
        _print_summary(report)


def model_omega0(cfg: RunConfig) -> float:
    from ..params import DimensionalParams

    return DimensionalParams(**cfg.dimensional).omega0  # type: ignore[arg-type]


def _print_summary(report: dict[str, Any]) -> None:
    from rich.console import Console
    from rich.table import Table

    ss = report["steady_state"]
    table = Table(title=f"steady state: {ss['kind']}  window {ss['window'][0]:.6g}..{ss['window'][1]:.6g}")
    table.add_column("quantity")
    table.add_column("value", justify="right")
    if ss["period"] is not None:
        table.add_row("period", f"{ss['period']:.10g}")
    if ss["decay_rate"] is not None:
        table.add_row("decay rate", f"{ss['decay_rate']:.6g} (heading: {ss['heading']})")
    for k, v in report["averages"].items():
        table.add_row(k, "n/a" if v is None else f"{v:.6e}")
    table.add_row("TR_B", "n/a" if report["TR_B"] is None else f"{report['TR_B']:.6g}")
    for k, v in report["amplitude"].items():
        table.add_row(k, f"{v:.6g}")
    table.add_row("energy residual", f"{report['energy_residual']:.2e}")
    Console().print(table)
