"""``frictionflow reproduce``: every figure of the reference paper, its data, and the report."""

from __future__ import annotations

import dataclasses
import json
import sys
from pathlib import Path
from typing import TYPE_CHECKING, Optional

import typer

from ..io import OutputError
from ..paper import Settings, reproduce as run_reproduction
from ..paper.export import OPTION
from ..paper.pipeline import check_out_dir
from ._app import app
from ..parameters import declared
from .options import bounded, renamed
from .vocabulary import checked_by, option, parameter_help

#: the declared parameters reproduce takes (with the paper's defaults), by name; their ranges are the declared ones
#: (checked as the command line is read, as simulate's), t_end's narrowed by the span the time histories show
HELP = parameter_help("reproduce", ("t_end", "dt"), {
    "t_end": f"Here: the run length of Figs. 2-6, > {Settings.shown_span:g} (the span its time histories show).",
    "dt": "Here: the step of the paper's method."})

if TYPE_CHECKING:
    from ..paper import Summary


@app.command()
@bounded
def reproduce(
    out: Path = option("--out", "Here: a directory (created if missing; its parent must exist).", required=True),
    t_end: Optional[float] = typer.Option(None, "--t-end", help=HELP["t_end"], rich_help_panel="Window",
                                          callback=checked_by("--t-end", declared()["t_end"])),
    dt: Optional[float] = typer.Option(None, "--dt", help=HELP["dt"], rich_help_panel="Solver",
                                       callback=checked_by("--dt", declared()["dt"])),
    workers: Optional[int] = option("--workers"),
    quick: bool = option("--quick"),
    as_json: bool = option("--json", "Here: the verdicts, files and timings."),
    dpi: float = option("--dpi"),
) -> None:
    """Reproduce Figs. 2-6 of the paper with its method and the exact solver; write figures, data and report.html."""
    base = Settings.quick() if quick else Settings()
    changes = {k: v for k, v in (("t_end", t_end), ("dt", dt)) if v is not None}
    if t_end is not None and t_end > base.window_t_end:
        changes["window_t_end"] = t_end  # the window study covers at least the run length
    try:  # validated by Settings (t_end beyond the span shown), named as the option
        settings = dataclasses.replace(base, **changes)
    except ValueError as e:
        raise renamed(e, "t_end", "--t-end") from None
    # every option is checked by now (the numbers as the command line was read): --out is the last, and is created
    # only once the work is accepted
    check_out_dir(out, "--out")  # named as the option (reproduce() checks it again before any work)
    try:
        summary = run_reproduction(out, settings, workers=workers, progress=sys.stderr.isatty(), dpi=dpi)
    except (ValueError, OutputError) as e:  # a write that failed on the way, said of the API's argument
        raise renamed(e, OPTION, "--out") from None
    if as_json:
        print(json.dumps(summary.to_dict()))
    else:
        _print_summary(summary)


def _print_summary(summary: Summary) -> None:
    """The verdicts as a table, and where the report is."""
    from rich.console import Console
    from rich.table import Table

    table = Table(title=f"paper claims checked: {summary.counts()}")
    table.add_column("figure")
    table.add_column("the paper's claim")
    table.add_column("our verdict on it")
    for c in summary.claims:
        table.add_row(c.figure, c.key, c.verdict)
    console = Console()
    console.print(table)
    console.print(f"report: {summary.report}  ({len(summary.files)} files, {summary.seconds:.1f} s)")
