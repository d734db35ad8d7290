"""A structure's section that does not repeat: quasi-periodic, chaotic or not settled, as the single mass tells them."""

from __future__ import annotations

import math
import tomllib
from pathlib import Path

import numpy as np
import pytest

import frictionflow as ff
from frictionflow import quantities as Q
from frictionflow.analysis.structure import (MAX_CROSSINGS, STRUCTURE_KINDS, certified_sliding, repeating,
                                             structure_steady_state)
from frictionflow.analysis import structure_lyapunov
from frictionflow.analysis.structure_lyapunov import revisits
from frictionflow.core import strobe
from frictionflow.friction import law_classes
from frictionflow.orbits import find_structure_orbit
from frictionflow.solvers import RK4, Adaptive, Exact
from frictionflow.solvers.structure import simulate_system
from frictionflow.sweep.model import probe_length
from frictionflow.system import System, assemble

from .test_structure_sweep import TWO

ZETA, VB, FD, FS = 0.05, 0.01, 0.02, 0.04


def test_the_kinds_are_the_shared_ones():
    assert set(STRUCTURE_KINDS) - {"contact_lost"} <= set(Q.KINDS)
    assert STRUCTURE_KINDS[:4] == ("periodic", "equilibrium", "not_settled", "contact_lost")  # stored codes kept


def _cycle_period(zeta: float, law, vb: float, solver=None) -> float:
    """The single mass's stick-slip cycle from rest (the single-mass solver, exact by default, and analysis)."""
    tr = ff.simulate(ff.BeltOscillator(zeta=zeta, vb=vb), law, solver or Exact(), t_end=800.0, x0=0.0, v0=0.0)
    ss = ff.analyze(tr).steady_state
    assert ss.kind == "periodic"
    return ss.period


def _no_return(ratio: float) -> bool:
    """No repetition within the crossings the classifier looks at: after p <= MAX_CROSSINGS section crossings
    of either mass (p of its periods), the other's phase is at least 1e-4 of a cycle away from where it was
    (its state then differs by ~6e-4 of its size, far above the test's rtol 1e-6)."""
    return all(abs(p * r - round(p * r)) > 1e-4 for r in (ratio, 1.0 / ratio) for p in range(1, MAX_CROSSINGS + 1))


def test_two_uncoupled_stick_slip_cycles_are_quasi_periodic():
    """Two masses, each its own single-mass stick-slip cycle, with periods in no ratio p/q of small q: the motion
    lies on the product of the two cycles (a torus), never repeats and never leaves it.

    Mass 2 (k = 2) is the single mass in time tau = sqrt(2) t: y'' + (c / sqrt 2) y' + y = F / 2 with the belt
    at b / sqrt 2, so its period is the single mass's with zeta = c / (2 sqrt 2), F_d, F_s halved, V_b / sqrt 2,
    divided by sqrt 2."""
    c, w = 2.0 * ZETA, math.sqrt(2.0)
    t1 = _cycle_period(ZETA, ff.Coulomb(FD, FS), VB)
    t2 = _cycle_period(c / (2.0 * w), ff.Coulomb(FD / 2.0, FS / 2.0), VB / w) / w
    assert _no_return(t1 / t2)
    model = {"dof": ["x1", "x2"], "mass": [1.0, 1.0],
             "spring": [{"on": {"x1": 1.0}, "k": 1.0}, {"on": {"x2": 1.0}, "k": 2.0}],
             "damper": [{"on": {"x1": 1.0}, "c": c}, {"on": {"x2": 1.0}, "c": c}],
             "contact": [{"on": {d: 1.0}, "belt": VB, "friction": "coulomb", "fd": FD, "fs": FS} for d in ("x1", "x2")]}
    ss = structure_steady_state(simulate_system(System.from_dict(model, source=None), 3000.0))
    assert ss.kind == "quasi_periodic"
    assert abs(ss.lyapunov) < 1e-3


def test_two_uncoupled_stribeck_cycles_are_quasi_periodic_through_the_adaptive_solver():
    """As above with Stribeck's smooth slip curve, which only the adaptive structure solver runs: the exponent's
    runs are the motion's own solver's (they were the exact solver's, which refused the law: the analysis of any
    such run that did not repeat failed).  Mass 2's equivalent single mass also has v_s / sqrt 2 (V_r scales as
    the time does)."""
    c, w, vs = 2.0 * ZETA, math.sqrt(2.0), 0.012
    t1 = _cycle_period(ZETA, ff.Stribeck(fd=FD, fs=FS, vs=vs), VB, Adaptive())
    t2 = _cycle_period(c / (2.0 * w), ff.Stribeck(fd=FD / 2.0, fs=FS / 2.0, vs=vs / w), VB / w, Adaptive()) / w
    assert _no_return(t1 / t2)
    model = {"dof": ["x1", "x2"], "mass": [1.0, 1.0],
             "spring": [{"on": {"x1": 1.0}, "k": 1.0}, {"on": {"x2": 1.0}, "k": 2.0}],
             "damper": [{"on": {"x1": 1.0}, "c": c}, {"on": {"x2": 1.0}, "c": c}],
             "contact": [{"on": {d: 1.0}, "belt": VB, "friction": "stribeck", "fd": FD, "fs": FS, "vs": vs}
                         for d in ("x1", "x2")]}
    motion = simulate_system(System.from_dict(model, source=None), 3000.0, solver="adaptive")
    ss = structure_steady_state(motion)
    assert ss.kind == "quasi_periodic"
    assert abs(ss.lyapunov) < 1e-3


def test_the_exponent_s_runs_take_the_motion_s_solver_and_tolerances(monkeypatch):
    """Every run the exponent makes is on the solver and with the tolerances of the run it measures (a user's
    ``--ode-rtol`` included), so that the pair of runs is the same flow as the motion."""
    model = {"dof": ["x1", "x2"], "mass": [1.0, 1.0],
             "spring": [{"on": {"x1": 1.0}, "k": 1.0}, {"on": {"x2": 1.0}, "k": 2.0}],
             "damper": [{"on": {"x1": 1.0}, "c": 0.1}, {"on": {"x2": 1.0}, "c": 0.1}],
             "contact": [{"on": {d: 1.0}, "belt": VB, "friction": "stribeck", "fd": FD, "fs": FS, "vs": 0.012}
                         for d in ("x1", "x2")]}
    motion = simulate_system(System.from_dict(model, source=None), 400.0, solver="adaptive", rtol=1e-9)
    assert motion.settings == {"rtol": 1e-9, "atol": 1e-13, "max_steps": 10_000_000}
    calls, real = [], structure_lyapunov.run_assembly

    def spy(*args, **kwargs):
        calls.append((kwargs.get("solver"), kwargs.get("settings")))
        return real(*args, **kwargs)

    monkeypatch.setattr(structure_lyapunov, "run_assembly", spy)
    ss = structure_steady_state(motion)
    assert ss.kind != "periodic" and math.isfinite(ss.lyapunov)  # the exponent was measured
    assert calls and set(c[0] for c in calls) == {"adaptive"}
    assert all(c[1] == motion.settings for c in calls)


def test_a_one_dof_model_at_the_single_mass_chaotic_point_is_chaotic():
    """The single mass's chaotic point (tests/analysis/test_forced.py): the same kind, and the exponent of two
    nearby exact runs against the single mass's tangent-space exponent (saltation matrices, RK4)."""
    osc, law = ff.BeltOscillator(zeta=0.01, vb=0.1, fex=0.5, omega=1.0), ff.Coulomb(0.5, 1.0)
    t_end = 300 * osc.forcing_period
    single = ff.analyze(ff.simulate(osc, law, Exact(), t_end=t_end, x0=0.0, v0=0.0)).steady_state
    mine = structure_steady_state(simulate_system(System.single_mass(osc, law), t_end))
    assert mine.kind == single.kind == "chaotic"
    assert mine.lyapunov == pytest.approx(single.lyapunov, rel=0.1)


def test_a_one_dof_model_at_the_single_mass_quasi_periodic_point_is_quasi_periodic():
    """The single mass's quasi-periodic point (tests/analysis/test_forced.py: the stick-slip cycle forced weakly
    at an unrelated frequency)."""
    osc, law = ff.BeltOscillator(zeta=ZETA, vb=VB, fex=0.003, omega=2.1), ff.Coulomb(FD, FS)
    t_end = 400 * osc.forcing_period
    single = ff.analyze(ff.simulate(osc, law, RK4(dt=1e-3), t_end=t_end, x0=0.02, v0=0.01)).steady_state
    mine = structure_steady_state(simulate_system(System.single_mass(osc, law, x0=0.02, v0=0.01), t_end))
    assert mine.kind == single.kind == "quasi_periodic"
    assert abs(mine.lyapunov) < 1e-3


def test_a_transient_is_not_settled():
    """The two-mass chain on its way to a stick-slip cycle: not settled at t = 100 (a negative exponent: still
    converging), periodic when run to 400."""
    system = System.from_dict(tomllib.loads(TWO), source=None).with_entry("contact.0.belt", 0.005)
    early = structure_steady_state(simulate_system(system, 100.0))
    assert early.kind == "not_settled" and early.lyapunov < 0.0
    assert structure_steady_state(simulate_system(system, 400.0)).kind == "periodic"


def test_the_revisit_test_in_two_components_is_the_single_mass_s():
    """On (x, v) pairs, the structure's revisit test (any number of components) decides as the single mass's."""
    rng = np.random.default_rng(3)
    angle = np.sort(rng.uniform(0.0, 2.0 * np.pi, 40))
    ring = np.vstack((np.cos(angle), np.sin(angle)))  # a closed curve, sampled twice over
    ring = np.hstack((ring, ring + rng.normal(0.0, 1e-3, ring.shape)))
    drift = ring * np.linspace(1.0, 2.0, ring.shape[1])  # a spiral: the second half leaves the first
    for points in (ring, drift, ring[:, :10]):
        for tol in (1e-2, 0.3):
            assert revisits(points, tol) == strobe.revisits(points[0].copy(), points[1].copy(), tol)
    assert revisits(ring, 1e-2) and not revisits(drift, 1e-2)


#: per time dimension a law's parameter may declare, its factor when time is measured in units s times shorter
TIME_FACTOR = {"velocity": lambda s: 1.0 / s, "frequency": lambda s: 1.0 / s, "damping": lambda s: s}
#: a law parameter's name -> its dimension, from every registered law's declared parameters
LAW_DIMENSION = {p.name: p.dimension for cls in law_classes() for p in getattr(cls, "parameters", ())}


def _in_time_units(system: System, s: float) -> System:
    """``system`` with time measured in units ``s`` times shorter: masses times s^2, dampers times s, belts (and
    the RK4 band), forcing frequencies and initial velocities over s, each law parameter by its declared dimension
    (a Stribeck velocity over s); q(t) becomes q(t / s)."""
    def factor(entry: str) -> float | None:
        kind, *_, last = entry.split(".")
        if kind == "mass":
            return s * s
        if kind == "damper" and last == "c":
            return s
        if (kind == "contact" and last in ("belt", "rk4_band")) or entry.startswith("initial.v.") or \
                (kind == "force" and last == "omega"):
            return 1.0 / s
        if kind == "contact" and LAW_DIMENSION.get(last) in TIME_FACTOR:
            return TIME_FACTOR[LAW_DIMENSION[last]](s)
        return None

    out = system
    for entry in system.entries():
        if factor(entry) is not None:
            out = out.with_entry(entry, system.entry(entry) * factor(entry))
    return out


def chaotic_chain() -> System:
    """Five unit masses on springs and light dampers, stick-slipping chaotically on one belt (exponent ~0.01)."""
    springs = [{"on": {"x1": 1.0}, "k": 1.0}, *({"on": {f"x{i}": 1.0, f"x{i + 1}": -1.0}, "k": 0.5}
                                                for i in range(1, 5)), {"on": {"x5": 1.0}, "k": 1.0}]
    return System.from_dict({
        "dof": [f"x{i}" for i in range(1, 6)], "mass": [1.0] * 5, "spring": springs,
        "damper": [{"on": {f"x{i}": 1.0}, "c": 0.01} for i in range(1, 6)],
        "contact": [{"on": {f"x{i}": 1.0}, "belt": 0.05, "friction": "coulomb", "fd": 0.1,
                     "fs": 0.3 if i % 2 else 0.35} for i in range(1, 6)],
        "initial": {"q": {"x5": 0.2}}})


@pytest.mark.parametrize("s", [1e3, 1e-3])
def test_a_chaotic_chain_in_other_units_of_time_is_chaotic(s):
    """Five masses stick-slipping chaotically (exponent ~0.01) told in units of time 1000 times longer and shorter:
    every rate scales by 1 / s, so the kind is the same and the exponent about the unit chain's over s (a
    finite run's estimate of a chaotic flow moves by tens of per cent with rounding).  The exponent's least
    uncertainty was an absolute 1e-4 a unit of time: with masses of 1e6 the chain (exponent 1e-5) was not
    settled however long it ran."""
    unit = chaotic_chain()
    base = structure_steady_state(simulate_system(unit, 300.0))
    other = structure_steady_state(simulate_system(_in_time_units(unit, s), 300.0 * s))
    assert base.kind == other.kind == "chaotic"
    assert 0.5 < other.lyapunov * s / base.lyapunov < 2.0


MODELS = Path(__file__).parents[2] / "examples" / "models"
#: a 2-mass slider forced off resonance (no switch): its velocities converge at 5e-6 of their size a period at t 1000
FORCED_SLIDER = {
    "dof": ["x1", "x2"], "mass": [1.0, 1.0],
    "spring": [{"on": {"x1": 1.0}, "k": 1.0}, {"on": {"x1": 1.0, "x2": -1.0}, "k": 0.5}, {"on": {"x2": 1.0}, "k": 1.0}],
    "damper": [{"on": {"x1": 1.0}, "c": 0.04}, {"on": {"x2": 1.0}, "c": 0.02}],
    "contact": [{"on": {d: 1.0}, "belt": 0.5, "friction": "coulomb", "fd": 0.1, "fs": 0.12} for d in ("x1", "x2")],
    "force": [{"on": {"x1": 1.0}, "amplitude": 0.2, "omega": (1.0 + math.sqrt(5.0)) / 2.0}],
    "initial": {"q": {"x2": 0.1}}}
#: one mass thrown at 1 against a fixed surface: it stops and sticks at t ~ 3 (a run shorter than 4 pi units)
STOPS = {"dof": ["x"], "mass": [1.0], "spring": [{"on": {"x": 1.0}, "k": 1.0}], "damper": [{"on": {"x": 1.0}, "c": 0.5}],
         "contact": [{"on": {"x": 1.0}, "belt": 0.0, "friction": "coulomb", "fd": 0.3, "fs": 0.4}],
         "initial": {"v": {"x": 1.0}}}


def _hoffmann_sliding() -> dict:
    """Hoffmann's 2-dof model below flutter (mu 0.5): slipping for good about a centre, frequencies sqrt 1.5 and
    sqrt 2 (tests/structure/test_structure_verdicts.py): quasi-periodic."""
    model = tomllib.loads((MODELS / "hoffmann_2dof.toml").read_text())
    model["contact"][0].update(fd=0.5, fs=0.5)
    return model


def _model(name: str) -> dict:
    return tomllib.loads((MODELS / f"{name}.toml").read_text())


@pytest.mark.parametrize("model, t_end, solver, kind", [
    pytest.param(FORCED_SLIDER, 1000.0, "exact", "periodic", id="forced_slider"),
    pytest.param(STOPS, 50.0, "exact", "equilibrium", id="stops_short_run"),
    pytest.param(_model("two_mass_chain"), 300.0, "exact", "equilibrium", id="two_mass_chain"),
    pytest.param(_model("stick_slip_chain"), 1500.0, "exact", "periodic", id="stick_slip_chain"),
    pytest.param(_model("stick_slip_chain"), 300.0, "exact", "not_settled", id="stick_slip_chain_transient"),
    pytest.param(_hoffmann_sliding(), 300.0, "exact", "quasi_periodic", id="hoffmann_torus"),
    pytest.param(_model("stribeck_chain"), 1500.0, "adaptive", "periodic", id="stribeck_chain_adaptive"),
    pytest.param(_model("stribeck_chain"), 300.0, "adaptive", "not_settled", id="stribeck_chain_transient_adaptive"),
])
@pytest.mark.parametrize("s", [1e-3, 1e3])
def test_a_structure_in_other_units_of_time_is_told_the_same(model, t_end, solver, kind, s):
    """The same structure with time measured in units s times shorter (:func:`_in_time_units`) is the same motion
    q(t / s): the same kind, its period, window and Lyapunov exponent scaled by s, the same stick fractions.
    The tests were in one scale over positions and velocities together, so that in milliseconds the velocities
    (1000 times larger) set the positions' tolerance and in kiloseconds the positions set the velocities': the
    forced slider was not settled in milliseconds and periodic in seconds, the stick-slip chain the other way
    round, the mass that stopped was not at rest over a tail of 4 pi time units (the whole run in milliseconds),
    the torus not quasi-periodic in kiloseconds; the adaptive solver refused its own exponent's sampling step
    (a block of 8,000 units, beyond the single mass's 1,000)."""
    system = System.from_dict(model, source=None)
    unit = structure_steady_state(simulate_system(system, t_end, solver=solver))
    other = structure_steady_state(simulate_system(_in_time_units(system, s), t_end * s, solver=solver))
    assert unit.kind == other.kind == kind
    np.testing.assert_allclose(other.stick_fraction, unit.stick_fraction, rtol=0, atol=1e-9)
    np.testing.assert_allclose(np.array(other.window) / s, unit.window, rtol=1e-9)
    if kind == "periodic":
        assert other.period / s == pytest.approx(unit.period, rel=1e-9)
    if math.isfinite(unit.lyapunov):
        assert other.lyapunov * s == pytest.approx(unit.lyapunov, rel=1e-4)  # the same pair of runs, scaled


def test_a_free_chain_carried_along_by_the_belt_is_periodic():
    """Two masses joined by a spring, none to the ground, the first on the belt, the second forced at 0.8: a
    period-5 subharmonic while the belt carries the pair along (13 units in 300).  Its section states repeat up to
    a shift along the free translation (1, 1), which no spring, damper, contact or force sees: it is periodic
    (it was not_settled however long it ran).  The period is five forcing periods; one period later the
    velocities are the same and the positions shifted alike."""
    omega = 0.8
    system = System.from_dict({
        "dof": ["x1", "x2"], "mass": [1.0, 1.0], "spring": [{"on": {"x1": 1.0, "x2": -1.0}, "k": 1.0}],
        "damper": [{"on": {"x1": 1.0}, "c": 0.05}],
        "contact": [{"on": {"x1": 1.0}, "belt": 0.05, "friction": "coulomb", "fd": 0.1, "fs": 0.3}],
        "force": [{"on": {"x2": 1.0}, "amplitude": 0.3, "omega": omega}], "initial": {"q": {"x2": 0.2}}})
    motion = simulate_system(system, 600.0)
    ss = structure_steady_state(motion)
    assert ss.kind == "periodic"
    assert ss.period == pytest.approx(5 * 2.0 * math.pi / omega, rel=1e-9)
    t0 = ss.window[0]
    a, b = (motion.states([t])[:, 0] for t in (t0, t0 + ss.period))
    np.testing.assert_allclose(b[2:], a[2:], rtol=0, atol=1e-9)
    shift = b[:2] - a[:2]
    assert shift[0] > 1e-3 and shift[1] == pytest.approx(shift[0], abs=1e-9)


@pytest.mark.parametrize("s", [1e-6, 1e7])
def test_steady_sliding_is_proven_in_any_unit_of_time(s):
    """The two-mass chain slides into steady sliding, proven from the linearisation's modes.  The proof's
    rounding floor and the eigenvectors' condition number were taken on the state in its own units: in
    microseconds the velocity rows (10^6 larger) made cond(V) 2.4e6 instead of 4.45, the floor (2e4) exceeded
    the decay rate (2e4) and the run was not_settled (QA).  Now velocities count over the fastest rate, as
    lengths."""
    unit_system = System.from_dict(_model("two_mass_chain"), source=None)
    unit = simulate_system(unit_system, 300.0)
    other = simulate_system(_in_time_units(unit_system, s), 300.0 * s)
    assert certified_sliding(unit) and certified_sliding(other)
    assert structure_steady_state(other).kind == structure_steady_state(unit).kind == "equilibrium"


def test_a_sweep_s_probe_is_a_number_of_natural_periods():
    """The estimate's probe ran 50 time units whatever the units: 5e-6 of a period in units of time 1e7 (a 5 s
    sweep estimated at 78 days) and 5e7 periods in microseconds (a probe running for minutes) (QA).  Now it
    runs the same number of the structure's slowest natural periods in any unit of time."""
    unit_system = System.from_dict(_model("stick_slip_chain"), source=None)
    unit = probe_length(assemble(unit_system), 1e12)
    assert 20.0 < unit < 100.0  # about the 50 time units it was for unit masses and springs
    for s in (1e-6, 1e7):
        assert probe_length(assemble(_in_time_units(unit_system, s)), 1e12 * s) == pytest.approx(s * unit, rel=1e-12)
    assert probe_length(assemble(unit_system), 10.0) == 10.0


#: two masses with a full mass matrix, one contact at an angle, one with a position-dependent normal load: from
#: x1 = 0.3 it settles on a stable cycle of 8 stick episodes whose coordinate crosses the section 17 times a period
LONG_CYCLE = {
    "dof": ["x1", "x2"], "mass": [[1.0, 0.3], [0.3, 0.8]],
    "spring": [{"on": {"x1": 1.0}, "k": 1.0}, {"on": {"x1": 1.0, "x2": -1.0}, "k": 0.7}, {"on": {"x2": 1.0}, "k": 0.4}],
    "damper": [{"on": {"x1": 1.0}, "c": 0.02}],
    "contact": [{"on": {"x1": 1.0, "x2": 1.0}, "belt": 0.2, "friction": "coulomb", "fd": 0.3, "fs": 0.45},
                {"on": {"x2": 1.0}, "belt": -0.1, "friction": "coulomb", "fd": 0.1, "fs": 0.2,
                 "normal": {"preload": 1.0, "x1": 0.5}}],
    "initial": {"q": {"x1": 0.3}}}


def test_a_cycle_crossing_the_section_more_than_twelve_times_a_period_is_periodic():
    """It was ``not_settled`` at any length of run (t_end 3000 and 30000 tried), its exponent -0.025 saying the
    motion contracts: the classifier looked for at most 12 crossings a period.  Now up to 64 (the orbit
    command's ``--returns`` range): periodic, with the period, the stick fractions and the energy balance of the
    orbit shot independently (Newton on the 17th return, ``orbit --returns 17``)."""
    system = System.from_dict(LONG_CYCLE, source=None)
    motion = simulate_system(system, 1000.0)
    found = repeating(motion)
    assert found is not None and found[2] == 17
    ss = structure_steady_state(motion)
    assert ss.kind == "periodic"
    orbit = find_structure_orbit(system, t_transient=1000.0, returns=17)
    assert orbit.stable
    assert ss.period == pytest.approx(orbit.period, rel=1e-10)
    assert np.allclose(ss.stick_fraction, orbit.stick_fraction, atol=1e-9)
