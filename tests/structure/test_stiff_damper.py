"""A stiff damper: an overdamped mode that dies within a phase no longer sets the walk's or the quadrature's pace.

Damper c on a unit mass makes one mode of rate about c and one of about k / c.
The fast one settles on its forcing within a few 1 / c; from then on its
z'' is near 0 while |lam|^2 |z| is not, and bounds taken from |z| held every
interval of the walk (and the work quadrature's node count) to the time scale
1 / c: the run's time grew as c (1e4: 31 s, 1e6: over 200 s for 300 time units).
Here: the run against an independent stiff integrator (scipy's Radau, the
reference's event loop), and the walk's bound on |g''| of a settled mode
against the true g'' and against its size.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.linalg import eigvals

from frictionflow import Coulomb
from frictionflow.core.structure.combo import build as build_combo
from frictionflow.core.structure.phase import DEAD, bound, lifetime, start
from frictionflow.solvers.structure import run_assembly
from frictionflow.system.assemble import free_directions

from . import reference as ref
from .chains import Elements, build
from .test_chain_vs_reference import spread, switch_times
from .test_conjugate_pairs import T0, moduli, second_derivative_maxima

T_END = 40.0
EPS = np.finfo(float).eps


def stiff_chain(c: float) -> Elements:
    """x1 on a damper ``c`` to the ground, x2 stick-slipping and forced, springs to the walls and between."""
    springs = ([[1.0, 0.0], [1.0, -1.0], [0.0, 1.0]], [1.0, 0.5, 1.0])
    dampers = ([[1.0, 0.0], [0.0, 1.0]], [c, 0.04])
    contacts = ([[1.0, 0.0], [0.0, 1.0]], [0.1, 0.1], [Coulomb(0.1, 0.15), Coulomb(0.1, 0.2)], None)
    return Elements(np.eye(2), springs, dampers, contacts, ([[0.0, 1.0]], [0.2], [0.7], [0.3]), [0.0, -0.3],
                    [0.0, 0.0])


@pytest.mark.parametrize("c", [1e4, 1e6, 1e8, 1e10])
def test_a_stiff_damper_chain_against_an_independent_radau_run(c):
    """Switch times, states and every element's work against Radau at rtol 1e-13, to its difference from Radau at
    rtol 1e-11 and rounding: not to the stiff rate times EPS.  The decomposition of the first-order matrix (norm ~c)
    left the oscillating pair ~c EPS off (3e-8 of its size at c = 1e9) and the creep root k / c 4e-7 off: at
    c = 1e8 the switch times were 1.2e-7 off, at 1e10 the states 3.4e-7, while the energy residual said 2e-8.  The
    general route's roots are now refined on the quadratic pencil (:mod:`frictionflow.core.structure.pencil`)."""
    asm = build(stiff_chain(c))
    motion = run_assembly(asm, T_END, dense_dt=0.5)
    times, inverse = np.unique(motion.t, return_inverse=True)
    fine, coarse = (ref.integrate(asm, T_END, t_eval=times, rtol=r, atol=1e-3 * r, work=True, method="Radau")
                    for r in (1e-13, 1e-11))
    assert len(fine.switches) >= 8 and len(coarse.switches) == len(fine.switches)
    switches = switch_times(motion)
    assert len(switches) == len(fine.switches)
    rounding = 1e3 * EPS  # the run's own rounding over 40 time units and 11 switches, whatever c
    np.testing.assert_allclose(switches, fine.switches, rtol=0, atol=spread(coarse.switches, fine.switches) + rounding)
    np.testing.assert_allclose(motion.state, fine.state[:, inverse], rtol=0,
                               atol=spread(coarse.state, fine.state) + rounding)
    np.testing.assert_allclose(motion.work, fine.work[:, inverse], rtol=0,
                               atol=spread(coarse.work, fine.work) + rounding)
    assert motion.energy_residual < 100 * EPS


def test_a_settled_stiff_modes_bound_follows_its_rate_not_its_size():
    """|g''| over an interval after the fast mode has died: the walk's bound holds (g'' from expm of the full
    first-order system) and is within 100x of the largest |g''| there; from |z| alone (the bound before) it is
    over 1e6 times that for the stiff mass's contact."""
    asm = build(stiff_chain(1e6))
    modes = np.array([1, 1], dtype=np.int8)
    cb = build_combo(asm, np.linalg.inv(asm.mass), modes)
    q0, v0 = np.array([0.01, 0.2]), np.array([0.0, -0.1])
    ph = start(cb, asm, q0, v0, T0)
    om = asm.force_omega
    a, h, d = 2.0 * DEAD / 1e6, 0.5, 1e-3
    assert min(lifetime(x) for x in cb.lam.real) < a  # the fast mode is dead from a on
    mg = moduli(cb, ph, om, a)
    g2 = second_derivative_maxima(asm, cb, modes, (q0, v0), a, h, d)
    from_size = mg._replace(w=np.full(len(cb.lam), np.inf), u=np.full(len(cb.lam), np.inf))  # min(.., inf)
    for e in np.nonzero(cb.active)[0]:
        m2 = bound(cb, om, e, a, h, mg, 2)
        assert g2[e] <= m2 <= 100.0 * g2[e] + 1e-9
    assert bound(cb, om, 0, a, h, from_size, 2) > 1e6 * g2[0]  # the stiff mass's contact: what it would cost


def stiff_pair(c: float) -> Elements:
    """Damper ``c`` between two masses on their own contacts; the second forced."""
    springs = ([[1.0, 0.0], [1.0, -1.0], [0.0, 1.0]], [1.0, 0.5, 1.0])
    dampers = ([[1.0, -1.0], [1.0, 0.0], [0.0, 1.0]], [c, 0.02, 0.02])
    contacts = ([[1.0, 0.0], [0.0, 1.0]], [0.05, 0.05], [Coulomb(0.1, 0.35), Coulomb(0.1, 0.3)], None)
    return Elements(np.eye(2), springs, dampers, contacts, ([[0.0, 1.0]], [0.1], [0.9], [0.0]), [0.0, 0.2],
                    [0.05, 0.05])


@pytest.mark.parametrize("a, h, d", [(0.0, 1e-6, 1e-8), (0.0, 1e-4, 1e-6), (1e-3, 1.0, 1e-3)])
def test_a_stiff_mode_on_its_forcing_is_bounded_by_its_rates_from_the_start(a, h, d):
    """x1 stuck, x2 starting to slip, a damper of 1e6 between them: the fast mode starts on its forcing (the
    damper's force from the stuck mass, ~c times the belt), so from |z| its |g''| bound is ~1e6 times the true
    one at the start and ~1e23 times it once the mode has died (under a forcing of frequency 0.9).  The bound
    from the modes' rates holds (g'' from expm of the full first-order system) and is within 3x of the largest
    |g''|, on intervals from the start, across the mode's life and after its death."""
    asm = build(stiff_pair(1e6))
    modes = np.array([0, 1], dtype=np.int8)
    cb = build_combo(asm, np.linalg.inv(asm.mass), modes)
    q0, v0 = np.array([0.0, 0.2]), np.array([0.05, 0.05])
    ph = start(cb, asm, q0, v0, T0)
    om = asm.force_omega
    mg = moduli(cb, ph, om, a)
    from_size = mg._replace(w=np.full(len(cb.lam), np.inf), u=np.full(len(cb.lam), np.inf))
    g2 = second_derivative_maxima(asm, cb, modes, (q0, v0), a, h, d)
    for e in np.nonzero(cb.active)[0]:
        m2 = bound(cb, om, e, a, h, mg, 2)
        assert g2[e] <= m2 <= 3.0 * g2[e]
        assert bound(cb, om, e, a, h, from_size, 2) > 1e5 * g2[e]


def stuck_chain(c: float) -> Elements:
    """Three masses on contacts, springs to the walls and between, light dampers to the ground and a damper ``c``
    between x2 and x3, x3 forced (QA's case: with c = 1e8 the run ended "stuck" at t = 15.67)."""
    springs = ([[1, 0, 0], [1, -1, 0], [0, 1, -1], [0, 0, 1]], [1.0, 0.5, 0.5, 1.0])
    dampers = ([[1, 0, 0], [0, 1, 0], [0, 0, 1], [0, 1, -1]], [0.02, 0.02, 0.02, c])
    laws = [Coulomb(0.1, 0.3), Coulomb(0.1, 0.35), Coulomb(0.1, 0.3)]
    return Elements(np.eye(3), springs, dampers, (np.eye(3), [0.05] * 3, laws, None),
                    ([[0.0, 0.0, 1.0]], [0.1], [0.9], [0.0]), [0.0, 0.0, 0.2], [0.0, 0.0, 0.0])


def test_a_stiff_damper_between_a_stuck_and_a_slipping_mass_runs_as_radau():
    """x3 leaves V_r = 0 while x2 sticks: its V_r departs from 0 at the start of a phase whose fast mode (rate
    2e8) sits on its forcing.  From |z| the walk's bound on V_r's |g''| was 5e7 times the true one, so the phase
    start could not be proven clear above the shortest interval: a touch was reported, the contact stuck again at
    once and the run ended "stuck".  Against Radau (the reference's event loop) at rtol 1e-8 and 1e-9: the same
    switches, times and states within their spread plus 40 c EPS, the held force through the damper being c times
    a velocity difference of rounding (measured: 15 c EPS in a switch time)."""
    c, t_end, upto = 1e8, 300.0, 16.0  # (the shortest interval is 1e-13 t_end: the run to 300 stopped, to 16 not)
    asm = build(stuck_chain(c))
    motion = run_assembly(asm, t_end, dense_dt=0.5)
    kept = motion.t <= upto
    times, inverse = np.unique(motion.t[kept], return_inverse=True)
    fine, coarse = (ref.integrate(asm, upto, t_eval=times, rtol=r, atol=1e-3 * r, work=True, method="Radau")
                    for r in (1e-9, 1e-8))
    assert len(fine.switches) >= 8 and np.any((fine.modes[1] == 0) & (fine.modes[2] != 0))  # what it is here for
    switches = switch_times(motion)
    assert len(switches[switches <= upto]) == len(fine.switches)
    basis = 40.0 * c * EPS
    np.testing.assert_allclose(switches[:len(fine.switches)], fine.switches, rtol=0,
                               atol=spread(coarse.switches, fine.switches) + basis)
    np.testing.assert_allclose(motion.state[:, kept], fine.state[:, inverse], rtol=0,
                               atol=spread(coarse.state, fine.state) + basis)
    np.testing.assert_allclose(motion.work[:, kept], fine.work[:, inverse], rtol=0,
                               atol=spread(coarse.work, fine.work) + basis)
    assert motion.energy_residual < basis


def test_a_damper_too_stiff_for_double_precision_is_named_with_the_rates_it_spans():
    """A damper of 5e10 to the ground on unit masses: its mode's rate 5e10 beside the creep k / c, 2e-11; the
    engine cannot resolve a mode basis over that span.  The line said "a mode combination's matrix is defective
    (e.g. an undamped rigid mode)": no mode of this structure is rigid.  Now it names the damper, its rate and
    the structure's slowest rate (here from the generalised eigenproblem of the quadratic pencil, QZ: its
    smallest finite root).  An undamped free structure (no spring or damper holds it) is told apart: its line
    names the free motion (tests/structure/test_free_motion.py)."""
    a = build(stiff_chain(5e10))
    n = 2
    pencil = (np.block([[np.zeros((n, n)), np.eye(n)], [-a.stiffness, -a.damping]]),
              np.block([[np.eye(n), np.zeros((n, n))], [np.zeros((n, n)), a.mass]]))
    slowest = float(np.abs(eigvals(*pencil)).min())
    assert 1e-11 < slowest < 1e-10  # about k / c
    with pytest.raises(ValueError) as err:
        run_assembly(a, 40.0)
    line = str(err.value)
    assert f"damper.0's rate 5e+10 (alone) beside its slowest rate {slowest:.3g}" in line, line
    assert "defective" not in line
    free = a._replace(stiffness=np.zeros((n, n)), damping=np.zeros((n, n)), spring_k=np.zeros(3),
                      damper_c=np.zeros(2))
    with pytest.raises(ValueError, match="along q. none does .*use solver=adaptive"):
        run_assembly(free, 10.0)


@pytest.mark.parametrize("elements", [stiff_chain, stiff_pair, stuck_chain], ids=["to_ground", "between", "three"])
@pytest.mark.parametrize("c", [1e12, 1e14])
def test_a_sprung_structure_beside_a_huge_damper_is_not_taken_for_a_free_one(elements, c):
    """Dampers of 1e12 and 1e14 on sprung unit masses: the line said "along q1 none does (an undamped free
    motion ...); use solver=adaptive", since the free directions were found from one rank over the springs and
    the dampers together, in which springs of 1 beside a damper of 1e12 were rounding.  Each part is now ranked
    in its own size: no direction is free, and the line names the damper too stiff for the modes."""
    a = build(elements(c))
    assert free_directions(a, undamped=True).shape[1] == 0
    with pytest.raises(ValueError, match=r"damper\.\d's rate .* spans more than one double-precision mode basis"):
        run_assembly(a, 40.0)

