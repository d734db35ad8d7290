"""Flow maps of smooth laws by the compiled DOP853 kernel, with parameter derivatives and work integrals.

:class:`CompiledFlow` is the engine :func:`~.flow.make_flow` picks for laws
with Coulomb's stick rule and a compiled slip curve (Stribeck, cubic; Coulomb
on request).  It runs :func:`frictionflow.core.flowmap.flow_map` and returns a
:class:`SensitiveSegment`: a :class:`~.hybrid.Segment` (phases, switches,
saltation matrices, as the solve_ivp engine of :mod:`.flow_smooth` builds)
that also carries

* ``M``: d y1 / d (X0, V0, lambda) at fixed time (2 x 3),
* the work integrals W_dv, W_fin and their derivatives (3 each),
* the smallest X at an upward zero of X' and its derivatives,

for the parameter ``param`` the flow was made for (None: no parameter column).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..core import flowmap as fm
from ..core import saltation as salt
from ..core.layout import LAW_A, LAW_B, LAW_C
from ..estimate import SECONDS_PER
from ..friction.base import FrictionLaw
from ..params import BeltOscillator
from .flow_smooth import SLIP_NAMES
from .hybrid import MAX_TIME, Phase, Segment, Switch

#: the oscillator's parameters with a column of their own
_MODEL_CODES = {"vb": fm.P_VB, "zeta": fm.P_ZETA}
_SLOT_CODES = {"fd": fm.P_FD, "fs": fm.P_FS}


def param_code(law: FrictionLaw, param: str | None) -> int | None:
    """The kernel's code for d/d``param`` (P_NONE for None; None: not differentiable in the kernel)."""
    if param is None:
        return fm.P_NONE
    if param in _MODEL_CODES:
        return _MODEL_CODES[param]
    own = {p.name for p in law.parameters}
    if param not in own:
        return None
    if param in _SLOT_CODES:
        return _SLOT_CODES[param]

    slot = getattr(law, "kernel_slots", {}).get(param)
    return {LAW_A: fm.P_A, LAW_B: fm.P_B, LAW_C: fm.P_C}.get(slot)


def supports(law: FrictionLaw) -> bool:
    """Can the compiled kernel run this law (a built-in compiled slip curve with Coulomb's stick rule)?"""
    return law.has_tangent_kernel


@dataclass(eq=False)
class SensitiveSegment(Segment):
    """A :class:`~.hybrid.Segment` with the parameter column, the work integrals and their derivatives."""

    M: np.ndarray | None = None  # d y1 / d (X0, V0, lambda) at fixed time
    W_dv: float = math.nan
    dW_dv: np.ndarray | None = None
    W_fin: float = math.nan
    dW_fin: np.ndarray | None = None
    x_min: float = math.nan
    dx_min: np.ndarray | None = None
    grazes: int = 0
    vr_min: float = math.inf  # the smallest V_r = d (V_b - X') at a maximum of d X' inside slip
    vr_x: float = math.nan  # X there
    dvr_min: np.ndarray | None = None  # its derivatives with respect to (X0, V0, lambda)

    def section_columns(self) -> np.ndarray:
        """d (X1, T) / d (X0, V0, lambda) when the end is the return to X' = 0 (2 x 3).

        A perturbed start returns dT = -dV1 / X''(end) earlier or later; X1
        moves by X' dT = 0 on the section.
        """
        a = float(self.f_end[1])
        fx = float(self.f_end[0])  # X' at the end: 0 on the section
        dX = self.M[0] - fx * self.M[1] / a if fx != 0.0 else self.M[0].copy()
        dT = -self.M[1] / a if a != 0.0 else np.full(3, np.nan)  # a tangential return: no return-time derivative
        return np.vstack([dX, dT])


#: steps a piece of the compiled flow may take (the step loop of :func:`frictionflow.core.flowmap.flow_map`)
FLOW_STEP_CAP = 1_000_000


def flow_seconds(law: FrictionLaw) -> float:
    """CPU seconds of a compiled flow over a cycle or two, for estimates; a law whose slip curve the steps cannot
    resolve (:meth:`FrictionLaw.resolvable`) is assumed to take two pieces to their step cap."""
    return SECONDS_PER["flow_run"] if law.resolvable() else 2 * FLOW_STEP_CAP * SECONDS_PER["flow_step"]


class CompiledFlow:
    """Flow maps of one (model, law), derivatives with respect to ``param`` included."""

    #: its cost per time unit flowed: a key of :data:`frictionflow.estimate.SECONDS_PER`
    time_cost = "compiled_flow_time"

    def __init__(self, model: BeltOscillator, law: FrictionLaw, param: str | None = None, rtol: float = 1e-11,
                 virtual: bool = False) -> None:
        if model.forced:
            raise ValueError("the compiled orbit engine is for the autonomous system (fex = 0)")
        if not supports(law):
            raise ValueError(f"friction={law.name} has no compiled slip curve with Coulomb's stick rule")
        if math.isinf(law.slip_slope(0.0)):
            raise ValueError(
                f"friction={law.name}: the slip curve has infinite slope at V_r = 0 (Stribeck delta < 1), "
                "where the variational equations (and Floquet multipliers) are not defined"
            )
        code = param_code(law, param)
        if code is None:
            raise ValueError(f"no compiled derivative with respect to {param!r} for friction={law.name}")
        self.model, self.law, self.param, self.code = model, law, param, code
        self.zeta, self.vb = float(model.zeta), float(model.vb)
        self.p = np.ascontiguousarray(law.kernel_params(), dtype=float)
        self.rtol = rtol
        self.virtual = virtual  # slip on through V_r = 0 (no switches): the smooth continuation past a touch
        self._ph = np.empty((64, fm.N_PH))
        self._sw = np.empty((64, fm.N_SW))
        self.tot = np.empty(fm.N_TOT)

    def raw(self, y0: tuple[float, float], *, duration: float = math.inf, returns: int = 0, max_time: float = MAX_TIME,
            quads: bool = True) -> int:
        """Run the kernel; the summary is left in ``self.tot`` (layout ``flowmap.T_*``); returns its status.

        ``quads`` False skips the work integrals (a quarter faster: Newton needs only the map).
        """
        horizon = min(duration, max_time)
        flow = fm.Flow(self.zeta, self.vb, self.p, self.code, self.rtol, self.virtual)
        while True:
            status = fm.flow_map(float(y0[0]), float(y0[1]), flow, int(returns), horizon, quads, self._ph, self._sw,
                                 self.tot)
            if status != fm.FULL:
                break
            n = 4 * self._ph.shape[0]
            if n > 1 << 20:
                break
            self._ph = np.empty((n, fm.N_PH))
            self._sw = np.empty((n, fm.N_SW))
        if status == fm.NO_RETURN and returns:
            raise RuntimeError(f"no return to the section X' = 0 within tau = {max_time:g} (the motion settles or sticks for good)")
        if status not in (fm.OK, fm.NO_RETURN):
            reason = {fm.FULL: "too many phases", fm.ZERO_PHASES: "repeated zero-length phases", fm.STEP_FAIL: "the step size collapsed",
                      fm.NOT_FINITE: "the state is not finite"}[status]
            raise RuntimeError(f"compiled flow from X={y0[0]:.17g}, X'={y0[1]:.17g} failed: {reason}")
        return status

    def run(self, y0: tuple[float, float], *, duration: float = math.inf, returns: int = 0, max_time: float = MAX_TIME) -> SensitiveSegment:
        """Flow from ``y0`` for ``duration``, or until the ``returns``-th crossing of the section."""
        self.raw(y0, duration=duration, returns=returns, max_time=max_time)
        return self.segment(y0)

    def segment(self, y0: tuple[float, float]) -> SensitiveSegment:
        """The :class:`SensitiveSegment` of the last :meth:`raw` run."""
        tot = self.tot
        nph, nsw = int(tot[fm.T_NPH]), int(tot[fm.T_NSW])
        phases = []
        for r in self._ph[:nph]:
            J = np.array([[r[7], r[8]], [r[9], r[10]]])
            phases.append(Phase(SLIP_NAMES[int(r[0])], float(r[1]), float(r[2]), r[3:5].copy(), r[5:7].copy(), J))
        switches = []
        for r in self._sw[:nsw]:
            n, fb, fa = r[5:7].copy(), r[7:9].copy(), r[9:11].copy()
            S = salt.matrix(fb, fa, n)
            switches.append(Switch(float(r[0]), r[1:3].copy(), SLIP_NAMES[int(r[3])], SLIP_NAMES[int(r[4])], n, fb, fa, S))
        M = np.array([[tot[fm.T_M00], tot[fm.T_M01], tot[fm.T_M02]], [tot[fm.T_M10], tot[fm.T_M11], tot[fm.T_M12]]])
        return SensitiveSegment(
            y0=np.array([float(y0[0]), float(y0[1])]),
            y1=np.array([tot[fm.T_X], tot[fm.T_V]]),
            duration=float(tot[fm.T_TIME]),
            phases=phases,
            switches=switches,
            returns=int(tot[fm.T_RET]),
            f_end=np.array([tot[fm.T_FX], tot[fm.T_FV]]),
            M=M,
            W_dv=float(tot[fm.T_WDV]),
            dW_dv=tot[fm.T_DWDV0:fm.T_DWDV2 + 1].copy(),
            W_fin=float(tot[fm.T_WFIN]),
            dW_fin=tot[fm.T_DWFIN0:fm.T_DWFIN2 + 1].copy(),
            x_min=float(tot[fm.T_XMIN]),
            dx_min=tot[fm.T_DXMIN0:fm.T_DXMIN2 + 1].copy(),
            grazes=int(tot[fm.T_GRAZE]),
            vr_min=float(tot[fm.T_VRMIN]),
            vr_x=float(tot[fm.T_VRX]),
            dvr_min=tot[fm.T_DVR0:fm.T_DVR2 + 1].copy(),
        )

    def poincare(self, x: float, returns: int = 1) -> tuple[float, float, float, float]:
        """(P(x), P'(x), dP/dlambda, period) of the section map from (x, 0), without building a segment."""
        self.raw((x, 0.0), returns=returns, quads=False)
        tot = self.tot
        a, fx = tot[fm.T_FV], tot[fm.T_FX]
        px = tot[fm.T_X]
        # on the section X' = 0 the end-time shift moves X by X' dT = 0
        dp = tot[fm.T_M00] - (fx * tot[fm.T_M10] / a if fx != 0.0 else 0.0)
        dl = tot[fm.T_M02] - (fx * tot[fm.T_M12] / a if fx != 0.0 else 0.0)
        return float(px), float(dp), float(dl), float(tot[fm.T_TIME])


def equilibrium_slope(model: BeltOscillator, law: FrictionLaw, param: str) -> float:
    """dX*/d``param`` of the sliding equilibrium X* = sgn(V_b) F(|V_b|) (exact; NaN without a kernel derivative)."""
    code = param_code(law, param)
    if code is None or model.vb == 0.0:
        return math.nan
    p = np.ascontiguousarray(law.kernel_params(), dtype=float)
    sgn = 1.0 if model.vb > 0 else -1.0
    _, Fp, Ft = fm.law_terms(p, abs(float(model.vb)), code)
    return float(Fp) if code == fm.P_VB else sgn * float(Ft)
