"""Model parameters and the dimensional <-> non-dimensional conversion (Eq. 3)."""

import math

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from frictionflow import BeltOscillator, DimensionalParams, Karnopp, Stribeck

pos = st.floats(1e-3, 1e3, allow_nan=False)


@given(m=pos, k=pos, l0=pos, zeta=st.floats(0, 5, allow_subnormal=False), vb=st.floats(-10, 10, allow_subnormal=False),
       fd=st.floats(0, 10, allow_subnormal=False), gap=st.floats(0, 10, allow_subnormal=False), vd=st.floats(1e-6, 1))
@settings(max_examples=200, deadline=None)
def test_round_trip_nondimensional_dimensional(m, k, l0, zeta, vb, fd, gap, vd):
    dim = DimensionalParams.from_nondimensional(zeta=zeta, vb=vb, fd=fd, fs=fd + gap, vd=vd, m=m, k=k, l_0=l0)
    nd = dim.nondimensional()
    for key, want in (("zeta", zeta), ("vb", vb), ("fd", fd), ("fs", fd + gap), ("vd", vd)):
        assert nd[key] == pytest.approx(want, rel=1e-12, abs=1e-12 * (1 + abs(want)))
    assert nd["omega0"] == pytest.approx(math.sqrt(k / m))


def test_eq3_by_hand():
    # m = 2, k = 8 -> omega0 = 2; c = 0.4 -> zeta = 0.4 / (2*2*2) = 0.05
    d = DimensionalParams(m=2.0, c=0.4, k=8.0, v_b=0.1, f_d=0.8, f_ms=1.2, v_d=0.004, l_0=0.5)
    nd = d.nondimensional()
    assert nd["omega0"] == 2.0
    assert nd["zeta"] == pytest.approx(0.05)
    assert nd["vb"] == pytest.approx(0.1 / (2.0 * 0.5))
    assert nd["fd"] == pytest.approx(0.8 / (8.0 * 0.5))
    assert nd["fs"] == pytest.approx(1.2 / (8.0 * 0.5))
    assert nd["vd"] == pytest.approx(0.004 / (2.0 * 0.5))


def test_dimensional_defaults_follow_the_paper():
    d = DimensionalParams(m=1.0, c=0.0, k=4.0, v_b=0.02, f_d=0.08)
    nd = d.nondimensional()
    assert "fs" not in nd  # unset: the law's own default, the paper's F_s = F_d for Karnopp (and 2 F_d for Stribeck)
    assert Karnopp(fd=nd["fd"]).fs == nd["fd"] and Stribeck(fd=nd["fd"]).fs == 2.0 * nd["fd"]
    assert nd["vd"] == pytest.approx(1e-3)


@pytest.mark.parametrize(
    "kwargs, name",
    [
        ({"zeta": -0.1}, "zeta"),
        ({"zeta": float("nan")}, "zeta"),
        ({"zeta": float("inf")}, "zeta"),
        ({"vb": float("nan")}, "vb"),
    ],
)
def test_bad_model_parameters(kwargs, name):
    with pytest.raises(ValueError, match=rf"^{name} must be"):
        BeltOscillator(**kwargs)


@pytest.mark.parametrize(
    "kwargs, name",
    [
        ({"m": 0.0}, "m"),
        ({"k": -1.0}, "k"),
        ({"c": -1.0}, "c"),
        ({"f_d": -0.1}, "f_d"),
        ({"f_ms": 0.01}, "f_ms"),
        ({"v_d": 0.0}, "v_d"),
    ],
)
def test_bad_dimensional_parameters(kwargs, name):
    base = dict(m=1.0, c=0.1, k=1.0, v_b=0.01, f_d=0.02)
    with pytest.raises(ValueError, match=rf"^{name} must be"):
        DimensionalParams(**(base | kwargs))


def test_dimensional_forcing_by_hand():
    # m = 2, k = 8: omega0 = 2; a force 0.3 cos(3 t + 0.4) on a spring with l_0 = 0.5
    nd = DimensionalParams(m=2.0, c=0.4, k=8.0, v_b=0.1, f_d=0.2, l_0=0.5, f_ex=0.3, w_ex=3.0, phi_ex=0.4).nondimensional()
    assert nd["fex"] == pytest.approx(0.3 / (8.0 * 0.5))
    assert nd["omega"] == pytest.approx(3.0 / 2.0)
    assert nd["phi"] == 0.4
    # unforced by default, and the forcing frequency defaults to the natural one
    plain = DimensionalParams(m=2.0, c=0.4, k=8.0, v_b=0.1, f_d=0.2).nondimensional()
    assert plain["fex"] == 0.0 and plain["omega"] == 1.0


def test_dimensional_forcing_reaches_the_model_from_the_command_line(capsys):
    import json

    from frictionflow.cli import main

    code = main(["simulate", "--friction", "coulomb", "--t-end", "60", "--json",
                 "--dimensional", "m=1,c=0.1,k=4,v_b=0.02,f_d=0.08,f_ex=0.4,w_ex=3"])
    assert code == 0
    params = json.loads(capsys.readouterr().out)["params"]
    assert params["fex"] == pytest.approx(0.1) and params["omega"] == pytest.approx(1.5)
