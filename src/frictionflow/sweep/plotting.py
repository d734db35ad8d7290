"""Figures of sweep results: heat maps over two parameters, and line cuts."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from .._figures import legend_outside, math_value, math_values, pyplot, symbol
from ..io import DEFAULT_DPI, write_figure


def _select(ds, var: str, keep: tuple[str, ...], sel: dict[str, Any]):
    """``var`` with ``sel`` picked, varying along ``keep`` only; one line naming a variable or dimension the dataset
    does not have, or a dimension given twice."""
    if var not in ds.data_vars:
        raise ValueError(f"var must be one of the dataset's variables ({', '.join(map(str, ds.data_vars))}), "
                         f"got {var!r}")
    dims = tuple(map(str, ds[var].dims))
    for d in (*keep, *sel):
        if d not in dims:
            raise ValueError(f"{d!r} is not a dimension of {var} (its dimensions: {', '.join(dims)})")
    if len(set(keep)) != len(keep):
        raise ValueError(f"the plotted dimensions must differ, got {', '.join(keep)}")
    da = ds[var]
    if sel:
        da = da.sel(sel, method="nearest")
    extra = [d for d in da.dims if d not in keep]
    if extra:
        raise ValueError(f"{var} still varies along {', '.join(extra)}: pick values with {', '.join(f'{d}=...' for d in extra)}")
    return da


def is_geometric(values: Any) -> bool:
    """Whether axis ``values`` are evenly spaced in log (``scale = "log"`` in a sweep's grid) and not linearly."""
    v = np.asarray(values, dtype=float)
    if v.ndim != 1 or len(v) < 3 or not np.all(v > 0):
        return False
    steps, log_steps = np.diff(v), np.diff(np.log(v))
    return bool(np.allclose(log_steps, log_steps[0], rtol=1e-9, atol=0)
                and not np.allclose(steps, steps[0], rtol=1e-9, atol=0))


def cell_edges(values: Any, log: bool) -> np.ndarray:
    """The edges of the cells centred on ``values``: midway between neighbours, in log on a log axis."""
    v = np.asarray(values, dtype=float)
    if len(v) < 2:
        half = 0.5 * abs(v[0]) if v[0] else 0.5
        return np.array([v[0] / 2, v[0] * 2]) if log else np.array([v[0] - half, v[0] + half])
    w = np.log(v) if log else v
    mid = 0.5 * (w[1:] + w[:-1])
    edges = np.concatenate([[w[0] - (mid[0] - w[0])], mid, [w[-1] + (w[-1] - mid[-1])]])
    return np.exp(edges) if log else edges


def plot_map(ds, var: str, x: str, y: str, path: str | Path | None = None, log: tuple[bool, bool] | None = None, *,
             name: str = "path", dpi: float = DEFAULT_DPI, **sel: Any):
    """Heat map of ``var`` over parameters ``x`` and ``y`` (other swept parameters fixed by ``sel``).

    Parameters
    ----------
    ds:
        A sweep's dataset (:func:`run_sweep`).
    var:
        The variable to draw (``R_c``, ``TR_B``, ``period``, ...).
    x, y:
        The swept parameters of the axes.
    path:
        A file to save the figure to (PNG, PDF, SVG or EPS by its suffix), or None.
    log:
        (x, y) log axes; None (default) takes a log axis wherever the values are evenly spaced in
        log (a sweep axis with ``scale = "log"``).  Every cell is centred on its value on either scale.
    name:
        How error messages name ``path``.
    dpi:
        Dots per inch of a raster file (PNG); default 150.
    **sel:
        A value for every other swept parameter, such as ``fd=0.02``.

    Returns
    -------
    matplotlib.figure.Figure
    """
    plt = pyplot(path)

    da = _select(ds, var, (x, y), sel).transpose(y, x)
    if log is None:
        log = (is_geometric(da[x].values), is_geometric(da[y].values))
    fig, ax = plt.subplots(figsize=(6.4, 4.8), layout="constrained")
    m = ax.pcolormesh(cell_edges(da[x].values, log[0]), cell_edges(da[y].values, log[1]), da.values, shading="flat")
    fig.colorbar(m, ax=ax, label=f"{var} ({ds[var].attrs.get('long_name', '')})"[:80])
    ax.set(xlabel=symbol(x), ylabel=symbol(y), xscale="log" if log[0] else "linear", yscale="log" if log[1] else "linear")
    if sel:
        ax.set_title(math_values(sel))
    if path is not None:
        write_figure(fig, path, name, dpi=dpi)  # atomic: no partial figure on failure
    return fig


def plot_cut(ds, var: str, x: str, path: str | Path | None = None, hue: str | None = None, *, name: str = "path",
             dpi: float = DEFAULT_DPI, **sel: Any):
    """Line cut of ``var`` along ``x``, one line per value of ``hue`` (if given).

    Parameters
    ----------
    ds:
        A sweep's dataset (:func:`run_sweep`).
    var:
        The variable to draw.
    x:
        The swept parameter of the horizontal axis (a log axis when its values are log-spaced).
    path:
        A file to save the figure to (PNG, PDF, SVG or EPS by its suffix), or None.
    hue:
        A swept parameter drawn as one line per value, or None.
    name:
        How error messages name ``path``.
    dpi:
        Dots per inch of a raster file (PNG); default 150.
    **sel:
        A value for every other swept parameter.

    Returns
    -------
    matplotlib.figure.Figure
    """
    plt = pyplot(path)

    keep = (x,) if hue is None else (x, hue)
    da = _select(ds, var, keep, sel)
    fig, ax = plt.subplots(figsize=(6.4, 4), layout="constrained")
    if hue is None:
        ax.plot(da[x].values, da.values, marker=".")
    else:
        for v in da[hue].values:
            ax.plot(da[x].values, da.sel({hue: v}).values, marker=".", label=math_value(hue, v))
        legend_outside(ax)
    ax.set(xlabel=symbol(x), ylabel=var, xscale="log" if is_geometric(da[x].values) else "linear")
    if sel:
        ax.set_title(math_values(sel))
    if path is not None:
        write_figure(fig, path, name, dpi=dpi)  # atomic: no partial figure on failure
    return fig
