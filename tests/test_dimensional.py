"""Dimensional input for every parameter with a dimension: the same runs as their non-dimensional values.

The conversions are derived here from the model: m x'' + c x' + k x = f with omega0 = sqrt(k/m), tau = omega0 t,
X = x / l_0.  Then F = f / (k l_0) for a force, z / l_0 for a length, v / (omega0 l_0) for a velocity; a
bristle stiffness s0 (f = s0 z) gives F = (s0 / k) Z, a damping-like s1 (f = s1 v) gives
F = s1 omega0 l_0 V / (k l_0) = (s1 omega0 / k) V; a frequency w gives w / omega0 (per unit of tau).
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from frictionflow import BeltOscillator, DimensionalParams, simulate
from frictionflow.cli import main
from frictionflow.config import RunConfig
from frictionflow.friction import ElastoPlastic, LuGre, RateState
from frictionflow.solvers import Stiff
from frictionflow.sweep.compute import compute_chunk
from frictionflow.sweep.config import parse_sweep

M, C, K, L0 = 2.0, 0.4, 8.0, 0.5
W0 = math.sqrt(K / M)  # 2
SCALES = {"m": M, "c": C, "k": K, "l_0": L0}
ZETA = C / (2.0 * M * W0)


def _force(f):
    return f / (K * L0)


def _speed(v):
    return v / (W0 * L0)


LUGRE_DIM = {"v_b": 0.04, "f_d": 0.08, "f_ms": 0.16, "vs": 0.02, "sigma0": 800.0, "sigma1": 20.0, "sigma2": 0.4}
LUGRE_ND = {"vb": _speed(0.04), "fd": _force(0.08), "fs": _force(0.16), "vs": _speed(0.02), "sigma0": 800.0 / K,
            "sigma1": 20.0 * W0 / K, "sigma2": 0.4 * W0 / K}


def test_api_converts_every_dimension_by_hand():
    d = DimensionalParams(m=M, c=C, k=K, v_b=0.04, l_0=L0, v_b_amp=0.01, w_b=3.0, phi_b=0.3,
                          law={"sigma0": 800.0, "sigma1": 20.0, "z_ba": 1e-4, "dc": 0.002, "normal": 4.0, "vref": 0.1})
    nd = d.nondimensional()
    expect = {"zeta": ZETA, "vb": _speed(0.04), "vb_amplitude": _speed(0.01), "vb_omega": 3.0 / W0, "vb_phi": 0.3,
              "sigma0": 800.0 / K, "sigma1": 20.0 * W0 / K, "z_ba": 1e-4 / L0, "dc": 0.002 / L0, "normal": _force(4.0),
              "vref": _speed(0.1)}
    for key, want in expect.items():
        assert nd[key] == pytest.approx(want, rel=1e-15), key
    assert "fd" not in nd  # no F_d given: the law keeps its own


def test_a_dimensional_lugre_run_is_the_nondimensional_run():
    cfg = RunConfig.from_mapping({"friction": "lugre", "solver": "stiff", "dimensional": {**SCALES, **LUGRE_DIM}})
    model, law, _ = cfg.build()
    assert model.zeta == pytest.approx(ZETA, rel=1e-15)
    for key, want in LUGRE_ND.items():
        value = model.vb if key == "vb" else getattr(law, key)
        assert value == pytest.approx(want, rel=1e-15), key
    hand_model = BeltOscillator(zeta=ZETA, vb=LUGRE_ND["vb"])
    hand_law = LuGre(**{k: v for k, v in LUGRE_ND.items() if k != "vb"})
    a = simulate(model, law, Stiff(rtol=1e-9), t_end=40.0, x0=0.0, v0=0.0)
    b = simulate(hand_model, hand_law, Stiff(rtol=1e-9), t_end=40.0, x0=0.0, v0=0.0)
    t = np.linspace(0.0, 40.0, 401)
    assert np.max(np.abs(a(t)[0] - b(t)[0])) < 1e-10


def test_rate_state_and_elastoplastic_lengths_forces_and_velocities():
    table = {**SCALES, "v_b": 0.04, "normal": 4.0, "dc": 0.002, "vref": 0.02}
    _, law, _ = RunConfig.from_mapping({"friction": "rate_state", "dimensional": table, "mu0": 0.5, "a": 0.02,
                                        "b": 0.03, "state_law": "slip"}).build()
    hand = RateState(normal=_force(4.0), mu0=0.5, a=0.02, b=0.03, dc=0.002 / L0, vref=_speed(0.02), state_law="slip")
    assert law.state_law == "slip" and (law.mu0, law.a, law.b) == (0.5, 0.02, 0.03)
    assert (law.normal, law.dc, law.vref) == pytest.approx((hand.normal, hand.dc, hand.vref), rel=1e-15)
    table = {**SCALES, "v_b": 0.04, "f_d": 0.08, "sigma0": 800.0, "z_ba": 1e-5}
    _, law, _ = RunConfig.from_mapping({"friction": "elastoplastic", "dimensional": table}).build()
    assert isinstance(law, ElastoPlastic)
    assert (law.fd, law.sigma0, law.z_ba) == pytest.approx((_force(0.08), 800.0 / K, 1e-5 / L0), rel=1e-15)


def test_belt_variation_keys_set_the_model():
    table = {**SCALES, "v_b": 0.04, "f_d": 0.08, "v_b_amp": 0.01, "w_b": 3.0, "phi_b": 0.3}
    model = RunConfig.from_mapping({"friction": "coulomb", "dimensional": table}).build()[0]
    assert (model.vb_amplitude, model.vb_omega, model.vb_phi) == pytest.approx((_speed(0.01), 3.0 / W0, 0.3), rel=1e-15)


def _cli_json(capsys, args):
    code = main(["simulate", "--json", "--t-end", "30", *args])
    out, err = capsys.readouterr()
    assert code == 0, err
    return json.loads(out)


def test_cli_dimensional_lugre_equals_the_nondimensional_options(capsys):
    text = ",".join(f"{k}={v!r}" for k, v in {**SCALES, **LUGRE_DIM}.items())
    dim = _cli_json(capsys, ["--friction", "lugre", "--solver", "stiff", "--dimensional", text])
    nd_args = [a for k, v in {"zeta": ZETA, **LUGRE_ND}.items() for a in (f"--{k}", repr(v))]
    nd = _cli_json(capsys, ["--friction", "lugre", "--solver", "stiff", *nd_args])
    for key in ("zeta", *LUGRE_ND):
        assert dim["params"][key] == pytest.approx(nd["params"][key], rel=1e-15), key
    assert dim["dimensional"]["omega0"] == pytest.approx(W0)
    for key in ("P_fin", "P_belt", "P_heat"):
        assert dim["averages"][key] == pytest.approx(nd["averages"][key], rel=1e-9), key


@pytest.mark.parametrize("law", ["karnopp", "coulomb", "stribeck", "lugre"])
def test_an_unset_static_force_is_the_law_s_own_default_as_without_dimensions(capsys, law):
    """Without f_ms the law's default F_s: F_d for Karnopp and Coulomb, 2 F_d for Stribeck (f_ms once defaulted to
    f_d for every law, so a dimensional Stribeck run had F_s = F_d and settled where the same point ran periodic)."""
    text = ",".join(f"{k}={v!r}" for k, v in {**SCALES, "v_b": 0.04, "f_d": 0.08}.items())
    dim = _cli_json(capsys, ["--friction", law, "--t-end", "50", "--dimensional", text])
    nd = _cli_json(capsys, ["--friction", law, "--t-end", "50", "--zeta", repr(ZETA), "--vb", repr(_speed(0.04)),
                            "--fd", repr(_force(0.08))])
    assert dim["params"]["fs"] == pytest.approx(nd["params"]["fs"], rel=1e-15)
    assert dim["params"]["fs"] == pytest.approx((2.0 if law == "stribeck" else 1.0) * dim["params"]["fd"], rel=1e-15)


@pytest.mark.parametrize("args, message", [
    (["--friction", "lugre", "--sigma0", "100"], "give sigma0 or dimensional, not both"),
    (["--friction", "lugre", "--vb", "0.01"], "give vb or dimensional, not both"),
    (["--friction", "rate_state", "--dc", "0.01"], "give dc or dimensional, not both"),
])
def test_mixing_nondimensional_and_dimensional_values_is_refused(args, message, capsys):
    code = main(["simulate", "--t-end", "1", "--dimensional", "m=1,c=0.1,k=4,v_b=0.02,f_d=0.08", *args])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and len(err) == 1 and message in err[0]


@pytest.mark.parametrize("table, message", [
    ("m=1,c=0.1,k=4,v_b=0.02,f_d=0.08,sigma0=-5", "sigma0 must be"),
    ("m=1,c=0.1,k=4,v_b=0.02,f_d=0.08,dc=1", "dc sets dc, not a parameter of friction=lugre"),
    ("m=1,c=0.1,k=4,v_b=0.02", "missing f_d"),
    ("m=1,c=0.1,k=4,v_b=0.02,f_d=0.08,bogus=1", "unknown key 'bogus'"),
    ("m=1,c=0.1,k=4,v_b=0.02,f_d=0.08,sigma1=nan", "dimensional sigma1"),
    ("m=1,c=0.1,k=4,v_b=0.02,f_d=0.08,m=2", "dimensional: m is given twice (1 and 2)"),  # the last won before
])
def test_bad_dimensional_tables_exit_2_with_one_line(table, message, capsys):
    code = main(["simulate", "--t-end", "1", "--friction", "lugre", "--dimensional", table])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and len(err) == 1 and message in err[0], err


def test_rate_state_needs_no_f_d():
    _, law, _ = RunConfig.from_mapping({"friction": "rate_state", "dimensional": "m=1,c=0.1,k=4,v_b=0.02,dc=0.01"}).build()
    assert law.dc == pytest.approx(0.01)  # l_0 = 1


def test_a_dimensional_sweep_is_the_nondimensional_sweep():
    dim = parse_sweep({"friction": "stribeck", "t_end": 50.0, "dimensional": {**SCALES, "f_d": 0.08, "f_ms": 0.16},
                       "grid": {"v_b": [0.02, 0.04], "vs": {"start": 0.01, "stop": 0.03, "num": 3}, "delta": 1.0}})
    nd = parse_sweep({"friction": "stribeck", "t_end": 50.0, "zeta": ZETA, "fd": _force(0.08), "fs": _force(0.16),
                      "grid": {"vb": [_speed(0.02), _speed(0.04)], "vs": {"start": _speed(0.01), "stop": _speed(0.03),
                                                                         "num": 3}, "delta": 1.0}})
    assert list(dim.axes) == list(nd.axes) == ["vb", "vs"]
    for key in nd.axes:
        assert dim.axes[key] == pytest.approx(nd.axes[key], rel=1e-15)
    index = tuple(np.array([0, 1, 1]) for _ in nd.axes)
    a, b = dim.point_params(index), nd.point_params(index)
    for key in b:
        assert a[key] == pytest.approx(b[key], rel=1e-15, nan_ok=True), key


@pytest.mark.parametrize("grid, message", [
    ({"vb": [0.01, 0.02]}, "grid.vb: with dimensional, sweep it as grid.v_b"),
    ({"k": [1.0, 2.0]}, "grid.k: m, c, k and l_0 set the units"),
])
def test_a_dimensional_sweep_refuses_mixed_axes(grid, message):
    with pytest.raises(ValueError, match=message):
        parse_sweep({"friction": "coulomb", "dimensional": {**SCALES, "v_b": 0.04, "f_d": 0.08}, "grid": grid})


def test_a_dimensional_sweep_computes_the_nondimensional_points():
    # w0 l_0 = 1 here: v_b = V_b; zeta = 0.05, F_d = 0.08 / 4 = 0.02, F_s = 0.04
    dim = parse_sweep({"friction": "coulomb", "t_end": 100.0, "dimensional": {**SCALES, "f_d": 0.08, "f_ms": 0.16},
                       "grid": {"v_b": [0.02, 0.04]}})
    nd = parse_sweep({"friction": "coulomb", "t_end": 100.0, "zeta": ZETA, "fd": _force(0.08), "fs": _force(0.16),
                      "grid": {"vb": [_speed(0.02), _speed(0.04)]}})
    a, b = compute_chunk(dim.source, (0,), (2,)), compute_chunk(nd.source, (0,), (2,))
    np.testing.assert_allclose(a, b, rtol=1e-13, equal_nan=True)


def test_a_dimensional_sweep_over_f_d_takes_the_tables_f_ms():
    """f_ms in the table and f_d a grid axis: it was refused ("f_ms needs f_d ... alone")."""
    cfg = parse_sweep({"friction": "stribeck", "t_end": 100.0, "grid": {"f_d": [0.08, 0.04]},
                       "dimensional": {"m": 1, "k": 4, "c": 0.4, "v_b": 0.02, "f_ms": 0.16}})
    _, law, _ = cfg.run.build()
    assert law.fs == pytest.approx(0.04)  # 0.16 / (k l_0)
    assert cfg.axes["fd"].tolist() == pytest.approx([0.02, 0.01])
    with pytest.raises(ValueError, match="fs must be >= fd"):  # f_ms below an axis value: refused per point
        parse_sweep({"friction": "stribeck", "t_end": 100.0, "grid": {"f_d": [0.08, 0.2]},
                     "dimensional": {"m": 1, "k": 4, "c": 0.4, "v_b": 0.02, "f_ms": 0.1}})
