"""Figures of one run: time history, phase portrait and power flow.

Every figure draws the true curve between the solver's samples
(:meth:`~frictionflow.trajectory.Trajectory.dense`: closed form or the
solver's interpolant at >= 64 points per natural period), never straight
lines between switches.
"""

from __future__ import annotations

from pathlib import Path



from ._figures import draws
from .analysis.power_flow import instantaneous_power
from .analysis.summary import Analysis
from .io import FIGURE_FORMATS, write_figure  # noqa: F401  (FIGURE_FORMATS: re-exported)
from .trajectory import Trajectory

MAX_POINTS = 20_000


def _thin(n: int, max_points: int = MAX_POINTS) -> slice:
    return slice(None, None, max(1, n // max_points))


@draws(Analysis)
def plot_run(result: Analysis, path: str | Path | None = None, *, name: str = "path"):
    """Draw X(tau), X'(tau), the phase portrait and the power flow of the steady window.

    Returns the matplotlib figure; saves it to ``path`` (PNG, PDF or SVG by
    extension) when given.

    Parameters
    ----------
    result:
        What :func:`~frictionflow.analyze` returned.
    path:
        A file to save the figure to, or None.
    name:
        How error messages name ``path`` (the command line passes its option, such as ``--plot``).
    """
    import matplotlib

    if path is not None:
        matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt

    traj = result.trajectory.dense()  # the true curve between samples, not straight lines between switches
    ss = result.steady_state
    i0, i1 = traj.index(ss.window[0]), traj.index(ss.window[1])
    whole = _thin(len(traj))
    win = slice(i0, i1 + 1)
    wthin = _thin(i1 + 1 - i0)

    fig, ax = plt.subplots(2, 2, figsize=(10, 7), constrained_layout=True)
    ax[0, 0].plot(traj.t[whole], traj.x[whole], lw=0.7, label="X")
    ax[0, 0].plot(traj.t[whole], traj.v[whole], lw=0.7, label="X'")
    ax[0, 0].axvspan(*ss.window, color="0.9", zorder=0, label=f"window ({ss.kind})")
    ax[0, 0].set(xlabel=r"$\tau$", title="time history")
    ax[0, 0].legend(loc="upper right", fontsize=8)

    ax[0, 1].plot(traj.x[whole], traj.v[whole], lw=0.5, color="0.7", label="whole run")
    ax[0, 1].plot(traj.x[win][wthin], traj.v[win][wthin], lw=1.0, color="C3", label="steady-state window")
    ax[0, 1].axhline(traj.vb, color="k", ls=":", lw=0.8, label=r"$X'=V_b$")
    ax[0, 1].set(xlabel="X", ylabel="X'", title="phase portrait")
    ax[0, 1].legend(loc="lower left", fontsize=8)

    # The last three periods of the window (or the last 20 time units) keep the waveform legible.
    span = 3 * ss.period if ss.period else 20.0
    j0 = max(i0, traj.index(ss.window[1] - span))
    last = slice(j0, i1 + 1)
    p = instantaneous_power(traj)
    lthin = _thin(i1 + 1 - j0)
    tw = traj.t[last][lthin]
    forced = traj.model.forced
    lines = [("P_f", r"$P_f$"), ("P_dv", r"$P_{dv}$"), ("P_heat", r"$P_{heat}$")] + ([("P_ex", r"$P_{ex}$")] if forced else [])
    for key, label in lines:
        ax[1, 0].plot(tw, p[key][last][lthin], lw=0.8, label=label)
    ax[1, 0].set(xlabel=r"$\tau$", title="instantaneous power (end of window)")
    ax[1, 0].legend(loc="upper right", fontsize=8)

    av = result.power.averages(forced=True)
    names = ["P_fin", "P_df", "P_dv", "P_belt", "P_heat"] + (["P_ex"] if forced else [])
    vals = [av[k] for k in names]
    ax[1, 1].bar(names, vals, color=["C2", "C1", "C0", "C4", "C3", "C5"][: len(names)])
    ax[1, 1].set(title=f"averages (residual {result.energy_residual:.1e})")
    ax[1, 1].ticklabel_format(axis="y", style="sci", scilimits=(-3, 3))

    params = f"ζ={traj.zeta:g}, V_b={traj.vb:g}, F_d={traj.friction.fd:g}, F_s={traj.friction.fs:g}"
    if forced:
        params += f", F_ex={traj.model.fex:g}, Ω={traj.model.omega:g}"
    fig.suptitle(f"{params}   TR_B={result.TR_B:.4g}")
    if path is not None:
        write_figure(fig, path, name)  # atomic: no partial figure on failure
    return fig


@draws(Trajectory)
def plot_trajectory(traj, path: str | Path | None = None, *, name: str = "path"):
    """X and X' against tau, and the phase portrait, on the true curve; the switches marked.

    Returns the matplotlib figure; saves it to ``path`` (PNG, PDF or SVG by
    extension) when given.

    Parameters
    ----------
    traj:
        A run, from :func:`~frictionflow.simulate`.
    path:
        A file to save the figure to, or None.
    name:
        How error messages name ``path`` (the command line passes its option, such as ``--plot``).
    """

    import matplotlib

    if path is not None:
        matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt

    curve = traj.dense()
    whole = _thin(len(curve))
    sw = traj.switches()
    fig, ax = plt.subplots(1, 2, figsize=(10, 3.6), constrained_layout=True)
    ax[0].plot(curve.t[whole], curve.x[whole], lw=0.8, label="X")
    ax[0].plot(curve.t[whole], curve.v[whole], lw=0.8, label="X'")
    ax[0].plot(traj.t[sw], traj.x[sw], "k.", ms=3, label="switches")
    ax[0].set(xlabel=r"$\tau$", title="time history")
    ax[0].legend(loc="upper right", fontsize=8)
    ax[1].plot(curve.x[whole], curve.v[whole], lw=0.8, color="C3")
    ax[1].plot(traj.x[sw], traj.v[sw], "k.", ms=3, label="switches")
    ax[1].axhline(traj.vb, color="k", ls=":", lw=0.8, label=r"$X'=V_b$")
    ax[1].set(xlabel="X", ylabel="X'", title="phase portrait")
    ax[1].legend(loc="lower left", fontsize=8)
    fig.suptitle(f"{traj.friction!r}, ζ={traj.zeta:g}, V_b={traj.vb:g}, solver {traj.solver.get('name', '?')}", fontsize=9)
    if path is not None:
        write_figure(fig, path, name)
    return fig


def plot_response(ds, path: str | Path | None = None, *, name: str = "path"):
    """The frequency response (:func:`frictionflow.analysis.response.frequency_response`) against Omega.

    Amplitude, TR_B, the power the external force puts in and what the damper
    and the interface take out, and the stick fraction; the up and down
    sweeps drawn apart, so that jumps and hysteresis show.  Steady states
    that are not periodic are marked (x: quasi-periodic, chaotic or not
    settled).
    """
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(2, 2, figsize=(11, 7), sharex=True)
    w = ds["omega"].values
    style = {"up": dict(color="C0", marker=">", ms=3), "down": dict(color="C3", marker="<", ms=3, ls="--")}
    for d in ds["direction"].values:
        sel = ds.sel(direction=d)
        kw = style.get(str(d), {})
        ax[0, 0].plot(w, sel["amplitude"], label=f"sweep {d}", **kw)
        ax[0, 1].plot(w, sel["TR_B"], **kw)
        ax[1, 0].plot(w, sel["P_ex"], label=f"$P_{{ex}}$ {d}", **kw)
        ax[1, 0].plot(w, sel["P_dv"], alpha=0.6, lw=0.8, color=kw.get("color"), ls=":", label=f"$P_{{dv}}$ {d}")
        ax[1, 1].plot(w, sel["stick_fraction"], **kw)
        other = sel["kind"].values != 0
        if other.any():
            ax[0, 0].plot(w[other], sel["amplitude"].values[other], "kx", ms=6)
    ax[0, 0].set(ylabel="amplitude $(X_{max}-X_{min})/2$", title="amplitude")
    ax[0, 0].legend(fontsize=8)
    ax[0, 1].set(ylabel=r"$TR_B$", title=r"transmissibility max$|X+2\zeta X'|/F_{ex}$")
    ax[1, 0].set(xlabel=r"$\Omega$", ylabel="power", title="power in (external force) and out (damper)")
    ax[1, 0].legend(fontsize=7)
    ax[1, 1].set(xlabel=r"$\Omega$", ylabel="stick fraction", title="stick fraction")
    attrs = ds.attrs
    fig.suptitle(f"ζ={attrs.get('zeta', 0):g}, V_b={attrs.get('vb', 0):g}, F_ex={attrs.get('fex', 0):g}, "
                 f"{attrs.get('friction', '')} F_d={attrs.get('fd', 0):g}, F_s={attrs.get('fs', 0):g}")
    fig.tight_layout()
    if path is not None:
        write_figure(fig, path, name)
    return fig
