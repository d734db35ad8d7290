"""A trajectory between its samples: the motion at any time of the span.

:meth:`Trajectory.at <frictionflow.trajectory.Trajectory.at>` delegates here,
to the interpolant the solver that made the run declares (its ``interpolant``, one of
:data:`FORMS`; :func:`interpolant`):

``closed_form`` (the exact solver)
    The closed form itself.  Between two samples the motion is one phase of
    constant-coefficient dynamics (:mod:`frictionflow.core.closed_form`): OSC
    X'' + 2 zeta X' + X = F about a constant F (slip at +-F_d, Karnopp's
    saturated band at +-F_s), LIN X'' = 0 (stick, Karnopp's band holding
    F_e = X + 2 zeta X', sliding on a band edge) or EXP X'' = -2 zeta X'
    (Karnopp's band holding F_e = X).  Which one follows a sample is read
    from the switch record ``events`` (the mode entered at each switch); the
    first phase, before any switch, from the first samples themselves.
    Under harmonic forcing OSC phases add the periodic particular solution
    (held forces are less f(tau)).  Accurate to rounding (~1e-15 relative).
``quintic_hermite`` (the adaptive solver)
    Quintic Hermite interpolation in each step of a slip phase, from X, X'
    and X'' = F_c - X - 2 zeta X' at both ends (the solver samples every
    step).  Error O(h^6) in X and O(h^5) in X' for a step h: below the
    solver's own tolerance at the steps its error control picks.  Stick
    phases (X' = V_b) are exact.
``cubic_hermite`` (fixed-step RK4, and a run of an unknown solver)
    Cubic Hermite interpolation between samples: X from X and X', X' from
    X' and X'' at both ends.  Error O(h^4) for a sample spacing h (1e-12 of
    the amplitude at the default dt = 1e-3); the numerical solution itself
    is RK4's.

F_c and the friction mode at any time follow the law (:meth:`Interpolant.force`).
The work integrals at points added between samples (:func:`dwork_on_grid`)
are Gauss-Legendre quadratures of the interpolated integrands over short
steps, corrected at each sample so that every sample interval keeps the
solver's own integrals: an analysis of a densified trajectory finds what it
finds in the samples.  The adaptive solver's samples at events inside a step
come from its own dense output (4th order): their error, not the
interpolation's, dominates there.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from .core import closed_form as cf
from .core.event_modes import EXACT_CODES, exact_motion, held_modes
from .core.hermite import hermite, quintic
from .core.layout import W_HEAT
from .modes import SwitchMode

#: dense sampling of figures and datasets: at least this many points per natural period 2 pi
POINTS_PER_PERIOD = 64
OSC, LIN, EXP = cf.OSC, cf.LIN, cf.EXP
#: 8-point Gauss-Legendre nodes and weights on [0, 1] (the work integrals at added points)
_GL_X, _GL_W = np.polynomial.legendre.leggauss(8)
_GL_X, _GL_W = 0.5 * (_GL_X + 1.0), 0.5 * _GL_W


#: solver name -> its declared form (``Solver.interpolant``), filled by :mod:`frictionflow.solvers.registry`
#: as it registers the solvers: this module sits below them and cannot import their registry
_BY_SOLVER: dict[str, str] = {}


def declare_interpolant(solver: str, form: str) -> None:
    """Evaluate the runs of solver ``solver`` with the form ``form`` (a key of :data:`FORMS`)."""
    if form not in FORMS:
        raise ValueError(f"interpolant must be one of {', '.join(FORMS)}, got {form!r} (solver {solver})")
    _BY_SOLVER[solver] = form


def form_of(solver: dict) -> str:
    """The form declared by the solver a run's ``solver`` record names (cubic Hermite when unknown)."""
    return _BY_SOLVER.get(solver.get("name"), "cubic_hermite")


def interpolant(traj) -> "Interpolant":
    """The interpolant of ``traj`` by the solver that made it (see the module's docstring)."""
    form = form_of(traj.solver)
    if form == "closed_form" and traj.events is None:
        form = "cubic_hermite"  # the closed forms read the phases from the switch record
    if form == "closed_form" and traj.model.belt_varies:
        return BeltClosedForm(traj)
    return FORMS[form](traj)


class Interpolant:
    """The motion of ``traj`` between its samples (a subclass per solver)."""

    def __init__(self, traj) -> None:
        self.traj = traj
        self.model = traj.model
        self.zeta = traj.model.zeta
        self.vb = traj.model.vb

    def belt(self, t: np.ndarray) -> Any:
        """V_b at the times ``t``: the belt's speed, varying (``model.belt_varies``) or the constant V_b."""
        return self.model.belt_speed(t) if self.model.belt_varies else self.vb

    def on_belt(self, x0: np.ndarray, t0: np.ndarray, t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(X, X') at ``t`` in stick phases from (t0, x0) on a moving belt: X = x0 + int V_b (closed form), X' = V_b."""
        m = self.model
        x = x0 + m.vb * (t - t0) - m.vb_amplitude / m.vb_omega * (np.cos(m.vb_omega * t + m.vb_phi)
                                                                   - np.cos(m.vb_omega * t0 + m.vb_phi))
        return x, m.belt_speed(t)

    def _local(self, t: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The sample interval of each time, its length, and the time's fraction of it (Hermite forms)."""
        i = self.interval(t)
        h = self.traj.t[i + 1] - self.traj.t[i]
        return i, h, np.divide(t - self.traj.t[i], h, out=np.zeros_like(t), where=h > 0)

    def interval(self, t: np.ndarray) -> np.ndarray:
        """Index i of the interval [t_i, t_i+1] holding each time (the last sample at or before it)."""
        ts = self.traj.t
        lo, hi = ts[0], ts[-1]
        bad = (t < lo) | (t > hi) | np.isnan(t)
        if np.any(bad):
            raise ValueError(f"t must lie in the trajectory's span [{lo:g}, {hi:g}], got {t[bad][0]!r}")
        i = np.searchsorted(ts, t, side="right") - 1
        return np.clip(i, 0, max(len(ts) - 2, 0))

    def state(self, t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(X, X') at the times ``t`` (an array inside the span)."""
        raise NotImplementedError

    def force(self, t: np.ndarray, x: np.ndarray, v: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(F_c, mode) at times ``t`` where the state is (x, v): slip by the law, stick as sampled."""
        i = self.interval(t)
        mode = self.traj.mode[i].astype(np.int8)
        stick = x + 2.0 * self.zeta * v - self.model.external_force(t)
        if self.model.belt_varies:
            stick = stick + self.model.belt_accel(t)  # X'' = V_b' while sticking
        return self._slip_or(mode, t, x, v, stick), mode

    def _slip_or(self, mode: np.ndarray, t: np.ndarray, x: np.ndarray, v: np.ndarray, stick: np.ndarray) -> np.ndarray:
        """The law's slip force where ``mode`` slips (at times ``t``), ``stick`` elsewhere."""
        fc = np.array(stick, dtype=float)
        slip = mode != 0
        if np.any(slip):
            speed = np.abs(np.broadcast_to(self.belt(t), v.shape)[slip] - v[slip])
            fc[slip] = mode[slip] * np.asarray(self.traj.friction.slip_magnitude(speed), dtype=float)
        return fc

    def acceleration_left(self) -> np.ndarray:
        """X'' at the right end of each interval as the interval's own phase sees it (before a switch there)."""
        tr = self.traj
        mode, nxt = tr.mode[:-1], tr.mode[1:]
        fc_right = np.where(nxt == mode, tr.fc[1:], 0.0)
        switched = (nxt != mode) & (mode != 0)
        if np.any(switched):
            speed = np.abs(np.broadcast_to(self.belt(tr.t[1:]), switched.shape)[switched] - tr.v[1:][switched])
            fc_right[switched] = mode[switched] * np.asarray(tr.friction.slip_magnitude(speed), dtype=float)
        return fc_right + self.model.external_force(tr.t[1:]) - tr.x[1:] - 2.0 * self.zeta * tr.v[1:]


# -- the exact solver: closed forms ----------------------------------------------------------------

class ClosedForm(Interpolant):
    """The exact solver's phases in closed form (vectorised; the same laws as :mod:`.core.closed_form`)."""

    def __init__(self, traj) -> None:
        super().__init__(traj)
        self.dyn, self.centre = self._phases()

    def _phases(self) -> tuple[np.ndarray, np.ndarray]:
        """(motion type, OSC centre F) of the phase that follows each sample."""
        tr = self.traj
        ev_t, ev_mode = tr.events["t"], tr.events["mode"].astype(np.int64)
        k = np.searchsorted(ev_t, tr.t, side="right")  # switches up to each sample
        modes = np.concatenate([[int(self._first_phase())], ev_mode])[k]  # k = 0: the first phase
        # lookup tables indexed by SwitchMode value + 1 (the values run from -1)
        table = self._table()
        dyn, centre = np.zeros(len(SwitchMode), dtype=np.int8), np.zeros(len(SwitchMode))
        for mode, (d, c) in table.items():
            dyn[mode + 1], centre[mode + 1] = d, c
        return dyn[modes + 1], centre[modes + 1]

    def _table(self) -> dict[SwitchMode, tuple[int, float]]:
        """Motion type and OSC centre of each mode the exact kernel records (:func:`.core.event_modes.exact_motion`)."""
        law = self.traj.friction
        fd, fs, res = law.fd, getattr(law, "fs", law.fd), law.stick_force != "spring"
        return {mode: exact_motion(mode, self.zeta, fd, fs, res) for mode in EXACT_CODES}

    def _first_phase(self) -> SwitchMode:
        """The mode of the run's first phase (no switch records it).

        The candidates are the modes whose F_c matches the first sample's;
        where several do (the start lies on a boundary between them), the one
        whose motion reaches the phase's last sample (the first switch, or
        the end of the run: X is continuous there).
        """
        tr = self.traj
        x, v, fc, m = tr.x[0], tr.v[0], tr.fc[0], int(tr.mode[0])
        if m != 0:
            return SwitchMode(m)
        held = held_modes(tr.friction.stick_rule)  # Coulomb's switch holds only in STICK, the band in its own modes
        if len(held) == 1:
            return held[0]
        table = self._table()
        tol = 1e-12 * (abs(x) + abs(v) + abs(fc) + tr.friction.fs + 1e-300)
        found = [s for s in held if abs(self._fc_of(s, table, x, v) - fc) <= tol]
        ev_t = tr.events["t"]
        last = np.searchsorted(tr.t, ev_t[0], side="left") if len(ev_t) else len(tr.t) - 1
        if len(found) <= 1 or tr.t[last] <= tr.t[0]:
            return found[0] if found else SwitchMode.BAND_HOLD
        s = tr.t[last] - tr.t[0]
        miss = [abs(self._one(table[c][0], table[c][1], x, v, s)[0] - tr.x[last]) for c in found]
        return found[int(np.argmin(miss))]

    def _fc_of(self, mode: SwitchMode, table: dict, x: float, v: float) -> float:
        """F_c of ``mode`` at the run's first sample (a held force less the external force there)."""
        dyn, centre = table[mode]
        if dyn == OSC:
            return centre
        return (x if dyn == EXP else x + 2.0 * self.zeta * v) - float(self.model.external_force(self.traj.t[0]))

    def _one(self, dyn: int, centre: float, x: float, v: float, s: float) -> tuple[float, float]:
        xs, vs = self._evaluate(np.array([dyn]), np.array([centre]), np.array([x]), np.array([v]), np.array([s]),
                                np.array([self.traj.t[0]]))
        return float(xs[0]), float(vs[0])

    def state(self, t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        i = self.interval(t)
        tr = self.traj
        return self._evaluate(self.dyn[i], self.centre[i], tr.x[i], tr.v[i], t - tr.t[i], tr.t[i])

    def _evaluate(self, dyn, centre, x0, v0, s, t0) -> tuple[np.ndarray, np.ndarray]:
        """X and X' a time ``s`` into phases of type ``dyn`` started at (x0, v0) at times ``t0``.

        The kernels' closed forms (:func:`frictionflow.core.closed_form.states`): forced OSC phases add
        the harmonic particular solution; LIN and EXP motions do not feel the external force.
        """
        m = self.model
        n = len(s)
        x, v = np.empty(n), np.empty(n)
        theta = m.omega * np.asarray(t0, dtype=float) + m.phi if m.forced else np.zeros(n)
        cf.states(np.asarray(dyn, dtype=np.int64), np.asarray(centre, dtype=float), np.asarray(x0, dtype=float),
                  np.asarray(v0, dtype=float), np.asarray(s, dtype=float), theta, self.zeta, float(m.fex) if m.forced else 0.0,
                  float(m.omega), x, v)
        return x, v

    def force(self, t, x, v):
        i = self.interval(t)
        dyn = self.dyn[i]
        held = np.where(dyn == EXP, x, x + 2.0 * self.zeta * v)
        if self.model.forced:
            held = held - self.model.external_force(t)
        fc = np.where(dyn == OSC, self.centre[i], held)
        return fc, self.traj.mode[i].astype(np.int8)


class BeltClosedForm(ClosedForm):
    """The exact solver on a moving belt (Coulomb's switch, :mod:`.core.exact_belt`): each sample's friction mode is
    the phase after it -- slip in closed form about d F_d (OSC), stick on the belt (:meth:`Interpolant.on_belt`)."""

    def _phases(self) -> tuple[np.ndarray, np.ndarray]:
        mode = self.traj.mode.astype(float)
        return np.full(len(mode), OSC, dtype=np.int8), mode * self.traj.friction.fd

    def state(self, t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        x, v = super().state(t)
        i = self.interval(t)
        stick = self.traj.mode[i] == 0
        x[stick], v[stick] = self.on_belt(self.traj.x[i][stick], self.traj.t[i][stick], t[stick])
        return x, v

    force = Interpolant.force  # slip: the law's d F_d; stick: X + 2 zeta V_b + V_b' - f


# -- the adaptive solver and RK4: Hermite interpolation -----------------------------------------------

class QuinticHermite(Interpolant):
    """The adaptive solver's steps: quintic Hermite in slip, the exact line in stick.

    X'' at a sample is F_c + f(tau) - X - 2 zeta X' (zero while sticking,
    where F_c holds X + 2 zeta V_b - f).
    """

    def __init__(self, traj) -> None:
        super().__init__(traj)
        tr = traj
        self.acc = tr.fc - tr.x - 2.0 * self.zeta * tr.v
        if self.model.forced:
            self.acc = self.acc + self.model.external_force(tr.t)
        self.acc_right = self.acceleration_left() if len(tr.t) > 1 else np.zeros(0)

    def state(self, t):
        tr = self.traj
        if len(tr.t) < 2:
            return np.full(t.shape, tr.x[0]), np.full(t.shape, tr.v[0])
        i, h, s = self._local(t)
        h2 = h * h
        x, dx = quintic(tr.x[i], tr.x[i + 1], h * tr.v[i], h * tr.v[i + 1], h2 * self.acc[i], h2 * self.acc_right[i], s)
        v = np.divide(dx, h, out=np.array(tr.v[i], dtype=float), where=h > 0)  # a zero-length interval: its start
        stick = tr.mode[i] == 0  # X' = V_b held: a straight line, exactly (on a moving belt: int V_b, closed form)
        if self.model.belt_varies:
            x[stick], v[stick] = self.on_belt(tr.x[i][stick], tr.t[i][stick], t[stick])
            return x, v
        x[stick] = tr.x[i][stick] + tr.v[i][stick] * (t[stick] - tr.t[i][stick])
        v[stick] = tr.v[i][stick]
        return x, v


class CubicHermite(Interpolant):
    """Interpolation between the samples of a fixed-step run (RK4): cubic Hermite in X and in X'."""

    def __init__(self, traj) -> None:
        super().__init__(traj)
        tr = traj
        self.acc = tr.fc - tr.x - 2.0 * self.zeta * tr.v

    def state(self, t):
        tr = self.traj
        if len(tr.t) < 2:
            return np.full(t.shape, tr.x[0]), np.full(t.shape, tr.v[0])
        i, h, s = self._local(t)
        x = hermite(tr.x[i], tr.x[i + 1], h * tr.v[i], h * tr.v[i + 1], s)
        v = hermite(tr.v[i], tr.v[i + 1], h * self.acc[i], h * self.acc[i + 1], s)
        return x, v

    def force(self, t, x, v):
        """Where the law has a stick band (RK4): the band's rule at the interpolated state."""
        law = self.traj.friction
        band = law.band
        if band is None:
            return super().force(t, x, v)
        vr = self.belt(t) - v
        mode = np.where(vr > band, 1, np.where(vr < -band, -1, 0)).astype(np.int8)
        held = np.clip(law.stick_force_value(x, v, self.zeta), -law.fs, law.fs)
        return self._slip_or(mode, t, x, v, held), mode


class StateHermite(Interpolant):
    """The stiff solver's steps (laws with internal state): quintic Hermite in X with X'' at both ends,
    cubic Hermite in each internal state with its rate at both ends; the force from the law at the
    interpolated state (F is continuous: no switch to keep apart)."""

    def __init__(self, traj) -> None:
        super().__init__(traj)
        tr, law = traj, traj.friction
        self.acc = tr.fc + self.model.external_force(tr.t) - tr.x - 2.0 * self.zeta * tr.v
        self.zrate = law.rate(self._belt(tr.t) - tr.v, tr.internal)

    def _belt(self, t):
        """V_b at times ``t`` (the constant ``vb`` itself for a belt at constant speed)."""
        return self.model.belt_speed(t) if self.model.belt_varies else self.vb

    def state(self, t):
        tr = self.traj
        if len(tr.t) < 2:
            return np.full(t.shape, tr.x[0]), np.full(t.shape, tr.v[0])
        i, h, s = self._local(t)
        x, dx = quintic(tr.x[i], tr.x[i + 1], h * tr.v[i], h * tr.v[i + 1], h * h * self.acc[i], h * h * self.acc[i + 1], s)
        return x, np.divide(dx, h, out=np.array(tr.v[i], dtype=float), where=h > 0)

    def internal(self, t: np.ndarray) -> np.ndarray:
        """The internal states (m, len(t)) at times ``t``."""
        tr = self.traj
        if len(tr.t) < 2:
            return np.repeat(tr.internal[:, :1], len(t), axis=1)
        i, h, s = self._local(t)
        z, r = tr.internal, self.zrate
        return hermite(z[:, i], z[:, i + 1], h * r[:, i], h * r[:, i + 1], s)

    def force(self, t, x, v):
        law = self.traj.friction
        vr = self._belt(t) - v
        return law.force(vr, self.internal(t)), law.mode_of(vr)


#: the interpolants by the name a solver declares (``Solver.interpolant``)
FORMS: dict[str, type[Interpolant]] = {
    "closed_form": ClosedForm, "quintic_hermite": QuinticHermite, "cubic_hermite": CubicHermite,
    "state_hermite": StateHermite,
}


# -- dense grids and the work integrals at added points ---------------------------------------------


def dense_times(t: np.ndarray, points_per_period: int = POINTS_PER_PERIOD) -> tuple[np.ndarray, np.ndarray]:
    """(times, is_sample): the samples ``t`` and evenly spaced points filling every gap above 2 pi / ``points_per_period``."""
    if not (isinstance(points_per_period, (int, np.integer)) and points_per_period >= 1):
        raise ValueError(f"points_per_period must be an integer >= 1, got {points_per_period!r}")
    gap = 2.0 * math.pi / points_per_period
    dt = np.diff(t)
    extra = np.maximum(np.ceil(dt / gap).astype(np.int64) - 1, 0)  # points added inside each interval
    counts = np.concatenate([[1], extra + 1])
    total = int(counts.sum())
    start = np.repeat(np.concatenate([[t[0]], t[:-1]]), counts)
    step = np.repeat(np.concatenate([[0.0], dt / (extra + 1)]), counts)
    first = np.cumsum(counts) - counts  # index of each sample's block
    k = np.arange(total) - np.repeat(first, counts)  # 0 at the sample ending each block ...
    owner = np.repeat(np.arange(len(t)), counts)
    is_sample = k == counts[owner] - 1
    # ... which sits at the end of its block: the added points come before it, k + 1 steps after the previous sample
    times = np.where(is_sample, t[owner], start + (k + 1) * step)
    return times, is_sample


def dwork_on_grid(traj, interp: Interpolant, grid: np.ndarray, is_sample: np.ndarray) -> np.ndarray:
    """Work increments (n, 5) over each step of ``grid``, a time grid holding every sample of ``traj``.

    A step ending at an added point: an 8-point Gauss-Legendre quadrature of
    the interpolated integrands over it (the grid's steps are short: see
    :func:`dense_times`).  A step ending at a sample: the solver's own
    increment since the previous sample less the added steps before it, so
    that every sample interval sums to the solver's exact integrals and each
    increment stays accurate to rounding of its own size.

    A law with internal state: the solver integrates the heat F_c V_r -
    dE_s/dtau at every instant (no stick rule), so an added step's heat is
    the quadrature of F_c V_r less the change of the stored energy E_s of the
    interpolated states over the step.
    """
    if traj.internal is None:
        return _on_grid(traj.dwork, _integrands, interp, grid, is_sample)
    offset = np.zeros((len(grid), traj.dwork.shape[1]))
    energy = np.asarray(traj.friction.stored_energy(interp.internal(grid)), dtype=float)
    offset[1:, W_HEAT] = -np.diff(energy)
    return _on_grid(traj.dwork, _integrands, interp, grid, is_sample, offset)


def dbelt_on_grid(traj, interp: Interpolant, grid: np.ndarray, is_sample: np.ndarray) -> np.ndarray:
    """The belt's work on the contact (n,) over each step of ``grid``, as :func:`dwork_on_grid` (``traj.dbelt``
    at the samples, the quadrature of F_c V_b between them)."""
    return _on_grid(traj.dbelt[:, None], _belt_integrand, interp, grid, is_sample)[:, 0]


def _on_grid(own: np.ndarray, integrands, interp: Interpolant, grid: np.ndarray, is_sample: np.ndarray,
             offset: np.ndarray | None = None) -> np.ndarray:
    """Increments (n, c) over each step of ``grid`` of the channels whose solver increments are ``own``
    (len(samples), c) and whose integrands ``integrands(interp, t)`` gives (len(t), c); ``offset`` (n, c):
    a part of each step's increment known in closed form, added to its quadrature."""
    channels = own.shape[1]
    inc = np.zeros((len(grid), channels))
    added = np.flatnonzero(~is_sample)
    if len(added):
        a, b = grid[added - 1], grid[added]
        nodes = a[:, None] + (b - a)[:, None] * _GL_X[None, :]
        f = integrands(interp, nodes.ravel()).reshape(len(added), len(_GL_X), channels)
        inc[added] = (b - a)[:, None] * np.einsum("k,nkj->nj", _GL_W, f)
        if offset is not None:
            inc[added] += offset[added]
    samples = len(own)
    sample_no = np.cumsum(is_sample) - 1  # the sample at or before each row
    before = np.zeros((samples, channels))  # the added steps inside each sample interval, by the sample ending it
    for col in range(channels):
        before[:, col] = np.bincount(sample_no[added] + 1, weights=inc[added, col], minlength=samples + 1)[:samples]
    inc[is_sample] = own - before
    return inc


def dwork_at(traj, interp: Interpolant, times: np.ndarray) -> np.ndarray:
    """Work increments (n, 5) between consecutive ``times`` (ascending, in the span); row 0 is zero."""
    return _at(traj, interp, times, dwork_on_grid)


def dbelt_at(traj, interp: Interpolant, times: np.ndarray) -> np.ndarray:
    """The belt's work on the contact (n,) between consecutive ``times``, as :func:`dwork_at`; row 0 is zero."""
    return _at(traj, interp, times, lambda *grid: dbelt_on_grid(*grid)[:, None])[:, 0]


def _at(traj, interp: Interpolant, times: np.ndarray, on_grid) -> np.ndarray:
    """Increments (n, c) between consecutive ``times`` of the channels ``on_grid(traj, interp, grid, is_sample)``
    gives on a grid holding every sample."""
    grid, is_sample = dense_times(traj.t)
    extra = np.setdiff1d(times, grid)
    merged = np.concatenate([grid, extra])
    order = np.argsort(merged, kind="stable")  # samples before an added point at the same time
    merged, flags = merged[order], np.concatenate([is_sample, np.zeros(len(extra), dtype=bool)])[order]
    inc = on_grid(traj, interp, merged, flags)
    rows = np.searchsorted(merged, times, side="right") - 1  # the last row at each time
    # each step's increments summed (short sums: no difference of large running totals)
    start, end = rows[:-1] + 1, rows[1:] + 1
    total = np.zeros((len(times), inc.shape[1]))
    if len(times) > 1:
        padded = np.vstack([inc[: end[-1]], np.zeros((1, inc.shape[1]))])  # reduceat needs every start in range
        sums = np.add.reduceat(padded, np.minimum(start, end[-1]), axis=0)
        total[1:] = np.where((end > start)[:, None], sums, 0.0)  # reduceat gives a row, not 0, for an empty step
    return total


def _integrands(interp: Interpolant, t: np.ndarray) -> np.ndarray:
    """2 zeta X'^2, max(P_f, 0), max(-P_f, 0), the heat F_c V_r (over slip for a static law, always for a law
    with internal state: see :func:`dwork_on_grid`) and X' f(tau) at times ``t``."""
    x, v = interp.state(t)
    fc, mode = interp.force(t, x, v)
    pf = v * fc
    heat = fc * (interp.belt(t) - v)
    if interp.traj.internal is None:  # a static law sticks with no heat: V_r = 0 there up to the kernel's band
        heat = np.where(mode != 0, heat, 0.0)
    return np.column_stack([2.0 * interp.zeta * v * v, np.maximum(pf, 0.0), np.maximum(-pf, 0.0), heat,
                            v * interp.model.external_force(t)])


def _belt_integrand(interp: Interpolant, t: np.ndarray) -> np.ndarray:
    """The belt's power on the contact F_c V_b at times ``t``, as one column."""
    x, v = interp.state(t)
    fc, _ = interp.force(t, x, v)
    return (fc * interp.belt(t))[:, None]


def switch_flags(traj) -> np.ndarray:
    """True at the samples where the friction mode switches: the located switches (``events``), or a mode change."""
    if traj.events is not None:
        return np.isin(traj.t, traj.events["t"])
    flags = np.zeros(len(traj.t), dtype=bool)
    flags[1:] = traj.mode[1:] != traj.mode[:-1]
    return flags
