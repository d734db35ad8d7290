"""The stability chart figure: codimension-one curves drawn over a sweep heat map."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from .._figures import draws, legend_outside, pyplot, symbol
from ..io import DEFAULT_DPI, write_figure
from .charting import Chart

#: how each curve is drawn, and what it means in the legend
STYLE = {
    "hopf": dict(color="black", ls="-", lw=1.8, label="Hopf: steady sliding loses stability"),
    "grazing": dict(color="tab:red", ls="--", lw=1.6, label="grazing: stick-slip cycle appears/vanishes"),
    "fold": dict(color="tab:blue", ls="-.", lw=1.6, label="fold of cycles"),
    "fold_at_grazing": dict(color="tab:blue", ls="none", marker="x", ms=5, label="fold at a grazing corner"),
    # the forced system's curves (one per kind and orbit period m)
    "period_doubling": dict(color="tab:orange", ls="-", lw=1.8, label="period doubling"),
    "neimark_sacker": dict(color="tab:green", ls=":", lw=1.8, label="Neimark-Sacker: a torus is born"),
}
#: forced curves: what each means, for the legend (with the orbits' period)
FORCED_LABELS = {"fold": "fold: the m-orbit appears/vanishes (jump)", "grazing": "grazing: a stick phase appears/vanishes"}
CODIM2 = {"bautin": dict(marker="o", color="black", label="Bautin (Hopf changes criticality)"),
          "fold_grazing": dict(marker="s", color="tab:purple", label="fold meets grazing")}


@draws(Chart)
def plot_chart(chart, path: str | Path | None = None, *, name: str = "path", dpi: float = DEFAULT_DPI):
    """Curves of ``chart`` (a :class:`~.charting.Chart`: stability or forced) over its sweep's heat map, if it has one.

    Returns the matplotlib figure; saves it to ``path`` (PNG, PDF, SVG or EPS
    by the suffix) when given.

    Parameters
    ----------
    chart:
        The chart to draw: what :func:`~frictionflow.orbits.stability_chart` or
        :func:`~frictionflow.orbits.forced_chart` returned.  Its sweep variable
        ``heat``, if it has a sweep, is drawn as a heat map under the curves
        (at the first value of any other sweep axis).
    path:
        A file to save the figure to, or None.
    name:
        How error messages name ``path`` (the command line passes its option).
    dpi:
        Dots per inch of a raster file (PNG); default 150.
    """
    plt = pyplot(path)

    fig, ax = plt.subplots(figsize=(9.5, 5), layout="constrained")
    xp, yp = chart.x_param, chart.y_param
    if chart.sweep is not None and chart.heat:
        da = chart.sweep[chart.heat]
        extra = [d for d in da.dims if d not in (xp, yp)]
        if extra:
            da = da.isel({d: 0 for d in extra})
        da = da.transpose(yp, xp)
        m = ax.pcolormesh(da[xp].values, da[yp].values, da.values, shading="auto", cmap="viridis", alpha=0.9)
        fig.colorbar(m, ax=ax, label=chart.heat)
    grid_y = chart.grid_axis == "y"  # joined along the grid: a forced chart's curves run through its y values
    for k, c in enumerate(chart.curves):
        xy = c.xy()
        if not len(xy):
            continue
        style = dict(STYLE.get(c.kind, {"label": c.kind}))
        if c.m is not None:
            style["label"] = FORCED_LABELS.get(c.kind, style["label"]) + f", m={c.m}"
            style.setdefault("marker", ".")
            if c.m > 1:  # subharmonic orbits' curves dashed, thinner
                style["lw"] = style.get("lw", 1.6) * 0.8
                style["ls"] = (0, (1 + c.m, 2))
        if style.get("ls") == "none":
            ax.plot(xy[:, 0], xy[:, 1], **style)
            continue
        first = True
        segs = ([s[:, ::-1] for s in _segments(xy[:, ::-1], chart.grid)] if grid_y else _segments(xy, chart.grid))
        for seg in segs:
            ax.plot(seg[:, 0], seg[:, 1], **({**style} if first else {k: v for k, v in style.items() if k != "label"}))
            first = False
    for kind in CODIM2:
        pts = [(p.x, p.y) for p in chart.codim2 if p.kind == kind]
        if pts:
            arr = np.array(pts)
            ax.plot(arr[:, 0], arr[:, 1], ls="none", ms=8, mfc="white", mew=2, **CODIM2[kind])
    ax.set(xlabel=symbol(xp), ylabel=symbol(yp), xlim=(chart.x_values[0], chart.x_values[-1]), ylim=tuple(chart.y_range),
           title=f"stability chart ({chart.params.get('friction', '?')})")
    if ax.get_legend_handles_labels()[0]:
        legend_outside(ax, fontsize=7)
    if path is not None:
        write_figure(fig, path, name, dpi=dpi)
    return fig


def _segments(xy: np.ndarray, xs: np.ndarray) -> list[np.ndarray]:
    """Points joined into lines: consecutive grid x values, nearest y (a curve with two roots at one x gives two lines)."""
    grid = {float(x): i for i, x in enumerate(xs)}
    lines: list[list[tuple[float, float]]] = []
    for x, y in sorted(map(tuple, xy)):
        i = grid.get(x)
        best = None
        for line in lines:
            lx, ly = line[-1]
            if i is not None and grid.get(lx) == i - 1 and (best is None or abs(ly - y) < abs(best[-1][1] - y)):
                best = line
        if best is not None and all(grid.get(l[-1][0]) != i for l in [best]):
            best.append((x, y))
        else:
            lines.append([(x, y)])
    return [np.array(line) for line in lines]
