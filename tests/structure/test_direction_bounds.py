"""A direction's nonzero coefficients are bounded (``checks.DIRECTION_MAX``): beyond, the engine failed.

A contact along 1e-200 crashed the exact engine (ZeroDivisionError: e M^-1 e underflows to 0); one along 1e16
sticks within ~1e-33 of its start, far below the switch times' rounding, and its mass ended 3.3e-9 from where it
stuck instead of ~1e-16.  At the bound itself the runs are right: checked against the model they reduce to.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from frictionflow.solvers.structure import simulate_system
from frictionflow.system import checks, load_system

from ..cli.processes import in_process, one_line

BELT = 0.05


def chain(tmp_path: Path, e1: str, name: str = "m.toml") -> Path:
    """Two masses (k 1, 0.5, 1), a damper on x1; contact.0 along ``x1 = e1``, contact.1 on x2, both on one belt."""
    path = tmp_path / name
    path.write_text(f"""
dof = ["x1", "x2"]
mass = [1.0, 1.0]
[[spring]]
on = {{ x1 = 1.0 }}
k = 1.0
[[spring]]
on = {{ x1 = 1.0, x2 = -1.0 }}
k = 0.5
[[spring]]
on = {{ x2 = 1.0 }}
k = 1.0
[[damper]]
on = {{ x1 = 1.0 }}
c = 0.04
[[contact]]
on = {{ x1 = {e1} }}
belt = {BELT}
friction = "coulomb"
fd = 0.1
fs = 0.15
[[contact]]
on = {{ x2 = 1.0 }}
belt = {BELT}
friction = "coulomb"
fd = 0.1
fs = 0.2
[initial]
q = {{ x2 = 0.2 }}
""")
    return path


def pinned(tmp_path: Path) -> Path:
    """What the chain is with x1 held at 0: x2 alone on k = 1 + 0.5, on its contact."""
    path = tmp_path / "pinned.toml"
    path.write_text(f"""
dof = ["x2"]
mass = [1.0]
[[spring]]
on = {{ x2 = 1.0 }}
k = 1.5
[[contact]]
on = {{ x2 = 1.0 }}
belt = {BELT}
friction = "coulomb"
fd = 0.1
fs = 0.2
[initial]
q = {{ x2 = 0.2 }}
""")
    return path


@pytest.mark.parametrize("e1", ["1e-200", "1e-13", "-1e13", "1e16"])
def test_out_of_range_direction_refused_in_one_line(tmp_path: Path, e1: str) -> None:
    path = chain(tmp_path, e1)
    with pytest.raises(ValueError, match=r"contact\.0\.on\.x1 must be 0 or within 1e-12 <= \|value\| <= 1e\+12"):
        load_system(path)
    code, _, err, _ = in_process("simulate", "--model", str(path), "--out", str(tmp_path / "r.nc"))
    assert code == 2, err
    one_line(err, "contact.0.on.x1", "1e-12", "1e+12")
    assert not (tmp_path / "r.nc").exists()


def test_every_element_kind_is_bounded() -> None:
    for address in ("spring.0", "damper.1", "force.0", "contact.2"):
        with pytest.raises(ValueError, match=rf"{address}\.on\.b must be 0 or within"):
            checks.direction(address, {"a": 1.0, "b": 2e12}, ("a", "b"))
    assert checks.direction("spring.0", {"a": 0.0, "b": 1e-12}, ("a", "b")) == (("a", 0.0), ("b", 1e-12))


def test_a_contact_at_the_upper_bound_pins_its_mass(tmp_path: Path) -> None:
    """Along 1e12 the contact sticks at once and holds x1' = belt / 1e12: x2 moves as it does with x1 pinned."""
    t_end = 60.0
    run = simulate_system(load_system(chain(tmp_path, "1e12")), t_end)
    ref = simulate_system(load_system(pinned(tmp_path)), t_end)
    assert run.status == "ok" and np.all(run.modes[0, 1:] == 0)
    q1 = run.state[0]
    np.testing.assert_allclose(q1[-1], BELT / 1e12 * t_end, rtol=0, atol=1e-15)   # the stuck drift (1e16: 3.3e-9)
    mine = run.switches[run.switch_contact == 1]
    assert len(mine) == len(ref.switches) >= 10
    np.testing.assert_allclose(mine, ref.switches, rtol=0, atol=1e-9)
    np.testing.assert_array_equal(run.switch_mode[run.switch_contact == 1], ref.switch_mode)


def test_a_contact_at_the_lower_bound_barely_acts(tmp_path: Path) -> None:
    """Along 1e-12 the contact's force on x1 is ~1e-13: contact.1 switches as it does with no contact.0."""
    t_end = 60.0
    run = simulate_system(load_system(chain(tmp_path, "1e-12")), t_end)
    text = chain(tmp_path, "1.0", "free.toml").read_text()
    start = text.index("[[contact]]")
    free = tmp_path / "free.toml"
    free.write_text(text[:start] + text[text.index("[[contact]]", start + 1):])
    ref = simulate_system(load_system(free), t_end)
    mine = run.switches[run.switch_contact == 1]
    assert len(mine) == len(ref.switches) >= 10 and np.all(run.modes[0] == 1)
    np.testing.assert_allclose(mine, ref.switches, rtol=0, atol=1e-9)
