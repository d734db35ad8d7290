"""The reference integrator of issue 22 (tests/structure/reference.py) checked on its own.

(a) one dof against the package's exact single-mass solver (``simulate`` with
Coulomb and ``Exact``): switch times, modes, states and forces; (b) two
masses in pure sliding (a linear ODE with constant and harmonic forces, with a
normal load linear in q) against the matrix exponential of the augmented
system; (c) the energy balance from its own work channels; (d) its
convergence in rtol on a chain with stick-slip of both masses; ties
(identical uncoupled masses), uncoupled masses each as its single mass, the
stick decision against a saddle-point solve, and a contact loss at the
closed form's root.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.linalg import expm
from scipy.optimize import brentq

from frictionflow import BeltOscillator, Coulomb, Exact, simulate
from frictionflow.core import layout

from . import reference as ref
from .chains import Elements, build, chain, single_mass

#: (zeta, V_b, law, x0, v0, forcing (F_ex, Omega, phi) or None)
SINGLE = {
    "paper stick-slip": (0.05, 0.01, Coulomb(0.02, 0.04), 0.02, 0.01, None),
    "spring rule, slip- first": (0.05, 0.3, Coulomb(0.2, 0.4, stick_force="spring"), 1.0, 0.0, None),
    "fs = fd, negative belt": (0.1, -0.05, Coulomb(0.1), -0.5, 0.0, None),
    "forced stick-slip": (0.02, 0.1, Coulomb(0.2, 0.3), 0.0, 0.1, (0.15, 0.9, 0.3)),
    "forced, spring rule": (0.03, 0.05, Coulomb(0.1, 0.25, stick_force="spring"), 0.3, -0.2, (0.3, 1.3, -1.0)),
}


@pytest.mark.parametrize("case", list(SINGLE))
def test_one_dof_against_exact_single_mass(case):
    zeta, vb, law, x0, v0, forcing = SINGLE[case]
    fex, omega, phi = forcing or (0.0, 1.0, 0.0)
    exact = simulate(BeltOscillator(zeta, vb, fex=fex, omega=omega, phi=phi), law, Exact(), t_end=80.0, x0=x0, v0=v0)
    r = ref.integrate(single_mass(zeta, vb, law, x0, v0, forcing), 80.0, t_eval=exact.t, rtol=1e-12, atol=1e-14)
    switches, modes = exact.events["t"], exact.events["mode"]
    assert r.status == "ok" and len(switches) >= 3
    assert len(r.switches) == len(switches)
    np.testing.assert_array_equal(r.switch_modes[:, 0], modes)
    np.testing.assert_allclose(r.switches, switches, rtol=0, atol=1e-10)
    np.testing.assert_allclose(r.state, exact.state, rtol=0, atol=1e-10)
    # the samples' modes agree away from the switches (a sample on a switch belongs to either side)
    away = np.min(np.abs(exact.t[:, None] - switches[None, :]), axis=1) > 1e-9
    np.testing.assert_array_equal(r.modes[0, away], exact.modes[0, away])
    stick = away & (exact.modes[0] == 0)
    slip = away & (exact.modes[0] != 0)
    np.testing.assert_allclose(r.force[0, slip], exact.force[0, slip], rtol=0, atol=1e-12)
    if law.stick_force == "resultant":  # the held force is the constraint force
        np.testing.assert_allclose(r.force[0, stick], exact.force[0, stick], rtol=0, atol=1e-9)


def sliding_pair() -> Elements:
    """Two masses (full mass matrix) sliding on fast belts: no contact reaches V_r = 0 over the run."""
    springs = ([[1.0, 0.0], [1.0, -1.0], [0.0, 1.0]], [1.0, 0.5, 0.8])
    dampers = ([[1.0, 0.0], [1.0, -1.0]], [0.05, 0.03])
    laws = [Coulomb(0.3, 0.4), Coulomb(0.2, 0.3)]
    normal = [[1.0, 0.0, -0.2], [1.0, 0.0, 0.0]]  # N_0 = 1 - 0.2 x2
    contacts = ([[1.0, 0.0], [0.0, 1.0]], [5.0, -4.0], laws, normal)
    forces = ([[0.0, 1.0], [1.0, 1.0]], [0.1, 0.05], [0.9, 1.7], [0.2, 0.0])
    return Elements([[2.0, 0.3], [0.3, 1.0]], springs, dampers, contacts, forces, [0.1, -0.2], [0.3, 0.0])


def sliding_closed_form(el: Elements, times: np.ndarray) -> np.ndarray:
    """(q, q') of the pair while both contacts slip in the belts' directions: z' = A z, z(t) = expm(A t) z(0).

    z = (q, q', 1, cos(Omega_1 t + phi_1), sin(...), cos(Omega_2 t + phi_2), sin(...)); assembled here
    from the element lists.
    """
    m = np.array(el.mass)
    k = sum(kk * np.outer(e, e) for e, kk in zip(np.array(el.springs[0]), el.springs[1]))
    c = sum(cc * np.outer(e, e) for e, cc in zip(np.array(el.dampers[0]), el.dampers[1]))
    cdir, belt, laws, normal = el.contacts
    gdir, amp, omega, phi = (np.array(a) for a in el.forces)
    a = np.zeros((9, 9))
    minv = np.linalg.inv(m)
    a[0:2, 2:4] = np.eye(2)
    stiff = -k.copy()
    push = np.zeros(2)
    for e, b, law, nrm in zip(np.array(cdir), belt, laws, np.array(normal)):
        f = np.sign(b) * law.fd  # slipping with V_r of the belt's sign: F = sgn(V_r) F_d (P + n.q)
        stiff += f * np.outer(e, nrm[1:])
        push += f * nrm[0] * e
    a[2:4, 0:2] = minv @ stiff
    a[2:4, 2:4] = -minv @ c
    a[2:4, 4] = minv @ push
    for i in range(2):
        a[2:4, 5 + 2 * i] = minv @ (amp[i] * gdir[i])
        a[5 + 2 * i, 6 + 2 * i] = -omega[i]
        a[6 + 2 * i, 5 + 2 * i] = omega[i]
    z0 = np.concatenate((el.q0, el.v0, [1.0], *([np.cos(p), np.sin(p)] for p in phi)))
    return np.array([expm(a * t) @ z0 for t in times]).T[:4]


def test_two_masses_pure_sliding_against_matrix_exponential():
    el = sliding_pair()
    times = np.linspace(0.0, 30.0, 61)
    exact = sliding_closed_form(el, times)
    fine = sliding_closed_form(el, np.linspace(0.0, 30.0, 3001))
    cdir, belt = np.array(el.contacts[0]), np.array(el.contacts[1])
    vr = belt[:, None] - cdir @ fine[2:]
    assert np.all(np.sign(vr) == np.sign(belt)[:, None]) and np.min(np.abs(vr)) > 1.0  # no stick on the way
    r = ref.integrate(build(el), 30.0, t_eval=times, rtol=1e-12, atol=1e-14)
    assert r.status == "ok" and len(r.switches) == 0
    np.testing.assert_array_equal(r.modes, np.sign(belt)[:, None] * np.ones((1, len(times))))
    np.testing.assert_allclose(r.state, exact, rtol=0, atol=1e-10 * np.max(np.abs(exact)))


def stick_slip_pair():
    """Two masses in a chain, each on its belt: phases with one mass stuck while the other slips."""
    return chain(2, [0.1, 0.1], [Coulomb(0.3, 0.4), Coulomb(0.2, 0.35)], q0=[0.0, 0.5])


def test_energy_balance_from_its_own_work():
    asm = stick_slip_pair()
    r = ref.integrate(asm, 100.0, dense_dt=0.05, rtol=1e-12, atol=1e-14, work=True)
    modes = set(map(tuple, r.modes.T.tolist()))
    assert {(0, 1), (1, 0), (0, 0), (1, 1)} <= modes
    w = dict(zip(r.channels, r.work))
    e = ref.energy(ref.as_arrays(asm), r.state)
    scale = np.max(np.abs(e))
    inputs = sum(w[c] for c in r.channels if c.startswith(("damper", "force")) or c.endswith("belt"))
    heat = sum(w[c] for c in r.channels if c.endswith("heat"))
    np.testing.assert_allclose(e - e[0], inputs - heat, rtol=0, atol=1e-10 * scale)
    # each spring's work is minus its own potential energy's change
    for i, (d, k) in enumerate(zip(asm.spring_dir, asm.spring_k)):
        pe = 0.5 * k * (d @ r.state[:2]) ** 2
        np.testing.assert_allclose(w[f"spring.{i}"], -(pe - pe[0]), rtol=0, atol=1e-10 * scale)
    for c in r.channels:  # dampers only take, the interfaces only heat
        if c.startswith("damper"):
            assert np.all(np.diff(w[c]) <= 1e-15 * scale)
        if c.endswith("heat"):
            assert np.all(np.diff(w[c]) >= -1e-15 * scale)


def test_converges_in_rtol_with_one_mass_stuck_while_the_other_slips():
    asm = stick_slip_pair()
    times = np.linspace(0.0, 100.0, 201)
    fine = ref.integrate(asm, 100.0, t_eval=times, rtol=1e-12, atol=1e-14)
    coarse = ref.integrate(asm, 100.0, t_eval=times, rtol=1e-9, atol=1e-11)
    assert len(fine.switches) > 20 and len(coarse.switches) == len(fine.switches)
    np.testing.assert_array_equal(coarse.switch_modes, fine.switch_modes)
    np.testing.assert_allclose(coarse.switches, fine.switches, rtol=0, atol=1e-6)
    np.testing.assert_allclose(coarse.state, fine.state, rtol=0, atol=1e-6)


def test_identical_uncoupled_masses_switch_together_as_the_single_mass():
    """Three copies of one oscillator: every switch a three-way tie, each copy the single mass's motion."""
    zeta, vb, law, x0, v0, _ = SINGLE["paper stick-slip"]
    exact = simulate(BeltOscillator(zeta, vb), law, Exact(), t_end=80.0, x0=x0, v0=v0)
    e = np.eye(3)
    el = Elements(e, (e, [1.0] * 3), (e, [2.0 * zeta] * 3), (e, [vb] * 3, [law] * 3, None), None, [x0] * 3, [v0] * 3)
    r = ref.integrate(build(el), 80.0, t_eval=exact.t, rtol=1e-12, atol=1e-14)
    assert len(r.switches) == len(exact.events["t"])
    np.testing.assert_allclose(r.switches, exact.events["t"], rtol=0, atol=1e-10)
    np.testing.assert_array_equal(r.switch_modes, np.repeat(exact.events["mode"][:, None], 3, axis=1))
    for i in range(3):
        np.testing.assert_allclose(r.state[[i, 3 + i]], exact.state, rtol=0, atol=1e-10)


def test_uncoupled_masses_each_as_its_own_single_mass():
    """Two different oscillators side by side (no ties): each dof follows its own single-mass solution."""
    cases = [SINGLE["paper stick-slip"], SINGLE["fs = fd, negative belt"]]
    t_end = 60.0
    e = np.eye(2)
    el = Elements(np.diag([1.0, 1.0]), (e, [1.0, 1.0]), (e, [2.0 * c[0] for c in cases]),
                  (e, [c[1] for c in cases], [c[2] for c in cases], None), None,
                  [c[3] for c in cases], [c[4] for c in cases])
    times = np.linspace(0.0, t_end, 121)
    r = ref.integrate(build(el), t_end, t_eval=times, rtol=1e-12, atol=1e-14)
    singles = [simulate(BeltOscillator(z, vb), law, Exact(), t_end=t_end, x0=x0, v0=v0)
               for z, vb, law, x0, v0, _ in cases]
    np.testing.assert_allclose(np.sort(r.switches), np.sort(np.concatenate([s.events["t"] for s in singles])),
                               rtol=0, atol=1e-10)
    for i, s in enumerate(singles):
        np.testing.assert_allclose(r.state[[i, 2 + i]], np.array([s.at(t) for t in times]).T, rtol=0, atol=1e-10)


def kkt(asm, y: np.ndarray, modes: np.ndarray):
    """Acceleration and stuck contacts' forces from the saddle-point system [[M, -E^T], [E, 0]] [a; lam] = [r; 0]."""
    n = asm.mass.shape[0]
    q, v = y[:n], y[n:]
    r = -asm.stiffness @ q - asm.damping @ v
    for j, s in enumerate(modes):
        if s != 0:
            r = r + asm.contact_dir[j] * s * asm.law[j, layout.FD] * (asm.normal[j, 0] + asm.normal[j, 1:] @ q)
    e = asm.contact_dir[modes == 0]
    s_ = len(e)
    lhs = np.block([[asm.mass, -e.T], [e, np.zeros((s_, s_))]])
    sol = np.linalg.solve(lhs, np.concatenate((r, np.zeros(s_))))
    return sol[:n], sol[n:]


def test_stick_decision_is_consistent_on_random_states():
    """Both contacts of a coupled pair at V_r = 0: the modes chosen satisfy the stick rule and slip the right way.

    Checked with the accelerations and held forces of a saddle-point solve,
    not the reference's projector: stuck contacts hold less than F_s N, a
    contact released from V_r = 0 accelerates away from it on its side.
    """
    rng = np.random.default_rng(22)
    el = sliding_pair()
    el = el._replace(forces=None, contacts=(el.contacts[0], [0.1, -0.2], el.contacts[2], el.contacts[3]))
    asm = ref.as_arrays(build(el))
    seen = set()
    for _ in range(300):
        q = rng.uniform(-1.0, 1.0, 2)
        y = np.concatenate((q, asm.belt))  # e_j = unit vectors: q' = b puts both at V_r = 0
        ph = ref.decide(asm, np.zeros(2, dtype=np.int8), 0.0, y, {})
        a, lam = kkt(asm, y, ph.modes)
        np.testing.assert_allclose(ph.jac @ y + ph.const, np.concatenate((y[2:], a)), rtol=0, atol=1e-12)
        limit = asm.law[ph.stuck, layout.FS] * ref.normal_load(asm, q)[ph.stuck]
        assert np.all(np.abs(lam) < limit)
        slipping = ph.modes != 0
        assert np.all(ph.modes[slipping] * (-asm.contact_dir[slipping] @ a) > 0.0)
        seen.add(tuple(ph.modes.tolist()))
    assert {(0, 0), (1, 0), (0, 1), (-1, 0), (0, -1)} <= seen and any(0 not in m for m in seen)


def test_contact_loss_at_the_closed_form_root():
    """One dof sliding on a fast belt with N = 1 + 2x: the run stops where the closed form's N reaches 0."""
    law = Coulomb(0.3, 0.4)
    el = Elements([[1.0]], ([[1.0]], [1.0]), ([[1.0]], [0.1]), ([[1.0]], [5.0], [law], [[1.0, 2.0]]), None, [0.0], [-1.0])
    # slip+ throughout: x'' = -x - 0.1 x' + 0.3 (1 + 2x), z = (x, x', 1)
    a = np.array([[0.0, 1.0, 0.0], [-1.0 + 0.6, -0.1, 0.3], [0.0, 0.0, 0.0]])
    z0 = np.array([0.0, -1.0, 1.0])

    def load(t):
        return 1.0 + 2.0 * (expm(a * t) @ z0)[0]

    t_lost = brentq(load, 0.0, 2.0, xtol=1e-15)  # x falls from 0 to -0.5 within the first 2 time units
    assert load(0.5 * t_lost) > 0.0 and (expm(a * t_lost) @ z0)[1] < 5.0  # one root, and still slipping
    r = ref.integrate(build(el), 10.0, dense_dt=0.1, rtol=1e-12, atol=1e-14)
    assert r.status == "contact_lost" and r.lost[0] == 0
    assert abs(r.lost[1] - t_lost) < 1e-10 and r.t[-1] == r.lost[1]
    np.testing.assert_allclose(r.state[:, -1], (expm(a * t_lost) @ z0)[:2], rtol=0, atol=1e-10)
