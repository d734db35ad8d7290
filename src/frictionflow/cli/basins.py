"""``frictionflow basins``: basins of attraction and basin stability over initial states.

Exit codes as for ``frictionflow sweep``: 0 done, 1 a failure that is not
the input's fault (the sweep's store in use, an interruption), 2 bad input.
"""

from __future__ import annotations

import json
import sys
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Optional

from .._display import num
from ..basins import Tolerances, basins as run_basins
from ..basins.labels import check_tolerance
from ..basins.study import SweepOptions, check_dataset_path, check_design, check_store, store_path
from ..io import check_output_path
from ..plotting import FIGURE_FORMATS
from ..sweep.config import NOT_IN_SWEEPS
from ._app import Interrupted, app
from .._ranges import parse_range as _parse_range
from .options import CONFIG_OPTION, command_config, parameter_names, with_options, with_parameters
from .output import provenance, show
from .vocabulary import option, parameter_help

#: the model's options, as a sweep takes them; the initial state is a range here (--x0, --v0), not a value
MODEL = tuple(n for n in parameter_names(("oscillator", "law", "solver"), run=("t_end", "friction", "solver", "rtol", "max_memory"))
              if n not in NOT_IN_SWEEPS)


@dataclass(frozen=True)
class BasinsOptions:
    """The basins command's own options (the model's come as ``params``), each with its typer option."""

    x0_range: str = option("--x0-range", required=True)
    v0_range: str = option("--v0-range", required=True)
    sample: Optional[int] = option("--sample")
    seed: int = option("--seed")
    vary: Optional[str] = option("--vary", "Here: basin stability against one parameter (vb, zeta, fd, ...), the same "
                                 "initial states at each value; or NAME=V1,V2,..")
    attractor_tol: Optional[float] = option("--attractor-tol", "Here: in (0, 1); never finer than the solver resolves "
                                            "(10 x its steady-state rtol, and 10 dt for RK4: 1e-2 at its default dt).")
    out: Optional[Path] = option("--out", "Here: the labelled dataset, .nc or .zarr.")
    plot: Optional[Path] = option("--plot", "Here: the basin map, or with --vary basin stability against the parameter.")
    dpi: float = option("--dpi")
    store: Optional[Path] = option("--store", "Here: [beside --out, removed once --out is written].")
    restart: bool = option("--restart")
    chunk_size: Optional[int] = option("--chunk-size")
    scheduler: Optional[str] = option("--scheduler")
    as_json: bool = option("--json")
    config: Optional[Path] = CONFIG_OPTION


@app.command(short_help="Basins of attraction and basin stability over initial states.")
@with_parameters(MODEL, parameter_help("basins", MODEL, {"t_end": "Here: the length of every simulation; points not "
                                                                  "settled by then are labelled not_settled."}))
@with_options(BasinsOptions)
def basins(params: dict[str, Any], opts: BasinsOptions) -> None:
    """Basins of attraction of the initial states at fixed parameters: attractors, basin stability (with binomial standard errors), map and dataset."""
    cfg = command_config("basins", opts.config, params)
    settings, (_, law, solver) = cfg.given, cfg.build()
    tol = opts.attractor_tol
    if tol is not None:  # checked under the option's name: Tolerances would name its field (period), not the option
        check_tolerance("--attractor-tol", tol)
    tolerances = Tolerances() if tol is None else Tolerances(period=tol, amplitude=tol, stick=tol)
    grid = opts.sample is None
    x, v = parse_range("--x0-range", opts.x0_range, grid), parse_range("--v0-range", opts.v0_range, grid)
    check_design(x, v, opts.sample, opts.seed, OPTION_NAMES)
    _check_outputs(opts.out, opts.plot, opts.store)
    run = SweepOptions(store=opts.store, restart=opts.restart, chunk_size=opts.chunk_size, scheduler=opts.scheduler,
                       progress=sys.stderr.isatty(), store_name="--store", out_name="--out")
    try:
        result = run_basins(settings, x0=x, v0=v, sample=opts.sample, seed=opts.seed, vary=parse_vary(opts.vary), out=opts.out,
                            plot=opts.plot, dpi=opts.dpi, tolerances=tolerances, sweep_options=run)
    except KeyboardInterrupt:
        raise _interrupted(opts.store, opts.out) from None
    if opts.as_json:
        print(json.dumps(result.to_dict(), allow_nan=False))
    else:
        _print(result, provenance(law, solver))


#: how messages name the initial states' arguments here: by their options
OPTION_NAMES = {"x0": "--x0-range", "v0": "--v0-range", "sample": "--sample", "seed": "--seed"}


def _check_outputs(out: Optional[Path], plot: Optional[Path], store: Optional[Path]) -> None:
    """Refuse, before any work and naming the option, outputs that could not be written."""
    if out is not None:
        check_dataset_path(out, "--out")  # (a .zarr is a directory: an existing Zarr store is replaced, nothing else)
    if store is not None:
        check_store(store, out, "--store", "--out")
    if plot is not None:
        check_output_path(plot, FIGURE_FORMATS, "--plot")


def _interrupted(store: Optional[Path], out: Optional[Path]) -> Interrupted:
    """The line for a run stopped by Ctrl-C or SIGTERM: what its sweep's store keeps, if anything."""
    path = store_path(store, out)
    if path is None:  # a temporary store, removed
        return Interrupted("interrupted: nothing was kept (without --out or --store the sweep runs in a temporary "
                           "store); give --out or --store to make a run resumable")
    if path.exists():
        return Interrupted(f"interrupted: the sweep's store {str(path)!r} keeps the chunks finished so far; run the "
                           "same command to resume")
    return Interrupted("interrupted before the sweep's store was made: nothing was written")


def parse_range(name: str, text: str, with_count: bool) -> tuple:
    """``FROM:TO:N`` (a grid) or ``FROM:TO`` (a sample's range: --sample is N) -> a tuple; ValueError naming the
    option."""
    r = _parse_range(name + (" (with --sample, N is --sample's)" if not with_count else ""), text,
                     "required" if with_count else "none")
    return (r.start, r.stop, r.num) if with_count else (r.start, r.stop)


def parse_vary(text: Optional[str]) -> Optional[dict[str, Any]]:
    """``NAME=FROM:TO:N`` (a linear range) or ``NAME=V1,V2,...`` -> ``{name: values}`` as :func:`basins` takes."""
    if text is None:
        return None
    name, sep, values = text.partition("=")
    name = name.strip().replace("-", "_")
    if not sep or not name or not values.strip():
        raise ValueError(f"--vary must be NAME=FROM:TO:N or NAME=V1,V2,..., got {text!r}")
    if ":" in values:
        r = _parse_range(f"--vary {name}", values.strip())
        return {name: {"start": r.start, "stop": r.stop, "num": r.num}}
    try:
        return {name: [float(v) for v in values.split(",")]}
    except ValueError:
        raise ValueError(f"--vary must be NAME=FROM:TO:N or NAME=V1,V2,... with numbers, got {text!r}") from None


def _print(result, caption: str) -> None:  # noqa: ANN001
    """The outcomes as a table (with --vary: basin stability per value)."""
    from rich.console import Console
    from rich.table import Table

    console = Console()
    title, _ = result._summary()
    if result.vary is None:
        table = Table(title=title)
        table.add_column("outcome", no_wrap=True)
        for col in ("code", "fraction", "s.e.", "period", "amplitude", "stick"):
            table.add_column(col, justify="right")
        for o in result.outcomes():
            table.add_row(o["name"], str(o["code"]), f"{o['fraction']:.4f}", f"{o['stderr']:.4f}", num(o["period"]), num(o["amplitude"], 4),
                          num(o["stick_fraction"], 4))
    else:
        report = result.to_dict()["results"]
        reached = [j for j, o in enumerate(report[0]["outcomes"]) if any(r["outcomes"][j]["count"] for r in report)]
        table = Table(title=f"basin stability ± standard error, {result.design['points']} initial states ({result.design['kind']})")
        table.add_column(result.vary, justify="right")
        for j in reached:
            table.add_column(report[0]["outcomes"][j]["name"], justify="right", no_wrap=True)
        for r in report:
            table.add_row(num(r[result.vary]), *(f"{r['outcomes'][j]['fraction']:.3f} ± {r['outcomes'][j]['stderr']:.3f}" for j in reached))
    show(console, table, caption)
    for key in ("out", "plot"):
        if key in result.files:
            console.print(f"{key}: {result.files[key]}")
