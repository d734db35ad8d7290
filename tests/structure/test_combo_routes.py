"""A combination's shortcuts against the general formulas, assembled with numpy by hand.

Stuck directions along coordinate axes (no SVD), symmetric problems split into their
uncoupled blocks, the event maps W = D T V from the real modes, and the run's cache.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.linalg import expm

from frictionflow import Coulomb
from frictionflow.core.layout import FD, FS, RESULTANT
from frictionflow.core.structure.combo import N_SLOTS, block_eigh, build, constraint_split, lookup, new_cache, split

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
    z, r, he = constraint_split(asm.contact_dir, np.linalg.inv(mass), idx)
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


def _loaded_structure(mass):
    """Four masses on scaled, signed axis contacts, two with q-dependent normal loads, two harmonic forces."""
    eye = np.eye(4)
    dirs = [2.0 * eye[0], -eye[1], 0.5 * eye[2], eye[3]]
    normals = [[1.5, 0.2, 0.0, 0.0, 0.0], None, [0.8, 0.0, -0.1, 0.3, 0.0], None]
    p = Coulomb(0.2, 0.4).kernel_params()
    springs = [(e, 1.0 + i) for i, e in enumerate(eye)] + [(eye[i] - eye[i + 1], 0.5) for i in range(3)]
    dampers = [(e, 0.03 * (i + 1)) for i, e in enumerate(eye)] + [(eye[0] - eye[1], 0.02)]
    forces = [(np.array([1.0, 0.0, -0.5, 0.0]), 0.3, 1.1, 0.2), (eye[3], -0.7, 0.6, 0.0)]
    contacts = [(d, 0.1 * (i + 1), p, nl) for i, (d, nl) in enumerate(zip(dirs, normals))]
    return assembly(mass, springs=springs, dampers=dampers, contacts=contacts, forces=forces)


@pytest.mark.parametrize("full_mass", [False, True])
@pytest.mark.parametrize("modes", [[0, 1, 0, -1], [1, 0, -1, 0], [0, 0, 0, 1]])
def test_split_and_held_rows_like_the_definitions(full_mass, modes):
    """K_eff, f0, R, HE of the stick rule's split and the stuck contacts' event rows F_s N -+ lambda,
    lambda = HE (C q' + K_eff q - f0 - forces), against numpy on the hand-assembled matrices."""
    rng = np.random.default_rng(5)
    a = rng.normal(size=(4, 4))
    asm = _loaded_structure(a @ a.T + 4 * np.eye(4) if full_mass else [1.0, 2.0, 0.5, 1.5])
    modes = np.array(modes, dtype=np.int8)
    stuck = np.nonzero(modes == 0)[0]
    keff, f0 = asm.stiffness.copy(), np.zeros(4)
    for j in np.nonzero(modes != 0)[0]:
        fd = modes[j] * asm.law[j, FD]
        keff -= fd * np.outer(asm.contact_dir[j], asm.normal[j, 1:])
        f0 += fd * asm.normal[j, 0] * asm.contact_dir[j]
    r, he = _general_split(asm, stuck)
    sp = split(asm, np.linalg.inv(asm.mass), modes)
    assert sp.keff == pytest.approx(keff, abs=1e-14) and sp.f0 == pytest.approx(f0, abs=1e-14)
    assert sp.R == pytest.approx(r, abs=1e-13) and sp.HE == pytest.approx(he, abs=1e-13)
    cb = build(asm, np.linalg.inv(asm.mass), modes)
    for i, j in enumerate(stuck):
        fs, damped = asm.law[j, FS], asm.law[j, RESULTANT] != 0.0
        for side, sg in ((0, -1.0), (1, 1.0)):
            e = N_SLOTS * j + side
            assert cb.active[e]
            assert cb.D[e, :4] == pytest.approx(fs * asm.normal[j, 1:] + sg * he[i] @ keff, abs=1e-13)
            assert cb.D[e, 4:] == pytest.approx(sg * he[i] @ asm.damping if damped else np.zeros(4), abs=1e-13)
            assert cb.dc[e] == pytest.approx(fs * asm.normal[j, 0] - sg * he[i] @ f0, abs=1e-13)
            assert cb.Dh[e] == pytest.approx(-sg * (asm.force_dir @ he[i]) * asm.force_amp, abs=1e-13)
