"""Exact derivatives along a branch of cycles, and codimension-one points located by Newton.

Along a branch of fixed points X0(lambda) = P(X0, lambda) of the Poincare map
(compiled engine, :mod:`.flow_compiled`),

    dX0/dlambda = P_lambda / (1 - P'),

and every per-period quantity Q = W / T (W a work integral, T the period)
moves by

    dQ/dlambda = (dW/dlambda) / T - W (dT/dlambda) / T^2,
    dW/dlambda = W_X0 dX0/dlambda + W_lambda  (and the same for T),

with W_X0, W_lambda from the variational equations (saltation and switch
jump terms included).  So the slope of P_dv, P_fin, P_df = P_fin - P_dv,
R_c = P_dv / P_fin, R_f = P_df / P_fin, the period and the amplitude along the
branch is exact (:func:`orbit_derivatives`), and their extrema can be found as
roots.

Codimension-one points, located to rounding of the map (~1e-10 in lambda):

* :func:`locate_fold`: Newton on (P - X, P' - 1) in (X, lambda), second
  derivatives by central differences of the exact first ones;
* :func:`locate_grazing`: a slip-only cycle touching V_r = 0: Newton on
  (P - X, min V_r) with the flow *continued through* V_r = 0 (no switch),
  so both functions stay smooth across the touch; exact Jacobian;
* :func:`stick_slip_grazing`: the stick-slip cycle (whose section point is
  fixed by the slip onset, X = s F_s - 2 zeta V_b) whose first slip excursion
  touches V_r = 0: one scalar equation in lambda, exact slope.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..friction.base import FrictionLaw
from ..params import BeltOscillator
from .flow_compiled import CompiledFlow, SensitiveSegment
from .parameters import get_param, with_param

#: the monitors with exact slopes along a branch
EXACT_MONITORS = ("P_dv", "P_fin", "P_df", "R_c", "R_f", "period", "amplitude", "X")


@dataclass(frozen=True)
class OrbitDerivatives:
    """Per-period quantities of one cycle and their slopes d/dlambda along its branch."""

    param: str
    value: float
    values: dict[str, float]
    slopes: dict[str, float]


def _segment(model: BeltOscillator, law: FrictionLaw, param: str, x0: float, returns: int, virtual: bool = False) -> SensitiveSegment:
    return CompiledFlow(model, law, param=param, virtual=virtual).run((x0, 0.0), returns=returns)


def orbit_derivatives(model: BeltOscillator, law: FrictionLaw, param: str, x0: float, returns: int = 1) -> OrbitDerivatives:
    """Values and exact branch slopes of :data:`EXACT_MONITORS` for the cycle through (x0, 0)."""
    seg = _segment(model, law, param, x0, returns)
    cols = seg.section_columns()
    dp, dpl = float(cols[0, 0]), float(cols[0, 2])
    dx0 = dpl / (1.0 - dp)  # the fixed point's motion along the branch
    T = seg.duration
    dT = float(cols[1, 0] * dx0 + cols[1, 2])

    def avg(W: float, dW: np.ndarray) -> tuple[float, float]:
        dWl = float(dW[0] * dx0 + dW[2])
        return W / T, dWl / T - W * dT / T**2

    pdv, dpdv = avg(seg.W_dv, seg.dW_dv)
    pfin, dpfin = avg(seg.W_fin, seg.dW_fin)
    pdf, dpdf = pfin - pdv, dpfin - dpdv
    xmin, dxmin = seg.x_min, float(seg.dx_min[0] * dx0 + seg.dx_min[2])
    values = {"P_dv": pdv, "P_fin": pfin, "P_df": pdf, "R_c": pdv / pfin, "R_f": pdf / pfin, "period": T,
              "amplitude": 0.5 * (x0 - xmin), "X": x0}
    slopes = {"P_dv": dpdv, "P_fin": dpfin, "P_df": dpdf,
              "R_c": (dpdv * pfin - pdv * dpfin) / pfin**2, "R_f": (dpdf * pfin - pdf * dpfin) / pfin**2,
              "period": dT, "amplitude": 0.5 * (dx0 - dxmin), "X": dx0}
    return OrbitDerivatives(param, get_param(model, law, param), values, slopes)


# -- folds -------------------------------------------------------------------------------------
def _map(model, law, param, lam, x, returns, virtual=False):
    m, lw = with_param(model, law, param, lam)
    return CompiledFlow(m, lw, param=param, virtual=virtual).poincare(x, returns)


def locate_fold(model: BeltOscillator, law: FrictionLaw, param: str, x: float, lam: float, *, returns: int = 1,
                tol: float = 1e-13, max_iter: int = 30, virtual: bool = False) -> tuple[float, float]:
    """(X, lambda) of the fold of cycles near (x, lam): P = X and P' = 1, by Newton.

    ``virtual``: of the slip-only family continued through V_r = 0 (no sticking), past where it touches.
    """
    sx = max(law.fs, abs(model.vb), 1e-12)
    _map_ = lambda lam_, x_: _map(model, law, param, lam_, x_, returns, virtual)  # noqa: E731
    best = math.inf
    for _ in range(max_iter):
        px, dp, dpl, _ = _map_(lam, x)
        F = np.array([px - x, dp - 1.0])
        hx = 1e-6 * sx
        hl = 1e-6 * max(abs(lam), 1e-6)
        dpxx = (_map_(lam, x + hx)[1] - _map_(lam, x - hx)[1]) / (2 * hx)
        dpxl = (_map_(lam + hl, x)[1] - _map_(lam - hl, x)[1]) / (2 * hl)
        J = np.array([[dp - 1.0, dpl], [dpxx, dpxl]])
        step = np.linalg.solve(J, -F)
        x += float(step[0])
        lam += float(step[1])
        if abs(step[1]) <= tol * max(abs(lam), 1e-12) and abs(step[0]) <= 1e-12 * sx:
            return _a_cycle(model, law, param, (x, lam), returns, virtual)
        best = min(best, abs(step[1]) / max(abs(lam), 1e-12))
    if best <= 1e-10:  # steps stalled at the noise of the differenced second derivatives
        return _a_cycle(model, law, param, (x, lam), returns, virtual)
    raise RuntimeError(f"the fold did not converge near {param}={lam:.10g}")


#: a "fold" whose cycle is smaller than this, relative to max(F_s, |V_b|), is the Hopf point's vanishing cycle
VANISHING = 1e-6


def _a_cycle(model: BeltOscillator, law: FrictionLaw, param: str, fold: tuple[float, float], returns: int,
             virtual: bool) -> tuple[float, float]:
    """``fold`` = (X, lambda) if its cycle has an amplitude; RuntimeError at a Hopf point, where the vanishing cycle
    solves P = X, P' = 1 too (a fold curve followed in a second parameter landed there: a map drew the Hopf point
    as a fold)."""
    x, lam = fold
    m, lw = with_param(model, law, param, lam)
    seg = _segment(m, lw, param, x, returns, virtual)
    if 0.5 * (x - seg.x_min) <= VANISHING * max(law.fs, abs(model.vb), 1e-12):
        raise RuntimeError(f"the fold near {param}={lam:.10g} is the vanishing cycle of a Hopf point")
    return x, lam


# -- grazing -----------------------------------------------------------------------------------
def locate_grazing(model: BeltOscillator, law: FrictionLaw, param: str, x: float, lam: float, *, returns: int = 1,
                   max_iter: int = 30) -> tuple[float, float]:
    """(X, lambda) of the slip-only cycle near (x, lam) that touches V_r = 0: P = X and min V_r = 0, by Newton."""
    sx = max(law.fs, abs(model.vb), 1e-12)
    for _ in range(max_iter):
        m, lw = with_param(model, law, param, lam)
        seg = CompiledFlow(m, lw, param=param, virtual=True).run((x, 0.0), returns=returns)
        cols = seg.section_columns()
        F = np.array([seg.y1[0] - x, seg.vr_min])
        J = np.array([[cols[0, 0] - 1.0, cols[0, 2]], [seg.dvr_min[0], seg.dvr_min[2]]])
        step = np.linalg.solve(J, -F)
        x += float(step[0])
        lam += float(step[1])
        if abs(step[1]) <= 1e-13 * max(abs(lam), 1e-12) and abs(step[0]) <= 1e-12 * sx:
            return x, lam
    raise RuntimeError(f"the grazing cycle did not converge near {param}={lam:.10g}")


def onset_point(model: BeltOscillator, law: FrictionLaw) -> tuple[float, float]:
    """Where the mass leaves the stick phase: X = s F_s - 2 zeta V_b (resultant rule) or s F_s, X' = V_b (s = sgn V_b)."""
    s = 1.0 if model.vb > 0 else -1.0
    k = 2.0 * model.zeta * model.vb if law.stick_force == "resultant" else 0.0
    return s * law.fs - k, float(model.vb)


def stick_slip_margin(model: BeltOscillator, law: FrictionLaw, param: str) -> tuple[float, float]:
    """(g, dg/dlambda): the smallest V_r in the first slip excursion from the slip onset (continued through 0).

    g < 0: the excursion comes back to V_b and sticks again (a period-1 stick-slip cycle exists);
    g > 0: it does not.  g = 0 is the grazing of the stick-slip cycle.
    """
    x0, v0 = onset_point(model, law)
    seg = CompiledFlow(model, law, param=param, virtual=True).run((x0, v0), returns=2)
    s = 1.0 if model.vb > 0 else -1.0
    res = 2.0 if law.stick_force == "resultant" else 0.0
    dvb = 1.0 if param == "vb" else 0.0
    dz = 1.0 if param == "zeta" else 0.0
    dfs = 1.0 if param == "fs" else 0.0
    dx0 = s * dfs - res * (dz * model.vb + model.zeta * dvb)
    g = seg.vr_min
    dg = float(seg.dvr_min[0] * dx0 + seg.dvr_min[1] * dvb + seg.dvr_min[2])
    return g, dg


def stick_slip_grazing(model: BeltOscillator, law: FrictionLaw, param: str, lo: float, hi: float, *, tol: float = 1e-12) -> float:
    """lambda in [lo, hi] where the stick-slip cycle grazes (g changes sign there), by safeguarded Newton."""

    def g(lam: float) -> tuple[float, float]:
        return stick_slip_margin(*with_param(model, law, param, lam), param)

    ga, _ = g(lo)
    gb, _ = g(hi)
    if not ga * gb < 0:
        raise ValueError(f"the stick-slip margin does not change sign between {param}={lo:g} and {hi:g}")
    lam = 0.5 * (lo + hi)
    for _ in range(100):
        gm, dg = g(lam)
        if gm == 0.0:
            return lam
        if (gm < 0) == (ga < 0):
            lo, ga = lam, gm
        else:
            hi = lam
        nxt = lam - gm / dg if dg != 0 else math.nan
        if not (lo < nxt < hi):
            nxt = 0.5 * (lo + hi)
        if abs(nxt - lam) <= tol * max(abs(lam), 1e-12) or hi - lo <= tol * max(abs(lam), 1e-12):
            return nxt
        lam = nxt
    return lam
