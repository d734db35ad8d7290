"""Flow maps of laws with Coulomb's stick rule and a smooth slip curve (Stribeck, user laws).

A slip phase in direction d = sgn(V_r) obeys

    X'' = d F(|V_r|) - X - 2 zeta X',    V_r = V_b - X'

which is integrated by :func:`scipy.integrate.solve_ivp` (DOP853) together
with its variational equations Phi' = A Phi,

    A = [[0, 1], [-1, -(2 zeta + F'(|V_r|))]]

(d/dX' of d F(d (V_b - X')) is -F'), with the switch V_r = 0 and the section
X' = 0 as events.  A stick phase (X' = V_b while |F_e| <= F_s) is a closed
form.  Coulomb's law fits here too (F constant), which gives an independent
check of the closed-form flow of :mod:`.flow_exact`.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np

from .._lazy import lazy_module
from ..core.friction import rest_mode, slip_magnitude_of, slip_slope_of, stick_duration
from ..friction.base import FrictionLaw
from ..params import BeltOscillator
from .hybrid import MAX_TIME, Phase, Segment, Switch, saltation

optimize = lazy_module("scipy.optimize")  # loaded on first use: importing the CLI stays quick
integrate = lazy_module("scipy.integrate")

SLIP_NAMES = {1: "slip+", -1: "slip-", 0: "stick"}
_MAX_ZERO_PHASES = 8


def slip_curve(law: FrictionLaw) -> tuple[Callable[[float], float], Callable[[float], float]]:
    """Scalar F(s) and F'(s) of the slip magnitude at relative speed s >= 0: the law's own functions."""
    if law.stick_rule != "switch":
        raise ValueError(f"friction={law.name} has no Coulomb stick rule with a slip curve (use the closed-form flow)")
    if not law.compiled_slip:  # a user's function
        return (lambda s: float(law.func(s))), (lambda s: float(law.slip_slope(max(s, 1e-12))))
    if law.magnitude is None:  # constant slip force
        fd = law.fd
        return (lambda s: fd), (lambda s: 0.0)
    if math.isinf(law.slip_slope(0.0)):
        raise ValueError(
            f"friction={law.name}: the slip curve has infinite slope at V_r = 0 (Stribeck delta < 1), "
            "where the variational equations (and Floquet multipliers) are not defined"
        )
    p = law.kernel_params()
    return (lambda s: slip_magnitude_of(p, s)), (lambda s: slip_slope_of(p, s))


class _Event:
    """An event function of solve_ivp: ``g(t, y)`` with the attributes solve_ivp reads."""

    def __init__(self, g: Callable[[float, np.ndarray], float], direction: float, terminal: bool = True) -> None:
        self.g, self.direction, self.terminal = g, direction, terminal

    def __call__(self, t: float, y: np.ndarray) -> float:
        return self.g(t, y)


class SmoothFlow:
    """Flow maps of one (model, law) whose slip force is a smooth function of |V_r|."""

    #: its cost per time unit flowed: a key of :data:`frictionflow.estimate.SECONDS_PER`
    time_cost = "smooth_flow_time"

    def __init__(self, model: BeltOscillator, law: FrictionLaw, rtol: float = 1e-11) -> None:
        self.F, self.dF = slip_curve(law)
        self.zeta, self.vb = float(model.zeta), float(model.vb)
        self.fs = float(law.fs)
        self.res = law.stick_force == "resultant"
        self.rtol = rtol
        scale = max(abs(self.fs), abs(self.vb), 1e-12)
        self.atol = np.array([rtol * scale, rtol * scale, rtol, rtol, rtol, rtol])
        self.f0 = self.F(0.0)

    # -- the stick rule -----------------------------------------------------
    def rest_mode(self, x: float) -> int:
        """At V_r = 0: 0 to stick, or the slip direction +-1 Coulomb's rule selects (the kernels' rule)."""
        return rest_mode(x, self.zeta, self.vb, self.fs, self.res, self.f0, 0.0, 0.0)

    def field(self, mode: int, x: float, v: float) -> np.ndarray:
        """The vector field (X', X'') of ``mode`` (+-1 slip, 0 stick) at (x, v)."""
        if mode == 0:
            return np.array([self.vb, 0.0])
        s = mode * (self.vb - v)
        return np.array([v, mode * self.F(abs(s)) - x - 2.0 * self.zeta * v])

    # -- phases ---------------------------------------------------------------
    def _slip(self, x: float, v: float, d: int, t_left: float, armed: bool, need: int):
        """Slip in direction d until V_r = 0, the ``need``-th section return, or ``t_left``.

        Returns (duration, x1, v1, Jacobian, how it ended, armed, returns counted).
        """
        zeta, vb, F, dF = self.zeta, self.vb, self.F, self.dF

        def rhs(t: float, y: np.ndarray) -> list[float]:
            s = abs(d * (vb - y[1]))
            k = -dF(s) - 2.0 * zeta  # d X'' / d X'
            return [y[1], d * F(s) - y[0] - 2.0 * zeta * y[1], y[4], y[5], -y[2] + k * y[4], -y[3] + k * y[5]]

        switch = _Event(lambda t, y: d * (vb - y[1]), -1.0)
        down = _Event(lambda t, y: y[1], -1.0)  # a maximum of X: the section
        up = _Event(lambda t, y: y[1], 1.0)  # a minimum of X: arms the section
        # extremes of X' (d X'' changes sign): checkpoints for crossings of V_b missed between steps
        extreme = _Event(lambda t, y: F(abs(d * (vb - y[1]))) - d * (y[0] + 2.0 * zeta * y[1]), 0.0, terminal=False)
        J = np.eye(2)
        T = 0.0
        count = 0
        while True:
            events = [switch] + ([(down if armed else up)] if need else []) + [extreme]
            y0 = [x, v, 1.0, 0.0, 0.0, 1.0]
            sol = integrate.solve_ivp(rhs, (0.0, t_left - T), y0, method="DOP853", rtol=self.rtol, atol=self.atol, events=events, dense_output=True)
            if sol.status < 0:
                raise RuntimeError(f"slip phase integration failed at X={x:.6g}, X'={v:.6g}: {sol.message}")
            t_c = self._missed_switch(sol, d)
            if t_c is not None:
                y = sol.sol(t_c)
                J = np.array([[y[2], y[3]], [y[4], y[5]]]) @ J
                return T + t_c, float(y[0]), vb, J, "switch", armed, count
            y = sol.y[:, -1]
            J = np.array([[y[2], y[3]], [y[4], y[5]]]) @ J
            T += float(sol.t[-1])
            x, v = float(y[0]), float(y[1])
            if sol.status == 0:
                return T, x, v, J, "time", armed, count
            if len(sol.t_events[0]):
                return T, x, vb, J, "switch", armed, count
            v = 0.0  # exactly on X' = 0
            if not armed:
                armed = True
                continue
            count += 1
            if count == need:
                return T, x, v, J, "section", armed, count
            armed = False  # the next maximum comes after the next minimum

    def _missed_switch(self, sol, d: int) -> float | None:
        """A crossing of V_r = 0 that solve_ivp stepped over, or None.

        solve_ivp compares event signs at step ends only, so a shallow
        crossing near grazing -- up through V_b and back inside one step --
        goes unseen.  An extreme of X' beyond V_b gives it away; the crossing
        is then located on the dense output between it and the extreme before.
        """
        vb = self.vb
        tol = 64 * np.finfo(float).eps * max(abs(vb), 1e-300)
        g_ext = d * (vb - sol.y_events[-1][:, 1]) if len(sol.t_events[-1]) else np.empty(0)
        beyond = np.nonzero(g_ext < -tol)[0]
        if not beyond.size:
            return None
        i = int(beyond[0])
        t_o = float(sol.t_events[-1][i])
        left = float(sol.t_events[-1][i - 1]) if i > 0 else 0.0

        def g(tau: float) -> float:
            return d * (vb - float(sol.sol(tau)[1]))

        if not g(left) > 0.0:
            return None
        return float(optimize.brentq(g, left, t_o, xtol=1e-15 * (1.0 + t_o), rtol=4 * np.finfo(float).eps))

    def _stick_time(self, x: float) -> float:
        """How long the mass sticks from X = x before |F_e| reaches F_s (inf: for good)."""
        return stick_duration(x, self.zeta, self.vb, self.fs, self.res)

    # -- the walk -------------------------------------------------------------
    def run(self, y0: tuple[float, float], *, duration: float = math.inf, returns: int = 0, max_time: float = MAX_TIME) -> Segment:
        """Flow from ``y0`` for ``duration``, or until the ``returns``-th crossing of the section."""
        x, v = float(y0[0]), float(y0[1])
        mode = self.rest_mode(x) if v == self.vb else (1 if self.vb > v else -1)
        seg = Segment(y0=np.array([x, v]), y1=np.empty(2), duration=0.0)
        horizon = min(duration, max_time)
        t = 0.0
        armed = v > 0.0
        zero_run = 0
        while True:
            if mode == 0:
                T = self._stick_time(x)
                if T < math.inf and self.rest_mode(x + self.vb * T) == 0:
                    T = math.inf  # |F_e| = F_s but no slip direction is consistent: the interface holds for good
                end = "switch"
                if t + T >= horizon:
                    T, end = horizon - t, "time"
                x1, v1, J = x + self.vb * T, self.vb, np.array([[1.0, T], [0.0, 1.0]])
                armed = armed or self.vb > 0.0
            else:
                T, x1, v1, J, end, armed, k = self._slip(x, v, mode, horizon - t, armed, returns - seg.returns)
                seg.returns += k
            seg.phases.append(Phase(SLIP_NAMES[mode], t, T, np.array([x, v]), np.array([x1, v1]), J))
            t += T
            if end != "switch":
                if end == "time" and returns and seg.returns < returns:
                    raise RuntimeError(f"no return to the section X' = 0 within tau = {max_time:g} (the motion settles or sticks for good)")
                seg.y1, seg.duration, seg.f_end = np.array([x1, v1]), t, self.field(mode, x1, v1)
                return seg
            zero_run = zero_run + 1 if T <= 1e-13 * (1.0 + t) else 0
            if zero_run > _MAX_ZERO_PHASES:
                raise RuntimeError(f"repeated zero-length phases at X={x1:.17g}, X'={v1:.17g}")
            new = self.rest_mode(x1)
            normal = np.array([1.0, 0.0]) if mode == 0 else np.array([0.0, 1.0])  # F_e = +-F_s, or X' = V_b
            f_before, f_after = self.field(mode, x1, v1), self.field(new, x1, v1)
            try:
                S = saltation(f_before, f_after, normal)
            except ZeroDivisionError:
                raise RuntimeError(f"a switch at X={x1:.17g}, X'={v1:.17g} is a tangential touch (grazing)") from None
            seg.switches.append(Switch(t, np.array([x1, v1]), SLIP_NAMES[mode], SLIP_NAMES[new], normal, f_before, f_after, S))
            x, v, mode = x1, v1, new
