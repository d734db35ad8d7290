"""``frictionflow response``: the frequency response of the forced oscillator."""

from __future__ import annotations

import json
import sys
from pathlib import Path
from typing import Any, Optional

import numpy as np
import typer

from .. import quantities as Q
from ..analysis.response import DIRECTIONS, frequency_response
from ..io import atomic_write, check_input_path, check_output_path
from ..plotting import FIGURE_FORMATS, plot_response
from ._app import app
from .basins import parse_range
from .options import CONFIG_OPTION, DPI_OPTION, PATH_METAVAR, merged_config, parameter_names, path_text, with_parameters

DATASET_FORMATS = (".nc",)


@app.command()
@with_parameters(tuple(n for n in parameter_names(("oscillator", "law", "solver"), run=("x0", "v0", "friction", "solver"))
                       if n != "omega"))
def response(
    params: dict[str, Any],
    omega: str = typer.Option(..., "--omega", metavar="FROM:TO:N", help="Forcing frequencies: N points from FROM to TO."),
    periods: int = typer.Option(300, "--periods", help="Forcing periods simulated at each frequency."),
    direction: str = typer.Option("both", "--direction", help="Sweep up, down or both (jumps and hysteresis show with both)."),
    as_json: bool = typer.Option(False, "--json", help="Print the response as one JSON object."),
    out: Optional[Path] = typer.Option(None, "--out", parser=path_text, metavar=PATH_METAVAR, help="Write the response dataset (.nc)."),
    plot: Optional[Path] = typer.Option(None, "--plot", parser=path_text, metavar=PATH_METAVAR, help="Draw the response curves (.png, .pdf, .svg, .eps)."),
    dpi: float = DPI_OPTION,
    config: Optional[Path] = CONFIG_OPTION,
) -> None:
    """Frequency response: steady amplitude, power, TR_B and stick fraction against the forcing frequency."""
    if config is not None:
        check_input_path(config, "--config")
    w0, w1, n = parse_range("--omega", omega, with_count=True)
    if not (1 <= n <= 100_000):
        raise ValueError(f"--omega: N must be in [1, 100000], got {n}")
    if direction not in (*DIRECTIONS, "both"):
        raise ValueError(f"--direction must be up, down or both, got {direction!r}")
    if out is not None:
        check_output_path(out, DATASET_FORMATS, "--out")
    if plot is not None:
        check_output_path(plot, FIGURE_FORMATS, "--plot")
    cfg = merged_config(config, params)
    model, law, solver = cfg.build()
    ds = frequency_response(model, law, np.linspace(w0, w1, n) if n > 1 else [w0], solver=solver, periods=periods,
                            directions=DIRECTIONS if direction == "both" else (direction,), x0=cfg.x0, v0=cfg.v0,
                            rtol=cfg.rtol, progress=sys.stderr.isatty())
    if out is not None:
        with atomic_write(out, "--out") as tmp:
            ds.to_netcdf(tmp)
    if plot is not None:
        plot_response(ds, plot, name="--plot", dpi=dpi)
    if as_json:
        print(json.dumps(_as_json(ds)))
    else:
        _print_table(ds)


def _as_json(ds) -> dict[str, Any]:
    """Parameters, frequencies and each variable per direction (NaN as null)."""
    def plain(a: np.ndarray) -> list:
        return [None if isinstance(x, float) and not np.isfinite(x) else x for x in a.tolist()]

    return {"params": dict(ds.attrs), "omega": plain(ds["omega"].values),
            **{str(d): {v: plain(ds[v].sel(direction=d).values) for v in ds.data_vars} for d in ds["direction"].values}}


def _print_table(ds) -> None:
    from rich.console import Console
    from rich.table import Table

    table = Table(title="frequency response")
    for col in ("Omega", "sweep", "kind", "m", "amplitude", "TR_B", "P_ex", "stick"):
        table.add_column(col, justify="right")
    for j, w in enumerate(ds["omega"].values):
        for d in ds["direction"].values:
            s = ds.sel(direction=d).isel(omega=j)
            table.add_row(f"{w:.5g}", str(d), Q.KINDS[int(s["kind"])], str(int(s["multiple"])), f"{float(s['amplitude']):.5g}",
                          f"{float(s['TR_B']):.5g}", f"{float(s['P_ex']):.4e}", f"{float(s['stick_fraction']):.3f}")
    Console().print(table)
