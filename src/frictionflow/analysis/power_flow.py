"""Power flow (paper Eq. 7-9) and the power balance.

Instantaneous (Eq. 8): K' + P_dv + U' = P_f with K' = X'X'', U' = X'X,
P_dv = 2 zeta X'^2 and P_f = X' F_c.

Averages over a window of length tau_p (Eq. 9):

* ``P_dv``  = mean of 2 zeta X'^2, the damper's dissipation;
* ``P_fin`` = mean of max(P_f, 0), the power friction puts in (Eq. 9c);
* ``P_df``  = mean of max(-P_f, 0), the power friction takes out, reported
  as a positive number.  Eq. 9b prints H(-P_f) with H the Heaviside step,
  which would be a time fraction, not a power; the text ("the power
  dissipated by the friction") and P_dv + P_df = P_fin for periodic motion
  only hold for the magnitude of the negative part;
* ``R_c`` = P_dv / P_fin and ``R_f`` = P_df / P_fin (NaN when friction puts
  in nothing above rounding, as at an equilibrium).

With an external force f(tau) (paper Eq. 1's f_ex), ``P_ex`` = mean of
X' f(tau) enters the balance: K' + P_dv + U' = P_f + X' f.

Beyond the paper, P_f = P_belt - P_heat with P_belt = F_c V_b the power the
belt delivers and P_heat = F_c V_r >= 0 the heat generated at the interface
while slipping (0 while sticking, where V_r is taken as 0 -- inside
Karnopp's band this makes P_belt = F_c X' there).  A law with internal
state stores energy E_s in the contact (its bristles): its heat is F_c V_r
less E_s', so P_belt = P_f + P_heat + Delta E_s / span (the last term 0
over whole periods).

The averages are sums of the work integrals the solver integrated between
samples (all >= 0, so accurate to rounding of the window's own size, even
deep in a decaying transient); the energy residual checks them against the
change of K + U.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from .. import _validate as check
from .. import quantities as Q
from .._display import Row, Summarized, num, pairs
from .. import _continuous as cont
from ..core import sections as sec
from ..trajectory import Trajectory


@dataclass(frozen=True, repr=False)
@Q.table_fields(Q.FORCED_AVERAGES, after="window")
class PowerFlow(Summarized):
    """Average power flow over a window, and the residual of the power balance.

    Its fields after ``window`` are the quantities ``simulate --json`` reports
    in ``averages`` (``frictionflow.quantities.AVERAGES``: P_dv, P_df,
    P_fin, R_c, R_f, P_belt, P_heat, P_f), in the table's order.
    ``energy_residual`` is |Delta(K+U) + W_dv - W_f| over the window relative
    to the friction input W_fin; when W_fin is below 1e-12 of the stored
    energy times the window length (an equilibrium), relative to the latter
    (see ``frictionflow.core.sections.averages``).

    Its ``repr`` (and ``_repr_html_`` in a notebook) shows the averages in
    significant digits; ``to_dict()`` has them exactly.

    Attributes
    ----------
    window:
        (t0, t1), the times averaged over.
    energy_residual:
        The power balance's relative residual over the window (above).
    P_dv:
        Mean power the damper dissipates, 2 zeta X'^2.
    P_fin, P_df:
        Mean power friction puts in, max(P_f, 0), and takes out,
        max(-P_f, 0).
    R_c, R_f:
        P_dv / P_fin and P_df / P_fin (NaN when P_fin is rounding).
    P_belt, P_heat:
        Mean power the belt delivers, F_c V_b, and the heat made at the
        interface, F_c V_r (P_f = P_belt - P_heat).
    P_f:
        Mean friction power X' F_c.
    P_ex:
        Mean power of the external force (0 unforced).
    """

    window: tuple[float, float]
    energy_residual: float

    @classmethod
    def from_row(cls, window: tuple[float, float], row: np.ndarray) -> PowerFlow:
        """The power flow held by ``row``, a row of the table's layout (``frictionflow.quantities``)."""
        values = {n: float(row[Q.INDEX[n]]) for n in (*Q.FORCED_AVERAGES, "energy_residual")}
        return cls(window=window, **values)

    def averages(self, forced: bool = False) -> dict[str, float]:
        """The averages by name (``forced=False``: without those only forced runs report)."""
        return {k: getattr(self, k) for k in (Q.FORCED_AVERAGES if forced else Q.AVERAGES)}

    def _summary(self) -> tuple[str, list[Row]]:
        av = self.averages(forced=True)
        rows = [("window", f"tau {num(self.window[0])} .. {num(self.window[1])}"),
                ("power", pairs({k: av[k] for k in ("P_fin", "P_df", "P_dv")})),
                ("ratios", pairs({k: av[k] for k in ("R_c", "R_f")})),
                ("belt, heat", pairs({k: av[k] for k in ("P_belt", "P_heat")})),
                ("net friction", pairs({"P_f": av["P_f"]}))]
        if av["P_ex"] != 0.0:
            rows.append(("external force", pairs({"P_ex": av["P_ex"]})))
        rows.append(("residual", num(self.energy_residual, 2)))
        return "PowerFlow", rows

    def to_dict(self) -> dict[str, Any]:
        return {"window": list(self.window), **self.averages(forced=True), "energy_residual": self.energy_residual}


def power_flow(traj: Trajectory, window: tuple[float, float] | None = None) -> PowerFlow:
    """Time-averaged power flow of ``traj`` over ``window`` (whole run if None).

    ``window`` = (t0, t1), any times of the run's span with t0 < t1: the

    averages are over exactly that window.  Where an end falls between
    samples, the motion is evaluated there (:meth:`frictionflow.Trajectory.at`) and the
    work of the partial sample interval integrated on the interpolant
    (``frictionflow._continuous.dwork_at``); windows that start and end
    on samples sum the solver's own work integrals.

    Parameters
    ----------
    traj:
        A run, from :func:`~frictionflow.simulate`.
    window:
        (t0, t1), or None for the whole run.
    """
    check.instance("traj", traj, Trajectory, "a Trajectory (from simulate)")

    t0, t1 = (float(traj.t[0]), float(traj.t[-1])) if window is None else traj.checked_window(window)
    # the first sample at t0 and the last at t1 (a switch can leave two samples at one time)
    i0, i1 = int(np.searchsorted(traj.t, t0)), int(np.searchsorted(traj.t, t1, side="right")) - 1
    if traj.t[i0] == t0 and traj.t[i1] == t1:  # on samples: the solver's own integrals
        row = sec.averages(*traj.window_work(i0, i1), *traj.energy[[i0, i1]], t1 - t0)
        stored = traj.friction.stored_energy(traj.internal[:, [i0, i1]]) if traj.internal is not None else None
        return PowerFlow.from_row((t0, t1), _with_stored(row, stored, t1 - t0))
    ends = np.array([t0, t1])
    interp = cont.interpolant(traj)
    x, v = interp.state(ends)
    dw = cont.dwork_at(traj, interp, ends)[1]
    e = 0.5 * (x * x + v * v)
    stored = traj.friction.stored_energy(interp.internal(ends)) if traj.internal is not None else None
    return PowerFlow.from_row((t0, t1), _with_stored(sec.averages(*dw, e[0], e[1], t1 - t0), stored, t1 - t0))


def _with_stored(row: np.ndarray, stored: np.ndarray | None, span: float) -> np.ndarray:
    """``row`` with P_belt the belt's whole input F_c V_b for a law with internal state: its heat is F_c V_r
    less what the contact stores, so the belt also pays the change of the stored energy (``stored``: at
    the window's ends; None for a static law, whose row is left as it is)."""
    if stored is not None:
        row[sec.P_BELT] += (float(stored[1]) - float(stored[0])) / span
    return row


def instantaneous_power(traj: Trajectory) -> dict[str, np.ndarray]:
    """Eq. 8 term by term at every sample: K', U', P_dv, P_f, P_belt, P_heat, P_ex.

    Parameters
    ----------
    traj:
        A run, from :func:`~frictionflow.simulate`.

    Returns
    -------
    dict
        ``K_dot``, ``U_dot``, ``P_dv``, ``P_f``, ``P_belt``, ``P_heat``,
        ``P_ex``: arrays over the samples ``traj.t``.
    """
    check.instance("traj", traj, Trajectory, "a Trajectory (from simulate)")

    v, fc = traj.v, traj.fc
    p_f = v * fc
    slipping = traj.mode != 0
    vb = traj.model.belt_speed(traj.t) if traj.model.belt_varies else traj.vb
    p_heat = np.where(slipping, fc * (vb - v), 0.0)
    return {
        "K_dot": v * traj.acceleration,
        "U_dot": v * traj.x,
        "P_dv": 2.0 * traj.zeta * v * v,
        "P_f": p_f,
        "P_belt": p_f + p_heat,
        "P_heat": p_heat,
        "P_ex": v * traj.model.external_force(traj.t),
    }
