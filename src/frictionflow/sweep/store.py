"""Where sweep results go: a Zarr store written chunk by chunk, resumable after a crash.

Each task computes exactly one chunk of the store (all variables), so every
write replaces whole Zarr chunks.  After a chunk's data is written its flag
in ``_chunks_done`` (one Zarr chunk, hence one file, per flag) is set; a
sweep killed at any moment and started again recomputes exactly the chunks
whose flag is not set -- a chunk half-written when the process died is
simply written again, with the same values.  When every chunk is done the
flags are removed, leaving a plain labelled dataset.  A ``.nc`` output is
journalled in ``PATH.partial.zarr`` and converted at the end.
"""

from __future__ import annotations

import json
import os
import platform
import shutil
from datetime import datetime, timezone
from pathlib import Path
from typing import Iterator

import numpy as np

from .. import quantities as Q
from ..parameters import declared
from .config import GRID_KEYS, SweepConfig, n_chunks

DONE = "_chunks_done"


def provenance(cfg: SweepConfig) -> dict[str, str]:
    import numba

    from .. import __version__

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


class SweepStore:
    """A sweep's Zarr store: created, or reopened to resume."""

    def __init__(self, path: str | Path, cfg: SweepConfig, chunks: tuple[int, ...], restart: bool = False) -> None:
        import zarr

        self.target = Path(path)
        suffix = self.target.suffix.lower()
        if suffix not in (".zarr", ".nc"):
            raise ValueError(f"out must end in .zarr or .nc, got {str(path)!r}")
        if not self.target.parent.exists():
            raise ValueError(f"out: directory {str(self.target.parent)!r} does not exist")
        self.netcdf = suffix == ".nc"
        self.path = self.target.with_name(self.target.name + ".partial.zarr") if self.netcdf else self.target
        self.cfg = cfg
        self.chunks = chunks
        self.grid = n_chunks(cfg.shape, chunks)
        if restart:
            for p in (self.path, self.target):
                if p.is_dir():
                    shutil.rmtree(p)
                elif p.exists():
                    p.unlink()
        self.complete = False
        if self.path.exists():
            try:
                root = zarr.open_group(str(self.path), mode="r+")
            except Exception:
                raise ValueError(f"out: {str(self.target)!r} exists and is not a sweep; use --restart to replace it") from None
            if root.attrs.get("config_sha256") != cfg.fingerprint():
                raise ValueError(f"out: {str(self.target)!r} holds a different sweep (its config changed); use --restart to start over")
            self.root = root
            self.chunks = tuple(root.attrs["chunk_shape"])  # resume with the chunks it was started with
            self.grid = n_chunks(cfg.shape, self.chunks)
        elif self.target.exists():  # a finished NetCDF sweep
            if _nc_fingerprint(self.target) != cfg.fingerprint():
                raise ValueError(f"out: {str(self.target)!r} exists and holds a different sweep; use --restart to replace it")
            self.complete = True
            self.root = None
        else:
            self.root = self._create()

    def _create(self):
        import zarr

        cfg = self.cfg
        root = zarr.open_group(str(self.path), mode="w", zarr_format=3)
        for name, values in cfg.axes.items():
            a = root.create_array(name, shape=values.shape, chunks=values.shape, dtype="f8", dimension_names=(name,))
            a[:] = values
            a.attrs.update(declared()[name].attrs)
        for q in Q.SWEPT:  # the result variables, as the quantities table describes them
            a = root.create_array(q.name, shape=cfg.shape, chunks=self.chunks, dtype=q.dtype, fill_value=_fill(q), dimension_names=cfg.dims)
            a.attrs.update(units=q.units, long_name=q.long_name)
            if q.flags:
                a.attrs.update(flag_values=list(range(len(q.flags))), flag_meanings=" ".join(q.flags))
        total = int(np.prod(self.grid))
        root.create_array(DONE, shape=(total,), chunks=(1,), dtype="i1", fill_value=0, dimension_names=("_chunk",))
        attrs = provenance(cfg)
        fixed = {k: v for k, v in cfg.fixed.items()}
        model, law, _ = cfg.run.build()  # every setting of a point, defaults resolved
        settings = {**model.as_dict(), **law.values(), "x0": cfg.run.x0, "v0": cfg.run.v0}
        for key, value in settings.items():
            if key in GRID_KEYS and key not in cfg.axes and value is not None:
                fixed.setdefault(key, value)
        attrs.update({f"fixed_{k}": float(v) for k, v in fixed.items()})
        attrs.update({"friction": cfg.run.friction, "solver": cfg.run.solver, "stick_force": cfg.run.stick_force, "t_end": cfg.run.t_end})
        attrs["chunk_shape"] = list(self.chunks)
        root.attrs.update(attrs)
        return root

    # -- chunks ------------------------------------------------------------------
    def _flat(self, chunk: tuple[int, ...]) -> int:
        return int(np.ravel_multi_index(chunk, self.grid))

    def todo(self) -> list[tuple[int, ...]]:
        """Chunks whose results are not yet committed, in order."""
        if self.complete or DONE not in self.root:
            return []
        done = self.root[DONE][:]
        return [tuple(int(i) for i in np.unravel_index(f, self.grid)) for f in np.nonzero(done == 0)[0]]

    def points_done(self) -> int:
        """How many grid points are committed."""
        from .compute import chunk_slices

        if self.complete or DONE not in self.root:
            return self.cfg.size
        done = np.nonzero(self.root[DONE][:])[0]
        total = 0
        for f in done:
            sl = chunk_slices(tuple(np.unravel_index(f, self.grid)), self.chunks, self.cfg.shape)
            total += int(np.prod([s.stop - s.start for s in sl]))
        return total

    def write(self, chunk: tuple[int, ...], results: np.ndarray) -> None:
        """Commit one chunk: its data first, then its flag."""
        from .compute import chunk_slices

        sl = chunk_slices(chunk, self.chunks, self.cfg.shape)
        for j, q in enumerate(Q.SWEPT):  # results: the kernels' rows, in the table's order
            arr = self.root[q.name]
            if q.dtype == "f8":
                arr[sl] = results[j]
            else:
                arr[sl] = np.where(np.isnan(results[j]), _fill(q), results[j]).astype(q.dtype)
        self.root[DONE][self._flat(chunk)] = 1

    def finish(self):
        """Remove the flags (and convert to NetCDF); returns the dataset (lazily opened)."""
        import xarray as xr

        if self.complete:
            return xr.open_dataset(self.target)
        if DONE in self.root:
            del self.root[DONE]
        if not self.netcdf:
            return xr.open_zarr(str(self.path), consolidated=False)
        ds = xr.open_zarr(str(self.path), consolidated=False)
        tmp = self.target.with_name(self.target.name + ".tmp")
        ds.to_netcdf(tmp)
        ds.close()
        os.replace(tmp, self.target)
        shutil.rmtree(self.path)
        return xr.open_dataset(self.target)


def _fill(q: Q.Quantity) -> float:
    """The value of a point not computed yet: NaN, or -1 for an integer code."""
    return np.nan if q.dtype == "f8" else -1


def iter_chunks(grid: tuple[int, ...]) -> Iterator[tuple[int, ...]]:
    for f in range(int(np.prod(grid))):
        yield tuple(int(i) for i in np.unravel_index(f, grid))


def _nc_fingerprint(path: Path) -> str | None:
    import xarray as xr

    try:
        with xr.open_dataset(path) as ds:
            return ds.attrs.get("config_sha256")
    except Exception:
        return None
