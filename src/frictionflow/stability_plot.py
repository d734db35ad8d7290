"""The figure of a stability scan: eigenvalue loci of steady sliding against the parameter, critical points marked."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from ._figures import draws, legend_outside, pyplot, sig
from .analysis.stability import KINDS, StabilityScan
from .analysis.stability_chart import StabilityChart
from .io import DEFAULT_DPI, write_figure

#: how each kind of critical point is marked
MARKERS = {"mode_coupling": ("o", "C3"), "negative_damping": ("s", "C2"), "divergence": ("D", "k")}


@draws(StabilityScan)
def plot_stability(scan: StabilityScan, path: str | Path | None = None, *, name: str = "path",
                   dpi: float = DEFAULT_DPI) -> Any:
    """Real part and frequency of every eigenvalue of the upper half plane against the parameter.

    Each tracked eigenvalue is one colour in both panels, so that two frequencies that coalesce and the
    real parts that split there read as one event; the critical points are marked by kind.  Returns the
    matplotlib figure; saves it to ``path`` (PNG, PDF, SVG or EPS by its suffix, ``dpi`` dots per inch) when given.

    Parameters
    ----------
    scan:
        A :class:`~frictionflow.analysis.stability.StabilityScan`.
    path:
        A file to save the figure to, or None.
    name:
        How error messages name ``path`` (the command line passes its option, such as ``--plot``).
    dpi:
        Dots per inch of a raster file (PNG).
    """
    plt = pyplot(path)

    fig, ax = plt.subplots(2, 1, figsize=(8, 6.5), sharex=True, layout="constrained")
    lam = scan.eigenvalues
    scale = max(float(np.abs(lam).max()), np.finfo(float).tiny)
    upper = np.where(lam.imag >= -1e-8 * scale, lam, np.nan)  # the conjugates repeat the same loci
    for i in range(lam.shape[1]):
        if np.all(np.isnan(upper[:, i])):
            continue
        ax[0].plot(scan.values, upper[:, i].real, lw=1.0, color=f"C{i % 10}")
        ax[1].plot(scan.values, upper[:, i].imag, lw=1.0, color=f"C{i % 10}")
    ax[0].axhline(0.0, color="k", lw=0.6, ls=":")
    for kind in KINDS:
        at = [c for c in scan.critical if c.kind == kind]
        if at:
            marker, color = MARKERS[kind]
            label = f"{kind.replace('_', ' ')}: " + ", ".join(sig(c.value, 6) for c in at)
            ax[0].plot([c.value for c in at], [0.0] * len(at), marker, color=color, ms=6, mfc="none", label=label)
            ax[1].plot([c.value for c in at], [c.frequency for c in at], marker, color=color, ms=6, mfc="none")
    for c in scan.critical:
        for a in ax:
            a.axvline(c.value, color="0.6", lw=0.6, ls="--")
    ax[0].set(ylabel=r"Re $\lambda$ (growth rate)", title="steady sliding: eigenvalues of the linearisation")
    ax[1].set(xlabel=scan.param, ylabel=r"Im $\lambda$ (frequency)")
    if scan.critical:
        legend_outside(ax[0])
    if path is not None:
        write_figure(fig, path, name, dpi=dpi)
    return fig


@draws(StabilityChart)
def plot_stability_chart(chart: StabilityChart, path: str | Path | None = None, *, name: str = "path",
                         dpi: float = DEFAULT_DPI) -> Any:
    """The growth rate of the most unstable mode over the two parameters, with the located boundary by kind.

    The colour is max Re lambda (diverging about 0: stable blue, unstable red); the grey contour is its zero
    on the grid, the markers the points located along x on each line (:class:`StabilityChart`.boundary).
    Returns the matplotlib figure; saves it to ``path`` (PNG, PDF, SVG or EPS by its suffix, ``dpi`` dots per
    inch) when given.

    Parameters
    ----------
    chart:
        A :class:`~frictionflow.analysis.stability_chart.StabilityChart`.
    path:
        A file to save the figure to, or None.
    name:
        How error messages name ``path`` (the command line passes its option, such as ``--plot``).
    dpi:
        Dots per inch of a raster file (PNG).
    """
    plt = pyplot(path)
    from matplotlib.colors import TwoSlopeNorm

    fig, ax = plt.subplots(figsize=(8, 6), layout="constrained")
    g = chart.growth
    top = max(float(np.abs(g).max()), np.finfo(float).tiny)
    norm = TwoSlopeNorm(0.0, vmin=min(float(g.min()), -top * 1e-3), vmax=max(float(g.max()), top * 1e-3))
    if len(chart.y_values) > 1:
        mesh = ax.pcolormesh(chart.x_values, chart.y_values, g, cmap="RdBu_r", norm=norm, shading="nearest")
        ax.contour(chart.x_values, chart.y_values, np.where(chart.stable, -1.0, 1.0), levels=[0.0], colors="0.4",
                   linewidths=0.8)
        fig.colorbar(mesh, ax=ax, label=r"max Re $\lambda$ (growth rate)")
    for kind in KINDS:
        at = [b for b in chart.boundary if b.point.kind == kind]
        if at:
            marker, color = MARKERS[kind]
            ax.plot([b.point.value for b in at], [b.y_value for b in at], marker, color=color, ms=5, mfc="none",
                    label=kind.replace("_", " "))
    ax.set(xlabel=chart.x, ylabel=chart.y, title="steady sliding: growth rate and stability boundary")
    if chart.boundary:
        legend_outside(ax)
    if path is not None:
        write_figure(fig, path, name, dpi=dpi)
    return fig
