"""assemble(system) against matrices assembled by hand, and the single mass against the BeltOscillator's numbers."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from frictionflow import BeltOscillator, Coulomb, Karnopp, Stribeck
from frictionflow.core import layout
from frictionflow.core.assembly import Assembly
from frictionflow.system import Contact, Spring, System, assemble, load_system

EXAMPLES = Path(__file__).resolve().parents[2] / "examples" / "models"

TWO_DOF = """
dof = ["x1", "x2"]
mass = [[2.0, 0.5], [0.5, 1.0]]

[[spring]]
on = { x1 = 1.0 }
k = 3.0

[[spring]]
on = { x1 = 1.0, x2 = -1.0 }
k = 0.5

[[spring]]
on = { x2 = 2.0 }
k = 0.25

[[damper]]
on = { x1 = 1.0 }
c = 0.04

[[damper]]
on = { x2 = 1.0, x1 = -1.0 }
c = 0.1

[[contact]]
on = { x1 = 1.0 }
belt = 0.1
friction = "coulomb"
fd = 0.3
fs = 0.4
normal = { preload = 1.0, x2 = -2.0 }

[[contact]]
on = { x2 = 1.0 }
belt = -0.2
friction = "stribeck"
fd = 0.1
vs = 0.05
stick_force = "spring"

[[force]]
on = { x2 = 1.0 }
amplitude = 0.1
omega = 0.9

[[force]]
on = { x1 = 0.5, x2 = 0.5 }
amplitude = 0.2
omega = 1.7
phi = -0.3

[initial]
q = { x1 = 0.0, x2 = 0.2 }
v = { x2 = -0.1 }
"""


@pytest.fixture
def two_dof(tmp_path):
    path = tmp_path / "two.toml"
    path.write_text(TWO_DOF)
    return load_system(path)


def test_two_dof_matrices_against_hand_assembly(two_dof):
    a = assemble(two_dof)
    assert isinstance(a, Assembly)
    # K: 3 x1^2 + 0.5 (x1 - x2)^2 + 0.25 (2 x2)^2 is the potential's double
    k_hand = np.array([[3.0 + 0.5, -0.5], [-0.5, 0.5 + 0.25 * 4.0]])
    # C: 0.04 x1'^2 + 0.1 (x2' - x1')^2
    c_hand = np.array([[0.04 + 0.1, -0.1], [-0.1, 0.1]])
    np.testing.assert_array_equal(a.mass, [[2.0, 0.5], [0.5, 1.0]])
    np.testing.assert_allclose(a.stiffness, k_hand, rtol=0, atol=1e-15)
    np.testing.assert_allclose(a.damping, c_hand, rtol=0, atol=1e-15)
    np.testing.assert_array_equal(a.contact_dir, [[1.0, 0.0], [0.0, 1.0]])
    np.testing.assert_array_equal(a.belt, [0.1, -0.2])
    np.testing.assert_array_equal(a.normal, [[1.0, 0.0, -2.0], [1.0, 0.0, 0.0]])
    np.testing.assert_array_equal(a.force_dir, [[0.0, 1.0], [0.5, 0.5]])
    np.testing.assert_array_equal(a.force_amp, [0.1, 0.2])
    np.testing.assert_array_equal(a.force_omega, [0.9, 1.7])
    np.testing.assert_array_equal(a.force_phi, [0.0, -0.3])
    np.testing.assert_array_equal(a.spring_dir, [[1.0, 0.0], [1.0, -1.0], [0.0, 2.0]])
    np.testing.assert_array_equal(a.spring_k, [3.0, 0.5, 0.25])
    np.testing.assert_array_equal(a.damper_dir, [[1.0, 0.0], [-1.0, 1.0]])
    np.testing.assert_array_equal(a.damper_c, [0.04, 0.1])
    np.testing.assert_array_equal(a.q0, [0.0, 0.2])
    np.testing.assert_array_equal(a.v0, [0.0, -0.1])


def test_two_dof_law_rows_hold_each_laws_parameters_in_the_kernel_layout(two_dof):
    row = assemble(two_dof).law
    assert row.shape == (2, layout.N_PARAMS)
    assert row[0, layout.LAW] == layout.COULOMB and row[1, layout.LAW] == layout.STRIBECK
    assert (row[0, layout.FD], row[0, layout.FS], row[0, layout.RESULTANT]) == (0.3, 0.4, 1.0)
    # Stribeck's F_s defaults to 2 F_d; its V_s goes to its first own slot; the "spring" stick force is 0
    assert (row[1, layout.FD], row[1, layout.FS], row[1, layout.LAW_A], row[1, layout.RESULTANT]) == (0.1, 0.2, 0.05, 0.0)
    assert not row[:, [layout.FEX, layout.OMEGA, layout.PHI]].any()


def test_every_array_is_float64_and_contiguous(two_dof):
    for name, value in assemble(two_dof)._asdict().items():
        assert value.dtype == np.float64 and value.flags.c_contiguous, name


def test_a_model_without_dampers_contacts_or_forces_has_empty_kinds():
    system = System(dof=("a", "b", "c"), mass=(1.0, 1.0, 1.0), springs=(Spring({"b": 1.0}, 2.0),))
    a = assemble(system)
    assert a.contact_dir.shape == (0, 3) and a.law.shape == (0, layout.N_PARAMS) and a.normal.shape == (0, 4)
    assert a.force_dir.shape == (0, 3) and a.force_amp.shape == (0,) and a.damper_dir.shape == (0, 3)
    assert a.belt.shape == a.force_omega.shape == a.force_phi.shape == a.damper_c.shape == (0,)
    np.testing.assert_array_equal(a.damping, np.zeros((3, 3)))
    np.testing.assert_array_equal(a.stiffness, np.diag([0.0, 2.0, 0.0]))


@pytest.mark.parametrize("fex", [0.0, 0.3])
def test_the_single_mass_is_the_belt_oscillators_numbers(fex):
    """X'' + 2 zeta X' + X = F_c + F_ex cos(Omega t + phi): M = 1, K = 1, C = 2 zeta, e = 1, b = V_b."""
    osc = BeltOscillator(zeta=0.07, vb=0.3, fex=fex, omega=0.8, phi=0.4)
    law = Stribeck(fd=0.02, fs=0.05, vs=0.1)
    system = System.single_mass(osc, law, x0=0.02, v0=0.3)
    a = assemble(system)
    assert system.dof == ("x",) and system.contacts[0].law is law
    np.testing.assert_array_equal(a.mass, [[1.0]])
    np.testing.assert_array_equal(a.stiffness, [[1.0]])
    np.testing.assert_array_equal(a.damping, [[2.0 * 0.07]])
    np.testing.assert_array_equal(a.contact_dir, [[1.0]])
    np.testing.assert_array_equal(a.belt, [0.3])
    np.testing.assert_array_equal(a.normal, [[1.0, 0.0]])
    np.testing.assert_array_equal(a.q0, [0.02])
    np.testing.assert_array_equal(a.v0, [0.3])
    assert (a.law[0, layout.FD], a.law[0, layout.FS], a.law[0, layout.LAW_A]) == (0.02, 0.05, 0.1)
    if fex:
        np.testing.assert_array_equal(a.force_dir, [[1.0]])
        assert (a.force_amp[0], a.force_omega[0], a.force_phi[0]) == (0.3, 0.8, 0.4)
        # the force record's own forcing slots: what the single-mass kernels get beside the law
        assert system.forces[0].amplitude * math.cos(0.8 * 2.0 + 0.4) == pytest.approx(float(osc.external_force(2.0)), abs=0)
    else:
        assert a.force_dir.shape == (0, 1)


def test_the_single_mass_file_is_the_single_mass_system(tmp_path):
    path = tmp_path / "one.toml"
    path.write_text('dof = ["x"]\nmass = [1.0]\n[[spring]]\non = { x = 1.0 }\nk = 1.0\n[[damper]]\non = { x = 1.0 }\n'
                    'c = 0.1\n[[contact]]\non = { x = 1.0 }\nbelt = 0.01\nfriction = "coulomb"\nfd = 0.02\n'
                    'fs = 0.03\nstick_force = "spring"\n')
    from_file = load_system(path)
    built = System.single_mass(BeltOscillator(zeta=0.05, vb=0.01), Coulomb(0.02, 0.03, stick_force="spring"))
    assert from_file == built
    for x, y in zip(assemble(from_file), assemble(built)):
        np.testing.assert_array_equal(x, y)


def test_the_single_mass_default_law_has_coulombs_stick_rule():
    system = System.single_mass(BeltOscillator(zeta=0.0, vb=0.01))
    assert system.contacts[0].law.stick_rule == "switch" and system.dampers[0].c == 0.0


def test_the_hoffmann_example_against_its_derivation():
    """The example's K from k1, k2, k3 at 135 degrees and kH; its flutter threshold from numpy's eigenvalues."""
    system = load_system(EXAMPLES / "hoffmann_2dof.toml")
    a = assemble(system)
    k1, k2, k3, kh, alpha = 1.0, 0.5, 1.0, 1.0, math.radians(135.0)
    e3 = np.array([math.cos(alpha), math.sin(alpha)])
    k_hand = np.diag([k1, k2 + kh]) + k3 * np.outer(e3, e3)
    np.testing.assert_allclose(a.stiffness, k_hand, rtol=0, atol=1e-15)
    np.testing.assert_array_equal(a.normal, [[1.0, 0.0, -kh]])

    def complex_pair(mu):  # K_eff = K - mu e n^T (the friction's x2 term moved to the left side)
        k_eff = a.stiffness - mu * np.outer(a.contact_dir[0], a.normal[0, 1:])
        return np.abs(np.linalg.eigvals(np.linalg.solve(a.mass, k_eff)).imag).max() > 0.0

    mu_c = 0.625  # the example's closed form (b^2 + (a - d)^2 / 4) / (-b kH)
    assert not complex_pair(mu_c - 1e-9) and complex_pair(mu_c + 1e-9)
    assert complex_pair(system.contacts[0].law.fd)  # the example's mu = 0.7 is past the threshold


def test_the_chain_example_loads():
    system = load_system(EXAMPLES / "two_mass_chain.toml")
    a = assemble(system)
    np.testing.assert_array_equal(a.stiffness, [[1.5, -0.5], [-0.5, 1.5]])
    assert system.contact_names == ("contact.0", "contact.1")


def test_a_contact_law_object_through_the_api():
    system = System(dof=("x",), mass=(1.0,), contacts=(Contact({"x": 1.0}, 0.5, Coulomb(0.1, 0.2)),))
    assert assemble(system).law[0, layout.FS] == 0.2
