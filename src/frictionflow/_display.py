"""How result objects show themselves: a short text ``repr`` and an HTML table for notebooks.

Every public result type (:class:`~frictionflow.trajectory.Trajectory`,
:class:`~frictionflow.analysis.Analysis`,
:class:`~frictionflow.orbits.PeriodicOrbit`,
:class:`~frictionflow.orbits.ContinuationResult`) derives from
:class:`Summarized` and says only *what* to show, in :meth:`Summarized._summary`:
a title and a few (label, value) rows.  This module renders them, once, as
text (``repr``) and as an HTML table (``_repr_html_``, which Jupyter shows).
Dataclasses that use it pass ``repr=False`` so that the generated field dump
does not replace it.
"""

from __future__ import annotations

import html
import math
from typing import Any

Row = tuple[str, str]


def num(x: Any, digits: int = 6) -> str:
    """A number in ``digits`` significant digits (``None``/NaN as ``-``, complex as a + bj)."""
    if x is None:
        return "-"
    if isinstance(x, complex):
        return f"{x.real:.{digits}g}{x.imag:+.{min(digits, 3)}g}j"
    try:
        f = float(x)
    except (TypeError, ValueError):
        return str(x)
    return "-" if math.isnan(f) else f"{f:.{digits}g}"


def pairs(values: dict[str, Any], digits: int = 4) -> str:
    """``a=1.2, b=3.4``: several numbers on one row."""
    return ", ".join(f"{k}={num(v, digits)}" for k, v in values.items())


def render_text(title: str, rows: list[Row]) -> str:
    """The title, then one indented ``label  value`` line per row."""
    width = max((len(label) for label, _ in rows), default=0)
    return "\n".join([title, *(f"  {label:<{width}}  {value}" for label, value in rows)])


def render_html(title: str, rows: list[Row]) -> str:
    """The same as an HTML table with the title as its caption (escaped: values can hold ``<``)."""
    body = "".join(
        f"<tr><th style='text-align:left'>{html.escape(label)}</th>"
        f"<td style='text-align:left'>{html.escape(value)}</td></tr>"
        for label, value in rows
    )
    caption = f"<caption style='text-align:left;font-weight:bold'>{html.escape(title)}</caption>"
    return f"<table class='frictionflow-summary'>{caption}{body}</table>"


class Summarized:
    """Mixin: ``repr`` and ``_repr_html_`` from :meth:`_summary` (a title and (label, value) rows)."""

    __slots__ = ()

    def _summary(self) -> tuple[str, list[Row]]:  # pragma: no cover - every subclass overrides it
        raise NotImplementedError

    def __repr__(self) -> str:
        return render_text(*self._summary())

    def _repr_html_(self) -> str:
        return render_html(*self._summary())


def system_row(model: Any, friction: Any) -> Row:
    """The oscillator and law of a result, on one row."""
    return "system", f"zeta={num(model.zeta, 4)}, V_b={num(model.vb, 4)}; {friction!r}"


def spoken(names: tuple[str, ...], conjunction: str = "or") -> str:
    """Names as a phrase for messages and help: "a", "a or b", "a, b or c"."""
    if len(names) <= 1:
        return "".join(names)
    return f"{', '.join(names[:-1])} {conjunction} {names[-1]}"
