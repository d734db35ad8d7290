"""Bad model files are refused in one line naming the file, the element, the entry and what is allowed.

Each case writes a small TOML file to a fresh directory and changes one thing
in an otherwise good model; nothing besides the file may appear there.
"""

from __future__ import annotations

import pytest

from frictionflow import LuGre
from frictionflow.friction import law_names
from frictionflow.friction.registry import law_class
from frictionflow.system import System, load_system
from frictionflow.system.parse import structure_laws

GOOD = {
    "dof": 'dof = ["x1", "x2"]',
    "mass": "mass = [1.0, 2.0]",
    "spring": '[[spring]]\non = { x1 = 1.0 }\nk = 1.0\n\n[[spring]]\non = { x1 = 1.0, x2 = -1.0 }\nk = 0.5',
    "damper": "[[damper]]\non = { x1 = 1.0 }\nc = 0.04",
    "contact": '[[contact]]\non = { x1 = 1.0 }\nbelt = 0.1\nfriction = "coulomb"\nfd = 0.3\nfs = 0.4\n'
               "normal = { preload = 1.0, x2 = -2.0 }",
    "force": "[[force]]\non = { x2 = 1.0 }\namplitude = 0.1\nomega = 0.9",
    "initial": "[initial]\nq = { x1 = 0.0, x2 = 0.2 }\nv = { x1 = 0.0 }",
}


def model_text(**changes: str) -> str:
    """The good model with some of its parts replaced (top-level keys first, as TOML needs)."""
    parts = {**GOOD, **changes}
    top = [parts.pop("dof"), parts.pop("mass"), parts.pop("extra", "")]
    return "\n".join(top) + "\n\n" + "\n\n".join(parts.values()) + "\n"


def refused(tmp_path, text: str, *fragments: str, error: type = ValueError) -> str:
    path = tmp_path / "m.toml"
    path.write_text(text)
    with pytest.raises(error) as info:
        load_system(path)
    message = str(info.value)
    assert "\n" not in message
    assert message.startswith(f"model {path}: "), message
    for fragment in fragments:
        assert fragment in message, (fragment, message)
    assert list(tmp_path.iterdir()) == [path]  # nothing written beside it
    return message


def test_the_good_model_loads(tmp_path):
    path = tmp_path / "m.toml"
    path.write_text(model_text())
    system = load_system(path)
    assert system.dof == ("x1", "x2") and system.source == str(path)
    assert system.element_names == ("spring.0", "spring.1", "damper.0", "contact.0", "force.0")


# -- the mass ---------------------------------------------------------------------------------------
def test_a_mass_matrix_that_is_not_positive_definite(tmp_path):
    refused(tmp_path, model_text(mass="mass = [[1.0, 2.0], [2.0, 1.0]]"), "mass must be positive definite",
            "smallest eigenvalue is -1")


def test_a_mass_matrix_that_is_not_symmetric(tmp_path):
    refused(tmp_path, model_text(mass="mass = [[1.0, 0.1], [0.2, 1.0]]"), "mass must be symmetric",
            "mass.0.1 = 0.1", "mass.1.0 = 0.2")


@pytest.mark.parametrize("mass", ["mass = [1.0]", "mass = [1.0, 1.0, 1.0]", "mass = [[1.0, 0.0], [0.0, 1.0], [0.0, 0.0]]",
                                  "mass = [[1.0, 0.0], [0.0]]"])
def test_a_mass_of_the_wrong_size(tmp_path, mass):
    refused(tmp_path, model_text(mass=mass), "mass must be 2 numbers > 0", "or a 2 x 2 matrix")


def test_a_zero_diagonal_mass(tmp_path):
    refused(tmp_path, model_text(mass="mass = [1.0, 0.0]"), "mass.1 must be > 0, got 0.0")


# -- dof --------------------------------------------------------------------------------------------
def test_an_unknown_dof(tmp_path):
    text = model_text(damper="[[damper]]\non = { x3 = 1.0 }\nc = 0.04")
    refused(tmp_path, text, "damper.0: unknown dof 'x3' (dof: x1, x2) in on")


def test_an_unknown_dof_in_the_normal_load_and_the_initial_state(tmp_path):
    contact = GOOD["contact"].replace("x2 = -2.0", "y = -2.0")
    refused(tmp_path, model_text(contact=contact), "contact.0: unknown dof 'y' (dof: x1, x2) in normal")
    (tmp_path / "m.toml").unlink()
    refused(tmp_path, model_text(initial="[initial]\nv = { x9 = 1.0 }"), "initial: unknown dof 'x9' (dof: x1, x2) in v")


def test_a_duplicate_dof(tmp_path):
    refused(tmp_path, model_text(dof='dof = ["x1", "x1"]'), "dof: duplicate dof 'x1'")


# -- missing and unknown keys ----------------------------------------------------------------------------
@pytest.mark.parametrize(("part", "text", "fragments"), [
    ("spring", "[[spring]]\non = { x1 = 1.0 }", ("spring.0: missing k (required: on, k)",)),
    ("contact", '[[contact]]\non = { x1 = 1.0 }\nfriction = "coulomb"', ("contact.0: missing belt",)),
    ("contact", "[[contact]]\non = { x1 = 1.0 }\nbelt = 0.1", ("contact.0: missing friction",)),
    ("force", "[[force]]\non = { x2 = 1.0 }\namplitude = 0.1", ("force.0: missing omega",)),
    ("contact", '[[contact]]\non = { x1 = 1.0 }\nbelt = 0.1\nfriction = "coulomb"\nnormal = { x2 = -1.0 }',
     ("contact.0.normal: missing preload",)),
])
def test_a_missing_parameter(tmp_path, part, text, fragments):
    refused(tmp_path, model_text(**{part: text}), *fragments)


def test_dof_and_mass_are_required(tmp_path):
    refused(tmp_path, "mass = [1.0]\n", "top level: missing dof (required: dof, mass)")


def test_an_unknown_key_lists_the_allowed_ones(tmp_path):
    refused(tmp_path, model_text(spring="[[spring]]\non = { x1 = 1.0 }\nk = 1.0\nstiffness = 2.0"),
            "spring.0: unknown key 'stiffness' (allowed: on, k)")


def test_a_key_of_another_law_is_unknown_for_this_one(tmp_path):
    """Karnopp's band vd is no parameter of Coulomb's law: the message lists Coulomb's."""
    message = refused(tmp_path, model_text(contact=GOOD["contact"] + "\nvd = 0.001"), "contact.0: unknown key 'vd'",
                      "on, belt, friction, normal, fd, fs, stick_force, rk4_band")
    assert "vs" not in message


def test_an_unknown_top_level_key(tmp_path):
    refused(tmp_path, model_text(extra="masses = [1.0, 1.0]"), "top level: unknown key 'masses'",
            "allowed: dof, mass, spring, damper, contact, force, initial")


# -- values -------------------------------------------------------------------------------------------
def test_a_negative_stiffness(tmp_path):
    refused(tmp_path, model_text(spring="[[spring]]\non = { x1 = 1.0 }\nk = -2"), "spring.0.k must be >= 0, got -2")


def test_a_negative_damping(tmp_path):
    refused(tmp_path, model_text(damper="[[damper]]\non = { x1 = 1.0 }\nc = -0.5"), "damper.0.c must be >= 0, got -0.5")


@pytest.mark.parametrize("on", ["on = { x1 = 0.0, x2 = 0.0 }", "on = {}"])
def test_a_zero_length_direction(tmp_path, on):
    refused(tmp_path, model_text(force=f"[[force]]\n{on}\namplitude = 0.1\nomega = 0.9"),
            "force.0.on must have a nonzero entry over the dof (x1, x2)")


STATEFUL = [name for name in law_names() if law_class(name).internal_names]
#: the laws a model's contact may name: those some structure solver runs (karnopp, whose stick band no structure
#: solver has, is refused with them)
RUNNABLE = list(structure_laws())


def test_an_unknown_friction_law_lists_the_registered_ones(tmp_path):
    contact = GOOD["contact"].replace('"coulomb"', '"columb"')
    refused(tmp_path, model_text(contact=contact), f"contact.0.friction must be one of {', '.join(RUNNABLE)}",
            "got 'columb'")


@pytest.mark.parametrize("name", STATEFUL)
def test_a_law_with_an_internal_state_is_refused_by_name(tmp_path, name):
    """A structure's state is q and q' alone: LuGre's z, rate and state's psi have no place in it (they reached the
    assembly and failed there with numpy's broadcast error; rate_state's own ``normal`` clashed with the contact's)."""
    assert {"lugre", "dahl", "elastoplastic", "rate_state"} <= set(STATEFUL) and "coulomb" in RUNNABLE
    contact = f'[[contact]]\non = {{ x1 = 1.0 }}\nbelt = 0.1\nfriction = "{name}"'
    state = ", ".join(law_class(name).internal_names)
    refused(tmp_path, model_text(contact=contact), f"contact.0.friction: {name} has an internal state ({state})",
            ", ".join(RUNNABLE))


def test_a_law_object_with_an_internal_state_is_refused_through_the_api():
    data = {"dof": ["x"], "mass": [1.0], "spring": [{"on": {"x": 1.0}, "k": 1.0}],
            "contact": [{"on": {"x": 1.0}, "belt": 0.1, "friction": LuGre()}]}
    with pytest.raises(ValueError, match=r"contact.0.friction: lugre has an internal state \(z\)"):
        System.from_dict(data, source=None)


@pytest.mark.parametrize(("old", "new", "fragment"), [
    ("fd = 0.3", "fd = -0.3", "contact.0.fd must be finite and in [0, 1e+15], got -0.3"),
    ("fs = 0.4", "fs = 0.2", "contact.0.fs must be >= fd = 0.3, got 0.2"),
    ("fs = 0.4", 'fs = 0.4\nstick_force = "both"', "contact.0.stick_force must be one of resultant, spring, got 'both'"),
])
def test_the_laws_own_ranges(tmp_path, old, new, fragment):
    refused(tmp_path, model_text(contact=GOOD["contact"].replace(old, new)), fragment)


def test_another_laws_own_ranges(tmp_path):
    """Stribeck's exponent is declared in (0, 100]: the range comes from the law's declaration."""
    contact = '[[contact]]\non = { x1 = 1.0 }\nbelt = 0.1\nfriction = "stribeck"\ndelta = 200.0'
    refused(tmp_path, model_text(contact=contact), "contact.0.delta must be finite and in (0, 100], got 200.0")


@pytest.mark.parametrize(("part", "old", "new", "fragment"), [
    ("spring", "k = 0.5", "k = inf", "spring.1.k must be finite, got inf"),
    ("contact", "belt = 0.1", "belt = nan", "contact.0.belt must be finite, got nan"),
    ("force", "omega = 0.9", "omega = -inf", "force.0.omega must be finite, got -inf"),
    ("initial", "x2 = 0.2", "x2 = inf", "initial.q.x2 must be finite, got inf"),
    ("spring", "x2 = -1.0", "x2 = -inf", "spring.1.on.x2 must be finite, got -inf"),
])
def test_non_finite_numbers(tmp_path, part, old, new, fragment):
    refused(tmp_path, model_text(**{part: GOOD[part].replace(old, new)}), fragment)


def test_a_normal_load_that_is_not_positive_at_the_initial_state(tmp_path):
    """N = 1 - 2 x2 with x2(0) = 0.5 is 0: the contact is open before the run starts."""
    text = model_text(initial="[initial]\nq = { x2 = 0.5 }")
    refused(tmp_path, text, "contact.0.normal: the normal load preload + n.q must be > 0 at the initial state, got 0")


@pytest.mark.parametrize(("changes", "fragment"), [
    ({"spring": '[[spring]]\non = { x1 = 1.0 }\nk = "1.0"'}, "spring.0.k must be a finite number >= 0, got '1.0'"),
    ({"spring": "[[spring]]\non = { x1 = 1.0 }\nk = true"}, "spring.0.k must be a finite number >= 0, got True"),
    ({"spring": "[[spring]]\non = 1.0\nk = 1.0"}, "spring.0.on must be a table, got 1.0"),
    ({"spring": "[[spring]]\non = { x1 = 'one' }\nk = 1.0"}, "spring.0.on.x1 must be a finite number, got 'one'"),
    ({"dof": 'dof = "x1"'}, "dof must be a non-empty list of names, got 'x1'"),
    ({"dof": 'dof = ["x1", 2]'}, "dof.1 must be a name"),
    ({"dof": 'dof = ["x1", "x.2"]'}, "dof.1 must be a name"),
    ({"mass": 'mass = "heavy"'}, "mass must be 2 numbers > 0"),
    ({"spring": "spring = { on = { x1 = 1.0 }, k = 1.0 }"}, "spring must be an array of tables ([[spring]])"),
    ({"initial": "[initial]\nq = 0.0"}, "initial.q must be a table, got 0.0"),
    ({"force": "[[force]]\non = { x2 = 1.0 }\namplitude = 0.1\nomega = 0.0"}, "force.0.omega must be > 0, got 0.0"),
])
def test_wrong_types_and_values(tmp_path, changes, fragment):
    refused(tmp_path, model_text(**changes), fragment)


def test_a_file_that_is_not_toml_or_not_there(tmp_path):
    refused(tmp_path, "dof = [x1]\n", "not valid TOML")
    missing = tmp_path / "none.toml"
    with pytest.raises(ValueError, match=f"model {missing}: cannot read it"):
        load_system(missing)
