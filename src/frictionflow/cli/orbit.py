"""``frictionflow orbit`` and ``frictionflow continue``: periodic orbits, Floquet multipliers, continuation."""

from __future__ import annotations

import json
import sys
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Optional

import numpy as np

from .._display import spoken
from ..config import RunConfig
from ..io import check_output_path
from ..orbits import continuation, find_orbit
from ..orbits.floquet import fd_monodromy
from ..orbits.monitors import MONITORS, branch_extrema
from ..orbits.plotting import plot_bifurcation, plot_orbit
from ..orbits.settings import CONTINUATION_RANGES, ContinuationSettings
from ..orbits.stateful import StatefulOrbit, fd_state_monodromy
from ..parameters import Param
from ..plotting import FIGURE_FORMATS
from ..solvers.registry import solver_names_where
from .._ranges import parse_named_range
from ._app import app
from .options import (CONFIG_OPTION, check_option, check_varied, command_config, parameter_names, refuse_fixed,
                      with_dimensional, with_options, with_parameters)
from .output import provenance, show, write_json
from .structure_orbit import DEFAULT_TRANSIENT as MODEL_TRANSIENT, ModelOrbitOptions, orbit_model
from .vocabulary import option, overlay_count, parameter_help

MODEL = parameter_names(("oscillator", "law"), run=("x0", "v0", "t_end", "friction", "solver", "dimensional"))
#: orbits need located switches: every solver but the fixed-step ones
LOCATING = ("auto", *solver_names_where(lambda cls: not cls.fixed_step))
SOLVER_HELP = f"Here: the transient's and the power-flow period's, {spoken(LOCATING)}."
OUT_FORMATS = (".json",)


#: N of continue's --vary: the grid points of the equilibrium branch (the options' own numbers are checked by
#: their vocabulary terms as the command line is read: --returns, --tol, --max-points, --max-period, --step)
POINTS = Param("points", "", "N of --vary: grid points of the equilibrium branch", "run", 101, kind="int", lower=2,
               upper=100_000)
POINTS_NAME = "--vary N (grid points of the equilibrium branch)"


def _config(command: str, config: Optional[Path], params: dict[str, Any]) -> RunConfig:
    cfg = command_config(command, config, params)
    if cfg.solver not in LOCATING:
        raise ValueError(f"solver={cfg.solver} cannot locate switches exactly; use {spoken(LOCATING)} for orbits")
    return cfg


def _dump(report: dict[str, Any]) -> None:
    print(json.dumps(report, allow_nan=False))


@dataclass(frozen=True)
class OrbitOptions:
    """The orbit command's own options (the model's come as ``params``)."""

    guess: bool = option("--guess")
    returns: Optional[int] = option("--returns")
    tol: Optional[float] = option("--tol")
    fd_check: bool = option("--fd-check")
    as_json: bool = option("--json")
    out: Optional[Path] = option("--out", "Here: the JSON object, .json.")
    plot: Optional[Path] = option("--plot", "Here: phase portrait, time history and power of the orbit.")
    dpi: float = option("--dpi")
    config: Optional[Path] = CONFIG_OPTION
    model: Optional[Path] = option("--model", "Here: its periodic orbit, Floquet multipliers and element powers.")


#: what orbit's --solver and --t-end do here
ORBIT_DETAIL = {"solver": SOLVER_HELP,
                "t_end": f"Here: the transient before shooting (with --model: {MODEL_TRANSIENT:g} unless given)."}


@app.command()
@with_parameters(MODEL, parameter_help("orbit", MODEL, ORBIT_DETAIL))
@with_options(OrbitOptions)
def orbit(params: dict[str, Any], opts: OrbitOptions) -> None:
    """Find a periodic orbit by Newton shooting; report its Floquet multipliers, power flow and TR_B."""
    if opts.model is not None:
        model_opts = ModelOrbitOptions(opts.guess, opts.returns, opts.tol, opts.fd_check, opts.as_json, opts.out)
        return orbit_model(opts.model, params, model_opts, opts.config, opts.plot)
    cfg = _config("orbit", opts.config, params)
    _check_outputs(opts.out, opts.plot)  # before any work: a bad path writes nothing
    model, law, solv = cfg.build()
    found = find_orbit(model, law, x0=cfg.x0, v0=cfg.v0, transient=0.0 if opts.guess else cfg.t_end,
                       returns=1 if opts.returns is None else opts.returns,
                       tol=opts.tol, solver=solv)
    report = with_dimensional(found.to_dict(), cfg)
    stateful = isinstance(found, StatefulOrbit)
    if opts.fd_check:
        M = fd_state_monodromy(found) if stateful else fd_monodromy(model, law, found.state, found.period, solver=solv)
        report["fd_monodromy"] = M.tolist()
        report["fd_deviation"] = float(np.max(np.abs(M - found.monodromy)))
    if opts.plot is not None:
        if stateful:
            raise ValueError(f"--plot: the orbit figure draws orbits of the section map, not of friction={law.name} (use --out)")
        plot_orbit(found, opts.plot, name="--plot", dpi=opts.dpi)
    printer = _print_stateful_orbit if stateful else _print_orbit
    _report(report, opts.out, opts.as_json, lambda: printer(report, provenance(law, solv, cfg.dimensional)))


def _check_outputs(out: Optional[Path], plot: Optional[Path]) -> None:
    if out is not None:
        check_output_path(out, OUT_FORMATS, "--out")
    if plot is not None:
        check_output_path(plot, FIGURE_FORMATS, "--plot")


def _report(report: dict[str, Any], out: Optional[Path], as_json: bool, table) -> None:  # noqa: ANN001
    """The report to --out, then as JSON or as the table on stdout."""
    if out is not None:
        write_json(out, report)
    if as_json:
        _dump(report)
    else:
        table()


@dataclass(frozen=True)
class ContinueOptions:
    """The continue command's own options (the model's come as ``params``), each with its typer option."""

    vary: str = option("--vary", "Here: the oscillator's or the law's parameter (zeta, vb, fd, ...); N grid points "
                       "of the equilibrium branch [101].", required=True)
    seeds: str = option("--seeds")
    max_points: int = option("--max-points")
    max_period: float = option("--max-period")
    step: float = option("--step")
    overlay: str = option("--overlay", "Here: N simulations across the range.")
    monitor: str = option("--monitor")
    tol: Optional[float] = option("--tol")
    as_json: bool = option("--json")
    out: Optional[Path] = option("--out", "Here: the JSON object, .json.")
    plot: Optional[Path] = option("--plot", "Here: the bifurcation diagram and power along the branches.")
    dpi: float = option("--dpi")
    config: Optional[Path] = CONFIG_OPTION


@app.command("continue")
@with_parameters(MODEL, parameter_help("continue", MODEL, {"solver": SOLVER_HELP,
                                                          "t_end": "Here: the length of the seed and overlay simulations."}))
@with_options(ContinueOptions)
def continue_(params: dict[str, Any], opts: ContinueOptions) -> None:
    """Continue equilibria and periodic orbits in one parameter; report Hopf points, folds, grazing and power along branches."""
    monitors = tuple(m.strip() for m in opts.monitor.split(",") if m.strip())
    for m in monitors:
        if m not in MONITORS:
            raise ValueError(f"--monitor must be among {', '.join(MONITORS)}, got {m!r}")
    param, span = parse_named_range("--vary", opts.vary, "optional")
    refuse_fixed(param, "--vary", "along the branch", opts.config, params)
    overlay = overlay_count(opts.overlay)
    cfg = _config("continue", opts.config, params)
    seed_list = tuple(s.strip() for s in opts.seeds.split(",") if s.strip())
    points = POINTS.default if span.num is None else check_option(POINTS_NAME, POINTS, span.num)
    check_option("--overlay", CONTINUATION_RANGES["sweep"], overlay)  # (the API's sweep: brute-force simulations)
    _check_outputs(opts.out, opts.plot)  # before any work: a bad path writes nothing
    model, law, solv = cfg.build()
    check_varied("--vary", param, law)
    # (unset: F_d and V_b at each parameter value, as start_state says at one)
    settings = ContinuationSettings(seeds=seed_list, transient=cfg.t_end, n_equilibria=points, max_points=opts.max_points,
                                    max_period=opts.max_period, step=opts.step, sweep=overlay, solver=solv, x0=cfg.x0,
                                    v0=cfg.v0, tol=opts.tol, progress=sys.stderr.isatty())
    result = continuation(model, law, param, span.start, span.stop, settings=settings)
    if opts.plot is not None:
        plot_bifurcation(result, opts.plot, name="--plot", dpi=opts.dpi)
    report = with_dimensional(result.to_dict(), cfg)
    if monitors:
        report["extrema"] = [e.to_dict() for m in monitors for e in branch_extrema(result, m, model, law)]
    _report(report, opts.out, opts.as_json, lambda: _print_continuation(report, provenance(law, solv, cfg.dimensional)))


def _fmt(v: Any, spec: str = ".6g") -> str:
    return "n/a" if v is None else format(v, spec)


def _print_orbit(report: dict[str, Any], caption: str) -> None:
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
    show(Console(), table, caption)


def _print_stateful_orbit(report: dict[str, Any], caption: str) -> None:
    from rich.console import Console
    from rich.table import Table

    table = Table(title=f"periodic orbit on the whole state: {report['stability']}, period {report['period']:.10g}")
    table.add_column("quantity")
    table.add_column("value", justify="right")
    for name, value in report["state"].items():
        table.add_row(f"state {name}", f"{value:.12g}")
    for i, (re, im) in enumerate(report["floquet_multipliers"]):
        table.add_row(f"Floquet multiplier {i + 1}", f"{re:.6g}{im:+.2g}j")
    table.add_row("stick fraction", f"{report['stick_fraction']:.6g}")
    table.add_row("amplitude (X_max-X_min)/2", f"{report['amplitude']:.6g}")
    for k, v in report["averages"].items():
        table.add_row(k, "n/a" if v is None else f"{v:.6e}")
    table.add_row("TR_B", _fmt(report["TR_B"]))
    for k, v in report["interface_balance"].items():
        table.add_row(f"belt work: {k}", f"{v:.6e}")
    if "fd_deviation" in report:
        table.add_row("max |M - M_fd|", f"{report['fd_deviation']:.2e}")
    show(Console(), table, caption)


def _print_continuation(report: dict[str, Any], caption: str) -> None:
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
    show(console, bt, caption)
    if report.get("extrema"):
        et = Table(title="extrema of monitors along the branches")
        for col in ("monitor", "kind", "value", "monitor value", "branch", "method"):
            et.add_column(col)
        for e in report["extrema"]:
            et.add_row(e["monitor"], e["kind"], f"{e['value']:.10g}", f"{e['monitor_value']:.8g}", str(e["branch"]), e["method"])
        console.print(et)
