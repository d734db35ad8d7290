"""A SlipLaw's kernels are compiled once, not once per user function (kept in the cache: tests/core/test_rebind.py).

Every compiled user function runs in the same rebuilt kernel, which calls the
function whose address the law's force record carries.  What must hold: the
kernel object is shared, each law still gets its own function's numbers (the
built-in Stribeck law's, to rounding), a law survives pickling, and a function
that raises in compiled code ends the run instead of returning a made-up force.
"""

from __future__ import annotations

import functools
import math
import pickle

import numpy as np
import pytest

from frictionflow import Adaptive, BeltOscillator, SlipLaw, Stribeck, simulate
from frictionflow.friction.user import ADDRESS, compiled_function
from frictionflow.solvers.adaptive import kernel_for

M = BeltOscillator(zeta=0.05, vb=0.01)


def stribeck(fd: float, fs: float, vs: float):
    """The built-in Stribeck curve (delta = 2) as a plain function, a new callable on every call."""
    def force(s):
        return fd + (fs - fd) * math.exp(-((s / vs) ** 2))
    return force


def gaussian_bump(s):
    return 0.02 + 0.02 * math.exp(-((s / 0.02) ** 2))


def test_every_compiled_user_law_runs_in_one_kernel():
    a, b = SlipLaw(stribeck(0.02, 0.04, 0.02)), SlipLaw(stribeck(0.03, 0.05, 0.01))
    (run_a, compiled_a), (run_b, compiled_b) = kernel_for(a), kernel_for(b)
    assert compiled_a and compiled_b and run_a is run_b
    # each record points at its own function
    assert a.kernel_params()[ADDRESS] != b.kernel_params()[ADDRESS]


@pytest.mark.parametrize(("fd", "fs", "vs"), [(0.02, 0.04, 0.02), (0.03, 0.05, 0.01), (0.01, 0.03, 0.005)])
def test_each_user_law_gets_its_own_numbers(fd, fs, vs):
    user = simulate(M, SlipLaw(stribeck(fd, fs, vs)), Adaptive(), t_end=30)
    builtin = simulate(M, Stribeck(fd, fs, vs=vs), Adaptive(), t_end=30)
    assert np.allclose(user.x, builtin.x, rtol=0, atol=1e-15) and np.array_equal(user.mode, builtin.mode)


def test_a_pickled_law_compiles_its_function_in_the_new_process_state():
    law = SlipLaw(gaussian_bump)
    law.kernel_params()  # compiled and held
    state = pickle.loads(pickle.dumps(law)).__dict__
    assert "_compiled_func" not in state  # an address is only valid in the process that compiled it
    again = pickle.loads(pickle.dumps(law))
    a = simulate(M, law, Adaptive(), t_end=20)
    b = simulate(M, again, Adaptive(), t_end=20)
    assert np.array_equal(a.x, b.x)


def test_the_compiled_form_is_kept_while_the_function_lives():
    assert compiled_function(gaussian_bump) is compiled_function(gaussian_bump)


def test_a_function_that_raises_in_compiled_code_ends_the_run():
    def refuses_fast(s):
        if s > 0.015:
            raise ValueError("too fast")
        return 0.02 + 0.02 * math.exp(-((s / 0.02) ** 2))

    traj = simulate(M, SlipLaw(refuses_fast, fd=0.02), Adaptive(), t_end=30, x0=0.0, v0=0.0)
    assert np.isnan(traj.x[-1])  # not the 0.0 a C callback returns when its exception is dropped


class _Bump:
    """A callable object: what numba cannot compile as a function."""

    def __call__(self, s):
        return gaussian_bump(s)


def _shaped(s, base, height):
    return base + height * math.exp(-((s / 0.02) ** 2))


@pytest.mark.parametrize("func", [_Bump(), functools.partial(_shaped, base=0.02, height=0.02)], ids=["object", "partial"])
def test_any_callable_runs_in_python_with_the_plain_function_s_numbers(func):
    # "any Python callable" (the guide): not compiled, run by the Python version of the same kernel
    assert compiled_function(func) is None
    plain = simulate(M, SlipLaw(gaussian_bump), Adaptive(), t_end=20)
    other = simulate(M, SlipLaw(func), Adaptive(), t_end=20)
    assert np.array_equal(other.x, plain.x) and np.array_equal(other.mode, plain.mode)
