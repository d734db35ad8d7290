"""Saltation matrices and phase Jacobians: the building blocks of the monodromy matrix."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.linalg import expm

from frictionflow.core import closed_form as cf
from frictionflow.orbits.flow_exact import phase_jacobian
from frictionflow.orbits.hybrid import saltation


def test_entering_stick_forgets_velocity_perturbations():
    # slip (X'' = a) onto the surface X' = V_b, then stick (X'' = 0): S = diag(1, 0)
    vb, a = 0.01, -0.013
    S = saltation(np.array([vb, a]), np.array([vb, 0.0]), np.array([0.0, 1.0]))
    np.testing.assert_allclose(S, [[1.0, 0.0], [0.0, 0.0]], atol=1e-15)


def test_saltation_maps_a_perturbed_crossing_onto_the_perturbed_trajectory():
    # Two straight-line flows meeting on a tilted line h = n . y - c = 0: follow a
    # perturbed start exactly and compare with S times the perturbation.
    f1, f2, n, c = np.array([1.0, 0.3]), np.array([0.2, -0.7]), np.array([0.6, 0.8]), 1.0
    y_hit = np.array([1.0, 0.5])  # on the line: 0.6 + 0.4 = 1
    T_after = 0.3

    def flow(y0):
        t_hit = (c - n @ y0) / (n @ f1)
        return y0 + t_hit * f1 + (T_total - t_hit) * f2

    y0 = y_hit - 0.5 * f1
    T_total = 0.5 + T_after
    d = np.array([1e-6, -2e-6])
    exact = (flow(y0 + d) - flow(y0)) / 1.0
    S = saltation(f1, f2, n)
    np.testing.assert_allclose(exact, S @ d, rtol=1e-9, atol=1e-18)


def test_tangential_crossing_is_refused():
    with pytest.raises(ZeroDivisionError):
        saltation(np.array([1.0, 0.0]), np.array([1.0, 1.0]), np.array([0.0, 1.0]))


@pytest.mark.parametrize("zeta", [0.0, 0.05, 1.0, 2.5])
@pytest.mark.parametrize("dyn", [cf.OSC, cf.LIN, cf.EXP])
def test_phase_jacobian_is_the_matrix_exponential(dyn, zeta):
    A = {cf.OSC: [[0, 1], [-1, -2 * zeta]], cf.LIN: [[0, 1], [0, 0]], cf.EXP: [[0, 1], [0, -2 * zeta]]}[dyn]
    for t in (0.0, 0.3, 4.0):
        np.testing.assert_allclose(phase_jacobian(dyn, zeta, t), expm(np.array(A, float) * t), rtol=1e-12, atol=1e-13)
