"""What every command's output shares: the table of a result, the line saying what produced it, the --out file."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any, Mapping, Optional

from ..io import atomic_write
from ..params import DimensionalParams

#: how each stick rule reads in the output
STICK_RULES = {"switch": "Coulomb's stick rule", "band": "a stick band |V_rel| < V_d"}
#: what runs the forced commands (a flow map, not a registered solver)
FLOW_MAP = "RK4 flow map with located switches"


def provenance(law: Any, solver: Any, dimensional: Optional[Mapping[str, Any]] = None) -> str:
    """One line: the law, its stick rule and the solver (a registered solver, or words) that produced a result; with
    the run's ``dimensional`` table, that the results are non-dimensional and the scales that convert them back."""
    rule = STICK_RULES.get(law.stick_rule, law.stick_rule)
    name = solver if isinstance(solver, str) else solver.name
    line = f"law {law.name} ({rule}), solver {name}"
    if dimensional:
        scales = DimensionalParams.from_table(dimensional)
        line += (f"; results non-dimensional: time tau = omega0 t (omega0 = {scales.omega0:.6g}), "
                 f"X = x / l_0 (l_0 = {scales.l_0:.6g}), forces f / (k l_0)")
    return line


def print_summary(result: Any, caption: str) -> None:
    """A result's summary rows (its ``_summary()``: a title and (label, value) rows) as a table, and the caption."""
    from rich.console import Console
    from rich.table import Table

    title, rows = result._summary()
    table = Table(title=title)
    table.add_column("quantity", no_wrap=True)
    table.add_column("value")
    for label, value in rows:
        table.add_row(label, value)
    show(Console(), table, caption)


def show(console: Any, table: Any, caption: str) -> None:
    """A table and, under it on one line (not wrapped to the table's width), what produced it."""
    console.print(table)
    console.print(caption, soft_wrap=True, highlight=False, markup=False)


def write_json(path: Path, report: dict[str, Any]) -> None:
    """``--out PATH.json``: the JSON object --json prints, written atomically."""
    with atomic_write(path, "--out") as tmp:
        Path(tmp).write_text(json.dumps(report, allow_nan=False) + "\n", encoding="utf-8")
