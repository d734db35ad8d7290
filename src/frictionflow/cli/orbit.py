"""``frictionflow orbit`` and ``frictionflow continue``: periodic orbits, Floquet multipliers, continuation."""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Optional

import numpy as np
import typer

from .._display import spoken
from ..config import RunConfig
from ..io import check_input_path, check_output_path
from ..orbits import continuation, find_orbit
from ..orbits.floquet import fd_monodromy
from ..orbits.monitors import MONITORS, branch_extrema
from ..orbits.plotting import plot_bifurcation, plot_orbit
from ..orbits.settings import ContinuationSettings
from ..parameters import Param
from ..plotting import FIGURE_FORMATS
from ..solvers.registry import solver_names_where
from ._app import app
from .options import CONFIG_OPTION, DPI_OPTION, PATH_METAVAR, merged_config, parameter_names, path_text, with_options, with_parameters

MODEL = parameter_names(("oscillator", "law"), run=("x0", "v0", "t_end", "friction", "solver", "dimensional"))
#: orbits need located switches: every solver but the fixed-step ones
LOCATING = ("auto", *solver_names_where(lambda cls: not cls.fixed_step))
SOLVER_HELP = f"Solver of the transient and the power-flow period: {spoken(LOCATING)} [auto]."


#: the orbit commands' own settings, with their ranges (bounded: each point costs a shooting or a simulation)
COMMAND_PARAMETERS = {p.name: p for p in (
    Param("returns", "", "crossings of the section per period", "run", 1, kind="int", lower=1, upper=64),
    Param("tol", "", "Newton tolerance", "run", None, lower=0.0, lower_open=True, upper=1e-3),
    Param("points", "", "grid points of the equilibrium branch", "run", 101, kind="int", lower=2, upper=100_000),
    Param("max_points", "", "points per orbit branch", "run", 300, kind="int", lower=2, upper=100_000),
    Param("sweep", "", "brute-force simulations", "run", 0, kind="int", lower=0, upper=10_000),
    Param("max_period", "", "period at which a branch ends", "run", 500.0, lower=0.0, lower_open=True, upper=1e6),
    Param("step", "", "first arclength step", "run", 0.02, lower=0.0, lower_open=True, upper=1.0),
)}


def _check(**values: Any) -> None:
    for name, value in values.items():
        if value is not None:
            COMMAND_PARAMETERS[name].check(value)


def _config(config: Optional[Path], params: dict[str, Any]) -> RunConfig:
    if config is not None:
        check_input_path(config, "--config")  # before reading it, naming the option
    cfg = merged_config(config, params)
    if cfg.solver not in LOCATING:
        raise ValueError(f"solver={cfg.solver} cannot locate switches exactly; use {spoken(LOCATING)} for orbits")
    return cfg


def _dump(report: dict[str, Any]) -> None:
    print(json.dumps(report, allow_nan=False))


@app.command()
@with_parameters(MODEL, {"x0": "Start X [F_d].", "v0": "Start X' [V_b].", "solver": SOLVER_HELP,
                         "t_end": "Transient simulated from the start before shooting [500]."})
def orbit(
    params: dict[str, Any],
    guess: bool = typer.Option(False, "--guess", help="Shoot from the start state itself, without a transient (to reach unstable orbits)."),
    returns: int = typer.Option(1, "--returns", help="Crossings of the section X'=0 per period (2: period-2 orbit)."),
    tol: Optional[float] = typer.Option(None, "--tol", help="Newton tolerance on P(X)-X relative to max(F_s, |V_b|) [1e-12 exact, 1e-9 smooth laws]."),
    fd_check: bool = typer.Option(False, "--fd-check", help="Also report the monodromy matrix by finite differences of simulations."),
    as_json: bool = typer.Option(False, "--json", help="Print one JSON object with the results to stdout."),
    plot: Optional[Path] = typer.Option(None, "--plot", parser=path_text, metavar=PATH_METAVAR, help="Draw the orbit: phase portrait, time history, power (.png, .pdf, .svg, .eps)."),
    dpi: float = DPI_OPTION,
    config: Optional[Path] = CONFIG_OPTION,
) -> None:
    """Find a periodic orbit by Newton shooting; report its Floquet multipliers, power flow and TR_B."""
    cfg = _config(config, params)
    _check(returns=returns, tol=tol)
    if plot is not None:
        check_output_path(plot, FIGURE_FORMATS, "--plot")  # before any work: a bad path writes nothing
    model, law, solv = cfg.build()
    found = find_orbit(model, law, x0=cfg.x0, v0=cfg.v0, transient=0.0 if guess else cfg.t_end, returns=returns, tol=tol, solver=solv)
    report = found.to_dict()
    if fd_check:
        M = fd_monodromy(model, law, found.state, found.period, solver=solv)
        report["fd_monodromy"] = M.tolist()
        report["fd_deviation"] = float(np.max(np.abs(M - found.monodromy)))
    if plot is not None:
        plot_orbit(found, plot, name="--plot", dpi=dpi)
    if as_json:
        _dump(report)
    else:
        _print_orbit(report)


@dataclass(frozen=True)
class ContinueOptions:
    """The continue command's own options (the model's come as ``params``), each with its typer option."""

    param: str = typer.Option(..., "--param", help="Parameter to continue: the oscillator's or the law's (zeta, vb, fd, ...).")
    start: float = typer.Option(..., "--from", help="Start value of the parameter.")
    stop: float = typer.Option(..., "--to", help="End value of the parameter.")
    seeds: str = typer.Option("hopf,start,stop", "--seeds", help="Where orbit branches start: hopf, start, stop (comma-separated).")
    points: int = typer.Option(101, "--points", help="Grid points of the equilibrium branch.")
    max_points: int = typer.Option(300, "--max-points", help="Points per orbit branch at most.")
    max_period: float = typer.Option(500.0, "--max-period", help="A branch ends (period_blowup) once its period exceeds this.")
    step: float = typer.Option(0.02, "--step", help="First arclength step, relative to the interval.")
    sweep: int = typer.Option(0, "--sweep", help="Overlay this many brute-force simulations across the interval.")
    monitor: str = typer.Option("", "--monitor", help="Locate the extrema of these per-orbit quantities along the branches "
                                "(comma-separated: P_fin, P_dv, P_df, R_c, R_f, P_belt, P_heat, TR_B, amplitude, stick_fraction, period).")
    tol: Optional[float] = typer.Option(None, "--tol", help="Newton tolerance on each orbit's X relative to max(F_s, |V_b|) [1e-12 exact, 1e-9 smooth laws].")
    as_json: bool = typer.Option(False, "--json", help="Print one JSON object (branches, bifurcations) to stdout.")
    plot: Optional[Path] = typer.Option(None, "--plot", parser=path_text, metavar=PATH_METAVAR, help="Bifurcation diagram and power along the branches (.png, .pdf, .svg, .eps).")
    dpi: float = DPI_OPTION
    config: Optional[Path] = CONFIG_OPTION


@app.command("continue")
@with_parameters(MODEL, {"x0": "Start X of the seed and sweep simulations [F_d].", "solver": SOLVER_HELP,
                         "v0": "Start X' of the seed and sweep simulations [V_b].",
                         "t_end": "Length of the seed and sweep simulations [500]."})
@with_options(ContinueOptions)
def continue_(params: dict[str, Any], opts: ContinueOptions) -> None:
    """Continue equilibria and periodic orbits in one parameter; report Hopf points, folds, grazing and power along branches."""
    monitors = tuple(m.strip() for m in opts.monitor.split(",") if m.strip())
    for m in monitors:
        if m not in MONITORS:
            raise ValueError(f"--monitor must be among {', '.join(MONITORS)}, got {m!r}")

    cfg = _config(opts.config, params)
    seed_list = tuple(s.strip() for s in opts.seeds.split(",") if s.strip())
    _check(points=opts.points, max_points=opts.max_points, sweep=opts.sweep, max_period=opts.max_period, step=opts.step, tol=opts.tol)
    if opts.plot is not None:
        check_output_path(opts.plot, FIGURE_FORMATS, "--plot")  # before any work: a bad path writes nothing
    model, law, solv = cfg.build()
    settings = ContinuationSettings(seeds=seed_list, transient=cfg.t_end, n_equilibria=opts.points, max_points=opts.max_points,
                                    max_period=opts.max_period, step=opts.step, sweep=opts.sweep, solver=solv, x0=cfg.x0,
                                    v0=cfg.v0, tol=opts.tol)
    result = continuation(model, law, opts.param, opts.start, opts.stop, settings=settings)
    if opts.plot is not None:
        plot_bifurcation(result, opts.plot, name="--plot", dpi=opts.dpi)
    report = result.to_dict()
    if monitors:
        report["extrema"] = [e.to_dict() for m in monitors for e in branch_extrema(result, m, model, law)]
    if opts.as_json:
        _dump(report)
    else:
        _print_continuation(report)


def _fmt(v: Any, spec: str = ".6g") -> str:
    return "n/a" if v is None else format(v, spec)


def _print_orbit(report: dict[str, Any]) -> None:
    from rich.console import Console
    from rich.table import Table

    table = Table(title=f"periodic orbit: {report['stability']}, period {report['period']:.10g}")
    table.add_column("quantity")
    table.add_column("value", justify="right")
    table.add_row("section point X (X'=0)", f"{report['state']['X']:.12g}")
    for i, (re, im) in enumerate(report["floquet_multipliers"]):
        table.add_row(f"Floquet multiplier {i + 1}", f"{re:.6g}{im:+.2g}j")
    table.add_row("phases", " -> ".join(p["mode"] for p in report["phases"]))
    table.add_row("stick fraction", f"{report['stick_fraction']:.6g}")
    table.add_row("amplitude (X_max-X_min)/2", f"{report['amplitude']:.6g}")
    for k, v in report["averages"].items():
        table.add_row(k, "n/a" if v is None else f"{v:.6e}")
    table.add_row("TR_B", _fmt(report["TR_B"]))
    table.add_row("energy residual", f"{report['energy_residual']:.2e}")
    if "fd_deviation" in report:
        table.add_row("max |M - M_fd|", f"{report['fd_deviation']:.2e}")
    Console().print(table)


def _print_continuation(report: dict[str, Any]) -> None:
    from rich.console import Console
    from rich.table import Table

    console = Console()
    table = Table(title=f"continuation in {report['param']} from {report['from']:g} to {report['to']:g}")
    for col in ("branch", "kind", "seed", "points", "range", "end"):
        table.add_column(col)
    for i, (pts, info) in enumerate(zip(report["branches"], report["branch_info"], strict=True)):
        vals = [p["value"] for p in pts]
        table.add_row(str(i), info["kind"], info["seed"], str(len(pts)), f"{min(vals):.6g}..{max(vals):.6g}", info["end"])
    console.print(table)
    bt = Table(title="bifurcations")
    for col in ("type", "value", "branch", "detail"):
        bt.add_column(col)
    for b in report["bifurcations"]:
        detail = ", ".join(f"{k}={v}" for k, v in b.items() if k not in ("type", "value", "branch"))
        bt.add_row(b["type"], f"{b['value']:.8g}", str(b["branch"]), detail)
    console.print(bt)
    if report.get("extrema"):
        et = Table(title="extrema of monitors along the branches")
        for col in ("monitor", "kind", "value", "monitor value", "branch", "method"):
            et.add_column(col)
        for e in report["extrema"]:
            et.add_row(e["monitor"], e["kind"], f"{e['value']:.10g}", f"{e['monitor_value']:.8g}", str(e["branch"]), e["method"])
        console.print(et)
