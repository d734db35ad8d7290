"""Changing one named parameter of a (model, law) pair."""

from __future__ import annotations

import pytest

from frictionflow import BeltOscillator, Coulomb, Karnopp, SlipLaw, Stribeck
from frictionflow.orbits import parameter_names, with_param
from frictionflow.orbits.parameters import get_param


def test_every_parameter_round_trips():
    model = BeltOscillator(zeta=0.05, vb=0.01)
    for law in (Karnopp(0.02, 0.04, vd=2e-3, stick_force="spring"), Coulomb(0.02, 0.04, rk4_band=3e-4), Stribeck(0.02, 0.05, 0.02, 1.5, 0.01)):
        for name in parameter_names(law):
            value = get_param(model, law, name) * 1.1 if name != "fd" else 0.021
            m2, l2 = with_param(model, law, name, value)
            assert get_param(m2, l2, name) == pytest.approx(value)
            # everything else is unchanged, including what as_dict does not show
            for other in parameter_names(law):
                if other != name:
                    assert get_param(m2, l2, other) == get_param(model, law, other)
            assert l2.stick_force == law.stick_force and getattr(l2, "rk4_band", None) == getattr(law, "rk4_band", None)


def test_unknown_and_invalid_values_are_refused():
    model = BeltOscillator()
    with pytest.raises(ValueError, match="param must be one of"):
        with_param(model, Coulomb(), "vs", 0.1)
    with pytest.raises(ValueError, match="param must be one of"):
        with_param(model, SlipLaw(lambda s: 0.02 + 0.01 / (1 + s)), "fd", 0.1)
    with pytest.raises(ValueError, match="zeta"):
        with_param(model, Coulomb(), "zeta", -1.0)
