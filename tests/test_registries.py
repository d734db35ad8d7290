"""What laws and solvers declare is what the package does with them, for every registered one.

Nothing here lists laws or solvers: a new one is covered by registering it.
The last tests scan the source: outside ``solvers/`` and ``friction/`` no
module compares a name to a literal solver or law name (it reads a declaration
instead), and no Python-level module outside ``core/`` and ``friction/``
branches on a law's kernel code.
"""

from __future__ import annotations

import ast
import math
from pathlib import Path

import numpy as np
import pytest

from frictionflow import BeltOscillator, simulate
from frictionflow import _continuous as cont
from frictionflow.analysis.steady_state import DEFAULT_RTOL, default_rtol, section_noise
from frictionflow.cli import main
from frictionflow.core import layout
from frictionflow.friction import STICK_RULES, FrictionLaw, law_classes, law_names
from frictionflow.friction.registry import switch_law_names, tangent_law_names
from frictionflow.friction.user import SlipLaw
from frictionflow.orbits.forced import find_forced_orbit
from frictionflow.solvers.registry import solver_classes, solver_names
from frictionflow.sweep.compute import compute_chunk
from frictionflow.sweep.config import parse_sweep
from frictionflow.sweep.runner import default_chunk_size

MODEL = BeltOscillator(zeta=0.05, vb=0.02)
FORCED = BeltOscillator(zeta=0.05, vb=0.02, fex=0.01, omega=0.8)
SRC = Path(__file__).resolve().parents[1] / "src" / "frictionflow"


def _user_slip(speed):
    return 0.02 + 0.01 * math.exp(-speed / 0.01)


def instance(cls: type[FrictionLaw]) -> FrictionLaw:
    """A law of every registered class: the defaults, or a user's slip function."""
    return SlipLaw(_user_slip) if cls is SlipLaw else cls()


LAWS = {cls.name: instance(cls) for cls in law_classes()}
PAIRS = [(s, name) for s in solver_classes() for name in LAWS]


def _ids(pair):
    return f"{pair[0].name}-{pair[1]}"


# -- solvers ------------------------------------------------------------------------------------------

@pytest.mark.filterwarnings("ignore::frictionflow.solvers.CoarseStepWarning")  # a short run: its step is not the point
@pytest.mark.parametrize("pair", PAIRS, ids=_ids)
def test_a_solver_runs_exactly_the_laws_it_supports(pair):
    cls, name = pair
    solver, law = cls(), LAWS[name]
    models = (MODEL, FORCED) if cls.supports_forcing else (MODEL,)
    for model in models:
        if solver.supports(law):
            traj = simulate(model, law, solver, t_end=20.0)
            assert traj.solver["name"] == cls.name and np.isfinite(traj.x).all()
        else:
            with pytest.raises(ValueError, match=f"solver={cls.name} does not support friction={name}"):
                simulate(model, law, solver, t_end=20.0)


def test_every_law_has_a_solver_and_auto_is_registered():
    for name, law in LAWS.items():
        assert any(cls().supports(law) for cls in solver_classes()), name
    assert solver_names() == ("auto", *(cls.name for cls in solver_classes()))


@pytest.mark.parametrize("cls", solver_classes(), ids=lambda c: c.name)
def test_the_declared_interpolant_is_the_one_trajectory_at_uses(cls):
    assert cls.interpolant in cont.FORMS
    law = next(law for law in LAWS.values() if cls().supports(law) and (law.compiled_slip or law.internal_names))
    traj = simulate(MODEL, law, cls(), t_end=20.0)
    interp = cont.interpolant(traj)
    assert type(interp) is cont.FORMS[cls.interpolant]
    t = np.array([7.3, 11.1])
    x, v = interp.state(t)
    at = traj.at(t)
    assert np.array_equal(at[0], x) and np.array_equal(at[1], v)


@pytest.mark.parametrize("cls", solver_classes(), ids=lambda c: c.name)
def test_classification_defaults_are_the_declared_ones(cls):
    solver = cls()
    assert DEFAULT_RTOL[cls.name] == cls.steady_rtol == default_rtol(solver.describe())
    assert section_noise(solver.describe()) == cls.section_noise(solver.describe()) >= 0.0
    assert default_rtol({"name": "no such solver"}) == 1e-6 and section_noise({"name": "no such solver"}) == 0.0


def _sweep(cls):
    law = next(name for name, law in LAWS.items() if law.configurable and cls().supports(law))
    return parse_sweep({"friction": law, "solver": cls.name, "t_end": 20.0, "grid": {"zeta": [0.05, 0.06]}})


@pytest.mark.parametrize("cls", solver_classes(), ids=lambda c: c.name)
def test_the_sweep_runs_the_declared_batched_kernel_and_chunk(cls, monkeypatch):
    if cls.batched is None:  # declared: the sweep runs only laws with internal states with it, a run per point
        cfg = _sweep(cls)
        assert cfg.run.build()[1].internal_names
        assert np.isfinite(compute_chunk(cfg.source, (0,), (2,))[2:5]).all()
        coulomb = {"friction": "coulomb", "solver": cls.name, "t_end": 20.0, "grid": {"zeta": [0.05, 0.06]}}
        with pytest.raises(ValueError, match=f"^solver={cls.name} does not support friction=coulomb"):
            parse_sweep(coulomb)
        return
    cfg = _sweep(cls)
    assert default_chunk_size(cfg) == cfg.run.build()[2].chunk_points(cfg.run.t_end) >= 1
    calls = []
    original = cls.batched

    def spy(*args):
        calls.append(len(args))
        return original(*args)

    monkeypatch.setattr(cls, "batched", staticmethod(spy))
    out = compute_chunk(cfg.source, (0,), (2,))
    assert calls and np.isfinite(out[2:5]).all()


def test_the_fixed_step_solvers_are_refused_for_orbits_by_declaration(capsys):
    fixed = [cls.name for cls in solver_classes() if cls.fixed_step]
    locating = [cls.name for cls in solver_classes() if not cls.fixed_step]
    for name in fixed:
        assert main(["orbit", "--solver", name, "--friction", "coulomb"]) != 0
        err = capsys.readouterr().err
        assert f"solver={name} cannot locate switches" in err and all(n in err for n in locating)


# -- laws ---------------------------------------------------------------------------------------------

@pytest.mark.parametrize("name", LAWS)
def test_a_law_declares_a_known_stick_rule_and_its_kernel_code_agrees(name):
    law = LAWS[name]
    assert law.stick_rule in STICK_RULES
    assert law.has_tangent_kernel == (law.stick_rule == "switch" and law.compiled_slip)
    if law.compiled_slip:  # the kernels dispatch on its code: the code's rule is the declared one
        assert law.code in (layout.BAND_LAWS if law.stick_rule == "band" else layout.SWITCH_LAWS)
        assert law.piecewise_constant == (law.code not in layout.SMOOTH_LAWS)


def test_an_unknown_stick_rule_is_refused_when_the_law_is_declared():
    with pytest.raises(ValueError, match="stick_rule must be one of switch, band"):
        type("Sticky", (FrictionLaw,), {"stick_rule": "glue"})


@pytest.mark.parametrize("name", LAWS)
def test_forced_orbits_refuse_exactly_the_laws_without_a_tangent_kernel(name):
    law = LAWS[name]
    if law.has_tangent_kernel:  # the law passes; the next check (m) refuses before any work
        with pytest.raises(ValueError, match="^m must"):
            find_forced_orbit(FORCED, law, m=0)
        return
    with pytest.raises(ValueError, match="^friction: forced periodic orbits need") as e:
        find_forced_orbit(FORCED, law)
    assert f"({', '.join(tangent_law_names())})" in str(e.value) and name in str(e.value)


def test_the_law_lists_of_messages_come_from_the_declarations():
    configurable = [cls for cls in law_classes() if cls.configurable]
    assert tangent_law_names() == tuple(c.name for c in configurable if c.has_tangent_kernel)
    assert switch_law_names() == tuple(c.name for c in configurable if c.stick_rule == "switch")
    assert set(tangent_law_names()) <= set(switch_law_names()) <= set(law_names())


# -- the source ---------------------------------------------------------------------------------------

#: comparisons with a literal solver or law name allowed outside solvers/ and friction/, and why
ALLOWED_NAME_LITERALS = {
    # the paper's figures style its two runs, the values of its datasets' ``solver`` coordinate
    # (paper.runs.SOLVERS): a plotting choice about those two runs, not a capability
    ("paper/transient.py", "rk4"),
    ("paper/transient.py", "exact"),
    # the orbit engines' own names (exact, compiled, smooth): "exact" names the closed-form flow, not the solver
    ("orbits/flow.py", "exact"),
}


def _literals(node: ast.AST, names: set[str]) -> list[str]:
    """Names among the string constants a comparison, a dict's keys or a ``case`` compare against."""
    if isinstance(node, ast.Compare):
        parts = [node.left, *node.comparators]
    elif isinstance(node, ast.Dict):
        parts = [k for k in node.keys if k is not None]
    elif isinstance(node, ast.MatchValue):
        parts = [node.value]
    else:
        return []
    flat = [e for p in parts for e in (p.elts if isinstance(p, (ast.Tuple, ast.List, ast.Set)) else [p])]
    return [e.value for e in flat if isinstance(e, ast.Constant) and e.value in names]


def _modules(exclude: tuple[str, ...]):
    for path in sorted(SRC.rglob("*.py")):
        rel = path.relative_to(SRC).as_posix()
        if not rel.startswith(exclude):
            yield rel, ast.parse(path.read_text(encoding="utf-8"))


def test_no_module_outside_solvers_and_friction_compares_names_to_literal_ones():
    names = {cls.name for cls in solver_classes()} | set(law_names(configurable=False))
    found, used = [], set()
    for rel, tree in _modules(("solvers/", "friction/")):
        for node in ast.walk(tree):
            for name in _literals(node, names):
                if (rel, name) in ALLOWED_NAME_LITERALS:
                    used.add((rel, name))
                else:
                    found.append(f"{rel}:{node.lineno}: {ast.unparse(node)[:80]}")
    assert not found, "compare a declaration, not a name:\n" + "\n".join(found)
    assert used == set(ALLOWED_NAME_LITERALS), f"stale exceptions: {set(ALLOWED_NAME_LITERALS) - used}"


def test_law_codes_are_branched_on_only_in_the_kernels():
    codes = {"KARNOPP", "COULOMB", "STRIBECK", "CUBIC", "SMOOTH_LAWS", "BAND_LAWS", "SWITCH_LAWS"}
    found = [f"{rel}:{node.lineno}" for rel, tree in _modules(("core/", "friction/")) for node in ast.walk(tree)
             if isinstance(node, (ast.Name, ast.alias)) and (getattr(node, "id", None) or getattr(node, "name", "")) in codes]
    assert not found, "a law's code read outside the kernels (declare a capability on FrictionLaw): " + ", ".join(found)
