"""``frictionflow sweep``, ``frictionflow sweep --verify OUT`` and ``sweep --verify OUT --repair``.

Exit codes: 0 done (or, with ``--verify``, intact); 1 a failure that is not
the input's fault -- the output in use by another run, a scheduler that does
not answer, a damaged output (``--verify``: any damage), an interruption;
2 bad input (including an output that is not a sweep, or another sweep).
"""

from __future__ import annotations

import json
import sys
import time
from contextlib import nullcontext
from pathlib import Path
from typing import Optional

import numpy as np
import typer

from ..solvers.structure_precompile import first_use
from ..sweep import repair_sweep, run_sweep
from ..sweep.model import ModelSweepConfig, load_any_sweep
from ..sweep.store import journal_path, verify_sweep
from ._app import Interrupted, app
from .options import bounded
from .vocabulary import option


@app.command()
@bounded
def sweep(
    config: Optional[Path] = typer.Argument(None, help="TOML file: simulate's settings plus a [grid] table of swept parameters "
                                            "(or model = FILE and a [grid] of its entries, e.g. \"contact.0.belt\")."),
    out: Optional[Path] = option("--out", "Here: PATH.zarr (chunked, for large grids) or PATH.nc."),
    verify: Optional[str] = option("--verify"),
    repair: bool = option("--repair"),
    restart: bool = option("--restart"),
    scheduler: Optional[str] = option("--scheduler"),
    scheduler_timeout: float = option("--scheduler-timeout"),
    chunk_size: Optional[int] = option("--chunk-size"),
    as_json: bool = option("--json", "Here: the summary (dims, counts per kind, points/s; with --verify the findings)."),
) -> None:
    """Sweep parameters over a grid; resumes where it stopped if killed, recomputing any damaged chunk."""
    if repair and verify is None:
        raise ValueError("--repair goes with --verify OUT (a run repairs what it resumes by itself)")
    if verify is not None:
        if out is not None or (config is not None and not repair):
            raise ValueError("--verify OUT checks an existing output: give it no CONFIG (unless --repair) and no --out")
        if repair:
            _repair(verify, config, as_json)
        else:
            _verify(verify, as_json)
        return
    if config is None:
        raise ValueError("missing CONFIG: a sweep's TOML file (or --verify OUT to check an output)")
    if out is None:
        raise ValueError("missing option --out (PATH.zarr or PATH.nc)")
    _run(config, out, restart, scheduler, scheduler_timeout, chunk_size, as_json)


def _run(config: Path, out: str, restart: bool, scheduler: Optional[str], timeout: float, chunk_size: Optional[int], as_json: bool) -> None:
    """Compute (or resume) the sweep and print its summary."""
    cfg = load_any_sweep(str(config))  # (--chunk-size and --scheduler-timeout: checked by their terms, as read)
    t0 = time.perf_counter()
    # a local model sweep compiles the structure engine here on a first use (a cluster's workers compile their own)
    ahead = first_use() if isinstance(cfg, ModelSweepConfig) and scheduler is None else nullcontext()
    with ahead:
        try:
            ds = run_sweep(cfg, out, restart=restart, scheduler=scheduler, chunk_size=chunk_size, progress=sys.stderr.isatty(),
                           scheduler_timeout=timeout, name="--out")
        except KeyboardInterrupt:  # the lock is released by now; the command ends with exit code 1
            raise _interrupted(out) from None
    elapsed = time.perf_counter() - t0
    kinds = np.asarray(ds["kind"].values)
    names = str(ds["kind"].attrs["flag_meanings"]).split()  # the single mass's kinds, or a structure's
    counts = {name: int(np.count_nonzero(kinds == i)) for i, name in enumerate(names)}
    summary = {
        "out": str(out),
        "dims": {d: int(ds.sizes[d]) for d in ds["kind"].dims},  # the grid's (not a model sweep's contact, dof, ...)
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


def _interrupted(out: Path) -> Interrupted:
    """The line for a sweep stopped by Ctrl-C: what its store keeps, if it got as far as making one (a model
    sweep's start-up, its probe run, comes before)."""
    target = Path(out)
    if target.exists() or journal_path(target).exists():
        return Interrupted(f"interrupted: {out} keeps the chunks finished so far; run the same command to resume")
    return Interrupted(f"interrupted (Ctrl-C or SIGTERM) before anything was written to {out}")


def _verify(path: str, as_json: bool) -> None:
    """Check an output: one line per bad chunk and a summary line; exit code 1 when damaged."""
    found = verify_sweep(path, name="--verify")
    if as_json:
        print(json.dumps(found.as_dict()))
    else:
        for line in found.lines():
            print(line)
    if not found.intact:
        raise RuntimeError(found.summary())  # one line on stderr, exit code 1
    if not as_json:
        print(found.summary())


def _repair(path: str, config: Optional[Path], as_json: bool) -> None:
    """Rebuild an output's damaged metadata and verify its chunks, computing nothing: one line (or JSON)."""
    found = repair_sweep(path, None if config is None else load_any_sweep(str(config)), name="--verify")
    if as_json:
        print(json.dumps(found.as_dict()))
    else:
        print(found.repair_line())
