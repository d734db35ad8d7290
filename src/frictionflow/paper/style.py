"""Matplotlib set-up shared by the figures: the paper's symbols and a non-interactive backend."""

from __future__ import annotations

from typing import Any

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


def figure(nrows: int, ncols: int, figsize: tuple[float, float], **adjust: float):
    """A figure with a grid of axes laid out once by ``subplots_adjust``.

    Matplotlib's constrained layout would re-measure every text on each of
    the two saves (PNG and PDF) and doubles the drawing time; fixed margins
    suffice for figures whose contents we know.
    """
    plt = pyplot()
    fig, axes = plt.subplots(nrows, ncols, figsize=figsize, squeeze=False)
    margins = {"left": 0.07, "right": 0.98, "bottom": 0.1, "top": 0.88, "wspace": 0.22, "hspace": 0.35}
    margins.update(adjust)
    fig.subplots_adjust(**margins)
    return fig, axes


def panel_title(ax: Any, letter: str, text: str = "") -> None:
    """The paper's panel letter, e.g. "(a)", with an optional description."""
    ax.set_title(f"({letter}) {text}".rstrip(), loc="left", fontsize=9)


def solver_note(ax: Any) -> None:
    """A small note saying which line style is which solver."""
    ax.text(0.99, 0.01, "solid: paper's method (RK4)   dashed: exact solver", transform=ax.transAxes,
            ha="right", va="bottom", fontsize=6.5, color="0.35")
