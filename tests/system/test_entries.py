"""Entries by address (entry, with_entry, entries) and the from_dict / to_dict round trip."""

from __future__ import annotations

import json

import numpy as np
import pytest

from frictionflow import Coulomb, SlipLaw
from frictionflow.system import Contact, Damper, Force, Initial, Normal, Spring, System, assemble, load_system

MODEL = {
    "dof": ["x1", "x2"],
    "mass": [1.0, 2.0],
    "spring": [{"on": {"x1": 1.0}, "k": 1.0}, {"on": {"x1": 1.0, "x2": -1.0}, "k": 0.5}],
    "damper": [{"on": {"x1": 1.0}, "c": 0.04}],
    "contact": [
        {"on": {"x1": 1.0}, "belt": 0.1, "friction": "coulomb", "fd": 0.3, "fs": 0.4,
         "normal": {"preload": 1.0, "x2": -2.0}},
        {"on": {"x2": 1.0}, "belt": 0.2, "friction": "cubic", "fs": 0.05, "k1": 0.2},
    ],
    "force": [{"on": {"x2": 1.0}, "amplitude": 0.1, "omega": 0.9}],
    "initial": {"q": {"x2": 0.2}, "v": {"x1": -0.1}},
}


@pytest.fixture
def system():
    return System.from_dict(MODEL)


def test_element_names_in_file_order(system):
    assert system.n == 2
    assert system.spring_names == ("spring.0", "spring.1") and system.damper_names == ("damper.0",)
    assert system.contact_names == ("contact.0", "contact.1") and system.force_names == ("force.0",)
    assert system.element_names == ("spring.0", "spring.1", "damper.0", "contact.0", "contact.1", "force.0")
    assert system.contacts[1].friction == "cubic" and system.contacts[1].law.k1 == 0.2


def test_entries_lists_every_numeric_entry(system):
    assert system.entries() == (
        "mass.0", "mass.1",
        "spring.0.k", "spring.0.on.x1", "spring.1.k", "spring.1.on.x1", "spring.1.on.x2",
        "damper.0.c", "damper.0.on.x1",
        "contact.0.belt", "contact.0.fd", "contact.0.fs", "contact.0.rk4_band", "contact.0.on.x1",
        "contact.0.normal.preload", "contact.0.normal.x2",
        "contact.1.belt", "contact.1.fs", "contact.1.k1", "contact.1.k3", "contact.1.rk4_band", "contact.1.on.x2",
        "force.0.amplitude", "force.0.omega", "force.0.phi", "force.0.on.x2",
        "initial.q.x1", "initial.q.x2", "initial.v.x1", "initial.v.x2",
    )


def test_entry_reads_the_models_numbers(system):
    expected = {"mass.1": 2.0, "spring.1.k": 0.5, "spring.1.on.x2": -1.0, "damper.0.c": 0.04, "contact.0.belt": 0.1,
                "contact.0.fd": 0.3, "contact.0.normal.x2": -2.0, "contact.1.k3": 10.0, "force.0.omega": 0.9,
                "force.0.phi": 0.0, "initial.q.x2": 0.2, "initial.v.x1": -0.1, "initial.q.x1": 0.0,
                "spring.0.on.x2": 0.0, "contact.1.normal.preload": 1.0, "contact.1.normal.x1": 0.0}
    for address, value in expected.items():
        assert system.entry(address) == value, address
    assert system.entry("contact.0.stick_force") == "resultant"


def test_with_entry_of_its_own_value_is_the_same_system(system):
    for address in system.entries():
        assert system.with_entry(address, system.entry(address)) == system, address


def test_with_entry_changes_that_entry_and_no_other(system):
    for address in system.entries():
        new = system.entry(address) + (0.125 if address != "contact.0.fd" else 0.05)  # fd stays <= fs = 0.4
        changed = system.with_entry(address, new)
        assert changed.entry(address) == new, address
        others = [a for a in system.entries() if a != address]
        assert [changed.entry(a) for a in others] == [system.entry(a) for a in others], address
        assert changed.with_entry(address, system.entry(address)) == system, address


def test_with_entry_reaches_the_assembly(system):
    a = assemble(system.with_entry("spring.1.k", 0.7).with_entry("contact.0.belt", -0.3))
    np.testing.assert_allclose(a.stiffness, [[1.7, -0.7], [-0.7, 0.7]], rtol=0, atol=1e-15)
    assert a.belt[0] == -0.3


def test_an_off_diagonal_mass_entry_is_set_symmetrically(system):
    full = system.with_entry("mass.0.1", 0.25)
    np.testing.assert_array_equal(full.mass_matrix, [[1.0, 0.25], [0.25, 2.0]])
    assert "mass.0.1" in full.entries() and full.entry("mass.1") == 2.0
    assert full.with_entry("mass.1", 3.0).mass == ((1.0, 0.25), (0.25, 3.0))
    with pytest.raises(ValueError, match="mass must be positive definite"):
        system.with_entry("mass.0.1", 2.0)


def test_a_normal_load_added_to_a_contact_without_one(system):
    loaded = system.with_entry("contact.1.normal.x1", 0.5)
    assert loaded.contacts[1].normal == Normal(1.0, (("x1", 0.5),))
    np.testing.assert_array_equal(assemble(loaded).normal[1], [1.0, 0.5, 0.0])


@pytest.mark.parametrize(("address", "value", "fragment"), [
    ("spring.1.k", -2, "model: spring.1.k must be >= 0, got -2"),
    ("contact.0.fs", 0.1, "model: contact.0.fs must be >= fd = 0.3, got 0.1"),
    ("contact.1.k3", 0.0, "model: contact.1.k3 must be finite and in (0, 1e+15], got 0.0"),
    ("contact.0.normal.preload", 0.4, "model: contact.0.normal: the normal load preload + n.q must be > 0"),
    ("force.0.omega", float("nan"), "model: force.0.omega must be finite, got nan"),
    ("spring.2.k", 1.0, "model: no entry 'spring.2.k': its element does not exist (spring: spring.0, spring.1)"),
    ("spring.0.c", 1.0, "model: no entry 'spring.0.c': spring.0's entries are k, on.DOF (dof: x1, x2)"),
    ("spring.0.on.x3", 1.0, "model: no entry 'spring.0.on.x3'"),
    ("contact.0.vd", 1.0, "entries are belt, fd, fs, stick_force, rk4_band, on.DOF, normal.preload, normal.DOF"),
    ("mass.2", 1.0, "model: no entry 'mass.2': the mass's are mass.i (diagonal) and mass.i.j, 0 <= i, j < 2"),
    ("initial.a.x1", 1.0, "model: no entry 'initial.a.x1'"),
    ("belt", 1.0, "model: no entry 'belt': an address starts with mass, spring, damper, contact, force or initial"),
])
def test_a_bad_entry_is_refused_in_one_line(system, address, value, fragment):
    with pytest.raises(ValueError) as info:
        system.with_entry(address, value)
    assert fragment in str(info.value) and "\n" not in str(info.value)


def test_messages_name_the_file_of_a_loaded_model(tmp_path, system):
    path = tmp_path / "m.toml"
    path.write_text('dof = ["x"]\nmass = [1.0]\n[[spring]]\non = { x = 1.0 }\nk = 1.0\n')
    loaded = load_system(path)
    with pytest.raises(ValueError, match=f"^model {path}: spring.0.k must be >= 0, got -1.0$"):
        loaded.with_entry("spring.0.k", -1.0)
    with pytest.raises(ValueError, match=f"^model {path}: no entry 'spring.1.k'"):
        loaded.entry("spring.1.k")
    assert loaded.with_entry("spring.0.k", 2.0).source == str(path)


def test_from_dict_to_dict_round_trip(system):
    data = system.to_dict()
    assert System.from_dict(data) == system
    assert System.from_dict(data).to_dict() == data
    json.dumps(data)  # plain data: numbers, text, lists and tables
    assert data["contact"][0] == {"on": {"x1": 1.0}, "belt": 0.1, "friction": "coulomb", "fd": 0.3, "fs": 0.4,
                                  "stick_force": "resultant", "rk4_band": 1e-4, "normal": {"preload": 1.0, "x2": -2.0}}
    assert data["initial"] == {"q": {"x1": 0.0, "x2": 0.2}, "v": {"x1": -0.1, "x2": 0.0}}


def test_the_api_objects_build_the_same_system(system):
    built = System(
        dof=("x1", "x2"), mass=(1.0, 2.0),
        springs=(Spring({"x1": 1.0}, 1.0), Spring({"x1": 1.0, "x2": -1.0}, 0.5)),
        dampers=(Damper({"x1": 1.0}, 0.04),),
        contacts=(Contact({"x1": 1.0}, 0.1, Coulomb(0.3, 0.4), Normal(1.0, {"x2": -2.0})), system.contacts[1]),
        forces=(Force({"x2": 1.0}, 0.1, 0.9),),
        initial=Initial(q={"x2": 0.2}, v={"x1": -0.1}),
    )
    assert built == system and hash(built) == hash(system)


def test_a_law_object_in_a_mapping_with_a_parameter_beside_it():
    data = {"dof": ["x"], "mass": [1.0], "contact": [{"on": {"x": 1.0}, "belt": 0.1, "friction": Coulomb(0.3, 0.4),
                                                      "fs": 0.5}]}
    assert System.from_dict(data).contacts[0].law == Coulomb(0.3, 0.5)


def test_elements_of_the_wrong_class_are_a_type_error():
    with pytest.raises(TypeError, match="^model: spring.0 must be a Spring, got"):
        System(dof=("x",), mass=(1.0,), springs=({"on": {"x": 1.0}, "k": 1.0},))
    with pytest.raises(TypeError, match="^model: contact.0.friction must be a friction law object, got 'coulomb'"):
        System(dof=("x",), mass=(1.0,), contacts=(Contact({"x": 1.0}, 0.1, "coulomb"),))


def test_a_law_built_from_a_function_round_trips_and_keeps_its_parameters():
    law = SlipLaw(lambda speed: 0.1 + 0.0 * speed, fs=0.2)
    system = System(dof=("x",), mass=(1.0,), contacts=(Contact({"x": 1.0}, 0.5, law),))
    assert System.from_dict(system.to_dict()) == system and system.to_dict()["contact"][0]["friction"] is law
    assert system.entry("contact.0.fs") == 0.2 and system.with_entry("contact.0.belt", 0.7).contacts[0].law is law
    with pytest.raises(ValueError, match="^model: contact.0: the law 'user' is built from a function"):
        system.with_entry("contact.0.fs", 0.3)
