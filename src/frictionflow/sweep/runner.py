"""Run a sweep: locally on this machine's cores, or as Dask tasks on a cluster.

A run holds the output's lock (:mod:`.lock`) from before it touches the
output until it returns, fails or is interrupted; a resumed output is
checked chunk by chunk first (:meth:`SweepStore.verify`).  A run that fails
-- a full disk, a Dask worker lost for good, a scheduler gone -- stops with
one line and leaves the store as resumable as an interrupted one.
"""

from __future__ import annotations

import logging
import os
import sys
import warnings
from concurrent.futures import CancelledError
from contextlib import contextmanager, suppress
from pathlib import Path
from typing import Any, Mapping

from .. import _validate as check
from .._progress import progress_bar
from ..estimate import Estimate, enforce
from .compute import VARIABLES, compute_chunk
from ..parameters import Param
from .config import MAX_AXIS, SweepConfig, chunk_shape, parse_sweep
from .model import ModelSweepConfig, compute_model_chunk, default_model_chunk, load_any_sweep, model_sweep_estimate
from .lock import STALE_AFTER, SweepLock
from .store import (KEPT, PATH, RepairWarning, SweepStore, Verification, _short, check_out, journal_path, stored_config,
                    verify_sweep, writing)

__all__ = ["CHUNK_SIZE", "SCHEDULER_TIMEOUT", "default_chunk_size", "repair_sweep", "run_sweep", "sweep_estimate",
           "verify_sweep"]

#: seconds to wait for a Dask scheduler before giving up
SCHEDULER_TIMEOUT = 5.0
#: a chunk is computed and held in memory at once (its points' results and runs): at most as many points as
#: an axis may have
CHUNK_SIZE = Param("chunk_size", "", "points per chunk (a task and a unit of commit)", "run", None, kind="int",
                   lower=1, upper=MAX_AXIS)
#: address schemes whose location is HOST:PORT (checked before connecting)
HOST_PORT_SCHEMES = ("tcp", "tls", "ws", "wss")

def default_chunk_size(cfg: SweepConfig | ModelSweepConfig) -> int:
    """About 0.2 s of work per chunk on one core (>= 100 ms per Dask task): what the solver declares.

    A model sweep's points are each far longer: a few points per chunk.
    """
    if isinstance(cfg, ModelSweepConfig):
        return default_model_chunk(cfg)
    _, _, solver = cfg.run.build()
    return solver.chunk_points(cfg.run.t_end)


def sweep_estimate(cfg: SweepConfig, out: str | Path | None = None, name: str = "out") -> Estimate:
    """Every point of ``cfg`` run to its t_end on this machine's cores, and the store ``out`` (given as ``name``)
    its results fill.

    A bound: a point stops once its steady state is settled.  A forced
    point, and a point of a law with internal states, is costed as a single
    run (the batched kernels and the façade alike); the store holds a float per variable and point.  A model sweep
    is costed from a probe run (:func:`~frictionflow.sweep.model.model_sweep_estimate`).
    """
    if isinstance(cfg, ModelSweepConfig):
        return model_sweep_estimate(cfg, out, name)
    model, law, solver = cfg.run.build()
    forced = model.driven or "fex" in cfg.axes or "fex" in cfg.sample or "vb_amplitude" in cfg.axes
    whole_run = forced or bool(law.internal_names)  # a law with internal states: each point a whole stiff run
    point = solver.cost(model, law, cfg.run.t_end) if whole_run else solver.point_cost(model, law, cfg.run.t_end)
    work = Estimate(float(cfg.size), f"points of {point.work:.3g} {point.unit}", point.seconds * cfg.size,
                    cores=os.cpu_count() or 1)
    return work.writing(out, float(cfg.size) * 8 * len(VARIABLES), name)


def run_sweep(
    config: SweepConfig | dict[str, Any] | str | Path,
    out: str | Path,
    *,
    restart: bool = False,
    client: Any = None,
    scheduler: str | None = None,
    chunk_size: int | None = None,
    progress: bool = False,
    scheduler_timeout: float = SCHEDULER_TIMEOUT,
    lock_stale_after: float = STALE_AFTER,
    name: str = "out",
):
    """Compute a sweep into ``out`` (.zarr or .nc) and return it as an :class:`xarray.Dataset`.

    Raises :class:`~frictionflow.sweep.lock.OutputInUseError` at once when
    another run holds ``out``.  An existing output is checked before it is
    resumed: damaged chunks are recomputed, with a warning saying which.
    An argument of the wrong type or range is refused (TypeError or
    ValueError naming it) before anything is written.

    Parameters
    ----------
    config:
        A :class:`SweepConfig`, a mapping as in a TOML file, or a path to one.
    out:
        The output: a Zarr store (``*.zarr``, chunked, for large grids) or a NetCDF file (``*.nc``).
    restart:
        Discard an existing output (needed when its config differs).
    client, scheduler:
        A ``distributed.Client``, or the address of a Dask scheduler
        (``tcp://host:port``): chunks are then Dask tasks.  Default: this
        machine's cores.
    chunk_size:
        Points per chunk (a chunk is a task and a unit of commit).
    scheduler_timeout:
        Seconds to wait for ``scheduler`` to answer (RuntimeError naming the address after that).
    lock_stale_after:
        Seconds after which another host's untouched lock on ``out`` counts as stale.
    progress:
        Draw a progress bar on stderr.
    name:
        How messages about ``out`` name it (``basins`` passes its store's option, ``--store``).
    """

    _check_run_arguments(out, restart, client, scheduler, progress, name)
    _seconds("scheduler_timeout", scheduler_timeout)
    _seconds("lock_stale_after", lock_stale_after)
    cfg = _as_config(config)
    size = default_chunk_size(cfg) if chunk_size is None else CHUNK_SIZE.check(chunk_size)
    target = check_out(out, name, sidecars=True)
    # within the limits in force (frictionflow.estimate.limited); a model sweep's probe runs only when they are
    enforce((lambda: sweep_estimate(cfg, out, name)) if isinstance(cfg, ModelSweepConfig) else sweep_estimate(cfg, out, name))
    with SweepLock(out, stale_after=lock_stale_after, name=name):
        own_client = _connect(scheduler, scheduler_timeout) if client is None and scheduler is not None else None
        try:
            with writing(target, name), _quiet(own_client is not None):
                store = SweepStore(out, cfg, chunk_shape(cfg.shape, size), restart=restart, name=name)
                if store.resumed:
                    _report(store.verify(repair=True), store)
                _compute(store, cfg, own_client or client, progress)
        finally:
            if own_client is not None:
                own_client.close()
        with writing(target, name):
            return store.finish()  # still locked: a .nc is converted by this run only


def repair_sweep(
    out: str | Path,
    config: SweepConfig | dict[str, Any] | str | Path | None = None,
    *,
    lock_stale_after: float = STALE_AFTER,
    name: str = "out",
) -> Verification:
    """Repair a sweep output without computing (``frictionflow sweep --verify OUT --repair``).

    Damaged or missing metadata (an emptied ``zarr.json`` of the root or of
    a variable) is rebuilt from the sweep's settings -- ``config``, or the
    settings the output records -- then every committed chunk is verified
    against its checksum: those that verify are kept, the flags of the others
    cleared, so that running the sweep again computes only them.  Returns
    the findings (:attr:`~frictionflow.sweep.store.Verification.rebuilt`,
    :meth:`~frictionflow.sweep.store.Verification.repair_line`).
    Raises ValueError for an output that is missing, not a sweep, or holds
    another sweep; :class:`~frictionflow.sweep.store.DamagedStoreError` when
    only ``--restart`` helps; :class:`~frictionflow.io.OutputError` when the
    disk fills (or fails) while repairing, in the words a sweep uses there:
    what it wrote is whole, and the same repair (or the sweep) goes on.

    Parameters
    ----------
    out:
        The sweep's output (``*.zarr`` or ``*.nc``).
    config:
        The sweep's settings (a :class:`SweepConfig`, a mapping or a TOML
        file), or None to use those the output records.
    lock_stale_after:
        Seconds after which another host's untouched lock on ``out`` counts as stale.
    name:
        How messages name ``out`` (the command line's ``--verify``).
    """

    check.instance(name, out, (str, os.PathLike), PATH)
    _seconds("lock_stale_after", lock_stale_after)
    target = check_out(out, name, sidecars=True)
    if not (target.exists() or journal_path(target).exists()):
        raise ValueError(f"{name}: {str(target)!r} does not exist")
    cfg = stored_config(target, name) if config is None else _as_config(config)
    with SweepLock(target, stale_after=lock_stale_after, name=name), writing(target, name):  # a full disk: the sweep's own line
        store = SweepStore(target, cfg, cfg.shape, name=name)  # (a resumed store keeps the chunks it was started with)
        try:
            return store.verify(repair=True)
        finally:
            store.close()


def _as_config(config: SweepConfig | ModelSweepConfig | dict[str, Any] | str | Path) -> SweepConfig | ModelSweepConfig:
    if isinstance(config, (str, os.PathLike)):
        return load_any_sweep(os.fspath(config))
    if isinstance(config, (SweepConfig, ModelSweepConfig)):
        return config
    check.instance("config", config, Mapping, "a SweepConfig, a mapping as in a sweep's TOML file, or a path to one")
    if "model" in config:
        raise ValueError("a model sweep is given as its file or a ModelSweepConfig (its model path is relative to the file)")
    return parse_sweep(config)


def _check_run_arguments(out: Any, restart: Any, client: Any, scheduler: Any, progress: Any, name: str) -> None:
    """run_sweep's arguments of the wrong type, as one TypeError naming the argument, before anything is created.

    Flags must be booleans: a string is truthy, and restart="no" would discard an existing output.
    """
    check.instance(name, out, (str, os.PathLike), PATH)
    check.instance("restart", restart, bool, "True or False")
    check.instance("progress", progress, bool, "True or False")
    check.instance("scheduler", scheduler, (str, type(None)), "a Dask scheduler's address (str) or None")
    # a Client exists only once distributed is imported: importing it here would cost every sweep its start-up
    client_class = getattr(sys.modules.get("distributed"), "Client", type(None))
    check.instance("client", client, (client_class, type(None)), "a dask.distributed Client or None")


def _seconds(name: str, value: Any) -> float:
    """A duration argument: a number of seconds > 0 (not a boolean or text), else ValueError naming it."""
    allowed = "a number of seconds > 0"
    x = check.number(name, value, allowed)
    if not x > 0:
        raise ValueError(f"{name} must be {allowed}, got {value!r}")
    return x


def chunk_function(cfg: SweepConfig | ModelSweepConfig):
    """What computes one chunk of ``cfg`` (a pure function of its source and the chunk: a Dask task)."""
    return compute_model_chunk if isinstance(cfg, ModelSweepConfig) else compute_chunk


def _connect(address: str, timeout: float):
    """A client of the scheduler at ``address``; a one-line error naming it when it cannot be reached in time.

    A malformed address is bad input (ValueError, exit code 2); a scheduler
    that does not answer is a failure of the environment (RuntimeError,
    exit code 1).
    """
    try:
        from distributed import Client
    except ImportError:
        raise RuntimeError("--scheduler needs the 'distributed' package (pip install distributed)") from None
    _check_address(address)
    why = _probe(address, timeout)  # before a Client exists: one that fails half-way lingers (see _check_address)
    if why is None:
        try:
            # not the default client: a failed one must not linger as it (xarray's writes would then look for it)
            return Client(address, timeout=timeout, set_as_default=False)
        except ValueError as e:
            raise ValueError(f"scheduler: bad address {address!r} ({e})") from None
        except Exception as e:  # OSError / TimeoutError from the comm layer: the scheduler went away since the probe
            why = _no_answer(e, timeout)
    raise RuntimeError(f"cannot connect to the Dask scheduler at {address}: {why}; is a scheduler running there? (--scheduler-timeout sets the wait)")


def _probe(address: str, timeout: float) -> str | None:
    """Why no Dask scheduler answers at ``address`` within ``timeout`` s (None: one does).

    A plain connection asking for the scheduler's identity, in an event loop
    of its own (the caller's may be running): something else listening there
    (a web server, a proxy) is told apart from a scheduler that is down.
    """
    import asyncio  # (only with a scheduler: not a cost of every command)
    from concurrent.futures import ThreadPoolExecutor

    from distributed.comm import connect

    async def identity():
        comm = await connect(address, timeout=timeout)
        try:
            await comm.write({"op": "identity", "reply": True})
            return await comm.read()
        finally:
            comm.abort()

    with ThreadPoolExecutor(1) as pool:
        try:
            reply = pool.submit(asyncio.run, asyncio.wait_for(identity(), timeout)).result()
        except (OSError, TimeoutError) as e:  # refused, unreachable, or silent: down (or not yet up)
            return _no_answer(e, timeout)
        except MemoryError:  # a foreign protocol's first bytes read as the length of a frame
            return "something answers there, but not in Dask's protocol"
        except Exception as e:
            return f"something answers there, but not as a Dask scheduler ({_short(e)})"
    if not (isinstance(reply, dict) and reply.get("type") == "Scheduler"):
        return f"something answers there, but not as a Dask scheduler (it says it is {str(reply)[:60]!r})"
    return None


class _Silence(logging.Filter):
    """Drops every log record below CRITICAL."""

    def filter(self, record: logging.LogRecord) -> bool:
        return record.levelno >= logging.CRITICAL


@contextmanager
def _quiet(on: bool):
    """Dask's log off the terminal while the run's own client works (``on``).

    What Dask recovers from by itself (a result gathered again after its
    worker died) needs no word, and what it cannot recover from ends the run
    in one line of ours.
    """
    loggers = [v for k, v in logging.root.manager.loggerDict.items() if k.split(".")[0] == "distributed"] if on else []
    handlers = {h for lg in loggers for h in getattr(lg, "handlers", ())}  # (distributed.client has its own)
    silence = _Silence()
    for h in handlers:
        h.addFilter(silence)
    try:
        yield
    finally:
        for h in handlers:
            h.removeFilter(silence)


def _no_answer(e: BaseException, timeout: float) -> str:
    """A failed connection in a few words ("no answer within T s" when it timed out)."""
    text = str(e).strip().splitlines()[0] if str(e).strip() else type(e).__name__
    return f"no answer within {timeout:g} s" if "timed out" in text.lower() or isinstance(e, TimeoutError) else text


def _check_address(address: str) -> None:
    """ValueError naming ``address`` unless it is SCHEME://HOST:PORT of a known scheme (or HOST:PORT, tcp).

    Checked before a ``Client`` is made: one refused its address half-built
    and lingered, its ``__del__`` then stalling the exit for 10 s and
    printing an ignored exception.
    """
    from distributed.comm.addressing import parse_address, parse_host_port
    from distributed.comm.registry import get_backend

    try:
        scheme, location = parse_address(address)
        get_backend(scheme)  # an unknown scheme: ValueError naming the known ones
        if scheme in HOST_PORT_SCHEMES:
            _, port = parse_host_port(location)
            if not 0 < port < 65536:
                raise ValueError(f"port {port} is not in 1..65535")
    except (TypeError, ValueError) as e:
        raise ValueError(f"scheduler: bad address {address!r} ({e})") from None


def _report(found: Verification, store: SweepStore) -> None:
    """Warn about what checking a resumed output found (nothing when all was well)."""
    out = store.target
    if found.problems or (found.unrecorded and not store.complete):  # (an older .nc is kept as it is)
        what = "; ".join(found.problems) if found.problems else "no chunk checksums recorded (an older store)"
        warnings.warn(
            f"{out}: {what}: checked every chunk's data instead, kept {found.unknown} complete chunks and recorded their checksums anew",
            RepairWarning,
            stacklevel=3,
        )
    if found.rebuilt:  # one line: what was rebuilt, kept and is recomputed
        warnings.warn(found.repair_line().replace("left to recompute", "recomputed"), RepairWarning, stacklevel=3)
    elif found.bad:
        kinds = ", ".join(f"{n} {k}" for k, n in found.counts().items())
        warnings.warn(f"{out}: recomputing {len(found.bad)} of {found.n_chunks} chunks that were damaged: {kinds}", RepairWarning, stacklevel=3)


def _compute(store: SweepStore, cfg: SweepConfig, client: Any, progress: bool) -> None:
    """Compute the chunks still to do, committing each as it comes."""
    todo, chunks = store.todo(), store.chunks  # a resumed sweep keeps the chunks it was started with
    with progress_bar("sweep", cfg.size, enabled=progress, done=store.points_done(), unit="points") as advance:
        if client is None:
            compute = chunk_function(cfg)
            for chunk in todo:
                res = compute(cfg.source, chunk, chunks)
                store.write(chunk, res)
                advance(res[0].size)
        else:
            with client.as_current():  # (ours is not the default client: see _connect)
                _run_dask(client, cfg, store, todo, chunks, advance)


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
    compute = chunk_function(cfg)

    def submit(chunk):
        return client.submit(compute, source, chunk, chunks, key=f"frictionflow-chunk-{store.cfg.fingerprint()[:12]}-{'-'.join(map(str, chunk))}", pure=False, retries=3)

    futures = {}
    for chunk in pending:
        futures[submit(chunk)] = chunk
        if len(futures) >= window:
            break
    ac = as_completed(list(futures))
    try:
        for fut in ac:
            chunk = futures.pop(fut)
            res = _result(fut, chunk)
            store.write(chunk, res)
            advance(res[0].size)
            del fut, res
            nxt = next(pending, None)
            if nxt is not None:
                f = submit(nxt)
                futures[f] = nxt
                ac.add(f)
    finally:
        if futures:  # stopped early: nothing left running for a result no one will collect
            with suppress(Exception):  # (a client that lost its scheduler cannot cancel: the failure is said already)
                client.cancel(list(futures))


def _result(fut, chunk: tuple[int, ...]):
    """A chunk task's result; a task the cluster lost for good (its workers died) as one line (RuntimeError).

    An error of the computation itself is raised as it is.
    """
    from distributed.comm.core import CommClosedError
    from distributed.scheduler import KilledWorker

    try:
        return fut.result()
    except KilledWorker:
        why = "every worker that ran it died (KilledWorker: see the workers' logs)"
    except CancelledError:
        why = "the scheduler cancelled it (the scheduler restarted, or this client lost it)"
    except (CommClosedError, TimeoutError) as e:
        why = f"the connection to the scheduler was lost ({_short(e)})"
    raise RuntimeError(f"the Dask cluster lost chunk {chunk}: {why}; {KEPT}")
