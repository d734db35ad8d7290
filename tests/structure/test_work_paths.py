"""The work quadrature's fast paths against the plain products and closed forms.

:func:`frictionflow.core.structure.work.accumulate` sums each element's power over the nonzeros of its
direction row (:data:`~frictionflow.core.structure.work.Pattern`, made from the Assembly), and takes z at
the Gauss nodes from a Taylor form about each subinterval's midpoint.  Here: the sparse sums against the
dense kernels (the same bits) and numpy's products on hand-made matrices, full and chain-sparse; z at the
nodes against the phase's closed form; and one phase's works against the spring's closed form
-k/2 [(e.q)^2] and the kinetic energy's change.
"""

from __future__ import annotations

import numpy as np
import pytest
from numba import njit

import frictionflow as ff
from frictionflow.core.layout import FD
from frictionflow.core.structure import work
from frictionflow.core.structure.combo import build
from frictionflow.core.structure.phase import modal_at, start, state_at

from .builders import assembly, chain

LAW = ff.Coulomb(fd=0.3, fs=0.4).kernel_params()


def full_model(seed: int = 3):
    """Three dofs, every matrix full: a full mass, springs, dampers, contacts and a force along random directions,
    normal loads that depend on every coordinate."""
    rng = np.random.default_rng(seed)
    a = rng.normal(size=(3, 3))
    rows = lambda count: [rng.normal(size=3) for _ in range(count)]  # noqa: E731
    contacts = [(e, 0.1 * (j + 1), LAW, [1.0, *(0.2 * rng.normal(size=3))]) for j, e in enumerate(rows(2))]
    return assembly(a @ a.T + 3.0 * np.eye(3), springs=[(e, 1.0 + i) for i, e in enumerate(rows(4))],
                    dampers=[(e, 0.05) for e in rows(2)], contacts=contacts,
                    forces=[(rng.normal(size=3), 0.3, 0.8, 0.2)], q0=0.1 * rng.normal(size=3))


def chain_model():
    """A chain of four masses (one nonzero or two per row, tridiagonal K and diagonal C), one force."""
    return chain(4, ff.Coulomb(fd=0.3, fs=0.4), belt=[0.1, 0.15, 0.05, 0.12], q0=[0.3, 0.0, -0.2, 0.1],
                 forces=[([0.0, 1.0, 0.0, 0.0], 0.2, 0.9, 0.3)])


def loaded_chain():
    """:func:`chain_model` with normal loads on other masses' coordinates and contact 0 along dofs 0 and 1: K_eff
    has nonzeros where K has none, in a row (1) that contact 1's held force uses when it sticks."""
    asm = chain_model()
    normal, cdir = asm.normal.copy(), asm.contact_dir.copy()
    normal[0, 1 + 3], normal[2, 1 + 0], normal[3, 1 + 1] = 0.3, -0.2, 0.1
    cdir[0, 1] = 0.5
    return asm._replace(normal=normal, contact_dir=cdir)


def unforced(asm):
    """``asm`` without its forces (a phase without harmonic terms: z at the nodes from the Taylor form)."""
    n = len(asm.q0)
    return asm._replace(force_amp=np.zeros(0), force_omega=np.zeros(0), force_phi=np.zeros(0), force_dir=np.zeros((0, n)))


def unforced_full():
    return unforced(full_model())


def unforced_chain():
    return unforced(chain_model())


@njit
def dense_forces(asm, cb, q, v, t):
    """The contacts' forces by plain loops over every coordinate (slipping: +-F_d N_j; stuck: HE (C q' + K_eff q -
    f0 - forces(t)))."""
    n, f = len(q), np.zeros(len(asm.belt))
    rest = np.empty(n)
    for i in range(n):
        x = -cb.f0[i]
        for b in range(n):
            x += asm.damping[i, b] * v[b] + cb.keff[i, b] * q[b]
        rest[i] = x
    for g in range(len(asm.force_amp)):
        c = asm.force_amp[g] * np.cos(asm.force_omega[g] * t + asm.force_phi[g])
        for i in range(n):
            rest[i] -= asm.force_dir[g, i] * c
    for j in range(len(f)):
        if cb.modes[j] != 0:
            nj = asm.normal[j, 0]
            for i in range(n):
                nj += asm.normal[j, 1 + i] * q[i]
            f[j] = cb.modes[j] * asm.law[j, FD] * nj
    for s in range(len(cb.stuck)):
        f[cb.stuck[s]] = work.dot_row(cb.HE, s, rest)
    return f


@njit
def both(asm, cb, q, v, t, room, dense, sparse):
    """Every channel's power and every contact's force at (q, q', t) by the dense loops and the sparse ones."""
    elastic = (asm.spring_k, asm.spring_dir, asm.damper_c, asm.damper_dir)
    forcing = (asm.force_amp, asm.force_omega, asm.force_phi, asm.force_dir)
    work.fill_assembly(asm, room)
    work.fill_combination(cb, room)
    f = dense_forces(asm, cb, q, v, t)
    c = work.element_powers(elastic, forcing, q, v, t, dense)
    work.contact_powers(asm.belt, asm.contact_dir, cb.modes, f, v, c, dense)
    room.q[:], room.v[:] = q, v
    c = work.sparse_element_powers(elastic, forcing, room.elements, q, v, t, sparse)
    work.sparse_slip_forces(asm.normal, asm.law, cb.modes, room.normal, q, room.f)
    work.sparse_held_forces(asm.damping, cb.keff, cb.f0, cb.HE, cb.stuck, forcing, room, q, v, t)
    work.sparse_contact_powers(asm.belt, asm.contact_dir, cb.modes, room.contact, room.f, v, c, sparse)
    return f, room.f.copy()


def numpy_powers(asm, cb, q, v, t):
    """The channels' powers from numpy products on the Assembly's matrices (the held forces as combo defines them)."""
    force = asm.force_amp * np.cos(asm.force_omega * t + asm.force_phi)
    n_load = asm.normal[:, 0] + asm.normal[:, 1:] @ q
    f = cb.modes * asm.law[:, FD] * n_load
    held = cb.HE @ (asm.damping @ v + cb.keff @ q - cb.f0 - asm.force_dir.T @ force)
    f[cb.stuck] = held
    vr = asm.belt - asm.contact_dir @ v
    heat = np.where(cb.modes == 0, 0.0, f * vr)
    return np.concatenate([-asm.spring_k * (asm.spring_dir @ q) * (asm.spring_dir @ v),
                           -asm.damper_c * (asm.damper_dir @ v) ** 2, force * (asm.force_dir @ v),
                           f * asm.belt, heat]), f


@pytest.mark.parametrize("make, modes", [(full_model, [1, 0]), (full_model, [-1, 1]), (chain_model, [1, 0, -1, 0]),
                                         (chain_model, [0, 0, 1, 1]), (loaded_chain, [1, 0, -1, 0]),
                                         (loaded_chain, [-1, 0, 1, 1])])
def test_sparse_rows_give_the_dense_sums(make, modes):
    asm = make()
    n, k = len(asm.q0), len(asm.belt)
    cb = build(asm, np.linalg.inv(asm.mass), np.array(modes, dtype=np.int8))
    rng = np.random.default_rng(5)
    nw = work.n_channels(asm)
    for _ in range(5):
        q, v, t = rng.normal(size=n), rng.normal(size=n), rng.uniform(0.0, 10.0)
        room, dense, sparse = work.new_room(nw, k, 2 * n, n), np.full(nw, np.nan), np.full(nw, np.nan)
        f_dense, f_sparse = both(asm, cb, q, v, t, room, dense, sparse)
        np.testing.assert_array_equal(sparse, dense)  # the nonzeros in the dense loop's order: the same bits
        np.testing.assert_array_equal(f_sparse, f_dense)
        expected, f = numpy_powers(asm, cb, q, v, t)
        np.testing.assert_allclose(sparse, expected, rtol=1e-13, atol=1e-13 * np.abs(expected).max())
        np.testing.assert_allclose(f_sparse, f, rtol=1e-13, atol=1e-13 * np.abs(f).max())


def test_chain_patterns_hold_only_the_nonzeros():
    """The patterns of a chain: a ground spring one dof, a coupling spring two, C and K_eff's rows three at most."""
    asm = chain_model()
    n, k = len(asm.q0), len(asm.belt)
    room = work.new_room(work.n_channels(asm), k, 2 * n, n)
    cb = build(asm, np.linalg.inv(asm.mass), np.array([1, 0, -1, 0], dtype=np.int8))
    both(asm, cb, asm.q0, asm.v0, 0.0, room, np.empty(work.n_channels(asm)), np.empty(work.n_channels(asm)))
    ns = len(asm.spring_k)
    counts = room.elements.count[:ns]
    np.testing.assert_array_equal(counts, (asm.spring_dir != 0).sum(axis=1))
    assert set(counts) == {1, 2}
    np.testing.assert_array_equal(room.held.count, ((asm.stiffness != 0) | (asm.damping != 0)).sum(axis=1))
    assert room.need.count[0] == 2  # the two stuck contacts' rows of HE use their own dof each
    assert room.normal.count.sum() == 0


@njit
def nodes_z(cb, ph, om, mid, half, nodes, zg):
    """z at the nodes by the Taylor form (no harmonic terms) or the closed form at each (harmonic terms)."""
    if ph.bh.shape[1]:
        work.harmonic_nodes(cb.lam, ph, om, mid, half, nodes, np.empty(len(cb.lam), dtype=np.complex128), zg)
    else:
        work.modal_nodes(cb.lam, ph, mid, half, nodes, zg)


@pytest.mark.parametrize("make, modes", [(full_model, [1, 0]), (chain_model, [1, 0, -1, 0]),
                                         (chain_model, [1, 1, 1, 1])])
@pytest.mark.parametrize("half", [0.01, 0.3, 2.0, 6.0])
def test_node_values_match_the_closed_form(make, modes, half):
    """z at the nodes mid + half x_g against the phase's closed form there (short and long stretches: the
    Taylor form, and the closed form where |lam s| >= 1), for every rule."""
    asm = unforced(make())
    cb = build(asm, np.linalg.inv(asm.mass), np.array(modes, dtype=np.int8))
    ph = start(cb, asm, asm.q0, np.full(len(asm.q0), 0.05), 1.5)
    om, mid = asm.force_omega, 0.7 + half
    for nodes in (work.NODES4, work.NODES6, work.NODES, work.NODES16, work.NODES32):
        zg = np.empty((len(work.NODES32), len(cb.lam)), dtype=np.complex128)
        nodes_z(cb, ph, om, mid, half, nodes, zg)
        for g, x in enumerate(nodes):
            exact = modal_at(cb, ph, om, mid + half * x)
            scale = np.abs(modal_at(cb, ph, om, mid)) + np.abs(exact)
            assert np.all(np.abs(zg[g, :len(cb.lam)] - exact) <= 1e-14 * scale)


@pytest.mark.parametrize("make, modes, span", [(full_model, [1, 0], 0.4), (full_model, [-1, 1], 9.0),
                                               (chain_model, [1, 0, -1, 0], 0.2), (chain_model, [0, 0, 1, 1], 30.0),
                                               (chain_model, [1, -1, 1, 1], 7.0), (unforced_full, [1, 0], 0.4),
                                               (unforced_full, [-1, 1], 9.0), (unforced_chain, [1, 0, -1, 0], 0.2),
                                               (unforced_chain, [0, 0, 1, 1], 30.0), (unforced_chain, [1, 1, 1, 1], 3.0)])
def test_phase_works_match_closed_forms(make, modes, span):
    """One phase's works: each spring's is -k/2 [(e.q)^2] between the ends, and the kinetic energy's change is the
    sum of the work on the structure (springs, dampers, forces, belt input less heat); with forces (z at each node
    from the closed form) and without (the Taylor form about each subinterval's midpoint)."""
    asm = make()
    n, ns, k = len(asm.q0), len(asm.spring_k), len(asm.belt)
    cb = build(asm, np.linalg.inv(asm.mass), np.array(modes, dtype=np.int8))
    q0, v0 = asm.q0, np.full(n, 0.05)
    for j in np.flatnonzero(cb.modes == 0):  # a stuck contact moves with its belt
        v0 = v0 + asm.contact_dir[j] * (asm.belt[j] - asm.contact_dir[j] @ v0) / (asm.contact_dir[j] @ asm.contact_dir[j])
    ph = start(cb, asm, q0, v0, 2.0)
    acc = np.zeros(work.n_channels(asm))
    work.integrate(asm, cb, ph, asm.force_omega, 0.0, span, acc)
    (qa, va), (qb, vb) = state_at(cb, ph, asm.force_omega, 0.0), state_at(cb, ph, asm.force_omega, span)
    springs = -0.5 * asm.spring_k * ((asm.spring_dir @ qb) ** 2 - (asm.spring_dir @ qa) ** 2)
    scale = np.abs(acc).sum() + 0.5 * vb @ asm.mass @ vb + 0.5 * va @ asm.mass @ va
    np.testing.assert_allclose(acc[:ns], springs, rtol=0, atol=1e-13 * scale)
    d_kinetic = 0.5 * vb @ asm.mass @ vb - 0.5 * va @ asm.mass @ va
    on_structure = acc[:-2 * k].sum() + acc[-2 * k:-k].sum() - acc[-k:].sum()
    assert abs(d_kinetic - on_structure) <= 1e-13 * scale
