"""Fig. 3: Case II (with damper) phase portraits the paper calls limit cycles.

They are drawn over the end of each run (the last ``shown_span`` time units,
about three turns), where the paper looked.  The turns do not close: the
motion is a spiral shrinking by exp(-2 pi zeta) per turn (see
:mod:`.transient`).
"""

from __future__ import annotations


from .._figures import equal_aspect
from .._lazy import lazy_module
from .cases import cases_dataset, select
from .results import Runner
from .runs import Point
from .style import EXACT_STYLE, LABELS, figure, legend, panel_title, solver_note

xr = lazy_module("xarray")  # loaded on first use: importing the CLI stays quick

CAPTION = (
    "Fig. 3. Limit cycles on steady-state response for case II (the effect of the damper is considered). "
    "In (a), the blue and red lines are characteristics for zeta = 0.01 and 0.03 with consistent parameters of "
    "F_d = 0.02, V_b = 0.01. In (b), the blue and red lines are the characteristic for V_b = 0.01 and 0.1 with "
    "consistent parameters of F_d = 0.02, zeta = 0.01. Initial conditions: X(0) = F_d, X'(0) = V_b."
)


CASES = (Point(0.01, 0.01, 0.02), Point(0.03, 0.01, 0.02), Point(0.01, 0.1, 0.02))

#: panel -> [(zeta, V_b, colour, legend)], all at F_d = 0.02
PANELS = {
    "a": [(0.01, 0.01, "tab:blue", r"$\zeta=0.01$"), (0.03, 0.01, "tab:red", r"$\zeta=0.03$")],
    "b": [(0.01, 0.01, "tab:blue", r"$V_b=0.01$"), (0.01, 0.1, "tab:red", r"$V_b=0.1$")],
}


def dataset(runner: Runner) -> xr.Dataset:
    """X and X' over the end of each run, with the window scalars and decay rates."""
    return cases_dataset(runner, CASES)


def plot(ds: xr.Dataset):
    """Two phase-portrait panels as the paper's, each orbit labelled with its size."""
    fig, grid = figure(1, 2, (13, 4.6))
    axes = grid[0]
    for ax, (letter, lines) in zip(axes, PANELS.items()):
        for zeta, vb, color, label in lines:
            c = select(ds, zeta, vb, 0.02)
            a = float(c.last_amplitude.sel(solver="rk4"))
            ax.plot(c.X.sel(solver="rk4"), c.V.sel(solver="rk4"), color=color, lw=1.0,
                    label=f"{label}: amplitude {a:.2g}")
            ax.plot(c.X.sel(solver="exact"), c.V.sel(solver="exact"), color=color, **EXACT_STYLE)
        ax.plot([0.02], [0.0], "k+", ms=9, label=r"sliding equilibrium $X^*=F_d$")
        ax.set(xlabel=LABELS["X"], ylabel=LABELS["V"])
        ax.ticklabel_format(style="sci", scilimits=(-3, 3), useOffset=True)
        equal_aspect(ax)
        ax.locator_params(axis="x", nbins=5)  # the X values differ in the 4th digit: long tick labels
        legend(ax, fontsize=7.5)
        solver_note(ax)
        t0, t1 = float(ds.tau[0]), float(ds.tau[-1])
        ax.text(0.99, 0.06, fr"$\tau \in [{t0:g}, {t1:g}]$", transform=ax.transAxes, ha="right", fontsize=7.5)
    panel_title(axes[0], "a", r"$F_d=0.02,\ V_b=0.01$")
    panel_title(axes[1], "b", r"$F_d=0.02,\ \zeta=0.01$")
    fig.suptitle("Case II: end of each run in the phase plane (the turns shrink: a spiral, not a limit cycle)",
                 fontsize=10)
    return fig

