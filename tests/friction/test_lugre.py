"""LuGre (Canudas de Wit et al. 1995) against its own formulas written here, and scipy's Radau."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from frictionflow import BeltOscillator, simulate
from frictionflow.cli import main
from frictionflow.friction import LuGre
from frictionflow.solvers import Stiff

# the stick-slip example of Canudas de Wit et al. (1995): m = 1 kg, k = 2 N/m pulled at 0.1 m/s, F_C = 1 N,
# F_S = 1.5 N, v_s = 0.001 m/s, sigma0 = 1e5 N/m, sigma1 = sqrt(1e5) Ns/m, sigma2 = 0.4 Ns/m; non-dimensional with
# omega_0 = sqrt(k/m), l_0 = 1 m: forces / k, stiffnesses / k, damping-like sigma1, sigma2 * omega_0 / k,
# velocities / omega_0
W0 = math.sqrt(2.0)
CANUDAS = dict(fd=1.0 / 2, fs=1.5 / 2, vs=0.001 / W0, delta=2.0, sigma0=1e5 / 2, sigma1=math.sqrt(1e5) * W0 / 2,
               sigma2=0.4 * W0 / 2)
CANUDAS_MODEL = BeltOscillator(zeta=0.0, vb=0.1 / W0)


def g(p, vr):
    """g(V_r) of the law, from its definition."""
    return p["fd"] + (p["fs"] - p["fd"]) * np.exp(-np.abs(vr / p["vs"]) ** p["delta"])


def lugre_rhs(p, zeta, vb, fex=0.0, omega=0.0, phi=0.0):
    """The belt oscillator with LuGre friction as a first-order system (X, X', z), written from the equations."""
    def rhs(t, y):
        x, v, z = y
        vr = vb - v
        zd = vr - p["sigma0"] * abs(vr) * z / g(p, vr)
        f = p["sigma0"] * z + p["sigma1"] * zd + p["sigma2"] * vr
        return [v, -x - 2.0 * zeta * v + f + fex * math.cos(omega * t + phi), zd]
    return rhs


@pytest.mark.parametrize("vb", [0.003, 0.01, 0.05, 0.5])
def test_steady_sliding_friction_is_g_plus_viscous(vb):
    p = dict(fd=0.02, fs=0.04, vs=0.01, delta=2.0, sigma0=1e4, sigma1=100.0, sigma2=0.05)
    model = BeltOscillator(zeta=2.0, vb=vb)  # overdamped: the mass settles, sliding at V_r = V_b
    traj = simulate(model, LuGre(**p), Stiff(rtol=1e-10), t_end=80.0, x0=0.0, v0=0.0)
    expected = g(p, vb) + p["sigma2"] * vb
    assert traj.fc[-1] == pytest.approx(expected, rel=1e-7)
    assert traj.x[-1] == pytest.approx(expected, rel=1e-7)  # X* = F at rest
    assert LuGre(**p).slip_force(vb) == pytest.approx(expected, rel=1e-14)
    assert p["sigma0"] * traj.internal[0, -1] == pytest.approx(g(p, vb), rel=1e-7)  # bristles at sigma0 z = g


def _presliding(frac):
    """A run under f = F_ex sin(Omega tau), F_ex = ``frac`` F_S, slow (Omega = 0.02), the belt at rest."""
    p = dict(fd=0.02, fs=0.03, vs=0.01, delta=2.0, sigma0=1e4, sigma1=100.0, sigma2=0.0)
    model = BeltOscillator(zeta=0.5, vb=0.0, fex=frac * p["fs"], omega=0.02, phi=-math.pi / 2)
    period = 2.0 * math.pi / model.omega
    traj = simulate(model, LuGre(**p), Stiff(rtol=1e-8), t_end=2.0 * period, x0=0.0, v0=0.0)
    return p, model, period, traj, model.fex / (1.0 + p["sigma0"])  # the linear elastic amplitude


def test_presliding_under_a_small_force_is_linear_elastic():
    p, model, _, traj, amp = _presliding(0.01)
    # spring and bristles (stiffness 1 + sigma0) hold the force; the nonlinearity sigma0 |z| / g is 1 %
    assert np.max(np.abs(traj.x - model.external_force(traj.t) / (1.0 + p["sigma0"]))) < 0.03 * amp
    assert np.max(np.abs(traj.x + traj.internal[0])) < 0.03 * amp  # the bristles take up the whole motion


def test_presliding_below_break_away_returns_and_the_hysteresis_loop_closes():
    p, model, period, traj, amp = _presliding(0.8)
    assert np.max(np.abs(p["sigma0"] * traj.internal[0])) < p["fs"]  # never breaks away
    assert np.all(traj.mode == 0)
    t = np.linspace(0.0, period, 2001)
    x1, _ = traj(t)
    x2, _ = traj(t + period)
    # the loop X(f) of the second period retraces the first: no drift (a slip would leave an offset ~ amp)
    assert np.max(np.abs(x2 - x1)) < 1e-2 * amp
    assert abs(traj(period)[0]) < 1e-2 * amp and abs(traj.x[-1]) < 1e-2 * amp
    assert np.max(np.abs(traj.x)) > 1.5 * amp  # ... and the loop is not the linear line: the bristles yield


def test_canudas_stick_slip_against_scipy_radau():
    law = LuGre(**CANUDAS)
    t_end = 20.0  # two stick-slip cycles
    traj = simulate(CANUDAS_MODEL, law, Stiff(rtol=1e-10, atol=1e-12), t_end=t_end, x0=0.0, v0=CANUDAS_MODEL.vb)
    ref = solve_ivp(lugre_rhs(CANUDAS, 0.0, CANUDAS_MODEL.vb), (0.0, t_end), [0.0, CANUDAS_MODEL.vb, 0.0],
                    method="Radau", rtol=1e-12, atol=[1e-13, 1e-13, 1e-18], dense_output=True)
    assert ref.success
    assert np.any(traj.mode == 0) and np.any(traj.mode == 1)  # it sticks and slips
    t = np.linspace(0.0, t_end, 4001)  # between the steps: the dense output
    x, v = traj(t)
    y = ref.sol(t)
    assert np.max(np.abs(x - y[0])) < 1e-7
    assert np.max(np.abs(v - y[1])) < 1e-7
    zs = ref.sol(traj.t)[2]
    assert np.max(np.abs(CANUDAS["sigma0"] * (traj.internal[0] - zs))) < 1e-5  # the bristle force, to 1e-5 F_S


def test_energy_balance_with_storage_closes_to_the_tolerance():
    law = LuGre(**CANUDAS)
    for rtol in (1e-7, 1e-10):
        traj = simulate(CANUDAS_MODEL, law, Stiff(rtol=rtol), t_end=20.0, x0=0.0, v0=CANUDAS_MODEL.vb)
        bal = traj.interface_balance()
        assert abs(bal.residual) <= 10 * rtol * bal.belt
        # the stored energy is sigma0 z^2 / 2 of the bristles at the end
        assert bal.stored == pytest.approx(0.5 * CANUDAS["sigma0"] * traj.internal[0, -1] ** 2, rel=1e-12)
        # the mass's balance: Delta(K + U) = int X' F_c - int 2 zeta X'^2
        w = traj.work[-1]
        assert traj.energy[-1] - traj.energy[0] == pytest.approx(w[1] - w[2] - w[0], rel=10 * rtol, abs=10 * rtol)
    # while it sticks the contact stores F^2 / (2 sigma0): the bristles carry the force elastically
    i = np.flatnonzero(traj.mode == 0)[-1]
    assert traj.stored_energy[i] == pytest.approx(0.5 * CANUDAS["sigma0"] * traj.internal[0, i] ** 2)
    assert traj.stored_energy[i] > 0.0


@pytest.mark.parametrize("bad, message", [
    (dict(sigma0=0.0), r"^sigma0 must be finite and in \(0, 1e\+12\], got 0"),
    (dict(sigma1=-1.0), r"^sigma1 must be finite and in \[0, 1e\+12\], got -1"),
    (dict(sigma2=-1.0), r"^sigma2 must be"),
    (dict(delta=0.5), r"^delta must be finite and in \[1, 100\], got 0.5"),
    (dict(fd=0.0), r"^fd must be finite and in \(0, 1000\], got 0"),
    (dict(vs=0.0), r"^vs must be"),
    (dict(fd=0.03, fs=0.02), r"^fs must be >= fd"),
])
def test_bad_parameters_are_refused_with_one_line(bad, message, capsys):
    with pytest.raises(ValueError, match=message) as e:
        LuGre(**bad)
    assert "\n" not in str(e.value)
    args = ["simulate", "--friction", "lugre", "--t-end", "1"]
    for k, v in bad.items():
        args += [f"--{k.replace('_', '-')}", str(v)]
    assert main(args) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and err.split(": ", 1)[1].split(" ")[0] == next(iter(bad)) or "fs" in err
