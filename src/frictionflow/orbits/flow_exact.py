"""Flow maps of piecewise-constant laws (Karnopp, Coulomb), switch by switch in closed form.

The mode logic and the switch search are those of the exact solver
(:mod:`frictionflow.core.exact`); this module walks the same phases from a
given state and keeps what the solver throws away: each phase's Jacobian and
each switch's saltation matrix.  Inside a phase the motion is linear in the
start state (X'' + 2 zeta X' + X = F with F constant, or X'' = 0, or
X'' = -2 zeta X'), so the phase Jacobian is the closed-form motion of the
homogeneous equation started from the unit vectors.
"""

from __future__ import annotations

import math

import numpy as np

from ..core import closed_form as cf
from ..core import exact as ke
from ..core.friction import FD, FS, RESULTANT, VD
from ..friction.base import FrictionLaw
from ..modes import SwitchMode
from ..params import BeltOscillator
from ..solvers.events import EXACT_EVENT_MODES
from .hybrid import MAX_TIME, Phase, Segment, Switch, saltation

#: how phases and switches name each mode (orbit reports and JSON use these labels)
PHASE_LABELS = {
    SwitchMode.SLIP_POSITIVE: "slip+",
    SwitchMode.SLIP_NEGATIVE: "slip-",
    SwitchMode.STICK: "stick",
    SwitchMode.BAND_HOLD: "stick",  # Karnopp's band holding the mass
    SwitchMode.BAND_SATURATED_POSITIVE: "band-sat+",
    SwitchMode.BAND_SATURATED_NEGATIVE: "band-sat-",
    SwitchMode.BAND_EDGE_LOWER: "edge-lo",
    SwitchMode.BAND_EDGE_UPPER: "edge-hi",
}
#: the walk below runs on the exact kernel's codes; name them through the solver's own table
MODE_NAMES = {code: PHASE_LABELS[mode] for code, mode in EXACT_EVENT_MODES.items()}
#: phases shorter than this many rounding units in a row mean the mode logic is stuck
_MAX_ZERO_PHASES = 8


def phase_jacobian(dyn: int, zeta: float, t: float) -> np.ndarray:
    """d(X, X')(t) / d(X0, X0') of one phase of motion type ``dyn``: the homogeneous motion from e1, e2."""
    x1, v1, _ = cf.state(dyn, zeta, 0.0, 1.0, 0.0, t)
    x2, v2, _ = cf.state(dyn, zeta, 0.0, 0.0, 1.0, t)
    return np.array([[x1, x2], [v1, v2]])


class ExactFlow:
    """Flow maps of one (model, law) with piecewise-constant friction."""

    #: its cost per time unit flowed: a key of :data:`frictionflow.estimate.SECONDS_PER`
    time_cost = "exact_flow_time"

    def __init__(self, model: BeltOscillator, law: FrictionLaw) -> None:
        if not law.piecewise_constant:
            raise ValueError(f"the closed-form flow needs a piecewise-constant law, got {law.name}")
        p = law.kernel_params()
        self.law = int(ke.closed_form_law(p))
        self.fd, self.fs, self.vd = float(p[FD]), float(p[FS]), float(p[VD])
        self.res = bool(p[RESULTANT] != 0.0)
        self.zeta, self.vb = float(model.zeta), float(model.vb)
        self._ev = np.empty((ke.MAX_EVENTS_PER_MODE, 4))
        self._lw = ke.law_record(self.law, self.fd, self.fs, self.vd, self.res)
        self._crit = np.empty(64)

    # -- the pieces ---------------------------------------------------------
    def _mode_at(self, x: float, v: float) -> int:
        m = ke.select_mode(self._lw, self.zeta, self.vb, x, v)
        if m < 0:  # no mode is consistent for a positive time: fall back on the region, as the solver does
            m = ke.region_mode(self.law, self.zeta, self.vb, self.fd, self.fs, self.vd, self.res, x, v)
        return int(m)

    def field(self, mode: int, x: float, v: float) -> np.ndarray:
        """The vector field (X', X'') of ``mode`` at (x, v)."""
        dyn, force, _ = ke.dynamics(mode, self.zeta, self.fd, self.fs, self.res)
        _, _, a = cf.state(dyn, self.zeta, force, x, v, 0.0)
        return np.array([v, a])

    def _section_time(self, dyn: int, force: float, x: float, v: float, T: float, armed: bool, need: int) -> tuple[float, bool, int]:
        """The ``need``-th downward zero of X' in (0, T) of this phase, if any.

        A downward zero (a maximum of X) counts only once X' has been
        positive since the start ("armed"): a start on the section itself is
        not a return.  Returns (time or inf, armed, downward zeros counted).
        """
        if dyn != cf.OSC:  # X' constant or decaying without a sign change
            return math.inf, armed or v > 0.0, 0
        count = 0
        t_from = 0.0
        while True:
            m = cf.critical_points(cf.coefficients(dyn, self.zeta, force, x, v), dyn, 1.0, 0.0, t_from, T, self._crit)
            for i in range(m):
                tc = float(self._crit[i])
                _, _, acc = cf.state(dyn, self.zeta, force, x, v, tc)
                if acc > 0.0:
                    armed = True
                elif acc < 0.0 and armed:
                    count += 1
                    if count == need:
                        return tc, armed, count
            if m < len(self._crit):
                return math.inf, armed, count
            t_from = float(self._crit[m - 1])

    # -- the walk -----------------------------------------------------------
    def run(self, y0: tuple[float, float], *, duration: float = math.inf, returns: int = 0, max_time: float = MAX_TIME) -> Segment:
        """Flow from ``y0`` for ``duration``, or until the ``returns``-th crossing of the section.

        Raises RuntimeError when neither happens before ``max_time``.
        """
        x, v = float(y0[0]), float(y0[1])
        mode = self._mode_at(x, v)
        if mode == ke.STICK:
            v = self.vb
        seg = Segment(y0=np.array([float(y0[0]), float(y0[1])]), y1=np.empty(2), duration=0.0)
        t = 0.0
        armed = v > 0.0
        zero_run = 0
        horizon = min(duration, max_time)
        while True:
            dyn, force, _ = ke.dynamics(mode, self.zeta, self.fd, self.fs, self.res)
            n_ev = ke.boundaries(mode, self.law, self.zeta, self.vb, self.fd, self.fs, self.vd, self.res, self._ev)
            tau, which, _never = ke.next_event(dyn, self.zeta, force, x, v, self._ev, n_ev, horizon - t, self._crit)
            T = float(tau) if which >= 0 else horizon - t
            normal = self._ev[which, :2].copy() if which >= 0 else None
            if which >= 0 and dyn == cf.LIN:
                # X moves linearly: the crossing of a X + b X' = c is explicit.  (The kernel's
                # bracketed search can be ~1e-12 late here when the horizon is long.)
                a, b, c, _ = self._ev[which]
                if a * v != 0.0:
                    T = max(0.0, float((c - a * x - b * v) / (a * v)))
            on_section = False
            if returns:
                ts, armed, k = self._section_time(dyn, force, x, v, T, armed, returns - seg.returns)
                if ts < math.inf:
                    T, on_section = ts, True
                else:
                    seg.returns += k
            x1, v1, _ = cf.state(dyn, self.zeta, force, x, v, T)
            if on_section:
                v1 = 0.0  # exactly on the section
                seg.returns = returns
            seg.phases.append(Phase(MODE_NAMES[mode], t, T, np.array([x, v]), np.array([x1, v1]), phase_jacobian(dyn, self.zeta, T)))
            t += T
            if on_section or which < 0:
                if not on_section and returns and t >= max_time:
                    raise RuntimeError(f"no return to the section X' = 0 within tau = {max_time:g} (the motion settles or sticks for good)")
                seg.y1, seg.duration = np.array([x1, v1]), t
                seg.f_end = self.field(mode, x1, v1)
                return seg
            # the switch: which mode continues, and how perturbations jump
            zero_run = zero_run + 1 if T <= 4.0 * ke.EPS * (1.0 + t) else 0
            if zero_run > _MAX_ZERO_PHASES:
                raise RuntimeError(f"repeated zero-length phases at X={x1:.17g}, X'={v1:.17g}")
            f_before = self.field(mode, x1, v1)
            new = self._mode_at(x1, v1)
            if new == ke.STICK:
                v1 = self.vb
            f_after = self.field(new, x1, v1)
            if new == ke.STICK:
                f_after[0] = self.vb
            try:
                S = saltation(f_before, f_after, normal)
            except ZeroDivisionError:
                raise RuntimeError(f"a switch at X={x1:.17g}, X'={v1:.17g} is a tangential touch (grazing)") from None
            seg.switches.append(Switch(t, np.array([x1, v1]), MODE_NAMES[mode], MODE_NAMES[new], normal, f_before, f_after, S))
            x, v, mode = x1, v1, new
            armed = armed or v > 0.0
