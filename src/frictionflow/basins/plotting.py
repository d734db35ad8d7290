"""Figures of basins: the basin map over the initial states, and basin stability against a parameter."""

from __future__ import annotations

from pathlib import Path
import numpy as np

from .._figures import draws, legend_outside, math_values, pyplot, sig
from ..io import DEFAULT_DPI, write_figure
from ..parameters import declared
from .study import Basins

#: one colour per outcome name, the same in every figure
_COLOURS = {"equilibrium": "tab:blue", "slip_cycle": "tab:orange", "stick_slip_cycle": "tab:red",
            "not_settled": "0.75", "diverged": "black", "quasi_periodic": "gold", "chaotic": "darkviolet"}
_MORE = ("tab:green", "tab:purple", "tab:brown", "tab:pink", "tab:olive", "tab:cyan")


def colour(name: str, i: int) -> str:
    """The colour of outcome ``name`` (the i-th outcome)."""
    return _COLOURS.get(name, _MORE[i % len(_MORE)])


@draws(Basins)
def plot_basins(result: Basins, path: str | Path | None = None, *, name: str = "path", dpi: float = DEFAULT_DPI):
    """The basin map, or with ``vary`` the basin-stability curves; saved atomically to ``path`` if given.

    Parameters
    ----------
    result:
        What :func:`basins` returned.
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

    fig, ax = plt.subplots(figsize=(7.6, 4.8) if result.vary else (7.6, 5.0), layout="constrained")
    if result.vary is None:
        _map(ax, result)
    else:
        _curves(ax, result)
    ds = result.dataset
    law = ds.attrs.get("friction", "")
    fixed = {k.removeprefix("fixed_"): ds.attrs[k] for k in ("fixed_zeta", "fixed_vb") if k in ds.attrs}
    ax.set_title(f"{law}: {math_values(fixed | {'t_end': ds.attrs.get('t_end', float('nan'))})}", fontsize=9)
    if path is not None:
        write_figure(fig, path, name, dpi=dpi)  # atomic: no partial figure on failure
    return fig


def _present(result: Basins) -> list[tuple[int, str]]:
    """(index, name) of the outcomes that some point reaches."""
    counts = np.asarray(result.dataset["basin_count"]).reshape(-1, len(result.names))
    return [(j, n) for j, n in enumerate(result.names) if counts[:, j].sum() > 0]


def _map(ax, result: Basins) -> None:
    """Every initial state coloured by its outcome; the legend gives each basin's stability."""
    from matplotlib.colors import ListedColormap
    from matplotlib.patches import Patch

    ds = result.dataset
    shown = _present(result)  # (every point has an outcome: never empty)
    labels = np.asarray(ds["label"].values)
    slot = np.full(labels.shape, np.nan)  # code -> colour slot
    for k, (j, _) in enumerate(shown):
        slot[labels == int(ds["outcome"][j])] = k
    cmap = ListedColormap([colour(n, j) for j, n in shown])
    if "sample" in ds.dims:
        ax.scatter(ds["x0"].values, ds["v0"].values, c=slot, cmap=cmap, vmin=-0.5, vmax=len(shown) - 0.5, s=6, linewidths=0)
    else:
        ax.pcolormesh(ds["x0"].values, ds["v0"].values, slot.T if ds["label"].dims == ("x0", "v0") else slot,
                      cmap=cmap, vmin=-0.5, vmax=len(shown) - 0.5, shading="auto")
    for j, n in shown:
        if n.startswith("equilibrium"):
            ax.plot(float(ds["attractor_x_mid"][j]), 0.0, marker="*", ms=12, color="white", mec="black", ls="none")
    p, se = result.fractions, result.stderr
    legend_outside(ax, handles=[Patch(color=colour(n, j), label=f"{n}: {sig(p[n])} ± {sig(se[n], 1)}") for j, n in shown],
                   title="basin stability")
    ax.set(xlabel="$X(0)$", ylabel="$X'(0)$")
    spans = np.ptp(ds["x0"].values), np.ptp(ds["v0"].values)
    if min(spans) > 0 and 1 / 3 < spans[0] / spans[1] < 3:
        ax.set_aspect("equal")  # X and X' in the same units: the energy's level sets look round


def _curves(ax, result: Basins) -> None:
    """Basin stability of each outcome against the varied parameter, with binomial error bars."""
    x = result.dataset[result.vary].values
    for j, n in _present(result):
        ax.errorbar(x, result.fractions[n], yerr=result.stderr[n], marker="o", ms=4, capsize=2, color=colour(n, j), label=n)

    ax.set(xlabel=declared()[result.vary].long_name, ylabel="basin stability", ylim=(-0.02, 1.02))
    legend_outside(ax)
