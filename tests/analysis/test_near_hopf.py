"""Just above a supercritical Hopf point: the slow spiral onto the sliding equilibrium.

Stribeck F(v) = F_d + (F_s - F_d) exp(-(v / v_s)^2) at V_b = v_s: zeta_H = -F'(V_b) / 2 = (F_s - F_d) / (v_s e)
= 0.735759; l1 ~ -F''' / 16 < 0 there, so no cycle exists for zeta > zeta_H and X* = F(V_b) attracts.  The
equilibrium's certified disc (where 2 zeta + s(u) > 0 for every secant s) shrinks to 0 at zeta_H; a grid of
512 steps over V_b missed it below about 4e-5, so a run deep inside it stayed ``not_settled``; and the
amplitude's Aitken limit over three records named a limit cycle of a few % of the amplitude (the cubic damping's
bias) as the heading.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from frictionflow import BeltOscillator, Stribeck, analyze, simulate
from frictionflow.core.certificate import certified_radius
from frictionflow.solvers.base import kernel_params

FD, FS, VS, VB = 0.02, 0.04, 0.01, 0.01
LAW = Stribeck(fd=FD, fs=FS, vs=VS)
ZETA_H = (FS - FD) / (VS * math.e)


def _force(v):
    return FD + (FS - FD) * np.exp(-(v / VS) ** 2)


def _true_radius(zeta: float) -> float:
    """The smallest |u| where 2 zeta + (F(V_b) - F(V_b - u)) / u <= 0, on a grid of 4e5 points."""
    u = np.concatenate([np.linspace(-0.0099, -1e-10, 200001), np.linspace(1e-10, 0.0099, 200001)])
    bad = np.abs(u[2 * zeta + (_force(VB) - _force(VB - u)) / u <= 0.0])
    return float(bad.min()) if bad.size else VB


@pytest.mark.parametrize("zeta", [0.7359, 0.7365, 0.738, 0.75])
def test_certified_radius_near_the_hopf_point(zeta):
    true = _true_radius(zeta)
    r = certified_radius(kernel_params(BeltOscillator(zeta=zeta, vb=VB), LAW), zeta, VB)
    assert 0.6 * true <= r <= true  # 0 below zeta = 0.738 before


def test_a_run_inside_the_disc_is_the_equilibrium_and_a_slow_decay_names_no_cycle():
    model = BeltOscillator(zeta=0.7365, vb=VB)
    assert model.zeta > ZETA_H
    long = analyze(simulate(model, LAW, t_end=8000.0, x0=0.0284, v0=0.0)).steady_state
    assert long.kind == "equilibrium" and long.limit["x"] == pytest.approx(float(_force(VB)), abs=1e-8)
    for t_end in (500.0, 2000.0):
        ss = analyze(simulate(model, LAW, t_end=t_end, x0=0.0284, v0=0.0)).steady_state
        assert ss.kind == "not_settled" and ss.decay_rate > 0.0
        assert ss.heading != "periodic"  # no cycle exists beyond a supercritical Hopf point
