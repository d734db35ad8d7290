"""The top-level namespace: subpackages are modules, nothing leaks, wrong arguments fail in one line."""

from __future__ import annotations

import importlib
import types

import pytest

import frictionflow
from frictionflow import _figures


def test_basins_is_the_subpackage_and_its_function_is_reachable():
    module = importlib.import_module("frictionflow.basins")
    assert isinstance(frictionflow.basins, types.ModuleType) and frictionflow.basins is module
    assert frictionflow.basins.Tolerances is module.Tolerances  # attribute access through the package works
    assert callable(module.basins)
    assert frictionflow.compute_basins is module.basins
    assert {"basins", "compute_basins"} <= set(frictionflow.__all__)


def test_the_old_call_through_the_top_level_name_still_works_with_a_deprecation(monkeypatch):
    """``from frictionflow import basins; basins(...)`` called the function before: for one release it still does."""
    seen = {}
    monkeypatch.setattr(frictionflow.basins, "basins", lambda *a, **k: seen.setdefault("args", (a, k)))
    with pytest.warns(DeprecationWarning, match="frictionflow.basins.basins"):
        frictionflow.basins({"friction": "coulomb"}, x0=(0, 1, 2), v0=(0, 1, 2))
    assert seen["args"] == (({"friction": "coulomb"},), {"x0": (0, 1, 2), "v0": (0, 1, 2)})


def test_import_helpers_do_not_leak():
    names = dir(frictionflow)
    assert "version" not in names and "PackageNotFoundError" not in names
    assert isinstance(frictionflow.__version__, str) and frictionflow.__version__


def test_every_public_name_exists():
    missing = [n for n in frictionflow.__all__ if not hasattr(frictionflow, n)]
    assert not missing


def test_analyze_refuses_a_model_in_one_line():
    with pytest.raises(TypeError) as info:
        frictionflow.analyze(frictionflow.BeltOscillator(zeta=0.05, vb=0.01))
    message = str(info.value)
    assert "\n" not in message
    assert "traj" in message and "Trajectory" in message and "BeltOscillator" in message


def test_every_result_with_a_plot_method_has_a_registered_figure():
    """The figures register on import of frictionflow (and frictionflow.orbits): ``.plot()`` finds them."""
    from frictionflow.analysis import Analysis
    from frictionflow.analysis.stability import StabilityScan
    from frictionflow.basins import Basins
    from frictionflow.orbits import ContinuationResult, ForcedChart, PeriodicOrbit, StabilityChart
    from frictionflow.trajectory import Trajectory

    for cls in (Trajectory, Analysis, Basins, ContinuationResult, PeriodicOrbit, StabilityChart, ForcedChart,
                StabilityScan):
        assert any(c in _figures._DRAWERS for c in cls.__mro__), cls.__name__


def test_an_unregistered_result_fails_clearly():
    class Unknown:
        pass

    with pytest.raises(RuntimeError, match="no figure is registered for Unknown"):
        _figures.draw(Unknown())
