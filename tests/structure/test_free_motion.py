"""Structures with an undamped free motion: a direction no spring, damper or normal load holds.

Along such a direction the motion is polynomial in time while the contacts slip (x'' constant), not a sum of
exponentials: the exact engine's modes refused it with "a mode combination's matrix is defective (e.g. an
undamped rigid mode)", and ``solver="auto"`` chose it anyway.  The adaptive solver runs them (its
``structure_free_motion``), and ``auto`` now picks it there.  The kinds of such a structure are told up to its
free translations: carried along by the belt at a constant speed it is at rest relative to it.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

import frictionflow as ff
from frictionflow.analysis.structure import STRUCTURE_KINDS, analyze_structure, structure_steady_state
from frictionflow.orbits.structure import find_structure_orbit
from frictionflow.solvers.structure import free_direction_text, simulate_system, structure_solver_for
from frictionflow.sweep import run_sweep
from frictionflow.sweep.model import parse_model_sweep
from frictionflow.system import System, load_system

from ..cli.processes import in_process, one_line
from .test_structure_kinds import _in_time_units

MODELS = Path(__file__).parents[2] / "examples" / "models"
#: a mass on a belt, nothing else: it catches up with the belt and rides on it
RIDER = {"dof": ["x"], "mass": [1.0],
         "contact": [{"on": {"x": 1.0}, "belt": 0.1, "friction": "coulomb", "fd": 0.1, "fs": 0.2}]}
B, C, K, FD, FS = 0.05, 0.02, 1.0, 0.12, 0.25


def _pair() -> System:
    """Two masses joined by a spring and a damper, nothing to the ground: x1 on a belt at B (it sticks there
    for good: the held force stays below its F_s 0.3), x2 on a fixed surface."""
    return System.from_dict({
        "dof": ["x1", "x2"], "mass": [1.0, 1.0], "spring": [{"on": {"x1": 1.0, "x2": -1.0}, "k": K}],
        "damper": [{"on": {"x1": 1.0, "x2": -1.0}, "c": C}],
        "contact": [{"on": {"x1": 1.0}, "belt": B, "friction": "coulomb", "fd": 0.1, "fs": 0.3},
                    {"on": {"x2": 1.0}, "belt": 0.0, "friction": "coulomb", "fd": FD, "fs": FS}],
        "initial": {"v": {"x1": B}}}, source=None)


def _two_belts() -> System:
    """The pair on two belts, both contacts slipping at times: the phase where both slip has x1 + x2 free."""
    return _pair().with_entry("contact.0.belt", -0.055).with_entry("contact.1.belt", -0.05)


def test_the_exact_engine_names_the_free_motion_and_auto_picks_the_adaptive_solver():
    for model, along in ((System.from_dict(RIDER, source=None), "along x none does"),
                         (_two_belts(), "along x1 \\+ x2 none does")):
        with pytest.raises(ValueError, match=f"solver=exact runs structures whose every motion .*{along}.*"
                                             "use solver=adaptive"):
            simulate_system(model, 50.0, solver="exact")
        assert structure_solver_for(model) == "adaptive"
    assert simulate_system(_two_belts(), 50.0, solver="adaptive").status == "ok"
    held = System.from_dict({**RIDER, "damper": [{"on": {"x": 1.0}, "c": 0.1}]}, source=None)
    assert structure_solver_for(held) == "exact"  # the damper holds it: exponential modes


def test_a_mass_riding_on_the_belt_is_at_rest_relative_to_it():
    """From rest it slips at F_d (x'' = 0.1) and catches the belt at t = 1; from then on it rides at 0.1 with no
    force: an equilibrium up to the free translation, every element's power 0, the balance closed."""
    motion = simulate_system(System.from_dict(RIDER, source=None), 50.0, solver=structure_solver_for(
        System.from_dict(RIDER, source=None)))
    result = analyze_structure(motion)
    assert result.steady_state.kind == "equilibrium"
    assert result.steady_state.stick_fraction == (1.0,)
    assert motion.states([50.0])[:, 0] == pytest.approx([0.05 + 0.1 * 49.0, 0.1], rel=1e-9)  # 0.05 by t = 1
    assert result.elements["contact.0"] == {"P_belt": 0.0, "P_heat": 0.0}
    assert abs(result.energy_residual) < 1e-12


def test_a_free_pair_dragged_by_one_belt_is_the_single_mass_in_the_belt_s_frame():
    """x1 rides on its belt, so y = x2 - x1 obeys y'' + C y' + K y = F(V_r) with V_r = 0 - x2' = -B - y': the
    single mass on a belt at -B (mirrored: at +B).  The structure's kind, period and x2's stick fraction are
    the single mass's (exact solver), within the adaptive solver's tolerance.  Its section is x2' falling to 0,
    where x2 sticks: the grid point after the stick was taken for the crossing, so the states (x1 moving on)
    depended on the grid's phase and the cycle was never periodic."""
    single = ff.analyze(ff.simulate(ff.BeltOscillator(zeta=C / 2.0, vb=B), ff.Coulomb(FD, FS), t_end=600.0,
                                    x0=0.0, v0=0.0)).steady_state
    assert structure_solver_for(_pair()) == "adaptive"  # the free motion could be met: auto cannot know
    for solver, rtol in (("adaptive", 1e-9), ("exact", 1e-12)):  # x1 never slips: the exact engine runs it
        ss = structure_steady_state(simulate_system(_pair(), 300.0, solver=solver))
        assert single.kind == ss.kind == "periodic"
        assert ss.period == pytest.approx(single.period, rel=rtol)
        assert ss.stick_fraction[0] == 1.0
        assert ss.stick_fraction[1] == pytest.approx(single.stick_fraction, abs=10 * rtol)


def test_orbits_say_they_follow_the_exact_engine_where_a_free_motion_is_met():
    """``orbit --model`` on the free pair on two belts stopped with the engine's "defective" line and two numpy
    warnings: now one line naming the free motion and the command that runs it."""
    with pytest.raises(ValueError, match="orbits follow the exact engine's phases.*along x1 \\+ x2 no spring.*"
                                         "simulate runs it with solver=adaptive"):
        find_structure_orbit(_two_belts(), t_transient=50.0)


def test_an_option_refused_beside_a_model_names_the_ones_the_command_takes(tmp_path):
    """The refusal said "(set them in the model file)" for --solver with orbit and --dt with simulate, which
    are no model file's entries: now it lists the single-mass options the command takes beside --model."""
    path = tmp_path / "m.toml"
    path.write_text('dof = ["x"]\nmass = [1.0]\n[[spring]]\non = { x = 1.0 }\nk = 1.0\n[[contact]]\n'
                    'on = { x = 1.0 }\nbelt = 0.1\nfriction = "coulomb"\nfd = 0.1\nfs = 0.2\n')
    code, out, err, _ = in_process("orbit", "--model", str(path), "--solver", "adaptive")
    assert code == 2 and out == ""
    one_line(err, "--solver cannot be given with it (beside it only --t-end, --tol, --returns, --guess, --fd-check, "
                  "--json, --out apply; the model's own entries are in its file)")
    code, out, err, _ = in_process("simulate", "--model", str(path), "--dt", "0.1")
    assert code == 2 and out == ""
    one_line(err, "--dt cannot be given with it (beside it only --t-end, --window, --rtol, --solver")
    for flag in ("--max-memory", "--json", "--out", "--plot"):  # the command's own options beside the model
        assert flag in err


def test_a_free_chain_riding_its_belt_is_an_equilibrium():
    """Two masses (2 and 0.7) joined by a spring of 5, both on a belt at 0.1, nothing to the ground: they catch
    the belt and ride on it.  The rigid mode's natural frequency comes out 3e-8, not 0, and was taken for the
    slowest natural period (2e8): the tail the kind is judged on was the whole run, transient included, and the
    run not_settled (auto runs it on the adaptive solver: the pair is free as a whole)."""
    system = System.from_dict({
        "dof": ["x1", "x2"], "mass": [2.0, 0.7], "spring": [{"on": {"x1": 1.0, "x2": -1.0}, "k": 5.0}],
        "contact": [{"on": {d: 1.0}, "belt": 0.1, "friction": "coulomb", "fd": 0.3, "fs": 0.4} for d in ("x1", "x2")],
        "initial": {"q": {"x2": 0.05}}}, source=None)
    motion = simulate_system(system, 200.0, solver=structure_solver_for(system))
    ss = structure_steady_state(motion)
    assert ss.kind == "equilibrium" and ss.window[0] > 100.0
    assert motion.states([200.0])[2:, 0] == pytest.approx([0.1, 0.1], rel=1e-9)


def test_the_free_direction_is_written_with_its_signs():
    assert free_direction_text(np.array([[-0.5], [1.0]]), ("x1", "x2")) == "-0.5 x1 + x2"
    assert free_direction_text(np.array([[1.0], [-1.0]]), ("x1", "x2")) == "x1 - x2"
    assert free_direction_text(np.array([[-1.0], [-0.2]]), ("x1", "x2")) == "x1 + 0.2 x2"


def test_a_sweep_point_that_frees_a_motion_runs_on_the_solver_that_runs_it(tmp_path):
    """A mass on a belt held by a damper to the ground (the exact engine runs it) swept over the damper down
    to 0, where nothing holds it: the sweep ran every point on the base model's solver, and the point c = 0
    failed the whole sweep.  Each point now takes simulate's choice at that point, and equals its run."""
    system = System.from_dict({**RIDER, "damper": [{"on": {"x": 1.0}, "c": 0.1}]}, source=None)
    ds = run_sweep(parse_model_sweep({"t_end": 60.0, "grid": {"damper.0.c": [0.1, 0.0]}}, system),
                   tmp_path / "r.nc").load()
    for i, c in enumerate((0.1, 0.0)):
        point = system.with_entry("damper.0.c", c)
        own = analyze_structure(simulate_system(point, 60.0, solver=structure_solver_for(point)))
        got = ds.isel({"damper.0.c": i})
        assert STRUCTURE_KINDS[int(got["kind"])] == own.steady_state.kind
        assert float(got["P_heat"].sel(contact="contact.0")) == own.elements["contact.0"]["P_heat"]
    assert structure_solver_for(system.with_entry("damper.0.c", 0.0)) == "adaptive"


def test_a_forced_mass_riding_its_belt_from_the_start_is_at_rest_relative_to_it():
    """A free mass started at its belt's speed with a harmonic force (0.3) below F_s (0.6): it rides the belt
    for good, the friction holding the force.  Its velocities had no range over the run, so the rest test's
    tolerance was 0 and the drift's removal left rounding in the positions: not_settled however long (QA).
    Now at rest relative to the belt, and the sweep's points reaching it from two starts agree."""
    model = {**RIDER, "contact": [{**RIDER["contact"][0], "belt": 0.2, "fd": 0.5, "fs": 0.6}],
             "force": [{"on": {"x": 1.0}, "amplitude": 0.3, "omega": 1.3}], "initial": {"v": {"x": 0.2}}}
    for v0 in (0.2, 0.0):
        system = System.from_dict(model, source=None).with_entry("initial.v.x", v0)
        ss = structure_steady_state(simulate_system(system, 300.0, solver=structure_solver_for(system)))
        assert ss.kind == "equilibrium" and ss.stick_fraction == (1.0,)


def test_a_bad_window_beside_a_model_is_the_single_mass_s_line(tmp_path):
    """``--window 10`` beside ``--model`` said "not enough values to unpack (expected 2, got 1)" (QA)."""
    out = tmp_path / "r.nc"
    for bad, line in (("10", "window must be T0:T1 with T0 < T1, got '10'"),
                      ("a:b", "window T0 must be a finite real number, got 'a'"),
                      ("5:3", "window must be T0:T1 with T0 < T1, got '5:3'")):
        code, stdout, err, _ = in_process("simulate", "--model", str(MODELS / "stick_slip_chain.toml"), "--window",
                                          bad, "--out", str(out))
        assert code == 2 and stdout == "" and not out.exists()
        one_line(err, line)


def test_a_window_given_beside_a_model_is_said_to_be_set_by_hand():
    """``--window A:B`` beside ``--model`` gave the window's averages without the single mass's ``manual_window``
    flag, so a report could not tell a window set by hand from one detected; the averages are the window's."""
    args = ("simulate", "--model", str(MODELS / "stick_slip_chain.toml"), "--t-end", "60", "--json")
    code, stdout, err, _ = in_process(*args, "--window", "20:40")
    assert code == 0, err
    ss = json.loads(stdout)["steady_state"]
    assert ss["window"] == [20.0, 40.0] and ss["manual_window"] is True
    code, stdout, err, _ = in_process(*args)
    assert code == 0, err
    assert json.loads(stdout)["steady_state"]["manual_window"] is False
    motion = simulate_system(load_system(MODELS / "stick_slip_chain.toml"), 60.0)
    by_hand = analyze_structure(motion, window=(20.0, 40.0))
    assert by_hand.steady_state.manual_window and "window set by hand" in str(by_hand.steady_state)
    assert by_hand.elements == motion.element_power(20.0, 40.0)


@pytest.mark.parametrize("s", [1e-5, 1e5])
def test_a_mass_on_a_belt_alone_runs_alike_in_any_unit_of_time(s):
    """A mass on a belt with nothing else has no time scale of its own; the adaptive solver's longest step
    was 0.25 time units then, so in units 1e5 times longer the run took ten million steps and hit the step
    cap (QA).  Now the longest step is a share of the run: the same motion, within a few thousand steps."""
    unit_system = System.from_dict(RIDER, source=None)
    system = _in_time_units(unit_system, s)
    unit = simulate_system(unit_system, 50.0, solver="adaptive", max_steps=20_000)
    other = simulate_system(system, 50.0 * s, solver="adaptive", max_steps=20_000)
    assert structure_steady_state(other).kind == structure_steady_state(unit).kind == "equilibrium"
    assert other.states([50.0 * s])[:, 0] == pytest.approx(unit.states([50.0])[:, 0] * [1.0, 1.0 / s], rel=1e-9)
