"""Fig. 2: Case I (no damper) friction power time histories in the steady state.

Case I's steady state in closed form (zeta = 0, F_s = F_d, F_e = X): slipping
forward (V_r > V_d) with F_c = F_d the motion is a circle about (F_d, 0) in
the (X, X') plane.  Inside the band with |X| < F_d, F_c = X and X'' = 0, so
X' stays at the band edge V_b - V_d until X = F_d, where the motion leaves
tangentially onto the circle of radius V_b - V_d -- which touches the band
edge again without entering it.  Hence, for V_b > V_d, a pure-slip circle:
period 2 pi, P_f = F_d X' and P_fin = P_df = F_d (V_b - V_d) / pi,
TR_B = (F_d + V_b - V_d) / F_d.
"""

from __future__ import annotations


from .._lazy import lazy_module
from .cases import cases_dataset, select
from .results import Runner
from .runs import Point
from .style import EXACT_STYLE, LABELS, figure, legend, panel_title, solver_note

xr = lazy_module("xarray")  # loaded on first use: importing the CLI stays quick

CAPTION = (
    "Fig. 2. Time histories of instantaneous power dissipation by the friction for case I in the steady state. "
    "In (a), the blue, red and green lines are the quantities for V_b = 0.001, 0.01 and 0.1 with a consistent "
    "F_d = 0.02, respectively. In (b), the blue and red lines are the characteristic for F_d = 0.02 and 0.04 "
    "with a consistent V_b = 0.01, respectively. Initial conditions: X(0) = F_d, X'(0) = V_b."
)


CASES = (Point(0.0, 0.001, 0.02), Point(0.0, 0.01, 0.02), Point(0.0, 0.1, 0.02), Point(0.0, 0.01, 0.04))

#: panel -> [(V_b, F_d, colour, legend)]
PANELS = {
    "a": [(0.001, 0.02, "tab:blue", r"$V_b=0.001$"), (0.01, 0.02, "tab:red", r"$V_b=0.01$"),
          (0.1, 0.02, "tab:green", r"$V_b=0.1$")],
    "b": [(0.01, 0.02, "tab:blue", r"$F_d=0.02$"), (0.01, 0.04, "tab:red", r"$F_d=0.04$")],
}


def dataset(runner: Runner) -> xr.Dataset:
    """P_f(tau) (and X, X', F_c) at the end of each Case I run, with its steady state."""
    ds = cases_dataset(runner, CASES)
    v_d = runner.settings.vd
    # the circle of radius V_b - V_d (module docstring); no cycle for V_b <= V_d
    ds["P_fin_closed_form"] = ("case", [p.fd * max(p.vb - v_d, 0.0) / 3.141592653589793 for p in CASES])
    return ds


def plot(ds: xr.Dataset):
    """Two panels as the paper's: (a) V_b at F_d = 0.02, (b) F_d at V_b = 0.01."""
    fig, grid = figure(1, 2, (12, 3.8))
    axes = grid[0]
    for ax, (letter, lines) in zip(axes, PANELS.items()):
        for vb, fd, color, label in lines:
            c = select(ds, 0.0, vb, fd)
            ax.plot(c.tau, c.P_f.sel(solver="rk4"), color=color, lw=1.2, label=label)
            ax.plot(c.tau, c.P_f.sel(solver="exact"), color=color, **EXACT_STYLE)
        ax.axhline(0.0, color="0.6", lw=0.6)
        ax.set(xlabel=LABELS["tau"], ylabel=LABELS["P_f"])
        ax.ticklabel_format(axis="y", style="sci", scilimits=(-3, 3))
        legend(ax, fontsize=8)
        solver_note(ax)
    panel_title(axes[0], "a", r"$F_d=0.02$")
    panel_title(axes[1], "b", r"$V_b=0.01$")
    fig.suptitle(r"Case I ($\zeta=0$): friction power $P_f = X'F_c$ at the end of the run", fontsize=10)
    return fig
