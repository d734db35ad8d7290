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
