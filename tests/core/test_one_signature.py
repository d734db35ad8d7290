"""Kernels that take a flag or a count compile once for all their callers.

numba types a literal ``True``/``False`` or ``0`` that a compiled caller passes as a type of its own, so a callee
called with a literal at one place and a value at another compiles twice (or three times) on a first run: the stiff
engine's Rodas step did, about 20 s each (a first LuGre ``simulate`` on an empty cache: 50 s, 31 s without).  The
callers pass ``np.bool_(...)``/``np.int64(...)``.

A counter or flag that starts as a literal and changes in a loop does the same without any literal at the call:
numba types the loop's body first with the start's literal type, compiles the callee for it, and then again for
``int64`` once the loop's type is settled (at most 5 s a kernel on the structure engine's first run: its root
finder ``locate``, the pencil's Newton steps).  Such a variable starts as ``np.int64(...)``/``np.bool_(...)``.

Which signatures a process holds depends on the cache (a caller loaded from it does not load its callees'
dispatchers), so the check reads the calls in the sources: it fails when a literal comes back at one of them.
"""

from __future__ import annotations

import ast
from pathlib import Path

import numpy as np
import pytest

import frictionflow as ff
from frictionflow.core import stiff
from frictionflow.core.layout import STICK
from frictionflow.core.structure import adaptive, run, stick

from ..structure.builders import single_mass

#: (module, callee, the argument given as a value, by position)
VALUE_ARGUMENTS = [(stiff, "step_from", 10), (stick, "decide_in", 9), (adaptive, "emit", 2), (run, "emit", 1)]


def calls(module, callee: str) -> list[ast.Call]:
    """The calls of ``callee`` by its bare name in ``module``'s source."""
    tree = ast.parse(Path(module.__file__).read_text(encoding="utf-8"))
    return [node for node in ast.walk(tree)
            if isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and node.func.id == callee]


@pytest.mark.parametrize("module, callee, position", VALUE_ARGUMENTS,
                         ids=[f"{m.__name__.rsplit('.', 1)[1]}.{c}" for m, c, _ in VALUE_ARGUMENTS])
def test_no_compiled_caller_passes_a_literal_where_others_pass_a_value(module, callee, position):
    found = calls(module, callee)
    assert len(found) >= 2, f"{callee}: fewer callers than this test was written for"
    literal = [ast.unparse(c) for c in found if isinstance(c.args[position], ast.Constant)]
    assert not literal, f"{callee} called with a literal (compiled once more): {literal}"


def test_the_check_would_see_a_literal():
    """The source check is not vacuous: a literal ``True`` at the flag's place is an ast.Constant."""
    call = ast.parse("step_from(q, zeta, vb, t, y, h, ynew, wnew, tol, ws, True)").body[0].value
    assert isinstance(call.args[10], ast.Constant)
    call = ast.parse("step_from(q, zeta, vb, t, y, h, ynew, wnew, tol, ws, np.bool_(True))").body[0].value
    assert not isinstance(call.args[10], ast.Constant)


def test_the_stick_rule_alone_and_with_directions_share_one_active_set_loop():
    """Compiled here or loaded, ``decide`` and ``release_over_limit`` (no run cache) type one ``decide_in``: after
    calling both, at most one signature without the cache is held (none when both were loaded from the cache)."""
    asm = single_mass(0.05, 0.1, ff.Coulomb(fd=0.3, fs=0.4), 0.2, 0.1)
    minv = np.linalg.inv(asm.mass)
    for call in (stick.decide, stick.release_over_limit):
        modes = np.array([STICK], dtype=np.int8)
        call(asm, minv, asm.q0.copy(), asm.v0.copy(), 0.0, modes, np.zeros(1, dtype=np.bool_))
        assert modes[0] == STICK  # its held force, about 0.21, is within F_s = 0.4: it stays stuck
    without_cache = [sig for sig in stick.decide_in.signatures if str(sig[7]) == "none"]
    assert len(without_cache) <= 1, without_cache


PACKAGE = Path(ff.__file__).parent
KERNEL_SOURCES = sorted((PACKAGE / "core").rglob("*.py"))


def decorator_kind(fn: ast.FunctionDef) -> str | None:
    """"inline" (numba inlines its IR), "compiled" (a kernel of its own), or None (not compiled)."""
    for d in fn.decorator_list:
        target = d.func if isinstance(d, ast.Call) else d
        if ast.unparse(target).rsplit(".", 1)[-1] not in ("njit", "jit"):
            continue
        keywords = d.keywords if isinstance(d, ast.Call) else []
        inline = any(k.arg == "inline" and getattr(k.value, "value", None) == "always" for k in keywords)
        return "inline" if inline else "compiled"
    return None


def bindings(fn: ast.FunctionDef) -> list[tuple[str, ast.expr | None]]:
    """Every (name, value bound or None when not known) in ``fn``, in the order of the source."""
    found = []
    for node in ast.walk(fn):
        if isinstance(node, ast.Assign):
            for target in node.targets:
                pairs = (zip(target.elts, node.value.elts) if isinstance(target, ast.Tuple)
                         and isinstance(node.value, ast.Tuple) else
                         [(e, None) for e in target.elts] if isinstance(target, ast.Tuple) else [(target, node.value)])
                found += [(t.id, v, t.lineno) for t, v in pairs if isinstance(t, ast.Name)]
        elif isinstance(node, (ast.AugAssign, ast.For)) and isinstance(node.target, ast.Name):
            found.append((node.target.id, None, node.lineno))
    return [(name, value) for name, value, _ in sorted(found, key=lambda b: b[2])]


def literal_starts(fn: ast.FunctionDef) -> set[str]:
    """The names in ``fn`` first bound to an int or bool literal (``-1`` too) and bound again later."""
    first: dict[str, ast.expr | None] = {}
    times: dict[str, int] = {}
    for name, value in bindings(fn):
        first.setdefault(name, value)
        times[name] = times.get(name, 0) + 1
    def literal(v):
        v = v.operand if isinstance(v, ast.UnaryOp) else v
        return isinstance(v, ast.Constant) and type(v.value) in (int, bool)
    return {name for name, value in first.items() if times[name] > 1 and literal(value)}


def literal_flows(trees: dict[str, ast.Module]) -> list[str]:
    """Each place a kernel passes such a name to a compiled kernel, or an inlined one returns it to its caller."""
    kernels = {fn.name for t in trees.values() for fn in ast.walk(t)
               if isinstance(fn, ast.FunctionDef) and decorator_kind(fn) == "compiled"}
    found = []
    for path, tree in trees.items():
        for fn in (f for f in ast.walk(tree) if isinstance(f, ast.FunctionDef) and decorator_kind(f)):
            names = literal_starts(fn)
            for node in ast.walk(fn):
                callee = getattr(node.func, "id", getattr(node.func, "attr", None)) if isinstance(node, ast.Call) else None
                passed = node.args if callee in kernels else []
                if isinstance(node, ast.Return) and decorator_kind(fn) == "inline" and node.value is not None:
                    passed = node.value.elts if isinstance(node.value, ast.Tuple) else [node.value]
                    callee = "its caller"
                found += [f"{path}:{node.lineno} {fn.name} gives {a.id} to {callee}"
                          for a in passed if isinstance(a, ast.Name) and a.id in names]
    return found


#: inlined kernels returning a loop's literal-started result that their callers only test, compute with or hand
#: to other inlined kernels (no compiled kernel receives it)
INLINE_RESULTS_NOT_PASSED_ON = {"_sections_at", "_aggregates", "nonzeros", "decide_interval", "phi2_terms",
                                "element_powers", "sparse_element_powers"}


def test_no_kernel_passes_a_loop_variable_that_starts_as_a_literal():
    trees = {str(p.relative_to(PACKAGE)): ast.parse(p.read_text(encoding="utf-8")) for p in KERNEL_SOURCES}
    found = [f for f in literal_flows(trees) if f.split()[1] not in INLINE_RESULTS_NOT_PASSED_ON]
    assert not found, "compiled once more for the start's literal type:\n" + "\n".join(found)


def test_the_flow_check_sees_a_counter_started_as_a_literal():
    """Not vacuous: the pattern numba compiles twice is found, and the fix is not."""
    source = """
@njit(cache=True)
def kernel(a):
    n = {start}
    for i in range(3):
        n = count(n, a)
    return n

@njit(cache=True)
def count(n, a):
    return n + len(a)
"""
    found = literal_flows({"m.py": ast.parse(source.format(start="0"))})
    assert found == ["m.py:6 kernel gives n to count"]
    assert literal_flows({"m.py": ast.parse(source.format(start="np.int64(0)"))}) == []
