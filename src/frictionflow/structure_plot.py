"""Figures of a structure's run: time histories and phase portraits per coordinate, where the energy goes.

The curves are the exact solution evaluated on a fine grid
(:meth:`~frictionflow.motion.Motion.at`), never straight lines between
switches.  The energy panel is a balance of two bars over the steady-state
window: what comes in (each belt's input, each force's work) and where it
goes (each contact's heat, each damper's dissipation), so that their
heights are equal when the balance closes.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from ._figures import draws, legend_outside, pyplot, sig
from .analysis.structure import StructureAnalysis, states_at
from .io import DEFAULT_DPI, write_figure

#: at most this many periods of the window are drawn in the time histories
SHOWN_PERIODS = 5
GRID_POINTS = 4000


def energy_budget(elements: dict[str, dict[str, float]]) -> tuple[list[tuple[str, float]], list[tuple[str, float]]]:
    """(inputs, outputs): (label, average power >= 0) that feed the structure and that it loses.

    A belt's input is ``P_belt`` of its contact; a contact's heat, a damper's
    dissipation (-P) and a force's negative work are outputs.  Springs store
    and give back (their average over whole periods is zero): they are left
    out.
    """
    inputs: list[tuple[str, float]] = []
    outputs: list[tuple[str, float]] = []
    for name, powers in elements.items():
        if name.startswith("contact."):
            _signed(inputs, outputs, f"{name} belt", powers["P_belt"])
            outputs.append((f"{name} heat", powers["P_heat"]))
        elif not name.startswith("spring."):
            _signed(inputs, outputs, name, powers["P"])
    return inputs, outputs


def _signed(inputs: list, outputs: list, label: str, value: float) -> None:
    (inputs if value >= 0.0 else outputs).append((label, abs(value)))


@draws(StructureAnalysis)
def plot_structure(result: StructureAnalysis, path: str | Path | None = None, *, name: str = "path",
                   dpi: float = DEFAULT_DPI):
    """Draw each coordinate's history and phase portrait, each contact's mode and the energy budget.

    Returns the matplotlib figure; saves it to ``path`` (PNG, PDF, SVG or EPS
    by the suffix) when given.

    Parameters
    ----------
    result:
        What :func:`~frictionflow.analysis.structure.analyze_structure` returned.
    path:
        A file to save the figure to, or None.
    name:
        How error messages name ``path`` (the command line passes its option).
    dpi:
        Dots per inch of a raster file (PNG); default 150.
    """
    plt = pyplot(path)

    motion, ss = result.motion, result.steady_state
    fig, ax = plt.subplots(2, 2, figsize=(12, 7.5), layout="constrained")
    t0, t1 = _shown(ss)
    grid = np.linspace(t0, t1, GRID_POINTS)
    states = states_at(motion, (grid))
    n = states.shape[0] // 2
    for i, dof in enumerate(motion.dof):
        ax[0, 0].plot(grid, states[i], lw=0.8, label=dof)
        ax[0, 1].plot(states[i], states[n + i], lw=0.8, label=dof)
    ax[0, 0].set(xlabel=r"$\tau$", ylabel="$q$", title="displacements")
    ax[0, 1].set(xlabel="$q$", ylabel="$q'$", title="phase portraits")
    legend_outside(ax[0, 0])
    legend_outside(ax[0, 1])
    _modes_panel(ax[1, 0], motion, (t0, t1))
    _budget_panel(ax[1, 1], result)
    fig.suptitle(f"{ss.kind}" + (f", period {sig(ss.period, 4)}" if ss.kind == "periodic" else ""))
    if path is not None:
        write_figure(fig, path, name, dpi=dpi)
    return fig


def _shown(ss: Any) -> tuple[float, float]:
    t0, t1 = ss.window
    if ss.kind == "periodic" and ss.period > 0.0:
        t0 = max(t0, t1 - SHOWN_PERIODS * ss.period)
    return t0, t1


def mode_steps(motion: Any, span: tuple[float, float]) -> tuple[np.ndarray, np.ndarray]:
    """(times, modes (k, len(times))): each contact's mode over ``span`` as a step curve: the mode in force at its
    start (the last sample at or before it), each sample inside, held to its end.

    A run samples at its switches, so a window without one (a settled equilibrium) holds no sample but its end.
    """
    t, modes = np.asarray(motion.t), np.asarray(motion.modes)
    first = max(int(np.searchsorted(t, span[0], side="right")) - 1, 0)
    inside = np.flatnonzero((t > span[0]) & (t < span[1]))
    last = inside[-1] if len(inside) else first
    return (np.concatenate(([span[0]], t[inside], [span[1]])),
            modes[:, np.concatenate(([first], inside, [last]))])


def _modes_panel(ax: Any, motion: Any, span: tuple[float, float]) -> None:
    """Each contact's mode (-1 slip-, 0 stick, +1 slip+) as a step curve, offset per contact."""
    times, modes = mode_steps(motion, span)
    for j, contact in enumerate(motion.contacts):
        ax.step(times, modes[j] + 3 * j, where="post", lw=0.8, label=contact)
    ax.set(xlabel=r"$\tau$", xlim=span, ylim=(-1.5, 3 * len(motion.contacts) - 1.5),
           title="contact modes (-1 slip-, 0 stick, +1 slip+; offset 3 per contact)")
    legend_outside(ax)


def _budget_panel(ax: Any, result: StructureAnalysis) -> None:
    """Two stacked bars: the average power coming in and where it goes."""
    inputs, outputs = energy_budget(result.elements)
    if not inputs and not outputs:  # a run that lost a contact: a transient, nothing averaged
        ax.text(0.5, 0.5, f"nothing averaged ({result.steady_state.kind.replace('_', ' ')})", ha="center",
                va="center", transform=ax.transAxes)
    for x, parts in ((0, inputs), (1, outputs)):
        bottom = 0.0
        for label, value in parts:
            ax.bar(x, value, bottom=bottom, label=label)
            bottom += value
    ax.set_xticks([0, 1], ["in", "out"])
    ax.set(title=f"where the energy goes (residual {sig(result.energy_residual, 2)})")
    ax.ticklabel_format(axis="y", style="sci", scilimits=(-3, 3))
    legend_outside(ax)
