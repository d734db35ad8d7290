"""Run a sweep: locally on this machine's cores, or as Dask tasks on a cluster."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

from .compute import compute_chunk
from .config import SweepConfig, chunk_shape, load_sweep, parse_sweep
from .store import SweepStore

#: points per task when none is given: each task should be ~0.1-1 s of work
DEFAULT_CHUNK = {"exact": 8192, "adaptive": 256}


def default_chunk_size(cfg: SweepConfig) -> int:
    """About 0.2 s of work per chunk on one core (>= 100 ms per Dask task)."""
    _, _, solver = cfg.run.build()
    if solver.name == "rk4":
        steps = math.ceil(cfg.run.t_end / cfg.run.dt)
        return max(64, int(0.2 / (steps * 10e-9)))  # ~10 ns per step per point, one core
    return DEFAULT_CHUNK[solver.name]


def run_sweep(
    config: SweepConfig | dict[str, Any] | str | Path,
    out: str | Path,
    *,
    restart: bool = False,
    client: Any = None,
    scheduler: str | None = None,
    chunk_size: int | None = None,
    progress: bool = False,
):
    """Compute a sweep into ``out`` (.zarr or .nc) and return it as an :class:`xarray.Dataset`.

    Parameters
    ----------
    config:
        A :class:`SweepConfig`, a mapping as in a TOML file, or a path to one.
    restart:
        Discard an existing output (needed when its config differs).
    client, scheduler:
        A ``distributed.Client``, or the address of a Dask scheduler
        (``tcp://host:port``): chunks are then Dask tasks.  Default: this
        machine's cores.
    chunk_size:
        Points per chunk (a chunk is a task and a unit of commit).
    """
    if isinstance(config, (str, Path)):
        cfg = load_sweep(str(config))
    elif isinstance(config, SweepConfig):
        cfg = config
    else:
        cfg = parse_sweep(config)
    size = chunk_size or default_chunk_size(cfg)
    if size < 1:
        raise ValueError(f"chunk_size must be >= 1, got {size}")
    chunks = chunk_shape(cfg.shape, size)
    store = SweepStore(out, cfg, chunks, restart=restart)
    chunks = store.chunks  # a resumed sweep keeps the chunks it was started with
    todo = store.todo()
    from .._progress import progress_bar

    own_client = None
    if client is None and scheduler is not None:
        from distributed import Client

        client = own_client = Client(scheduler)
    with progress_bar("sweep", cfg.size, enabled=progress, done=store.points_done(), unit="points") as advance:
        if client is None:
            for chunk in todo:
                res = compute_chunk(cfg.source, chunk, chunks)
                store.write(chunk, res)
                advance(res[0].size)
        else:
            try:
                _run_dask(client, cfg, store, todo, chunks, advance)
            finally:
                if own_client is not None:
                    own_client.close()
    return store.finish()


def _run_dask(client: Any, cfg: SweepConfig, store: SweepStore, todo: list, chunks: tuple[int, ...], advance) -> None:
    """Chunks as Dask tasks, a bounded number in flight; results committed as they arrive.

    A worker that dies takes its running tasks with it; the scheduler reruns
    them elsewhere, and since every chunk is a pure function of the config
    the results are the same whoever computes them.
    """
    from distributed import as_completed

    workers = max(1, len(client.scheduler_info().get("workers", {})))
    window = 2 * workers + 2
    pending = iter(todo)
    source = cfg.source

    def submit(chunk):
        return client.submit(compute_chunk, source, chunk, chunks, key=f"frictionflow-chunk-{store.cfg.fingerprint()[:12]}-{'-'.join(map(str, chunk))}", pure=False, retries=3)

    futures = {}
    for chunk in pending:
        futures[submit(chunk)] = chunk
        if len(futures) >= window:
            break
    ac = as_completed(list(futures))
    for fut in ac:
        chunk = futures.pop(fut)
        res = fut.result()
        store.write(chunk, res)
        advance(res[0].size)
        del fut, res
        nxt = next(pending, None)
        if nxt is not None:
            f = submit(nxt)
            futures[f] = nxt
            ac.add(f)
