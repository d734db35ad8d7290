"""Late binding of result objects to their figures.

Figures are the package's leaf layer (:mod:`frictionflow._layers`): nothing
below them may import a figure module.  So a result's ``.plot()`` calls
:func:`draw`, and each figure module registers its function for the result
classes it draws with :func:`draws` when it is imported -- which
``import frictionflow`` (and each subpackage with figures) does.
"""

from __future__ import annotations

from typing import Any, Callable

_DRAWERS: dict[type, Callable[..., Any]] = {}


def draws(*classes: type) -> Callable[[Callable[..., Any]], Callable[..., Any]]:
    """Decorator: ``func(result, path, **options)`` draws instances of ``classes`` (and their subclasses)."""
    def register(func: Callable[..., Any]) -> Callable[..., Any]:
        for cls in classes:
            _DRAWERS[cls] = func
        return func

    return register


def draw(result: Any, *args: Any, **kwargs: Any) -> Any:
    """The figure of ``result`` by the function registered for its class; returns what that returns."""
    for cls in type(result).__mro__:
        func = _DRAWERS.get(cls)
        if func is not None:
            return func(result, *args, **kwargs)
    raise RuntimeError(f"no figure is registered for {type(result).__name__}: import frictionflow, whose figure "
                       "modules register them")


# -- what every figure shares: numbers in labels, legends beside the data, phase planes ----------

#: significant digits of a number in a legend, title or label (a figure is read, not parsed)
DIGITS = 3

#: the parameters' symbols in math text, for titles and legends beside math axis labels
SYMBOLS = {"zeta": r"\zeta", "vb": r"V_b", "fd": r"F_d", "fs": r"F_s", "fex": r"F_{ex}", "omega": r"\Omega",
           "phi": r"\varphi", "vd": r"V_d", "x0": r"X(0)", "v0": r"X'(0)", "t_end": r"\tau_{end}"}


def sig(x: Any, digits: int = DIGITS) -> str:
    """``x`` rounded to ``digits`` significant digits (``0.00772279`` -> ``0.00772``); text as given."""
    try:
        return f"{float(x):.{digits}g}"
    except (TypeError, ValueError):
        return str(x)


def _tex(name: str) -> str:
    return SYMBOLS.get(name, r"\mathrm{" + name.replace("_", r"\_") + "}")


def symbol(name: str) -> str:
    """A parameter's symbol as math text (``$V_b$``), for axis labels; its name if it has none."""
    return f"${_tex(name)}$"


def math_value(name: str, x: Any, digits: int = DIGITS) -> str:
    """``$V_b=0.00772$``: a parameter and its value as math text (its symbol if it has one, else its name)."""
    return f"${_tex(name)}={sig(x, digits)}$"


def math_values(values: dict[str, Any], digits: int = DIGITS) -> str:
    """Several parameters as math text, comma-separated."""
    return ", ".join(math_value(k, v, digits) for k, v in values.items())


def pyplot(path: Any) -> Any:
    """``matplotlib.pyplot``, on the file-only Agg backend when the figure goes to ``path`` (not shown)."""
    import matplotlib

    if path is not None:
        matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt

    return plt


def legend_outside(ax: Any, **kw: Any) -> Any:
    """The axes' legend to the right of the axes, where it hides no data (a layout engine makes room); None when no
    artist has a label (an empty panel: matplotlib would warn)."""
    if not ax.get_legend_handles_labels()[1] and "handles" not in kw:
        return None
    kw.setdefault("fontsize", 8)
    return ax.legend(loc="upper left", bbox_to_anchor=(1.02, 1.0), borderaxespad=0.0, frameon=False, **kw)


def equal_aspect(ax: Any) -> None:
    """One unit of X as long as one of X' (both are lengths over l_0 in the same time scale): circles look round.

    The data limits grow to fill the panel instead of the panel shrinking.
    """
    ax.set_aspect("equal", adjustable="datalim")
