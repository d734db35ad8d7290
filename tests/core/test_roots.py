"""The bracketed root finder (core.roots) against SciPy's brentq on hard brackets."""

from __future__ import annotations

import math
import random

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from numba import njit
from scipy.optimize import brentq

from frictionflow.core import roots as R

RTOL = 4 * R.EPS


def _bound(lo, hi, tol):
    """Points the safeguards allow: the bracket at least halves every STALL + 1 of them."""
    return (R.STALL + 1) * math.ceil(math.log2(abs(0.5 * hi - 0.5 * lo)) + 1.0 - math.log2(tol)) + 2


def _brent(f, lo, hi, xtol):
    return brentq(f, lo, hi, xtol=max(xtol, 1e-320), rtol=RTOL, maxiter=5000)


#: name: (f, lo, hi, xtol, the accuracy to which f's computed sign fixes the root)
HARD = {
    # flat: x^9 is 0 to rounding over |x| < 1e-36, so the absolute tolerance decides
    "flat_x9": (lambda x: x**9, -1.0, 2.0, 1e-12, 0.0),
    "steep_tanh": (lambda x: math.tanh(1e6 * (x - 0.3)), -1.0, 2.0, 0.0, 0.0),
    "triple_root": (lambda x: (x - 1.0) ** 3, 0.0, 3.0, 0.0, 0.0),
    # convex and very asymmetric: plain regula falsi keeps the left end for ever (see below)
    "convex": (lambda x: math.expm1(10.0 * (x - 0.3)), -1.0, 3.0, 0.0, 0.0),
    "concave": (lambda x: -math.expm1(10.0 * (x - 0.3)), -1.0, 3.0, 0.0, 0.0),
    "kepler": (lambda x: x - 0.9 * math.sin(x) - 0.1, 0.0, 3.0, 0.0, 2 * R.EPS),
    "tiny_near_1e-300": (lambda x: x - 2e-300, 1e-300, 4e-300, 0.0, 0.0),
    "tiny_sine_near_1e-300": (lambda x: math.sin(x * 1e300 - 2.0), 1e-300, 3e-300, 0.0, 4e-316),
    "huge_log": (lambda x: math.log(x / 3e302), 1e300, 1e305, 0.0, 0.0),
    "root_near_the_left_end": (lambda x: x - 1e-9, 0.0, 1.0, 1e-18, 0.0),
}


@pytest.mark.parametrize("name", HARD)
def test_hard_brackets_agree_with_brentq(name):
    f, lo, hi, xtol, noise = HARD[name]
    root, status, n = R.find_root(f, lo, hi, xtol=xtol, rtol=RTOL, maxiter=1000)
    ref = _brent(f, lo, hi, xtol)
    tol = xtol + RTOL * abs(ref)
    assert status == R.CONVERGED
    # both lie within their tolerance of the root (f's computed sign, where it is noisy, widens it)
    assert abs(root - ref) <= 2 * tol + 2 * noise
    assert n <= _bound(lo, hi, tol)


@pytest.mark.parametrize("name", ["steep_tanh", "convex", "concave", "kepler", "tiny_near_1e-300", "huge_log"])
def test_simple_roots_take_few_points(name):
    f, lo, hi, xtol, _ = HARD[name]
    _, status, n = R.find_root(f, lo, hi, xtol=xtol, rtol=RTOL)
    assert status == R.CONVERGED and n <= 60


def test_plain_regula_falsi_stalls_where_illinois_does_not():
    f, lo, hi = HARD["convex"][:3]
    a, b, fa, fb = lo, hi, f(lo), f(hi)
    for _ in range(200):  # plain false position: the right end never moves
        m = b - fb * (b - a) / (fb - fa)
        fm = f(m)
        if fm < 0.0:
            a, fa = m, fm
        else:
            b, fb = m, fm
    assert b == hi and b - a > 2.0
    root, status, n = R.find_root(f, lo, hi)
    assert status == R.CONVERGED and n < 30 and root == pytest.approx(0.3, rel=1e-15)


def test_huge_bracket_over_the_whole_float_range():
    root, status, n = R.find_root(lambda x: x - 1e300, -1e308, 1.5e308)
    assert status == R.CONVERGED and root == pytest.approx(1e300, rel=4 * RTOL)
    assert n <= _bound(-1e308, 1.5e308, RTOL * 1e300)


def test_a_root_at_either_end_is_taken_at_once():
    assert R.find_root(lambda x: x - 1.0, 1.0, 3.0) == (1.0, R.CONVERGED, 0)
    assert R.find_root(lambda x: x - 3.0, 1.0, 3.0) == (3.0, R.CONVERGED, 0)
    assert R.find_root(lambda x: x - 1.0, 3.0, 1.0) == (1.0, R.CONVERGED, 0)  # ends in either order


def test_an_exact_interior_zero_ends_the_search_on_it():
    # the first secant of a line is its root exactly
    assert R.find_root(lambda x: x - 0.5, 0.0, 1.0) == (0.5, R.CONVERGED, 1)
    # a plateau of zeros: any point of it, found as soon as one is hit
    root, status, _ = R.find_root(lambda x: 0.0 if abs(x - 0.3) < 0.1 else x - 0.3, -1.0, 2.0)
    assert status == R.CONVERGED and abs(root - 0.3) < 0.1


def test_a_point_within_ftol_is_the_root():
    root, status, n = R.find_root(lambda x: x**3 - 2.0, 0.0, 2.0, ftol=1e-3)
    assert status == R.CONVERGED and abs(root**3 - 2.0) <= 1e-3


def test_no_sign_change_is_a_status_not_a_hang():
    for f, lo, hi in [(lambda x: x * x + 1.0, -1.0, 1.0), (lambda x: -1.0, 0.0, 1.0), (lambda x: math.nan, 0.0, 1.0)]:
        root, status, n = R.find_root(f, lo, hi)
        assert status == R.NO_SIGN_CHANGE and n == 0


def test_out_of_points_is_reported():
    _, status, n = R.find_root(lambda x: (x - 1.0) ** 3, 0.0, 3.0, maxiter=5)
    assert status == R.MAX_ITER and n == 5


def test_the_bracket_keeps_the_sign_of_its_ends():
    f = lambda x: math.cos(x) - x  # noqa: E731
    b = R.bracket(0.0, 1.0, f(0.0), f(1.0), 0.0, RTOL, 0.0, 100)
    while b.status == R.RUNNING:
        assert min(b.lo, b.hi) < b.x < max(b.lo, b.hi)
        b = R.update(b, b.x, f(b.x))
        assert f(b.lo) > 0.0 >= f(b.hi) or b.status == R.CONVERGED
    assert b.hi == pytest.approx(0.7390851332151607, rel=1e-15)


@njit(cache=True)
def _cos_minus_x(x):
    return math.cos(x) - x


@njit(cache=True)
def _newton_steered(lo, hi):
    """Reverse communication inside a kernel, with a Newton step as the next point where it is inside."""
    b = R.bracket(lo, hi, _cos_minus_x(lo), _cos_minus_x(hi), 0.0, 4 * R.EPS, 0.0, 100)
    x = b.x
    while b.status == R.RUNNING:
        fx = _cos_minus_x(x)
        b = R.update(b, x, fx)
        b = R.steer(b, x - fx / (-math.sin(x) - 1.0))
        x = b.x
    return b.hi, b.n


def test_compiled_callers_and_a_newton_guess():
    root, n = _newton_steered(0.0, 1.0)
    assert root == pytest.approx(0.7390851332151607, rel=1e-15) and n <= 8
    assert R.find_root(lambda x: math.cos(x) - x, 0.0, 1.0)[0] == pytest.approx(root, rel=1e-15)


@settings(max_examples=200, deadline=None)
@given(
    roots=st.lists(st.floats(-100.0, 100.0, allow_nan=False), min_size=3, max_size=3, unique=True),
    scale=st.floats(1e-3, 1e3) | st.floats(-1e3, -1e-3),
    u=st.floats(0.01, 0.99),
    w=st.floats(0.01, 0.99),
)
def test_random_cubics_with_a_bracketed_simple_root(roots, scale, u, w):
    r1, r2, r3 = sorted(roots)
    if min(r2 - r1, r3 - r2) < 1e-6:
        return
    lo, hi = r1 + u * (r2 - r1), r2 + w * (r3 - r2)  # only r2 inside
    f = lambda x: scale * (x - r1) * (x - r2) * (x - r3)  # noqa: E731
    root, status, n = R.find_root(f, lo, hi, xtol=1e-14, rtol=RTOL)
    ref = _brent(f, lo, hi, 1e-14)
    tol = 1e-14 + RTOL * abs(ref)
    assert status == R.CONVERGED
    assert abs(root - r2) <= tol and abs(root - ref) <= 2 * tol
    assert n <= _bound(lo, hi, tol)


def _newton_root(f, df, lo, hi, xtol=0.0, rtol=RTOL, maxiter=1000):
    """(root, status, points, every bracket) of the search with f' known (update_newton)."""
    b = R.bracket(lo, hi, f(lo), f(hi), xtol, rtol, 0.0, maxiter)
    seen = [b]
    while b.status == R.RUNNING:
        x = b.x
        b = R.update_newton(b, x, f(x), df(x))
        seen.append(b)
    return b.hi, b.status, b.n, seen


#: name: (f, f', lo, hi): monotone on the bracket, as the structure engine's certified brackets are
MONOTONE = {
    "convex": (lambda x: math.expm1(10.0 * (x - 0.3)), lambda x: 10.0 * math.exp(10.0 * (x - 0.3)), -1.0, 3.0),
    "concave": (lambda x: -math.expm1(10.0 * (x - 0.3)), lambda x: -10.0 * math.exp(10.0 * (x - 0.3)), -1.0, 3.0),
    "kepler": (lambda x: x - 0.9 * math.sin(x) - 0.1, lambda x: 1.0 - 0.9 * math.cos(x), 0.0, 3.0),
    "cos_minus_x": (lambda x: math.cos(x) - x, lambda x: -math.sin(x) - 1.0, 0.0, 1.0),
    "steep_tanh": (lambda x: math.tanh(1e6 * (x - 0.3)), lambda x: 1e6 * (1.0 - math.tanh(1e6 * (x - 0.3)) ** 2),
                   -1.0, 2.0),
    "far_from_0": (lambda x: math.log(x / 1234.5), lambda x: 1.0 / x, 1000.0, 2000.0),
    "cubic": (lambda x: (x - 0.2) ** 3 + 0.5 * (x - 0.4), lambda x: 3.0 * (x - 0.2) ** 2 + 0.5, -0.6, 1.0),
}


@pytest.mark.parametrize("name", MONOTONE)
def test_newton_in_the_bracket_agrees_with_brentq_and_closes_it(name):
    f, df, lo, hi = MONOTONE[name]
    root, status, n, seen = _newton_root(f, df, lo, hi)
    ref = _brent(f, lo, hi, 0.0)
    tol = RTOL * abs(ref)
    assert status == R.CONVERGED
    last = seen[-1]
    # the bracket itself closed to the tolerance (not only the points converged), its ends of their signs
    assert abs(last.hi - last.lo) <= R.tolerance(last, last.hi) or f(last.hi) == 0.0
    assert f(last.hi) * f(hi) > 0.0 or f(last.hi) == 0.0
    assert abs(root - ref) <= 2 * tol
    assert n <= _bound(lo, hi, tol)
    for b in seen:  # every point evaluated strictly inside the bracket of its time
        assert b.status != R.RUNNING or min(b.lo, b.hi) < b.x < max(b.lo, b.hi)


@pytest.mark.parametrize("name", ["convex", "concave", "kepler", "cos_minus_x", "far_from_0", "cubic"])
def test_newton_in_the_bracket_takes_fewer_points_than_illinois(name):
    f, df, lo, hi = MONOTONE[name]
    n_newton = _newton_root(f, df, lo, hi)[2]
    n_illinois = R.find_root(f, lo, hi, rtol=RTOL)[2]
    assert n_newton < n_illinois


@settings(max_examples=100, deadline=None)
@given(seed=st.integers(0, 2**32 - 1))
def test_a_wrong_derivative_still_converges_within_the_safeguards_bound(seed):
    rng = random.Random(seed)
    f = lambda x: math.expm1(10.0 * (x - 0.3))  # noqa: E731
    lo, hi = -1.0, 3.0
    root, status, n, _ = _newton_root(f, lambda x: rng.uniform(-100.0, 100.0), lo, hi)
    tol = RTOL * 0.3
    assert status == R.CONVERGED and abs(root - 0.3) <= 2 * tol
    assert n <= _bound(lo, hi, tol)
