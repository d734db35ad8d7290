"""``frictionflow stability``: complex eigenvalues of a structure's steady sliding along one or two model entries.

``--vary ENTRY=FROM:TO[:N]`` (the issue's spelling ``--param ENTRY --from A --to B [--points N]`` is rewritten
to it, :data:`~frictionflow.cli.vocabulary.PIECES`) scans one entry; ``--x ENTRY=...`` with ``--y ENTRY=...`` (as
``map`` spells its two parameters) charts two, the boundary located along x on every value of y.
"""

from __future__ import annotations

import functools
import json
import sys
from pathlib import Path
from typing import Optional

import numpy as np

from .. import stability_plot  # noqa: F401  (registers StabilityScan's figure)
from .._ranges import parse_named_range
from ..analysis.stability import StabilityScan, scan_estimate, stability_scan
from ..analysis.stability_chart import StabilityChart, chart_estimate, stability_chart
from ..estimate import enforce
from ..io import FIGURE_FORMATS, check_input_path, check_output_path
from ..system import System, assemble, load_system
from ._app import app
from .options import bounded
from .output import print_summary, write_json
from .vocabulary import option

#: the command list's line (click would cut the docstring); cli.SHORT_HELP may name it too
SHORT_HELP = "Eigenvalues of a structure's steady sliding over one or two model entries: flutter, negative damping."
OUT_FORMATS = (".json",)
#: values of the entry when --vary gives no N
DEFAULT_POINTS = 101
#: values of each entry of a chart when --x or --y gives no N
DEFAULT_CHART_POINTS = 41
#: at most this many values (the estimate bounds the time; this, the JSON's size)
MAX_POINTS = 100_000


@app.command(short_help=SHORT_HELP)
@bounded
def stability(
    model: Path = option("--model", "Here: the structure whose steady sliding is analysed.", required=True),
    vary: Optional[str] = option("--vary", "Here: a model entry such as contact.0.belt or spring.1.k (N values "
                                 f"[{DEFAULT_POINTS}]); or --x and --y for two entries."),
    x: Optional[str] = option("--x", f"Here: a model entry, with --y: a chart over two (N values [{DEFAULT_CHART_POINTS}]);"
                              " the boundary is located along x."),
    y: Optional[str] = option("--y", f"Here: the chart's second model entry (N values [{DEFAULT_CHART_POINTS}])."),
    as_json: bool = option("--json"),
    out: Optional[Path] = option("--out", "Here: the JSON object, .json."),
    plot: Optional[Path] = option("--plot", "Here: real part and frequency of the eigenvalues against the entry; "
                                  "with --x and --y the growth-rate chart and its boundary."),
    dpi: float = option("--dpi"),
) -> None:
    """Complex eigenvalues of steady sliding along one model entry, or over two; where a mode's damping changes
    sign, located and told apart: mode coupling (two frequencies coalesce) or negative damping (one mode alone)."""
    _check_study(vary, x, y)
    if out is not None:
        check_output_path(out, OUT_FORMATS, "--out")
    if plot is not None:
        check_output_path(plot, FIGURE_FORMATS, "--plot")
    check_input_path(model, "--model")
    system = load_system(model)
    result = _scan(system, vary) if vary is not None else _chart(system, x, y)
    report = {"model": str(model), **result.to_dict()}
    if out is not None:
        write_json(out, report)
    if plot is not None:
        result.plot(plot, name="--plot", dpi=dpi)
    if as_json:
        print(json.dumps(report, allow_nan=False))
    else:
        print_summary(result, caption(system, model, result))


def _check_study(vary: str | None, x: str | None, y: str | None) -> None:
    """One study: --vary alone, or --x with --y."""
    if vary is not None and (x is not None or y is not None):
        raise ValueError("--vary scans one entry, --x with --y charts two: give one or the other")
    if vary is None and (x is None or y is None):
        missing = "--vary, or --x with --y" if x is None and y is None else ("--y" if y is None else "--x")
        raise ValueError(f"stability needs {missing} (the model entries to vary)")


def _scan(system: System, vary: str) -> StabilityScan:
    entry, values = entry_values(system, vary)
    enforce(scan_estimate(system.n, len(values)))
    # steady sliding alone: the file's initial state is no start here, so its normal loads are not checked
    at = functools.lru_cache(maxsize=4)(lambda value: system.with_entry(entry, value, start=False))
    return stability_scan(lambda value: assemble(at(value)), values, param=entry)


def _chart(system: System, x: str, y: str) -> StabilityChart:
    (xe, xs), (ye, ys) = (entry_values(system, text, flag, DEFAULT_CHART_POINTS) for flag, text in
                          (("--x", x), ("--y", y)))
    if xe == ye:
        raise ValueError(f"--x and --y name the same entry {xe}: give two different ones")
    enforce(chart_estimate(system.n, len(xs), len(ys)))
    # both entries set at once: they may bound each other (a contact's fd and fs)
    return stability_chart(lambda a, b: assemble(system.with_entries({xe: a, ye: b}, start=False)), xs, ys, x=xe, y=ye,
                           progress=sys.stderr.isatty())


def entry_values(system: System, text: str, flag: str = "--vary",
                 default_points: int = DEFAULT_POINTS) -> tuple[str, np.ndarray]:
    """``ENTRY=FROM:TO[:N]`` -> (ENTRY, its N values); one line if the entry is not the model's or the range is bad."""
    key, rng = parse_named_range(flag, text, "optional", least=2)
    entry = text.partition("=")[0].strip()  # the address as written (parse_named_range spells names with _)
    value = system.entry(entry)  # an unknown address: the model's own one-line error
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise ValueError(f"{flag} {entry}: not a numeric entry (it is {value!r}): vary a number of the model")
    if entry.split(".")[0] == "initial":
        raise ValueError(f"{flag} {entry}: steady sliding and its eigenvalues do not depend on the initial state: "
                         "vary an element's or the mass's entry")
    num = default_points if rng.num is None else rng.num
    if num > MAX_POINTS:
        raise ValueError(f"{flag} {key}: N must be in [2, {MAX_POINTS}], got {num}")
    if rng.start == rng.stop:
        raise ValueError(f"{flag} {key}: FROM and TO must differ, got {rng.start:g} twice")
    return entry, rng.grid(num)


def caption(system: System, model: Path, result: StabilityScan | StabilityChart) -> str:
    """What the table was computed from, on one line."""
    k = len(system.contact_names)
    what = (f"{len(result.values)} values of {result.param}" if isinstance(result, StabilityScan) else
            f"{len(result.x_values)} x {len(result.y_values)} values of {result.x} x {result.y}")
    return (f"model {model}: {system.n} dof, {k} contact{'' if k == 1 else 's'}; eigenvalues of the "
            f"linearisation about steady sliding, {what}")
