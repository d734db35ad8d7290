"""The package's layer order, declared once; ``tests/test_layers.py`` holds the code to it.

A module may import modules of its own layer or of a lower one, never of a
higher one, and only at module level (an import hidden in a function hides a
cycle).  Figures are a leaf layer: result objects' ``.plot()`` methods reach
them through :mod:`frictionflow._figures`, where the figure modules register
their functions when :mod:`frictionflow` imports them.

Each layer lists dotted module prefixes: a prefix covers the module and
everything under it, the longest matching prefix wins, and ``pkg.__init__``
names a package's own ``__init__`` only (a facade re-exporting a higher layer).
"""

from __future__ import annotations

#: lowest first; a module's rank is the index of its layer
LAYERS: tuple[tuple[str, tuple[str, ...]], ...] = (
    ("rules", (
        "frictionflow.core", "frictionflow.modes", "frictionflow.quantities", "frictionflow.parameters",
        "frictionflow._validate", "frictionflow._progress", "frictionflow.estimate", "frictionflow._display", "frictionflow._layers",
        "frictionflow._figures", "frictionflow._json", "frictionflow._version", "frictionflow._lazy",
        "frictionflow._ranges", "frictionflow._compile_ahead", "frictionflow._interrupt",
    )),
    ("laws", ("frictionflow.friction",)),
    ("model", ("frictionflow.params", "frictionflow.system")),
    ("engines", (
        "frictionflow.solvers", "frictionflow._continuous", "frictionflow.trajectory", "frictionflow.simulate",
        "frictionflow.config", "frictionflow.motion",
    )),
    ("results", ("frictionflow.io",)),
    ("analysis", ("frictionflow.analysis",)),
    ("studies", ("frictionflow.orbits", "frictionflow.sweep", "frictionflow.basins")),
    ("figures", (
        "frictionflow.plotting", "frictionflow.basins.plotting", "frictionflow.orbits.plotting",
        "frictionflow.orbits.chart_plot", "frictionflow.orbits.forced_plot", "frictionflow.sweep.plotting",
        "frictionflow.structure_plot", "frictionflow.stability_plot",
        "frictionflow.paper",
    )),
    # the facades: the package and the subpackages whose namespace re-exports figures
    ("api", (
        "frictionflow.__init__", "frictionflow.orbits.__init__", "frictionflow.sweep.__init__",
        "frictionflow.basins.__init__",
    )),
    ("cli", ("frictionflow.cli", "frictionflow.__main__")),
)


def layer_of(module: str, is_package: bool = False) -> tuple[int, str]:
    """(rank, layer name) of dotted ``module`` (``is_package``: it is a package's ``__init__``).

    KeyError if no layer covers it: every module must be placed.
    """
    best: tuple[int, int, str] | None = None  # (prefix length, rank, name)
    for rank, (name, prefixes) in enumerate(LAYERS):
        for prefix in prefixes:
            if prefix.endswith(".__init__"):
                hit = is_package and module == prefix.removesuffix(".__init__")
            else:
                hit = module == prefix or module.startswith(prefix + ".")
            if hit and (best is None or len(prefix) > best[0]):
                best = (len(prefix), rank, name)
    if best is None:
        raise KeyError(f"{module} is in no layer of frictionflow._layers.LAYERS")
    return best[1], best[2]
