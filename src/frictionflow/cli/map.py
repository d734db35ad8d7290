"""``frictionflow map``: a stability chart in two parameters -- Hopf, grazing and fold curves over a sweep heat map."""

from __future__ import annotations

import json
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any, Optional

import numpy as np
import typer

from .._display import spoken
from ..basins.study import write_dataset
from ..friction.registry import SMOOTH_SWITCH_LAW, switch_law_names
from ..io import check_output_path
from ..orbits.chart import CURVES, stability_map
from ..orbits.chart_plot import plot_chart
from ..orbits.forced_chart import FORCED_CURVES, forced_map
from ..parameters import Param
from ..plotting import FIGURE_FORMATS
from ._app import app
from .options import CONFIG_OPTION, PATH_METAVAR, merged_config, parameter_names, path_text, with_options, with_parameters

MODEL = parameter_names(("oscillator", "law"), run=("t_end", "friction", "dimensional"))
HELP = {"t_end": "Length of each sweep simulation (the heat map) [500].",
        "friction": f"Friction law with Coulomb's stick rule: {spoken(switch_law_names())} [{SMOOTH_SWITCH_LAW}]."}
#: the command's own settings, with their ranges (bounded: the cost grows with them)
COMMAND_PARAMETERS = {p.name: p for p in (
    Param("x_points", "", "values of the first parameter", "run", 41, kind="int", lower=2, upper=10_000),
    Param("scan", "", "scan points of the second parameter", "run", 201, kind="int", lower=3, upper=1_000_000),
    Param("fold_every", "", "x values between fold seeds", "run", 2, kind="int", lower=1, upper=10_000),
    Param("y_points", "", "grid values of the second parameter (forced maps)", "run", 5, kind="int", lower=1, upper=10_000),
)}
#: a map in these runs the forced system's curves (continued in x at each y of a grid)
FORCING = ("omega", "fex")
DATASET_FORMATS = (".nc", ".zarr")
#: the command list's line (click would cut the docstring); cli.SHORT_HELP may name it too
SHORT_HELP = "Stability chart in two parameters: Hopf, grazing, fold (and forced: period-doubling) curves."


def _shape(text: str) -> tuple[int, int] | None:
    """``NXxNY`` (e.g. 40x30) or 0 for no sweep."""
    if text.strip() in ("", "0"):
        return None
    try:
        nx, ny = (int(v) for v in text.lower().split("x"))
    except ValueError:
        raise ValueError(f"--sweep must be NXxNY (e.g. 40x30) or 0, got {text!r}") from None
    if not (2 <= nx <= 2000 and 2 <= ny <= 2000):
        raise ValueError(f"--sweep must have 2..2000 points per axis, got {text!r}")
    return nx, ny


@dataclass(frozen=True)
class MapOptions:
    """The map command's own options (the model's come as ``params``), each with its typer option."""

    x: str = typer.Option("vb", "--x", help="First parameter (horizontal axis).")
    x_from: float = typer.Option(..., "--x-from", help="First value of the first parameter.")
    x_to: float = typer.Option(..., "--x-to", help="Last value of the first parameter.")
    x_points: int = typer.Option(41, "--x-points", help="Values of the first parameter (the curves' resolution in x).")
    y: str = typer.Option("zeta", "--y", help="Second parameter (vertical axis).")
    y_from: float = typer.Option(..., "--y-from", help="Lower end of the second parameter.")
    y_to: float = typer.Option(..., "--y-to", help="Upper end of the second parameter.")
    scan: int = typer.Option(201, "--scan", help="Scan points in y where sign changes are looked for (each root is then refined).")
    curves: Optional[str] = typer.Option(None, "--curves", help="Curves to compute (comma-separated): hopf, grazing, fold "
                                         "[all]; forced (--x/--y omega, fex): fold, period_doubling, neimark_sacker, grazing [all].")
    y_points: int = typer.Option(5, "--y-points", help="Forced maps: grid values of the second parameter; at each the "
                                 "orbits are continued in the first over [--x-from, --x-to] from --x-from.")
    m: str = typer.Option("1", "--m", help="Forced maps: periods of the orbits followed, in forcing periods (e.g. 1,2).")
    fold_every: int = typer.Option(2, "--fold-every", help="A continuation in y seeds fold curves at every n-th x value.")
    sweep: str = typer.Option("0", "--sweep", help="Heat map: NXxNY simulations over the plane (e.g. 40x30); 0 for none.")
    heat: str = typer.Option("R_c", "--heat", help="Sweep variable of the heat map (R_c, TR_B, P_fin, ...).")
    sweep_out: Optional[Path] = typer.Option(None, "--sweep-out", parser=path_text, metavar=PATH_METAVAR, help="Keep the sweep here (.zarr or .nc) [a temporary file].")
    dataset: Optional[Path] = typer.Option(None, "--dataset", parser=path_text, metavar=PATH_METAVAR, help="Write the curves (and the sweep) as an xarray dataset (.nc, .zarr).")
    as_json: bool = typer.Option(False, "--json", help="Print one JSON object (curves, codimension-two points) to stdout.")
    plot: Optional[Path] = typer.Option(None, "--plot", parser=path_text, metavar=PATH_METAVAR, help="Stability chart: the curves over the heat map (.png, .pdf, .svg).")
    config: Optional[Path] = CONFIG_OPTION


@app.command("map", short_help=SHORT_HELP)
@with_parameters(MODEL, HELP)
@with_options(MapOptions)
def map_(params: dict[str, Any], opts: MapOptions) -> None:
    """Stability chart in two parameters: the Hopf curve of steady sliding (with its criticality and Bautin points),
    the grazing curve of the stick-slip cycle, fold curves of cycles and where a fold meets the grazing.  With
    --x/--y among omega and fex: the forced system's fold, period-doubling, Neimark-Sacker and grazing curves."""
    for name in ("x_points", "scan", "fold_every", "y_points"):
        COMMAND_PARAMETERS[name].check(getattr(opts, name))
    if opts.x in FORCING or opts.y in FORCING or "phi" in (opts.x, opts.y):
        _forced_map(params, opts)
        return
    curve_list = _curve_list(opts.curves, CURVES, "")
    shape = _shape(opts.sweep)
    _check_outputs(opts)
    cfg = _config(params, opts.config)
    model, law, _ = cfg.build()
    xs = np.linspace(opts.x_from, opts.x_to, opts.x_points)
    chart = stability_map(model, law, opts.x, xs, opts.y, (opts.y_from, opts.y_to), sweep_shape=shape,
                          sweep_out=opts.sweep_out, t_end=cfg.given.get("t_end", 500.0), heat=opts.heat,
                          curves=curve_list, n_scan=opts.scan, fold_every=opts.fold_every)
    _report(chart, opts)


def _curve_list(text: Optional[str], allowed: tuple[str, ...], what: str) -> tuple[str, ...]:
    """``--curves``: comma-separated names among ``allowed`` (None: all of them)."""
    out = tuple(c.strip() for c in (text or ",".join(allowed)).split(",") if c.strip())
    for c in out:
        if c not in allowed:
            raise ValueError(f"--curves must be among {', '.join(allowed)}{what}, got {c!r}")
    return out


def _check_outputs(opts: MapOptions) -> None:
    """The output paths, before any work: a bad path writes nothing."""
    if opts.plot is not None:
        check_output_path(opts.plot, FIGURE_FORMATS, "--plot")
    if opts.dataset is not None:
        check_output_path(opts.dataset, DATASET_FORMATS, "--dataset")


def _config(params: dict[str, Any], config: Optional[Path]):
    """The run's config: the file's values, the options given, and the registry's law with a stick rule by default."""
    given = dict(params)
    if given.get("friction") is None:
        given["friction"] = SMOOTH_SWITCH_LAW
    return merged_config(config, given)


def _report(chart, opts: MapOptions) -> None:
    """The chart's figure and dataset where asked, then its JSON or summary on stdout."""
    if opts.plot is not None:
        plot_chart(chart, opts.plot, name="--plot")
    if opts.dataset is not None:
        _write_dataset(chart.to_xarray(), opts.dataset)
    if opts.as_json:
        print(json.dumps(chart.to_dict(), allow_nan=False))
    else:
        print(repr(chart))


def _orders(text: str) -> tuple[int, ...]:
    """``--m``: comma-separated periods in forcing periods, 1..1000."""
    try:
        out = tuple(int(v) for v in text.split(",") if v.strip())
    except ValueError:
        out = ()
    if not out or not all(1 <= v <= 1000 for v in out):
        raise ValueError(f"--m must be comma-separated integers in [1, 1000], got {text!r}")
    return out


def _check_forced_plane(opts: MapOptions) -> None:
    """Both parameters among the forcing's, distinct, with finite positive ends and two distinct x ends."""
    for flag, name in (("--x", opts.x), ("--y", opts.y)):
        if name not in FORCING:
            raise ValueError(f"{flag}: a forced map needs both parameters among {', '.join(FORCING)}, got {name!r}")
    if opts.x == opts.y:
        raise ValueError(f"--y must differ from --x ({opts.x!r})")
    for flag, value in (("--x-from", opts.x_from), ("--x-to", opts.x_to), ("--y-from", opts.y_from), ("--y-to", opts.y_to)):
        if not (np.isfinite(value) and value > 0):
            raise ValueError(f"{flag}: {opts.x if flag.startswith('--x') else opts.y} must be finite and > 0 here, got {value!r}")
    if opts.x_from == opts.x_to:
        raise ValueError(f"--x-to must differ from --x-from ({opts.x_from!r})")


def _forced_map(params: dict[str, Any], opts: MapOptions) -> None:
    """The forced system's chart: continuation in x at each of ``y_points`` values of y."""
    _check_forced_plane(opts)
    curve_list = _curve_list(opts.curves, FORCED_CURVES, " for a forced map")
    orders = _orders(opts.m)
    shape = _shape(opts.sweep)
    _check_outputs(opts)
    cfg = _config(params, opts.config)
    model, law, _ = cfg.build()
    if law.stick_rule != "switch":
        raise ValueError(f"--friction: forced maps need Coulomb's stick rule ({', '.join(switch_law_names())}), got {law.name}")
    x, y = opts.x, opts.y
    model = replace(model, **{x: float(opts.x_from), y: float(opts.y_from)})
    ys = np.linspace(opts.y_from, opts.y_to, opts.y_points) if opts.y_points > 1 else np.array([float(opts.y_from)])
    chart = forced_map(model, law, x, (opts.x_from, opts.x_to), y, ys, sweep_shape=shape, sweep_out=opts.sweep_out,
                       t_end=cfg.given.get("t_end", 500.0), heat=opts.heat, sweep_y_range=(opts.y_from, opts.y_to),
                       m=orders, x_start=float(opts.x_from), curves=curve_list)
    _report(chart, opts)


def _write_dataset(ds, path: Path) -> None:
    """NetCDF or Zarr by the extension, atomically: complete or not at all (a failure in one line)."""
    write_dataset(ds, path, "--dataset")
