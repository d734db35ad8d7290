"""Periodic orbits of forced structures (issue 22, item 4): Newton on the stroboscopic map, exact monodromy.

Independent references: the single-mass forced orbit finder (its own RK4 flow map, located switches and
saltation) for one dof; for contacts that never stick, the linear structure's harmonic response written out
here, q(t) = K^-1 f0 + Re[(K - Omega^2 M + i Omega C)^-1 F e^{i Omega t}], and its multipliers
eig(exp(A T)) from scipy's expm; finite-difference monodromies of the engine's own time-T map.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from scipy.linalg import expm

from frictionflow import BeltOscillator, Coulomb
from frictionflow.orbits.forced import find_forced_orbit
from frictionflow.orbits.structure import fd_structure_monodromy, find_structure_orbit
from frictionflow.solvers.structure import run_assembly
from frictionflow.system import load_system
from tests.cli.processes import in_process

from .builders import chain, single_mass

STICK_SLIP = (BeltOscillator(zeta=0.05, vb=0.1, fex=0.5, omega=1.8), 2)  # a period-2 stick-slip orbit
HARMONIC = (BeltOscillator(zeta=0.1, vb=0.2, fex=0.3, omega=0.9), 1)


@pytest.mark.parametrize("model, m", [STICK_SLIP, HARMONIC])
def test_one_dof_equals_the_single_mass_forced_orbit(model, m):
    law = Coulomb(fd=0.1, fs=0.2)
    # RK4 on a fine grid (located switches): 400 -> 1,600 steps a period cut its error 256-fold onto this engine's
    single = find_forced_orbit(model, law, m, transient_periods=400, steps=6400)
    asm = single_mass(model.zeta, model.vb, law, 0.0, 0.0, force=(model.fex, model.omega, model.phi))
    found = find_structure_orbit(asm, single.state, t_transient=0.0, returns=m)
    assert not found.autonomous and found.section == "stroboscopic" and found.returns == m
    assert found.period == pytest.approx(m * 2 * math.pi / model.omega, rel=1e-15)
    assert np.allclose(found.state, single.state, rtol=0, atol=1e-11)
    assert np.allclose(np.sort_complex(found.multipliers), np.sort_complex(single.multipliers), atol=1e-9)
    assert found.stability == single.stability
    assert found.stick_fraction[0] == pytest.approx(single.stick_fraction, abs=1e-8)


def test_contacts_that_never_stick_give_the_linear_harmonic_response():
    # belts far faster than the motion: both contacts slip at +F_d throughout, the structure is linear
    n, fd, omega, amp = 2, 0.1, 0.7, 0.4
    asm = chain(n, Coulomb(fd=fd, fs=0.2), [5.0, 5.0], c=0.1, k_couple=0.5, forces=[([1.0, -0.5], amp, omega, 0.3)])
    found = find_structure_orbit(asm, t_transient=200.0)
    M, C, K = asm.mass, asm.damping, asm.stiffness
    f0 = fd * np.ones(n)
    F = amp * np.array([1.0, -0.5]) * np.exp(1j * 0.3)
    q = np.linalg.solve(K, f0) + (np.linalg.solve(K - omega**2 * M + 1j * omega * C, F)).real
    v = (1j * omega * np.linalg.solve(K - omega**2 * M + 1j * omega * C, F)).real
    assert np.allclose(found.state, np.concatenate((q, v)), rtol=0, atol=1e-11)
    A = np.block([[np.zeros((n, n)), np.eye(n)], [-np.linalg.solve(M, K), -np.linalg.solve(M, C)]])
    expected = np.linalg.eigvals(expm(A * 2 * math.pi / omega))
    assert np.allclose(np.sort_complex(found.multipliers), np.sort_complex(expected), atol=1e-12)
    assert found.stick_fraction == (0.0, 0.0) and found.stable


def _stick_slip_chain():
    return chain(2, Coulomb(fd=0.1, fs=0.2), [0.05, 0.06], c=0.2, k_couple=0.5, q0=[0.0, 0.3],
                 forces=[([1.0, 0.0], 0.3, 1.1, 0.0)])


def test_a_forced_chain_orbit_is_a_fixed_point_of_the_period_and_its_monodromy_matches_differences():
    asm = _stick_slip_chain()
    found = find_structure_orbit(asm, t_transient=300.0)
    assert max(found.stick_fraction) > 0.01  # a stick-slip orbit, not the sliding response
    n = 2
    end = run_assembly(asm._replace(q0=found.state[:n].copy(), v0=found.state[n:].copy()), found.period).state[:, -1]
    assert np.allclose(end, found.state, rtol=0, atol=1e-10)
    fd = fd_structure_monodromy(asm, found.state, found.period, eps=1e-7)
    free = [i for i in range(2 * n) if not _across_stuck(asm, found, i)]
    assert np.allclose(found.monodromy[:, free], fd[:, free], rtol=0, atol=1e-5)
    assert found.energy_residual < 1e-10
    # Newton itself, from a start off the orbit and no transient
    again = find_structure_orbit(asm, found.state + np.array([2e-3, -1e-3, 1e-3, 0.0]), t_transient=0.0)
    assert again.iterations >= 2 and np.allclose(again.state, found.state, rtol=0, atol=1e-11)


def _across_stuck(asm, found, i):
    """A velocity column across a contact stuck at the start (its FD column starts that contact slipping)."""
    n = len(asm.q0)
    stuck = np.asarray(found.motion.modes)[:, 0] == 0
    return i >= n and bool(np.any(asm.contact_dir[stuck][:, i - n] != 0.0))


def test_forces_of_different_frequencies_and_a_section_are_refused_in_one_line():
    asm = chain(2, Coulomb(fd=0.1, fs=0.2), [0.05, 0.06], forces=[([1.0, 0.0], 0.3, 1.1, 0.0),
                                                                  ([0.0, 1.0], 0.3, 1.3, 0.0)])
    with pytest.raises(ValueError, match=r"frequencies differ \(1.1, 1.3\)"):
        find_structure_orbit(asm)
    with pytest.raises(ValueError, match="section must be None for a forced structure"):
        find_structure_orbit(_stick_slip_chain(), section=0)


FORCED_MODEL = """
dof = ["x1", "x2"]
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
c = 0.2
[[damper]]
on = { x2 = 1.0 }
c = 0.2
[[contact]]
on = { x1 = 1.0 }
belt = 0.05
friction = "coulomb"
fd = 0.1
fs = 0.2
[[contact]]
on = { x2 = 1.0 }
belt = 0.06
friction = "coulomb"
fd = 0.1
fs = 0.2
[[force]]
on = { x1 = 1.0 }
amplitude = 0.3
omega = 1.1
[initial]
q = { x2 = 0.3 }
"""


def test_cli_orbit_of_a_forced_model_is_the_apis(tmp_path):
    path = tmp_path / "forced.toml"
    path.write_text(FORCED_MODEL, encoding="utf-8")
    code, out, err, _ = in_process("orbit", "--model", str(path), "--json", "--fd-check")
    assert code == 0, err
    report = json.loads(out)
    api = find_structure_orbit(load_system(path), t_transient=300.0)
    assert report["section"] == "stroboscopic" and report["autonomous"] is False
    assert report["period"] == pytest.approx(2 * math.pi / 1.1, rel=1e-15)
    assert report["state"]["q"]["x1"] == pytest.approx(api.state[0], abs=1e-12)
    assert report["stick_fraction"] == pytest.approx(list(api.stick_fraction), abs=1e-12)
    assert report["energy_residual"] < 1e-10
