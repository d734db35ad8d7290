"""Figures of one run: time history, phase portrait and power flow.

Every figure draws the true curve between the solver's samples
(:meth:`~frictionflow.trajectory.Trajectory.dense`: closed form or the
solver's interpolant at >= 64 points per natural period), never straight
lines between switches.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ._figures import draws, equal_aspect, legend_outside, math_values, pyplot, sig
from .analysis.power_flow import instantaneous_power
from .analysis.summary import Analysis
from .io import DEFAULT_DPI, FIGURE_FORMATS, write_figure  # noqa: F401  (FIGURE_FORMATS: re-exported)
from .trajectory import Trajectory

MAX_POINTS = 20_000
#: a time history longer than this many periods is drawn over its last ``SHOWN_PERIODS`` only: more
#: periods than this across a panel merge into a solid band
LONG_PERIODS = 20
SHOWN_PERIODS = 10


def _thin(n: int, max_points: int = MAX_POINTS) -> slice:
    return slice(None, None, max(1, n // max_points))


def shown_span(t0: float, t1: float, period: float | None) -> tuple[float, float]:
    """The part of [t0, t1] a time history shows: all of it, or its last ``SHOWN_PERIODS`` periods when it
    is longer than ``LONG_PERIODS`` (``period`` None: the natural period 2 pi)."""
    period = period if period else 2 * np.pi
    if t1 - t0 <= LONG_PERIODS * period:
        return t0, t1
    return t1 - SHOWN_PERIODS * period, t1


def _history_title(span: tuple[float, float], whole: tuple[float, float]) -> str:
    """"time history", saying which part of the run when it is not all of it."""
    if span == whole:
        return "time history"
    return rf"time history, $\tau\in[{sig(span[0], 4)}, {sig(span[1], 4)}]$ of $[{sig(whole[0], 4)}, {sig(whole[1], 4)}]$"


def _system_title(traj: Trajectory) -> str:
    """The run's parameters as math text, rounded to significant digits."""
    values = {"zeta": traj.zeta, "vb": traj.vb, "fd": traj.friction.fd, "fs": traj.friction.fs}
    if traj.model.forced:
        values.update(fex=traj.model.fex, omega=traj.model.omega)
    return f"{traj.friction.name}: " + math_values(values)


@draws(Analysis)
def plot_run(result: Analysis, path: str | Path | None = None, *, name: str = "path", dpi: float = DEFAULT_DPI):
    """Draw X(tau), X'(tau), the phase portrait and the power flow of the steady window.

    A run longer than ``LONG_PERIODS`` periods shows the last
    ``SHOWN_PERIODS`` periods of its steady-state window in the time
    history (the phase portrait still shows the whole run).  Returns the
    matplotlib figure; saves it to ``path`` (PNG, PDF, SVG or EPS by the
    suffix, ``dpi`` dots per inch) when given.

    Parameters
    ----------
    result:
        What :func:`~frictionflow.analyze` returned.
    path:
        A file to save the figure to, or None.
    name:
        How error messages name ``path`` (the command line passes its option, such as ``--plot``).
    dpi:
        Dots per inch of a raster file (PNG); default 150.
    """
    plt = pyplot(path)

    traj = result.trajectory.dense()  # the true curve between samples, not straight lines between switches
    ss = result.steady_state
    i0, i1 = traj.index(ss.window[0]), traj.index(ss.window[1])
    whole = _thin(len(traj))
    win = slice(i0, i1 + 1)
    wthin = _thin(i1 + 1 - i0)

    fig, ax = plt.subplots(2, 2, figsize=(12, 7.5), layout="constrained")
    _history_panel(ax[0, 0], traj, ss)

    ax[0, 1].plot(traj.x[whole], traj.v[whole], lw=0.5, color="0.7", label="whole run")
    ax[0, 1].plot(traj.x[win][wthin], traj.v[win][wthin], lw=1.0, color="C3", label="steady-state\nwindow")
    ax[0, 1].axhline(traj.vb, color="k", ls=":", lw=0.8, label=r"$X'=V_b$")
    ax[0, 1].set(xlabel="$X$", ylabel="$X'$", title="phase portrait")
    equal_aspect(ax[0, 1])
    legend_outside(ax[0, 1])

    # The last three periods of the window (or the last 20 time units) keep the waveform legible.
    period = 3 * ss.period if ss.period else 20.0
    j0 = max(i0, traj.index(ss.window[1] - period))
    last = slice(j0, i1 + 1)
    p = instantaneous_power(traj)
    lthin = _thin(i1 + 1 - j0)
    tw = traj.t[last][lthin]
    forced = traj.model.forced
    lines = [("P_f", r"$P_f$"), ("P_dv", r"$P_{dv}$"), ("P_heat", r"$P_{heat}$")] + ([("P_ex", r"$P_{ex}$")] if forced else [])
    for key, label in lines:
        ax[1, 0].plot(tw, p[key][last][lthin], lw=0.8, label=label)
    ax[1, 0].set(xlabel=r"$\tau$", title="instantaneous power (end of window)")
    legend_outside(ax[1, 0])

    av = result.power.averages(forced=True)
    names = ["P_fin", "P_df", "P_dv", "P_belt", "P_heat"] + (["P_ex"] if forced else [])
    vals = [av[k] for k in names]
    ax[1, 1].bar([f"$P_{{{k[2:]}}}$" for k in names], vals, color=["C2", "C1", "C0", "C4", "C3", "C5"][: len(names)])
    ax[1, 1].set(title=f"averages (residual {sig(result.energy_residual, 2)})")
    ax[1, 1].ticklabel_format(axis="y", style="sci", scilimits=(-3, 3))

    fig.suptitle(f"{_system_title(traj)}   $TR_B={sig(result.TR_B, 4)}$")
    if path is not None:
        write_figure(fig, path, name, dpi=dpi)  # atomic: no partial figure on failure
    return fig


def _history_panel(ax, traj: Trajectory, ss) -> None:
    """X and X' against tau over the run, or over the end of the steady-state window of a long run; the window shaded."""
    run = (float(traj.t[0]), float(traj.t[-1]))
    span = shown_span(*run, ss.period)
    if span != run:
        span = shown_span(float(ss.window[0]), float(ss.window[1]), ss.period)
    shown = slice(traj.index(span[0]), traj.index(span[1]) + 1)
    sthin = _thin(shown.stop - shown.start)
    ax.plot(traj.t[shown][sthin], traj.x[shown][sthin], lw=0.7, label="$X$")
    ax.plot(traj.t[shown][sthin], traj.v[shown][sthin], lw=0.7, label="$X'$")
    ax.axvspan(max(ss.window[0], span[0]), ss.window[1], color="0.9", zorder=0, label=f"window ({ss.kind})")
    ax.set(xlabel=r"$\tau$", title=_history_title(span, run))
    legend_outside(ax)


@draws(Trajectory)
def plot_trajectory(traj, path: str | Path | None = None, *, name: str = "path", dpi: float = DEFAULT_DPI):
    """X and X' against tau, and the phase portrait, on the true curve; the switches marked.

    A run longer than ``LONG_PERIODS`` natural periods shows its last
    ``SHOWN_PERIODS`` in the time history.
    Returns the matplotlib figure; saves it to ``path`` (PNG, PDF, SVG or EPS by
    its suffix, ``dpi`` dots per inch) when given.

    Parameters
    ----------
    traj:
        A run, from :func:`~frictionflow.simulate`.
    path:
        A file to save the figure to, or None.
    name:
        How error messages name ``path`` (the command line passes its option, such as ``--plot``).
    dpi:
        Dots per inch of a raster file (PNG); default 150.
    """

    plt = pyplot(path)

    curve = traj.dense()
    whole = _thin(len(curve))
    run = (float(curve.t[0]), float(curve.t[-1]))
    span = shown_span(*run, None)
    shown = slice(curve.index(span[0]), curve.index(span[1]) + 1)
    sthin = _thin(shown.stop - shown.start)
    sw = traj.switches()
    sw_shown = sw & (traj.t >= span[0]) & (traj.t <= span[1])
    fig, ax = plt.subplots(1, 2, figsize=(11, 4), layout="constrained")
    ax[0].plot(curve.t[shown][sthin], curve.x[shown][sthin], lw=0.8, label="$X$")
    ax[0].plot(curve.t[shown][sthin], curve.v[shown][sthin], lw=0.8, label="$X'$")
    ax[0].plot(traj.t[sw_shown], traj.x[sw_shown], "k.", ms=3, label="switches")
    ax[0].set(xlabel=r"$\tau$", title=_history_title(span, run))
    legend_outside(ax[0])
    ax[1].plot(curve.x[whole], curve.v[whole], lw=0.8, color="C3")
    ax[1].plot(traj.x[sw], traj.v[sw], "k.", ms=3, label="switches")
    ax[1].axhline(traj.vb, color="k", ls=":", lw=0.8, label=r"$X'=V_b$")
    ax[1].set(xlabel="$X$", ylabel="$X'$", title="phase portrait")
    equal_aspect(ax[1])
    legend_outside(ax[1])
    fig.suptitle(f"{_system_title(traj)}; solver {traj.solver.get('name', '?')}", fontsize=9)
    if path is not None:
        write_figure(fig, path, name, dpi=dpi)
    return fig


def plot_response(ds, path: str | Path | None = None, *, name: str = "path", dpi: float = DEFAULT_DPI):
    """The frequency response (:func:`frictionflow.analysis.response.frequency_response`) against Omega.

    Amplitude, TR_B, the power the external force puts in and what the damper
    and the interface take out, and the stick fraction; the up and down
    sweeps drawn apart, so that jumps and hysteresis show.  Steady states
    that are not periodic are marked (x: quasi-periodic, chaotic or not
    settled).  Saved to ``path`` (PNG, PDF, SVG or EPS by the suffix, ``dpi``
    dots per inch) when given.
    """
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(2, 2, figsize=(12, 7.5), sharex=True, layout="constrained")
    w = ds["omega"].values
    style = {"up": dict(color="C0", marker=">", ms=3), "down": dict(color="C3", marker="<", ms=3, ls="--")}
    for d in ds["direction"].values:
        sel = ds.sel(direction=d)
        kw = style.get(str(d), {})
        ax[0, 0].plot(w, sel["amplitude"], label=f"sweep {d}", **kw)
        ax[0, 1].plot(w, sel["TR_B"], **kw)
        ax[1, 0].plot(w, sel["P_ex"], label=f"$P_{{ex}}$ {d}", **kw)
        ax[1, 0].plot(w, sel["P_dv"], alpha=0.6, lw=0.8, color=kw.get("color"), ls=":", label=f"$P_{{dv}}$ {d}")
        ax[1, 1].plot(w, sel["stick_fraction"], **kw)
        other = sel["kind"].values != 0
        if other.any():
            ax[0, 0].plot(w[other], sel["amplitude"].values[other], "kx", ms=6)
    ax[0, 0].set(ylabel="amplitude $(X_{max}-X_{min})/2$", title="amplitude")
    legend_outside(ax[0, 0])
    ax[0, 1].set(ylabel=r"$TR_B$", title=r"transmissibility max$|X+2\zeta X'|/F_{ex}$")
    ax[1, 0].set(xlabel=r"$\Omega$", ylabel="power", title="power in (external force) and out (damper)")
    legend_outside(ax[1, 0], fontsize=7)
    ax[1, 1].set(xlabel=r"$\Omega$", ylabel="stick fraction", title="stick fraction")
    attrs = ds.attrs
    values = {k: attrs.get(k, 0) for k in ("zeta", "vb", "fex", "fd", "fs")}
    fig.suptitle(f"{attrs.get('friction', '')}: " + math_values(values))
    if path is not None:
        write_figure(fig, path, name, dpi=dpi)
    return fig
