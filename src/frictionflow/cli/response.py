"""``frictionflow response``: the frequency response of the forced oscillator."""

from __future__ import annotations

import json
import sys
from pathlib import Path
from typing import Any, Optional

import numpy as np
from .. import quantities as Q
from ..analysis.response import DIRECTIONS, check_periods, frequency_response, response_bytes, response_estimate
from ..estimate import enforce
from ..io import atomic_write, check_output_path
from ..orbits.forced import check_parameter
from ..plotting import FIGURE_FORMATS, plot_response
from ._app import app
from .._ranges import parse_named_range
from .options import CONFIG_OPTION, command_config, parameter_names, start_state, with_parameters
from .output import provenance, show
from .vocabulary import option, parameter_help

DATASET_FORMATS = (".nc",)
NAMES = tuple(n for n in parameter_names(("oscillator", "law", "solver"), run=("x0", "v0", "friction", "solver")) if n != "omega")
#: rows of the table (the whole response is in --json and --out)
TABLE_ROWS = 12


@app.command()
@with_parameters(NAMES, parameter_help("response", NAMES))
def response(
    params: dict[str, Any],
    vary: str = option("--vary", "Here: omega=FROM:TO:N, the forcing frequencies.", required=True),
    periods: int = option("--periods"),
    direction: str = option("--direction"),
    as_json: bool = option("--json"),
    out: Optional[Path] = option("--out", "Here: the response dataset, .nc."),
    plot: Optional[Path] = option("--plot", "Here: the response curves."),
    dpi: float = option("--dpi"),
    config: Optional[Path] = CONFIG_OPTION,
) -> None:
    """Frequency response: steady amplitude, power, TR_B and stick fraction against the forcing frequency."""
    name, omega = parse_named_range("--vary", vary)
    if name != "omega":
        raise ValueError(f"--vary: response varies omega (the forcing frequency), got {name!r}")
    w0, w1, n = omega.start, omega.stop, omega.num
    for end, value in (("FROM", w0), ("TO", w1)):  # the ends as typed (a grid point beyond one named nothing)
        check_parameter("omega", value, f"--vary {end}")
    if not (1 <= n <= 100_000):
        raise ValueError(f"--vary: N must be in [1, 100000], got {n}")
    check_periods(periods, "--periods")  # before its time estimate, which it sizes
    if direction not in (*DIRECTIONS, "both"):
        raise ValueError(f"--direction must be up, down or both, got {direction!r}")
    if out is not None:
        check_output_path(out, DATASET_FORMATS, "--out")
    if plot is not None:
        check_output_path(plot, FIGURE_FORMATS, "--plot")
    cfg = command_config("response", config, params, config_only=("rtol",))
    model, law, solver = cfg.build()
    x0, v0 = start_state(cfg, model, law)
    omegas, directions = omega.grid(n) if n > 1 else np.array([w0]), DIRECTIONS if direction == "both" else (direction,)
    if out is not None and model.forced:  # the file joins the runs' estimate (the first accepted is the command's)
        runs = response_estimate(model, law, solver, omegas, periods).times(len(directions))
        enforce(runs.writing(out, response_bytes(len(directions), len(omegas)), "--out"))
    ds = frequency_response(model, law, omegas, solver=solver, periods=periods, directions=directions, x0=x0, v0=v0,
                            rtol=cfg.rtol, progress=sys.stderr.isatty())
    if out is not None:
        with atomic_write(out, "--out") as tmp:
            ds.to_netcdf(tmp)
    if plot is not None:
        plot_response(ds, plot, name="--plot", dpi=dpi)
    if as_json:
        print(json.dumps(_as_json(ds)))
    else:
        _print_table(ds, provenance(law, solver))


def _as_json(ds) -> dict[str, Any]:
    """Parameters, frequencies, the kinds' names by code (``kind`` holds codes, as the dataset's) and each
    variable per direction (NaN as null)."""
    def plain(a: np.ndarray) -> list:
        return [None if isinstance(x, float) and not np.isfinite(x) else x for x in a.tolist()]

    return {"params": dict(ds.attrs), "omega": plain(ds["omega"].values),
            "kinds": ds["kind"].attrs["flag_meanings"].split(),
            **{str(d): {v: plain(ds[v].sel(direction=d).values) for v in ds.data_vars} for d in ds["direction"].values}}


def _print_table(ds, caption: str) -> None:
    """At most :data:`TABLE_ROWS` frequencies, evenly spaced over the range (both ends kept)."""
    from rich.console import Console
    from rich.table import Table

    n = ds.sizes["omega"]
    shown = sorted(set(np.linspace(0, n - 1, min(n, TABLE_ROWS)).round().astype(int).tolist()))
    if len(shown) < n:
        caption += f"; {len(shown)} of {n} frequencies shown (--json or --out for all)"
    table = Table(title="frequency response")
    for col in ("Omega", "sweep", "kind", "m", "amplitude", "TR_B", "P_ex", "stick"):
        table.add_column(col, justify="right")
    for j in shown:
        w = ds["omega"].values[j]
        for d in ds["direction"].values:
            s = ds.sel(direction=d).isel(omega=j)
            table.add_row(f"{w:.5g}", str(d), Q.KINDS[int(s["kind"])], str(int(s["multiple"])), f"{float(s['amplitude']):.5g}",
                          f"{float(s['TR_B']):.5g}", f"{float(s['P_ex']):.4e}", f"{float(s['stick_fraction']):.3f}")
    show(Console(), table, caption)
