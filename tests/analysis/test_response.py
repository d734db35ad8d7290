"""The frequency response: closed form of the linear oscillator, continuation of the state, validation."""

from __future__ import annotations

import math

import numpy as np
import pytest
import xarray as xr

from dataclasses import replace

from frictionflow import BeltOscillator, analyze, simulate
from frictionflow.analysis.response import frequency_response
from frictionflow.friction import Karnopp
from frictionflow.solvers import RK4

ZETA, FEX = 0.1, 0.5
NO_FRICTION = Karnopp(fd=0.0, fs=0.0, vd=1e-3)
OMEGAS = np.linspace(0.6, 1.4, 5)


@pytest.fixture(scope="module")
def linear():
    with pytest.warns(UserWarning):  # a step coarse for a band no motion reaches
        return frequency_response(BeltOscillator(zeta=ZETA, vb=0.0, fex=FEX), NO_FRICTION, OMEGAS,
                                  solver=RK4(dt=1e-2), periods=80)


def test_linear_response_curve_matches_the_closed_form(linear):
    a = FEX / np.hypot(1 - OMEGAS**2, 2 * ZETA * OMEGAS)
    for d in ("up", "down"):
        sel = linear.sel(direction=d)
        assert (sel["kind"].values == 0).all() and (sel["multiple"].values == 1).all()
        np.testing.assert_allclose(sel["amplitude"].values, a, rtol=1e-5)
        np.testing.assert_allclose(sel["P_dv"].values, ZETA * OMEGAS**2 * a * a, rtol=1e-5)
        np.testing.assert_allclose(sel["P_ex"].values, sel["P_dv"].values, rtol=1e-6)
        np.testing.assert_allclose(sel["TR_B"].values, a * np.hypot(1, 2 * ZETA * OMEGAS) / FEX, rtol=1e-4)


def test_dataset_carries_units_and_round_trips(linear, tmp_path):
    assert linear["P_ex"].attrs["units"] == "1" and "external force" in linear["P_ex"].attrs["long_name"]
    assert linear["kind"].attrs["flag_meanings"].split()[:3] == ["periodic", "equilibrium", "not_settled"]
    assert linear.attrs["fex"] == FEX and "omega" not in linear.attrs
    linear.to_netcdf(tmp_path / "r.nc")
    with xr.open_dataset(tmp_path / "r.nc") as back:
        xr.testing.assert_identical(back.load(), linear)


def test_each_frequency_continues_from_the_previous_state():
    """The second frequency starts where the first ended (same forcing phase): the runs done by hand agree."""
    model = BeltOscillator(zeta=ZETA, vb=0.0, fex=FEX)
    solver = RK4(dt=1e-2)
    with pytest.warns(UserWarning):
        ds = frequency_response(model, NO_FRICTION, [0.9, 1.0], solver=solver, periods=8, directions=("up",), x0=5.0, v0=0.0)
        first = simulate(replace(model, omega=0.9), NO_FRICTION, solver, t_end=8 * 2 * math.pi / 0.9, x0=5.0, v0=0.0)
        second = simulate(replace(model, omega=1.0), NO_FRICTION, solver, t_end=8 * 2 * math.pi, x0=first.x[-1], v0=first.v[-1])
    for j, tr in enumerate((first, second)):
        an = analyze(tr)
        assert ds["amplitude"].values[0, j] == 0.5 * (an.amplitude["X_max"] - an.amplitude["X_min"])
        assert ds["kind"].values[0, j] == 2  # 8 periods: the transient 5 e^(-zeta tau) has not decayed


@pytest.mark.parametrize("kwargs, message", [
    (dict(omegas=[1.0, 0.5]), "omega must be increasing"),
    (dict(omegas=[0.0, 1.0]), "omega"),
    (dict(periods=3), "periods"),
    (dict(directions=("sideways",)), "directions"),
])
def test_bad_input_is_refused(kwargs, message):
    args = dict(omegas=[0.5, 1.0]) | kwargs
    with pytest.raises(ValueError, match=message):
        frequency_response(BeltOscillator(zeta=ZETA, vb=0.0, fex=FEX), NO_FRICTION, args.pop("omegas"), **args)


def test_unforced_model_is_refused():
    with pytest.raises(ValueError, match="fex must be > 0"):
        frequency_response(BeltOscillator(zeta=ZETA, vb=0.0), NO_FRICTION, [1.0])
