"""Bad arguments to the forced-orbit, continuation and response entry points: refused up front, in one line naming
the argument, as ``find_orbit`` and ``simulate`` refuse them -- not an AttributeError or a bound deep inside."""

from __future__ import annotations

import re

import pytest

from frictionflow import BeltOscillator, Coulomb, simulate
from frictionflow.analysis.response import frequency_response
from frictionflow.cli import main
from frictionflow.orbits.continuation import continuation
from frictionflow.orbits.forced import continue_forced, find_forced_orbit, stroboscopic_sweep

FORCED = BeltOscillator(zeta=0.05, vb=0.1, fex=0.5, omega=1.0)
LAW = Coulomb(0.5, 1.0)
#: undamped resonance (the CLI's default zeta = 0 with --omega 1): the exact solver has no closed form there
RESONANT = BeltOscillator(zeta=0.0, vb=0.01, fex=0.3, omega=1.0)
RESONANT_LAW = Coulomb(0.02)

NOT_A_MODEL = "model must be a BeltOscillator, got NoneType"
NOT_A_LAW = "friction must be a FrictionLaw, got {}"


@pytest.mark.parametrize("call, message", [
    (lambda: find_forced_orbit(None, LAW), NOT_A_MODEL),
    (lambda: continue_forced(None, LAW, "omega", 1.0, 1.1), NOT_A_MODEL),
    (lambda: frequency_response(None, LAW, [0.9, 1.0]), NOT_A_MODEL),
    (lambda: stroboscopic_sweep(None, LAW, "omega", [0.9, 1.0]), NOT_A_MODEL),
    (lambda: continuation(None, LAW, "zeta", 0.01, 0.1), NOT_A_MODEL),
    (lambda: find_forced_orbit(FORCED, "coulomb"), NOT_A_LAW.format("str")),
    (lambda: frequency_response(FORCED, "coulomb", [0.9, 1.0]), NOT_A_LAW.format("str")),
    (lambda: continuation(FORCED, "coulomb", "zeta", 0.01, 0.1), NOT_A_LAW.format("str")),
    (lambda: stroboscopic_sweep(FORCED, "coulomb", "omega", [0.9, 1.0]), NOT_A_LAW.format("str")),
    # the class, not an instance: its class attributes passed the law checks, and kernel_params failed unbound
    (lambda: find_forced_orbit(FORCED, Coulomb), NOT_A_LAW.format("type")),
    (lambda: continue_forced(FORCED, Coulomb, "omega", 1.0, 1.1), NOT_A_LAW.format("type")),
], ids=["find_forced_orbit-model", "continue_forced-model", "frequency_response-model", "stroboscopic_sweep-model",
        "continuation-model", "find_forced_orbit-law", "frequency_response-law", "continuation-law",
        "stroboscopic_sweep-law", "find_forced_orbit-law-class", "continue_forced-law-class"])
def test_a_wrong_model_or_law_is_a_type_error_naming_the_argument(call, message):
    with pytest.raises(TypeError, match=f"^{re.escape(message)}$"):
        call()


def _simulate_refusal() -> str:
    """What ``simulate`` says at the resonant point: the reason the forced orbits must give too."""
    with pytest.raises(ValueError) as e:
        simulate(RESONANT, RESONANT_LAW)
    assert "undamped resonance" in str(e.value)
    return str(e.value)


@pytest.mark.parametrize("call", [
    lambda: find_forced_orbit(RESONANT, RESONANT_LAW),
    lambda: continue_forced(RESONANT, RESONANT_LAW, "fex", 0.3, 0.4),
], ids=["find_forced_orbit", "continue_forced"])
def test_undamped_resonance_is_refused_with_simulates_reason(call):
    # before: the transient grew without bound and one_period refused it as "x0 must be finite and in [...]"
    with pytest.raises(ValueError, match=f"^{re.escape(_simulate_refusal())}$"):
        call()


@pytest.mark.parametrize("args", [
    ["forced-orbit", "--fex", "0.3", "--omega", "1"],
    ["forced-continue", "--omega", "1", "--vary", "fex=0.3:0.4"],  # the branch sets fex
], ids=["forced-orbit", "forced-continue"])
def test_cli_undamped_resonance_exits_2_with_simulates_line(args, capsys):
    assert main(["simulate", "--fex", "0.3", "--omega", "1"]) == 2
    expected = capsys.readouterr().err.strip()
    assert expected.startswith("error: solver=exact: undamped resonance")
    assert main(args) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert err == [expected]
