"""A structure's stick decided at the rounding of V_r: a stuck start, and the Lyapunov pair's restarts.

V_r = belt - e . q' of a start meant to stick is rarely 0 in binary (3 x
-0.1 is not -0.3): the engines slipped from such a start.  The Lyapunov
exponent of a structure's non-repeating section restarts a second run from
the reference's states, perturbed in every velocity: a stuck contact's
velocity kicked off its belt slipped, an O(1) departure counted as
exponential growth (0.277 where two runs 1e-10 apart diverge at ~0.02).
"""

from __future__ import annotations

import numpy as np
import pytest

from frictionflow.analysis.structure import analyze_structure
from frictionflow.analysis.structure_lyapunov import on_stick
from frictionflow.solvers.structure import simulate_system
from frictionflow.system import load_system

# one mass on a spring, its contact along 3 x1: V_r(0) = -0.3 - 3 (-0.1) = 5.6e-17 in binary.  Stuck, the held
# force k x1 / 3 grows from 0.2 to F_s = 0.3 at x1 = -0.9: the stick lasts (0.6 + 0.9) / 0.1 = 15 exactly.
ONE = """
dof = ["x1"]
mass = [1.0]
[[spring]]
on = { x1 = 1.0 }
k = 1.0
[[contact]]
on = { x1 = 3.0 }
belt = -0.3
friction = "coulomb"
fd = 0.1
fs = 0.3
[initial]
q = { x1 = 0.6 }
v = { x1 = -0.1 }
"""

# three masses, three contacts (one along x3 + 0.3 x2), a spring across three dofs: chaotic stick-slip
THREE = """
dof = ["x1", "x2", "x3"]
mass = [1.0, 0.7, 1.3]
[[spring]]
on = { x1 = 1.0 }
k = 1.0
[[spring]]
on = { x1 = 1.0, x2 = -1.0 }
k = 0.6
[[spring]]
on = { x2 = 1.0, x3 = -1.0 }
k = 0.9
[[spring]]
on = { x1 = 0.5, x2 = 0.5, x3 = -1.0 }
k = 0.3
[[spring]]
on = { x3 = 1.0 }
k = 0.4
[[damper]]
on = { x2 = 1.0 }
c = 0.01
[[damper]]
on = { x1 = 1.0, x3 = -1.0 }
c = 0.015
[[contact]]
on = { x1 = 1.0 }
belt = 0.08
friction = "coulomb"
fd = 0.1
fs = 0.25
[[contact]]
on = { x2 = 1.0 }
belt = 0.08
friction = "coulomb"
fd = 0.12
fs = 0.2
[[contact]]
on = { x3 = 1.0, x2 = 0.3 }
belt = 0.1
friction = "coulomb"
fd = 0.09
fs = 0.3
[initial]
v = { x1 = 0.08, x2 = 0.08 }
q = { x3 = 0.1 }
"""


def _system(tmp_path, text):
    path = tmp_path / "m.toml"
    path.write_text(text)
    return load_system(path)


@pytest.mark.parametrize("solver", ["exact", "adaptive"])
def test_a_start_stuck_to_rounding_sticks_for_the_closed_form_time(tmp_path, solver):
    motion = simulate_system(_system(tmp_path, ONE), 20.0, solver=solver)
    assert motion.switches[0] == pytest.approx(15.0, abs=1e-9)  # slipped at once before (first stick at 2.498)
    assert motion.switch_mode[0] == -1


def test_on_stick_keeps_the_perturbation_on_the_stuck_contacts_belts(tmp_path):
    a = simulate_system(_system(tmp_path, ONE), 1.0).assembly
    state = np.array([0.6, -0.1])
    fixed, d = on_stick(a, state, np.array([1e-7, 1e-7]))
    assert abs(-0.3 - 3.0 * fixed[1]) <= 1e-16  # on its belt to rounding
    assert d[1] == 0.0 and d[0] == 1e-7  # the velocity kick removed, the position's kept
    slipping = np.array([0.6, 0.05])
    assert on_stick(a, slipping, np.array([1e-7, 1e-7]))[1][1] == 1e-7  # a slipping contact: unchanged


def test_structure_lyapunov_exponent_is_the_divergence_of_two_nearby_runs(tmp_path):
    system = _system(tmp_path, THREE)
    ss = analyze_structure(simulate_system(system, 400.0)).steady_state
    assert ss.kind == "chaotic"
    # independently of the exponent's code: two runs 1e-10 apart in x1(0), their separation's growth rate
    # between 100 times the start and 1e-3
    ts = np.arange(0.0, 2500.0, 1.0)
    a = simulate_system(system, 2500.0).states(ts)
    b = simulate_system(system.with_entry("initial.q.x1", 1e-10), 2500.0).states(ts)
    sep = np.max(np.abs(a - b), axis=0)
    grow = (sep > 1e-8) & (sep < 1e-3)
    rate = np.polyfit(ts[grow], np.log(sep[grow]), 1)[0]
    assert 0.015 < rate < 0.03
    assert 0.5 * rate < ss.lyapunov < 1.5 * rate  # 0.277 before: 11x the divergence's rate
