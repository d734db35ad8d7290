"""API arguments refused in one line naming them, not taken for something else (booleans, tolerances, sequences)."""

from __future__ import annotations

import re

import numpy as np
import pytest

import frictionflow as ff
import frictionflow.system
from frictionflow.sweep.config import parse_sweep

NOT_BOOLEANS = ["no", "yes", float("nan"), [0.1], -1, 1, 0, None]


# 1. boolean settings ------------------------------------------------------------------------------------------

@pytest.mark.parametrize("value", NOT_BOOLEANS)
def test_exact_replicate_must_be_true_or_false(value):
    with pytest.raises(TypeError, match=r"^replicate must be True or False, got "):
        ff.Exact(replicate=value)


@pytest.mark.parametrize("value", [True, False, np.bool_(True), np.bool_(False)])
def test_exact_replicate_takes_python_and_numpy_booleans(value):
    assert ff.Exact(replicate=value).replicate is bool(value)


@pytest.mark.parametrize("solver, law", [(ff.Exact(), ff.Coulomb()), (ff.RK4(dt=1e-2), ff.Coulomb()),
                                         (ff.Adaptive(), ff.Coulomb()), (ff.Stiff(), ff.LuGre())],
                         ids=["exact", "rk4", "adaptive", "stiff"])
def test_solve_progress_must_be_true_or_false(solver, law):
    model = ff.BeltOscillator(zeta=0.05, vb=0.1)
    with pytest.raises(TypeError, match=r"^progress must be True or False, got str$"):
        solver.solve(model, law, 0.0, 0.0, 1.0, progress="no")


def test_stiff_solve_state_progress_must_be_true_or_false():
    model, law = ff.BeltOscillator(zeta=0.05, vb=0.1), ff.LuGre()
    with pytest.raises(TypeError, match=r"^progress must be True or False, got str$"):
        ff.Stiff().solve_state(model, law, np.zeros(2 + len(law.internal_names)), 1.0, progress="no")


# 2. atol ------------------------------------------------------------------------------------------------------

@pytest.mark.parametrize("cls", [ff.Adaptive, ff.Stiff])
@pytest.mark.parametrize("value", ["0.1", True, False, None])
def test_atol_refuses_text_booleans_and_none(cls, value):
    with pytest.raises(ValueError, match=r"^atol must be finite and > 0, got "):
        cls(atol=value)


@pytest.mark.parametrize("cls", [ff.Adaptive, ff.Stiff])
def test_atol_takes_numpy_numbers(cls):
    assert cls(atol=np.float64(1e-12)).atol == 1e-12
    assert cls(atol=np.float32(0.5)).atol == 0.5


# 3. assemble --------------------------------------------------------------------------------------------------

@pytest.mark.parametrize("value", ["x", None, 3.0])
def test_assemble_refuses_what_is_not_a_system(value):
    with pytest.raises(TypeError, match=r"^system must be a System .*, got "):
        frictionflow.system.assemble(value)


# 4. frequency_response and stability_scan sequences ----------------------------------------------------------

FORCED = ff.BeltOscillator(zeta=0.05, vb=0.01, fex=0.01)


@pytest.mark.parametrize("omegas", ["ab", None, [True, False], [[1.0, 2.0], [3.0]], ["1.0", "2.0"], 1.0])
def test_frequency_response_names_omegas(omegas):
    with pytest.raises(ValueError, match=r"^omegas must be a non-empty sequence of numbers"):
        ff.frequency_response(FORCED, ff.Coulomb(), omegas)


@pytest.mark.parametrize("directions", ["sideways", 5, (), ["up", 1]])
def test_frequency_response_directions_are_named_as_given(directions):
    with pytest.raises(ValueError, match=r"^directions must be some of \('up', 'down'\), got " + re.escape(repr(directions)) + "$"):
        ff.frequency_response(FORCED, ff.Coulomb(), [1.0, 1.1], directions=directions)


def test_frequency_response_takes_a_bare_direction():
    ds = ff.frequency_response(FORCED, ff.Coulomb(), np.array([1.0, 1.1]), directions="up", periods=8)
    assert list(ds.direction.values) == ["up"]


def test_frequency_response_progress_must_be_true_or_false():
    with pytest.raises(TypeError, match=r"^progress must be True or False, got str$"):
        ff.frequency_response(FORCED, ff.Coulomb(), [1.0, 1.1], progress="no")


@pytest.mark.parametrize("values", ["ab", None, [True, False], [[0.1, 0.2], [0.3]], ["0.1", "0.2"]])
def test_stability_scan_names_values(values):
    with pytest.raises(ValueError, match=r"^values must be a sequence of at least 2 finite numbers, got "):
        ff.stability_scan(lambda v: None, values)


# 5. parse_sweep from the Python API ---------------------------------------------------------------------------

@pytest.mark.parametrize("entry", [
    {"start": 0, "stop": 0.1, "num": np.int64(2)},
    {"start": np.float64(0.0), "stop": np.float32(0.1), "num": np.int32(2)},
    np.array([0.0, 0.1]),
    (0.0, 0.1),
    [np.float64(0.0), np.float64(0.1)],
], ids=["np-num", "np-all", "array", "tuple", "np-items"])
def test_parse_sweep_takes_numpy_and_tuples(entry):
    cfg = parse_sweep({"grid": {"zeta": entry}})
    np.testing.assert_allclose(cfg.axes["zeta"], [0.0, 0.1], rtol=1e-7)
    assert type(cfg.source["grid"]["zeta"]) in (list, dict)  # recorded as TOML gives it


def test_parse_sweep_sample_takes_numpy_and_tuples():
    cfg = parse_sweep({"grid": {"zeta": [0.0, 0.1], "sample": {"num": np.int64(3), "seed": np.int64(1),
                                                                "x0": np.array([-1.0, 1.0])}}})
    assert cfg.sample["x0"].shape == (3,)


@pytest.mark.parametrize("entry, message", [
    (np.array([[0.0, 0.1]]), r"^grid\.zeta\[0\]: zeta must be"),
    (np.array([True, False]), r"^grid\.zeta\[0\]: zeta must be"),
    ({"start": 0, "stop": 0.1, "num": np.float64(2.5)}, r"^grid\.zeta\.num must be an integer"),
    ({"start": 0, "stop": 0.1, "num": np.bool_(True)}, r"^grid\.zeta\.num must be an integer"),
])
def test_parse_sweep_still_refuses_what_is_not_a_list_of_numbers(entry, message):
    with pytest.raises(ValueError, match=message):
        parse_sweep({"grid": {"zeta": entry}})
