"""Basins of attraction and basin stability, computed as a sweep over initial states.

:func:`basins` builds a sweep (:mod:`frictionflow.sweep`) whose axes are the
initial state -- a grid ``x0 x v0``, or one ``sample`` axis of seeded random
initial states -- and, for a basin-stability study, one parameter in front of
them; runs it with :func:`~frictionflow.sweep.run_sweep` (chunked,
resumable, local or Dask); then labels the attractors over the whole dataset
(:func:`~frictionflow.basins.labels.label_attractors`).
"""

from __future__ import annotations

import math
import shutil
import tempfile
import time
import warnings
from dataclasses import dataclass, field, fields, replace
from pathlib import Path
from typing import Any, Mapping, Sequence

import numpy as np

from .. import _validate as check
from .._display import Summarized, num
from .._figures import draw, pyplot
from ..io import DEFAULT_DPI, FIGURE_FORMATS, atomic_write, check_dpi, check_output_path, write_figure, write_zarr
from ..sweep.config import GRID_KEYS, SAMPLE, SAMPLE_KEYS, SweepConfig, parse_sweep
from ..estimate import Estimate, enforce
from ..sweep.compute import VARIABLES
from ..sweep.runner import run_sweep, sweep_estimate
from ..sweep.store import check_out
from .labels import NOT_SETTLED, OUTCOMES, Attractor, Tolerances, label_attractors, resolution

#: what an output dataset can be
DATASET_FORMATS = (".nc", ".zarr")


@dataclass(repr=False)
class Basins(Summarized):
    """The result of :func:`basins`: the labelled dataset and the basin stability of each outcome.

    ``dataset`` holds every point's steady-state quantities, its ``label`` and
    the per-outcome tables (``basin_stability``, ``basin_stability_stderr``,
    ``attractor_period``, ...; see ``frictionflow.basins.labels.TABLES``).
    ``attractors`` lists, per value of the varied parameter (one entry
    without ``vary``), the attractors found there.

    Attributes
    ----------
    dataset:
        The labelled ``xarray.Dataset`` (above).
    attractors:
        Per value of the varied parameter, the :class:`Attractor` s found.
    codes:
        The code of every attractor by name (0, 1, ...; the other outcomes
        have the negative codes of ``frictionflow.basins.labels.OUTCOMES``).
    tolerances:
        The :class:`Tolerances` the labels were given with, its ``resolution``
        the solver's (``frictionflow.basins.labels.resolution``).
    design:
        How the initial states were chosen: the grid or the random sample
        (ranges, number, seed).
    vary:
        The varied parameter of a basin-stability study, or None.
    seconds:
        Wall time of the whole computation.
    files:
        The files written, by role (``out``, ``plot``, ...).
    """

    dataset: Any
    attractors: list[list[Attractor]]
    codes: dict[str, int]
    tolerances: Tolerances
    design: dict[str, Any]
    vary: str | None = None
    seconds: float = float("nan")
    files: dict[str, str] = field(default_factory=dict)

    @property
    def names(self) -> list[str]:
        """Every outcome by code, the attractors (0, 1, ...) first, then ``not_settled``, ``diverged``,
        ``quasi_periodic`` and ``chaotic``."""
        return str(self.dataset["outcome"].attrs["flag_meanings"]).split()

    @property
    def fractions(self) -> dict[str, Any]:
        """Basin stability per outcome name (an array over the varied parameter's values with ``vary``)."""
        return self._by_name("basin_stability")

    @property
    def stderr(self) -> dict[str, Any]:
        """Binomial standard error sqrt(p (1 - p) / N) of each fraction."""
        return self._by_name("basin_stability_stderr")

    def _by_name(self, var: str) -> dict[str, Any]:
        da = self.dataset[var]
        return {n: (float(da.isel(outcome=j)) if self.vary is None else da.isel(outcome=j).values) for j, n in enumerate(self.names)}

    def outcomes(self, index: int | None = None) -> list[dict[str, Any]]:
        """One dict per outcome (name, code, kind, count, fraction, stderr, period, amplitude, stick fraction, X mid).

        With ``vary``, ``index`` picks the varied parameter's value.
        """
        ds = self.dataset if self.vary is None else self.dataset.isel({self.vary: index or 0})
        kinds = {a.name: a.kind for group in self.attractors for a in group}
        rows = []
        for j, name in enumerate(self.names):
            row = {"name": name, "code": int(ds["outcome"][j]), "kind": kinds.get(name, name)}
            row["count"] = int(ds["basin_count"][j])
            for key, var in (("fraction", "basin_stability"), ("stderr", "basin_stability_stderr"), ("period", "attractor_period"),
                             ("amplitude", "attractor_amplitude"), ("stick_fraction", "attractor_stick_fraction"), ("x_mid", "attractor_x_mid")):
                v = float(ds[var][j])
                row[key] = None if math.isnan(v) else v
            rows.append(row)
        return rows

    def to_dict(self) -> dict[str, Any]:
        """Everything ``frictionflow basins --json`` prints (NaN as null)."""
        report: dict[str, Any] = {"design": self.design, "tolerances": self.tolerances.as_dict(),
                                  "labels": {str(c): n for c, n in zip(self.dataset["outcome"].values.tolist(), self.names)}}
        if self.vary is None:
            report["outcomes"] = self.outcomes()
        else:
            values = self.dataset[self.vary].values
            report["vary"] = self.vary
            report["results"] = [{self.vary: float(v), "outcomes": self.outcomes(i)} for i, v in enumerate(values)]
        report["seconds"] = self.seconds
        report.update(self.files)
        return report

    def plot(self, path: str | Path | None = None, *, name: str = "path", dpi: float = DEFAULT_DPI):
        """The basin map (or, with ``vary``, basin stability against the parameter); saved to ``path`` if given
        (``dpi`` dots per inch)."""
        return draw(self, path, name=name, dpi=dpi)

    def _summary(self) -> tuple[str, list[tuple[str, str]]]:
        title = f"basins: {self.design['points']} initial states ({self.design['kind']})"
        if self.vary:
            title += f" at {len(self.dataset[self.vary])} values of {self.vary}"
        rows = []
        for j, name in enumerate(self.names):
            p, se = self.fractions[name], self.stderr[name]
            if self.vary is None:
                rows.append((name, f"{num(p, 4)} ± {num(se, 2)}"))
            elif np.any(np.asarray(p) > 0):
                rows.append((name, ", ".join(num(x, 3) for x in p)))
        return title, rows


@dataclass(frozen=True)
class SweepOptions:
    """How :func:`~frictionflow.basins.basins` runs its sweep, and where the sweep's resumable store lives.

    Attributes
    ----------
    store:
        The sweep's own store (``.zarr``, resumable, kept; not ``out``).
        Default: beside ``out`` (``OUT.sweep.zarr``), removed once ``out`` is
        written, so that an interrupted run resumes; a temporary directory
        (removed, not resumable) without ``out``.
    restart, chunk_size, client, scheduler, progress:
        As for :func:`~frictionflow.sweep.run_sweep`.
    store_name, out_name:
        How error messages name ``store`` and ``out`` (the command line passes ``--store``, ``--out``).
    """

    store: str | Path | None = None
    restart: bool = False
    chunk_size: int | None = None
    client: Any = None
    scheduler: str | None = None
    progress: bool = False
    store_name: str = "store"
    out_name: str = "out"


def basins(
    settings: Mapping[str, Any] | None = None,
    *,
    x0: Sequence[float],
    v0: Sequence[float],
    sample: int | None = None,
    seed: int = 0,
    vary: Mapping[str, Any] | None = None,
    out: str | Path | None = None,
    plot: str | Path | None = None,
    tolerances: Tolerances | None = None,
    sweep_options: SweepOptions | None = None,
    dpi: float = DEFAULT_DPI,
    **params: Any,
) -> Basins:
    """Basins of attraction of the initial states, and their basin stability.

    Parameters
    ----------
    settings, params:
        The fixed run settings, as in a sweep's TOML file or ``simulate``'s
        options (``friction``, ``fd``, ``zeta``, ``vb``, ``t_end``, ``solver``, ...),
        as a mapping and/or keywords.
    x0, v0:
        Ranges of the initial state: ``(low, high, n)`` for an n-point grid
        axis, or ``(low, high)`` with ``sample``.
    sample, seed:
        Draw ``sample`` initial states uniformly in the ranges instead (one
        ``sample`` axis; the same points for a given seed everywhere).
    vary:
        ``{name: values}``: a basin-stability study against one parameter
        (values: a list or ``{start, stop, num[, scale]}``), the same initial
        states at each value, attractors labelled per value.
    out:
        The labelled dataset, ``.nc`` or ``.zarr`` (written atomically).
    plot:
        The basin map, or with ``vary`` the basin-stability curves (.png, .pdf, .svg, .eps).
    tolerances:
        How close steady states must be to be one attractor (:class:`Tolerances`);
        never finer than the solver resolves (its ``resolution`` is raised to
        ``frictionflow.basins.labels.resolution`` of the run's solver).
    dpi:
        Resolution of ``plot`` in dots per inch.
    sweep_options:
        How the sweep runs and where its store lives (:class:`~frictionflow.basins.study.SweepOptions`).
        Its fields are also taken as keywords among ``params``, replacing the
        record's: ``store`` (the sweep's resumable ``.zarr`` store, not
        ``out``; default beside ``out``, removed once ``out`` is written), ``restart``,
        ``chunk_size``, ``client``, ``scheduler`` and ``progress`` (as for
        :func:`~frictionflow.sweep.run_sweep`).

    Returns
    -------
    Basins
        The labelled dataset, the attractors, fractions and standard errors.
    """
    tol = tolerances or Tolerances()
    if not isinstance(tol, Tolerances):
        raise ValueError(f"tolerances must be a Tolerances, got {tol!r}")
    run = _sweep_options(sweep_options, params)
    values = {**(settings or {}), **params}
    grid, design = _design(x0, v0, sample, seed)
    along, grid = _vary(vary, values, grid)
    cfg = parse_sweep({**values, "grid": grid}, source="basins")
    _check_outputs(out, plot, dpi, run)
    tol = replace(tol, resolution=max(tol.resolution, resolution(cfg.run.build()[2], cfg.run.rtol)))
    design["points"] = int(cfg.size // (len(cfg.axes[along]) if along else 1))
    enforce(_estimate(cfg, run, out))  # within the limits in force (frictionflow.estimate.limited)
    t0 = time.perf_counter()
    with _sweep_store(run.store, out) as path:
        labelled, found = label_attractors(_swept(cfg, path, run), along, tol)
        labelled.attrs.update(_design_attrs(design, along))
        result = Basins(labelled, found, _codes(labelled), tol, design, along, time.perf_counter() - t0)
        _write(result, out, plot, dpi, run.out_name)
    _warn_unsettled(labelled["label"].values, cfg.run.t_end)
    return result


def _warn_unsettled(label: np.ndarray, t_end: float) -> None:
    """Say when points did not settle: each is its own outcome (``not_settled``), but it may belong to any basin,
    so every other fraction is only a lower bound (a slow transient, or a torus whose exponent is still unsure)."""
    n = int(np.count_nonzero(label == NOT_SETTLED))
    if n:
        warnings.warn(f"{n} of {label.size} runs did not settle by t_end = {t_end:g} (not_settled): where "
                      "they go is unknown, so the other outcomes' fractions are lower bounds; a longer t_end settles "
                      "them", stacklevel=3)


def _write(result: Basins, out: str | Path | None, plot: str | Path | None, dpi: float, out_name: str = "out") -> None:
    """The figure drawn first (a figure that cannot be drawn leaves nothing written), then ``out``, then the figure
    saved."""
    fig = None
    if plot is not None:
        plt = pyplot(plot)  # the file-only backend
        fig = result.plot(None, name="plot", dpi=dpi)
    if out is not None:
        try:
            write_dataset(result.dataset, out, out_name)
        except BaseException:
            if fig is not None:
                plt.close(fig)
            raise
        result.files["out"] = str(out)
    if fig is not None:
        write_figure(fig, plot, "plot", dpi=dpi)
        result.files["plot"] = str(plot)


def _check_outputs(out: str | Path | None, plot: str | Path | None, dpi: float, run: SweepOptions) -> None:
    """Refuse, before any work, an ``out`` (:func:`check_dataset_path`) or a store (:func:`check_store`) that
    could not be written, and a ``plot`` of an unknown format or resolution."""
    if out is not None:
        check_dataset_path(out, run.out_name)
    if run.store is not None:
        check_store(run.store, out, run.store_name, run.out_name)
    if plot is not None:
        check_output_path(plot, FIGURE_FORMATS, "plot")
        check_dpi(dpi)


def check_dataset_path(path: str | Path, name: str = "out") -> Path:
    """Refuse, before any work, a dataset output that could not be written, naming it ``name``.

    Refused: an extension other than .nc or .zarr; a missing or unwritable
    directory; for .nc an existing directory (or a read-only file); for
    .zarr an existing file or directory that is not a Zarr store (an
    existing Zarr store is replaced, as the sweep's store treats it:
    :func:`~frictionflow.io.zarr_problem`).
    """
    return check_output_path(path, DATASET_FORMATS, name)


def check_store(store: str | Path, out: str | Path | None, name: str = "store", out_name: str = "out") -> Path:
    """Refuse, before any work, a sweep store (``name``) that is not a .zarr in a writable directory, or that is
    the dataset output ``out`` (``out_name``) itself."""
    p = Path(store)
    if p.suffix.lower() != ".zarr":
        raise ValueError(f"{name} must end in .zarr, got {str(store)!r}")
    check_out(p, name, sidecars=True)  # its directory, and room for its lock's name
    if out is not None and p.resolve() == Path(out).resolve():
        raise ValueError(f"{name} must not be {out_name} ({str(out)!r}): the sweep's store and the dataset are two "
                         "outputs")
    return p


def store_path(store: str | Path | None, out: str | Path | None) -> Path | None:
    """Where the sweep's store goes: ``store``, else beside ``out`` (``OUT.sweep.zarr``); None: a temporary
    directory (removed whatever happens)."""
    if store is not None:
        return Path(store)
    if out is not None:
        return Path(out).with_name(Path(out).name + ".sweep.zarr")
    return None


def _sweep_options(given: SweepOptions | None, params: dict[str, Any]) -> SweepOptions:
    """``given`` (default :class:`SweepOptions`) with its fields among the keywords ``params`` (taken out of them)."""
    if given is not None and not isinstance(given, SweepOptions):
        raise TypeError(f"basins(): sweep_options must be a SweepOptions, got {type(given).__name__}")
    own = {f.name: params.pop(f.name) for f in fields(SweepOptions) if f.name in params}
    return replace(given if given is not None else SweepOptions(), **own)


def _estimate(cfg: SweepConfig, run: SweepOptions, out: str | Path | None) -> Estimate:
    """The sweep's estimate with its store where :class:`_sweep_store` puts it, the results held in memory to
    be labelled, and ``out`` written from them."""
    results = float(cfg.size) * 8 * len(VARIABLES)
    store = store_path(run.store, out) or Path(tempfile.gettempdir()) / "sweep.zarr"
    return replace(sweep_estimate(cfg, store, _store_name(run)), memory=results).writing(out, results)


def _store_name(run: SweepOptions) -> str:
    """How messages name the sweep's store: as given, else by the output it goes beside (``out``)."""
    return run.store_name if run.store is not None else run.out_name


def _swept(cfg: SweepConfig, path: Path, run: SweepOptions):
    """The sweep computed (or resumed) into the store ``path``, loaded into memory."""
    lazy = run_sweep(cfg, path, restart=run.restart, client=run.client, scheduler=run.scheduler, chunk_size=run.chunk_size,
                     progress=run.progress, name=_store_name(run))
    try:
        return _plain(lazy.load())
    finally:
        lazy.close()


def _range(name: str, value: Any, with_count: bool) -> tuple[float, float, int | None]:
    """``(low, high, n)`` or ``(low, high)``, checked; n is None for a sample's range."""
    want = "(low, high, n)" if with_count else "(low, high) (the sample's size is sample)"
    try:
        parts = list(value)
    except TypeError:
        raise ValueError(f"{name} must be {want}, got {value!r}") from None
    if len(parts) != (3 if with_count else 2):
        raise ValueError(f"{name} must be {want}, got {value!r}")
    low, high = (_real(name, v) for v in parts[:2])
    if not low <= high:
        raise ValueError(f"{name}: low {low:g} > high {high:g}")
    if not with_count:
        return low, high, None
    n = parts[2]
    if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n < 1:
        raise ValueError(f"{name}: the number of points must be an integer >= 1, got {n!r}")
    if n > 1 and low == high:
        raise ValueError(f"{name}: low == high with {n} points")
    if n == 1 and low != high:  # (as a sweep's axis: one point would keep low and drop high without a word)
        raise ValueError(f"{name}: 1 point holds one value, but low {low:g} and high {high:g} differ; "
                         "give 2 points or more, or low == high")
    return low, high, int(n)


def _real(name: str, v: Any) -> float:
    return check.number(name, v, "finite numbers")


def _design(x0: Any, v0: Any, sample: int | None, seed: int,
            names: Mapping[str, str] | None = None) -> tuple[dict[str, Any], dict[str, Any]]:
    """The sweep's grid entries of the initial states, and the design as reported; messages name x0, v0, sample
    and seed as ``names`` does (the command line's options), else by themselves."""
    name = {k: k for k in ("x0", "v0", "sample", "seed")} | dict(names or {})
    if sample is None:
        (a, b, n), (c, d, m) = _range(name["x0"], x0, True), _range(name["v0"], v0, True)
        grid = {"x0": {"start": a, "stop": b, "num": n}, "v0": {"start": c, "stop": d, "num": m}}
        return grid, {"kind": "grid", "x0": [a, b, n], "v0": [c, d, m]}
    if isinstance(sample, bool) or not isinstance(sample, (int, np.integer)) or sample < 1:
        raise ValueError(f"{name['sample']} must be an integer >= 1, got {sample!r}")
    (a, b, _), (c, d, _) = _range(name["x0"], x0, False), _range(name["v0"], v0, False)
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or not 0 <= seed < 2**63:
        raise ValueError(f"{name['seed']} must be an integer in [0, 2^63), got {seed!r}")
    grid = {SAMPLE: {"num": int(sample), "seed": int(seed), "x0": [a, b], "v0": [c, d]}}
    return grid, {"kind": "sample", "x0": [a, b], "v0": [c, d], "sample": int(sample), "seed": int(seed)}


def check_design(x0: Any, v0: Any, sample: int | None, seed: int, names: Mapping[str, str]) -> None:
    """Refuse initial states :func:`basins` would refuse, naming them as ``names`` does (``{"x0": "--x0-range",
    ...}``: the command line's options)."""
    _design(x0, v0, sample, seed, names)


def _vary(vary: Mapping[str, Any] | None, values: Mapping[str, Any], grid: dict[str, Any]) -> tuple[str | None, dict[str, Any]]:
    """The varied parameter, and the grid with it in front (chunks then hold whole slices of initial states)."""
    if vary is None:
        return None, grid
    if not isinstance(vary, Mapping) or len(vary) != 1:
        raise ValueError(f"vary must be one {{name: values}}, got {vary!r}")
    (name, axis), = vary.items()
    if name not in GRID_KEYS or name in SAMPLE_KEYS:
        allowed = ", ".join(k for k in GRID_KEYS if k not in SAMPLE_KEYS)
        raise ValueError(f"vary: {name!r} cannot be varied; one of {allowed}")
    if name in values:
        raise ValueError(f"vary: {name} is also given as a fixed setting; give one or the other")
    if isinstance(axis, np.ndarray):
        axis = axis.tolist()
    if not isinstance(axis, (list, tuple, Mapping)):
        raise ValueError(f"vary: {name} must be a list of values or {{start, stop, num[, scale]}}, got {axis!r}")
    return name, {name: list(axis) if isinstance(axis, tuple) else axis, **grid}


def _design_attrs(design: dict[str, Any], along: str | None) -> dict[str, Any]:
    out = {f"basins_{k}": v for k, v in design.items()}
    if along:
        out["basins_vary"] = along
    return out


def _codes(ds) -> dict[str, int]:
    names = str(ds["outcome"].attrs["flag_meanings"]).split()
    return {n: int(c) for n, c in zip(names, ds["outcome"].values) if n not in OUTCOMES.values()}


def _plain(ds):
    """The sweep dataset in memory, without the store's encodings (they would be imposed on the output)."""
    for var in ds.variables.values():
        var.encoding = {}
    if SAMPLE in ds.dims:
        ds = ds.assign_coords({SAMPLE: ds[SAMPLE].astype(np.int64).assign_attrs(ds[SAMPLE].attrs)})
    return ds


class _sweep_store:
    """Where the sweep runs (see :func:`basins`, ``store``); yields its path and removes it unless it was given."""

    def __init__(self, store: str | Path | None, out: str | Path | None) -> None:
        self.given = store
        self.out = out
        self.tmp: str | None = None

    def __enter__(self):
        self.path = store_path(self.given, self.out)
        if self.path is None:
            self.tmp = tempfile.mkdtemp(prefix="frictionflow-basins-")
            self.path = Path(self.tmp) / "sweep.zarr"
        return self.path

    def __exit__(self, exc_type, exc, tb) -> None:
        if self.tmp is not None:  # a temporary store cannot be resumed: always removed
            shutil.rmtree(self.tmp, ignore_errors=True)
        elif exc_type is None and self.given is None:  # the output holds everything now; kept on failure to resume
            shutil.rmtree(self.path, ignore_errors=True)


def write_dataset(ds, path: str | Path, name: str = "out") -> Path:
    """Write ``ds`` as NetCDF or (consolidated) Zarr by the extension, atomically: complete or not at all.

    Parameters
    ----------
    ds:
        The dataset to write.
    path:
        ``*.nc`` (NetCDF) or any other name (a Zarr store).
    name:
        How error messages name ``path`` (the command line passes its option, such as ``--out``).
    """

    p = Path(path)
    with atomic_write(p, name) as tmp:  # (an existing Zarr store is replaced only once the new one is complete)
        if p.suffix.lower() == ".nc":
            ds.to_netcdf(tmp)
        else:
            write_zarr(ds, tmp)
    return p
