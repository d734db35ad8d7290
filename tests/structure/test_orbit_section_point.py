"""The structure's shooting starts from section points that continue the motion, and says which return count to use.

Random structures of the fuzzing against independent paths (their numbers
rounded but for DRIFTING's):

* OBLIQUE: 2 dof, two oblique contacts.  Its cycle (period 15.50) passes the
  section x1' = 0 while contact.1, oblique to x1, is stuck with a held force
  between F_d N and F_s N.  Zeroing x1' of the located crossing moved that
  contact's V_r by its rounding, past the engine's test for V_r = 0: the run
  from the point began slipping, a branch on which the motion leaves the
  stuck state for good, and Newton converged there to a "period 5.157" that
  ended stuck where it began slipping and did not repeat after one period.
* NEARING: 3 dof, full mass matrix.  Its cycle crosses the section twice a
  period, and at t = 300 the transient repeats to 1e-3 but not to simulate's
  1e-6.  The one-return map has no fixed point: Newton crept towards a
  switch's boundary down to a residual of 5e-10 and stalled without saying
  that two returns find the orbit.
* TWO_ORBITS: 2 dof, one contact.  From its start it settles on a cycle of
  period 18.69 crossing the section twice; one return finds another stable
  orbit (period 9.32), so shooting with one return by default reported an
  orbit that is not the one simulate finds.  The default count is now the
  transient's cycle's.
* FORCED: 2 dof, a harmonic force and a state-dependent normal load.  Its
  attractor is a cycle of two forcing periods with a multiplier 0.93 (the
  one-period orbit is unstable, 1.012): after t = 300 Newton stalled at a
  residual of 1.5e-3 with nothing to say.
* DRIFTING: 3 dof, forced; its run to t = 600 is just periodic, the mean of
  its crossings 4e-8 off the forcing period it reports.

The references are the exact engine's own continuous runs and simulate's
analysis; the orbits found must repeat over several periods when run again.
The section's crossings are also checked on a closed-form velocity whose
zero sits next to a grid point of their search (a trial return's run is 1.5
times the last return, so the crossing near that time is often on the grid:
a random 2-dof structure stalled at a residual of 4e-11 there).
"""

from __future__ import annotations

import json
import math
import tomllib
from types import SimpleNamespace

import numpy as np
import pytest

from frictionflow.analysis.structure import repeating, structure_steady_state
from frictionflow.core.layout import STICK
from frictionflow.orbits.shooting import ShootingError
from frictionflow.orbits import structure as shooting
from frictionflow.orbits.structure import find_structure_orbit, on_section
from frictionflow.orbits.structure_flow import GRID_PER_PERIOD, NOISE, Flow, crossings
from frictionflow.orbits.structure_transient import strobe_count, strobe_hint
from frictionflow.solvers.structure import simulate_system
from frictionflow.system import System, assemble

from ..cli.processes import cli
from .test_structure_kinds import chaotic_chain

OBLIQUE = """
dof = ["x1", "x2"]
mass = [[0.515, 0.0], [0.0, 0.7984]]
[[spring]]
on = { x1 = 1.0 }
k = 0.9397
[[spring]]
on = { x2 = 1.0 }
k = 1.9151
[[spring]]
on = { x1 = -0.4695, x2 = -1.1968 }
k = 0.8743
[[spring]]
on = { x1 = -0.1456, x2 = 0.3983 }
k = 0.4197
[[damper]]
on = { x1 = 0.2552, x2 = 0.1732 }
c = 0.0506
[[contact]]
on = { x1 = 0.9441, x2 = 0.1299 }
belt = -0.1589
friction = "coulomb"
fd = 0.2804
fs = 0.3116
[[contact]]
on = { x1 = -0.3862, x2 = 1.115 }
belt = -0.1059
friction = "coulomb"
fd = 0.2047
fs = 0.3888
[initial]
q = { x1 = 0.1416, x2 = -0.1351 }
"""

NEARING = """
dof = ["x1", "x2", "x3"]
mass = [[1.086, 0.007, 0.098], [0.007, 1.107, -0.014], [0.098, -0.014, 1.218]]
[[spring]]
on = { x1 = 1.0 }
k = 0.918
[[spring]]
on = { x2 = 1.0 }
k = 0.882
[[spring]]
on = { x3 = 1.0 }
k = 1.168
[[spring]]
on = { x1 = -0.029, x2 = 0.695, x3 = -1.344 }
k = 0.813
[[damper]]
on = { x1 = -1.29, x2 = -1.842, x3 = -0.235 }
c = 0.065
[[damper]]
on = { x1 = 0.271, x2 = 0.157, x3 = -0.187 }
c = 0.052
[[damper]]
on = { x1 = -0.539, x2 = -0.049, x3 = 0.113 }
c = 0.055
[[contact]]
on = { x1 = 0.147, x2 = -0.979, x3 = -0.809 }
belt = -0.262
friction = "coulomb"
fd = 0.349
fs = 0.403
[[contact]]
on = { x1 = 1.061, x2 = -0.808, x3 = -0.033 }
belt = 0.177
friction = "coulomb"
fd = 0.292
fs = 0.508
[initial]
q = { x1 = 1.0, x2 = 0.381, x3 = -0.6 }
"""

TWO_ORBITS = """
dof = ["x1", "x2"]
mass = [[1.245, 0.0], [0.0, 0.756]]
[[spring]]
on = { x1 = 1.0 }
k = 0.568
[[spring]]
on = { x2 = 1.0 }
k = 1.564
[[damper]]
on = { x1 = -0.483, x2 = 0.639 }
c = 0.023
[[contact]]
on = { x1 = -1.493, x2 = -1.92 }
belt = 0.296
friction = "coulomb"
fd = 0.34
fs = 0.411
[initial]
q = { x1 = -0.458, x2 = 0.988 }
"""

FORCED = """
dof = ["x1", "x2"]
mass = [[0.7077, 0.0], [0.0, 0.7295]]
[[spring]]
on = { x1 = 1.0 }
k = 1.2331
[[spring]]
on = { x2 = 1.0 }
k = 0.9979
[[spring]]
on = { x1 = 1.3122, x2 = 1.5108 }
k = 0.5429
[[damper]]
on = { x1 = 0.3487, x2 = -1.0582 }
c = 0.0207
[[contact]]
on = { x1 = 1.2051, x2 = 0.058 }
belt = -0.1661
friction = "coulomb"
fd = 0.3341
fs = 0.5197
normal = { preload = 1.0, x1 = 0.0415, x2 = -0.676 }
[[contact]]
on = { x1 = 0.2209, x2 = 1.2384 }
belt = -0.0622
friction = "coulomb"
fd = 0.3854
fs = 0.4989
[[force]]
on = { x1 = -0.6307, x2 = -0.093 }
amplitude = 0.2659
omega = 1.2158
phi = 1.1193
[initial]
q = { x1 = -0.6385, x2 = -0.7862 }
"""

#: a forced 3-dof structure whose run to t = 600 just passes simulate's periodic test (one forcing period)
DRIFTING = """
dof = ["x1", "x2", "x3"]
mass = [[1.6553908768712984, -0.3792701753407138, -0.32330943666292594], [-0.3792701753407138, 1.3982601107723585, 0.07294729882073195], [-0.32330943666292594, 0.07294729882073195, 1.2324740192122572]]
[[spring]]
on = { x1 = 1.0 }
k = 1.0172645904721178
[[spring]]
on = { x2 = 1.0 }
k = 0.828455072162267
[[spring]]
on = { x3 = 1.0 }
k = 0.8385852092952841
[[spring]]
on = { x1 = -1.1050464100827455, x2 = -0.6922059642247175, x3 = 0.6222206124353614 }
k = 0.663784859704292
[[spring]]
on = { x1 = -1.218957865341841, x2 = 0.08074577287047363, x3 = -0.26683072489114207 }
k = 0.5940057439169026
[[damper]]
on = { x1 = 0.590188658364506, x2 = -0.19347900495752512, x3 = -0.12056107598100044 }
c = 0.019808364264335483
[[damper]]
on = { x1 = 0.12721857150834673, x2 = -1.266926823660342, x3 = -0.1723316093578593 }
c = 0.05144025168686072
[[damper]]
on = { x1 = 0.06382043234650693, x2 = 0.5609928456656607, x3 = -1.276752562937137 }
c = 0.011209895688342512
[[contact]]
on = { x1 = -0.45440546650687597, x2 = -0.4264536594840153, x3 = 1.2290645801080327 }
belt = 0.23172417200951473
friction = "coulomb"
fd = 0.3216905908861164
fs = 0.5446734358630064
[[contact]]
on = { x1 = 0.5001004823410974, x2 = -1.1128215773823462, x3 = 0.7674470410749694 }
belt = 0.1273332868457499
friction = "coulomb"
fd = 0.34040859676232565
fs = 0.5303259192140778
[[force]]
on = { x1 = -1.112391631758333, x2 = 0.8010547859906434, x3 = -0.20631149102531054 }
amplitude = 0.11580265081665313
omega = 0.7891068020047274
phi = 4.736097567342702
[initial]
q = { x1 = -0.20876169883862944, x2 = -0.41300947637144547, x3 = -0.32202355903923824 }
"""


def _system(text):
    return System.from_dict(tomllib.loads(text), source=None)


def _repeats(system, orbit, periods):
    """Largest deviation of the exact engine's run from the orbit's state after 1..``periods`` periods, each
    component relative to the orbit's scale (the engine run once over the whole span: no restart at the section)."""
    flow = Flow(assemble(system))
    run = flow.run(orbit.state, periods * orbit.period + 1.0)
    ends = flow.states(run, orbit.period * np.arange(1, periods + 1))
    return float(np.max(np.abs(ends - orbit.state) / orbit.scale))


def _same(a, b):
    """Two orbits found the same way: the same numbers, bit for bit."""
    assert a.returns == b.returns and a.period == b.period
    np.testing.assert_array_equal(a.state, b.state)
    np.testing.assert_array_equal(a.monodromy, b.monodromy)


def test_a_run_from_a_section_point_continues_the_motion_through_a_stuck_contact():
    """Every downward crossing of x1' = 0 in the transient's second half while contact.1 (oblique to x1) is
    stuck: the engine run from the section point starts in the transient's modes and follows the transient
    over the next 20 time units (the transient's own states, 1e-9)."""
    system = _system(OBLIQUE)
    flow = Flow(assemble(system), {"dof": tuple(system.dof)})
    motion = flow.run(np.concatenate((flow.assembly.q0, flow.assembly.v0)), 300.0)
    row = flow.n  # x1'
    checked = 0
    for tc in crossings(flow, motion, row, 150.0):
        modes = np.asarray(motion.modes)[:, int(np.searchsorted(motion.t, tc, side="right")) - 1]
        if modes[1] != STICK or tc > 280.0:
            continue
        point = on_section(flow, motion, tc, row)
        assert point[row] == 0.0
        run = flow.run(point, 20.0)
        np.testing.assert_array_equal(np.asarray(run.modes)[:, 0], modes)
        tau = np.linspace(0.0, 20.0, 41)
        scale = np.max(np.abs(flow.states(motion, 150.0 + tau * 7.0)), axis=0)  # each component's size, t 150-290
        assert np.max(np.abs(flow.states(run, tau) - flow.states(motion, tc + tau)) / scale) < 1e-9
        checked += 1
    assert checked >= 5


def test_an_orbit_shot_through_a_stuck_contact_is_the_cycle_simulate_finds():
    """With one return the map jumps between the cycle's three crossings: Newton stalls and says returns=3 (it
    used to return a "period 5.157" ending in other modes than it began); with three, the orbit is simulate's
    cycle, its multipliers hold the autonomous orbit's trivial 1, and it repeats over three periods."""
    system = _system(OBLIQUE)
    ss = structure_steady_state(simulate_system(system, 600.0))
    assert ss.kind == "periodic"
    with pytest.raises(ShootingError, match=r"settles on a cycle of period 15\.50.* x1' = 0 3 times a period: "
                                            "returns=3"):
        find_structure_orbit(system, t_transient=300.0, returns=1)
    orbit = find_structure_orbit(system, t_transient=300.0, returns=3)
    _same(find_structure_orbit(system, t_transient=300.0), orbit)  # by default, the transient's count
    assert orbit.period == pytest.approx(ss.period, rel=1e-9)
    assert orbit.stick_fraction == pytest.approx(ss.stick_fraction, abs=1e-6)
    assert np.min(np.abs(orbit.multipliers - 1.0)) < 1e-8
    assert _repeats(system, orbit, 3) < 1e-9


def test_a_fixed_point_whose_run_is_not_the_motion_ending_there_is_refused(monkeypatch):
    """The section points as they were made before (only q'_row zeroed): Newton converges on the slipping branch
    to the "period 5.157", and the returned orbit's check refuses it -- its monodromy carries the vector field
    at its start 0.79 of its size away from itself, where an orbit's carries it to itself."""
    def zeroed(flow, motion, t, row):
        y = flow.states(motion, np.array([t]))[0]
        y[row] = 0.0
        return y

    monkeypatch.setattr(shooting, "on_section", zeroed)
    with pytest.raises(ShootingError, match=r"fixed point is not a periodic orbit: the monodromy carries the vector "
                                            r"field at its start 0\.\d+ of its size away"):
        find_structure_orbit(_system(OBLIQUE), t_transient=300.0, returns=1)


def test_newton_stalled_beside_a_cycle_still_converging_says_how_many_returns():
    """At t = 300 simulate's analysis does not call the run periodic yet (its section states repeat to 1e-3, not
    1e-6); the stall's line still names the cycle's two crossings a period, and two returns find it: simulate's
    period at t = 1200, repeating over three periods.  After a transient of 50 the line says it is too short."""
    system = _system(NEARING)
    assert structure_steady_state(simulate_system(system, 300.0)).kind == "not_settled"
    settled = structure_steady_state(simulate_system(system, 1200.0))
    assert settled.kind == "periodic"
    with pytest.raises(ShootingError, match=r"stalled.*nears a cycle of period 7\.9615.*repeat to 0\.001\) that "
                                            "crosses the section x3' = 0 2 times a period: returns=2"):
        find_structure_orbit(system, t_transient=300.0, returns=1)
    orbit = find_structure_orbit(system, t_transient=300.0, returns=2)
    _same(find_structure_orbit(system, t_transient=300.0), orbit)
    assert orbit.period == pytest.approx(settled.period, rel=1e-9)
    assert _repeats(system, orbit, 3) < 1e-9
    with pytest.raises(ShootingError, match=r"stalled.*the transient has not settled \(its section states do not "
                                            r"repeat to 0\.001 over its second half\): a longer one"):
        find_structure_orbit(system, t_transient=50.0)


class _Sine:
    """A flow of one dof with q = cos(c - t), q' = sin(c - t): q' crosses 0 downwards at t = c (+ 2 pi k)."""

    def __init__(self, c, amplitude=1.0):
        self.c, self.amplitude = c, amplitude
        self.omega_max, self.assembly = 1.0, SimpleNamespace(belt=np.array([0.1]))

    def states(self, motion, times):
        times = np.asarray(times, dtype=float)
        return self.amplitude * np.column_stack((np.cos(self.c - times), np.sin(self.c - times)))

    def field(self, modes, y, t):
        return self.amplitude * np.array([np.sin(self.c - t), -np.cos(self.c - t)])


def test_a_crossing_next_to_a_grid_point_of_the_search_is_found():
    """q' = sin(c - t) with c 1e-13 after a point of the search's grid (its value there positive, far below the
    noise floor): the one crossing in [0, 10] is found at c; a velocity of rounding size still has none."""
    t_end = 10.0
    count = math.ceil(t_end / (2.0 * math.pi) * GRID_PER_PERIOD) + 2  # the search's grid over [0, t_end]
    grid = np.linspace(0.0, t_end, count)
    motion = SimpleNamespace(t=np.array([0.0, t_end]), modes=np.zeros((1, 2), dtype=np.int8))
    for i in (40, 50, 60):
        flow = _Sine(grid[i] + 1e-13)
        assert 0.0 < flow.states(motion, grid[i:i + 1])[0, 1] <= NOISE * 0.1  # within the floor, above 0
        found = crossings(flow, motion, 1)
        assert len(found) == 1 and abs(found[0] - flow.c) < 1e-14
    assert len(crossings(_Sine(grid[50] + 0.01, amplitude=1e-13), motion, 1)) == 0


def test_newton_stalled_on_a_forced_structure_says_what_its_transient_does():
    """FORCED after t = 300 (simulate: not settled): the stall's line says the transient is too short; after 600
    two forcing periods find the cycle simulate settles on, as does the default count (the transient's).  That
    transient, shot for one forcing period, is said to near a cycle of two."""
    system = _system(FORCED)
    assert structure_steady_state(simulate_system(system, 300.0)).kind == "not_settled"
    settled = structure_steady_state(simulate_system(system, 600.0))
    forcing = 2.0 * math.pi / 1.2158
    assert settled.kind == "periodic" and settled.period == pytest.approx(2.0 * forcing, rel=1e-12)
    with pytest.raises(ShootingError, match=r"stalled.*the transient has not settled on a cycle of whole forcing "
                                            r"periods \(its section states do not repeat to 0\.001 over its second "
                                            r"half\): a longer one"):
        find_structure_orbit(system, t_transient=300.0, returns=2)
    orbit = find_structure_orbit(system, t_transient=600.0, returns=2)
    assert orbit.period == pytest.approx(settled.period, rel=1e-12)
    _same(find_structure_orbit(system, t_transient=600.0), orbit)  # by default, the transient's two periods
    assert orbit.stick_fraction == pytest.approx(settled.stick_fraction, abs=1e-6)
    assert orbit.stable and _repeats(system, orbit, 3) < 1e-9
    flow = Flow(assemble(system))
    transient = flow.run(np.concatenate((flow.assembly.q0, flow.assembly.v0)), 600.0)
    hint = strobe_hint(transient, forcing, 1)
    assert "nears a cycle of 2 forcing periods" in hint and "returns=2" in hint
    assert strobe_hint(transient, forcing, 2) == ""
    assert strobe_count(transient, forcing) == 2


def test_by_default_the_orbit_is_the_cycle_the_transient_nears_not_another_one(tmp_path):
    """TWO_ORBITS after t = 300 (not yet periodic to simulate's 1e-6, its section states repeating to 1e-3 after
    two crossings): one return reaches another stable orbit, a real one (it repeats when run on); the default
    count, two, gives the cycle simulate settles on by t = 600: its period and stick fraction; so does
    ``orbit --model`` without ``--returns``."""
    system = _system(TWO_ORBITS)
    assert structure_steady_state(simulate_system(system, 300.0)).kind == "not_settled"
    settled = structure_steady_state(simulate_system(system, 600.0))
    assert settled.kind == "periodic"
    other = find_structure_orbit(system, returns=1)
    assert other.stable and other.period == pytest.approx(9.3238, abs=1e-4) and _repeats(system, other, 3) < 1e-9
    orbit = find_structure_orbit(system)
    assert orbit.returns == 2 and orbit.period == pytest.approx(settled.period, rel=1e-8)
    assert orbit.stick_fraction == pytest.approx(settled.stick_fraction, abs=1e-6)
    assert orbit.stable and _repeats(system, orbit, 3) < 1e-9
    (tmp_path / "m.toml").write_text(TWO_ORBITS)
    code, stdout, _, _ = cli("orbit", "--model", str(tmp_path / "m.toml"), "--json")
    report = json.loads(stdout)
    assert code == 0 and report["returns"] == 2 and report["period"] == orbit.period


def test_a_forced_cycle_lasts_whole_forcing_periods_as_its_orbit():
    """simulate's period of a forced cycle is m 2 pi / Omega, bit for bit the orbit's: DRIFTING's crossings at
    t = 600 still give a mean 4e-8 longer than one forcing period (within simulate's 1e-6), FORCED's two
    periods to rounding."""
    system = _system(DRIFTING)
    motion = simulate_system(system, 600.0)
    forcing = 2.0 * math.pi / float(assemble(system).force_omega[0])
    assert abs(repeating(motion)[0] / forcing - 1.0) > 1e-8  # what the crossings measure
    ss = structure_steady_state(motion)
    assert ss.kind == "periodic" and ss.period == forcing
    system = _system(FORCED)
    ss = structure_steady_state(simulate_system(system, 600.0))
    assert ss.period == find_structure_orbit(system, t_transient=600.0).period


def test_a_stall_on_a_chaotic_motion_does_not_promise_a_cycle():
    """Five masses stick-slipping chaotically (simulate: chaotic at t = 300, test_structure_kinds' chain):
    the stall's line says a longer transient helps only if the motion settles on a cycle, and that simulate
    tells whether it does."""
    chain = chaotic_chain()
    assert structure_steady_state(simulate_system(chain, 300.0)).kind == "chaotic"
    with pytest.raises(ShootingError, match=r"stalled.*has not settled .*starts nearer a cycle if the motion "
                                            r"settles on one \(simulate --model says whether it does: "
                                            r"quasi-periodic and chaotic motions do not\)"):
        find_structure_orbit(chain)
