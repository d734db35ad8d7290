"""Every number of a model file is at most 1e15 in magnitude, refused by its address before anything runs.

Finite but huge entries passed the loader and failed later without naming
themselves: a preload, force amplitude, force frequency or damper of 1e300
stopped the run with "status 'stuck'" (exit 1), masses of 1e30 and 1 gave
"a mode combination's matrix is defective", a belt of 1e300 ran.
"""

from __future__ import annotations

import copy

import pytest

from frictionflow.system import System, checks

from ..cli.processes import in_process, one_line

BASE = {"dof": ["x1", "x2"], "mass": [1.0, 1.0],
        "spring": [{"on": {"x1": 1.0}, "k": 1.0}, {"on": {"x1": 1.0, "x2": -1.0}, "k": 0.5}],
        "damper": [{"on": {"x1": 1.0}, "c": 0.04}],
        "contact": [{"on": {"x1": 1.0}, "belt": 0.1, "friction": "coulomb", "fd": 0.1, "fs": 0.15,
                     "normal": {"preload": 1.0, "x2": 0.1}}],
        "force": [{"on": {"x2": 1.0}, "amplitude": 0.1, "omega": 0.9, "phi": 0.0}]}
#: (path into BASE, the entry's address)
ENTRIES = [(("mass", 0), "mass.0"), (("spring", 1, "k"), "spring.1.k"), (("damper", 0, "c"), "damper.0.c"),
           (("contact", 0, "belt"), "contact.0.belt"),
           (("contact", 0, "normal", "preload"), "contact.0.normal.preload"),
           (("contact", 0, "normal", "x2"), "contact.0.normal.x2"), (("force", 0, "amplitude"), "force.0.amplitude"),
           (("force", 0, "omega"), "force.0.omega"), (("force", 0, "phi"), "force.0.phi")]


def with_value(path, value):
    model = copy.deepcopy(BASE)
    place = model
    for key in path[:-1]:
        place = place[key]
    place[path[-1]] = value
    return model


@pytest.mark.parametrize("path, address", ENTRIES, ids=[a for _, a in ENTRIES])
@pytest.mark.parametrize("value", [1e300, 2.0 * checks.MAGNITUDE_MAX])
def test_a_huge_entry_is_refused_by_its_address(path, address, value):
    with pytest.raises(ValueError, match=rf"^model: {address.replace('.', '[.]')} must be at most 1e\+15 in magnitude"):
        System.from_dict(with_value(path, value))


@pytest.mark.parametrize("path, address", ENTRIES, ids=[a for _, a in ENTRIES])
def test_an_entry_at_the_bound_is_taken(path, address):
    assert System.from_dict(with_value(path, checks.MAGNITUDE_MAX)) is not None


def test_simulate_model_refuses_a_huge_preload_exit_2_nothing_written(tmp_path):
    text = (f'dof = ["x"]\nmass = [1.0]\n[[spring]]\non = {{ x = 1.0 }}\nk = 1.0\n[[contact]]\non = {{ x = 1.0 }}\n'
            f'belt = 0.1\nfriction = "coulomb"\nfd = 0.1\nfs = 0.2\nnormal = {{ preload = 1e300 }}\n')
    (tmp_path / "m.toml").write_text(text)
    out = tmp_path / "run.nc"
    code, stdout, err, _ = in_process("simulate", "--model", str(tmp_path / "m.toml"), "--out", str(out))
    assert code == 2 and stdout == "" and not out.exists()
    one_line(err, "contact.0.normal.preload must be at most 1e+15 in magnitude")
