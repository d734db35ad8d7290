"""The result of a simulation: samples of the motion and running work integrals.

Every solver returns a :class:`Trajectory`.  Besides t, X, X', F_c and the
friction mode it carries the work integrals (damper, friction in, friction
out, interface heat) between consecutive samples, integrated by the solver
itself, so an average over any window is a sum of the solver's own integrals
rather than a re-quadrature of a discontinuous signal.  They are kept as
increments, not running totals: every integrand is >= 0, so a window's sum is
accurate to rounding of *its own* size even deep in a decay, where a
difference of two large running totals would keep nothing.

A trajectory is also a continuous object: ``traj(t)`` (or :meth:`Trajectory.at`)
gives (X, X') at any time of its span -- in closed form for the exact solver,
by Hermite interpolation of the steps for the others (see
``frictionflow._continuous``) -- :meth:`Trajectory.sample` resamples it,
and :meth:`Trajectory.dense`, :meth:`Trajectory.to_xarray` and the figures show
the true curve between the samples, with the samples and switches marked.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, NamedTuple

import numpy as np

from . import _continuous as cont
from ._display import Row, Summarized, num, system_row
from ._figures import draw
from .friction.base import FrictionLaw
from .params import BeltOscillator

#: column order of :attr:`Trajectory.dwork` and :attr:`Trajectory.work`
WORK_NAMES = ("W_dv", "W_fin", "W_fout", "W_heat", "W_ex")
#: the row names of the single mass's state and contact blocks
SINGLE_MASS_STATE = ("X", "V")
SINGLE_CONTACT = ("belt",)
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
    "W_ex": ("1", "cumulative work of the external force int X' F_ex cos(Omega tau + phi) dtau"),
    "E_s": ("1", "energy stored in the contact (the law's internal states; sigma0 z^2/2 for LuGre)"),
    "W_belt": ("1", "cumulative work of the belt on the contact int F_c V_b dtau"),
    "is_sample": ("1", "the solver's own sample (False: a point added on the true curve between samples)"),
    "switch": ("1", "a sample where the friction mode switches"),
}


@dataclass(repr=False)
class Trajectory(Summarized):
    """Samples of one run, and the motion between them.

    ``traj(t)`` evaluates (X, X') anywhere in the span (:meth:`at`).

    The state and the contacts are blocks, so that the record does not
    assume one mass or one contact: ``state`` has one row per state
    component (the layout of ``scipy.integrate.solve_ivp``'s ``y``),
    ``force`` and ``modes`` one row per contact.  The single mass on the belt
    has the state (X, X') and one contact; :attr:`x`, :attr:`v`, :attr:`fc`
    and :attr:`mode` are views of its rows (writing into them writes the
    blocks).

    Attributes
    ----------
    t:
        Time tau of each sample, ascending.
    state:
        (n, len(t)): the state's components, named by ``state_names``
        (the single mass: displacement X and velocity X').
    force:
        (k, len(t)): the friction force of each contact (the single mass:
        F_c on the mass).
    modes:
        (k, len(t)) int8: each contact's friction mode at each sample, +1
        slip+ (V_r > 0), 0 stick, -1 slip-.
    dwork:
        (len(t), 5) integrals over (t[i-1], t[i]] (row 0 is zero), columns
        ``WORK_NAMES``: ``W_dv`` = int 2 zeta X'^2, ``W_fin`` =
        int max(P_f, 0), ``W_fout`` = int max(-P_f, 0), ``W_heat`` =
        int F_c V_r over slip (P_f = X' F_c), ``W_ex`` = int X' f(tau).
    model, friction:
        What was simulated.
    solver:
        Description of the solver and its settings.
    events:
        Switches, for solvers that locate them (else ``None``): ``"t"`` the
        switch times and ``"mode"`` the mode entered at each, an ``int8``
        array of :class:`~frictionflow.modes.SwitchMode` values (never a
        kernel's own codes; ``SwitchMode(m)`` gives an element's member).
    extra:
        Solver-specific facts (the exact solver: when the final phase began).
    recorded:
        Which points are the solver's own samples, for trajectories made by
        :meth:`dense` or :meth:`sample` (None: every point is one).
    state_names, contact_names:
        Names of the rows of :attr:`state` and of :attr:`force` /
        :attr:`modes` (the datasets' variable names).
    internal:
        (m, len(t)): the friction law's internal states (LuGre's bristle
        deflection z), named by :attr:`internal_names`; None for a static law.
    internal_names:
        Names of the rows of :attr:`internal` (the law's ``internal_names``).
    dbelt:
        Increments of the belt's work on the contact int F_c V_b over
        (t[i-1], t[i]] (row 0 zero), where the solver integrates it (the
        stiff solver); None otherwise.  :meth:`dense` and :meth:`sample` carry
        it as the other work integrals.  See :meth:`interface_balance`.
    """

    t: np.ndarray
    state: np.ndarray
    force: np.ndarray
    modes: np.ndarray
    dwork: np.ndarray
    model: BeltOscillator
    friction: FrictionLaw
    solver: dict[str, Any]
    events: dict[str, np.ndarray] | None = None
    extra: dict[str, Any] = field(default_factory=dict)
    recorded: np.ndarray | None = None
    state_names: tuple[str, ...] = SINGLE_MASS_STATE
    contact_names: tuple[str, ...] = SINGLE_CONTACT
    internal: np.ndarray | None = None
    internal_names: tuple[str, ...] = ()
    dbelt: np.ndarray | None = None

    @classmethod
    def single_mass(cls, t: np.ndarray, x: np.ndarray, v: np.ndarray, fc: np.ndarray, mode: np.ndarray,
                    dwork: np.ndarray, **rest: Any) -> "Trajectory":
        """The trajectory of the single mass on the belt from its columns (X, X', F_c, mode); ``rest``: the
        remaining fields (``model``, ``friction``, ``solver``, ...)."""
        return cls(t=np.asarray(t), state=np.stack((x, v)), force=np.asarray(fc)[None, :],
                   modes=np.asarray(mode)[None, :], dwork=dwork, **rest)

    # -- the single mass's views ------------------------------------------------
    @property
    def x(self) -> np.ndarray:
        """Displacement X (the state's first row)."""
        return self.state[0]

    @property
    def v(self) -> np.ndarray:
        """Velocity X' (the state's second row)."""
        return self.state[1]

    @property
    def fc(self) -> np.ndarray:
        """Friction force F_c of the first contact."""
        return self.force[0]

    @property
    def mode(self) -> np.ndarray:
        """Friction mode of the first contact."""
        return self.modes[0]

    def __len__(self) -> int:
        return len(self.t)

    # -- display ----------------------------------------------------------------
    def _summary(self) -> tuple[str, list[Row]]:
        settings = ", ".join(f"{k}={v:g}" for k, v in self.solver.items()
                             if k not in ("name", "max_steps", "steps") and isinstance(v, (int, float)) and v is not None)
        rows = [
            system_row(self.model, self.friction),
            ("solver", self.solver.get("name", "?") + (f" ({settings})" if settings else "")),
            ("span", f"tau {num(self.t[0])} .. {num(self.t[-1])}" if len(self.t) else "empty"),
            ("samples", f"{len(self.t)}" + ("" if self.recorded is None else f" ({int(self.recorded.sum())} recorded)")),
            ("switches", self._switch_text()),
        ]
        return "Trajectory", rows

    def _switch_text(self) -> str:
        if self.events is not None:
            return f"{len(self.events['t'])}"
        changes = int(np.count_nonzero(np.diff(self.mode))) if len(self.mode) else 0
        return f"{changes} mode changes between samples (not located by this solver)"

    def plot(self, path: Any = None, **options: Any):
        """X(tau), X'(tau) and the phase portrait on the true curve, switches marked; returns the figure.

        ``options``: the figure function's keywords (``dpi``: dots per inch, ``name``).
        """
        return draw(self, path, **options)

    # -- the motion at any time -------------------------------------------------------
    def at(self, t: Any) -> tuple[Any, Any]:
        """(X, X') at time(s) ``t`` in the span: floats for a scalar, arrays shaped like ``t`` otherwise.

        Closed form for the exact solver (to rounding), quintic Hermite on
        the steps for the adaptive one (error O(h^6), below its tolerance),
        cubic Hermite between samples for RK4 (O(h^4)); see
        ``frictionflow._continuous``.  ValueError outside the span.
        """
        ts = np.asarray(t, dtype=float)
        x, v = cont.interpolant(self).state(ts.ravel())
        if ts.ndim == 0:
            return float(x[0]), float(v[0])
        return x.reshape(ts.shape), v.reshape(ts.shape)

    __call__ = at

    def sample(self, dt: float, start: float | None = None, stop: float | None = None) -> "Trajectory":
        """The motion resampled every ``dt`` from ``start`` to ``stop`` (default: the span), as a Trajectory.

        X, X', F_c and the mode come from :meth:`at` and the law; the work
        integrals are the solver's over whole sample intervals and a
        Gauss-Legendre quadrature of the interpolated integrands over parts
        of one (``frictionflow._continuous.dwork_at``).
        """
        if not dt > 0:
            raise ValueError(f"dt must be > 0, got {dt!r}")
        t0 = self.t[0] if start is None else float(start)
        t1 = self.t[-1] if stop is None else float(stop)
        times = t0 + dt * np.arange(int(np.floor((t1 - t0) / dt * (1 + 1e-12))) + 1)
        return self._at_times(times, np.isin(times, self.t))

    def dense(self, points_per_period: int = cont.POINTS_PER_PERIOD) -> "Trajectory":
        """The samples plus points on the true curve filling every gap wider than 2 pi / ``points_per_period``.

        The solver's own samples keep their values exactly and are marked in
        :attr:`recorded`; what the analysis finds in it is what it finds in
        ``self``.  A run already sampled that densely comes back unchanged.
        """
        times, is_sample = cont.dense_times(self.t, points_per_period)
        if is_sample.all():
            return self
        interp = cont.interpolant(self)
        dbelt = None if self.dbelt is None else cont.dbelt_on_grid(self, interp, times, is_sample)
        out = self._at_times(times, is_sample, interp, cont.dwork_on_grid(self, interp, times, is_sample), dbelt)
        keep = np.flatnonzero(is_sample)
        for block in ("state", "force", "modes", "internal"):  # the samples as recorded, not re-evaluated
            if getattr(self, block) is not None:
                getattr(out, block)[:, keep] = getattr(self, block)
        if self.recorded is not None:
            out.recorded[keep] = self.recorded
        return out

    def _at_times(self, times: np.ndarray, recorded: np.ndarray, interp=None, dwork=None, dbelt=None) -> "Trajectory":
        """A Trajectory evaluated at ``times`` (ascending, in the span); ``dwork``, ``dbelt``: the work
        increments between them, when the caller has them (else integrated here)."""
        interp = interp or cont.interpolant(self)
        x, v = interp.state(times)
        fc, mode = interp.force(times, x, v)
        dwork = cont.dwork_at(self, interp, times) if dwork is None else dwork
        # the belt's work goes the way of the other work channels: the solver's own over whole sample intervals
        if self.dbelt is not None and dbelt is None:
            dbelt = cont.dbelt_at(self, interp, times)
        internal = None if self.internal is None else interp.internal(times)
        return Trajectory.single_mass(times, x, v, fc, mode, dwork, model=self.model, friction=self.friction,
                                      solver=dict(self.solver), events=self.events, extra=dict(self.extra),
                                      recorded=recorded, internal=internal, internal_names=self.internal_names,
                                      dbelt=dbelt)

    def switches(self) -> np.ndarray:
        """True at the points where the friction mode switches (the located switches, or a mode change for RK4)."""
        return cont.switch_flags(self)

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

    @property
    def stored_energy(self) -> np.ndarray:
        """Energy stored in the contact at each sample (the law's ``stored_energy`` of the internal states;
        zero for a static law)."""
        if self.internal is None:
            return np.zeros(len(self.t))
        return np.asarray(self.friction.stored_energy(self.internal), dtype=float)

    def interface_balance(self, i0: int = 0, i1: int = -1) -> "InterfaceBalance":
        """Where the belt's work on the contact goes over samples (i0, i1]: into the mass (the friction
        work int X' F_c), into heat, and into the energy the contact stores.

        Needs the belt's work (:attr:`dbelt`, recorded by the solvers that integrate internal states).
        """
        if self.dbelt is None:
            raise ValueError(f"solver={self.solver.get('name')} does not record the belt's work (dbelt): "
                             "run a law with internal state through a solver that integrates them")
        i1 = i1 % len(self.t)
        w = self.window_work(i0, i1)
        belt = float(self.dbelt[i0 + 1 : i1 + 1].sum())
        stored = float(self.stored_energy[i1] - self.stored_energy[i0])
        friction, heat = float(w[1] - w[2]), float(w[3])
        return InterfaceBalance(belt, friction, heat, stored, belt - friction - heat - stored)

    def window_work(self, i0: int, i1: int) -> np.ndarray:
        """The work integrals (``WORK_NAMES``) over samples (i0, i1]."""
        return self.dwork[i0 + 1 : i1 + 1].sum(axis=0)

    @property
    def acceleration(self) -> np.ndarray:
        """X'' = F_c + f(tau) - X - 2 zeta X' (Eq. 4, with the external force)."""
        return self.fc + self.model.external_force(self.t) - self.x - 2.0 * self.zeta * self.v

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

    def checked_window(self, window: Any) -> tuple[float, float]:
        """``window`` as two floats inside the run's span, start before end; ValueError otherwise (every function
        that takes a window of a run checks it here)."""
        try:
            t0, t1 = (float(w) for w in window)
        except (TypeError, ValueError):
            raise ValueError(f"window must be (start, end), two times, got {window!r}") from None
        lo, hi = float(self.t[0]), float(self.t[-1])
        if not (lo <= t0 < t1 <= hi):
            raise ValueError(f"window must satisfy {lo:g} <= start < end <= {hi:g} (the run's span), got {window!r}")
        return t0, t1

    def to_xarray(self, dense: bool = True, points_per_period: int = cont.POINTS_PER_PERIOD):
        """The motion as an :class:`xarray.Dataset` over ``tau`` with units and long names.

        ``dense`` (default): the true curve, the samples plus points filling
        every gap wider than 2 pi / ``points_per_period`` (:meth:`dense`);
        ``dense=False``: the samples only.  ``is_sample`` marks the solver's
        own samples (``ds.where(ds.is_sample, drop=True)`` gives them back)
        and ``switch`` the samples where the friction mode switches.  The
        work columns are running totals (:attr:`work`); the model, law and
        solver settings become attributes.
        """
        import xarray as xr  # imported here: it is slow to import and only exports need it

        traj = self.dense(points_per_period) if dense else self
        is_sample = np.ones(len(traj.t), dtype=bool) if traj.recorded is None else traj.recorded.copy()
        switch = np.zeros(len(traj.t), dtype=bool)
        switch[is_sample] = self.switches() if self.recorded is None else self.switches()[self.recorded]
        data = dict(zip(self.state_names, traj.state))
        data.update(_contact_variables(traj))
        data.update({name: traj.work[:, j] for j, name in enumerate(WORK_NAMES)})
        if traj.internal is not None:
            data.update(zip(self.internal_names, traj.internal))
            data["E_s"] = traj.stored_energy
        if traj.dbelt is not None:
            data["W_belt"] = np.cumsum(traj.dbelt)
        data.update(is_sample=is_sample, switch=switch)
        ds = xr.Dataset(
            {k: ("tau", np.asarray(v)) for k, v in data.items()},
            coords={"tau": ("tau", traj.t, {"units": "1", "long_name": "non-dimensional time tau = omega0 t"})},
        )
        for k, (units, long_name) in DATASET_VARIABLES.items():
            if k in ds:
                ds[k].attrs.update(units=units, long_name=long_name)
        for k in self.internal_names:
            ds[k].attrs.update(units="1", long_name=f"internal state {k} of friction={self.friction.name}")
        for k in ds:
            if k == "mode" or k.startswith("mode_"):
                ds[k].attrs.update(_mode_flags())
        ds.attrs.update(self.model.report())
        # the law's name as ``friction`` (not under its own prefix), its parameters as ``friction_<name>``
        ds.attrs.update({k if k == "friction" else f"friction_{k}": v for k, v in self.friction.as_dict().items()})
        ds.attrs.update({f"solver_{k}": v for k, v in self.solver.items() if v is not None})
        return ds


class InterfaceBalance(NamedTuple):
    """The belt's work on the contact over a window and where it went (:meth:`frictionflow.Trajectory.interface_balance`).

    ``belt`` = int F_c V_b, ``friction`` = int X' F_c (into the mass), ``heat`` = int (F_c V_r - dE_s/dtau),
    ``stored`` = the change of the stored energy E_s, ``residual`` = belt - friction - heat - stored.
    """

    belt: float
    friction: float
    heat: float
    stored: float
    residual: float


def _contact_variables(traj: Trajectory) -> dict[str, np.ndarray]:
    """The contact block's variables: ``F_c`` and ``mode`` for one contact, ``F_c_<name>``, ``mode_<name>`` for several."""
    if len(traj.contact_names) == 1:
        return {"F_c": traj.force[0], "mode": traj.modes[0]}
    out = {}
    for name, fc, mode in zip(traj.contact_names, traj.force, traj.modes):
        out.update({f"F_c_{name}": fc, f"mode_{name}": mode})
    return out


def _mode_flags() -> dict[str, Any]:
    """CF ``flag_values`` / ``flag_meanings`` of the sample mode codes."""
    codes = sorted(MODE_NAMES)
    meanings = (MODE_NAMES[k].replace("+", "_pos").replace("-", "_neg") for k in codes)
    return {"flag_values": np.array(codes, dtype=np.int8), "flag_meanings": " ".join(meanings)}
