"""Matplotlib set-up shared by the figures: the paper's symbols, a non-interactive backend, the layout and legends."""

from __future__ import annotations

from typing import Any

from .._figures import legend_outside

#: axis labels in the paper's symbols
LABELS = {
    "tau": r"$\tau$",
    "X": r"$X$",
    "V": r"$X'$",
    "P_f": r"$P_f$",
    "P_dv": r"$P_{dv}$",
    "R_c": r"$R_c$",
    "R_f": r"$R_f$",
    "TR_B": r"$TR_B$",
    "zeta": r"$\zeta$",
    "vb": r"$V_b$",
}

#: how the exact solver is drawn over the paper's method in the same colour
EXACT_STYLE = {"ls": (0, (2, 2)), "lw": 1.0, "alpha": 0.9}


def pyplot():
    """``matplotlib.pyplot`` on the Agg backend (files only; no display needed)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def figure(nrows: int, ncols: int, figsize: tuple[float, float]):
    """A figure with a grid of axes, laid out by matplotlib's constrained layout (legends beside the axes fit).

    The layout is computed when the figure is first drawn; :func:`freeze_layout`
    keeps it for further saves instead of measuring every text again.
    """
    plt = pyplot()
    fig, axes = plt.subplots(nrows, ncols, figsize=figsize, squeeze=False, layout="constrained")
    return fig, axes


def freeze_layout(fig: Any) -> None:
    """Keep the layout of the last draw: a second save (the PDF after the PNG) does not lay the figure out again."""
    fig.set_layout_engine("none")


def legend(ax: Any, **kw: Any) -> Any:
    """The panel's legend beside it, off the data (:func:`frictionflow._figures.legend_outside`)."""
    return legend_outside(ax, **kw)


def panel_title(ax: Any, letter: str, text: str = "") -> None:
    """The paper's panel letter, e.g. "(a)", with an optional description."""
    ax.set_title(f"({letter}) {text}".rstrip(), loc="left", fontsize=9)


def solver_note(ax: Any) -> None:
    """A small note saying which line style is which solver."""
    ax.text(0.99, 0.01, "solid: paper's method (RK4)   dashed: exact solver", transform=ax.transAxes,
            ha="right", va="bottom", fontsize=6.5, color="0.35")
