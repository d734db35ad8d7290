"""Run every study of the paper, write figures, data and the report.

The work is a list of independent jobs (one per figure's cases, per block of
the damping sweep, per transient case, ...), spread over ``workers``
processes; the figures are then drawn in parallel too.  With ``workers=1``
everything runs in this process, in order.
"""

from __future__ import annotations

import json
import multiprocessing
import os
import signal
import time
from collections.abc import Callable
from concurrent.futures import Executor, Future, ProcessPoolExecutor
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any


from .._lazy import lazy_module
from .. import _validate as check
from .._progress import progress_bar
from ..estimate import SECONDS_PER, Estimate, enforce
from ..analysis import analyze
from ..io import DEFAULT_DPI, atomic_write, check_dpi, check_output_dir, check_output_path
from ..params import BeltOscillator
from ..simulate import simulate
from ..solvers import Exact, RK4
from . import band, fig2, fig3, fig4, fig5, fig6, sweep, transient
from .claims import Claim, evaluate
from .export import OPTION, annotate, save_figure, write_dataset
from .report import write_report
from .results import Runner
from .runs import paper_law
from .settings import Settings
from .style import pyplot

xr = lazy_module("xarray")  # loaded on first use: importing the CLI stays quick

CAPTIONS = {"fig2": fig2.CAPTION, "fig3": fig3.CAPTION, "fig4": fig4.CAPTION, "fig5": fig5.CAPTION,
            "fig6": fig6.CAPTION}


#: data set name -> (file stem, title)
DATASETS = {
    "fig2": ("fig2", "Fig. 2: Case I friction power time histories"),
    "fig3": ("fig3", "Fig. 3: Case II phase portraits"),
    "fig4": ("fig4", "Fig. 4: Case II instantaneous damper and friction power"),
    "fig5": ("fig5", "Fig. 5: dissipation ratios R_c and R_f against zeta"),
    "fig6": ("fig6", "Fig. 6: force transmissibility TR_B against zeta"),
    "transient": ("case2_transient", "Case II: averages over one cycle against the window position"),
    "band_sweep": ("karnopp_band_sweep", "Case I steady motion against V_b around V_d"),
    "band_history": ("karnopp_band_history", "Case I at V_b = V_d: rest (exact) and creep (RK4)"),
}


@dataclass
class Summary:
    """What :func:`reproduce` wrote and what it found.

    Attributes
    ----------
    out_dir:
        The directory written to.
    report:
        The self-contained ``report.html``.
    files:
        Every file written (figures, data, ``claims.json``, the report).
    claims:
        Each :class:`Claim` with its verdict.
    settings:
        The :class:`Settings` the studies ran with.
    seconds:
        Wall time of the whole reproduction.
    timings:
        Wall time of each stage, by name.
    data:
        The studies' data sets by name (as :func:`compute` returns them).
    """

    out_dir: Path
    report: Path
    files: list[Path]
    claims: list[Claim]
    settings: Settings
    seconds: float
    timings: dict[str, float] = field(default_factory=dict)
    data: dict[str, xr.Dataset] = field(repr=False, default_factory=dict)

    def counts(self) -> dict[str, int]:
        """Number of claims per verdict."""
        out = {"supported": 0, "refuted": 0, "partly": 0}
        for c in self.claims:
            out[c.verdict] += 1
        return out

    def to_dict(self) -> dict[str, Any]:
        return {
            "out_dir": str(self.out_dir),
            "report": str(self.report),
            "seconds": self.seconds,
            "timings": self.timings,
            "counts": self.counts(),
            "claims": [c.__dict__ for c in self.claims],
            "files": [p.name for p in self.files],
        }


# -- jobs (module-level so that worker processes can run them) -------------------------------------

def _cases_job(name: str, settings: Settings) -> dict[str, xr.Dataset]:
    module = {"fig2": fig2, "fig3": fig3, "fig4": fig4}[name]
    return {name: module.dataset(Runner(settings))}


def _sweep_job(vb: float, fd: float, settings: Settings) -> dict[str, xr.Dataset]:
    return {f"sweep/{vb}/{fd}": sweep.dataset(Runner(settings), (vb,), (fd,))}


def _transient_job(case: int, settings: Settings) -> dict[str, xr.Dataset]:
    return {f"transient/{case}": transient.case_dataset(settings, case)}


def _band_job(model: str, settings: Settings) -> dict[str, xr.Dataset]:
    return {f"band_sweep/{model}": band.sweep_dataset(settings, (model,))}


def _history_job(settings: Settings) -> dict[str, xr.Dataset]:
    return {"band_history": band.history_dataset(settings)}


def _plot_job(stem: str, plot: Callable[..., Any], args: tuple, out_dir: Path, dpi: float) -> list[Path]:
    return save_figure(plot(*args), out_dir, stem, dpi)


def compute_jobs(settings: Settings) -> list[tuple[Callable[..., dict[str, xr.Dataset]], tuple]]:
    """The independent computations, longest first (so two workers finish together)."""
    jobs: list[tuple[Callable[..., dict[str, xr.Dataset]], tuple]] = []
    jobs += [(_band_job, (m, settings)) for m, _ in band.MODELS]
    jobs += [(_sweep_job, (vb, fd, settings)) for vb in sweep.VB for fd in sweep.FD]
    jobs += [(_cases_job, (n, settings)) for n in ("fig2", "fig3", "fig4")]
    jobs += [(_transient_job, (i, settings)) for i in range(len(transient.CASES))]
    jobs.append((_history_job, (settings,)))
    return jobs


#: CPU seconds of the pipeline besides its RK4 steps (start-up, the exact runs, analyses, figures, report), and
#: per RK4 step: ``reproduce --workers 1`` took 9.5 s of CPU with the quick settings (3.1e7 steps) and 11.4 s
#: with the published ones (1.1e8 steps) on the project's machine, rounded up
PAPER_SECONDS = 10.0
SECONDS_PER_PAPER_STEP = SECONDS_PER["rk4_step"]


def reproduce_estimate(settings: Settings) -> Estimate:
    """The RK4 steps of the paper's runs at ``settings.dt`` (the creep runs at their own steps), and the time of
    the pipeline (:data:`PAPER_SECONDS` and :data:`SECONDS_PER_PAPER_STEP`)."""
    runs = ((len(sweep.VB) * len(sweep.FD) * len(settings.zeta_grid) + len(fig2.CASES) + len(fig3.CASES)
             + len(fig4.CASES)) * settings.t_end + len(transient.CASES) * settings.window_t_end
            + len(settings.band_vb) * settings.band_t_end + settings.band_history_t_end)
    steps = runs / settings.dt + settings.band_history_t_end * sum(1.0 / dt for dt in band.CREEP_DT)
    return Estimate(steps, "RK4 steps", PAPER_SECONDS + steps * SECONDS_PER_PAPER_STEP)


def assemble(parts: dict[str, xr.Dataset]) -> dict[str, xr.Dataset]:
    """Join the jobs' pieces into one data set per study."""
    data = {k: v for k, v in parts.items() if "/" not in k}
    data["sweep"] = xr.combine_by_coords([v for k, v in parts.items() if k.startswith("sweep/")],
                                         combine_attrs="drop_conflicts")
    data["transient"] = transient.combine([v for k, v in parts.items() if k.startswith("transient/")])
    pieces = [parts[f"band_sweep/{m}"] for m, _ in band.MODELS]
    data["band_sweep"] = xr.concat(pieces, dim="model")
    data["fig5"] = fig5.dataset(data["sweep"])
    data["fig6"] = fig6.dataset(data["sweep"])
    return data


def compute(settings: Settings | None = None) -> dict[str, xr.Dataset]:
    """Every study's data set, computed in this process (no files): what the figures and claims read.

    Parameters
    ----------
    settings:
        Run length, step and grids (default :class:`Settings`: the paper's method at tau_end = 600, dt = 1e-3).
    """

    settings = Settings() if settings is None else settings
    parts: dict[str, xr.Dataset] = {}
    for fn, args in compute_jobs(settings):
        parts.update(fn(*args))
    return assemble(parts)


#: every figure, slowest to draw first
FIGURES = ("fig4", "window_dependence", "karnopp_band", "fig5", "fig2", "fig3", "case2_decay", "fig6")


def figure_jobs(data: dict[str, xr.Dataset], settings: Settings) -> list[tuple[str, Callable[..., Any], tuple]]:
    """(file stem, plot function, its arguments) of every figure, in the order of :data:`FIGURES`."""
    t_end = settings.t_end
    return [
        ("fig4", fig4.plot, (data["fig4"],)),
        ("window_dependence", transient.plot_window, (data["transient"], t_end)),
        ("karnopp_band", band.plot, (data["band_sweep"], data["band_history"])),
        ("fig5", fig5.plot, (data["fig5"], t_end)),
        ("fig2", fig2.plot, (data["fig2"],)),
        ("fig3", fig3.plot, (data["fig3"],)),
        ("case2_decay", transient.plot_decay, (data["transient"],)),
        ("fig6", fig6.plot, (data["fig6"], t_end)),
    ]


class _Inline(Executor):
    """Runs each job as it is submitted (``workers=1``)."""

    def submit(self, fn, /, *args, **kwargs) -> Future:
        f: Future = Future()
        f.set_result(fn(*args, **kwargs))
        return f


def _executor(workers: int) -> Executor:
    if workers == 1:
        return _Inline()
    # fork: the workers inherit the imported modules and loaded kernels instead of importing them again
    methods = multiprocessing.get_all_start_methods()
    ctx = multiprocessing.get_context("fork" if "fork" in methods else None)
    return ProcessPoolExecutor(max_workers=workers, mp_context=ctx, initializer=_worker_signals)


def _worker_signals() -> None:
    """SIGTERM's default action in a pool process: a forked one inherits the command's handler, which raised
    KeyboardInterrupt wherever the pool's shutdown found it (a traceback on the shared stderr, beside the one
    error line, when one worker was killed and the pool terminated the others)."""
    signal.signal(signal.SIGTERM, signal.SIG_DFL)


def check_out_dir(out_dir: str | Path, name: str = OPTION) -> Path:
    """The output directory, created if missing; its parent must exist.

    Checked before any work: the directory can be created or written, and no
    file :func:`reproduce` writes under a known name is blocked (a directory
    in its place, a read-only file).  Errors name it ``name`` (the command
    line passes its option).
    """
    out = check_output_dir(out_dir, name)
    if out.is_dir():
        for file in output_names():
            check_output_path(out / file, None, name)
    return out


def output_names() -> list[str]:
    """The files :func:`reproduce` writes whose names are known before computing."""
    names = [f"{stem}{ext}" for stem in FIGURES for ext in (".png", ".pdf")]
    names += [f"{stem}{ext}" for stem, _title in DATASETS.values() for ext in (".nc", ".csv")]
    return names + ["claims.json", "report.html"]


def reproduce(out_dir: str | Path, settings: Settings | None = None, *, workers: int | None = None,
              progress: bool = False, dpi: float = DEFAULT_DPI) -> Summary:
    """Run every study of Figs. 2-6 with the paper's method and the exact solver; write everything to ``out_dir``.

    Writes ``fig2`` ... ``fig6`` and the three figures of "where the paper
    differs" (``case2_decay``, ``window_dependence``, ``karnopp_band``) as PNG
    and PDF, the data behind each as NetCDF and CSV, ``claims.json`` and the
    self-contained ``report.html``.

    Parameters
    ----------
    out_dir:
        Output directory (created if missing; its parent must exist).
    settings:
        Step, run length and grids; default :class:`Settings()` (the published
        configuration), :meth:`Settings.quick` for a smoke test.
    workers:
        Processes to use (default: up to 2, the cores available); at most one per independent computation.
    progress:
        Draw a progress bar on stderr.
    dpi:
        Resolution of the PNG figures (and of the report's images) in dots per inch.
    """
    start = time.perf_counter()
    settings = Settings() if settings is None else settings
    out = check_out_dir(out_dir)
    dpi = check_dpi(dpi)
    workers = min(2, os.cpu_count() or 1) if workers is None else check.positive_int("workers", workers)
    enforce(replace(reproduce_estimate(settings), cores=workers))  # within the limits in force, if any
    out.mkdir(exist_ok=True)

    jobs = compute_jobs(settings)
    files: list[Path] = []
    timings: dict[str, float] = {}
    lap = _Lap(start, timings)
    _warm_up(settings)
    lap("start-up")
    with _executor(min(workers, len(jobs))) as pool:  # a process beyond one per job would have nothing to do
        # every job is submitted before the progress bar starts its thread (workers are forked on first submit)
        pending = [pool.submit(fn, *args) for fn, args in jobs]
        with progress_bar("reproduce", len(jobs) + len(FIGURES) + len(DATASETS) + 1, enabled=progress) as advance:
            parts: dict[str, xr.Dataset] = {}
            for f in pending:
                parts.update(f.result())
                advance(1)
            data = assemble(parts)
            lap("simulations")
            described = settings.describe()
            for name, (stem, title) in DATASETS.items():
                annotate(data[name], title, described)
            outputs = [pool.submit(_plot_job, stem, fn, args, out, dpi) for stem, fn, args in figure_jobs(data, settings)]
            outputs += [pool.submit(write_dataset, data[name], out, stem) for name, (stem, _t) in DATASETS.items()]
            for f in outputs:
                files += f.result()
                advance(1)
            lap("figures and data files")
            claims = evaluate(data)
            with atomic_write(out / "claims.json", OPTION) as tmp:
                tmp.write_text(json.dumps([c.__dict__ for c in claims], indent=1), encoding="utf-8")
            report = write_report(out, data, claims, CAPTIONS, settings, time.perf_counter() - start)
            advance(1)
            lap("claims and report")
    files += [out / "claims.json", report]
    return Summary(out_dir=out, report=report, files=files, claims=claims, settings=settings,
                   seconds=time.perf_counter() - start, timings=timings, data=data)


class _Lap:
    """Records the time since the previous lap under a name."""

    def __init__(self, start: float, into: dict[str, float]) -> None:
        self.last, self.into = start, into

    def __call__(self, name: str) -> None:
        now = time.perf_counter()
        self.into[name] = now - self.last
        self.last = now


def _warm_up(settings: Settings) -> None:
    """Load what every job needs once, before the workers are forked from this process.

    The compiled kernels (from numba's disk cache, or compiled once here on a
    fresh cache), the plotting library and its fonts, and the NetCDF library
    would otherwise be loaded -- or compiled -- again by each worker.
    """
    law = paper_law(0.02, settings)
    # the solvers, both RK4 output paths (every step, thinned) and the analysis the jobs use
    for solver in (RK4(dt=settings.dt), RK4(dt=settings.dt, record_every=2), Exact(dense_dt=settings.exact_dense_dt)):
        analyze(simulate(BeltOscillator(zeta=0.01, vb=0.01), law, solver, t_end=max(1.0, 4.0 * settings.dt)))
    plt = pyplot()
    fig, ax = plt.subplots()
    ax.set(xlabel=r"$\tau$", ylabel=r"$X'$")
    fig.canvas.draw()
    plt.close(fig)
    import netCDF4  # noqa: F401
