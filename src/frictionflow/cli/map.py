"""``frictionflow map``: a stability chart in two parameters -- Hopf, grazing and fold curves over a sweep heat map."""

from __future__ import annotations

import json
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any, Optional

import numpy as np

from .._ranges import Range, parse_named_range
from ..basins.study import check_store, write_dataset
from ..friction.registry import switch_law_names
from ..io import check_output_path
from ..orbits.chart import CURVES, stability_map
from ..orbits.chart_plot import plot_chart
from ..orbits.forced_chart import FORCED_CURVES, forced_map
from ..parameters import Param
from ..plotting import FIGURE_FORMATS
from ..sweep.compute import VARIABLES
from ._app import app
from .options import (CONFIG_OPTION, check_varied, command_config, parameter_names, refuse_fixed, renamed,
                      with_options, with_parameters)
from .output import FLOW_MAP, print_summary, provenance, write_json
from .vocabulary import ORDER, check_term, option, overlay_shape, parameter_help

MODEL = parameter_names(("oscillator", "law"), run=("t_end", "friction", "dimensional"))
#: the command's own settings, with their ranges (bounded: the cost grows with them)
COMMAND_PARAMETERS = {
    "x_points": Param("--x N", "", "values of the first parameter", "run", 41, kind="int", lower=2, upper=10_000),
    "scan": Param("--y N", "", "scan points of the second parameter", "run", 201, kind="int", lower=3, upper=1_000_000),
    "y_points": Param("--y N", "", "grid values of the second parameter (forced maps)", "run", 5, kind="int", lower=1,
                      upper=10_000),
}
#: a map in these runs the forced system's curves (continued in x at each y of a grid)
FORCING = ("omega", "fex")
DATASET_FORMATS = (".nc", ".zarr", ".json")
#: the command list's line (click would cut the docstring); cli.SHORT_HELP may name it too
SHORT_HELP = "Stability chart in two parameters: Hopf, grazing, fold (and forced: period-doubling) curves."


@dataclass(frozen=True)
class MapOptions:
    """The map command's own options (the model's come as ``params``), each with its typer option."""

    x: str = option("--x", "Here: N values, the curves' resolution in x [41].", required=True)
    y: str = option("--y", "Here: N points, the scan for sign changes [201]; forced maps, the grid [5].",
                    required=True)
    curves: Optional[str] = option("--curves")
    m: str = option("--m", "Here: forced maps (e.g. 1,2).")
    fold_every: int = option("--fold-every")
    overlay: str = option("--overlay", "Here: NXxNY simulations over the plane, a heat map (e.g. 40x30).")
    heat: str = option("--heat")
    store: Optional[Path] = option("--store", "Here: the --overlay sweep [a temporary file].")
    out: Optional[Path] = option("--out", "Here: the curves (and the overlay) as an xarray dataset, .nc or .zarr; "
                                 "or the JSON object, .json.")
    as_json: bool = option("--json")
    plot: Optional[Path] = option("--plot", "Here: the stability chart, the curves over the heat map.")
    dpi: float = option("--dpi")
    config: Optional[Path] = CONFIG_OPTION


@dataclass(frozen=True)
class Plane:
    """The two parameters of a map and their ranges (N of y: None, the kind of map's default)."""

    x: str
    xs: Range
    y: str
    ys: Range

    @classmethod
    def of(cls, opts: MapOptions) -> "Plane":
        x, xs = parse_named_range("--x", opts.x, "optional")
        y, ys = parse_named_range("--y", opts.y, "optional")
        return cls(x, xs, y, ys)

    @property
    def forced(self) -> bool:
        return self.x in FORCING or self.y in FORCING or "phi" in (self.x, self.y)


@app.command("map", short_help=SHORT_HELP)
@with_parameters(MODEL, parameter_help("map", MODEL, {"t_end": "Here: the length of each --overlay simulation."}))
@with_options(MapOptions)
def map_(params: dict[str, Any], opts: MapOptions) -> None:
    """Stability chart in two parameters: the Hopf curve of steady sliding (with its criticality and Bautin points),
    the grazing curve of the stick-slip cycle, fold curves of cycles and where a fold meets the grazing.  With
    --x/--y among omega and fex: the forced system's fold, period-doubling, Neimark-Sacker and grazing curves."""
    plane = Plane.of(opts)
    for flag, name in (("--x", plane.x), ("--y", plane.y)):
        refuse_fixed(name, flag, "across the chart", opts.config, params)
    nx = _count("x_points", plane.xs.num)
    if plane.forced:
        _forced_map(params, opts, plane, nx)
        return
    n_scan = _count("scan", plane.ys.num)
    curve_list = _curve_list(opts.curves, CURVES, "")
    shape = _overlay(opts)
    _check_outputs(opts)
    cfg = command_config("map", opts.config, params)
    model, law, _ = cfg.build()
    for flag, name in (("--x", plane.x), ("--y", plane.y)):
        check_varied(flag, name, law)
    xs = plane.xs.grid(nx)
    chart = stability_map(model, law, plane.x, xs, plane.y, (plane.ys.start, plane.ys.stop), sweep_shape=shape,
                          sweep_out=opts.store, t_end=cfg.given.get("t_end", 500.0), heat=opts.heat,
                          sweep_name="--store", curves=curve_list, n_scan=n_scan, fold_every=opts.fold_every)
    _report(chart, opts, provenance(law, "auto", cfg.dimensional))


def _count(name: str, given: int | None) -> int:
    """N of a range, checked by its declaration (None: its default)."""
    p = COMMAND_PARAMETERS[name]
    return p.default if given is None else p.check(given)


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
    if opts.out is not None:
        check_output_path(opts.out, DATASET_FORMATS, "--out")
    if opts.store is not None:  # the sweep's own store (resumable), never the chart's dataset
        check_store(opts.store, opts.out, "--store", "--out")


def _report(chart, opts: MapOptions, caption: str) -> None:  # noqa: ANN001
    """The chart's figure and dataset where asked, then its JSON or table on stdout."""
    if opts.plot is not None:
        plot_chart(chart, opts.plot, name="--plot", dpi=opts.dpi)
    if opts.out is not None and opts.out.suffix == ".json":
        write_json(opts.out, chart.to_dict())
    elif opts.out is not None:
        _write_dataset(chart.to_xarray(), opts.out)
    if opts.as_json:
        print(json.dumps(chart.to_dict(), allow_nan=False))
    else:
        print_summary(chart, caption)


def _orders(text: str) -> tuple[int, ...]:
    """``--m``: comma-separated periods in forcing periods, each in --m's range (:data:`~.vocabulary.ORDER`)."""
    try:
        out = tuple(int(v) for v in text.split(",") if v.strip())
    except ValueError:
        out = ()
    if not out:
        raise ValueError(f"--m must be comma-separated integers, {ORDER.range_text}, got {text!r}")
    return tuple(check_term("--m", v) for v in out)


def _overlay(opts: MapOptions) -> tuple[int, int] | None:
    """``--overlay NXxNY`` (None: none), and ``--heat`` checked with it: a variable of the sweep (unused without)."""
    shape = overlay_shape(opts.overlay)
    names = [v[0] for v in VARIABLES]
    if shape is not None and opts.heat not in names:
        raise ValueError(f"--heat must be a sweep variable ({', '.join(names)}), got {opts.heat!r}")
    return shape


def _check_forced_plane(plane: Plane) -> None:
    """Both parameters among the forcing's, distinct, with finite positive ends and two distinct x ends."""
    for flag, name in (("--x", plane.x), ("--y", plane.y)):
        if name not in FORCING:
            raise ValueError(f"{flag}: a forced map needs both parameters among {', '.join(FORCING)}, got {name!r}")
    if plane.x == plane.y:
        raise ValueError(f"--y must differ from --x ({plane.x!r})")
    for flag, name, value in (("--x", plane.x, plane.xs.start), ("--x", plane.x, plane.xs.stop),
                              ("--y", plane.y, plane.ys.start), ("--y", plane.y, plane.ys.stop)):
        if not value > 0:
            raise ValueError(f"{flag}: {name} must be finite and > 0 here, got {value!r}")
    if plane.xs.start == plane.xs.stop:
        raise ValueError(f"--x: TO must differ from FROM ({plane.xs.start!r})")


def _forced_map(params: dict[str, Any], opts: MapOptions, plane: Plane, nx: int) -> None:
    """The forced system's chart: continuation in x at each of N values of y (N of --y)."""
    _check_forced_plane(plane)
    ny = _count("y_points", plane.ys.num)
    curve_list = _curve_list(opts.curves, FORCED_CURVES, " for a forced map")
    orders = _orders(opts.m)
    shape = _overlay(opts)
    _check_outputs(opts)
    cfg = command_config("map", opts.config, params)
    model, law, _ = cfg.build()
    if law.stick_rule != "switch":
        raise ValueError(f"--friction: forced maps need Coulomb's stick rule ({', '.join(switch_law_names())}), got {law.name}")
    x, y, (x0, x1), (y0, y1) = plane.x, plane.y, (plane.xs.start, plane.xs.stop), (plane.ys.start, plane.ys.stop)
    model = replace(model, **{x: float(x0), y: float(y0)})
    ys = plane.ys.grid(ny) if ny > 1 else np.array([float(y0)])
    try:
        chart = forced_map(model, law, x, (x0, x1), y, ys, sweep_shape=shape, sweep_out=opts.store,
                           t_end=cfg.given.get("t_end", 500.0), heat=opts.heat, sweep_y_range=(y0, y1),
                           m=orders, x_start=float(x0), curves=curve_list)
    except (ValueError, RuntimeError) as e:  # forced_map names its store by the API's argument
        raise renamed(e, "sweep_out", "--store", everywhere=True) from None
    _report(chart, opts, provenance(law, FLOW_MAP, cfg.dimensional))


def _write_dataset(ds, path: Path) -> None:
    """NetCDF or Zarr by the extension, atomically: complete or not at all (a failure in one line)."""
    write_dataset(ds, path, "--out")
