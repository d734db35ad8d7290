"""Every number of a model file is at most 1e15 in magnitude, refused by its address before anything runs.

Finite but huge entries passed the loader and failed later without naming
themselves: a preload, force amplitude, force frequency or damper of 1e300
stopped the run with "status 'stuck'" (exit 1), masses of 1e30 and 1 gave
"a mode combination's matrix is defective", a belt of 1e300 ran.
"""

from __future__ import annotations

import copy
import tomllib
from pathlib import Path

import numpy as np
import pytest

from frictionflow.analysis.structure import analyze_structure
from frictionflow.solvers.structure import simulate_system
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


def _in_newtons(model: dict, f: float) -> dict:
    """``model`` with forces measured in units ``f`` times smaller: masses, stiffnesses, dampers, friction
    levels and force amplitudes times f (lengths and time unchanged): the same motion."""
    out = copy.deepcopy(model)
    out["mass"] = [m * f for m in out["mass"]]
    for kind, key in (("spring", "k"), ("damper", "c"), ("force", "amplitude")):
        for element in out.get(kind, []):
            element[key] *= f
    for contact in out["contact"]:
        for key in ("fd", "fs", "viscous"):
            if key in contact:
                contact[key] *= f
    return out


def test_a_friction_law_takes_the_model_s_units_not_the_single_mass_s_ranges():
    """Friction levels of 1e5 (newtons on a 10^5 kg structure) were refused with "contact.0.fd must be finite
    and in [0, 1000]": the law's range, set for the nondimensional single mass.  In a model file a law's
    parameter capped there reaches the model's 1e15 like every other number; its narrower caps (Stribeck's
    exponent) and its rules (F_s >= F_d) hold.  The stick-slip chain with forces times 1e5 moves as the unit
    one: the same switches, stick fractions and kind, every power times 1e5."""
    model = tomllib.loads((Path(__file__).parents[2] / "examples" / "models" / "stick_slip_chain.toml").read_text())
    unit = analyze_structure(simulate_system(System.from_dict(model, source=None), 100.0))
    big = analyze_structure(simulate_system(System.from_dict(_in_newtons(model, 1e5), source=None), 100.0))
    np.testing.assert_allclose(big.motion.t, unit.motion.t, rtol=1e-12)
    assert big.steady_state.kind == unit.steady_state.kind
    assert big.steady_state.stick_fraction == pytest.approx(unit.steady_state.stick_fraction, abs=1e-12)
    for name, powers in unit.elements.items():
        for key, value in powers.items():
            assert big.elements[name][key] == pytest.approx(1e5 * value, rel=1e-9, abs=1e-9 * 1e5)
    over = _in_newtons(model, 1e5)
    over["contact"][0]["fd"] = 2.0 * checks.MAGNITUDE_MAX
    with pytest.raises(ValueError, match=r"contact\.0\.fd must be .*1e\+15"):
        System.from_dict(over, source=None)
    over["contact"][0].update(fd=4e5, fs=3e5)
    with pytest.raises(ValueError, match=r"contact\.0\.fs must be >= fd"):
        System.from_dict(over, source=None)
    stribeck = {**BASE, "contact": [{"on": {"x1": 1.0}, "belt": 1e4, "friction": "stribeck", "fd": 1e5, "fs": 2e5,
                                     "vs": 5e3, "delta": 150.0}]}
    with pytest.raises(ValueError, match=r"contact\.0\.delta must be .*100"):
        System.from_dict(stribeck, source=None)
    stribeck["contact"][0]["delta"] = 2.0
    assert System.from_dict(stribeck, source=None).contacts[0].law.vs == 5e3
