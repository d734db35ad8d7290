"""Fig. 4: Case II instantaneous damper power (a-c) and friction power (d-f)."""

from __future__ import annotations


from .._lazy import lazy_module
from .cases import cases_dataset, select
from .results import Runner
from .runs import Point
from .style import EXACT_STYLE, LABELS, figure, legend, panel_title, solver_note

xr = lazy_module("xarray")  # loaded on first use: importing the CLI stays quick

CAPTION = (
    "Fig. 4. Instantaneous power flow quantities of system on steady-state motion for case II (the effect of the "
    "viscous damper is considered). In (a) and (d), the black and red lines are characteristics for F_d = 0.02 and "
    "0.04 with consistent parameters of zeta = 0.01 and V_b = 0.01. In (b) and (e), the black and blue lines are "
    "characteristics for V_b = 0.01 and 0.1 with consistent parameters of F_d = 0.02 and zeta = 0.01. In (c) and "
    "(f), the blue and red lines are characteristics for zeta = 0.01 and 0.03 with consistent parameters of "
    "F_d = 0.02 and V_b = 0.01. (a), (b) and (c) are the instantaneous power dissipation characteristics by the "
    "viscous damping. (d), (e) and (f) are power flow quantities of the friction force. "
    "Initial conditions: X(0) = F_d, X'(0) = V_b."
)


CASES = (Point(0.01, 0.01, 0.02), Point(0.01, 0.01, 0.04), Point(0.01, 0.1, 0.02), Point(0.03, 0.01, 0.02))

#: column -> [(zeta, V_b, F_d, colour, legend)]; the top row shows P_dv, the bottom row P_f
COLUMNS = (
    [(0.01, 0.01, 0.02, "black", r"$F_d=0.02$"), (0.01, 0.01, 0.04, "tab:red", r"$F_d=0.04$")],
    [(0.01, 0.01, 0.02, "black", r"$V_b=0.01$"), (0.01, 0.1, 0.02, "tab:blue", r"$V_b=0.1$")],
    [(0.01, 0.01, 0.02, "tab:blue", r"$\zeta=0.01$"), (0.03, 0.01, 0.02, "tab:red", r"$\zeta=0.03$")],
)


def dataset(runner: Runner) -> xr.Dataset:
    """P_dv(tau) and P_f(tau) at the end of each run, with peaks and last-cycle averages."""
    return cases_dataset(runner, CASES)


def plot(ds: xr.Dataset):
    """2 x 3 panels as the paper's; each legend entry carries the line's peak value."""
    fig, axes = figure(2, 3, (16, 6.5))
    for col, lines in enumerate(COLUMNS):
        for row, (var, peak, sym) in enumerate((("P_dv_inst", "peak_P_dv", "P_dv"), ("P_f", "peak_P_f", "P_f"))):
            ax = axes[row, col]
            for zeta, vb, fd, color, label in lines:
                c = select(ds, zeta, vb, fd)
                top = float(c[peak].sel(solver="rk4"))
                ax.plot(c.tau, c[var].sel(solver="rk4"), color=color, lw=1.0, label=f"{label} (peak {top:.2g})")
                ax.plot(c.tau, c[var].sel(solver="exact"), color=color, **EXACT_STYLE)
            ax.set(xlabel=LABELS["tau"], ylabel=LABELS[sym])
            ax.ticklabel_format(axis="y", style="sci", scilimits=(-3, 3))
            legend(ax, fontsize=7)
            panel_title(ax, "abcdef"[3 * row + col])
    solver_note(axes[1, 2])
    fig.suptitle("Case II: instantaneous damper power (top) and friction power (bottom) at the end of the run",
                 fontsize=10)
    return fig
