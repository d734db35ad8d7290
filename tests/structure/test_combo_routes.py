"""A combination's shortcuts against the general formulas, assembled with numpy by hand.

Stuck directions along coordinate axes (no SVD), symmetric problems split into their
uncoupled blocks, the event maps W = D T V from the real modes, and the run's cache.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.linalg import expm

from frictionflow import Coulomb
from frictionflow.core.structure.combo import block_eigh, build, constraint_split, lookup, new_cache

from .builders import assembly, chain


def _general_split(asm, stuck):
    """Z (any orthonormal null-space basis), R, HE from the definitions."""
    e = asm.contact_dir[stuck]
    mi = np.linalg.inv(asm.mass)
    r = mi @ e.T @ np.linalg.inv(e @ mi @ e.T)
    return r, r.T


@pytest.mark.parametrize("stuck", [[0], [1, 3], [3, 0, 2]])
def test_stuck_axes_split_like_the_definitions(stuck):
    """Scaled, signed axes and a full (non-diagonal) mass matrix: E R = I, Z^T M R = 0, Z spans E's null space."""
    rng = np.random.default_rng(7)
    a = rng.normal(size=(4, 4))
    mass = a @ a.T + 4 * np.eye(4)
    dirs = [2.0 * np.eye(4)[0], -np.eye(4)[1], 0.5 * np.eye(4)[2], np.eye(4)[3]]
    p = Coulomb(0.2, 0.4).kernel_params()
    asm = assembly(mass, springs=[(e, 1.0) for e in np.eye(4)], contacts=[(d, 0.1, p, None) for d in dirs])
    idx = np.array(stuck)
    z, r, he = constraint_split(asm, np.linalg.inv(mass), idx)
    r_ref, he_ref = _general_split(asm, idx)
    e = asm.contact_dir[idx]
    assert r == pytest.approx(r_ref, abs=1e-13)
    assert he == pytest.approx(he_ref, abs=1e-13)
    assert z.T @ z == pytest.approx(np.eye(4 - len(stuck)), abs=0)
    assert np.abs(e @ z).max() == 0.0
    assert np.abs(z.T @ mass @ r).max() < 1e-13


def test_block_eigh_matches_numpy_on_a_permuted_block_matrix():
    """Three uncoupled blocks (sizes 1, 2, 3) interleaved by a permutation: the same spectrum as numpy's eigh."""
    rng = np.random.default_rng(3)
    blocks = [rng.normal(size=(s, s)) for s in (1, 2, 3)]
    full = np.zeros((6, 6))
    at = 0
    for b in blocks:
        s = len(b)
        full[at:at + s, at:at + s] = b + b.T
        at += s
    perm = rng.permutation(6)
    sym = full[np.ix_(perm, perm)]
    w, u = block_eigh(sym)
    assert np.sort(w) == pytest.approx(np.linalg.eigvalsh(sym), abs=1e-13)
    assert u.T @ u == pytest.approx(np.eye(6), abs=1e-14)
    assert u @ np.diag(w) @ u.T == pytest.approx(sym, abs=1e-13)


@pytest.mark.parametrize("modes", [[0, 1, 0, -1, 0, 0, 1], [1, 1, -1, 1, -1, 1, 1], [0, 0, 0, 0, 0, 0, 1]])
def test_event_maps_are_d_t_v(modes):
    """W = D T V (T: (y, y') -> (q, q')) on the active slots, and Re(V diag(e^{lam t}) V^-1 x) = e^{A t} x for
    real x (A the reduced first-order matrix; one root of each conjugate pair kept, its column of V doubled)."""
    asm = chain(7, Coulomb(0.2, 0.4), 0.1, c=0.04)
    cb = build(asm, np.linalg.inv(asm.mass), np.array(modes, dtype=np.int8))
    z, r = cb.Z, cb.Z.shape[1]
    t = np.block([[z, np.zeros_like(z)], [np.zeros_like(z), z]])
    w = cb.D @ t @ cb.V
    assert cb.W[cb.active] == pytest.approx(w[cb.active], abs=1e-13)
    assert cb.WA == pytest.approx(np.abs(cb.W), rel=1e-15, abs=0)  # (numba's hypot and numpy's: an ulp apart)
    mr, kr, cr = z.T @ asm.mass @ z, z.T @ cb.keff @ z, z.T @ asm.damping @ z
    a = np.block([[np.zeros((r, r)), np.eye(r)], [-np.linalg.solve(mr, kr), -np.linalg.solve(mr, cr)]])
    x = np.random.default_rng(1).normal(size=(2 * r, 3))
    for tau in (0.0, 0.4, 3.0):
        flow = (cb.V @ np.diag(np.exp(cb.lam * tau)) @ cb.Vi @ x).real
        assert flow == pytest.approx(expm(a * tau) @ x, abs=1e-12)
    assert cb.VB == pytest.approx(cb.Vi[:, r:] @ np.linalg.inv(mr), abs=1e-13)


def test_the_cache_returns_the_combination_asked_for():
    asm = chain(5, Coulomb(0.2, 0.4), 0.1)
    minv = np.linalg.inv(asm.mass)
    cache = new_cache(asm, minv)
    rng = np.random.default_rng(2)
    asked = [rng.choice(np.array([-1, 0, 1], dtype=np.int8), 5) for _ in range(12)]
    for modes in asked + asked[::-1]:
        cb = lookup(cache, asm, minv, modes)
        fresh = build(asm, minv, modes)
        assert np.array_equal(cb.modes, modes)
        assert np.array_equal(cb.W, fresh.W) and np.array_equal(cb.Vi, fresh.Vi)
    assert cache.used[0] == len({tuple(m) for m in asked} | {(0,) * 5})
