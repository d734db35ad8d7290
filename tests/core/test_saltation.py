"""Saltation stated once (core.saltation): against maps derived here, and the tangent integrator's closed forms held to it."""

from __future__ import annotations


import numpy as np
import pytest

from frictionflow import BeltOscillator, Coulomb
from frictionflow.core import saltation as salt
from frictionflow.core import tangent
from frictionflow.core.friction import external_force_rate
from frictionflow.solvers.base import kernel_params


def _two_field_map(y0, lam, f_minus, f_plus, g, T):
    """y(T) for y' = f- until h = y[0] + g t - lam reaches 0, then y' = f+ (constant fields: exact)."""
    t_star = (lam - y0[0]) / (f_minus[0] + g)
    return y0 + f_minus * t_star + f_plus * (T - t_star)


@pytest.mark.parametrize("n", [2, 3, 5])
def test_apply_is_the_jacobian_of_a_crossing_derived_here(n):
    rng = np.random.default_rng(n)
    f_minus, f_plus = rng.uniform(0.5, 1.5, n), rng.normal(size=n)
    g, lam, T = 0.3, 1.0, 5.0
    y0 = np.zeros(n)
    # d y(T) / d (y0, lam), derived by hand from _two_field_map
    den = f_minus[0] + g
    exact = np.eye(n, n + 1)
    exact[:, 0] -= (f_minus - f_plus) / den
    exact[:, n] = (f_minus - f_plus) / den
    cols = np.eye(n, n + 1)
    h_par = np.zeros(n + 1)
    h_par[n] = -1.0  # dh/dlam
    assert salt.apply(cols, f_minus, f_plus, np.eye(n)[0], g, h_par)
    # the columns after the switch, carried by the constant field f+ (identity): the map's jacobian
    np.testing.assert_allclose(cols, exact, rtol=1e-14, atol=1e-15)
    # and a finite difference of the map itself (independent of any formula)
    eps = 1e-6
    for c in range(n):
        d = np.zeros(n)
        d[c] = eps
        fd = (_two_field_map(y0 + d, lam, f_minus, f_plus, g, T) - _two_field_map(y0 - d, lam, f_minus, f_plus, g, T)) / (2 * eps)
        np.testing.assert_allclose(cols[:, c], fd, rtol=1e-8, atol=1e-9)


def test_matrix_is_the_textbook_form_and_nan_at_grazing():
    rng = np.random.default_rng(1)
    fb, fa, nrm = rng.normal(size=4), rng.normal(size=4), rng.normal(size=4)
    np.testing.assert_allclose(salt.matrix(fb, fa, nrm), np.eye(4) + np.outer(fa - fb, nrm) / (nrm @ fb), rtol=1e-13)
    assert np.isnan(salt.matrix(np.array([1.0, 0.0]), np.array([0.0, 1.0]), np.array([0.0, 1.0]))).all()
    assert not salt.apply(np.eye(2), np.array([1.0, 0.0]), np.array([0.0, 1.0]), np.array([0.0, 1.0]), 0.0, np.zeros(2))


FORCED = BeltOscillator(0.05, 0.3, fex=0.2, omega=0.8, phi=0.4)
P = kernel_params(FORCED, Coulomb(0.3, 0.5))


def _tangent_state():
    return np.array([0.31, 0.3, 0.7, -0.4, -1.3, 2.1])


def _general(y, f_minus, f_plus, normal, h_t):
    cols = np.array([[y[2], y[4]], [y[3], y[5]]])
    assert salt.apply(cols, f_minus, f_plus, normal, h_t, np.zeros(2))
    return cols


@pytest.mark.parametrize("t", [0.0, 1.7, 4.2])
def test_the_tangent_integrators_closed_forms_are_the_general_rule(t):
    zeta, vb = FORCED.zeta, FORCED.vb
    x = _tangent_state()[0]
    a = {d: tangent._a_rest(d, x, t, zeta, vb, P) for d in (-1.0, 1.0)}
    cases = {
        # stick onset at V = V_b: surface V - V_b, into X' = V_b, X'' = 0
        "stick": (lambda y: tangent.saltation_stick(y), (np.array([vb, a[1.0]]), np.array([vb, 0.0]), np.array([0.0, 1.0]), 0.0)),
        # slip onset: the held force reaches F_s, surface X + ... - f(t) = const, moving with f(t)
        "slip": (lambda y: tangent.saltation_slip(y, 1, t, zeta, vb, P),
                 (np.array([vb, 0.0]), np.array([vb, a[1.0]]), np.array([1.0, 0.0]), -external_force_rate(P, t))),
        # slip reversal through V_r = 0: the field's X'' jumps from one slip direction's to the other's
        "reversal": (lambda y: tangent.saltation_reversal(y, -1.0, 1, t, zeta, vb, P),
                     (np.array([vb, a[-1.0]]), np.array([vb, a[1.0]]), np.array([0.0, 1.0]), 0.0)),
    }
    for name, (closed, general) in cases.items():
        y = _tangent_state()
        want = _general(y, *general)
        closed(y)
        got = np.array([[y[2], y[4]], [y[3], y[5]]])
        np.testing.assert_allclose(got, want, rtol=1e-14, atol=1e-15, err_msg=name)
