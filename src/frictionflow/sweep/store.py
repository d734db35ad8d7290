"""Where sweep results go: a Zarr store written chunk by chunk, resumable after a crash, checked on resume.

Each task computes exactly one chunk of the store (all variables), so every
write replaces whole Zarr chunks.  After a chunk's data is written its entry
in ``_sweep/chunks_done`` (one Zarr chunk, hence one file, per entry) is set
to the chunk's checksum (:func:`chunk_checksum`: the first 8 bytes of the
SHA-256 of its variables as written); 0 means not done.  Flag and checksum
are one value written at once, so they cannot disagree.

A sweep killed at any moment and started again recomputes the chunks whose
flag is not set -- a chunk half-written when the process died is simply
written again, with the same values.  Before that it reads back every chunk
it would skip (:meth:`SweepStore.verify`): one whose data is missing,
unreadable (a truncated file) or no longer matches its checksum is
recomputed too, with a warning saying how many and why.  Flags that cannot
be read (an emptied flag file) lose only their checksums: those chunks are
checked for complete, readable data instead (every chunk file is written,
even an all-NaN one, so a missing file is damage), kept or recomputed, and
the flags are written anew.

Metadata that is damaged or missing (an emptied ``zarr.json`` of the root or
of a variable) is rebuilt on resume (:meth:`SweepStore._rebuild_metadata`, or
:func:`~frictionflow.sweep.runner.repair_sweep`): the layout is a function of
the config and the chunk shape, which the root's attributes and, as a spare
copy, the bookkeeping group's attributes record.  The chunk files are left as
they are and each committed one is then verified against its checksum, so the
finished work is kept and only what does not verify is recomputed.

The flags stay in the finished store, in its ``_sweep`` group, which
:func:`xarray.open_zarr` does not read, so that :func:`verify_sweep`
(``frictionflow sweep --verify``) can check the store later.  A ``.nc``
output is journalled in ``PATH.partial.zarr`` and converted at the end, with
the checksums in its ``_sweep`` group.
"""

from __future__ import annotations

import hashlib
import json
import os
import platform
import shutil
import tempfile
from collections import Counter
from contextlib import contextmanager
from dataclasses import dataclass, field
from datetime import datetime, timezone
from pathlib import Path
from typing import Iterator, NamedTuple, Sequence

import numpy as np

from .. import _validate as check
from .._version import __version__
from ..io import (_directory_problem, _limit, atomic_write, remove_store, stale_temporaries, temporary_path,
                  write_error, zarr_problem)
from .compute import chunk_slices
from .config import SAMPLE, SINGLE_MASS, SweepConfig, Variable, n_chunks
from .lock import lock_path
from .model import config_from_source

#: the sweep's bookkeeping group (not part of the dataset: xarray reads only the root's arrays)
BOOK = "_sweep"
#: what a message advises for an existing output: a run replaces what a sweep wrote (:func:`foreign`), a check has
#: nothing to check
REPLACE = "use --restart to replace it"
NOT_TO_CHECK = "nothing to verify: give the .zarr or .nc a sweep wrote"
#: what a message advises for a damaged output a sweep wrote
RESTART = "use --restart to start over"
#: what a run says of an existing path a sweep did not write: nothing replaces it (``{name}``: how it is given)
KEEP = "frictionflow did not write it, so it is never replaced: give another {name} or remove it yourself"
#: what a message advises for a damaged NetCDF file whose attributes cannot be read (a sweep's or not: not replaced)
UNTOLD = "its attributes cannot be read to tell it a sweep's, so it is never replaced: remove it yourself to start over"
#: what a path argument must be (a sweep's output, or the one to check)
PATH = "a path (str or os.PathLike) ending in .zarr or .nc"
#: per chunk: 0 while not done, then its checksum
DONE = f"{BOOK}/chunks_done"
#: the 0/1 flags of stores written before checksums were recorded
LEGACY_DONE = "_chunks_done"
_BOOK_ATTRS = {
    "description": "frictionflow sweep bookkeeping: per chunk (C order over the chunk grid) 0 = not computed, "
    "else the first 8 bytes (little-endian) of the SHA-256 of the chunk's variables as written, in table order, NaN canonical",
}
#: what a run that failed to write says it leaves (its lock held: nothing else writes the store meanwhile)
KEPT = "the chunks finished so far are kept: run the same command again to resume"
NOT_CREATED = "nothing was written: run the same command again"
#: the first bytes of a NetCDF-4 (HDF5) and of a classic NetCDF file
_NC_MAGIC = (b"\x89HDF\r\n\x1a\n", b"CDF\x01", b"CDF\x02", b"CDF\x05")


def provenance(cfg: SweepConfig) -> dict[str, str]:
    import numba

    return {
        "title": "frictionflow parameter sweep",
        "frictionflow_version": __version__,
        "config": json.dumps(cfg.source, sort_keys=True, default=str),
        "config_sha256": cfg.fingerprint(),
        "created": datetime.now(timezone.utc).isoformat(timespec="seconds"),
        "platform": platform.platform(),
        "python": platform.python_version(),
        "numpy": np.__version__,
        "numba": numba.__version__,
        "Conventions": "CF-1.10",
    }


def chunk_checksum(values: Sequence[np.ndarray]) -> int:
    """A chunk's checksum: SHA-256 of its variables as stored (table order), first 8 bytes; never 0.

    NaN is hashed in one bit pattern: the kernels' NaN and the one a format
    reads back may differ in sign, not in meaning.
    """
    h = hashlib.sha256()
    for v in values:
        v = np.ascontiguousarray(v)
        if v.dtype.kind == "f":
            v = np.where(np.isnan(v), np.nan, v)
        h.update(v.tobytes())
    return int.from_bytes(h.digest()[:8], "little") or 1  # 0 means "not done"


@contextmanager
def writing(target: Path, name: str = "out") -> Iterator[None]:
    """A file-system failure while a run writes its store, as one line (:func:`~frictionflow.io.write_error`).

    Zarr writes each file under a temporary name and renames it, and a
    chunk's done-flag is written after its data: whatever failed, the store
    holds whole files and flags only for whole chunks, so it resumes.
    """
    try:
        yield
    except OSError as e:
        if e.errno is None:  # not the file system's (a Dask connection closed, ...): raised as it is
            raise
        raise write_error(e, name, target, KEPT) from None


def check_out(path: str | Path, name: str = "out", sidecars: bool = False) -> Path:
    """Refuse, before any work, an output that cannot be a sweep's: its extension, its directory, and with
    ``sidecars`` a name too long for the files a run writes beside it (:func:`sidecar_names`); messages naming it
    ``name``."""
    p = _sweep_path(path, name)
    problem = _directory_problem(p.parent)
    if problem is not None:
        raise ValueError(f"{name}: {problem}")
    if sidecars:
        _check_name_lengths(p, name)
    return p


def sidecar_names(target: Path) -> list[str]:
    """The names a run on ``target`` gives the files beside it: its lock and, for a NetCDF output, its journal
    (every temporary name is cut to fit wherever the target fits)."""
    names = [lock_path(target).name]
    if target.suffix.lower() == ".nc":
        names.append(journal_path(target).name)
    return names


def _check_name_lengths(target: Path, name: str) -> None:
    """ValueError naming ``name`` when ``target``'s name, or a name of its sidecars, is too long for its directory."""
    longest = _limit(target.parent, "PC_NAME_MAX", 255)
    size = len(os.fsencode(target.name))
    if size > longest:
        raise ValueError(f"{name}: the file name of {str(target)!r} is too long ({size} bytes; at most {longest} here)")
    need = max(len(os.fsencode(n)) for n in sidecar_names(target)) - longest
    if need > 0:
        raise ValueError(f"{name}: the file name of {str(target)!r} is too long: its lock/partial files need {need} "
                         f"more byte{'s' if need > 1 else ''} (at most {longest} bytes a name here; its own {size})")


def _sweep_path(path: str | Path, name: str) -> Path:
    """``path`` as a Path if it ends in .zarr or .nc, else ValueError naming it ``name``."""
    p = Path(path)
    if p.suffix.lower() not in (".zarr", ".nc"):
        raise ValueError(f"{name} must end in .zarr or .nc, got {str(path)!r}")
    return p


class RepairWarning(UserWarning):
    """A resumed output had damage, now being repaired (chunks recomputed, flags rewritten)."""


class DamagedStoreError(RuntimeError):
    """A store damaged beyond what a rerun repairs (its metadata, an unopenable file): ``--restart`` is needed."""

    def __init__(self, target: Path, problem: str, name: str = "out", advice: str = RESTART) -> None:
        self.problem = problem
        self.advice = advice  #: how to go on (--restart only for what a sweep is known to have written)
        super().__init__(f"{name}: {str(target)!r} is damaged: {problem}; {advice}")


class ChunkReadError(Exception):
    """A chunk's data cannot be read (a truncated or corrupt file); the message names the variable."""


class BadChunk(NamedTuple):
    """A committed chunk that cannot be kept."""

    chunk: tuple[int, ...]
    where: str  #: the grid block, e.g. ``zeta[0:6] vb[0:2]``
    reason: str  #: ``missing: ...``, ``unreadable: ...``, ``checksum mismatch`` or ``incomplete: ...``

    @property
    def kind(self) -> str:
        return self.reason.split(":")[0]


@dataclass
class Verification:
    """What checking a sweep store found (``SweepStore.verify``, :func:`~frictionflow.sweep.verify_sweep`)."""

    path: Path  #: the sweep output checked (its ``.zarr`` or ``.nc`` path, also while a ``.nc`` is in its journal)
    n_chunks: int  #: chunks in the sweep's grid (0 when the store could not be opened)
    done: int = 0  #: committed chunks found intact
    bad: list[BadChunk] = field(default_factory=list)  #: committed chunks that cannot be kept, each with where and why
    problems: list[str] = field(default_factory=list)  #: damage beyond single chunks (the done-flags, ...)
    unrecorded: bool = False  #: no checksums at all, as in an older store; data checked for completeness only
    unknown: int = 0  #: chunks whose checksum was lost or never recorded, checked for complete data instead
    repairable: bool = True  #: whether running the sweep again repairs it (else ``--restart`` is needed)
    rebuilt: list[str] = field(default_factory=list)  #: metadata documents rebuilt from the settings (``root``, variables)
    fix: str = ""  #: how to go on when not repairable, if not "run the sweep again with --restart"

    @property
    def intact(self) -> bool:
        """Whether all is well (no bad chunk and no damage beyond single chunks)."""
        return not self.bad and not self.problems

    def counts(self) -> dict[str, int]:
        """Bad chunks per kind of damage."""
        return dict(Counter(b.kind for b in self.bad))

    def lines(self) -> list[str]:
        """One line per bad chunk."""
        return [f"{self.path}: chunk {b.chunk} ({b.where}): {b.reason}" for b in self.bad]

    def summary(self) -> str:
        """One line: intact (and whether complete), or what is damaged."""
        if self.intact:
            state = "complete" if self.done == self.n_chunks else f"incomplete, {self.n_chunks - self.done} chunks still to compute"
            note = "; no checksums recorded (an older store): data checked for completeness only" if self.unrecorded else ""
            return f"{self.path}: intact: {self.done} of {self.n_chunks} chunks verified ({state}){note}"
        parts = list(self.problems)
        if self.bad:
            kinds = ", ".join(f"{n} {k}" for k, n in self.counts().items())
            parts.append(f"{len(self.bad)} of {self.n_chunks} chunks bad ({kinds})")
        fix = "run the same sweep again to recompute what is bad" if self.repairable else self.fix or "run the sweep again with --restart"
        return f"{self.path}: damaged: {'; '.join(parts)}; {fix}"

    def repair_line(self) -> str:
        """One line: what a repair rebuilt, kept and left to recompute."""
        parts = [f"rebuilt the metadata of {', '.join(self.rebuilt)} from the sweep's settings"] if self.rebuilt else []
        parts.append(f"kept {self.done} finished chunks that verify")
        if self.bad:
            kinds = ", ".join(f"{n} {k}" for k, n in self.counts().items())
            parts.append(f"{len(self.bad)} damaged chunks ({kinds}) left to recompute")
        return f"{self.path}: repaired: {'; '.join(parts)}"

    def as_dict(self) -> dict:
        return {
            "out": str(self.path),
            "intact": self.intact,
            "chunks": self.n_chunks,
            "verified": self.done,
            "bad": [{"chunk": list(b.chunk), "where": b.where, "reason": b.reason} for b in self.bad],
            "problems": self.problems,
            "checksums_recorded": not self.unrecorded,
            "rebuilt": self.rebuilt,
        }


class SweepStore:
    """A sweep's Zarr store: created, or reopened to resume (or, with :meth:`existing`, to be checked)."""

    def __init__(self, path: str | Path, cfg: SweepConfig, chunks: tuple[int, ...], restart: bool = False,
                 name: str = "out") -> None:
        self._locate(check_out(path, name, sidecars=True))
        self.name = name
        self.cfg = cfg
        self.table = cfg.variables
        self.shape = cfg.shape
        self.dims = cfg.dims
        self.chunks = chunks
        self.grid = n_chunks(cfg.shape, chunks)
        if restart:
            discard((self.path, self.target), name)
        for old in stale_temporaries(self.path):  # a creation killed half-way (under the lock: not a live one)
            shutil.rmtree(old, ignore_errors=True)
        #: an existing output: what it holds is checked (:meth:`verify`) before it is trusted
        self.resumed = self.path.exists() or self.target.exists()
        if self.path.exists():
            if self.netcdf:  # the conversion at the end replaces the file: only a sweep's
                self._refuse_foreign(self.target)
            if self.path.is_dir():
                self.rebuilt = self._rebuild_metadata()
            self._reopen(mode="r+")
            if self.root.attrs.get("config_sha256") != cfg.fingerprint():
                raise ValueError(f"{self.name}: {str(self.target)!r} holds a different sweep (its config changed); use --restart to start over")
        elif self.target.exists():  # a finished NetCDF sweep
            self._open_nc()
            if self._nc.attrs.get("config_sha256") != cfg.fingerprint():
                self.close()
                raise ValueError(f"{self.name}: {str(self.target)!r} holds a different sweep (its config changed); use --restart to replace it")
        else:
            self.root = self._create_whole()

    @classmethod
    def existing(cls, path: str | Path, name: str = "out") -> "SweepStore":
        """An existing output opened read-only, to be checked: no config needed (messages naming it ``name``)."""
        self = cls.__new__(cls)
        self._locate(_sweep_path(path, name))
        self.name, self.advice = name, NOT_TO_CHECK  # --restart (a run's) is no advice to a check
        self.cfg = None
        self.resumed = True
        self.table = _stored_table(self.path) if self.path.is_dir() else None
        if self.path.exists():
            self._reopen(mode="r")
        elif self.target.exists():
            self._open_nc()
        else:
            raise ValueError(f"{name}: {str(self.target)!r} does not exist")
        return self

    def _locate(self, target: Path) -> None:
        self.target = target
        self.name, self.advice = "out", REPLACE  # how messages name the output, and what they advise for a foreign one
        self.netcdf = target.suffix.lower() == ".nc"
        self.path = journal_path(target)
        self.complete = False
        self.root = None
        self._nc = None
        self._vars = None
        self._flag_array = None
        self.rebuilt: list[str] = []  #: metadata documents rebuilt from the settings when reopened

    def _reopen(self, mode: str) -> None:
        """Open the existing Zarr store, refusing anything that is not a sweep's."""
        import zarr

        shown = str(self.target)
        if not self.path.is_dir():
            raise ValueError(f"{self.name}: {shown!r} {zarr_problem(self.path)}; {self._advice(self.path)}")
        try:
            # the files themselves, not the consolidated snapshot: the bookkeeping may have changed or be damaged since
            root = zarr.open_group(str(self.path), mode=mode, use_consolidated=False)
            attrs = dict(root.attrs)
        except Exception:
            raise ValueError(f"{self.name}: {shown!r} exists and is not a Zarr store; {self._advice(self.path)}") from None
        if "config_sha256" not in attrs or "chunk_shape" not in attrs:
            raise ValueError(f"{self.name}: {shown!r} is a Zarr store but not a frictionflow sweep; {self._advice(self.path)}")
        self.root = root
        self.chunks = tuple(int(c) for c in attrs["chunk_shape"])  # resume with the chunks it was started with
        self._layout_from(lambda name: self.root[name])

    def _open_nc(self) -> None:
        """Open a finished NetCDF sweep (raw values: as written), refusing anything that is not one."""
        import xarray as xr

        shown = str(self.target)
        if self.target.is_dir():
            raise ValueError(f"{self.name}: {shown!r} is a directory, not a NetCDF file; {self._advice(self.target)}")
        try:
            self._nc = xr.open_dataset(self.target, mask_and_scale=False, decode_times=False, cache=False)
        except Exception as e:
            if _nc_magic(self.target):  # ours or not, it claims to be NetCDF: damaged
                problem = f"a NetCDF file that cannot be opened ({_short(e)})"  # (its attributes unread: maybe not a sweep's)
                raise DamagedStoreError(self.target, problem, self.name, UNTOLD) from None
            raise ValueError(f"{self.name}: {shown!r} exists and is not a NetCDF file; {self._advice(self.target)}") from None
        attrs = self._nc.attrs
        if self.table is None:
            self.table = _table_of(attrs.get("config"))
        if "config_sha256" not in attrs or "chunk_shape" not in attrs or self.table[0].name not in self._nc:
            self._nc.close()
            raise ValueError(f"{self.name}: {shown!r} is a NetCDF file but not a frictionflow sweep; {self._advice(self.target)}")
        self.complete = True
        self.chunks = tuple(int(c) for c in np.atleast_1d(attrs["chunk_shape"]))
        self._layout_from(lambda name: self._nc[name])

    def _advice(self, path: Path) -> str:
        """What a refusal of the existing ``path`` advises: a check's advice, else --restart only for what a sweep
        wrote (:func:`foreign`)."""
        if self.advice != REPLACE:
            return self.advice
        return REPLACE if foreign(path) is None else KEEP.format(name=self.name)

    def _refuse_foreign(self, path: Path) -> None:
        """ValueError naming ``path`` if it exists and a sweep did not write it (:func:`foreign`)."""
        what = foreign(path)
        if what is not None:
            raise ValueError(f"{self.name}: {str(path)!r} {what}; {KEEP.format(name=self.name)}")

    def _layout_from(self, get) -> None:
        """Shape, dims and chunk grid from the stored ``kind`` variable."""
        try:
            first = get(self.table[0].name)  # (the kind: over the grid's dims only)
            self.shape = tuple(first.shape)
            self.dims = tuple(getattr(first, "dims", None) or first.metadata.dimension_names)
        except Exception as e:
            raise DamagedStoreError(self.target, f"its variable {self.table[0].name!r} cannot be read ({_short(e)})", self.name) from None
        self.grid = n_chunks(self.shape, self.chunks)

    def _create(self, path: Path | None = None):
        """The store's layout, each metadata document written once with its attributes (a write costs a
        round trip through zarr's event loop); the root's attributes, which mark it as this sweep's, last."""
        import zarr

        cfg = self.cfg
        root = zarr.open_group(str(path or self.path), mode="w", zarr_format=3)
        for name, values in cfg.axes.items():
            a = root.create_array(name, shape=values.shape, chunks=values.shape, dtype="f8", dimension_names=(name,),
                                  attributes=cfg.axis_attrs(name))
            a[:] = values
        for name, values in cfg.sample.items():  # the drawn values, coordinates along the sample axis
            a = root.create_array(name, shape=values.shape, chunks=values.shape, dtype="f8", dimension_names=(SAMPLE,),
                                  attributes=cfg.axis_attrs(name))
            a[:] = values
        _create_labels(root, cfg.labels)
        for q in self.table:  # the result variables, as the config's table describes them
            attrs = {"units": q.units, "long_name": q.long_name} if q.units else {"long_name": q.long_name}
            if cfg.sample:  # (CF: xarray then reads the drawn values as coordinates, not variables)
                attrs["coordinates"] = " ".join(cfg.sample)
            if q.flags:
                attrs.update(flag_values=list(range(len(q.flags))), flag_meanings=" ".join(q.flags))
            extra = tuple(len(cfg.labels[d]) for d in q.dims)
            root.create_array(q.name, shape=cfg.shape + extra, chunks=tuple(self.chunks) + extra, dtype=q.dtype,
                              fill_value=_fill(q), dimension_names=cfg.dims + q.dims, attributes=attrs)
        self._create_flags(root)
        attrs = provenance(cfg)
        attrs.update(cfg.attributes())
        attrs["chunk_shape"] = list(self.chunks)
        root.update_attributes(attrs)
        return root

    def _create_whole(self):
        """A new store, built under a hidden name beside its path and renamed into place: whole or absent.

        (A store half-created when the disk filled would not even say which
        sweep it is, and only ``--restart`` could replace it.)
        """
        import zarr

        tmp = temporary_path(self.path)
        try:
            self._create(tmp)
            os.replace(tmp, self.path)
        except BaseException as e:
            remove_store(tmp)
            # not KEPT (``writing``'s): no chunk was finished, and there is no store to resume from
            failed = write_error(e, self.name, self.path, NOT_CREATED) if isinstance(e, OSError) and e.errno else None
            if failed is None:
                raise
            raise failed from None
        self._flag_array = None  # (opened under the temporary name)
        return zarr.open_group(str(self.path), mode="r+", use_consolidated=False)

    def _create_flags(self, root):
        """The done-flag array (all 0), in the bookkeeping group; replaces a damaged one."""
        total = int(np.prod(self.grid))
        book = root.require_group(BOOK)
        book.update_attributes({**_BOOK_ATTRS, **self._identity()})
        self._flag_array = book.create_array(
            "chunks_done", shape=(total,), chunks=(1,), dtype="u8", fill_value=0, dimension_names=("chunk",), overwrite=True
        )
        return self._flag_array

    def _identity(self) -> dict:
        """What matches a store to its settings, kept in the bookkeeping group too (the root may be the damaged part)."""
        if self.cfg is not None:
            source = json.dumps(self.cfg.source, default=str)  # (unsorted: the grid's order is the dimensions')
            return {"config": source, "config_sha256": self.cfg.fingerprint(), "chunk_shape": list(self.chunks), "dims": list(self.cfg.dims)}
        attrs = dict(self.root.attrs) if self.root is not None else {}
        return {k: attrs[k] for k in ("config", "config_sha256", "chunk_shape") if k in attrs} | {"dims": list(self.dims)}

    def _rebuild_metadata(self) -> list[str]:
        """Damaged or missing ``zarr.json`` documents rewritten from the settings; the names of those rebuilt.

        Only for a store that identifies itself as this sweep's (the root's
        attributes, else the bookkeeping group's); anything else is left to
        :meth:`_reopen` to refuse.  The chunk files are not touched:
        :meth:`verify` judges them against their checksums afterwards.  The
        done-flag array's own metadata is left to :meth:`verify` too (it
        checks the data of chunks whose flags are lost).
        """
        names = ["", *self.cfg.axes, *self.cfg.sample, *self.cfg.labels, *(q.name for q in self.table)]
        names += [BOOK] if (self.path / BOOK).is_dir() else []
        broken = [n for n in names if not _readable_doc(self.path / n / "zarr.json")]
        identity = _stored_identity(self.path) if broken else None
        if identity is None:
            return []
        if identity["config_sha256"] != self.cfg.fingerprint():
            raise ValueError(f"{self.name}: {str(self.target)!r} holds a different sweep (its config changed); use --restart to start over")
        self.chunks = identity["chunk_shape"]
        self.grid = n_chunks(self.shape, self.chunks)
        short = os.fsdecode(os.fsencode(self.path.name)[:64])  # (fits wherever the store's name fits)
        with tempfile.TemporaryDirectory(prefix=f".{short}.rebuild-", dir=self.path.parent) as tmp:
            template = Path(tmp) / "template.zarr"
            self._create(template)  # the layout a fresh run would write, with the store's chunks
            self._flag_array = None
            for name in broken:
                doc = self.path / name / "zarr.json"
                doc.parent.mkdir(parents=True, exist_ok=True)
                with atomic_write(doc, self.name) as part:
                    shutil.copyfile(template / name / "zarr.json", part)
        return ["root" if n == "" else n for n in broken]

    # -- chunks ------------------------------------------------------------------
    def _flat(self, chunk: tuple[int, ...]) -> int:
        return int(np.ravel_multi_index(chunk, self.grid))

    def _chunk(self, flat: int) -> tuple[int, ...]:
        return tuple(int(i) for i in np.unravel_index(flat, self.grid))

    def _slices(self, chunk: tuple[int, ...]) -> tuple[slice, ...]:
        return chunk_slices(chunk, self.chunks, self.shape)

    def _where(self, chunk: tuple[int, ...]) -> str:
        return " ".join(f"{d}[{s.start}:{s.stop}]" for d, s in zip(self.dims, self._slices(chunk)))

    def _flags(self):
        if self._flag_array is None:
            self._flag_array = self.root[DONE]
        return self._flag_array

    def _arrays(self) -> list:
        """The result variables' arrays, writing every chunk file (even all-fill ones: a missing file is then damage)."""
        if self._vars is None:
            arrays = []
            for q in self.table:
                try:
                    arrays.append(self.root[q.name].with_config({"write_empty_chunks": True}))
                except Exception as e:
                    raise DamagedStoreError(self.target, f"its variable {q.name!r} cannot be read ({_short(e)})", self.name) from None
            self._vars = arrays
        return self._vars

    def todo(self) -> Iterator[tuple[int, ...]]:
        """Chunks whose results are not yet committed, in order (lazily: a grid may have millions)."""
        if self.complete:
            return iter(())
        if not self.resumed:  # just created: every chunk, without reading a flag file per chunk
            return iter_chunks(self.grid)
        return (self._chunk(f) for f in np.nonzero(self._flags()[:] == 0)[0])

    def points_done(self) -> int:
        """How many grid points are committed."""
        if self.complete:
            return int(np.prod(self.shape))
        if not self.resumed:
            return 0
        done = np.unravel_index(np.nonzero(self._flags()[:])[0], self.grid)
        sizes = [np.minimum(c, n - i * c) for i, c, n in zip(done, self.chunks, self.shape)]  # edge chunks are smaller
        return int(np.sum(np.prod(sizes, axis=0))) if len(done[0]) else 0

    def write(self, chunk: tuple[int, ...], results: np.ndarray) -> None:
        """Commit one chunk: its data first, then its flag, which is the data's checksum."""
        values = [_stored(q, results[j]) for j, q in enumerate(self.table)]  # results: one array per variable, in the table's order
        self._commit(chunk, values)

    def _commit(self, chunk: tuple[int, ...], values: list[np.ndarray]) -> None:
        sl = self._slices(chunk)
        for arr, v in zip(self._arrays(), values):
            arr[sl] = v
        self._flags()[self._flat(chunk)] = np.uint64(chunk_checksum(values))

    # -- checking ------------------------------------------------------------------
    def verify(self, repair: bool = False) -> Verification:
        """Read back every committed chunk and compare it with its checksum.

        With ``repair``, the flags of bad chunks are cleared (so that
        :meth:`todo` lists them), lost or missing checksums of chunks whose
        data is complete are recorded, damaged flags are written anew, and a
        damaged finished NetCDF file is rebuilt as a journal of its good
        chunks.
        """
        report = Verification(self.target, int(np.prod(self.grid)), rebuilt=list(self.rebuilt))
        try:
            flags, unknown = self._read_flags(report)
            self._check_chunks(flags, unknown, report)
        except DamagedStoreError as e:
            if repair:
                raise
            report.problems.append(e.problem)
            report.repairable = False
            return report
        if repair:
            self._repair(flags, report)
        return report

    def _read_flags(self, report: Verification) -> tuple[np.ndarray, np.ndarray]:
        """The recorded checksums (0: not done), and which chunks' checksums are unknown (lost or never recorded)."""
        total = report.n_chunks
        if self.complete:
            return self._nc_flags(report)
        try:
            book = self.root[BOOK]
        except KeyError:  # no bookkeeping group: a store from before the checksums
            return self._legacy_flags(report)
        except Exception as e:
            return self._lost_flags(report, f"the bookkeeping group is unreadable ({_short(e)})")
        try:
            arr = book["chunks_done"]
            if tuple(arr.shape) != (total,):
                return self._lost_flags(report, f"the done-flag array has shape {tuple(arr.shape)}, not ({total},)")
        except KeyError:
            return self._lost_flags(report, "the done-flag array is missing")
        except Exception as e:
            return self._lost_flags(report, f"the done-flag array is unreadable ({_short(e)})")
        try:
            return np.asarray(arr[:], dtype="u8"), np.zeros(total, bool)
        except Exception:
            return self._flags_one_by_one(arr, report)

    def _flags_one_by_one(self, arr, report: Verification) -> tuple[np.ndarray, np.ndarray]:
        """Flags read singly, when some cannot be read (an emptied flag file): those checksums are lost."""
        total = report.n_chunks
        flags, unknown = np.zeros(total, "u8"), np.zeros(total, bool)
        for f in range(total):
            try:
                flags[f] = arr[f]
            except Exception:
                unknown[f] = True
        report.problems.append(f"done-flags: {int(unknown.sum())} of {total} unreadable (their checksums are lost)")
        return flags, unknown

    def _lost_flags(self, report: Verification, why: str) -> tuple[np.ndarray, np.ndarray]:
        report.problems.append(f"done-flags: {why}")
        return np.zeros(report.n_chunks, "u8"), np.ones(report.n_chunks, bool)

    def _legacy_flags(self, report: Verification) -> tuple[np.ndarray, np.ndarray]:
        """A store without checksums: its 0/1 flags if it still has them (in progress), else every chunk."""
        report.unrecorded = True
        total = report.n_chunks
        try:
            unknown = np.asarray(self.root[LEGACY_DONE][:]) != 0
        except Exception:
            unknown = np.ones(total, bool)  # finished (its flags were removed then) or damaged: check all
        return np.zeros(total, "u8"), unknown

    def _nc_flags(self, report: Verification) -> tuple[np.ndarray, np.ndarray]:
        """The checksums a finished NetCDF sweep carries in its ``_sweep`` group (every chunk is done)."""
        import xarray as xr

        total = report.n_chunks
        try:
            with xr.open_dataset(self.target, group=BOOK, cache=False) as book:
                flags = np.asarray(book["chunks_done"].values, dtype="u8")
        except Exception:
            report.unrecorded = True
            return np.zeros(total, "u8"), np.ones(total, bool)
        if flags.shape != (total,):
            return self._lost_flags(report, f"the done-flag array has shape {flags.shape}, not ({total},)")
        unknown = flags == 0
        if unknown.any():
            report.problems.append(f"done-flags: {int(unknown.sum())} of {total} chunks unflagged in a finished file")
        return flags, unknown

    def _check_chunks(self, flags: np.ndarray, unknown: np.ndarray, report: Verification) -> None:
        """Check every committed chunk (and every one of unknown state); clear the flags of bad ones, record lost checksums."""
        for f in np.nonzero((flags != 0) | unknown)[0]:
            chunk = self._chunk(f)
            recorded = None if unknown[f] else int(flags[f])
            reason, checksum = self._check_chunk(chunk, recorded)
            if reason == "not computed":  # unknown state and no data at all: simply still to do
                continue
            if reason is None:
                flags[f] = checksum
                report.done += 1
                report.unknown += int(recorded is None)
            else:
                flags[f] = 0
                report.bad.append(BadChunk(chunk, self._where(chunk), reason))

    def _check_chunk(self, chunk: tuple[int, ...], recorded: int | None) -> tuple[str | None, int]:
        """Why chunk cannot be kept (None if it can), and its checksum as read."""
        missing = self._missing_files(chunk)
        if missing and recorded is None and len(missing) == len(self.table):
            return "not computed", 0
        if missing:
            return f"missing: {', '.join(missing)}", 0
        try:
            values = self._read(chunk)
        except ChunkReadError as e:
            return f"unreadable: {e}", 0
        checksum = chunk_checksum(values)
        if recorded is None:  # checksum lost: the data must at least be complete
            unset = int(np.count_nonzero(values[0] < 0))  # kind is -1 where nothing was written
            return (f"incomplete: {unset} points without a result", 0) if unset else (None, checksum)
        return (None, checksum) if checksum == recorded else ("checksum mismatch", 0)

    def _missing_files(self, chunk: tuple[int, ...]) -> list[str]:
        """Variables whose chunk file is absent (a Zarr store writes every one)."""
        if self._nc is not None:
            return []
        missing = []
        for q, arr in zip(self.table, self._arrays()):
            key = arr.metadata.encode_chunk_key(tuple(chunk) + (0,) * len(q.dims))  # (extra dims: one chunk each)
            if not (self.path / q.name / key).is_file():
                missing.append(q.name)
        return missing

    def _read(self, chunk: tuple[int, ...]) -> list[np.ndarray]:
        """A chunk's variables as stored, in table order; an error names the variable that failed."""
        sl = self._slices(chunk)
        values = []
        for j, q in enumerate(self.table):
            try:
                v = self._nc[q.name][sl].values if self._nc is not None else self._arrays()[j][sl]
            except Exception as e:
                raise ChunkReadError(f"{q.name} ({_short(e)})") from None
            values.append(np.asarray(v).astype(q.dtype, copy=False))
        return values

    def _repair(self, flags: np.ndarray, report: Verification) -> None:
        """Make the bookkeeping match what was found: bad chunks to do, checksums recorded, flags rewritten."""
        if self.complete:
            if not report.intact:
                self._rebuild_journal(flags)
            return
        if report.problems or report.unrecorded:  # the flag array itself cannot be trusted: write it anew
            shutil.rmtree(self.path / BOOK, ignore_errors=True)
            arr = self._create_flags(self.root)
            arr[:] = flags
            if report.unrecorded and LEGACY_DONE in self.root:
                del self.root[LEGACY_DONE]
            return
        for b in report.bad:
            self._flags()[self._flat(b.chunk)] = 0

    def _rebuild_journal(self, flags: np.ndarray) -> None:
        """A damaged finished NetCDF sweep: its good chunks copied into a new journal, the bad ones left to do."""
        self.root = self._create_whole()
        for f in np.nonzero(flags)[0]:
            chunk = self._chunk(f)
            self._commit(chunk, self._read(chunk))  # read from the NetCDF file, written into the journal
        self._nc.close()
        self._nc = None
        self.complete = False

    def close(self) -> None:
        """Close a NetCDF file opened for checking."""
        if self._nc is not None:
            self._nc.close()
            self._nc = None

    def finish(self):
        """Convert to NetCDF if asked (the checksums stay, in ``_sweep``); returns the dataset (lazily opened)."""
        import xarray as xr

        if self.complete:
            self.close()
            return xr.open_dataset(self.target)
        if not self.netcdf:
            _consolidate(self.path)  # xarray.open_zarr then reads one metadata document, without a warning
            return xr.open_zarr(str(self.path), consolidated=True)

        # a conversion killed earlier left its temporary (and the journal, so it is simply redone)
        for old in [*stale_temporaries(self.target), self.target.with_name(self.target.name + ".tmp")]:
            old.unlink(missing_ok=True)
        ds = xr.open_zarr(str(self.path), consolidated=False)
        try:
            kept = f"every chunk is kept in {str(self.path)!r}: run the same command again to convert it"
            with atomic_write(self.target, self.name, kept) as tmp:  # r.nc appears only complete
                ds.to_netcdf(tmp)
                self._record_checksums(tmp)
        finally:
            ds.close()
        discard([self.path], self.name)  # after the rename: a kill in between leaves the journal to convert again
        return xr.open_dataset(self.target)

    def _record_checksums(self, nc: Path) -> None:
        """The chunks' checksums into the NetCDF file's ``_sweep`` group (which xarray's default group omits)."""
        import xarray as xr

        book = xr.Dataset({"chunks_done": ("chunk", np.asarray(self._flags()[:], dtype="u8"))}, attrs=_BOOK_ATTRS)
        book.to_netcdf(nc, mode="a", group=BOOK)


def _consolidate(path: Path) -> None:
    """All metadata of a finished store into its root document (zarr's note that Zarr v3 does not specify this yet, silenced)."""
    import warnings

    import zarr

    with warnings.catch_warnings():
        warnings.filterwarnings("ignore", message=".*[Cc]onsolidated metadata.*")
        zarr.consolidate_metadata(str(path))


def _create_labels(root, labels: dict[str, tuple[str, ...]]) -> None:
    """The labels of the dims beyond the grid's (``contact``, ``dof``, ...) as text coordinates."""
    for dim, names in labels.items():
        a = root.create_array(dim, shape=(len(names),), chunks=(max(1, len(names)),), dtype=str,
                              dimension_names=(dim,), attributes={"long_name": f"{dim} name"})
        a[:] = np.array(names, dtype=object)


def _table_of(config: str | None) -> tuple[Variable, ...]:
    """The result variables of the sweep whose recorded settings are ``config`` (JSON); the single mass's if unknown."""
    try:
        return config_from_source(json.loads(config)).variables
    except Exception:  # not recorded or unreadable: an older store, or damage the checks report
        return SINGLE_MASS


def _stored_table(store: Path) -> tuple[Variable, ...]:
    """The result variables of the Zarr store at ``store`` (from its recorded settings)."""
    identity = _stored_identity(store)
    return _table_of(None if identity is None else identity.get("config"))


def _fill(q: Variable) -> float:
    """The value of a point not computed yet: NaN, or -1 for an integer code."""
    return np.nan if q.dtype == "f8" else -1


def _stored(q: Variable, row: np.ndarray) -> np.ndarray:
    """A kernel result row as the variable stores it (an integer code: NaN becomes the fill value)."""
    if q.dtype == "f8":
        return np.asarray(row, dtype="f8")
    return np.where(np.isnan(row), _fill(q), row).astype(q.dtype)


def iter_chunks(grid: tuple[int, ...]) -> Iterator[tuple[int, ...]]:
    for f in range(int(np.prod(grid))):
        yield tuple(int(i) for i in np.unravel_index(f, grid))


def verify_sweep(path: str | Path, *, name: str = "path") -> Verification:
    """Check a sweep output (``.zarr``, ``.nc``, or a ``.nc`` still in its journal) without computing.

    Every committed chunk is read back and compared with its checksum.  The
    result lists each bad chunk and why (:attr:`~frictionflow.sweep.store.Verification.bad`), and
    damage beyond single chunks (:attr:`~frictionflow.sweep.store.Verification.problems`);
    :attr:`~frictionflow.sweep.store.Verification.intact` says whether all is well.  Raises ValueError
    for a path that is not a sweep output at all.

    Parameters
    ----------
    path:
        The sweep's output (``*.zarr`` or ``*.nc``).
    name:
        How messages name ``path`` (the command line's ``--verify``).
    """

    check.instance(name, path, (str, os.PathLike), PATH)
    target = _sweep_path(path, name)
    journal = journal_path(target)
    broken = _broken_docs(journal) if journal.is_dir() else []
    if broken and _stored_identity(journal) is not None:
        problem = f"its metadata is unreadable (zarr.json of {', '.join(broken)}); --verify OUT --repair rebuilds it from the sweep's settings"
        return Verification(target, 0, problems=[problem])
    try:
        store = SweepStore.existing(target, name)
    except DamagedStoreError as e:
        fix = "" if e.advice == RESTART else e.advice
        return Verification(target, 0, problems=[e.problem], repairable=False, fix=fix)
    try:
        return store.verify()
    finally:
        store.close()


def journal_path(target: Path) -> Path:
    """The Zarr store a sweep output is written in: ``target`` itself, or for a NetCDF one its ``.partial.zarr`` journal."""
    return target.with_name(target.name + ".partial.zarr") if target.suffix.lower() == ".nc" else target


def _readable_doc(path: Path) -> bool:
    """Whether ``path`` is a readable Zarr v3 metadata document (not emptied, truncated or missing)."""
    try:
        doc = json.loads(path.read_bytes())
    except (OSError, ValueError):
        return False
    return isinstance(doc, dict) and doc.get("zarr_format") == 3 and doc.get("node_type") in ("group", "array")


def _stored_identity(store: Path, spare_first: bool = False) -> dict | None:
    """A store's config, its fingerprint and chunk shape: from the root's attributes, else from the bookkeeping group's.

    ``spare_first``: the bookkeeping group's first (its config keeps the grid's order; the root's is sorted).
    """
    docs = [store / "zarr.json", store / BOOK / "zarr.json"]
    for doc in reversed(docs) if spare_first else docs:
        try:
            attrs = json.loads(doc.read_bytes()).get("attributes", {})
            chunks = tuple(int(c) for c in attrs["chunk_shape"])
            if isinstance(attrs["config_sha256"], str) and chunks and min(chunks) >= 1:
                return {**attrs, "chunk_shape": chunks}
        except Exception:  # unreadable, not JSON, or without the keys: try the next
            continue
    return None


def _stored_dims(store: Path) -> list[str] | None:
    """The grid's dimensions in order, from the first readable result variable's metadata."""
    for q in _stored_table(store):
        try:
            dims = list(json.loads((store / q.name / "zarr.json").read_bytes())["dimension_names"])
            return dims[:len(dims) - len(q.dims)]
        except Exception:
            continue
    return None


def _broken_docs(store: Path) -> list[str]:
    """The nodes of a sweep store whose metadata cannot be read (``root`` for the group)."""
    names = ["", *sorted({d.name for d in store.iterdir() if d.is_dir()} | {q.name for q in _stored_table(store)})]
    return ["root" if n == "" else n for n in names if not _readable_doc(store / n / "zarr.json")]


def stored_config(path: str | Path, name: str = "out") -> SweepConfig:
    """The settings a sweep output was written with (recorded in its attributes), to repair it without its config
    file (messages naming it ``name``)."""
    target = Path(path)
    journal = journal_path(target)
    identity = _stored_identity(journal, spare_first=True) if journal.is_dir() else _nc_identity(target)
    if identity is None or "config" not in identity:
        raise ValueError(f"{name}: {str(target)!r} records no readable settings (its metadata is damaged or it is not a sweep); "
                         "give the sweep's CONFIG to repair it, or use --restart to start over")
    source = json.loads(identity["config"])
    dims = identity.get("dims") or (_stored_dims(journal) if journal.is_dir() else None) or []
    grid = {**{d: source["grid"][d] for d in dims if d in source["grid"]}, **source["grid"]}  # the axes in their order
    cfg = config_from_source({**source, "grid": grid}, str(target))
    if cfg.fingerprint() != identity["config_sha256"]:
        raise ValueError(f"{name}: {str(target)!r}: its recorded settings do not match their fingerprint; give the sweep's CONFIG, or use --restart")
    return cfg


def _nc_identity(target: Path, need_config: bool = True) -> dict | None:
    """A finished NetCDF sweep's config and fingerprint (None if it cannot be read, or is not a sweep's: without
    ``need_config``, its fingerprint and chunk shape suffice)."""
    import xarray as xr

    keys = ("config", "config_sha256") if need_config else ("config_sha256", "chunk_shape")
    try:
        with xr.open_dataset(target, cache=False, decode_times=False) as ds:
            first = _table_of(ds.attrs.get("config"))[0].name
            return {**{k: ds.attrs[k] for k in keys}, "dims": list(ds[first].dims)}
    except Exception:
        return None


def foreign(path: Path) -> str | None:
    """Why the existing ``path`` is not an output a sweep wrote, or None: the one rule of what a sweep may remove.

    A sweep wrote: a directory whose root or bookkeeping group records a
    sweep's settings, or that holds a sweep's done-flags (its metadata
    damaged) -- a Zarr output, or a NetCDF one's ``.partial.zarr`` journal;
    a NetCDF file whose attributes record a sweep's settings.  Anything else
    (a user's directory, a foreign Zarr store or NetCDF file, a file that
    cannot be read) is never removed or replaced, ``--restart`` or not.
    None too for a path that does not exist (nothing to lose).
    """
    if not (path.exists() or path.is_symlink()):
        return None
    if path.is_symlink():
        return "is a symbolic link"
    if path.is_dir():
        if _stored_identity(path) is not None or (path / DONE).is_dir() or (path / LEGACY_DONE).is_dir():
            return None
        return "is a directory without a sweep's settings or bookkeeping"
    if _nc_identity(path, need_config=False) is not None:
        return None
    if _nc_magic(path):
        return "is a NetCDF file without a sweep's settings, or whose attributes cannot be read"
    return "is a file without a sweep's settings (not a sweep's NetCDF output)"


def discard(paths: Sequence[Path], name: str = "out") -> None:
    """Remove ``paths`` (files or directory trees, where they exist) if a sweep wrote every one (:func:`foreign`),
    else ValueError naming the first that it did not (messages naming it ``name``): nothing is removed then."""
    for p in paths:
        what = foreign(p)
        if what is not None:
            raise ValueError(f"{name}: {str(p)!r} {what}; {KEEP.format(name=name)}")
    for p in paths:
        if p.is_dir():
            shutil.rmtree(p)
        elif p.exists():
            p.unlink()


def _nc_magic(path: Path) -> bool:
    """Whether ``path`` starts like a NetCDF (HDF5 or classic) file."""
    try:
        with open(path, "rb") as f:
            head = f.read(8)
    except OSError:
        return False
    return any(head.startswith(m) for m in _NC_MAGIC)


def _short(e: BaseException) -> str:
    """An exception in a few words, for a one-line message."""
    text = str(e).strip().splitlines()[0] if str(e).strip() else ""
    return f"{type(e).__name__}: {text}" if text else type(e).__name__
