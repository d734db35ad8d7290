"""Fig. 6: force transmissibility TR_B against zeta."""

from __future__ import annotations


from .._lazy import lazy_module
from .style import LABELS, figure, legend

xr = lazy_module("xarray")  # loaded on first use: importing the CLI stays quick

CAPTION = (
    "Fig. 6. Force transmissibility of system versus damping ratio zeta in steady-state motion. The black and blue "
    "lines are the characteristics of V_b = 0.01 for F_d = 0.02 and 0.04. The red and green lines are the "
    "characteristics of V_b = 0.1 for F_d = 0.02 and 0.04. Initial conditions: X(0) = F_d, X'(0) = V_b."
)


#: (V_b, F_d) -> colour, as in the paper
LINES = {(0.01, 0.02): "black", (0.01, 0.04): "tab:blue", (0.1, 0.02): "tab:red", (0.1, 0.04): "tab:green"}

VARIABLES = ("last_TR_B", "steady_TR_B", "last_amplitude", "kind")


def dataset(sweep: xr.Dataset) -> xr.Dataset:
    """TR_B over the last cycle and in the steady state, over (solver, vb, fd, zeta)."""
    return sweep[list(VARIABLES)]


def plot(ds: xr.Dataset, t_end: float):
    """One panel as the paper's; the exact solver's steady state as open squares."""
    fig, grid = figure(1, 1, (8.5, 4.5))
    ax = grid[0, 0]
    for (vb, fd), color in LINES.items():
        ax.plot(ds.zeta, ds.last_TR_B.sel(solver="rk4", vb=vb, fd=fd), "o-", color=color, ms=3.5,
                label=fr"$V_b={vb:g},\ F_d={fd:g}$")
        ax.plot(ds.zeta, ds.steady_TR_B.sel(solver="exact", vb=vb, fd=fd), "s", color=color, ms=7, mfc="none")
    ax.set(xlabel=LABELS["zeta"], ylabel=LABELS["TR_B"])
    legend(ax, fontsize=8)
    ax.set_title(rf"o-: paper's method, last cycle before $\tau={t_end:g}$;  □: exact steady state", fontsize=8)
    return fig
