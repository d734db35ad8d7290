"""The elasto-plastic law: true stiction (no drift below break-away), LuGre's sliding, scipy's Radau."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from frictionflow import BeltOscillator, simulate
from frictionflow.cli import main
from frictionflow.friction import ElastoPlastic, LuGre
from frictionflow.solvers import Stiff

from .test_lugre import CANUDAS, CANUDAS_MODEL, g

P = dict(fd=0.02, fs=0.03, vs=0.01, delta=2.0, sigma0=1e4, sigma1=100.0, sigma2=0.0, z_ba=1e-6)


def alpha(p, z, vr):
    """The plastic fraction of Dupont et al. (2002), written from its definition."""
    zss = g(p, vr) / p["sigma0"]
    if z * vr <= 0.0 or abs(z) <= p["z_ba"]:
        return 0.0
    if abs(z) >= zss:
        return 1.0
    return 0.5 * math.sin(math.pi * (abs(z) - 0.5 * (zss + p["z_ba"])) / (zss - p["z_ba"])) + 0.5


def rhs(p, zeta, vb):
    def f(t, y):
        x, v, z = y
        vr = vb - v
        zd = vr - alpha(p, z, vr) * abs(vr) * z * p["sigma0"] / g(p, vr)
        return [v, -x - 2.0 * zeta * v + p["sigma0"] * z + p["sigma1"] * zd + p["sigma2"] * vr, zd]
    return f


def _held(law):
    # a constant load (Omega tau stays ~1e-3 rad: the load changes by 1e-6 of itself) at half the break-away force
    model = BeltOscillator(zeta=0.5, vb=0.0, fex=0.5 * P["sigma0"] * P["z_ba"], omega=5e-7, phi=0.0)
    return simulate(model, law, Stiff(rtol=1e-10), t_end=2000.0, x0=0.0, v0=0.0)


def test_a_sub_break_away_load_is_held_without_drift():
    traj = _held(ElastoPlastic(**P))
    assert np.max(np.abs(traj.internal[0])) < P["z_ba"]  # elastic throughout
    # alpha = 0: z' = V_r = -X', so X + z keeps its initial value 0: no creep at all
    assert np.max(np.abs(traj.x + traj.internal[0])) < 1e-14
    # LuGre's bristles creep under the same load: X + z drifts
    lugre = _held(LuGre(**{k: v for k, v in P.items() if k != "z_ba"}))
    assert abs(lugre.x[-1] + lugre.internal[0, -1]) > 1e3 * np.max(np.abs(traj.x + traj.internal[0])) + 1e-12


def test_steady_sliding_friction_is_g_plus_viscous():
    p = {**P, "sigma2": 0.05}
    vb = 0.01
    traj = simulate(BeltOscillator(zeta=2.0, vb=vb), ElastoPlastic(**p), Stiff(rtol=1e-10), t_end=80.0, x0=0.0, v0=0.0)
    assert traj.fc[-1] == pytest.approx(g(p, vb) + p["sigma2"] * vb, rel=1e-7)


def test_stick_slip_against_scipy_radau():
    p = {**CANUDAS, "z_ba": 0.5 * CANUDAS["fd"] / CANUDAS["sigma0"]}
    t_end = 20.0
    traj = simulate(CANUDAS_MODEL, ElastoPlastic(**p), Stiff(rtol=1e-10, atol=1e-12), t_end=t_end, x0=0.0,
                    v0=CANUDAS_MODEL.vb)
    ref = solve_ivp(rhs(p, 0.0, CANUDAS_MODEL.vb), (0.0, t_end), [0.0, CANUDAS_MODEL.vb, 0.0], method="Radau",
                    rtol=1e-12, atol=[1e-13, 1e-13, 1e-18], dense_output=True)
    assert ref.success and np.any(traj.mode == 0)
    t = np.linspace(0.0, t_end, 4001)
    x, v = traj(t)
    assert np.max(np.abs(x - ref.sol(t)[0])) < 1e-6
    assert np.max(np.abs(v - ref.sol(t)[1])) < 1e-6
    bal = traj.interface_balance()
    assert abs(bal.residual) < 1e-8 * bal.belt


def test_a_break_away_deflection_beyond_the_steady_one_is_refused(capsys):
    with pytest.raises(ValueError, match=r"^z_ba must be in \(0, fd/sigma0 = 2e-06\) for friction=elastoplastic"):
        ElastoPlastic(**{**P, "z_ba": 3e-6})
    assert main(["simulate", "--friction", "elastoplastic", "--z-ba", "3e-6", "--t-end", "1"]) == 2
    assert len(capsys.readouterr().err.strip().splitlines()) == 1
