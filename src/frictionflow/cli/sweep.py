"""``frictionflow sweep``."""

from __future__ import annotations

import json
import sys
import time
from pathlib import Path
from typing import Optional

import numpy as np
import typer

from . import app


@app.command()
def sweep(
    config: Path = typer.Argument(..., help="TOML file: simulate's settings plus a [grid] table of swept parameters."),
    out: Path = typer.Option(..., "--out", help="Results: PATH.zarr (chunked, for large grids) or PATH.nc."),
    restart: bool = typer.Option(False, "--restart", help="Discard an existing output (required when the config changed)."),
    scheduler: Optional[str] = typer.Option(None, "--scheduler", help="Dask scheduler address tcp://HOST:PORT; default: this machine's cores."),
    chunk_size: Optional[int] = typer.Option(None, "--chunk-size", help="Points per chunk (a task and a unit of commit)."),
    as_json: bool = typer.Option(False, "--json", help="Print a JSON summary (dims, counts per kind, points/s)."),
) -> None:
    """Sweep parameters over a grid; resumes where it stopped if killed."""
    from ..sweep import KIND_NAMES, load_sweep, run_sweep

    cfg = load_sweep(str(config))
    if chunk_size is not None and chunk_size < 1:
        raise ValueError(f"chunk-size must be an integer >= 1, got {chunk_size}")
    t0 = time.perf_counter()
    ds = run_sweep(cfg, out, restart=restart, scheduler=scheduler, chunk_size=chunk_size, progress=sys.stderr.isatty())
    elapsed = time.perf_counter() - t0
    kinds = np.asarray(ds["kind"].values)
    counts = {name: int(np.count_nonzero(kinds == i)) for i, name in enumerate(KIND_NAMES)}
    summary = {
        "out": str(out),
        "dims": {d: int(n) for d, n in ds.sizes.items()},
        "points": int(kinds.size),
        "kinds": counts,
        "seconds": elapsed,
        "points_per_second": kinds.size / elapsed if elapsed > 0 else None,
    }
    ds.close()
    if as_json:
        print(json.dumps(summary))
    else:
        dims = " x ".join(f"{d}={n}" for d, n in summary["dims"].items())
        print(f"{summary['points']} points ({dims}) -> {out}: " + ", ".join(f"{k} {v}" for k, v in counts.items()))
