"""Dahl's law against its formulas written here and scipy's Radau."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from frictionflow import BeltOscillator, simulate
from frictionflow.cli import main
from frictionflow.friction import Dahl
from frictionflow.solvers import Stiff

P = dict(fd=0.05, sigma0=2e3, alpha=1.0)


def dahl_rhs(p, zeta, vb):
    """The belt oscillator with Dahl friction (X, X', z), written from the equations."""
    def rhs(t, y):
        x, v, z = y
        vr = vb - v
        u = 1.0 - p["sigma0"] * z * np.sign(vr) / p["fd"]
        zd = vr * abs(u) ** p["alpha"] * np.sign(u)
        return [v, -x - 2.0 * zeta * v + p["sigma0"] * z, zd]
    return rhs


def test_steady_sliding_friction_is_the_coulomb_level():
    law = Dahl(**P)
    traj = simulate(BeltOscillator(zeta=2.0, vb=0.02), law, Stiff(rtol=1e-10), t_end=150.0, x0=0.0, v0=0.0)
    assert traj.fc[-1] == pytest.approx(P["fd"], rel=1e-9)
    assert traj.x[-1] == pytest.approx(P["fd"], rel=1e-9)  # X* = F at rest


def test_with_alpha_two_the_force_saturates_algebraically():
    # u = 1 - sigma0 z / F_C obeys u' = -(sigma0 V_r / F_C) u^2: u = 1 / (1 + sigma0 V_r t / F_C) from rest
    law = Dahl(**{**P, "alpha": 2.0})
    vb, t_end = 0.02, 60.0
    traj = simulate(BeltOscillator(zeta=2.0, vb=vb), law, Stiff(rtol=1e-10), t_end=t_end, x0=0.0, v0=0.0)
    deficit = P["fd"] / (1.0 + P["sigma0"] * vb * t_end / P["fd"])
    assert P["fd"] - traj.fc[-1] == pytest.approx(deficit, rel=0.1)  # V_r = V_b but for the first time units


@pytest.mark.parametrize("alpha", [1.0, 2.0])
def test_a_transient_against_scipy_radau(alpha):
    p = {**P, "alpha": alpha}
    model = BeltOscillator(zeta=0.05, vb=0.01)
    t_end = 30.0
    traj = simulate(model, Dahl(**p), Stiff(rtol=1e-10, atol=1e-12), t_end=t_end, x0=0.2, v0=0.0)
    ref = solve_ivp(dahl_rhs(p, 0.05, 0.01), (0.0, t_end), [0.2, 0.0, 0.0], method="Radau", rtol=1e-12,
                    atol=[1e-13, 1e-13, 1e-17], dense_output=True)
    t = np.linspace(0.0, t_end, 3001)
    x, v = traj(t)
    assert np.max(np.abs(x - ref.sol(t)[0])) < 1e-7
    assert np.max(np.abs(v - ref.sol(t)[1])) < 1e-7
    bal = traj.interface_balance()
    assert abs(bal.residual) < 1e-8 * abs(bal.belt) + 1e-12


def test_from_rest_the_force_rises_with_the_rest_stiffness():
    # z' = V_r (1 - sigma0 z / F_C) from z = 0 at constant V_r: sigma0 z = F_C (1 - exp(-sigma0 V_r t / F_C))
    law = Dahl(**P)
    model = BeltOscillator(zeta=0.0, vb=1.0)  # the rise takes F_C / (sigma0 V_b) = 2.5e-5: the mass has no time to move
    traj = simulate(model, law, Stiff(rtol=1e-10), t_end=2e-4, x0=0.0, v0=0.0)
    rise = P["fd"] * (1.0 - np.exp(-P["sigma0"] * model.vb * traj.t / P["fd"]))
    assert np.max(np.abs(traj.fc - rise)) < 1e-3 * P["fd"]


@pytest.mark.parametrize("bad, message", [
    (dict(fd=0.0), r"^fd must be finite and in \(0, 1000\], got 0"),
    (dict(sigma0=-1.0), r"^sigma0 must be finite and in \(0, 1e\+12\], got -1"),
    (dict(alpha=0.5), r"^alpha must be finite and in \[1, 100\], got 0.5"),
])
def test_bad_parameters_are_refused_with_one_line(bad, message, capsys):
    with pytest.raises(ValueError, match=message):
        Dahl(**bad)
    args = ["simulate", "--friction", "dahl", "--t-end", "1"] + [a for k, v in bad.items() for a in (f"--{k}", str(v))]
    assert main(args) == 2
    assert len(capsys.readouterr().err.strip().splitlines()) == 1
