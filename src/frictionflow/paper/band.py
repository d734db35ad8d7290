"""Artefacts of Karnopp's band at belt speeds V_b <= V_d (the paper's V_b = 0.001 = V_d).

Karnopp's law treats every |V_r| <= V_d as "stick" and there, with the
paper's F_e = X, sets F_c = X: X'' = 0, the velocity is *frozen* wherever it
entered the band -- not set to the belt's.  Consequences, for zeta = 0:

* V_b = V_d: after one slip arc the mass enters the band at X' = 0 and stays
  there, at rest at X = F_d - V_b, while the belt moves at V_b (V_r = V_b,
  not 0: this is not stick).  Fixed-step RK4 enters the band a fraction of a
  step late and keeps that residual velocity (1e-7 at dt = 1e-3, varying with
  dt): it creeps until X = F_d, thousands of time units later.
* V_b < V_d: the band contains X' = 0 and negative velocities; the mass
  shuttles between X = +-F_d at constant speed, against the belt half the
  time, all inside "stick".
* V_b > V_d: the cycle is the slip circle of radius V_b - V_d, where ideal
  Coulomb friction gives radius V_b -- 10 % smaller at the paper's V_b = 0.01.
"""

from __future__ import annotations

import math

import numpy as np

from .._lazy import lazy_module
from ..analysis import analyze
from ..friction import Coulomb
from ..params import BeltOscillator
from ..simulate import simulate
from ..solvers import RK4, Exact
from .runs import Point, paper_law
from .settings import Settings
from .style import LABELS, figure, legend, panel_title

xr = lazy_module("xarray")  # loaded on first use: importing the CLI stays quick

#: the three models compared: (name, description)
MODELS = (
    ("karnopp_rk4", "Karnopp, paper's method (RK4)"),
    ("karnopp_exact", "Karnopp, exact solver"),
    ("coulomb_exact", "ideal Coulomb (no band), exact"),
)
FD = 0.02
#: RK4 steps at which the creep speed at V_b = V_d is measured
CREEP_DT = (2e-3, 1e-3, 5e-4)
#: the creep speed is read this long after the start
CREEP_AT = 100.0
#: length of the V_b = V_d / 2 history: one shuttle -F_d -> +F_d -> -F_d takes about 8 F_d / V_b
SHUTTLE_T_END = 400.0
#: the run whose steady state (whole shuttles: a period of 4 F_d / V_b + 2 pi, 166 at V_b = V_d / 2) gives the shares of
#: time in the band and against the belt
SHARES_T_END = 1200.0


def _trajectory(model: str, vb: float, settings: Settings, t_end: float, samples_per_unit: float):
    point = Point(0.0, vb, FD)
    osc = BeltOscillator(zeta=0.0, vb=vb)
    if model == "karnopp_rk4":
        every = max(1, round(1.0 / (samples_per_unit * settings.dt)))
        return simulate(osc, paper_law(point.fd, settings), RK4(dt=settings.dt, record_every=every), t_end=t_end)
    if model == "karnopp_exact":
        return simulate(osc, paper_law(point.fd, settings), Exact(dense_dt=1.0 / samples_per_unit), t_end=t_end)
    return simulate(osc, Coulomb(FD, stick_force="spring"), Exact(dense_dt=1.0 / samples_per_unit), t_end=t_end)


def sweep_dataset(settings: Settings, models: tuple[str, ...] | None = None) -> xr.Dataset:
    """The steady motion of Case I against V_b around V_d, for the three models (or ``models``)."""
    models = tuple(m for m, _ in MODELS) if models is None else models
    described = dict(MODELS)
    vbs = sorted(settings.band_vb)
    names = ("V_max", "V_min", "X_max", "X_min", "P_fin", "stick_fraction", "period")
    data = {k: np.full((len(models), len(vbs)), np.nan) for k in names}
    kind = np.full((len(models), len(vbs)), "", dtype=object)
    for i, model in enumerate(models):
        for j, vb in enumerate(vbs):
            traj = _trajectory(model, vb, settings, settings.band_t_end, samples_per_unit=100.0)
            res = analyze(traj)
            for k in ("V_max", "V_min", "X_max", "X_min"):
                data[k][i, j] = res.amplitude[k]
            data["P_fin"][i, j] = res.power.P_fin
            ss = res.steady_state
            data["stick_fraction"][i, j] = math.nan if ss.stick_fraction is None else ss.stick_fraction
            data["period"][i, j] = math.nan if ss.period is None else ss.period
            kind[i, j] = ss.kind
    dims = ("model", "vb")
    ds = xr.Dataset({(k if k in ("stick_fraction", "period") else f"steady_{k}"): (dims, v) for k, v in data.items()},
                    coords={"model": list(models), "vb": vbs,
                            "model_description": ("model", [described[m] for m in models])})
    ds["kind"] = (dims, kind.astype(str))
    ds.attrs.update(vd=settings.vd, fd=FD)
    return ds


def history_dataset(settings: Settings) -> xr.Dataset:
    """Time histories inside the band.

    V_b = V_d: the first turns (fine grid), the long run (coarse grid) and
    RK4's creep speed against dt.  V_b = V_d / 2: one shuttle between
    X = -F_d and +F_d, with the friction mode.
    """
    vb = settings.vd
    short = np.linspace(0.0, 30.0, 1501)
    long = np.linspace(0.0, settings.band_history_t_end, 2401)
    half = np.linspace(0.0, SHUTTLE_T_END, 2001)
    v_short = np.empty((len(MODELS), len(short)))
    x_short = np.empty_like(v_short)
    x_long = np.empty((len(MODELS), len(long)))
    v_half = np.empty((len(MODELS), len(half)))
    mode_half = np.empty((len(MODELS), len(half)), dtype=np.int8)
    shares = np.empty((len(MODELS), 2))
    for i, (model, _d) in enumerate(MODELS):
        fine = _trajectory(model, vb, settings, short[-1], samples_per_unit=100.0)
        v_short[i] = np.interp(short, fine.t, fine.v)
        x_short[i] = np.interp(short, fine.t, fine.x)
        coarse = _trajectory(model, vb, settings, settings.band_history_t_end, samples_per_unit=1.0)
        x_long[i] = np.interp(long, coarse.t, coarse.x)
        # one run: the plotted first shuttles, and the shares over the steady state's whole ones
        shuttle = _trajectory(model, 0.5 * vb, settings, SHARES_T_END, samples_per_unit=20.0)
        v_half[i] = np.interp(half, shuttle.t, shuttle.v)
        # the mode of the sample at or before each grid time
        mode_half[i] = shuttle.mode[np.clip(np.searchsorted(shuttle.t, half, side="right") - 1, 0, len(shuttle) - 1)]
        shares[i] = _shares(shuttle)
    creep = []
    for dt in CREEP_DT:
        tr = simulate(BeltOscillator(zeta=0.0, vb=vb), paper_law(FD, settings), RK4(dt=dt, record_every=1000),
                      t_end=CREEP_AT)
        creep.append(float(tr.v[-1]))
    ds = xr.Dataset(
        {
            "V": (("model", "tau_short"), v_short),
            "X": (("model", "tau_short"), x_short),
            "X_long": (("model", "tau_long"), x_long),
            "V_half": (("model", "tau_half"), v_half),
            "mode_half": (("model", "tau_half"), mode_half),
            "band_share_half": (("model",), shares[:, 0]),
            "backward_share_half": (("model",), shares[:, 1]),
            "creep_speed": (("dt",), creep),
        },
        coords={"model": [m for m, _ in MODELS], "model_description": ("model", [d for _, d in MODELS]),
                "tau_short": short, "tau_long": long, "tau_half": half, "dt": list(CREEP_DT)},
    )
    ds.attrs.update(vb=vb, vb_half=0.5 * vb, vd=settings.vd, fd=FD)
    return ds


def _shares(traj) -> tuple[float, float]:
    """(in the band, moving against the belt): shares of the time over the run's steady-state window, whole
    periods (over a window of 2.4 shuttles the mass moved against the belt 58 % of the time, over whole ones 50 %)."""
    t0, t1 = analyze(traj).steady_state.window
    grid = np.linspace(t0, t1, 40001)
    v = np.interp(grid, traj.t, traj.v)
    mode = traj.mode[np.clip(np.searchsorted(traj.t, grid, side="right") - 1, 0, len(traj) - 1)]
    return float(np.mean(mode == 0)), float(np.mean(v < 0.0))


COLORS = {"karnopp_rk4": "tab:blue", "karnopp_exact": "tab:orange", "coulomb_exact": "0.3"}
STYLES = {"karnopp_rk4": {"marker": "o", "ms": 5, "ls": "-"}, "karnopp_exact": {"marker": "x", "ms": 7, "ls": ":"},
          "coulomb_exact": {"lw": 2.5, "alpha": 0.45}}
#: time histories: the exact solver dashed over RK4, so that both show where they coincide
LINES = {"karnopp_rk4": {"lw": 1.6}, "karnopp_exact": {"lw": 1.2, "ls": "--"}, "coulomb_exact": {"lw": 1.0}}


def plot(sweep: xr.Dataset, hist: xr.Dataset):
    """(a) velocity amplitude against V_b; (b) X' at V_b = V_d / 2; (c) X' and (d) X at V_b = V_d."""
    fig, axes = figure(2, 2, (14, 7.5))
    vd = float(sweep.attrs["vd"])
    ax = axes[0, 0]
    for model, desc in MODELS:
        c = sweep.sel(model=model)
        amp = 0.5 * (c.steady_V_max - c.steady_V_min)
        ax.plot(c.vb, amp.where(amp > 1e-15), color=COLORS[model], label=desc, **STYLES[model])
    vb = np.geomspace(vd * 1.05, float(sweep.vb.max()), 50)
    ax.plot(vb, vb - vd, color="k", lw=0.7, ls="--", label=r"$V_b - V_d$")
    ax.axvline(vd, color="k", lw=0.8, ls="-.")
    ax.set(xscale="log", yscale="log", xlabel=LABELS["vb"], ylabel=r"half the range of $X'$ in the steady state")
    legend(ax, fontsize=7)
    panel_title(ax, "a", r"$\zeta=0$, $F_d=0.02$; dash-dot: $V_b=V_d$ (exact: at rest, off the axis)")

    ax = axes[0, 1]
    vh = float(hist.attrs["vb_half"])
    ax.axhspan(vh - vd, vh + vd, color="0.92", label=r"Karnopp band $|V_b - X'| \leq V_d$ ('stick')")
    for model, desc in MODELS[:2]:  # ideal Coulomb: the slip circle of radius V_b, as in (c)
        ax.plot(hist.tau_half, hist.V_half.sel(model=model), color=COLORS[model], label=desc, **LINES[model])
    ax.axhline(vh, color="k", ls="--", lw=0.8, label=r"belt $V_b$")
    exact = hist.sel(model="karnopp_exact")
    inside, backwards = float(exact.band_share_half), float(exact.backward_share_half)
    ax.set(xlabel=LABELS["tau"], ylabel=LABELS["V"], ylim=(vh - 1.6 * vd, vh + 2.2 * vd))
    ax.ticklabel_format(axis="y", style="sci", scilimits=(-3, 3))
    legend(ax, fontsize=6.5)
    panel_title(ax, "b", fr"$V_b=V_d/2$: in the band {100 * inside:.0f} % of the time, "
                         fr"moving against the belt {100 * backwards:.0f} %")

    ax = axes[1, 0]
    for model, desc in MODELS:
        ax.plot(hist.tau_short, hist.V.sel(model=model), color=COLORS[model], label=desc, **LINES[model])
    ax.axhline(float(hist.attrs["vb"]), color="k", ls="--", lw=0.8, label=r"belt $V_b$ (what stick would mean)")
    ax.set(xlabel=LABELS["tau"], ylabel=LABELS["V"])
    ax.ticklabel_format(axis="y", style="sci", scilimits=(-3, 3))
    legend(ax, fontsize=7)
    panel_title(ax, "c", r"$V_b=V_d=0.001$: the mass stops, the belt does not")

    ax = axes[1, 1]
    for model, desc in MODELS[:2]:  # ideal Coulomb circles about F_d with radius V_b: a filled band at this scale
        ax.plot(hist.tau_long, hist.X_long.sel(model=model), color=COLORS[model], label=desc, **LINES[model])
    ax.axhline(FD, color="k", lw=0.6, ls=":", label=r"$X = F_d$")
    ax.set(xlabel=LABELS["tau"], ylabel=LABELS["X"])
    legend(ax, fontsize=7)
    speeds = "\n".join(f"{v:.1e} (dt = {d:g})" for d, v in zip(hist.dt.values, hist.creep_speed.values))
    ax.text(0.03, 0.55, f"RK4 creep speed X' at τ = {CREEP_AT:g}:\n{speeds}", transform=ax.transAxes, fontsize=7)
    panel_title(ax, "d", r"$V_b=V_d$: exact rests at $F_d-V_b$; RK4 creeps on to $F_d$")
    fig.suptitle(r"Karnopp's band at $V_b \leq V_d$: rest, creep and backward 'stick' -- not stick", fontsize=10)
    return fig
