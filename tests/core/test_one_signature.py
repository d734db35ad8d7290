"""Kernels that take a flag or a count compile once for all their callers.

numba types a literal ``True``/``False`` or ``0`` that a compiled caller passes as a type of its own, so a callee
called with a literal at one place and a value at another compiles twice (or three times) on a first run: the stiff
engine's Rodas step did, about 20 s each (a first LuGre ``simulate`` on an empty cache: 50 s, 31 s without).  The
callers pass ``np.bool_(...)``/``np.int64(...)``.

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
