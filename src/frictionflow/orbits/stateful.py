"""Periodic orbits of laws with internal state: Newton shooting on the whole state, with Floquet multipliers.

The flow of a stateful law (LuGre, Dahl, elasto-plastic, any
:class:`~frictionflow.friction.stateful.StatefulLaw`) is Lipschitz and has no
switches, so the orbit is a fixed point of a smooth map of the whole state
y = (X, X', z ...), and the monodromy M = dy(T)/dy(0) comes from the
variational equations (:mod:`.flow_stiff`).

Unforced, the section is X' = 0: the unknowns are (X, z ...) on it and the
period T, and the n equations are phi_T(X, 0, z) - (X, 0, z) = 0; their
Jacobian is [M - I without the X' column | y'(T)].  One multiplier of an
autonomous cycle is the trivial 1 (the flow's direction); it is dropped from
the nontrivial ones (the one nearest 1, as :func:`.floquet.nontrivial` does).
Forced, the map is the stroboscopic one over T = m 2 pi / Omega on the whole
state (X, X', z ...), with Jacobian M - I and no trivial multiplier.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, NamedTuple

import numpy as np

from .._display import Row, Summarized, num, system_row
from .._json import jsonable
from ..friction.base import FrictionLaw
from ..analysis.steady_state import stick_fraction as window_stick_fraction
from ..params import BeltOscillator
from ..simulate import simulate
from ..solvers.stiff import Stiff
from ..trajectory import Trajectory
from . import floquet
from .errors import ShootingError
from .flow_stiff import StiffFlow, check_stateful
from .measures import OrbitMeasures, measures_of

#: Newton's default tolerance on the residual, relative to each component's scale
STATE_TOL = 1e-9
#: the guess without a transient: the section crossings of this long a run from the start
GUESS_SPAN = 60.0


@dataclass(frozen=True, repr=False, eq=False)
class StatefulOrbit(floquet.MultiplierStability, Summarized):
    """A periodic orbit on the whole state (X, X', z ...), its Floquet multipliers and one period of it.

    Attributes
    ----------
    model, friction:
        The oscillator and its law.
    state:
        The orbit's point y0 = (X, X', z ...): on the section X' = 0 (unforced) or at tau = 0 (forced).
    period:
        Its period.
    monodromy:
        dy(T)/dy(0), n x n.
    residual:
        The largest scaled |phi_T(y0) - y0| at the end.
    iterations:
        Newton iterations taken.
    trajectory:
        One period from ``state`` by the stiff solver.
    """

    model: BeltOscillator
    friction: FrictionLaw
    state: np.ndarray
    period: float
    monodromy: np.ndarray
    residual: float
    iterations: int
    trajectory: Trajectory

    @property
    def autonomous(self) -> bool:
        return not self.model.forced

    @property
    def multipliers(self) -> np.ndarray:
        """All Floquet multipliers, largest modulus first (the trivial 1 included when unforced)."""
        return floquet.multipliers(self.monodromy)

    @property
    def amplitude(self) -> float:
        """(max X - min X) / 2 over the period's samples."""
        x = self.trajectory.x
        return float(0.5 * (np.max(x) - np.min(x)))

    @property
    def measures(self) -> OrbitMeasures:
        """Averages over the period, TR_B and the extremes of X and X' (of :attr:`trajectory`)."""
        return measures_of(self.trajectory)

    @property
    def stick_fraction(self) -> float:
        """The fraction of the period the law counts as stuck (``mode_of``, |V_r| below its creep speed)."""
        return stick_fraction(self.trajectory)

    def _summary(self) -> tuple[str, list[Row]]:
        names = ("X", "X'", *self.friction.internal_names)
        rows = [
            system_row(self.model, self.friction),
            ("period", num(self.period, 10)),
            ("state", ", ".join(f"{k}={num(v, 10)}" for k, v in zip(names, self.state, strict=True))),
            ("stability", f"{self.stability}, multiplier {num(self.multiplier)}"),
            ("stick fraction", num(self.stick_fraction, 4)),
            ("amplitude", num(self.amplitude)),
            ("Newton", f"{self.iterations} iterations, residual {num(self.residual, 2)}"),
        ]
        return "StatefulOrbit", rows

    def to_dict(self) -> dict[str, Any]:
        """A JSON-ready report (NaN becomes None, complex numbers [re, im])."""
        bal = self.trajectory.interface_balance()
        names = ("X", "V", *self.friction.internal_names)
        return jsonable({
            "params": {**self.model.report(), **self.friction.as_dict()},
            "state": dict(zip(names, (float(v) for v in self.state), strict=True)),
            "period": self.period,
            "floquet_multipliers": [complex(m) for m in self.multipliers],
            "multiplier": self.multiplier,
            "stable": self.stable,
            "stability": self.stability,
            "stick_fraction": self.stick_fraction,
            "amplitude": self.amplitude,
            "interface_balance": bal._asdict(),
            "averages": self.measures.averages(forced=self.model.forced),
            "TR_B": self.measures.TR_B,
            "energy_residual": self.measures.power.energy_residual,
            "monodromy": self.monodromy,
            "newton": {"iterations": self.iterations, "residual": self.residual},
        })


def stick_fraction(traj: Trajectory) -> float:
    """The fraction of ``traj``'s time the law counts as stuck, as simulate's analysis measures a window."""
    return window_stick_fraction(traj, (float(traj.t[0]), float(traj.t[-1])))


class Newton(NamedTuple):
    """A converged shooting: the unknowns, the flow's end there, the scaled residual, iterations."""

    u: np.ndarray
    end: Any
    residual: float
    iterations: int


class ShootingMap:
    """The shooting equations of one system: unknowns u, residual R(u) and its Jacobian (module docstring)."""

    def __init__(self, flow: StiffFlow, period: float | None = None) -> None:
        self.flow = flow
        self.forced = period is not None
        self.period = period
        n = flow.n
        self.cols = list(range(n)) if self.forced else [0, *range(2, n)]  # the unforced section fixes X' = 0
        law, model = flow.law, flow.model
        self.scale = np.concatenate([[max(law.fs, abs(model.vb), 1e-12)] * 2, law.internal_scale()])

    def state(self, u: np.ndarray) -> tuple[np.ndarray, float]:
        """(y0, T) of the unknowns."""
        if self.forced:
            return np.asarray(u, dtype=float), float(self.period)
        y0 = np.zeros(self.flow.n)
        y0[self.cols] = u[:-1]
        return y0, float(u[-1])

    def unknowns(self, y0: np.ndarray, period: float) -> np.ndarray:
        return np.array(y0, dtype=float) if self.forced else np.append(np.asarray(y0)[self.cols], period)

    def evaluate(self, u: np.ndarray) -> tuple[np.ndarray, np.ndarray, Any]:
        """(R, dR/du, the flow's end) at u."""
        y0, period = self.state(u)
        end = self.flow.run(y0, period)
        eye = np.eye(self.flow.n)
        jac = end.jacobian[:, self.cols] - eye[:, self.cols]
        if not self.forced:
            jac = np.column_stack([jac, end.field])
        return end.y - y0, jac, end

    def size(self, r: np.ndarray) -> float:
        return float(np.max(np.abs(r) / self.scale))


def newton(smap: ShootingMap, u: np.ndarray, tol: float, max_iter: int = 30) -> Newton:
    """Newton with backtracking on the scaled residual; ShootingError if it does not converge."""
    u = np.asarray(u, dtype=float)
    try:
        r, jac, end = smap.evaluate(u)
    except RuntimeError as e:
        raise ShootingError(f"the flow from the start failed: {e}") from None
    size = smap.size(r)
    for it in range(max_iter + 1):
        if size <= tol:
            return Newton(u, end, size, it)
        try:
            du = np.linalg.solve(jac, -r)
        except np.linalg.LinAlgError:
            raise ShootingError("the shooting Jacobian is singular: no isolated orbit here") from None
        for _ in range(12):  # backtrack until the scaled residual falls
            un = u + du
            try:
                if smap.forced or un[-1] > 0.0:
                    rn, jn, en = smap.evaluate(un)
                    if smap.size(rn) < size:
                        break
            except RuntimeError:
                pass
            du = 0.5 * du
        else:
            raise ShootingError(f"Newton stalled (scaled residual {size:.3g}): no periodic orbit near this start")
        u, r, jac, end, size = un, rn, jn, en, smap.size(rn)
    raise ShootingError(f"Newton did not converge in {max_iter} iterations (scaled residual {size:.3g})")


def section_guess(traj: Trajectory, last: bool, returns: int = 1) -> tuple[np.ndarray, float]:
    """(y on X' = 0, the time of ``returns`` returns to it) of a stiff run (which samples each downward
    crossing of X' = 0): at its last crossings (``last``) or its first ones."""
    v = traj.v
    down = np.flatnonzero((v[:-1] > 0.0) & (v[1:] == 0.0)) + 1
    if len(down) < returns + 1:
        if np.ptp(traj.x) == 0.0 and np.ptp(v) == 0.0:  # an equilibrium, which a run from it never leaves
            raise ShootingError(f"the run stayed where it started (X = {traj.x[0]:.6g}, X' = {v[0]:.6g}): an "
                                "equilibrium, stable or not, which a run from it never leaves; start off it "
                                "(x0 or v0) to find an orbit around it")
        raise ShootingError(f"the run crossed X' = 0 downward {len(down)} times in tau <= {traj.t[-1]:.6g}: "
                            "it settled (no orbit to shoot from there)")
    i, j = (down[-1 - returns], down[-1]) if last else (down[0], down[returns])
    y = np.concatenate([[traj.x[j], 0.0], traj.internal[:, j]])
    return y, float(traj.t[j] - traj.t[i])


def find_stateful_orbit(model: BeltOscillator, friction: FrictionLaw, *, x0: float | None = None,
                        v0: float | None = None, transient: float = 500.0, returns: int = 1,
                        tol: float | None = None, max_iter: int = 30, solver: Stiff | None = None) -> StatefulOrbit:
    """A periodic orbit of a law with internal state, from a run of ``transient`` (0: straight from the start).

    Parameters
    ----------
    model, friction:
        The oscillator (unforced or forced, a constant belt) and a law with internal state.
    x0, v0:
        Start state (default X = F_d, X' = V_b; the internal states relaxed).
    transient:
        First simulate this long (> 0: towards an attractor; 0: the first section crossings of a run of
        ``GUESS_SPAN`` give the guess).
    returns:
        Section crossings per period (unforced) or forcing periods per period (forced), in [1, 64].
    tol:
        Newton tolerance on the return's miss, relative to each state's scale (default ``STATE_TOL``).
    max_iter:
        Newton iterations before giving up (:class:`~.errors.ShootingError`).
    solver:
        The stiff solver of the runs (default ``Stiff(rtol=1e-10, atol=1e-12)``); its rtol is the flow's.
    """
    check_stateful(model, friction)
    if not (isinstance(returns, int) and 1 <= returns <= 64):
        raise ValueError(f"returns must be an integer in [1, 64], got {returns!r}")
    if transient < 0 or not math.isfinite(transient):
        raise ValueError(f"transient must be finite and >= 0, got {transient!r}")
    solver = solver if isinstance(solver, Stiff) else Stiff(rtol=1e-10, atol=1e-12)
    x, v = (float(u) for u in friction.start(model.vb, x0, v0))
    if model.forced:
        period = returns * model.forcing_period
        span = math.ceil(transient / period) * period
        y0 = np.concatenate([[x, v], friction.initial_state()])
        if span > 0:
            y0 = _end_state(simulate(model, friction, solver, t_end=span, x0=x, v0=v))
        smap = ShootingMap(StiffFlow(model, friction, rtol=solver.rtol), period)
        u0 = smap.unknowns(y0, period)
    else:
        traj = simulate(model, friction, solver, t_end=transient if transient > 0 else GUESS_SPAN, x0=x, v0=v)
        y0, period = section_guess(traj, transient > 0, returns)
        smap = ShootingMap(StiffFlow(model, friction, rtol=solver.rtol))
        u0 = smap.unknowns(y0, period)
    return orbit_of(smap, newton(smap, u0, STATE_TOL if tol is None else tol, max_iter), solver)


def _end_state(traj: Trajectory) -> np.ndarray:
    return np.concatenate([[traj.x[-1], traj.v[-1]], traj.internal[:, -1]])


def orbit_of(smap: ShootingMap, found: Newton, solver: Stiff) -> StatefulOrbit:
    """The :class:`StatefulOrbit` at a converged shooting; ShootingError if it is the sliding equilibrium."""
    y0, period = smap.state(found.u)
    flow = smap.flow
    traj = solver.solve_state(flow.model, flow.law, y0, period)
    orbit = StatefulOrbit(flow.model, flow.law, y0, period, found.end.jacobian, found.residual, found.iterations, traj)
    if not smap.forced and orbit.amplitude < 1e-9 * smap.scale[0]:
        raise ShootingError(f"shooting converged onto the sliding equilibrium X={y0[0]:.10g}: no periodic orbit here")
    return orbit


def fd_state_monodromy(orbit: StatefulOrbit, solver: Stiff | None = None, eps: float = 1e-6) -> np.ndarray:
    """The monodromy by central differences of one-period runs of the stiff solver from the perturbed state
    (step ``eps`` of each component's scale): a check on the variational equations."""
    solver = solver if isinstance(solver, Stiff) else Stiff(rtol=1e-12, atol=1e-14)
    law, model = orbit.friction, orbit.model
    scale = np.concatenate([[max(law.fs, abs(model.vb), 1e-12)] * 2, law.internal_scale()])
    cols = []
    for j, size in enumerate(scale):
        ends = []
        for sign in (1.0, -1.0):
            y = np.array(orbit.state, dtype=float)
            y[j] += sign * eps * size
            ends.append(_end_state(solver.solve_state(model, law, y, orbit.period)))
        cols.append((ends[0] - ends[1]) / (2.0 * eps * size))
    return np.column_stack(cols)
