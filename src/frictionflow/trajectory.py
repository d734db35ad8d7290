"""The result of a simulation: samples of the motion and running work integrals.

Every solver returns a :class:`Trajectory`.  Besides t, X, X', F_c and the
friction mode it carries the work integrals (damper, friction in, friction
out, interface heat) between consecutive samples, integrated by the solver
itself, so an average over any window is a sum of the solver's own integrals
rather than a re-quadrature of a discontinuous signal.  They are kept as
increments, not running totals: every integrand is >= 0, so a window's sum is
accurate to rounding of *its own* size even deep in a decay, where a
difference of two large running totals would keep nothing.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from .friction.base import FrictionLaw
from .params import BeltOscillator

#: column order of :attr:`Trajectory.dwork` and :attr:`Trajectory.work`
WORK_NAMES = ("W_dv", "W_fin", "W_fout", "W_heat")
MODE_NAMES = {-1: "slip-", 0: "stick", 1: "slip+"}


@dataclass
class Trajectory:
    """Samples of one run.

    Attributes
    ----------
    t, x, v, fc:
        Time tau, displacement X, velocity X', friction force F_c.
    mode:
        Friction mode at each sample: +1 slip+ (V_r > 0), 0 stick, -1 slip-.
    dwork:
        (n, 4) integrals over (t[i-1], t[i]] (row 0 is zero): ``W_dv`` =
        int 2 zeta X'^2, ``W_fin`` = int max(P_f, 0), ``W_fout`` =
        int max(-P_f, 0), ``W_heat`` = int F_c V_r over slip (P_f = X' F_c).
    model, friction:
        What was simulated.
    solver:
        Description of the solver and its settings.
    events:
        Switch times and the modes entered (solvers that locate switches).
    """

    t: np.ndarray
    x: np.ndarray
    v: np.ndarray
    fc: np.ndarray
    mode: np.ndarray
    dwork: np.ndarray
    model: BeltOscillator
    friction: FrictionLaw
    solver: dict[str, Any]
    events: dict[str, np.ndarray] | None = None
    extra: dict[str, Any] = field(default_factory=dict)

    def __len__(self) -> int:
        return len(self.t)

    # -- derived quantities --------------------------------------------------
    @property
    def zeta(self) -> float:
        return self.model.zeta

    @property
    def vb(self) -> float:
        return self.model.vb

    @property
    def work(self) -> np.ndarray:
        """Running totals of the work integrals from t[0] (for plots and files; windows use :attr:`dwork`)."""
        return np.cumsum(self.dwork, axis=0)

    def window_work(self, i0: int, i1: int) -> np.ndarray:
        """The four work integrals over samples (i0, i1]."""
        return self.dwork[i0 + 1 : i1 + 1].sum(axis=0)

    @property
    def acceleration(self) -> np.ndarray:
        """X'' = F_c - X - 2 zeta X' (Eq. 4)."""
        return self.fc - self.x - 2.0 * self.zeta * self.v

    @property
    def energy(self) -> np.ndarray:
        """Mechanical energy K + U = X'^2/2 + X^2/2."""
        return 0.5 * self.v**2 + 0.5 * self.x**2

    @property
    def transmitted_force(self) -> np.ndarray:
        """Force on the wall F_tB = X + 2 zeta X' (Eq. 6)."""
        return self.x + 2.0 * self.zeta * self.v

    def index(self, t: float) -> int:
        """Index of the sample nearest to time ``t``."""
        i = int(np.searchsorted(self.t, t))
        if i <= 0:
            return 0
        if i >= len(self.t):
            return len(self.t) - 1
        return i if self.t[i] - t < t - self.t[i - 1] else i - 1

    def to_xarray(self):
        """The samples as an :class:`xarray.Dataset` with units and long names."""
        from .io import trajectory_to_dataset

        return trajectory_to_dataset(self)
