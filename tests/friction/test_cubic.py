"""The cubic law F = sgn(V_r)(mu_s - k1 |V_r| + k3 |V_r|^3) end to end: formula, Hopf point, stick-slip onset.

Closed forms derived here: the minimum of the curve at v_m = sqrt(k1 / (3 k3));
steady sliding X* = F(V_b) loses stability where 2 zeta + F'(V_b) = 0, i.e.
V_b,H = sqrt((k1 - 2 zeta) / (3 k3)), with linear frequency 1 there (period 2 pi).
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from scipy.optimize import minimize_scalar

from frictionflow import RK4, Adaptive, BeltOscillator, analyze, simulate
from frictionflow.cli import main
from frictionflow.friction import Cubic
from frictionflow.orbits import continuation, find_orbit

MU, K1, K3, ZETA = 0.04, 0.3, 10.0, 0.05
LAW = Cubic(MU, K1, K3)
VB_HOPF = math.sqrt((K1 - 2 * ZETA) / (3 * K3))


def F(s):
    return MU - K1 * s + K3 * s**3


def test_slip_force_slope_and_kinetic_level_follow_the_formula():
    s = np.linspace(0.0, 0.3, 31)
    assert LAW.slip_magnitude(s) == pytest.approx(F(s), rel=1e-14, abs=1e-16)
    assert LAW.slip_force(-0.05) == pytest.approx(-F(0.05), rel=1e-14)
    for v in (0.01, 0.1, 0.2):
        h = 1e-6
        assert LAW.slip_slope(v) == pytest.approx((F(v + h) - F(v - h)) / (2 * h), rel=1e-7, abs=1e-9)
    m = minimize_scalar(F, bounds=(0.0, 1.0), method="bounded", options={"xatol": 1e-12})
    assert LAW.fd == pytest.approx(m.fun, rel=1e-9)
    assert LAW.sliding_equilibrium(0.05) == pytest.approx(F(0.05), rel=1e-14)


def test_a_slip_force_that_would_turn_negative_is_refused():
    with pytest.raises(ValueError, match="k1 must be <="):
        Cubic(0.01, 0.3, 10.0)  # F_min = 0.01 - 0.02 < 0
    with pytest.raises(ValueError, match="k3"):
        Cubic(0.04, 0.3, 0.0)


def test_hopf_point_of_continuation_agrees_with_2zeta_plus_slope_zero():
    res = continuation(BeltOscillator(zeta=ZETA, vb=0.09), LAW, "vb", 0.09, 0.06, seeds=("hopf",), n_equilibria=21, transient=300)
    hopf = [b for b in res.bifurcations if b.type == "hopf"]
    assert len(hopf) == 1 and hopf[0].value == pytest.approx(VB_HOPF, rel=1e-10)
    cycles = [b for b in res.branches if b.points and b.points[0].kind == "periodic"]
    first = cycles[0].points[0]  # born at the Hopf point with the linear frequency 1
    assert first.period == pytest.approx(2 * math.pi, abs=5e-3) and first.amplitude < 5e-3


@pytest.mark.parametrize("side, grows", [(-0.01, True), (+0.01, False)])
def test_simulation_grows_or_decays_on_either_side_of_the_hopf_damping(side, grows):
    zeta_h = LAW.hopf_damping(0.05)
    assert zeta_h == pytest.approx((K1 - 3 * K3 * 0.05**2) / 2, rel=1e-14)
    x_star = F(0.05)
    tr = simulate(BeltOscillator(zeta=zeta_h + side, vb=0.05), LAW, t_end=200.0, x0=x_star + 1e-4, v0=0.0)
    late = np.abs(tr.x[tr.t > 150.0] - x_star).max()
    # the linearisation grows or decays at rate |side|: e^{0.01 * 150} ~ 4.5
    assert (late > 2e-4) if grows else (late < 0.5e-4)


def test_stick_slip_onset_of_continuation_agrees_with_simulation():
    res = continuation(BeltOscillator(zeta=ZETA, vb=0.09), LAW, "vb", 0.09, 0.05, seeds=("hopf",), n_equilibria=21, transient=300)
    graze = [b for b in res.bifurcations if b.type == "grazing"]
    assert len(graze) == 1 and graze[0].detail["stick_phase"] == "appears"
    vg = graze[0].value
    assert vg < VB_HOPF
    below = analyze(simulate(BeltOscillator(ZETA, 0.98 * vg), LAW, t_end=800.0))
    above = analyze(simulate(BeltOscillator(ZETA, 1.02 * vg), LAW, t_end=800.0))
    assert below.steady_state.kind == above.steady_state.kind == "periodic"
    assert below.steady_state.stick_fraction > 0.005
    assert above.steady_state.stick_fraction == 0.0


def test_rk4_and_adaptive_agree_on_the_stick_slip_cycle():
    model = BeltOscillator(ZETA, 0.04)
    a = analyze(simulate(model, LAW, Adaptive(), t_end=400.0))
    r = analyze(simulate(model, LAW, RK4(dt=2e-4), t_end=400.0))
    assert a.steady_state.kind == "periodic" and abs(a.energy_residual) < 1e-7
    assert r.steady_state.period == pytest.approx(a.steady_state.period, rel=1e-3)
    assert r.power.P_fin == pytest.approx(a.power.P_fin, rel=2e-2)


def test_orbit_of_the_cubic_law_is_a_periodic_stick_slip_cycle():
    found = find_orbit(BeltOscillator(ZETA, 0.04), LAW, transient=300.0)
    ref = analyze(simulate(BeltOscillator(ZETA, 0.04), LAW, t_end=400.0))
    assert found.period == pytest.approx(ref.steady_state.period, rel=1e-6)
    assert found.stable


def test_cli_simulate_orbit_continue_and_sweep_run_the_cubic_law(capsys, tmp_path):
    args = ["--friction", "cubic", "--fs", "0.04", "--k1", "0.3", "--k3", "10", "--zeta", "0.05", "--vb", "0.04"]
    assert main(["simulate", *args, "--t-end", "300", "--json"]) == 0
    d = json.loads(capsys.readouterr().out)
    assert d["params"]["friction"] == "cubic" and d["params"]["k1"] == 0.3 and d["steady_state"]["kind"] == "periodic"
    assert main(["orbit", *args, "--t-end", "300", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["stable"] is True
    fixed = [a for i, a in enumerate(args) if "--k1" not in args[max(i - 1, 0):i + 1]]  # continue sets k1 itself
    assert main(["continue", *fixed, "--param", "k1", "--from", "0.3", "--to", "0.2", "--points", "5",
                 "--seeds", "start", "--max-points", "20", "--t-end", "200", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["branches"]
    cfg = tmp_path / "s.toml"
    cfg.write_text('friction = "cubic"\nzeta = 0.05\nt_end = 200.0\n[grid]\nk1 = [0.2, 0.3]\nvb = [0.04, 0.12]\n')
    assert main(["sweep", str(cfg), "--out", str(tmp_path / "r.nc")]) == 0
    import xarray as xr

    ds = xr.open_dataset(tmp_path / "r.nc")
    assert ds["kind"].shape == (2, 2) and np.isfinite(ds["P_fin"]).all()
    assert ds["k1"].attrs["long_name"].startswith("cubic")


def test_fd_is_not_a_parameter_of_the_cubic_law(capsys):
    assert main(["simulate", "--friction", "cubic", "--fd", "0.02"]) == 2
    assert "fd is not a parameter of friction=cubic" in capsys.readouterr().err
