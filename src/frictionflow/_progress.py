"""Progress bars (rich) on standard error, so ``--json`` output stays clean."""

from __future__ import annotations

from contextlib import contextmanager
from typing import Callable, Iterator

from rich.console import Console
from rich.progress import (
    BarColumn,
    MofNCompleteColumn,
    Progress,
    TaskProgressColumn,
    TextColumn,
    TimeElapsedColumn,
    TimeRemainingColumn,
)


@contextmanager
def progress_bar(
    description: str, total: float, enabled: bool = True, done: float = 0, unit: str | None = None
) -> Iterator[Callable[[float], None]]:
    """Yield ``advance(n)``; draws a bar on stderr when ``enabled``.

    With ``unit`` (e.g. "points") the bar also shows the rate in units/s.
    """
    if not enabled:
        yield lambda n: None
        return
    columns = [TextColumn("[bold]{task.description}"), BarColumn(), TaskProgressColumn(), MofNCompleteColumn()]
    if unit:
        columns.append(TextColumn("{task.fields[rate]} " + unit + "/s"))
    bar = Progress(*columns, TimeElapsedColumn(), TimeRemainingColumn(), console=Console(stderr=True))
    with bar:
        task = bar.add_task(description, total=total, completed=done, rate="-")

        def advance(n: float) -> None:
            bar.advance(task, n)
            if unit:
                speed = bar.tasks[task].speed
                bar.update(task, rate=f"{speed:,.0f}" if speed else "-")

        yield advance
