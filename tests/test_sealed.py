"""Friction laws and solvers are fixed once built: every registered class, by the registries (no names here).

A law's kernel parameters are computed once and kept, so a value set afterwards would run the old one; and
a value set afterwards would skip its range check.  Setting or removing an attribute is refused with one
line; copies and pickles stay sealed and equal."""

from __future__ import annotations

import copy
import pickle

import numpy as np
import pytest

from frictionflow import BeltOscillator, simulate
from frictionflow.friction.registry import law_class, law_names
from frictionflow.solvers.registry import solver_classes


def _laws():
    return [law_class(name)() for name in law_names()]  # every configurable law, its defaults


@pytest.mark.parametrize("obj", _laws() + [cls() for cls in solver_classes()], ids=lambda o: type(o).__name__)
def test_a_built_law_or_solver_refuses_to_change(obj):
    params = [p.name for p in obj.parameters]
    assert params, "every registered class declares its parameters"
    name = getattr(obj, "keywords", {}).get(params[0], params[0])  # a solver's config name -> its attribute
    before = getattr(obj, name)
    with pytest.raises(AttributeError, match=rf"^{type(obj).__name__} cannot change {name} after it is built"):
        setattr(obj, name, -1.0)
    with pytest.raises(AttributeError, match=rf"cannot remove {name}"):
        delattr(obj, name)
    assert getattr(obj, name) == before
    for other in (copy.copy(obj), copy.deepcopy(obj), pickle.loads(pickle.dumps(obj))):
        assert getattr(other, name) == before
        with pytest.raises(AttributeError, match="after it is built"):
            setattr(other, name, before)


def test_a_law_run_once_keeps_its_numbers():
    # the kernel parameters are cached on first use: a value set afterwards used to mix into later runs (the
    # start X = F_d took the new fd, the kernels' slip force kept the old one)
    law = law_class("coulomb")(fd=0.3, fs=0.4)
    model = BeltOscillator(zeta=0.05, vb=0.1)
    first = simulate(model, law, t_end=50.0)
    with pytest.raises(AttributeError):
        law.fd = 0.2
    again = simulate(model, law, t_end=50.0)
    assert np.array_equal(first.x, again.x) and law.fd == 0.3
