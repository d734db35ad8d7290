"""File formats: reading TOML configs, writing trajectories (CSV, NetCDF, Zarr), checking and writing output paths.

What a trajectory *is* as a table (its xarray form) belongs to
:meth:`frictionflow.trajectory.Trajectory.to_xarray`; this module only
imports :mod:`.trajectory`, never the other way round.

Every file the package writes goes through :func:`atomic_write`: it is
written under a temporary name beside its target and renamed into place only
when complete, so a failure or a kill never leaves a partial file under the
target's name.  :func:`check_output_path` refuses, before any work, the
paths that could not be written at all.

A write that fails is one of two things (:func:`write_error`): a path the
user chose that cannot be written (permission denied, a read-only file
system, a directory in the way: :class:`ValueError`, bad input, exit code 2)
or a file system failing under a good path (a full disk, an I/O error:
:class:`OutputError`, exit code 1, the same command succeeds once it is fixed).

A write is not interrupted half-way: Ctrl-C (and SIGTERM, which the command
line turns into Ctrl-C) during :func:`atomic_write`'s block takes effect when
the block returns, before the rename (see :func:`_signals_held`).
"""

from __future__ import annotations

import errno
import os
import re
import secrets
import shutil
import signal
import sys
import threading
import tomllib
import warnings
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

import numpy as np

from ._lazy import lazy_module
from .trajectory import WORK_NAMES, Trajectory

zarr = lazy_module("zarr")  # (its import is heavy: loaded when a store is first read)

TRAJECTORY_FORMATS = (".csv", ".nc", ".zarr")
#: errors of a write that mean the path itself cannot be written (bad input); any other error of the file
#: system (ENOSPC, EDQUOT, EIO, EFBIG, ...) is a failure under a good path
PATH_ERRNOS = frozenset({errno.EACCES, errno.EPERM, errno.EROFS, errno.EISDIR, errno.ENOTDIR, errno.ENAMETOOLONG,
                         errno.ENOENT, errno.EEXIST, errno.ENOTEMPTY, errno.ELOOP, errno.EXDEV})


class OutputError(RuntimeError):
    """An output could not be written although its path is fine: a full disk, an I/O error (exit code 1).

    ``errno`` is the system's error number when one is known.
    """

    def __init__(self, message: str, number: int | None = None) -> None:
        super().__init__(message)
        self.errno = number
#: bytes of the target's stem kept in a temporary's name (so that it fits wherever the target fits)
_TEMP_STEM_BYTES = 64


def trajectory_to_dataset(traj: Trajectory):
    """The same as ``traj.to_xarray()``, kept for callers of this older name."""
    return traj.to_xarray()


# -- checks before any work ---------------------------------------------------------------------

def check_output_path(path: str | Path, allowed: tuple[str, ...] | None, name: str) -> Path:
    """Refuse, before any work, an output path that could not be written.

    ``allowed`` lists the extensions accepted (None: any); ``name`` is the
    option or argument that gave the path, named in the error.  Refused: a
    wrong extension, an existing directory, a parent that is missing, not a
    directory or not writable, an existing file that is read-only, and a name
    too long for the file system.
    """
    p = Path(path)
    if allowed is not None and p.suffix.lower() not in allowed:
        raise ValueError(f"{name} must end in one of {', '.join(allowed)}, got {str(path)!r}")
    problem = _guarded(_output_problem, p, "write")
    if problem is not None:
        raise ValueError(f"{name}: {problem}")
    return p


def check_output_dir(path: str | Path, name: str) -> Path:
    """Refuse, before any work, an output directory that could not be created or written into."""
    p = Path(path)
    problem = _guarded(_output_dir_problem, p, "write")
    if problem is not None:
        # "out must be a directory, ..." reads as a sentence; the rest as "out: why"
        raise ValueError(f"{name} {problem}" if problem.startswith("must ") else f"{name}: {problem}")
    return p


def check_input_path(path: str | Path, name: str) -> Path:
    """Refuse, before any work, an input file that is missing, a directory, under a file or unreadable."""
    p = Path(path)
    problem = _guarded(_input_problem, p, "read")
    if problem is not None:
        raise ValueError(f"{name}: {problem}")
    return p


def _guarded(problem: Callable[[Path], str | None], p: Path, verb: str) -> str | None:
    """``problem(p)``, or the system's reason when ``p`` cannot even be looked up (a name too long, ...)."""
    try:
        return problem(p)
    except OSError as e:
        return f"cannot {verb} {str(p)!r}: {_reason(e)}"


def _input_problem(p: Path) -> str | None:
    """Why ``p`` could not be read, or None."""
    if p.is_dir():
        return f"{str(p)!r} is a directory, not a file"
    if not p.exists():
        blocker = _file_ancestor(p)
        if blocker is not None:
            return f"{str(blocker)!r} is a file, not a directory (in {str(p)!r})"
        return f"file {str(p)!r} not found"
    if not os.access(p, os.R_OK):
        return f"{str(p)!r} is not readable (permission denied)"
    return None


def _output_problem(p: Path) -> str | None:
    """Why file ``p`` could not be written, or None."""
    return _directory_problem(p.parent) or _name_problem(p) or _target_problem(p)


def _output_dir_problem(p: Path) -> str | None:
    """Why directory ``p`` could not be created or written into, or None."""
    if too_long := _name_problem(p):  # first: a name too long cannot even be looked up
        return too_long
    if p.is_dir():
        return _directory_problem(p)
    if p.exists():
        return f"must be a directory, got the file {str(p)!r}"
    if not p.parent.exists() and _file_ancestor(p.parent) is None:
        return f"parent directory {str(p.parent)!r} does not exist"
    return _directory_problem(p.parent)


def _name_problem(p: Path) -> str | None:
    """A name or path too long for the file system (checked first: looking such a path up fails)."""
    size, longest = len(os.fsencode(p.name)), _limit(p.parent, "PC_NAME_MAX", 255)
    if size > longest:
        return f"the file name of {str(p)!r} is too long ({size} bytes; at most {longest} here)"
    if len(os.fsencode(os.path.abspath(p))) >= _limit(p.parent, "PC_PATH_MAX", 4096):
        return f"the path {str(p)!r} is too long"
    return None


def _target_problem(p: Path) -> str | None:
    """An existing directory, or a read-only file, where the file should go."""
    if p.suffix.lower() == ".zarr" and p.exists():  # an existing store is replaced (:func:`atomic_write`), nothing else
        problem = zarr_problem(p)
        return None if problem is None else f"{str(p)!r} {problem}; it would be replaced: give another path or remove it"
    if p.is_dir():
        return f"{str(p)!r} is a directory"
    if p.exists() and not os.access(p, os.W_OK):
        return f"{str(p)!r} exists and is read-only"
    return None


def _directory_problem(d: Path) -> str | None:
    """Why files cannot be created in directory ``d``, or None."""
    if d.is_dir():
        if os.access(d, os.W_OK | os.X_OK):
            return _probe_problem(d)  # the mode allows it; a pseudo file system (/proc, /sys) may still refuse
        why = "on a read-only file system" if _read_only(d) else "not writable (permission denied)"
        return f"directory {str(d)!r} is {why}"
    if d.exists():
        return f"{str(d)!r} is a file, not a directory"
    blocker = _file_ancestor(d)
    if blocker is not None:
        return f"{str(blocker)!r} is a file, not a directory"
    return f"directory {str(d)!r} does not exist"


def _probe_problem(d: Path) -> str | None:
    """Why no file can be created in directory ``d`` although its mode allows it, or None: an empty file is
    created and removed to find out.

    Root may write anywhere by mode, but a pseudo file system (/proc, /sys) refuses new files (ENOENT, EACCES)
    and has no blocks at all, which a later check of free space would take for a full disk.  A failure that is
    not the path's (no inodes left, an I/O error) is left to the space check and the write to report.
    """
    probe = d / f".frictionflow-probe.{secrets.token_hex(4)}"
    try:
        os.close(os.open(probe, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o600))
    except OSError as e:
        if e.errno not in PATH_ERRNOS or e.errno == errno.EEXIST:
            return None
        kind = "a virtual file system: " if _virtual(d) else ""
        return f"cannot write files in directory {str(d)!r} ({kind}{_reason(e)})"
    try:
        os.unlink(probe)
    except OSError:
        pass
    return None


def _virtual(d: Path) -> bool:
    """Whether ``d`` is on a file system without storage (/proc, /sys: no blocks at all)."""
    try:
        return os.statvfs(d).f_blocks == 0
    except OSError:
        return False


def _file_ancestor(p: Path) -> Path | None:
    """The nearest existing ancestor of ``p`` when it is a file (``p`` lies under a file), else None."""
    for a in p.parents:
        if a.exists():
            return None if a.is_dir() else a
    return None


def _read_only(d: Path) -> bool:
    try:
        return bool(os.statvfs(d).f_flag & os.ST_RDONLY)
    except OSError:
        return False


def _limit(d: Path, key: str, default: int) -> int:
    """A file-system limit (``PC_NAME_MAX``, ``PC_PATH_MAX``) of directory ``d``."""
    try:
        return int(os.pathconf(d if d.is_dir() else ".", key))
    except (OSError, ValueError, AttributeError):  # no pathconf (Windows) or no such limit
        return default


# -- atomic writing -------------------------------------------------------------------------------

def temporary_path(path: str | Path, token: str | None = None) -> Path:
    """A hidden temporary name beside ``path`` with its extension (which writers read the format from)."""
    p = Path(path)
    stem = os.fsdecode(os.fsencode(p.stem)[:_TEMP_STEM_BYTES])
    suffix = p.suffix if len(p.suffix) <= 16 else ""
    return p.with_name(f".{stem}.{token or secrets.token_hex(4)}.tmp{suffix}")


def stale_temporaries(path: str | Path) -> list[Path]:
    """Temporaries of ``path`` left by writers that were killed (only safe to remove when no writer runs)."""
    p = Path(path)
    pattern = re.compile(re.escape(temporary_path(p, "TOKEN").name).replace("TOKEN", "[0-9a-f]{8}"))
    try:
        return [q for q in p.parent.iterdir() if pattern.fullmatch(q.name)]
    except OSError:
        return []


@contextmanager
def atomic_write(path: str | Path, name: str = "path", then: str = "") -> Iterator[Path]:
    """Yield a temporary path beside ``path``; rename it to ``path`` only when the block completes.

    The block writes the whole file to the temporary path.  On any failure
    (or interruption) the temporary is removed and ``path`` is left as it
    was; a file-system failure becomes one line naming ``name`` (the option
    that gave the path) and the path (:func:`write_error`): a ``ValueError``
    when the path cannot be written (permission denied, a read-only file
    system, a directory in the way, a name too long), an :class:`OutputError`
    when the file system failed under it (a full disk, an I/O error);
    ``then`` is added to it (what was kept, how to go on).
    """
    target = Path(path)
    if target.is_symlink():
        target = target.resolve()  # replace the file it points to, as writing through it would, not the link
    tmp = temporary_path(target)
    with _signals_held() as deliver:  # Ctrl-C: once the write returns, then the temporary is removed
        try:
            yield tmp
            _sync(tmp)  # the data on disk before the name: a crash cannot leave a named, empty file
            deliver()  # a Ctrl-C during the write: the old file stays
            _replace(tmp, target)
        except BaseException as e:
            error = write_error(e, name, target, then)  # before removing: the disk is still full
            _remove(tmp)
            if error is None:
                raise
            raise error from None


def _replace(tmp: Path, target: Path) -> None:
    """Rename ``tmp`` to ``target``; an existing Zarr store there (a directory, which a rename cannot replace) is
    moved aside first, put back if the rename fails, and removed after it."""
    if not (target.is_dir() and tmp.is_dir() and zarr_problem(target) is None):
        os.replace(tmp, target)
        return
    old = temporary_path(target)
    os.replace(target, old)
    try:
        os.replace(tmp, target)
    except BaseException:
        os.replace(old, target)
        raise
    shutil.rmtree(old, ignore_errors=True)


def zarr_problem(path: Path) -> str | None:
    """Why the existing ``path`` is not a Zarr store (a file, a directory zarr cannot open), or None."""
    if not path.is_dir():
        return "exists and is not a Zarr store (it is a file)"
    try:
        zarr.open_group(str(path), mode="r", use_consolidated=False)
    except Exception:
        return "exists and is not a Zarr store"
    return None


#: the signals a write holds back (SIGTERM: the command line raises KeyboardInterrupt for it, as for Ctrl-C)
_HELD_SIGNALS = (signal.SIGINT, signal.SIGTERM)


@contextmanager
def _signals_held() -> Iterator[Callable[[], None]]:
    """Ctrl-C and SIGTERM held back during the block and delivered after it, or when it calls the yielded function.

    The libraries cannot be interrupted safely: xarray's NetCDF writer takes its locks in Python
    (``with lock:``), and a Ctrl-C that arrives while the library writes is raised on entry to the lock's
    ``__exit__``, before the release; the writer's own clean-up (``finally: store.close()``) then waits for
    that lock forever.  Only signals whose handler is Python's (raising KeyboardInterrupt) are held, and only in
    the main thread (the only one signals reach).  A block inside another delivers to the handler the outer one
    held back (its temporary removed, not renamed), at the same safe point.
    """
    pending: list[tuple[int, Any]] = []
    installed: dict[int, Callable] = {}  # the handlers to put back
    originals: dict[int, Callable] = {}  # the handlers a held signal goes to (an outer block's, not its hold)

    def hold(signum: int, frame: Any) -> None:
        pending.append((signum, frame))

    def deliver() -> None:
        if pending:
            signum, frame = pending[0]
            pending.clear()
            originals[signum](signum, frame)

    hold.originals = originals  # type: ignore[attr-defined]
    try:  # installing inside: a signal between two installs still puts the first handler back
        for number in _HELD_SIGNALS if threading.current_thread() is threading.main_thread() else ():
            handler = signal.getsignal(number)
            if callable(handler):
                installed[number] = handler
                originals[number] = getattr(handler, "originals", {}).get(number, handler)
                signal.signal(number, hold)
        yield deliver
    finally:
        for number, handler in installed.items():
            signal.signal(number, handler)
        deliver()


def write_error(e: BaseException, name: str, target: str | Path, then: str = "") -> Exception | None:
    """The one-line error for a failed write of ``target``, or None when ``e`` is not the file system's.

    ``name: cannot write 'TARGET': WHY[; THEN]``, as a :class:`ValueError`
    when the path cannot be written (:data:`PATH_ERRNOS`: bad input) and as
    an :class:`OutputError` otherwise (a full disk, an I/O error).  ``then``
    says what was kept and how to go on.
    """
    found = _write_problem(e, Path(target).parent)
    if found is None:
        return None
    problem, number = found
    message = f"{name}: cannot write {str(target)!r}: {problem}" + (f"; {then}" if then else "")
    if number in PATH_ERRNOS:
        return ValueError(message)
    return OutputError(message, number)


def _sync(path: Path) -> None:
    """The file on disk; a directory (a Zarr store): every file in it, then the directories' entries."""
    if path.is_dir():
        for root, _, files in os.walk(path, topdown=False):
            for name in files:
                _sync(Path(root, name))
            _sync_one(Path(root))
        return
    _sync_one(path)


def _sync_one(path: Path) -> None:
    fd = os.open(path, os.O_RDONLY)
    try:
        os.fsync(fd)
    finally:
        os.close(fd)


def remove_store(path: str | Path, ignore_errors: bool = True) -> None:
    """Remove a Zarr store written only in part, after the writes zarr still has in flight (:func:`settle_zarr`)."""
    settle_zarr()
    shutil.rmtree(path, ignore_errors=ignore_errors)


def settle_zarr(timeout: float = 30.0) -> None:
    """Wait for the writes zarr still has in flight (nothing to wait for when zarr was never imported).

    zarr writes on an event loop of its own, each key in a worker thread.  When one write of a batch fails (a
    full disk), the call raises while its siblings are still writing, and one of them can create its directory
    again after the store was removed: a half-made store left behind.
    """
    sync = sys.modules.get("zarr.core.sync")
    if sync is None:
        return
    import asyncio  # loaded by zarr already; not at start-up, where it would cost 23 ms

    async def others() -> None:
        pending = [t for t in asyncio.all_tasks() if t is not asyncio.current_task()]
        await asyncio.gather(*pending, return_exceptions=True)

    try:
        sync.sync(others(), timeout=timeout)
    except Exception:  # zarr's loop closed or moved: nothing left to wait for, or no way to
        pass


def _remove(path: Path) -> None:
    try:
        if path.is_dir() and not path.is_symlink():  # a Zarr store written only in part
            remove_store(path, ignore_errors=False)
        else:
            os.unlink(path)
    except FileNotFoundError:
        pass


def _write_problem(e: BaseException, directory: Path) -> tuple[str, int | None] | None:
    """What a failed write hit, in a few words, and its errno, when it was the file system; None for anything else."""
    if isinstance(e, OSError):
        if e.errno in (errno.EACCES, errno.EPERM) and _full(directory) and os.access(directory, os.W_OK):
            return _NO_SPACE, errno.ENOSPC  # the NetCDF library's word for a file it could not create on a full disk
        return _reason(e), e.errno
    if isinstance(e, RuntimeError) and str(e).startswith("NetCDF:"):
        # the NetCDF library reports a full disk as a generic "HDF error"
        return (_NO_SPACE, errno.ENOSPC) if _full(directory) else (str(e), None)
    return None


_NO_SPACE = os.strerror(errno.ENOSPC).lower()


def _reason(e: OSError) -> str:
    """The system's words for an OSError ("permission denied"), without the errno and path."""
    text = e.strerror or str(e) or type(e).__name__
    return text[0].lower() + text[1:]


def _full(directory: Path) -> bool:
    """Whether the disk of ``directory`` is full (a pseudo file system such as /proc has no blocks: not a disk)."""
    try:
        stat = os.statvfs(directory)
    except OSError:
        return False
    return stat.f_bavail == 0 and stat.f_blocks > 0


#: the figure formats the package writes, chosen by the file's suffix (PNG raster; PDF, SVG and EPS vector)
FIGURE_FORMATS = (".png", ".pdf", ".svg", ".eps")
#: dots per inch of a written figure unless the caller says otherwise (fit for print at column width)
DEFAULT_DPI = 150.0
#: the resolutions accepted: below 10 dpi text is unreadable, above 2400 a page-sized PNG runs to gigabytes
DPI_RANGE = (10.0, 2400.0)


def check_dpi(dpi: Any, name: str = "dpi") -> float:
    """``dpi`` as a float, or a one-line ``ValueError`` naming ``name`` and the allowed range."""
    lo, hi = DPI_RANGE
    if isinstance(dpi, bool) or not isinstance(dpi, (int, float, np.integer, np.floating)) or not lo <= dpi <= hi:
        raise ValueError(f"{name} must be a number in [{lo:g}, {hi:g}] (dots per inch), got {dpi!r}")
    return float(dpi)


def write_figure(fig, path: str | Path, name: str = "path", *, close: bool = True, dpi: float = DEFAULT_DPI,
                 **savefig: Any) -> Path:
    """Save a matplotlib figure atomically and, unless ``close=False``, close it.

    The format is the suffix's (:data:`FIGURE_FORMATS`); ``dpi`` sets the
    resolution of a PNG and of the raster parts of a vector file.  A bad
    suffix or ``dpi`` raises a one-line ``ValueError`` and writes nothing.
    """
    import matplotlib.pyplot as plt

    try:
        dpi = check_dpi(dpi)
        if Path(path).suffix.lower() not in FIGURE_FORMATS:
            raise ValueError(f"{name} must end in one of {', '.join(FIGURE_FORMATS)}, got {str(path)!r}")
        with atomic_write(path, name) as tmp:
            fig.savefig(tmp, dpi=dpi, format=Path(path).suffix.lower()[1:], **savefig)
    finally:
        if close:
            plt.close(fig)
    return Path(path)


# -- trajectories and configs ---------------------------------------------------------------------

def trajectory_bytes(samples: float, path: str | Path) -> float:
    """About the size of a trajectory file of ``samples`` rows (:func:`write_trajectory`): 24 characters a
    CSV value (``%.17g``), 8 bytes a NetCDF or Zarr one."""
    values = 5 + len(WORK_NAMES)
    return samples * values * (24 if Path(path).suffix.lower() == ".csv" else 8)


def write_trajectory(traj: Trajectory, path: str | Path, *, name: str = "out") -> Path:
    """Write ``traj`` as CSV, NetCDF or Zarr, chosen by the extension; ``name`` is the option named in errors.

    Parameters
    ----------
    traj:
        A run, from :func:`~frictionflow.simulate`.
    path:
        ``*.csv`` (one row per sample: tau, X, V, F_c, mode and the work integrals; a law's internal states
        by their names, the stored energy ``E_s`` and the belt's work ``W_belt`` where the run has them), or
        ``*.nc`` / ``*.zarr`` (the dataset of :meth:`~frictionflow.Trajectory.to_xarray`; a Zarr store is a
        directory: an existing store is replaced once the new one is complete, anything else there is refused).
    name:
        How error messages name ``path`` (the command line passes its option, such as ``--out``).
    """
    p = check_output_path(path, TRAJECTORY_FORMATS, name)
    with atomic_write(p, name) as tmp:
        if p.suffix.lower() == ".nc":
            traj.to_xarray().to_netcdf(tmp)
        elif p.suffix.lower() == ".zarr":
            write_zarr(traj.to_xarray(), tmp)
        else:
            _write_csv(traj, tmp)
    return p


def write_zarr(ds, path: str | Path, mode: str = "w-") -> None:
    """``ds`` as a Zarr store at ``path`` with consolidated metadata, as the sweep, basins and map stores.

    ``xr.open_zarr`` then reads every array's metadata from the root document at once, without its
    RuntimeWarning about a store that is not consolidated.  zarr's note that Zarr v3 does not specify
    consolidated metadata yet is silenced.  ``mode`` is :meth:`xarray.Dataset.to_zarr`'s (``"w-"``: refuse an
    existing store).  Not atomic by itself: write to a temporary (:func:`atomic_write`).
    """
    with warnings.catch_warnings():
        warnings.filterwarnings("ignore", message=".*[Cc]onsolidated metadata.*")
        ds.to_zarr(path, mode=mode, consolidated=True)


def _write_csv(traj: Trajectory, path: Path) -> None:
    """The samples as CSV: the NetCDF file's columns (``is_sample`` and ``switch`` as 0/1), full precision."""
    is_sample = np.ones(len(traj.t), dtype=bool) if traj.recorded is None else traj.recorded
    switch = traj.switches() & is_sample  # as to_xarray: switches are marked on the solver's own samples
    extra, names = [], []
    if traj.internal is not None:  # a law's internal states, by its names, and the energy they store
        extra += [*traj.internal, traj.stored_energy]
        names += [*traj.internal_names, "E_s"]
    if traj.dbelt is not None:
        extra.append(np.cumsum(traj.dbelt))
        names.append("W_belt")
    cols = np.column_stack([traj.t, traj.x, traj.v, traj.fc, traj.mode, traj.work, *extra, is_sample, switch])
    header = ",".join(["tau", "X", "V", "F_c", "mode", *WORK_NAMES, *names, "is_sample", "switch"])
    np.savetxt(path, cols, delimiter=",", header=header, comments="", fmt="%.17g")


def read_config(path: str | Path, name: str = "config") -> dict[str, Any]:
    """Parse a TOML config; a missing, unreadable or malformed file raises ValueError naming ``name``.

    Parameters
    ----------
    path:
        The TOML file.
    name:
        How error messages name ``path`` (the command line passes its option, such as ``--config``).
    """

    p = check_input_path(path, name)
    try:
        with open(p, "rb") as f:
            return tomllib.load(f)
    except tomllib.TOMLDecodeError as e:
        raise ValueError(f"{name}: {str(path)!r} is not valid TOML ({e})") from None
    except UnicodeDecodeError as e:
        raise ValueError(f"{name}: {str(path)!r} is not UTF-8 text (byte {e.start})") from None
    except OSError as e:
        raise ValueError(f"{name}: cannot read {str(path)!r}: {_reason(e)}") from None
