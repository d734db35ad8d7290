"""Fig. 5: the dissipation ratios R_c (damper) and R_f (friction) against zeta.

The paper's caption draws blue and green lines for F_d = 0.02 and 0.04 at
V_b = 0.01, "solid lines for zeta = 0.01 and dash lines for zeta = 0.03", and a
red symbol for V_b = 0.1 (zeta = 0.01, F_d = 0.02); it does not name the
horizontal axis.  Here the axis is zeta (as issue 4 asks) and the paper's two
damping ratios are marked by a solid (0.01) and a dashed (0.03) vertical line;
the same legend scheme against the averaging window's position is
:func:`frictionflow.paper.transient.plot_window`.
"""

from __future__ import annotations

import numpy as np

from .._lazy import lazy_module
from .style import LABELS, figure, legend, panel_title

xr = lazy_module("xarray")  # loaded on first use: importing the CLI stays quick

CAPTION = (
    "Fig. 5. Effects of the magnitude of friction F_d, damping coefficient zeta and conveyor belt speed V_b on the "
    "time-averaged power dissipation ratio (a) by the damper R_c of the system and (b) by the friction R_f. The blue "
    "and green lines are characteristics of V_b = 0.01, F_d = 0.02 and 0.04. The solid lines show the time-averaged "
    "power dissipation ratio of zeta = 0.01 and the dash lines are for zeta = 0.03. The red symbol indicates the "
    "case for V_b = 0.1 of zeta = 0.01 and F_d = 0.02. Initial conditions: X(0) = F_d, X'(0) = V_b."
)


VARIABLES = ("last_P_dv", "last_P_fin", "last_P_df", "last_R_c", "last_R_f", "last_net_friction", "last_dE",
             "steady_P_fin", "steady_R_c", "steady_R_f", "kind")


def dataset(sweep: xr.Dataset) -> xr.Dataset:
    """The ratios and the averages they are made of, over (solver, vb, fd, zeta)."""
    return sweep[list(VARIABLES)]


def plot(ds: xr.Dataset, t_end: float):
    """(a) R_c and (b) R_f against zeta over the last cycle before ``t_end``."""
    fig, grid = figure(1, 2, (13, 4.4))
    axes = grid[0]
    for ax, (name, letter) in zip(axes, (("R_c", "a"), ("R_f", "b"))):
        for fd, color in ((0.02, "tab:blue"), (0.04, "tab:green")):
            line = ds[f"last_{name}"].sel(vb=0.01, fd=fd)
            z = ds.zeta.values
            keep = z > 0 if name == "R_c" else np.ones_like(z, dtype=bool)  # R_c = 0 at zeta = 0: off a log axis
            ax.plot(z[keep], line.sel(solver="rk4").values[keep], "o-", color=color, ms=3.5, lw=1.3,
                    label=fr"$V_b=0.01,\ F_d={fd:g}$")
            ax.plot(z[keep], line.sel(solver="exact").values[keep], "x", color=color, ms=6)
        red = float(ds[f"last_{name}"].sel(solver="rk4", vb=0.1, fd=0.02, zeta=0.01))
        ax.plot([0.01], [red], "*", color="tab:red", ms=12, label=r"$V_b=0.1,\ F_d=0.02,\ \zeta=0.01$")
        ax.axvline(0.01, color="0.5", lw=0.8, ls="-")
        ax.axvline(0.03, color="0.5", lw=0.8, ls="--")
        if name == "R_c":
            ax.set_yscale("log")
        ax.set(xlabel=LABELS["zeta"], ylabel=LABELS[name])
        legend(ax, fontsize=7.5)
        panel_title(ax, letter, rf"last cycle before $\tau={t_end:g}$")
        ax.text(0.01, 0.01, "o-: paper's method (RK4)   x: exact solver, same window\n"
                r"exact steady state: $P_{fin}=0$ for every $\zeta>0$, so $R_c$ and $R_f$ are undefined",
                transform=ax.transAxes, fontsize=6.5, color="0.35", va="bottom")
    fig.suptitle(r"Dissipation ratios against damping (vertical lines: the paper's $\zeta=0.01$ solid, $0.03$ dashed)",
                 fontsize=10)
    return fig
