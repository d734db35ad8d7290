"""Case II is a transient: how the averages depend on where the window sits.

With the damper on and F_s = F_d, the run leaves the band within the first
turn or two and never reaches it again (the exact solver proves it: it marks
the time ``t_terminal`` after which the motion is a free slip spiral).  In
slip the friction is the constant F_d, so the motion is a damped oscillation
about the sliding equilibrium X* = F_d whose amplitude A decays as
exp(-zeta tau).  Over one cycle, to leading order in zeta,

    P_dv ~ zeta A^2,    P_fin ~ P_df ~ F_d A / pi,    R_c ~ pi zeta A / F_d,

so every average the paper reports shrinks with the window's position, at
rates zeta (friction, R_c) and 2 zeta (damper), and there is no steady value
to report.  The net friction power over a cycle is F_d (change of X) / period:
its sign depends on whether the cycle starts at a maximum or a minimum of X
(R_f = e^(pi zeta) or e^(-pi zeta)), and it is ~F_d / A times the damper
power -- not the damper power the paper's periodic balance
P_fin = P_df + P_dv would need.

This module runs the five cases of the paper's Fig. 5 legend to
``window_t_end`` and evaluates Eq. 9 over the first whole cycle after each
window position.
"""

from __future__ import annotations

import numpy as np

from .._lazy import lazy_module
from .results import AMPLITUDE_FLOOR, decay_rate
from .runs import SOLVERS, Point, run
from .settings import Settings
from .style import EXACT_STYLE, LABELS, figure, legend, panel_title
from .windows import CYCLE_STARTS, Cycles

xr = lazy_module("xarray")  # loaded on first use: importing the CLI stays quick

#: the paper's Fig. 5 legend: (point, colour, line style, label)
CASES = (
    (Point(0.01, 0.01, 0.02), "tab:blue", "-", r"$F_d=0.02,\ \zeta=0.01$"),
    (Point(0.03, 0.01, 0.02), "tab:blue", "--", r"$F_d=0.02,\ \zeta=0.03$"),
    (Point(0.01, 0.01, 0.04), "tab:green", "-", r"$F_d=0.04,\ \zeta=0.01$"),
    (Point(0.03, 0.01, 0.04), "tab:green", "--", r"$F_d=0.04,\ \zeta=0.03$"),
    (Point(0.01, 0.1, 0.02), "tab:red", "-", r"$V_b=0.1,\ F_d=0.02,\ \zeta=0.01$"),
)


#: the paper's numbers that fix its window, for (zeta, V_b, F_d) = (0.01, 0.01, 0.02):
#: name -> (variable, value, where the paper says it)
PAPER_NUMBERS = {
    "damper power below 1e-11": ("peak_P_dv", 1e-11, "Sec. 4 on Fig. 4(a)-(c)"),
    "friction power of order 1e-6": ("peak_P_f", 1e-6, "Sec. 4 on Fig. 4(d)-(f)"),
    "99.99 % dissipated by friction": ("R_c", 1e-4, "Sec. 4 on Fig. 5"),
}

WINDOW_VARS = ("P_dv", "P_fin", "P_df", "R_c", "R_f", "TR_B", "amplitude", "net_friction", "dE")


def case_dataset(settings: Settings, case: int) -> xr.Dataset:
    """Eq. 9 over the first cycle after each window position, for one case and both solvers."""
    point = CASES[case][0]
    positions = np.arange(0.0, settings.window_t_end, settings.window_step)
    shape = (1, len(SOLVERS), len(CYCLE_STARTS), len(positions))
    data = {k: np.full(shape, np.nan) for k in (*WINDOW_VARS, "window_start", "peak_P_dv", "peak_P_f")}
    rate = np.full(shape[:2], np.nan)
    t_term = np.full(shape[:2], np.nan)
    w_dv = np.full(shape[:2], np.nan)
    w_net = np.full(shape[:2], np.nan)
    for j, s in enumerate(SOLVERS):
        traj = run(point, s, settings, t_end=settings.window_t_end)
        # whole-run totals: where the damper's energy came from (running integrals are exact at the end)
        w_dv[0, j] = traj.work[-1, 0]
        w_net[0, j] = traj.work[-1, 1] - traj.work[-1, 2]
        cycles = Cycles(traj)
        # the first turns visit the band; the decay is measured on the free spiral after them
        rate[0, j] = decay_rate(cycles, t_from=min(50.0, 0.1 * settings.window_t_end))
        t_term[0, j] = np.nan if traj.extra.get("t_terminal") is None else traj.extra["t_terminal"]
        for k, at in enumerate(CYCLE_STARTS):
            starts = cycles.starts(at)
            if len(starts) < 2:
                continue
            a = cycles.averages(starts)
            # the first whole cycle starting at or after each position
            first = np.searchsorted(a["t0"], positions)
            ok = first < len(a["t0"])
            ok[ok] &= a["amplitude"][first[ok]] > AMPLITUDE_FLOOR  # below: rounding noise about X* = F_d
            for name in (*WINDOW_VARS, "peak_P_dv", "peak_P_f"):
                data[name][0, j, k, ok] = a[name][first[ok]]
            data["window_start"][0, j, k, ok] = a["t0"][first[ok]]
    dims = ("case", "solver", "cycle_start", "tau_i")
    ds = xr.Dataset(
        {k: (dims, v) for k, v in data.items()},
        coords={
            "case": [case],
            "solver": list(SOLVERS),
            "cycle_start": list(CYCLE_STARTS),
            "tau_i": ("tau_i", positions, {"units": "1",
                                           "long_name": "window position: the cycle is the first whole one after tau_i"}),
            "zeta": ("case", [point.zeta]),
            "vb": ("case", [point.vb]),
            "fd": ("case", [point.fd]),
            "label": ("case", [point.label]),
        },
    )
    ds["decay_rate"] = (("case", "solver"), rate)
    ds["t_terminal"] = (("case", "solver"), t_term)
    ds["run_W_dv"] = (("case", "solver"), w_dv)
    ds["run_W_f_net"] = (("case", "solver"), w_net)
    ds["initial_K"] = (("case",), [0.5 * point.vb**2])
    return ds


def combine(parts: list[xr.Dataset]) -> xr.Dataset:
    """The cases together, with the window positions at which the paper's numbers are reached."""
    ds = xr.concat(sorted(parts, key=lambda p: int(p.case[0])), dim="case")
    implied, values = implied_window(ds)
    ds = ds.assign_coords(paper_number=("paper_number", list(PAPER_NUMBERS),
                                        {"long_name": "a number the paper reports for zeta = 0.01, V_b = 0.01, F_d = 0.02"}))
    ds["paper_value"] = ("paper_number", values, {"units": "1", "long_name": "the paper's value"})
    ds["implied_tau"] = ("paper_number", implied, {
        "units": "1", "long_name": "window position at which the paper's method gives the paper's value"})
    return ds


def dataset(settings: Settings) -> xr.Dataset:
    """All cases (serially; :func:`frictionflow.paper.reproduce` runs them in parallel)."""
    return combine([case_dataset(settings, i) for i in range(len(CASES))])


def implied_window(ds: xr.Dataset) -> tuple[list[float], list[float]]:
    """Where the paper's method reaches each of the paper's numbers (base case, RK4, cycles from maxima).

    Each quantity decays monotonically with the window position, so the
    crossing is found by interpolating log(quantity) against tau_i.
    """
    base = ds.sel(solver="rk4", cycle_start="max").isel(case=0)
    out, values = [], []
    for var, value, _where in PAPER_NUMBERS.values():
        y = base[var].values
        t = base.window_start.values
        ok = np.isfinite(y) & (y > 0)
        ly, lt = np.log(y[ok])[::-1], t[ok][::-1]  # increasing in y for np.interp
        inside = ly[0] <= np.log(value) <= ly[-1]
        out.append(float(np.interp(np.log(value), ly, lt)) if inside else float("nan"))
        values.append(value)
    return out, values


def _lines(ax, ds: xr.Dataset, var: str, cycle_start: str = "max", offset: float = 0.0) -> None:
    for i, (_p, color, ls, label) in enumerate(CASES):
        for s in SOLVERS:
            c = ds.sel(solver=s, cycle_start=cycle_start).isel(case=i)
            kw = {"color": color, "ls": ls, "lw": 1.2, "label": label} if s == "rk4" else {"color": color, **EXACT_STYLE}
            if s == "exact":
                kw["ls"] = ":"
            ax.plot(c.window_start, c[var] - offset, **kw)


YLABELS = {"peak_P_dv": r"max $P_{dv}$ over the cycle", "peak_P_f": r"max $|P_f|$ over the cycle",
           "R_c": LABELS["R_c"], "TR_B": r"$TR_B - 1$"}


def plot_window(ds: xr.Dataset, t_end: float):
    """The paper's numbers against the window position, in the paper's Fig. 5 legend scheme."""
    fig, axes = figure(2, 2, (12.5, 7.5))
    panels = (
        ("peak_P_dv", "a", r"largest instantaneous $P_{dv}$ in the cycle (Fig. 4a-c)", "damper power below 1e-11"),
        ("peak_P_f", "b", r"largest instantaneous $|P_f|$ in the cycle (Fig. 4d-f)", "friction power of order 1e-6"),
        ("R_c", "c", r"$R_c = \bar P_{dv}/\bar P_{f,in}$ (Fig. 5a)", "99.99 % dissipated by friction"),
        ("TR_B", "d", r"$TR_B - 1$ (Fig. 6)", None),
    )
    for ax, (var, letter, title, number) in zip(axes.flat, panels):
        _lines(ax, ds, var, offset=1.0 if var == "TR_B" else 0.0)
        if number is not None:
            value = float(ds.paper_value.sel(paper_number=number))
            at = float(ds.implied_tau.sel(paper_number=number))
            ax.axhline(value, color="k", lw=0.8, ls="-.")
            ax.annotate(f"paper: {number}\n(reached at τ ≈ {at:.0f})", (0.98, 0.97), xycoords="axes fraction",
                        ha="right", va="top", fontsize=7.5)
        ax.axvline(t_end, color="0.5", lw=0.8)
        ax.set_yscale("log")
        ax.set(xlabel=r"window position $\tau_i$ (start of the averaging cycle)", ylabel=YLABELS[var])
        panel_title(ax, letter, title)
    legend(axes[0, 0], fontsize=7)
    fig.suptitle(f"Case II: everything the paper averages decays with the window's position "
                 f"(solid/dashed: paper's method; dotted: exact; grey line: our t_end = {t_end:g})", fontsize=9.5)
    return fig


def plot_decay(ds: xr.Dataset):
    """(a) cycle amplitude against time with fitted rates; (b) the power balance of the base case."""
    fig, grid = figure(1, 2, (13, 4.3))
    axes = grid[0]
    ax = axes[0]
    for i, (p, color, ls, label) in enumerate(CASES):
        c = ds.sel(cycle_start="max").isel(case=i)
        r = float(c.decay_rate.sel(solver="rk4"))
        ax.plot(c.window_start.sel(solver="rk4"), c.amplitude.sel(solver="rk4"), color=color, ls=ls,
                label=f"{label}: rate {r:.5f}")
        ax.plot(c.window_start.sel(solver="exact"), c.amplitude.sel(solver="exact"), color=color, ls=":")
    ax.set_yscale("log")
    ax.set(xlabel=LABELS["tau"], ylabel="cycle amplitude (half the range of X)")
    legend(ax, fontsize=7)
    panel_title(ax, "a", r"amplitude decays as $e^{-\zeta\tau}$: no limit cycle")

    ax = axes[1]
    base = ds.sel(solver="rk4").isel(case=0)
    ax.plot(base.window_start.sel(cycle_start="max"), base.P_dv.sel(cycle_start="max"), color="k",
            label=r"$\bar P_{dv}$ (damper)")
    ax.plot(base.window_start.sel(cycle_start="min"), base.net_friction.sel(cycle_start="min"), color="tab:orange",
            label=r"$\bar P_{f,in}-\bar P_{df}$, cycles from a minimum of X (> 0)")
    ax.plot(base.window_start.sel(cycle_start="max"), -base.net_friction.sel(cycle_start="max"), color="tab:purple",
            ls="--", label=r"$-(\bar P_{f,in}-\bar P_{df})$, cycles from a maximum of X (net < 0)")
    ax.set_yscale("log")
    ax.set(xlabel=r"window position $\tau_i$", ylabel="power")
    legend(ax, fontsize=7)
    panel_title(ax, "b", r"$\zeta=0.01, V_b=0.01, F_d=0.02$: friction's net input vs the damper")
    return fig
