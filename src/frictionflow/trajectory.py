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
#: the per-sample friction mode codes of :attr:`Trajectory.mode`
MODE_NAMES = {-1: "slip-", 0: "stick", 1: "slip+"}

#: (units, long name) of each variable of :meth:`Trajectory.to_xarray`
DATASET_VARIABLES = {
    "X": ("1", "displacement X = x / l_0"),
    "V": ("1", "velocity X' = dX/dtau"),
    "F_c": ("1", "friction force on the mass F_c = f_c / (k l_0)"),
    "mode": ("1", "friction mode: 1 slip+ (V_r > 0), 0 stick, -1 slip-"),
    "W_dv": ("1", "cumulative damper work int 2 zeta X'^2 dtau"),
    "W_fin": ("1", "cumulative friction input int max(X' F_c, 0) dtau"),
    "W_fout": ("1", "cumulative friction output int max(-X' F_c, 0) dtau"),
    "W_heat": ("1", "cumulative interface heat int F_c V_r dtau over slip"),
}


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
        Switches, for solvers that locate them (else ``None``): ``"t"`` the
        switch times and ``"mode"`` the mode entered at each, an ``int8``
        array of :class:`~frictionflow.modes.SwitchMode` values (never a
        kernel's own codes; ``SwitchMode(m)`` gives an element's member).
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
        """The samples as an :class:`xarray.Dataset` over ``tau`` with units and long names.

        The work columns are running totals (:attr:`work`); the model, law
        and solver settings become attributes.
        """
        import xarray as xr  # imported here: it is slow to import and only exports need it

        data = {"X": self.x, "V": self.v, "F_c": self.fc, "mode": self.mode}
        data.update({name: self.work[:, j] for j, name in enumerate(WORK_NAMES)})
        ds = xr.Dataset(
            {k: ("tau", np.asarray(v)) for k, v in data.items()},
            coords={"tau": ("tau", self.t, {"units": "1", "long_name": "non-dimensional time tau = omega0 t"})},
        )
        for k, (units, long_name) in DATASET_VARIABLES.items():
            ds[k].attrs.update(units=units, long_name=long_name)
        ds["mode"].attrs.update(_mode_flags())
        ds.attrs.update({"zeta": self.model.zeta, "vb": self.model.vb})
        ds.attrs.update({f"friction_{k}": v for k, v in self.friction.as_dict().items()})
        ds.attrs.update({f"solver_{k}": v for k, v in self.solver.items() if v is not None})
        return ds


def _mode_flags() -> dict[str, Any]:
    """CF ``flag_values`` / ``flag_meanings`` of the sample mode codes."""
    codes = sorted(MODE_NAMES)
    meanings = (MODE_NAMES[k].replace("+", "_pos").replace("-", "_neg") for k in codes)
    return {"flag_values": np.array(codes, dtype=np.int8), "flag_meanings": " ".join(meanings)}
