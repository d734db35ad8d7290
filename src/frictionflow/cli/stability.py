"""``frictionflow stability``: complex eigenvalues of a structure's steady sliding along one model entry.

``--vary ENTRY=FROM:TO[:N]`` (the issue's spelling ``--param ENTRY --from A --to B [--points N]`` is rewritten
to it, :data:`~frictionflow.cli.vocabulary.PIECES`).
"""

from __future__ import annotations

import functools
import json
from pathlib import Path
from typing import Optional

import numpy as np

from .. import stability_plot  # noqa: F401  (registers StabilityScan's figure)
from .._ranges import parse_named_range
from ..analysis.stability import StabilityScan, scan_estimate, stability_scan
from ..estimate import enforce
from ..io import FIGURE_FORMATS, check_input_path, check_output_path
from ..system import System, assemble, load_system
from ._app import app
from .options import bounded
from .output import print_summary, write_json
from .vocabulary import option

#: the command list's line (click would cut the docstring); cli.SHORT_HELP may name it too
SHORT_HELP = "Eigenvalues of a structure's steady sliding along one model entry: flutter and negative damping."
OUT_FORMATS = (".json",)
#: values of the entry when --vary gives no N
DEFAULT_POINTS = 101
#: at most this many values (the estimate bounds the time; this, the JSON's size)
MAX_POINTS = 100_000


@app.command(short_help=SHORT_HELP)
@bounded
def stability(
    model: Path = option("--model", "Here: the structure whose steady sliding is analysed.", required=True),
    vary: str = option("--vary", f"Here: a model entry such as contact.0.belt or spring.1.k (N values [{DEFAULT_POINTS}]).",
                       required=True),
    as_json: bool = option("--json"),
    out: Optional[Path] = option("--out", "Here: the JSON object, .json."),
    plot: Optional[Path] = option("--plot", "Here: real part and frequency of the eigenvalues against the entry."),
    dpi: float = option("--dpi"),
) -> None:
    """Complex eigenvalues of steady sliding along one model entry; where a mode's damping changes sign, located
    and told apart: mode coupling (two frequencies coalesce) or negative damping (one mode alone)."""
    if out is not None:
        check_output_path(out, OUT_FORMATS, "--out")
    if plot is not None:
        check_output_path(plot, FIGURE_FORMATS, "--plot")
    check_input_path(model, "--model")
    system = load_system(model)
    entry, values = entry_values(system, vary)
    enforce(scan_estimate(system.n, len(values)))
    at = functools.lru_cache(maxsize=4)(lambda value: system.with_entry(entry, value))
    result = stability_scan(lambda value: assemble(at(value)), values, param=entry)
    report = {"model": str(model), **result.to_dict()}
    if out is not None:
        write_json(out, report)
    if plot is not None:
        result.plot(plot, name="--plot", dpi=dpi)
    if as_json:
        print(json.dumps(report, allow_nan=False))
    else:
        print_summary(result, caption(system, model, result))


def entry_values(system: System, text: str) -> tuple[str, np.ndarray]:
    """``ENTRY=FROM:TO[:N]`` -> (ENTRY, its N values); one line if the entry is not the model's or the range is bad."""
    key, rng = parse_named_range("--vary", text, "optional")
    entry = text.partition("=")[0].strip()  # the address as written (parse_named_range spells names with _)
    system.entry(entry)  # an unknown address: the model's own one-line error
    num = DEFAULT_POINTS if rng.num is None else rng.num
    if not 2 <= num <= MAX_POINTS:
        raise ValueError(f"--vary {key}: N must be in [2, {MAX_POINTS}], got {num}")
    if rng.start == rng.stop:
        raise ValueError(f"--vary {key}: FROM and TO must differ, got {rng.start:g} twice")
    return entry, np.linspace(rng.start, rng.stop, num)


def caption(system: System, model: Path, result: StabilityScan) -> str:
    """What the table was computed from, on one line."""
    k = len(system.contact_names)
    return (f"model {model}: {system.n} dof, {k} contact{'' if k == 1 else 's'}; eigenvalues of the "
            f"linearisation about steady sliding, {len(result.values)} values of {result.param}")
