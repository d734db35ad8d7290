"""Bifurcation diagrams of forced periodic orbits, with the stroboscopic brute-force overlay.

:func:`plot_forced_branches` draws branches of :func:`~.forced.continue_forced`
against lambda (Omega or F_ex): the amplitude (or the stroboscopic X at
tau = 0), stable pieces solid and unstable ones dashed, bifurcation points
marked, and beside it the power along the branch (P_ex, P_dv, P_fin, P_df)
and TR_B.  With a :class:`~.forced.StroboscopicSweep` the brute-force
section points (X at tau_k of the last forcing periods, swept with state
continuation) are overlaid as dots on the X panel: where the branch is
stable they lie on it, and past a bifurcation they show what the motion
does instead.  Saved as PNG, PDF or SVG by the file's extension.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from pathlib import Path

import numpy as np

from ..io import write_figure
from .forced import ForcedBranch, StroboscopicSweep

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
                         sweep: StroboscopicSweep | None = None, name: str = "path"):
    """The bifurcation diagram of ``branches`` (one parameter), with ``sweep``'s brute-force dots on the X panel.

    Parameters
    ----------
    branches:
        One or more branches from :func:`~frictionflow.orbits.continue_forced`, in the same parameter.
    path:
        A file to save the figure to (PNG, PDF or SVG by its extension), or None.
    sweep:
        A :func:`~frictionflow.orbits.stroboscopic_sweep` to draw as dots, or None.
    name:
        How error messages name ``path`` (the command line passes its option, such as ``--plot``).

    Returns
    -------
    matplotlib.figure.Figure
    """

    import matplotlib

    if path is not None:
        matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt

    if isinstance(branches, ForcedBranch):
        branches = [branches]
    if not branches:
        raise ValueError("branches: nothing to plot")
    parameter = branches[0].parameter
    if any(b.parameter != parameter for b in branches) or (sweep is not None and sweep.parameter != parameter):
        raise ValueError("branches and sweep must share one parameter")
    fig, ax = plt.subplots(2, 2, figsize=(11, 7.5), sharex=True)
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
    ax[0, 0].legend(fontsize=7)
    ax[0, 1].set(ylabel=r"$X(\tau_k)$", title="stroboscopic X" + (" with brute force" if sweep is not None else ""))
    if sweep is not None:
        ax[0, 1].legend(fontsize=7)
    ax[1, 0].set(xlabel=xl, ylabel="average power", title="power along the branches")
    ax[1, 0].legend(fontsize=7)
    ax[1, 1].set(xlabel=xl, ylabel=r"$TR_B$", title=r"max$|X+2\zeta X'|/F_{ex}$")
    m = branches[0].model
    fig.suptitle(f"ζ={m.zeta:g}, V_b={m.vb:g}, " + (f"Ω={m.omega:g}" if parameter == "fex" else f"F_ex={m.fex:g}")
                 + f"; {branches[0].friction!r}", fontsize=9)
    fig.tight_layout()
    if path is not None:
        write_figure(fig, path, name)
    return fig
