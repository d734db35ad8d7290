"""A combination that keeps one root of each conjugate pair against the full first-order solution.

On the real-mode route a combination keeps one root of each underdamped mode's pair, its columns of V
and W doubled (:mod:`frictionflow.core.structure.combo`).  Here a phase of a chain with Rayleigh damping
(underdamped and overdamped modes), harmonic forces and stuck contacts is evaluated by the engine and,
independently, by the matrix exponential of the reduced first-order system augmented with the constant,
the time and the forces' oscillators, assembled with numpy from the definitions (scipy's expm).
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.linalg import expm, null_space

from frictionflow import Coulomb
from frictionflow.core.layout import FD, STICK
from frictionflow.core.structure.combo import build
from frictionflow.core.structure.events import values
from frictionflow.core.structure.phase import Mags, bound, modal_at, rates_into, start, state_at

from .builders import assembly

T0 = 0.7
TAUS = (0.0, 0.3, 1.1, 2.5, 6.0)


def rayleigh_chain(n, alpha, beta, k_couple, full_mass=False):
    """n masses on ground springs (k = 1) coupled by springs ``k_couple``, C = alpha M + beta K, two forces."""
    eye = np.eye(n)
    mass = np.diag(1.0 + 0.1 * np.arange(n))
    if full_mass:
        mass = mass + 0.05 * (np.eye(n, k=1) + np.eye(n, k=-1))
    springs = [(e, 1.0) for e in eye] + [(eye[i] - eye[i + 1], k_couple) for i in range(n - 1)]
    p = Coulomb(0.2, 0.4).kernel_params()
    forces = [(eye[1], 0.3, 0.9, 0.4), (eye[n - 1], 0.2, 2.3, -1.0)]
    asm = assembly(mass, springs=springs, contacts=[(eye[i], 0.1 + 0.02 * i, p, None) for i in range(n)],
                   forces=forces)
    return asm._replace(damping=alpha * asm.mass + beta * asm.stiffness)


def reference_states(asm, modes, q0, v0, taus):
    """(q, q') at each tau from the full first-order system: expm of the augmented generator, no modal split."""
    n = len(q0)
    stuck = np.nonzero(modes == STICK)[0]
    e = asm.contact_dir[stuck]
    z = null_space(e) if len(stuck) else np.eye(n)  # any orthonormal basis: q does not depend on it
    mi = np.linalg.inv(asm.mass)
    r = mi @ e.T @ np.linalg.inv(e @ mi @ e.T) if len(stuck) else np.zeros((n, 0))
    bs, u0 = asm.belt[stuck], e @ q0
    f0 = sum(modes[j] * asm.law[j, FD] * asm.normal[j, 0] * asm.contact_dir[j] for j in range(len(modes))
             if modes[j] != STICK)
    k, c = asm.stiffness, asm.damping  # constant normal loads: K_eff = K
    nr, nf = z.shape[1], len(asm.force_amp)
    mr_inv = np.linalg.inv(z.T @ asm.mass @ z)
    size = 2 * nr + 2 + 2 * nf  # (y, y', 1, tau, cos_i, sin_i)
    g = np.zeros((size, size))
    g[:nr, nr:2 * nr] = np.eye(nr)
    g[nr:2 * nr, :nr] = -mr_inv @ z.T @ k @ z
    g[nr:2 * nr, nr:2 * nr] = -mr_inv @ z.T @ c @ z
    g[nr:2 * nr, 2 * nr] = mr_inv @ z.T @ (f0 - c @ r @ bs - k @ r @ u0)
    g[nr:2 * nr, 2 * nr + 1] = mr_inv @ z.T @ (-k @ r @ bs)
    g[2 * nr + 1, 2 * nr] = 1.0
    for i in range(nf):
        ci, si, om = 2 * nr + 2 + 2 * i, 2 * nr + 3 + 2 * i, asm.force_omega[i]
        g[nr:2 * nr, ci] = mr_inv @ z.T @ (asm.force_amp[i] * asm.force_dir[i])
        g[ci, si], g[si, ci] = -om, om
    x0 = np.concatenate((z.T @ (q0 - r @ u0), z.T @ (v0 - r @ bs), [1.0, 0.0],
                         np.ravel([(np.cos(w * T0 + p), np.sin(w * T0 + p))
                                   for w, p in zip(asm.force_omega, asm.force_phi)])))
    out = []
    for tau in taus:
        x = expm(g * tau) @ x0
        out.append((z @ x[:nr] + r @ (u0 + bs * tau), z @ x[nr:2 * nr] + r @ bs))
    return out


def start_state(asm, modes, seed):
    """A random (q, q') whose stuck contacts move with their belts."""
    rng = np.random.default_rng(seed)
    n = asm.mass.shape[0]
    q0, v0 = rng.normal(scale=0.3, size=n), rng.normal(scale=0.3, size=n)
    for j in np.nonzero(modes == STICK)[0]:
        v0[np.argmax(asm.contact_dir[j])] = asm.belt[j]
    return q0, v0


CASES = {
    "all slipping": (np.array([1, -1, 1, 1, -1], dtype=np.int8), False),
    "two stuck": (np.array([1, 0, -1, 0, 1], dtype=np.int8), False),
    "full mass, one stuck": (np.array([-1, 1, 0, 1, 1], dtype=np.int8), True),
}


@pytest.mark.parametrize("case", CASES)
def test_paired_phase_equals_the_full_first_order_solution(case):
    """States and event functions of a phase with under- and overdamped modes, forced, against expm."""
    modes, full = CASES[case]
    asm = rayleigh_chain(5, 0.05, 1.0, 3.0, full_mass=full)
    cb = build(asm, np.linalg.inv(asm.mass), modes)
    nr = cb.Z.shape[1]
    under = int(np.sum(cb.lam.imag != 0.0))  # one root per underdamped mode, both of each overdamped one
    assert 0 < under < nr and len(cb.lam) == under + 2 * (nr - under)
    q0, v0 = start_state(asm, modes, 11)
    ph = start(cb, asm, q0, v0, T0)
    om = asm.force_omega
    for tau, (q_ref, v_ref) in zip(TAUS, reference_states(asm, modes, q0, v0, TAUS)):
        q, v = state_at(cb, ph, om, tau)
        scale = np.abs(np.concatenate((q_ref, v_ref))).max()
        assert np.abs(q - q_ref).max() < 1e-12 * scale and np.abs(v - v_ref).max() < 1e-12 * scale
        g = np.zeros(len(cb.dc))
        values(cb, ph, om, tau, modal_at(cb, ph, om, tau), g)
        t = T0 + tau
        g_ref = cb.D @ np.concatenate((q_ref, v_ref)) + cb.dc + cb.Dh @ np.cos(om * t + asm.force_phi)
        assert np.abs(g - g_ref)[cb.active].max() < 1e-12 * (np.abs(cb.D).max() * scale + np.abs(cb.dc).max())


def test_paired_second_derivative_bound_holds():
    """The walk's bound on |g''| over an interval holds for the full solution's g'' (differences of expm)."""
    modes = CASES["two stuck"][0]
    asm = rayleigh_chain(5, 0.05, 1.0, 3.0)
    cb = build(asm, np.linalg.inv(asm.mass), modes)
    q0, v0 = start_state(asm, modes, 5)
    ph = start(cb, asm, q0, v0, T0)
    om, a, h, d = asm.force_omega, 0.4, 0.5, 1e-3
    mg = moduli(cb, ph, om, a)
    g2 = second_derivative_maxima(asm, cb, modes, (q0, v0), a, h, d)
    for e in np.nonzero(cb.active)[0]:
        assert g2[e] <= bound(cb, om, e, a, h, mg, 2)


def moduli(cb, ph, om: np.ndarray, a: float) -> Mags:
    """The walk's moduli for an interval from ``a``: |z(a)|, the phase's, and its decaying modes' rates at 0."""
    m = len(cb.lam)
    mg = Mags(np.abs(modal_at(cb, ph, om, a)), np.abs(ph.b0), np.abs(ph.b1), np.abs(ph.bh), np.abs(cb.lam),
              np.zeros(m), np.zeros(m))
    rates_into(cb, ph, om, mg)
    return mg


def second_derivative_maxima(asm, cb, modes, start, a, h, d=1e-3):
    """max |g_e''| over [a, a + h] for every event function: central differences (step ``d``) of g from
    :func:`reference_states` (expm of the full first-order system) from the phase's ``start`` = (q0, q0')."""
    taus = np.arange(a + d, a + h - d / 2, d)
    grid = reference_states(asm, modes, *start, np.concatenate((taus - d, taus, taus + d)))
    g = np.array([cb.D @ np.concatenate(s) + cb.dc for s in grid])
    g += np.cos(np.outer(T0 + np.concatenate((taus - d, taus, taus + d)), asm.force_omega) + asm.force_phi) @ cb.Dh.T
    m = len(taus)
    return np.abs(g[:m] - 2.0 * g[m:2 * m] + g[2 * m:]).max(axis=0) / d ** 2


def test_the_general_route_keeps_every_root():
    """Damping on one mass only couples the modes: eig's roots, all 2 r of them."""
    asm = rayleigh_chain(4, 0.0, 0.0, 1.0)
    asm = asm._replace(damping=np.diag([0.3, 0.0, 0.0, 0.0]))
    cb = build(asm, np.linalg.inv(asm.mass), np.array([1, 1, 0, -1], dtype=np.int8))
    assert len(cb.lam) == 2 * cb.Z.shape[1] and cb.V.shape == (2 * cb.Z.shape[1], len(cb.lam))
