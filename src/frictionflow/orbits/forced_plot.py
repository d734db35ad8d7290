"""Bifurcation diagrams of forced periodic orbits, with the stroboscopic brute-force overlay.

:func:`plot_forced_branches` draws branches of :func:`~frictionflow.orbits.continue_forced`
against lambda (Omega or F_ex): the amplitude (or the stroboscopic X at
tau = 0), stable pieces solid and unstable ones dashed, bifurcation points
marked, and beside it the power along the branch (P_ex, P_dv, P_fin, P_df)
and TR_B.  With a :class:`~.forced.StroboscopicSweep` the brute-force
section points (X at tau_k of the last forcing periods, swept with state
continuation) are overlaid as dots on the X panel: where the branch is
stable they lie on it, and past a bifurcation they show what the motion
does instead.  Saved as PNG, PDF, SVG or EPS by the file's suffix, at ``dpi``
dots per inch.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from pathlib import Path

import numpy as np

from .._figures import equal_aspect, legend_outside, math_values, pyplot
from ..core import forced_map as fm
from ..io import DEFAULT_DPI, write_figure
from ..solvers.base import kernel_params
from .forced import DEFAULT_STEPS, ForcedBranch, ForcedOrbit, StroboscopicSweep

MARKERS = {"fold": "s", "period_doubling": "^", "neimark_sacker": "o", "grazing": "D", "branch_end": "x",
           "branch_point": "*"}
LABELS = {"omega": r"$\Omega$", "fex": r"$F_{ex}$"}


def _runs(branch: ForcedBranch) -> Iterable[tuple[bool, list[int]]]:
    """Consecutive index runs of equal stability (each shares its end point with the next)."""
    pts = branch.points
    start = 0
    for i in range(1, len(pts) + 1):
        if i == len(pts) or pts[i].stable != pts[start].stable:
            yield pts[start].stable, list(range(start, min(i + 1, len(pts))))
            start = i


def _event_value(branch: ForcedBranch, lam: float, what: str) -> float:
    """The branch's value at lambda of an event (the nearest point's; events lie between points)."""
    i = int(np.argmin(np.abs(branch.lam - lam)))
    p = branch.points[i]
    return p.amplitude if what == "amplitude" else p.state[0]


def plot_forced_branches(branches: ForcedBranch | Sequence[ForcedBranch], path: str | Path | None = None, *,
                         sweep: StroboscopicSweep | None = None, name: str = "path", dpi: float = DEFAULT_DPI):
    """The bifurcation diagram of ``branches`` (one parameter), with ``sweep``'s brute-force dots on the X panel.

    Parameters
    ----------
    branches:
        One or more branches from :func:`~frictionflow.orbits.continue_forced`, in the same parameter.
    path:
        A file to save the figure to (PNG, PDF, SVG or EPS by its suffix), or None.
    sweep:
        A :func:`~frictionflow.orbits.stroboscopic_sweep` to draw as dots, or None.
    name:
        How error messages name ``path`` (the command line passes its option, such as ``--plot``).
    dpi:
        Dots per inch of a raster file (PNG); default 150.

    Returns
    -------
    matplotlib.figure.Figure
    """

    plt = pyplot(path)

    if isinstance(branches, ForcedBranch):
        branches = [branches]
    if not branches:
        raise ValueError("branches: nothing to plot")
    parameter = branches[0].parameter
    if any(b.parameter != parameter for b in branches) or (sweep is not None and sweep.parameter != parameter):
        raise ValueError("branches and sweep must share one parameter")
    fig, ax = plt.subplots(2, 2, figsize=(12, 7.5), sharex=True, layout="constrained")
    if sweep is not None:
        lam, x = sweep.points()
        ax[0, 1].plot(lam, x, ".", color="0.55", ms=2, label="brute force (section)", zorder=1)
    seen = set()
    for bi, b in enumerate(branches):
        color = f"C{bi}"
        for stable, idx in _runs(b):
            kw = dict(color=color, ls="-" if stable else "--", lw=1.5 if stable else 1.0)
            lam = b.lam[idx]
            label = f"m={b.m}" if idx[0] == 0 else None
            ax[0, 0].plot(lam, [b.points[i].amplitude for i in idx], label=label, **kw)
            ax[0, 1].plot(lam, [b.points[i].state[0] for i in idx], **kw)
            ax[1, 1].plot(lam, [b.points[i].TR_B for i in idx], **kw)
        for key, style in (("P_ex", "-"), ("P_dv", ":"), ("P_fin", "-."), ("P_df", "--")):
            ax[1, 0].plot(b.lam, [p.averages[key] for p in b.points], color=color, ls=style, lw=1.0,
                          label=f"${key[0]}_{{{key[2:]}}}$" if bi == 0 else None)
        for e in b.events:
            marker = MARKERS.get(e.type, "x")
            label = e.type.replace("_", " ") if e.type not in seen else None
            seen.add(e.type)
            ax[0, 0].plot([e.lam], [_event_value(b, e.lam, "amplitude")], marker, color="k", mfc="none", ms=7,
                          label=label, zorder=3)
            ax[0, 1].plot([e.lam], [e.state[0]], marker, color="k", mfc="none", ms=7, zorder=3)
    xl = LABELS.get(parameter, parameter)
    ax[0, 0].set(ylabel="amplitude $(X_{max}-X_{min})/2$", title="branches (solid stable, dashed unstable)")
    legend_outside(ax[0, 0], fontsize=7)
    ax[0, 1].set(ylabel=r"$X(\tau_k)$", title="stroboscopic X" + (" with brute force" if sweep is not None else ""))
    if sweep is not None:
        legend_outside(ax[0, 1], fontsize=7)
    ax[1, 0].set(xlabel=xl, ylabel="average power", title="power along the branches")
    legend_outside(ax[1, 0], fontsize=7)
    ax[1, 1].set(xlabel=xl, ylabel=r"$TR_B$", title=r"max$|X+2\zeta X'|/F_{ex}$")
    m = branches[0].model
    fixed = {"zeta": m.zeta, "vb": m.vb} | ({"omega": m.omega} if parameter == "fex" else {"fex": m.fex})
    fig.suptitle(math_values(fixed) + f"; {branches[0].friction!r}", fontsize=9)
    if path is not None:
        write_figure(fig, path, name, dpi=dpi)
    return fig


def plot_forced_orbit(orbit: ForcedOrbit, path: str | Path | None = None, *, name: str = "path", dpi: float = DEFAULT_DPI):
    """Phase portrait (equal aspect) and X(tau) over one period of a forced orbit, by runs of the flow map from tau = 0.

    Saved to ``path`` (PNG, PDF, SVG or EPS by the suffix, ``dpi`` dots per inch) when given.
    """
    plt = pyplot(path)

    n = 200 * orbit.m
    ts = np.linspace(0.0, orbit.period, n + 1)[1:]
    steps = int(orbit.settings.get("steps_per_period", DEFAULT_STEPS))  # the grid the orbit was found on
    pts = np.array([orbit.state, *(_state_at(orbit, t, steps) for t in ts)])
    tt = np.concatenate([[0.0], ts])
    fig, ax = plt.subplots(1, 2, figsize=(11, 4.2), layout="constrained")
    ax[0].plot(pts[:, 0], pts[:, 1], lw=1.2)
    ax[0].plot([orbit.state[0]], [orbit.state[1]], "ko", mfc="none", label=r"$\tau = 0$")
    ax[0].axhline(orbit.model.vb, color="0.6", lw=0.8, ls=":", label=r"$X'=V_b$")
    ax[0].set(xlabel="$X$", ylabel="$X'$", title=f"orbit, $m={orbit.m}$ ({orbit.stability})")
    equal_aspect(ax[0])
    legend_outside(ax[0])
    ax[1].plot(tt, pts[:, 0], label="$X$")
    ax[1].plot(tt, pts[:, 1], label="$X'$")
    ax[1].set(xlabel=r"$\tau$", title="one period")
    legend_outside(ax[1])
    m = orbit.model
    fig.suptitle(math_values({"zeta": m.zeta, "vb": m.vb, "fex": m.fex, "omega": m.omega}) + f"; {orbit.friction!r}",
                 fontsize=9)
    if path is not None:
        write_figure(fig, path, name, dpi=dpi)
    return fig


def _state_at(orbit: ForcedOrbit, t: float, steps: int) -> np.ndarray:
    """The orbit's state at time t (< its period), by the flow map over [0, t] (t need not be whole periods)."""
    model = orbit.model
    p = kernel_params(model, orbit.friction)
    out = fm.map_out()
    n = max(4, int(np.ceil(steps * t / model.forcing_period)))
    fm.flow_map(float(orbit.state[0]), float(orbit.state[1]), model.zeta, model.vb, p, float(t), n, out)
    return out.end.copy()
