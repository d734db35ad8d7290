"""Model files refused when they are loaded, in one line, instead of failing (or running wrongly) later.

* contacts along linearly dependent directions (two stuck ones hold indeterminate forces: the switching engine
  crashed with numpy's "Matrix is singular to machine precision");
* a friction law no structure solver runs (``karnopp`` passed the loader and failed only when run);
* initial entries beyond the single mass's own bound on X(0), X'(0) (1e200 overflowed to ``"P": null``, exit 0);

and a model sweep over ``mass.i.j`` of a diagonal mass, which ``System.with_entry`` and ``stability --param``
accept, taken by the sweep too (it said "grid.mass.0: unknown key '1'").
"""

from __future__ import annotations

import math
import re
import tomllib
from pathlib import Path

import numpy as np
import pytest

from frictionflow.friction.registry import law_class, law_names
from frictionflow.analysis.stability import stability_scan
from frictionflow.orbits import find_structure_orbit
from frictionflow.solvers.structure import simulate_system, structure_solvers, supported_laws
from frictionflow.sweep.model import load_model_sweep, parse_model_sweep
from frictionflow.system import System, assemble, checks, load_system
from frictionflow.system.checks import MAGNITUDE_MAX

from ..cli.processes import in_process, one_line

DOCS = Path(__file__).resolve().parents[2] / "docs" / "guide" / "models.md"

TWO_DOF = """
dof = ["x1", "x2"]
mass = {mass}
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
c = 0.02
{contacts}
[initial]
v = {{ x1 = {v} }}
"""


def contact(on: str, fd: float = 0.1, fs: float = 0.2, friction: str = "coulomb", extra: str = "") -> str:
    return f'[[contact]]\non = {{ {on} }}\nbelt = 0.05\nfriction = "{friction}"\nfd = {fd}\nfs = {fs}\n{extra}'


def model(tmp_path: Path, *contacts: str, mass: str = "[1.0, 1.0]", v: float = 0.05, name: str = "m.toml") -> Path:
    path = tmp_path / name
    path.write_text(TWO_DOF.format(mass=mass, contacts="\n".join(contacts), v=v))
    return path


def refused_by_cli(tmp_path: Path, path: Path, *words: str, command: str = "simulate") -> str:
    """``COMMAND --model PATH --out r.nc``: exit 2, one error line holding ``words``, no file written."""
    before = sorted(p.name for p in tmp_path.iterdir())
    code, _, err, _ = in_process(command, "--model", str(path), *(("--out", str(tmp_path / "r.nc")) if command == "simulate"
                                                                 else ()))
    assert code == 2, err
    line = one_line(err, *words)
    assert sorted(p.name for p in tmp_path.iterdir()) == before
    return line


# -- 1. contacts along dependent directions ----------------------------------------------------------------------

@pytest.mark.parametrize(("ons", "bad", "of"), [
    (("x1 = 1.0", "x1 = 1.0"), "contact.1", ("contact.0",)),           # the QA's R.toml: both along x1
    (("x1 = 1.0", "x1 = -2.0"), "contact.1", ("contact.0",)),          # a multiple, either sign
    (("x1 = 1.0", "x2 = 1.0", "x1 = 0.5, x2 = -0.5"), "contact.2", ("contact.0", "contact.1")),  # e2 = (e0 - e1)/2
    (("x2 = 1.0", "x1 = 1.0", "x1 = 3.0"), "contact.2", ("contact.1",)),  # a multiple of a later-listed one alone
])
def test_contacts_along_dependent_directions_are_refused_by_the_engines_naming_them(tmp_path, ons, bad, of):
    """The directions' dependence is built into the cases (a multiple, a combination), independently of the code:
    the model loads (it is one: steady sliding needs no stick), and a run is refused before it starts, naming the
    dependent contact and the ones it combines (and no other)."""
    system = load_system(model(tmp_path, *(contact(on) for on in ons)))
    for solver in ("exact", "adaptive"):
        with pytest.raises(ValueError) as info:
            simulate_system(system, 10.0, solver=solver)
        message = str(info.value)
        assert "\n" not in message and message.startswith(f"{bad}: its direction is")
        assert "dependent directions" in message and "merge them into one contact" in message
        others = {f"contact.{i}" for i in range(len(ons))} - {bad}
        assert {c for c in others if c in message} == set(of)


def test_contacts_along_independent_directions_run(tmp_path):
    """Nearly parallel but independent directions (1e-3 apart: far above rounding) and two contacts on two dof run;
    three contacts on two dof cannot be independent (the rank is at most 2)."""
    for ons in (("x1 = 1.0", "x1 = 1.0, x2 = 1e-3"), ("x1 = 1.0", "x2 = 1.0")):
        system = load_system(model(tmp_path, *(contact(on) for on in ons)))
        assert simulate_system(system, 1.0).status == "ok"
    three = (contact("x1 = 1.0"), contact("x2 = 1.0"), contact("x1 = 1.0, x2 = 1.0"))
    assert np.linalg.matrix_rank(np.array([[1.0, 0.0], [0.0, 1.0], [1.0, 1.0]])) == 2
    with pytest.raises(ValueError, match="contact.2: its direction is a combination of those of contact.0 and contact.1"):
        simulate_system(load_system(model(tmp_path, *three)), 1.0)


def test_the_check_takes_coefficients_whose_norm_under_or_overflows():
    """|v| of 1e-200 or 1e200 entries under- or overflows: the check failed with numpy's "SVD did not converge"."""
    checks.independent([("contact.0", np.array([1e-200, 0.0])), ("contact.1", np.array([0.0, 1e200]))])
    with pytest.raises(ValueError, match=r"^contact.1: its direction is a multiple of contact.0's"):
        checks.independent([("contact.0", np.array([1e-200, 0.0])), ("contact.1", np.array([-3e-200, 0.0]))])


def test_dependent_contacts_are_refused_by_simulate_model_exit_2_nothing_written(tmp_path):
    """The QA's R.toml crashed ``simulate --model`` with "Matrix is singular to machine precision" (exit 2 from a
    numerical failure after loading); now the run is refused before it starts, naming both contacts."""
    path = model(tmp_path, contact("x1 = 1.0", 0.1, 0.2), contact("x1 = 1.0", 0.05, 0.1))
    line = refused_by_cli(tmp_path, path, "contact.1", "contact.0", "dependent directions")
    assert "singular" not in line


def test_a_stability_scan_passes_through_dependent_directions(tmp_path):
    """Steady sliding holds no contact stuck: a scan of a direction that makes two contacts parallel at one value
    (contact.1 along (1, x2) with x2 = 0) runs there too, as it did before the engines' check existed."""
    system = load_system(model(tmp_path, contact("x1 = 1.0"), contact("x1 = 1.0, x2 = 0.5")))
    scan = stability_scan(lambda v: assemble(system.with_entry("contact.1.on.x2", v)), [-1.0, -0.5, 0.0, 0.5, 1.0],
                          param="contact.1.on.x2")
    assert not scan.lost.any() and np.all(np.isfinite(scan.eigenvalues))


# -- 2. laws no structure solver runs ------------------------------------------------------------------------------

def runnable() -> list[str]:
    """The registered laws some structure solver runs, from the solvers' own lists (law codes they accept)."""
    runs = {name for solver in structure_solvers() for name in supported_laws(solver).values()}
    return [name for name in law_names() if name in runs]


@pytest.mark.parametrize("name", law_names())
def test_a_contact_takes_exactly_the_laws_some_structure_solver_runs(tmp_path, name):
    """Each registered law, with its default parameters: loaded iff a structure solver runs it; karnopp (no
    structure solver runs its stick band) and the laws with an internal state are refused, the message listing
    the runnable ones."""
    cls = law_class(name)
    assert "karnopp" in law_names() and "karnopp" not in runnable() and "coulomb" in runnable()
    text = f'[[contact]]\non = {{ x1 = 1.0 }}\nbelt = 0.05\nfriction = "{name}"\n'
    path = model(tmp_path, text)
    if name in runnable():
        assert load_system(path).contacts[0].law == cls()
        return
    with pytest.raises(ValueError) as info:
        load_system(path)
    message = str(info.value)
    assert message.startswith(f"model {path}: contact.0.friction: ") and name in message
    assert message.endswith(", ".join(runnable())), message


def test_an_unknown_law_lists_the_runnable_ones(tmp_path):
    with pytest.raises(ValueError, match=rf"contact.0.friction must be one of {', '.join(runnable())} "
                                         r"\(the laws a structure's contacts take\), got 'columb'$"):
        load_system(model(tmp_path, '[[contact]]\non = { x1 = 1.0 }\nbelt = 0.05\nfriction = "columb"\n'))


def test_karnopp_model_is_refused_by_simulate_orbit_and_sweep(tmp_path):
    """The QA's oneK.toml passed validation; ``orbit --model`` said "(simulate runs it on the adaptive solver)",
    which ``simulate`` then refused.  Now each command refuses the file when it loads it."""
    path = tmp_path / "oneK.toml"
    path.write_text('dof = ["x"]\nmass = [1.0]\n[[spring]]\non = { x = 1.0 }\nk = 1.0\n[[damper]]\non = { x = 1.0 }\n'
                    'c = 0.1\n[[contact]]\non = { x = 1.0 }\nbelt = 0.01\nfriction = "karnopp"\nfd = 0.02\nfs = 0.04\n'
                    'vd = 0.002\n[initial]\nv = { x = 0.01 }\n')
    for command in ("simulate", "orbit"):
        line = refused_by_cli(tmp_path, path, "contact.0.friction", "karnopp", ", ".join(runnable()), command=command)
        assert "simulate runs it" not in line
    sweep = tmp_path / "swK.toml"
    sweep.write_text('model = "oneK.toml"\nt_end = 100.0\n[grid]\n"contact.0.belt" = [0.01, 0.02]\n')
    with pytest.raises(ValueError, match="contact.0.friction: karnopp has a velocity band, which no structure solver runs"):
        load_model_sweep(sweep)


def test_the_guide_lists_the_runnable_laws_as_the_allowed_ones():
    """docs/guide/models.md's table listed karnopp among a contact's laws."""
    row = next(line for line in DOCS.read_text().splitlines() if line.startswith("| `[[contact]]`"))
    allowed, _, refused = row.partition("refused")
    assert f"({', '.join(runnable())}" in allowed and "karnopp" not in allowed and "karnopp" in refused


# -- 3. a sweep over an off-diagonal entry of a diagonal mass ----------------------------------------------------------

def test_a_sweep_over_an_off_diagonal_entry_of_a_diagonal_mass(tmp_path):
    """``mass.0.1`` of a diagonal mass is the coupling M_01 = M_10 (0 as written): ``with_entry`` sets it (the mass
    becomes a full matrix), so the sweep takes it.  Each point is the model written with that full matrix by hand."""
    diagonal = load_system(model(tmp_path, contact("x1 = 1.0"), mass="[1.0, 1.5]"))
    cfg = parse_model_sweep({"t_end": 50.0, "grid": {"mass.0.1": [0.0, 0.2], "contact.0.fd": [0.1, 0.15]}}, diagonal)
    assert list(cfg.axes) == ["mass.0.1", "contact.0.fd"] and cfg.axes["mass.0.1"].tolist() == [0.0, 0.2]
    for i, m01 in enumerate((0.0, 0.2)):
        for j, fd in enumerate((0.1, 0.15)):
            by_hand = load_system(model(tmp_path, contact("x1 = 1.0", fd), mass=f"[[1.0, {m01}], [{m01}, 1.5]]",
                                        name=f"full{i}{j}.toml"))
            point = cfg.point_system((i, j))
            np.testing.assert_array_equal(point.mass_matrix, by_hand.mass_matrix)
            assert point.contacts == by_hand.contacts
    with pytest.raises(ValueError, match=r"grid.mass.0.1\[1\] = 1.5: .*mass must be positive definite"):
        parse_model_sweep({"t_end": 50.0, "grid": {"mass.0.1": [0.0, 1.5]}}, diagonal)  # 1 * 1.5 < 1.5^2


def test_the_sweep_takes_the_addresses_with_entry_takes(tmp_path):
    """The sweep's test of an address is ``System.entry``'s (``stability --param``'s); an index out of range is an
    unknown entry, not a range table's key."""
    system = load_system(model(tmp_path, contact("x1 = 1.0"), mass="[1.0, 1.5]"))
    for address in ("mass.0.1", "mass.1.0", "spring.0.on.x2", "contact.0.normal.preload"):
        system.with_entry(address, 0.1 if "mass" in address else 1.0)  # accepted by with_entry ...
        parse_model_sweep({"grid": {address: [0.1, 0.2] if "mass" in address else [1.0, 2.0]}}, system)  # ... and here
    with pytest.raises(ValueError, match=r"unknown grid key 'mass.0.5': not an entry of the model"):
        parse_model_sweep({"grid": {"mass.0.5": [0.1, 0.2]}}, system)
    with pytest.raises(ValueError, match=r"grid.contact.0.belt: unknown key 'from'; allowed: num, scale, start, stop"):
        parse_model_sweep({"grid": {"contact.0.belt": {"from": 0.1, "stop": 0.2, "num": 2}}}, system)


# -- 4. the initial state's bound ---------------------------------------------------------------------------------------

@pytest.mark.parametrize("key", ["q", "v"])
def test_initial_entries_are_bounded_like_every_number_of_a_model(tmp_path, key):
    """The model's initial entries are bounded as its other numbers are (MAGNITUDE_MAX): the ends load, the next
    floats beyond are refused naming the entry (1e200 overflowed the run to "P": null).  They had the single
    mass's x0 / v0 range (1e6), which refused a start the model's own belts could reach."""
    system = load_system(model(tmp_path, contact("x1 = 1.0"), contact("x2 = 1.0")))
    for edge in (-MAGNITUDE_MAX, MAGNITUDE_MAX, 5e7):
        assert system.with_entry(f"initial.{key}.x2", edge).entry(f"initial.{key}.x2") == edge
    for beyond in (math.nextafter(MAGNITUDE_MAX, math.inf), math.nextafter(-MAGNITUDE_MAX, -math.inf), 1e200):
        with pytest.raises(ValueError, match=rf"^model [^:]*: initial\.{key}\.x2 must be finite and in "
                                             + re.escape(f"[{-MAGNITUDE_MAX:g}, {MAGNITUDE_MAX:g}], got")):
            system.with_entry(f"initial.{key}.x2", beyond)


def test_a_huge_initial_velocity_is_refused_by_simulate_model_exit_2_nothing_written(tmp_path):
    """The QA's bad/hugev.toml: initial.v.x1 = 1e200 ran with overflow warnings and exit 0."""
    path = model(tmp_path, contact("x1 = 1.0"), contact("x2 = 1.0"), v=1e200)
    refused_by_cli(tmp_path, path, "initial.v.x1", f"{MAGNITUDE_MAX:g}", "got 1e+200")


def test_orbit_refuses_dependent_contacts_before_shooting(tmp_path):
    system = load_system(model(tmp_path, contact("x1 = 1.0", 0.1, 0.2), contact("x1 = 1.0", 0.05, 0.1)))
    with pytest.raises(ValueError, match=r"^contact.1: its direction is a multiple of contact.0's"):
        find_structure_orbit(system, t_transient=10.0)
