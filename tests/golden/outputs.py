"""Produce the golden outputs from the current code (shared by the recorder and the test)."""

from __future__ import annotations

import contextlib
import io
import json
import math
from pathlib import Path
from typing import Any

import numpy as np

from frictionflow.cli import main

DATA = Path(__file__).with_name("data")


def cli_json(argv: list[str]) -> Any:
    """Run the CLI in this process and parse the one JSON object it prints."""
    buf, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(buf), contextlib.redirect_stderr(err):
        code = main([*argv, "--json"])
    if code != 0:
        raise RuntimeError(f"{argv}: exit {code}: {err.getvalue()}")
    return json.loads(buf.getvalue())


def simulate_json(argv: list[str]) -> Any:
    return cli_json(["simulate", *argv])


def sweep_arrays(spec: dict[str, Any], tmp: Path) -> dict[str, Any]:
    """The data variables and coordinates of a small sweep, as nested lists (NaN as None)."""
    from frictionflow.sweep import run_sweep
    from frictionflow.sweep.config import parse_sweep

    ds = run_sweep(parse_sweep(spec), tmp / "golden.zarr")
    out = {name: _plain(ds[name].values) for name in list(ds.data_vars) + list(ds.coords)}
    return out


def _plain(a: np.ndarray) -> Any:
    return [None if (isinstance(x, float) and math.isnan(x)) else x for x in np.asarray(a, dtype=float).ravel().tolist()]


def claims_json() -> Any:
    """The verdicts and numbers of the paper's claims, from the quick reproduction's data."""
    from frictionflow.paper import Settings, compute

    return claims_of(compute(Settings.quick()))


def claims_of(data: Any) -> Any:
    from frictionflow.paper.claims import evaluate

    return json.loads(json.dumps([c.__dict__ for c in evaluate(data)], default=float))
