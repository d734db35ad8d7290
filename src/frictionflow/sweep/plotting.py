"""Figures of sweep results: heat maps over two parameters, and line cuts."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from ..io import write_figure


def _select(ds, var: str, keep: tuple[str, ...], sel: dict[str, Any]):
    da = ds[var]
    if sel:
        da = da.sel(sel, method="nearest")
    extra = [d for d in da.dims if d not in keep]
    if extra:
        raise ValueError(f"{var} still varies along {', '.join(extra)}: pick values with {', '.join(f'{d}=...' for d in extra)}")
    return da


def plot_map(ds, var: str, x: str, y: str, path: str | Path | None = None, log: tuple[bool, bool] = (False, False), *,
             name: str = "path", **sel: Any):
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
        A file to save the figure to (PNG, PDF or SVG by its extension), or None.
    log:
        Logarithmic (x, y) axes.
    name:
        How error messages name ``path``.
    **sel:
        A value for every other swept parameter, such as ``fd=0.02``.

    Returns
    -------
    matplotlib.figure.Figure
    """
    import matplotlib

    if path is not None:
        matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt

    da = _select(ds, var, (x, y), sel).transpose(y, x)
    fig, ax = plt.subplots(figsize=(6, 4.5), constrained_layout=True)
    m = ax.pcolormesh(da[x].values, da[y].values, da.values, shading="auto")
    fig.colorbar(m, ax=ax, label=f"{var} ({ds[var].attrs.get('long_name', '')})"[:80])
    ax.set(xlabel=x, ylabel=y, xscale="log" if log[0] else "linear", yscale="log" if log[1] else "linear")
    if sel:
        ax.set_title(", ".join(f"{k}={v:g}" for k, v in sel.items()))
    if path is not None:
        write_figure(fig, path, name)  # atomic: no partial figure on failure
    return fig


def plot_cut(ds, var: str, x: str, path: str | Path | None = None, hue: str | None = None, *, name: str = "path", **sel: Any):
    """Line cut of ``var`` along ``x``, one line per value of ``hue`` (if given).

    Parameters
    ----------
    ds:
        A sweep's dataset (:func:`run_sweep`).
    var:
        The variable to draw.
    x:
        The swept parameter of the horizontal axis.
    path:
        A file to save the figure to (PNG, PDF or SVG by its extension), or None.
    hue:
        A swept parameter drawn as one line per value, or None.
    name:
        How error messages name ``path``.
    **sel:
        A value for every other swept parameter.

    Returns
    -------
    matplotlib.figure.Figure
    """

    import matplotlib

    if path is not None:
        matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt

    keep = (x,) if hue is None else (x, hue)
    da = _select(ds, var, keep, sel)
    fig, ax = plt.subplots(figsize=(6, 4), constrained_layout=True)
    if hue is None:
        ax.plot(da[x].values, da.values, marker=".")
    else:
        for v in da[hue].values:
            ax.plot(da[x].values, da.sel({hue: v}).values, marker=".", label=f"{hue}={v:g}")
        ax.legend(fontsize=8)
    ax.set(xlabel=x, ylabel=var)
    if path is not None:
        write_figure(fig, path, name)  # atomic: no partial figure on failure
    return fig
