"""A combination's eigen-decomposition against numpy's on the first-order matrix assembled by hand.

Classically damped reduced systems (C_r = a M_r + b K_r, K_r symmetric) take the real-mode route of
:func:`frictionflow.core.structure.combo.classical`; coupled damping or a non-symmetric K_eff the general
one.  Either must give A = V diag(lam) V^-1 with A = [[0, I], [-M_r^-1 K_r, -M_r^-1 C_r]].
"""

from __future__ import annotations

import numpy as np
import pytest

from frictionflow.core.structure.combo import classical as classical_with, modal, new_eigs


def _spd(rng, n):
    a = rng.normal(size=(n, n))
    return a @ a.T + n * np.eye(n)


def _first_order(m, c, k):
    n = m.shape[0]
    mi = np.linalg.inv(m)
    return np.block([[np.zeros((n, n)), np.eye(n)], [-mi @ k, -mi @ c]])


def classical(mr, kr, cr):
    """:func:`~frictionflow.core.structure.combo.classical` with an eigen-block cache of its own, as a run's builder
    calls it (one compilation of its tree, not a second one without a cache)."""
    return classical_with(mr, kr, cr, new_eigs())


def _check(m, c, k, z):
    lam, v, vi, vb = modal(m, c, k, z)
    a = _first_order(z.T @ m @ z, z.T @ c @ z, z.T @ k @ z)
    expected = np.linalg.eigvals(a)
    assert np.sort_complex(np.round(lam, 12)) == pytest.approx(np.sort_complex(np.round(expected, 12)), abs=1e-10)
    assert v @ np.diag(lam) @ vi == pytest.approx(a, abs=1e-11)
    assert vi @ v == pytest.approx(np.eye(len(lam)), abs=1e-12)
    r = z.shape[1]
    assert vb == pytest.approx(vi[:, r:] @ np.linalg.inv(z.T @ m @ z), abs=1e-12)


@pytest.mark.parametrize("alpha,beta", [(0.0, 0.0), (0.05, 0.0), (0.02, 0.03), (3.0, 0.5)])
def test_rayleigh_damping_takes_the_real_modes(alpha, beta):
    """C = alpha M + beta K: under-, over-damped and undamped modes, on a constraint's null space too."""
    rng = np.random.default_rng(4)
    m, k = _spd(rng, 5), _spd(rng, 5)
    c = alpha * m + beta * k
    z_full = np.eye(5)
    # an orthonormal null space of two directions, C-ordered like every Z the engine makes (a second array layout
    # would compile the builder's tree once more, for nothing)
    z_sub = np.ascontiguousarray(np.linalg.svd(rng.normal(size=(2, 5)))[2][2:].T)
    for z in (z_full, z_sub):
        mr, kr, cr = z.T @ m @ z, z.T @ k @ z, z.T @ c @ z
        assert classical(mr, kr, cr).real
        _check(m, c, k, z)


def test_coupled_damping_and_nonsymmetric_stiffness_take_the_general_route():
    rng = np.random.default_rng(5)
    m, k = _spd(rng, 4), _spd(rng, 4)
    c = np.diag([0.1, 0.0, 0.3, 0.0])  # not a combination of M and K: couples the modes
    assert not classical(m, k, c).real
    _check(m, c, k, np.eye(4))
    kn = k.copy()
    kn[0, 1] += 0.2  # a normal load depending on q makes K_eff non-symmetric
    assert not classical(m, kn, 0.1 * m).real
    _check(m, 0.1 * m, kn, np.eye(4))


def test_an_undamped_rigid_mode_is_refused_on_both_routes():
    m, k = np.eye(2), np.array([[1.0, -1.0], [-1.0, 1.0]])  # a free translation: a double root at 0
    with pytest.raises(ValueError, match="defective"):
        modal(m, np.zeros((2, 2)), k, np.eye(2))
