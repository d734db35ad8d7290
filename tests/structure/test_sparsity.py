"""A combination's patterns of nonzeros (:mod:`frictionflow.core.structure.sparsity`) and the sums over them.

The patterns against numpy's nonzeros of Z and R, on a chain cut into pieces
by stuck masses (mostly zeros) and on a model whose every matrix is full (no
zeros: a pattern that missed one would change the sums); and the phase
start's and the state's sums over the patterns against plain dense loops
written here, which add every term in index order: the same bits (a skipped
term is an exact 0 x finite).
"""

from __future__ import annotations

import numpy as np
import pytest
from numba import njit

import frictionflow as ff
from frictionflow.core.structure import phase, sparsity
from frictionflow.core.structure.combo import build

from .builders import chain
from .test_work_paths import full_model, loaded_chain

CASES = [("chain", [1, 0, -1, 0, 1, 1, 0, -1]), ("chain", [1, 1, -1, 1, 1, -1, 1, 1]), ("full", [1, 0]),
         ("full", [-1, 1]), ("loaded", [1, 0, -1, 0])]


def cut_chain():
    """Eight masses on a belt: stuck masses cut it into pieces that do not couple."""
    return chain(8, ff.Coulomb(fd=0.3, fs=0.4), belt=[0.1, 0.15, 0.05, 0.12, 0.2, 0.08, 0.1, 0.03],
                 q0=[0.3, 0.0, -0.2, 0.1, 0.05, -0.1, 0.2, 0.0], forces=[([0.0, 1.0] + [0.0] * 6, 0.2, 0.9, 0.3)])


def combination(kind, modes):
    """(Assembly, Combo) of ``kind`` ("chain", "full" or "loaded") in ``modes``."""
    asm = {"chain": cut_chain, "full": full_model, "loaded": loaded_chain}[kind]()
    return asm, build(asm, np.linalg.inv(asm.mass), np.array(modes, dtype=np.int8))


def block(nz, b, count):
    """The ``count`` rows of block ``b`` as lists of indices."""
    first = nz[0, b]
    return [list(nz[first + i, 1:1 + nz[first + i, 0]]) for i in range(count)]


def nonzero_rows(a):
    """numpy's nonzero columns of each row of ``a``."""
    return [list(np.flatnonzero(row)) for row in a]


@pytest.mark.parametrize("kind, modes", CASES)
def test_patterns_hold_exactly_the_nonzeros(kind, modes):
    _, cb = combination(kind, modes)
    nz, ns = cb.nz, len(cb.stuck)
    assert block(nz, sparsity.ZC, cb.Z.shape[1]) == nonzero_rows(cb.Z.T)
    assert block(nz, sparsity.RC, ns) == nonzero_rows(cb.R.T)
    assert block(nz, sparsity.RU, 1) == [list(np.flatnonzero(np.any(cb.R != 0, axis=1)))]


def test_a_cut_chain_is_mostly_zeros_and_a_full_model_has_none():
    """The cases above test what they mean to: the cut chain's Z and R skip most coordinates, the full model's
    R none (its Z, a null-space basis of a full direction, is full too)."""
    _, cb = combination("chain", CASES[0][1])
    assert (cb.Z != 0).mean() < 0.5 and (cb.R != 0).mean() < 0.5
    _, full = combination("full", [1, 0])
    assert (full.R != 0).all() and (full.Z != 0).all()


@njit
def dense_state(cb, ph, tau, z, q, v):
    """Re(V z) through Z plus R (u0 + b_S tau), every product over all rows and columns."""
    n, r = cb.Z.shape
    q[:] = 0.0
    v[:] = 0.0
    for a in range(2 * r):
        x = 0.0
        for b in range(len(z)):
            x += (cb.V[a, b] * z[b]).real
        for i in range(n):
            if a < r:
                q[i] += cb.Z[i, a] * x
            else:
                v[i] += cb.Z[i, a - r] * x
    for s in range(len(ph.u0)):
        for i in range(n):
            q[i] += cb.R[i, s] * (ph.u0[s] + ph.bs[s] * tau)
            v[i] += cb.R[i, s] * ph.bs[s]


def dense_start(cb, asm, q, v):
    """(z0, b0, e0) of a phase from (q, q') by dense products summed in index order (:func:`.phase.start`)."""
    return _dense_start(cb, asm, q, v, np.zeros(len(cb.lam), dtype=np.complex128),
                        np.zeros(len(cb.lam), dtype=np.complex128), np.zeros(len(cb.D)))


@njit
def _dense_start(cb, asm, q, v, z0, b0, e0):
    n, ns, nr = len(q), len(cb.stuck), cb.Z.shape[1]
    u0, ru, f = np.zeros(ns), np.zeros(n), cb.f0.copy()
    for i in range(ns):
        for a in range(n):
            u0[i] += asm.contact_dir[cb.stuck[i], a] * q[a]
    for i in range(n):
        s = 0.0
        for a in range(ns):
            s += cb.R[i, a] * u0[a]
        ru[i] += s
    for i in range(n):
        s, t = 0.0, 0.0
        for a in range(n):
            s += asm.damping[i, a] * cb.rb[a]
        f[i] -= s
        for a in range(n):
            t += cb.keff[i, a] * ru[a]
        f[i] -= t
    x, p0 = np.zeros(2 * nr), np.zeros(nr)
    for c in range(nr):
        for a in range(n):
            x[c] += cb.ZT[c, a] * (q[a] - ru[a])
            x[nr + c] += cb.ZT[c, a] * (v[a] - cb.rb[a])
            p0[c] += cb.ZT[c, a] * f[a]
    for m in range(len(z0)):
        s, t = 0.0j, 0.0j
        for a in range(2 * nr):
            s += cb.Vi[m, a] * x[a]
        for a in range(nr):
            t += cb.VB[m, a] * p0[a]
        z0[m], b0[m] = s, t
    for e in range(len(e0)):
        s = 0.0
        for a in range(n):
            s += cb.D[e, a] * ru[a] + cb.D[e, n + a] * cb.rb[a]
        e0[e] = cb.dc[e] + s
    return z0, b0, e0


@pytest.mark.parametrize("kind, modes", CASES)
def test_sums_over_the_patterns_are_the_dense_sums_bit_for_bit(kind, modes):
    asm, cb = combination(kind, modes)
    om = asm.force_omega
    rng = np.random.default_rng(11)
    for _ in range(4):
        q, v, t0, tau = rng.normal(size=len(asm.q0)), rng.normal(size=len(asm.q0)), rng.uniform(0, 9), rng.uniform(0, 2)
        ph = phase.start(cb, asm, q, v, t0)
        for got, want in zip((ph.z0, ph.b0, ph.e0), dense_start(cb, asm, q, v)):
            np.testing.assert_array_equal(got, want)
        qs, vs = phase.state_at(cb, ph, om, tau)
        qd, vd = np.empty_like(qs), np.empty_like(vs)
        dense_state(cb, ph, tau, phase.modal_at(cb, ph, om, tau), qd, vd)
        np.testing.assert_array_equal(qs, qd)
        np.testing.assert_array_equal(vs, vd)
