"""Everything ``simulate --json`` reports about one run, in one call."""

from __future__ import annotations

import math
from dataclasses import dataclass, fields
from typing import Any

import numpy as np

from .. import quantities as Q
from .._display import Row, Summarized, num, pairs, system_row
from .._figures import draw
from ..trajectory import Trajectory
from .between_samples import refines
from .equilibrium import equilibrium_values
from .power_flow import PowerFlow, power_flow
from .steady_state import DEFAULT_RTOL, SteadyState, classified_steady_state, default_rtol
from .transmissibility import amplitude, amplitude_of, transmissibility


@dataclass(frozen=True, repr=False)
class Analysis(Summarized):
    """Steady state, power flow, TR_B and amplitudes over the steady-state window.

    Shows itself as a short summary (``repr``, and a table in notebooks);
    :meth:`plot` draws the run.

    Attributes
    ----------
    trajectory:
        The run analysed.
    steady_state:
        What it settled on, and the window (:class:`SteadyState`).
    power:
        The averages over that window (:class:`PowerFlow`).
    TR_B:
        The force transmissibility over that window.
    amplitude:
        ``X_min``, ``X_max``, ``V_min``, ``V_max`` over that window.
    """

    trajectory: Trajectory
    steady_state: SteadyState
    power: PowerFlow
    TR_B: float
    amplitude: dict[str, float]

    @property
    def energy_residual(self) -> float:
        return self.power.energy_residual

    def _summary(self) -> tuple[str, list[Row]]:
        traj, ss = self.trajectory, self.steady_state
        av = self.power.averages(forced=True)
        kind = ", ".join(x for x in (ss.kind, ss.stability) if x)
        if ss.period:
            kind += f", period {num(ss.period, 8)}"
        if ss.forcing_multiple:
            kind += f" ({ss.forcing_multiple} forcing period{'s' if ss.forcing_multiple > 1 else ''})"
        if ss.lyapunov is not None:
            kind += f", Lyapunov exponent {num(ss.lyapunov, 3)}"
        if ss.decay_rate is not None:
            kind += f", decay rate {num(ss.decay_rate, 4)}" + (f", heading {ss.heading}" if ss.heading else "")
        rows = [
            system_row(traj.model, traj.friction),
            ("solver", str(traj.solver.get("name", "?"))),
            ("steady state", kind),
            ("window", f"tau {num(ss.window[0])} .. {num(ss.window[1])}"
             + (f", stick fraction {num(ss.stick_fraction, 4)}" if ss.stick_fraction is not None else "")),
            ("power", pairs({k: av[k] for k in ("P_fin", "P_df", "P_dv")})),
            ("ratios", pairs({k: av[k] for k in ("R_c", "R_f")})),
            ("belt, heat", pairs({k: av[k] for k in ("P_belt", "P_heat")})),
            *([("external force", pairs({"P_ex": av["P_ex"]}))] if traj.model.forced else []),
            ("TR_B", num(self.TR_B)),
            ("residual", num(self.energy_residual, 2)),
        ]
        return "Analysis", rows

    def plot(self, path: Any = None, **options: Any):
        """Time history, phase portrait, power and averages (:func:`frictionflow.plotting.plot_run`); returns the figure.

        ``options``: the figure function's keywords (``dpi``: dots per inch, ``name``).
        """
        return draw(self, path, **options)

    def quantities(self) -> dict[str, float]:
        """Every quantity of the table (``frictionflow.quantities``) by name, ``kind`` as its code."""
        ss = self.steady_state
        values = {"kind": Q.KINDS.index(ss.kind), "period": ss.period, "TR_B": self.TR_B,
                  "stick_fraction": ss.stick_fraction, "energy_residual": self.energy_residual,
                  **self.power.averages(forced=True), **self.amplitude}
        return {n: float("nan") if values[n] is None else values[n] for n in Q.NAMES}

    def to_dict(self) -> dict[str, Any]:
        """A JSON-ready dict (NaN becomes None); the reports in the order of the quantities table."""
        traj = self.trajectory
        report = {
            "steady_state": self.steady_state.to_dict(),
            "averages": self.power.averages(forced=traj.model.forced),
            "TR_B": self.TR_B,
            "amplitude": self.amplitude,
            "energy_residual": self.power.energy_residual,
        }
        d = {
            "params": {**traj.model.report(), **traj.friction.as_dict()},
            "solver": traj.solver,
            **{key: report[key] for key in Q.REPORTS},
        }
        if traj.events is not None:
            d["events"] = int(len(traj.events["t"]))
        return _clean(d)


def _clean(obj: Any) -> Any:
    if isinstance(obj, dict):
        return {k: _clean(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [_clean(v) for v in obj]
    if hasattr(obj, "item"):  # numpy scalar
        obj = obj.item()
    if isinstance(obj, float) and not math.isfinite(obj):
        return None
    return obj


DEFAULT_RTOL = DEFAULT_RTOL  # re-exported: the sweeps read it from here


def analyze(
    traj: Trajectory,
    *,
    window: tuple[float, float] | None = None,
    rtol: float | None = None,
    min_periods: int = 3,
) -> Analysis:
    """Find the steady state of ``traj`` and evaluate power flow, TR_B and amplitudes over it.

    For an equilibrium the averages, TR_B and amplitudes are those of the
    equilibrium itself (the motion left over the tail is below the
    convergence tolerance) and the energy residual is that of the whole run.

    Parameters
    ----------
    traj:
        A run, from :func:`~frictionflow.simulate`.
    window:
        (t0, t1) to average over instead of the detected window; the kind
        is still the detected one.
    rtol:
        The steady-state tolerance, relative to the motion's scale
        (default: the solver's: RK4 1e-6, adaptive 1e-8, exact 1e-10).
    min_periods:
        Number of consecutive repeated periods a periodic orbit needs.
    """

    if not isinstance(traj, Trajectory):  # a model or law passed by mistake would fail deep inside
        raise TypeError(f"analyze: traj must be a Trajectory (from simulate(model, friction, ...)), "
                        f"got {type(traj).__name__}")
    if rtol is None:
        rtol = default_rtol(traj.solver)
    ss, summary = classified_steady_state(traj, rtol=rtol, min_periods=min_periods, window=window)
    if ss.kind == "equilibrium" and not ss.manual_window:
        return _at_equilibrium(traj, ss)
    if ss.kind == "diverged":  # nothing about the motion is meaningful: every number is NaN
        nan = float("nan")
        power = PowerFlow(**{f.name: nan for f in fields(PowerFlow)} | {"window": ss.window})
        return Analysis(trajectory=traj, steady_state=ss, power=power, TR_B=nan,
                        amplitude={k: nan for k in Q.AMPLITUDE})
    return Analysis(
        trajectory=traj,
        steady_state=ss,
        power=power_flow(traj, ss.window),
        TR_B=transmissibility(traj, ss.window),
        amplitude=_amplitude(traj, ss.window, summary),
    )


def _amplitude(traj: Trajectory, window: tuple[float, float], summary: np.ndarray | None) -> dict[str, float]:
    """The records' extremes where they decided the window (between samples at the turns of X, as a sweep has
    them), X''s located between samples where the solver leaves them there; else the samples'."""
    if summary is None:
        return amplitude(traj, window)
    found = amplitude_of(summary)
    if refines(traj):
        sampled = amplitude(traj, window)
        found.update(V_min=sampled["V_min"], V_max=sampled["V_max"])
    return found


def _at_equilibrium(traj: Trajectory, ss: SteadyState) -> Analysis:
    """The equilibrium's own values: at rest, X = F_c; sliding, the belt's power is all heat."""
    x = ss.limit["x"] if ss.limit else float(traj.x[-1])
    whole = power_flow(traj)  # at rest nothing is left to balance: check the whole run
    power, trb, amp = equilibrium_values(
        x, traj.vb, traj.friction.fd, window=ss.window, stick=ss.stick_fraction, residual=whole.energy_residual
    )
    return Analysis(trajectory=traj, steady_state=ss, power=power, TR_B=trb, amplitude=amp)
