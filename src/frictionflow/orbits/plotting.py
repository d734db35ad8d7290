"""Bifurcation diagrams, power along branches, and the picture of one orbit.

Stable solutions are drawn solid, unstable (and neutral) dashed; equilibria
in grey, orbits in colour; bifurcations are marked on the amplitude panel and
brute-force sweep points overlaid as dots.  Figures are saved as PNG, PDF,
SVG or EPS by the file's suffix, at ``dpi`` dots per inch (150 by default).
"""

from __future__ import annotations

from collections.abc import Iterable
from pathlib import Path
from typing import Any

import numpy as np

from .._figures import draws, equal_aspect, legend_outside, math_values, pyplot, sig, symbol
from ..analysis.power_flow import instantaneous_power
from ..io import DEFAULT_DPI, FIGURE_FORMATS, write_figure  # noqa: F401  (FIGURE_FORMATS: re-exported)
from .branches import Branch, ContinuationResult
from .shooting import PeriodicOrbit
_MARKERS = {"hopf": "o", "fold": "s", "grazing": "D", "switching": "v", "period_blowup": "x", "branch_end": "x"}


def _runs(branch: Branch) -> Iterable[tuple[bool, list[int]]]:
    """Consecutive index runs of equal stability (each run shares its end point with the next)."""
    pts = branch.points
    start = 0
    for i in range(1, len(pts) + 1):
        if i == len(pts) or pts[i].stable != pts[start].stable:
            yield pts[start].stable, list(range(start, min(i + 1, len(pts))))
            start = i


def _draw(ax, result: ContinuationResult, quantity: str, colors: dict[int, Any], label_branches: bool = False) -> None:
    for bi, b in enumerate(result.branches):
        color = "0.4" if b.kind == "equilibrium" else colors[bi]
        for stable, idx in _runs(b):
            xs = [b.points[i].value for i in idx]
            ys = [_value(b.points[i], quantity) for i in idx]
            label = None
            if label_branches and idx[0] == 0:
                label = "equilibrium" if b.kind == "equilibrium" else f"orbits ({b.seed})"
            ax.plot(xs, ys, ls="-" if stable else "--", color=color, lw=1.4 if stable else 1.0, label=label)


def _value(point, quantity: str) -> float:
    if quantity == "amplitude":
        return point.amplitude
    if quantity == "period":
        return np.nan if point.period is None else point.period
    if quantity == "TR_B":
        return point.measures.TR_B
    return point.measures.averages()[quantity]


@draws(ContinuationResult)
def plot_bifurcation(result: ContinuationResult, path: str | Path | None = None, *, sweep: bool = True, name: str = "path",
                     dpi: float = DEFAULT_DPI):
    """Amplitude, power flow, power ratios and TR_B against the parameter, one panel each.

    Returns the figure; saves it to ``path`` when given.

    Parameters
    ----------
    result:
        What :func:`~frictionflow.orbits.continuation` returned.
    path:
        A file to save the figure to (PNG, PDF, SVG or EPS by its suffix), or None.
    sweep:
        Draw the brute-force simulations of ``result.sweep`` as dots.
    name:
        How error messages name ``path`` (the command line passes its option, such as ``--plot``).
    dpi:
        Dots per inch of a raster file (PNG); default 150.
    """
    plt = pyplot(path)
    fig, ax = plt.subplots(2, 2, figsize=(12, 8), sharex=True, layout="constrained")
    colors = {bi: f"C{bi % 10}" for bi in range(len(result.branches))}
    a = ax[0, 0]
    _draw(a, result, "amplitude", colors, label_branches=True)
    for bif in result.bifurcations:
        b = result.branches[bif.branch] if bif.branch is not None else None
        y = 0.0
        if b is not None and b.kind == "periodic" and b.points:
            near = min(b.points, key=lambda p: abs(p.value - bif.value))
            y = near.amplitude
        a.plot([bif.value], [y], _MARKERS.get(bif.type, "*"), color="k", ms=6, mfc="none")
        a.annotate(bif.type.replace("_", " "), (bif.value, y), textcoords="offset points", xytext=(4, 4), fontsize=7)
    if sweep and result.sweep:
        sw = [s for s in result.sweep if s["kind"] in ("periodic", "equilibrium")]
        a.plot([s["value"] for s in sw], [s["amplitude"] for s in sw], ".", color="k", ms=4, label="simulations")
    a.set(ylabel=r"amplitude $(X_{max}-X_{min})/2$", title="bifurcation diagram (solid stable, dashed unstable)")
    legend_outside(a, fontsize=7)

    _draw_quantities(ax[0, 1], result, (("P_fin", "C2"), ("P_df", "C1"), ("P_dv", "C0")))
    ax[0, 1].set(title="average power along the orbit branches", ylabel="power")
    ax[0, 1].ticklabel_format(axis="y", style="sci", scilimits=(-3, 3))
    _draw_quantities(ax[1, 0], result, (("R_c", "C0"), ("R_f", "C1")))
    ax[1, 0].set(xlabel=symbol(result.param), ylabel="ratio", title=r"$R_c = P_{dv}/P_{fin}$, $R_f = P_{df}/P_{fin}$")

    _draw(ax[1, 1], result, "TR_B", colors)
    ax[1, 1].set(xlabel=symbol(result.param), ylabel=r"$TR_B$", title="force transmissibility")
    fig.suptitle(_title(result))
    if path is not None:
        write_figure(fig, path, name, dpi=dpi)  # atomic: no partial figure on failure
    return fig


def _draw_quantities(ax, result: ContinuationResult, quantities: tuple[tuple[str, str], ...]) -> None:
    """Several quantities of every orbit branch, one colour per quantity (equilibria carry no vibration power)."""
    for q, color in quantities:
        for b in result.branches:
            if b.kind != "periodic":
                continue
            for stable, idx in _runs(b):
                ax.plot([b.points[i].value for i in idx], [_value(b.points[i], q) for i in idx], ls="-" if stable else "--",
                        color=color, label=f"${q[0]}_{{{q[2:]}}}$")
    _legend_unique(ax)


def _legend_unique(ax) -> None:
    handles, labels = ax.get_legend_handles_labels()
    seen: dict[str, Any] = {}
    for h, l in zip(handles, labels, strict=True):
        if l not in seen or (seen[l].get_linestyle() != "-" and h.get_linestyle() == "-"):
            seen[l] = h  # a solid (stable) line stands for the quantity in the legend
    if seen:
        legend_outside(ax, handles=list(seen.values()), labels=list(seen.keys()), fontsize=7)


def _title(result: ContinuationResult) -> str:
    fixed = {k: v for k, v in result.params.items() if isinstance(v, float) and k != result.param}
    return f"continuation in {symbol(result.param)} ({result.params.get('friction')}: {math_values(fixed)})"


@draws(PeriodicOrbit)
def plot_orbit(orbit: PeriodicOrbit, path: str | Path | None = None, *, name: str = "path", dpi: float = DEFAULT_DPI):
    """Phase portrait (equal aspect), X(tau) and the instantaneous friction and damper power over one period.

    Parameters
    ----------
    orbit:
        What :func:`~frictionflow.orbits.find_orbit` returned.
    path:
        A file to save the figure to (PNG, PDF, SVG or EPS by its suffix), or None.
    name:
        How error messages name ``path`` (the command line passes its option, such as ``--plot``).
    dpi:
        Dots per inch of a raster file (PNG); default 150.

    Returns
    -------
    matplotlib.figure.Figure
    """

    plt = pyplot(path)
    traj = orbit.trajectory(dense_dt=orbit.period / 400)
    fig, ax = plt.subplots(1, 3, figsize=(15, 4.2), layout="constrained")
    stick = traj.mode == 0
    ax[0].plot(traj.x, traj.v, color="C3", lw=1.2)
    ax[0].plot(traj.x[stick], traj.v[stick], ".", color="k", ms=2, label="stick")
    ax[0].plot([orbit.state[0]], [0.0], "o", color="k", mfc="none", label="section point")
    ax[0].axhline(orbit.model.vb, color="k", ls=":", lw=0.8)
    ax[0].set(xlabel="$X$", ylabel="$X'$", title="phase portrait")
    equal_aspect(ax[0])
    legend_outside(ax[0], fontsize=7)
    ax[1].plot(traj.t, traj.x, label="$X$")
    ax[1].plot(traj.t, traj.v, label="$X'$")
    ax[1].set(xlabel=r"$\tau$", title=f"one period $T={sig(orbit.period, 4)}$")
    legend_outside(ax[1], fontsize=7)
    p = instantaneous_power(traj)
    ax[2].plot(traj.t, p["P_f"], label="$P_f$")
    ax[2].plot(traj.t, p["P_dv"], label="$P_{dv}$")
    ax[2].set(xlabel=r"$\tau$", title="instantaneous power")
    ax[2].ticklabel_format(axis="y", style="sci", scilimits=(-3, 3))
    legend_outside(ax[2], fontsize=7)
    mu = orbit.multiplier
    fig.suptitle(f"{orbit.stability} orbit, multiplier {sig(mu.real, 4)}{mu.imag:+.2g}j, "
                 f"stick fraction {sig(orbit.stick_fraction)}, $TR_B={sig(orbit.measures.TR_B, 4)}$")
    if path is not None:
        write_figure(fig, path, name, dpi=dpi)  # atomic: no partial figure on failure
    return fig
