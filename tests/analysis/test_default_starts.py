"""The API's functions that run the oscillator start where ``simulate`` and every command start by default: the law's
start, the paper's X(0) = F_d, X'(0) = V_b.  ``lyapunov_exponents`` and ``frequency_response`` started at (0, 0), so
the lyapunov guide's example gave 0.0810 in Python and 0.0777 on the command line."""

from __future__ import annotations

import json

import numpy as np

from frictionflow import BeltOscillator, Coulomb, Stribeck
from frictionflow.analysis import frequency_response, lyapunov_exponents

from ..cli.processes import in_process


def test_lyapunov_exponents_start_at_the_law_s_start_as_the_command_does():
    model, law = BeltOscillator(zeta=0.05, vb=0.01), Stribeck(0.02, 0.04, vs=0.01)
    default = lyapunov_exponents(model, law, t_transient=100.0, t_end=400.0)
    given = lyapunov_exponents(model, law, x0=0.02, v0=0.01, t_transient=100.0, t_end=400.0)
    assert (default.settings["x0"], default.settings["v0"]) == (0.02, 0.01)
    assert default.exponents == given.exponents
    code, out, err, _ = in_process("lyapunov", "--friction", "stribeck", "--fd", "0.02", "--fs", "0.04", "--vs", "0.01",
                                   "--zeta", "0.05", "--vb", "0.01", "--t-transient", "100", "--t-end", "400", "--json")
    assert code == 0, err
    assert json.loads(out)["exponents"][0] == default.exponents[0]  # the second is -inf (a stick phase): null in JSON


def test_a_frequency_response_starts_at_the_law_s_start():
    model, law = BeltOscillator(zeta=0.05, vb=0.01, fex=0.02, omega=1.0), Coulomb(0.02, 0.04)
    omegas = [0.8, 1.2]
    default = frequency_response(model, law, omegas, periods=20, directions=("up",))
    given = frequency_response(model, law, omegas, periods=20, directions=("up",), x0=0.02, v0=0.01)
    at_rest = frequency_response(model, law, omegas, periods=20, directions=("up",), x0=0.0, v0=0.0)
    np.testing.assert_array_equal(default["X_max"].values, given["X_max"].values)
    assert not np.array_equal(default["X_max"].values, at_rest["X_max"].values)  # the start shows after 20 periods
