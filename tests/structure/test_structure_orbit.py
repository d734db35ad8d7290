"""Periodic orbits of structures (issue 22 item 4): shooting on the return map, exact monodromy, Floquet multipliers.

Independent references: the single-mass orbit finder (its own flow maps and
saltation) on the golden Coulomb cases; finite-difference monodromies from
runs of the exact engine written here; the flow direction (vector field
assembled by hand) as the trivial multiplier's eigenvector; one period of
the engine from the orbit's state returning to it.
"""

from __future__ import annotations

import json
import tomllib
from pathlib import Path

import numpy as np
import pytest

from frictionflow import BeltOscillator, Coulomb
from frictionflow.core.layout import FD
from frictionflow.analysis.structure import analyze_structure, section_times, structure_steady_state
from frictionflow.orbits import find_orbit
from frictionflow.orbits.shooting import ShootingError
from frictionflow.orbits.structure import find_structure_orbit
from frictionflow.solvers.structure import run_assembly, simulate_system
from frictionflow.system import System, load_system
from frictionflow.cli.structure_orbit import DEFAULT_TRANSIENT, orbit_report
from tests.cli.processes import cli, in_process, one_line
from tests.golden.cases import ORBIT

from .builders import assembly, chain, single_mass
from .test_structure_kinds import _in_time_units

EXAMPLES = Path(__file__).parents[2] / "examples" / "models"

#: two-mass chains with stick-slip orbits: (fs, belts, damper c, coupling k, section crossings per period)
CHAINS = {
    "both_stick": (0.2, (0.02, 0.026), 0.3, 0.5, 1),
    "light_damping": (0.2, (0.02, 0.026), 0.1, 0.5, 1),
    "one_sticks": (0.2, (0.02, 0.04), 0.3, 0.3, 1),
    "period_two": (0.2, (0.01, 0.013), 0.6, 0.5, 2),
}


def _chain(name):
    fs, belts, c, kc, returns = CHAINS[name]
    return chain(2, Coulomb(fd=0.1, fs=fs), list(belts), c=c, k_couple=kc, q0=[0.0, 0.5]), returns


def _golden_args(case):
    argv = ORBIT[case]
    values = {argv[i][2:]: argv[i + 1] for i in range(1, len(argv) - 1, 2) if argv[i].startswith("--")}
    assert values["friction"] == "coulomb"
    return BeltOscillator(zeta=float(values["zeta"]), vb=float(values["vb"])), \
        Coulomb(fd=float(values["fd"]), fs=float(values["fs"])), float(values["t-end"])


def _end(asm, y, t_end):
    n = len(asm.q0)
    motion = run_assembly(asm._replace(q0=y[:n].copy(), v0=y[n:].copy()), t_end)
    return motion.state[:, -1]


def _fd_monodromy(asm, y, period, h=1e-7):
    """Central differences of the engine's time-``period`` map (independent of the phase matrices and saltation)."""
    cols = [(_end(asm, y + h * e, period) - _end(asm, y - h * e, period)) / (2 * h) for e in np.eye(len(y))]
    return np.column_stack(cols)


def _field(asm, y):
    """(q', q'') with every contact slipping, assembled by hand: M q'' = -K q - C q' + sum sigma_j fd_j e_j."""
    n = len(asm.q0)
    q, v = y[:n], y[n:]
    sigma = np.sign(asm.belt - asm.contact_dir @ v)
    friction = asm.contact_dir.T @ (sigma * asm.law[:, FD])
    return np.concatenate((v, np.linalg.solve(asm.mass, -asm.stiffness @ q - asm.damping @ v + friction)))


@pytest.mark.parametrize("case", sorted(c for c in ORBIT if c.startswith("orbit_coulomb")))
def test_one_dof_equals_the_single_mass_orbit(case):
    osc, law, transient = _golden_args(case)
    ref = find_orbit(osc, law, transient=transient)
    found = find_structure_orbit(System.single_mass(osc, law, x0=law.fd, v0=osc.vb), t_transient=transient)
    assert found.period == pytest.approx(ref.period, rel=1e-9, abs=0)
    assert found.state[0] == pytest.approx(ref.state[0], rel=1e-9) and found.state[1] == 0.0
    np.testing.assert_allclose(np.sort_complex(found.multipliers), np.sort_complex(ref.multipliers), atol=1e-9)
    np.testing.assert_allclose(found.monodromy, ref.monodromy, atol=1e-9)
    assert found.stability == ref.stability == "stable"
    assert found.stick_fraction[0] == pytest.approx(ref.stick_fraction, abs=1e-9)


@pytest.mark.parametrize("zeta, vb, stick_force", [(0.05, 0.01, "spring"), (0.02, 0.005, "spring"),
                                                   (0.03, 0.01, "resultant")])
def test_one_dof_equals_the_single_mass_orbit_for_either_held_force(zeta, vb, stick_force):
    osc, law = BeltOscillator(zeta=zeta, vb=vb), Coulomb(fd=0.02, fs=0.04, stick_force=stick_force)
    ref = find_orbit(osc, law, transient=300.0)
    found = find_structure_orbit(System.single_mass(osc, law, x0=law.fd, v0=vb), t_transient=300.0)
    assert found.period == pytest.approx(ref.period, rel=1e-9, abs=0)
    np.testing.assert_allclose(found.monodromy, ref.monodromy, atol=1e-9)


def test_one_dof_monodromy_against_finite_differences():
    law = Coulomb(fd=0.02, fs=0.04)
    asm = single_mass(0.05, 0.01, law, 0.02, 0.01)
    found = find_structure_orbit(asm)
    np.testing.assert_allclose(found.monodromy, _fd_monodromy(asm, found.state, found.period), atol=1e-6)


@pytest.mark.parametrize("name", sorted(CHAINS))
def test_chain_orbit_is_a_fixed_point_of_one_period(name):
    asm, returns = _chain(name)
    found = find_structure_orbit(asm, returns=returns)
    assert found.state[2 + ["q0", "q1"].index(found.section)] == 0.0
    np.testing.assert_allclose(_end(asm, found.state, found.period), found.state, atol=1e-10)
    assert all(0.0 <= s < 1.0 for s in found.stick_fraction) and max(found.stick_fraction) > 0.1
    assert found.energy_residual < 1e-12


@pytest.mark.parametrize("name", sorted(CHAINS))
def test_chain_monodromy_against_finite_differences(name):
    asm, returns = _chain(name)
    found = find_structure_orbit(asm, returns=returns)
    assert np.all(found.motion.modes[:, 0] != 0)  # the section point slips: every perturbation is admissible
    fd = _fd_monodromy(asm, found.state, found.period)
    np.testing.assert_allclose(found.monodromy, fd, atol=1e-6 * max(1.0, np.abs(fd).max()))
    mu_fd = np.linalg.eigvals(fd)
    for mu in found.multipliers:
        assert np.min(np.abs(mu_fd - mu)) < 1e-5


def test_chain_with_a_state_dependent_normal_load():
    """contact.0's load N = 1 - 0.3 x2: the slip force adds stiffness and the stick limit moves with x2."""
    law = Coulomb(fd=0.1, fs=0.2).kernel_params()
    asm = assembly([1.0, 1.0], springs=[([1, 0], 1.0), ([0, 1], 1.0), ([1, -1], 0.5)],
                   dampers=[([1, 0], 0.3), ([0, 1], 0.3)],
                   contacts=[([1, 0], 0.02, law, [1.0, 0.0, -0.3]), ([0, 1], 0.026, law, None)], q0=[0.0, 0.5])
    found = find_structure_orbit(asm)
    assert min(found.stick_fraction) > 0.1
    np.testing.assert_allclose(_end(asm, found.state, found.period), found.state, atol=1e-10)
    fd = _fd_monodromy(asm, found.state, found.period)
    np.testing.assert_allclose(found.monodromy, fd, atol=1e-6 * max(1.0, np.abs(fd).max()))


@pytest.mark.parametrize("name", sorted(CHAINS))
def test_trivial_multiplier_is_the_flow_direction(name):
    asm, returns = _chain(name)
    found = find_structure_orbit(asm, returns=returns)
    f0 = _field(asm, found.state)
    np.testing.assert_allclose(found.monodromy @ f0, f0, atol=1e-9 * np.abs(f0).max())
    assert np.min(np.abs(found.multipliers - 1.0)) < 1e-9
    assert found.stable and abs(found.multiplier) < 1.0


def test_newton_from_a_perturbed_guess_converges_to_the_same_orbit():
    asm, _ = _chain("light_damping")
    found = find_structure_orbit(asm)
    guess = found.state + np.array([0.01, -0.01, 0.0, 0.002])
    again = find_structure_orbit(asm, guess, t_transient=0.0, section=found.section)
    assert again.iterations >= 1
    assert again.period == pytest.approx(found.period, rel=1e-10)
    np.testing.assert_allclose(again.state, found.state, atol=1e-10)


@pytest.mark.parametrize("name", ["both_stick", "light_damping"])
def test_a_section_point_with_a_stuck_contact(name):
    """On q0' = 0 contact.1 is stuck (q1' = its belt): Newton moves within that constraint, and the orbit, its
    period and its multipliers are those found on the other section."""
    asm, _ = _chain(name)
    other = find_structure_orbit(asm, section="q1")
    found = find_structure_orbit(asm, section="q0")
    assert list(found.motion.modes[:, 0]) == [1, 0] and found.state[3] == asm.belt[1]
    assert found.period == pytest.approx(other.period, rel=1e-12)
    np.testing.assert_allclose(np.sort_complex(found.multipliers), np.sort_complex(other.multipliers), atol=1e-9)
    again = find_structure_orbit(asm, found.state + np.array([0.002, -0.002, 0.0, 0.0]), t_transient=0.0,
                                 section="q0")
    assert again.iterations >= 1
    np.testing.assert_allclose(again.state, found.state, atol=1e-12)
    np.testing.assert_allclose(_end(asm, found.state, found.period), found.state, atol=1e-10)


def test_element_powers_over_one_period_balance():
    asm, _ = _chain("both_stick")
    found = find_structure_orbit(asm)
    el = found.elements
    # over a period the stored energy returns: the belts' input is what the dampers and interfaces take out
    springs = sum(p["P"] for name, p in el.items() if name.startswith("spring."))
    dampers = sum(p["P"] for name, p in el.items() if name.startswith("damper."))
    belts = sum(p["P_belt"] for name, p in el.items() if name.startswith("contact."))
    heat = sum(p["P_heat"] for name, p in el.items() if name.startswith("contact."))
    assert abs(springs) < 1e-12 and dampers < 0.0 < heat
    assert belts + dampers - heat == pytest.approx(0.0, abs=1e-12 * belts)
    # V_r >= 0 throughout (no slip-): the heat F_d |V_r| averages to F_d <V_r> = F_d (b - <q'>) = F_d b
    assert np.all(found.motion.modes >= 0)
    for j in range(2):
        assert el[f"contact.{j}"]["P_heat"] == pytest.approx(asm.law[j, FD] * asm.belt[j], rel=1e-12)


def test_bad_arguments_are_refused_in_one_line():
    asm, _ = _chain("both_stick")
    with pytest.raises(ValueError, match="tol must be in"):
        find_structure_orbit(asm, tol=0.1)
    with pytest.raises(ValueError, match="returns must be"):
        find_structure_orbit(asm, returns=0)
    with pytest.raises(ValueError, match="guess_state must be 4"):
        find_structure_orbit(asm, [0.0, 1.0])
    with pytest.raises(ValueError, match="section must be"):
        find_structure_orbit(asm, section="x9")
    with pytest.raises(TypeError, match="system_or_assembly"):
        find_structure_orbit("model.toml")


def test_a_settled_equilibrium_is_no_orbit():
    asm = chain(2, Coulomb(fd=0.1, fs=0.1), [0.5, 0.5], c=0.5, q0=[0.1, 0.1])  # fast belt: steady sliding
    with pytest.raises(ShootingError, match="equilibrium"):
        find_structure_orbit(asm, t_transient=200.0)


def test_a_slow_spiral_into_steady_sliding_is_no_orbit_as_simulate_finds():
    # the shipped two-mass chain: light damping (c = 0.04), so after the transient the motion still crosses the
    # section, ever smaller; Newton used to chase the shrinking spiral and stall ("Newton stalled at residual
    # 3e-11").  The run's end is certified to slide into the equilibrium, the same proof simulate's analysis uses
    system = load_system(Path(__file__).parents[2] / "examples" / "models" / "two_mass_chain.toml")
    motion = simulate_system(system, 300.0)
    assert analyze_structure(motion).steady_state.kind == "equilibrium"
    assert len(section_times(motion)) > 10  # still crossing: the old route went on to Newton
    with pytest.raises(ShootingError, match="^the motion settles on the steady-sliding equilibrium .* t=300 "):
        find_structure_orbit(system, t_transient=300.0)


MODEL = """dof = ["x1", "x2"]
mass = [1.0, 1.0]
[[spring]]
on = { x1 = 1.0 }
k = 1.0
[[spring]]
on = { x2 = 1.0 }
k = 1.0
[[spring]]
on = { x1 = 1.0, x2 = -1.0 }
k = 0.5
[[damper]]
on = { x1 = 1.0 }
c = 0.3
[[damper]]
on = { x2 = 1.0 }
c = 0.3
[[contact]]
on = { x1 = 1.0 }
belt = 0.02
friction = "coulomb"
fd = 0.1
fs = 0.2
[[contact]]
on = { x2 = 1.0 }
belt = 0.026
friction = "coulomb"
fd = 0.1
fs = 0.2
[initial]
q = { x2 = 0.5 }
"""


def test_cli_orbit_model_json(tmp_path):
    path = tmp_path / "chain.toml"
    path.write_text(MODEL, encoding="utf-8")
    code, out, err, _ = in_process("orbit", "--model", str(path), "--json", "--tol", "1e-11")
    assert code == 0, err
    report = json.loads(out)
    api = find_structure_orbit(_chain("both_stick")[0], tol=1e-11)
    assert report["period"] == pytest.approx(api.period, rel=1e-10)
    assert report["section"] == "x2" and report["stable"] is True
    assert [m["re"] for m in report["multipliers"]] == pytest.approx([m.real for m in api.multipliers], abs=1e-9)
    assert report["stick_fraction"] == pytest.approx(list(api.stick_fraction), abs=1e-9)
    assert set(report["elements"]) == set(load_system(path).element_names)
    assert report["energy_residual"] < 1e-12
    assert report["state"]["v"]["x2"] == 0.0


def test_cli_orbit_model_refuses_single_mass_options(tmp_path):
    path = tmp_path / "chain.toml"
    path.write_text(MODEL, encoding="utf-8")
    code, out, err, _ = in_process("orbit", "--model", str(path), "--zeta", "0.1")
    assert code == 2 and out == ""
    one_line(err, "--zeta", "--model")
    code, out, err, _ = in_process("orbit", "--model", str(path), "--plot", str(tmp_path / "o.png"))
    assert code == 2 and not (tmp_path / "o.png").exists()
    one_line(err, "--plot")
    for bad in ("-5", "nan"):  # named as the option's t_end (it said the API's "t_transient must be ...")
        code, out, err, _ = in_process("orbit", "--model", str(path), "--t-end", bad)
        assert code == 2 and out == ""
        one_line(err, "t_end must be a finite number > 0 (the transient before shooting)")


def test_cli_orbit_model_estimated_before_work(tmp_path):
    """A transient whose switches alone would take hours is refused in one line before any run."""
    path = tmp_path / "chain.toml"
    path.write_text(MODEL, encoding="utf-8")
    code, out, err, seconds = cli("orbit", "--model", str(path), "--t-end", "1e9", "--json")
    assert code == 2 and out == ""
    one_line(err, "switches", "--no-limit")


def test_a_contact_the_exact_engine_does_not_run_is_refused_without_advice_that_cannot_be_followed(tmp_path):
    """Shooting and its monodromy are the exact engine's: a Stribeck contact is refused in one line that names it
    and no --solver (the command takes none with --model; it once said "use solver=adaptive")."""
    model = tmp_path / "s.toml"
    model.write_text('dof = ["x"]\nmass = [1.0]\n[[spring]]\non = { x = 1.0 }\nk = 1.0\n[[damper]]\non = { x = 1.0 }\n'
                     'c = 0.1\n[[contact]]\non = { x = 1.0 }\nbelt = 0.01\nfriction = "stribeck"\nvs = 0.01\nfd = 0.02\n'
                     'fs = 0.04\n')
    with pytest.raises(ValueError, match=r"exact engine, which runs contacts with the laws coulomb; contact.0 has "
                                         r"friction=stribeck"):
        find_structure_orbit(load_system(model))
    code, out, err, _ = in_process("orbit", "--model", str(model))
    assert code == 2 and out == ""
    assert "solver=" not in one_line(err, "contact.0 has friction=stribeck")



def test_the_fd_check_compares_along_the_stuck_contacts_constraints():
    """A full mass matrix, x2 stuck at the section (QA: stick_slip_chain with these entries): a kick to x2' across its
    stick constraint is held by the exact monodromy (a zero column) and spread to x1' by M^-1 in the differences
    (0.2 of x1''s column), a convention, not an error: --fd-check reported 0.06.  Along the constraint the two agree
    to the differences' accuracy."""
    system = load_system(EXAMPLES / "stick_slip_chain.toml").with_entries({
        "mass.0.1": 0.2, "mass.1": 1.5, "contact.0.normal.preload": 1.0, "contact.0.normal.x1": 0.5,
        "contact.0.normal.x2": -1.0})
    found = find_structure_orbit(system, t_transient=DEFAULT_TRANSIENT)
    report = orbit_report(found, EXAMPLES / "stick_slip_chain.toml", DEFAULT_TRANSIENT, fd_check=True)  # --fd-check's
    M, fd = np.array(report["monodromy"]), np.array(report["fd_monodromy"])
    assert report["stick_fraction"][1] > 0 and report["fd_deviation"] < 1e-6
    across = np.abs(fd - M).max(axis=0)  # by column: (q1, q2, q1', q2')
    assert across[3] > 1e-2 and np.all(M[:, 3] == 0.0) and max(across[:3]) < 1e-6


def test_a_stiff_dampers_creep_multiplier_is_told_from_the_trivial_one():
    """m1 on a damper c to the ground: the orbit has a creep multiplier 1 - O(T / c) beside the trivial 1.  At
    c = 1e9 the monodromy's rounding (~c EPS) moved the trivial one to 1 + 2.4e-7, farther from 1 than the creep
    one, so dropping the multiplier nearest 1 kept it and called the orbit unstable.  Now the nontrivial
    multipliers are M's across the flow vector: at c = 1e7 the same as dropping the one nearest 1; the creep
    multiplier scales as 1 / c (c (1 - mu) the same at 1e7 and 1e9, measured 10.11); the orbit is not unstable."""
    base = load_system(EXAMPLES / "stick_slip_chain.toml")
    orbits = {c: find_structure_orbit(base.with_entry("damper.0.c", c)) for c in (1e7, 1e9)}
    low = orbits[1e7]
    mu = low.multipliers
    np.testing.assert_allclose(low.nontrivial, np.delete(mu, np.argmin(np.abs(mu - 1.0))), rtol=0, atol=1e-9)
    creep = {c: c * (1.0 - o.multiplier.real) for c, o in orbits.items()}
    assert creep[1e7] > 1.0 and creep[1e9] == pytest.approx(creep[1e7], rel=1e-3)
    assert orbits[1e9].stability != "unstable" and abs(orbits[1e9].multiplier.imag) == 0.0
    f = orbits[1e9].tangent
    # M f = f to the monodromy's rounding, ~c EPS (its modal basis's condition number; measured 7 c EPS)
    assert np.abs(orbits[1e9].monodromy @ f - f).max() < 16.0 * 1e9 * np.finfo(float).eps * np.abs(f).max()


def _frozen_third(c: float | None):
    """The stick-slip pair of ``CHAINS["both_stick"]`` with x1 sprung (0.01) to a third mass held by a damper ``c``
    and a spring to the ground; None: the third mass frozen, its spring added to x1's ground spring."""
    law = Coulomb(fd=0.1, fs=0.2).kernel_params()
    n = 2 if c is None else 3
    e = np.eye(n)
    springs = [(e[0], 1.0 if c else 1.01), (e[1], 1.0), (e[0] - e[1], 0.5)]
    dampers = [(e[0], 0.3), (e[1], 0.3)]
    if c is not None:
        springs += [(e[0] - e[2], 0.01), (e[2], 1.0)]
        dampers += [(e[2], c)]
    return assembly(np.ones(n), springs=springs, dampers=dampers,
                    contacts=[(e[0], 0.02, law, None), (e[1], 0.026, law, None)], q0=[0.0, 0.5, 0.0][:n])


@pytest.mark.parametrize("c", [1e4, 1e6, 1e9])
def test_an_orbit_beside_a_stiff_damper_is_the_frozen_models_orbit(c):
    """A third mass held by a damper c moves by O(1/c) a period: the orbit is the 2-dof model's with that mass
    frozen (an independent run on well-scaled matrices) to O(1/c) -- period (measured 2.84e-4 / c) and its
    nontrivial multiplier -- plus a creep multiplier 1 - (k + 0.01) T / c and one fast multiplier near 0.  The
    creep's 1 - mu is measured to 1e-4 of itself up to c = 1e6; beyond, it sinks into the monodromy's rounding
    (~c EPS, as above: 3 % off at c = 1e9, measured), which the bound allows."""
    frozen = find_structure_orbit(_frozen_third(None))
    orbit = find_structure_orbit(_frozen_third(c), section=0)
    assert abs(orbit.period - frozen.period) < 1e-3 / c + 1e-11
    mu = np.sort(np.abs(orbit.multipliers))
    slow = np.sort(np.abs(frozen.multipliers))
    assert mu[3] == pytest.approx(slow[2], abs=1e-3 / c + 1e-9)  # the pair's nontrivial multiplier
    creep = 1.01 * orbit.period / c  # the third mass's: rate (k + 0.01) / c, back-coupling O(1e-4) of it
    assert abs((1.0 - mu[4]) - creep) <= 1e-3 * creep + c * np.finfo(float).eps
    assert mu[5] == pytest.approx(1.0, abs=1e-9) and max(mu[:3]) < 1e-12  # trivial; the fast root's and the stuck


def test_newton_from_a_transient_shorter_than_the_slowest_time_scale_says_so():
    """A damper of 1e4 between the stick-slip chain's masses: a creep of multiplier 0.99955 a period (time scale
    2 pi / |lambda| = 6.65e4).  From the default transient (300) Newton's steps along it are long and it does not
    converge in 40 iterations: the line now names the time scale and what to change; from a transient of 2e4 it
    converges onto an orbit that one period maps onto itself."""
    system = load_system(EXAMPLES / "stick_slip_chain.toml")
    system = System.from_dict({**system.to_dict(),
                               "damper": [*system.to_dict()["damper"], {"on": {"x1": 1.0, "x2": -1.0}, "c": 1e4}]})
    with pytest.raises(ShootingError, match=r"slowest time scale, 2 pi / its least \|lambda\| = 6\.65e\+04, is longer "
                                            r"than the transient \(300\): a longer one"):
        find_structure_orbit(system)
    orbit = find_structure_orbit(system, t_transient=2e4)
    end = orbit.motion.states(np.array([orbit.period]))[:, 0]
    assert np.abs(end - orbit.state).max() < 1e-9 and orbit.stability == "stable"
    assert 0.999 < orbit.multiplier.real < 1.0  # the creep


#: three masses, a q-dependent normal load: a stick-slip cycle that crosses x2' = 0 twice a period
THREE_TWICE = """
dof = ["x1", "x2", "x3"]
mass = [1.0, 0.8, 1.2]
[[spring]]
on = { x1 = 1.0 }
k = 1.0
[[spring]]
on = { x1 = 1.0, x2 = -1.0 }
k = 0.6
[[spring]]
on = { x2 = 1.0, x3 = -1.0 }
k = 0.4
[[spring]]
on = { x3 = 1.0 }
k = 0.9
[[damper]]
on = { x1 = 1.0 }
c = 0.02
[[damper]]
on = { x2 = 1.0, x3 = -1.0 }
c = 0.015
[[contact]]
on = { x1 = 1.0 }
belt = 0.05
friction = "coulomb"
fd = 0.1
fs = 0.3
normal = { preload = 1.0, x3 = 0.2 }
[[contact]]
on = { x3 = 1.0 }
belt = 0.05
friction = "coulomb"
fd = 0.12
fs = 0.25
[initial]
v = { x1 = 0.05, x3 = 0.05 }
"""


def test_newton_stalled_on_a_cycle_crossing_its_section_twice_says_how_many_returns():
    """The default section (x2, whose velocity varies most) is crossed twice a period by this chain's cycle,
    so the one-return map jumps between the two crossings and Newton stalled with "no periodic orbit near this
    start" (QA).  The line now says the transient settles on a cycle (simulate's analysis) crossing the section
    twice; with returns=2 the orbit is found, its period simulate's, and by default (the transient's count)
    the same orbit."""
    system = System.from_dict(tomllib.loads(THREE_TWICE), source=None)
    ss = structure_steady_state(simulate_system(system, 4000.0))
    assert ss.kind == "periodic"
    with pytest.raises(ShootingError, match="stalled.*settles on a cycle of period 9.386.* crosses the section "
                                            "x2' = 0 2 times a period: returns=2"):
        find_structure_orbit(system, t_transient=4000.0, returns=1)
    found = find_structure_orbit(system, t_transient=4000.0, returns=2)
    assert found.period == pytest.approx(ss.period, rel=1e-9)
    default = find_structure_orbit(system, t_transient=4000.0)  # the transient's count: the same orbit
    assert default.returns == 2 and default.period == found.period


@pytest.mark.parametrize("s", [1e-6, 1e6])
def test_an_orbit_in_other_units_of_time_is_the_same_orbit(s):
    """The stick-slip chain with time measured in units s times shorter: its period is the unit chain's times s
    and its Floquet multipliers (dimensionless) the same.  Newton's tolerance was one scale over positions and
    velocities: in microseconds the belt's speed (5e4) set the positions' tolerance and the period came out
    1.3e-7 off."""
    unit_system = load_system(Path(__file__).parents[2] / "examples" / "models" / "stick_slip_chain.toml")
    unit = find_structure_orbit(unit_system)
    other = find_structure_orbit(_in_time_units(unit_system, s), t_transient=300.0 * s)
    assert other.period / s == pytest.approx(unit.period, rel=1e-12)
    np.testing.assert_allclose(np.sort_complex(other.multipliers), np.sort_complex(unit.multipliers), atol=1e-8)
    assert other.stable and unit.stable
