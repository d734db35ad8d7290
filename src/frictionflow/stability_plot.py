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
MARKERS = {"mode_coupling": ("o", "C3"), "negative_damping": ("s", "C2"), "divergence": ("D", "k"),
           "contact_loss": ("v", "k")}
#: the shading of the values without steady sliding (a contact lost, or no isolated equilibrium)
LOST_SHADE = {"color": "0.85", "alpha": 0.6, "lw": 0}


@draws(StabilityScan)
def plot_stability(scan: StabilityScan, path: str | Path | None = None, *, name: str = "path",
                   dpi: float = DEFAULT_DPI) -> Any:
    """Real part and frequency of every eigenvalue of the upper half plane against the parameter.

    Each tracked eigenvalue is one colour in both panels, so that two frequencies that coalesce and the
    real parts that split there read as one event; the critical points are marked by kind.  Values without
    steady sliding (:attr:`~frictionflow.StabilityScan.lost`) break the loci and are
    shaded, up to the located ``contact_loss`` boundary (marked at Re = 0 in the upper panel only: it has
    no frequency).  Returns the
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
    scale = max(float(np.nanmax(np.abs(lam))), np.finfo(float).tiny)  # NaN rows: no steady sliding there
    # the conjugates repeat the same loci (NaN in both parts: a plain NaN would be NaN + 0j, a locus at Im = 0)
    upper = np.where(lam.imag >= -1e-8 * scale, lam, complex(np.nan, np.nan))
    for i in range(lam.shape[1]):
        if np.all(np.isnan(upper[:, i])):
            continue
        ax[0].plot(scan.values, upper[:, i].real, lw=1.0, color=f"C{i % 10}")
        ax[1].plot(scan.values, upper[:, i].imag, lw=1.0, color=f"C{i % 10}")
    ax[0].axhline(0.0, color="k", lw=0.6, ls=":")
    for k, (lo, hi) in enumerate(_lost_spans(scan)):
        for a in ax:
            a.axvspan(lo, hi, **LOST_SHADE, label="no steady sliding" if k == 0 and a is ax[0] else None)
    for kind in KINDS:
        at = [c for c in scan.critical if c.kind == kind]
        if at:
            marker, color = MARKERS[kind]
            label = f"{kind.replace('_', ' ')}: " + ", ".join(sig(c.value, 6) for c in at)
            ax[0].plot([c.value for c in at], [0.0] * len(at), marker, color=color, ms=6, mfc="none", label=label)
            if kind != "contact_loss":  # no mode, no frequency
                ax[1].plot([c.value for c in at], [c.frequency for c in at], marker, color=color, ms=6, mfc="none")
    for c in scan.critical:
        for a in ax:
            a.axvline(c.value, color="0.6", lw=0.6, ls="--")
    ax[0].set(ylabel=r"Re $\lambda$ (growth rate)", title="steady sliding: eigenvalues of the linearisation")
    ax[1].set(xlabel=scan.param, ylabel=r"Im $\lambda$ (frequency)")
    if scan.critical or np.any(scan.lost):
        legend_outside(ax[0])
    if path is not None:
        write_figure(fig, path, name, dpi=dpi)
    return fig


def _lost_spans(scan: StabilityScan) -> list[tuple[float, float]]:
    """(lo, hi) of each run of values without steady sliding, widened to the ``contact_loss`` point located
    between the run and its neighbour with sliding (to the run's own last value where none is)."""
    values, lost = scan.values, scan.lost
    losses = [c.value for c in scan.critical if c.kind == "contact_loss"]
    spans = []
    i = 0
    while i < len(values):
        if not lost[i]:
            i += 1
            continue
        j = i
        while j + 1 < len(values) and lost[j + 1]:
            j += 1
        ends = [values[i], values[j]]
        for end, neighbour in ((values[i], i - 1), (values[j], j + 1)):
            if 0 <= neighbour < len(values):
                lo, hi = sorted((end, values[neighbour]))
                ends += [v for v in losses if lo <= v <= hi]
        spans.append((float(min(ends)), float(max(ends))))
        i = j + 1
    return spans


@draws(StabilityChart)
def plot_stability_chart(chart: StabilityChart, path: str | Path | None = None, *, name: str = "path",
                         dpi: float = DEFAULT_DPI) -> Any:
    """The growth rate of the most unstable mode over the two parameters, with the located boundary by kind.

    The colour is max Re lambda (diverging about 0: stable blue, unstable red); the grey contour is its zero
    on the grid, the markers the points located along x on each line (:attr:`frictionflow.StabilityChart.boundary`).
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
    g = chart.growth  # NaN where a line had no steady sliding (blank in the chart)
    finite = g[np.isfinite(g)]
    top = max(float(np.abs(finite).max()) if finite.size else 0.0, np.finfo(float).tiny)
    low, high = (float(finite.min()), float(finite.max())) if finite.size else (0.0, 0.0)
    norm = TwoSlopeNorm(0.0, vmin=min(low, -top * 1e-3), vmax=max(high, top * 1e-3))
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
