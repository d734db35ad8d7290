"""Force transmissibility TR_B (paper Eq. 6)."""

from __future__ import annotations

import numpy as np

from .. import _validate as check
from .. import quantities as Q
from ..trajectory import Trajectory
from .between_samples import force_peak, refines, velocity_extremes


def _slice(traj: Trajectory, window: tuple[float, float] | None) -> slice:
    if window is None:
        return slice(0, len(traj))
    t0, t1 = traj.checked_window(window)
    return slice(traj.index(t0), traj.index(t1) + 1)


def excitation_level(traj: Trajectory) -> float:
    """The force TR_B refers to (Eq. 6): the external force's amplitude F_ex when forced, else F_d.

    The paper's Eq. 6 divides by the excitation amplitude; its system is
    unforced, and it takes the friction level F_d as the excitation.
    """
    return traj.model.fex if traj.model.forced else traj.friction.fd


def transmissibility(traj: Trajectory, window: tuple[float, float] | None = None) -> float:
    """TR_B = max |F_tB| / F_ex over the window, F_tB = X + 2 zeta X' (Eq. 6; F_ex = F_d unforced).

    NaN when the reference force is 0 (no excitation level to refer to).  The peak between samples too where
    the run's solver leaves it there (``between_samples.refines``).

    Parameters
    ----------
    traj:
        A run, from :func:`~frictionflow.simulate`.
    window:
        (t0, t1), or None for the whole run.
    """
    check.instance("traj", traj, Trajectory, "a Trajectory (from simulate)")
    ref = excitation_level(traj)
    if ref <= 0:
        return float("nan")
    s = _slice(traj, window)
    peak = force_peak(traj, s) if refines(traj) else np.max(np.abs(traj.transmitted_force[s]))
    return float(peak / ref)


def amplitude(traj: Trajectory, window: tuple[float, float] | None = None) -> dict[str, float]:
    """Extremes of X and X' over the window (the table's ``amplitude`` quantities, in its order); X''s between
    samples too where the run's solver leaves them there (``between_samples.refines``).

    Parameters
    ----------
    traj:
        A run, from :func:`~frictionflow.simulate`.
    window:
        (t0, t1), or None for the whole run.
    """

    s = _slice(traj, window)
    x, v = traj.x[s], traj.v[s]
    vmin, vmax = velocity_extremes(traj, s) if refines(traj) else (v.min(), v.max())
    found = {"X_min": x.min(), "X_max": x.max(), "V_min": vmin, "V_max": vmax}
    return {n: float(found[n]) for n in Q.AMPLITUDE}


def amplitude_of(row: np.ndarray) -> dict[str, float]:
    """The ``amplitude`` quantities held by ``row``, a row of the table's layout."""
    return {n: float(row[Q.INDEX[n]]) for n in Q.AMPLITUDE}
