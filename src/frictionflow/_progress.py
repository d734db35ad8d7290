"""Progress bars (rich) on standard error, so ``--json`` output stays clean."""

from __future__ import annotations

from contextlib import contextmanager
from contextvars import ContextVar
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

#: the estimate of the work under way (set by :func:`frictionflow.estimate.enforce`), shown after each bar's name
ESTIMATE: ContextVar[str | None] = ContextVar("frictionflow_estimate", default=None)


@contextmanager
def progress_bar(
    description: str, total: float, enabled: bool = True, done: float = 0, unit: str | None = None
) -> Iterator[Callable[[float], None]]:
    """Yield ``advance(n)``; draws a bar on stderr when ``enabled``.

    With ``unit`` (e.g. "points") the bar also shows the rate in units/s; the
    estimate of the work under way, if any, follows the description.
    """
    if not enabled:
        yield lambda n: None
        return
    estimate = ESTIMATE.get()
    if estimate:
        description = f"{description} (estimated {estimate})"
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
