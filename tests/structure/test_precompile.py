"""The structure engine's later kernels compiled in a second process during a first run
(solvers.structure_precompile): the signatures it compiles are the ones the run and the analysis use."""

from __future__ import annotations

import io
import sys
import time
from pathlib import Path

import numba
import numpy as np
import pytest

from frictionflow import motion as motion_module
from frictionflow import _compile_ahead
from frictionflow.core.structure import evaluate, run
from frictionflow.core.structure.combo import Combo, build
from frictionflow.solvers import structure_precompile as pre
from frictionflow.solvers.structure import simulate_system
from frictionflow.system import assemble, load_system

CHAIN = Path(__file__).parents[2] / "examples" / "models" / "two_mass_chain.toml"


def test_the_empty_combination_has_the_type_of_built_ones():
    assert tuple(pre.COMBO_FIELDS) == Combo._fields
    asm = assemble(load_system(CHAIN))
    minv = np.linalg.inv(asm.mass)
    empty = numba.typeof(pre.empty_combo())
    for modes in ([0, 0], [1, 0], [1, -1]):  # all stuck, one stuck, none: different shapes, one type
        assert numba.typeof(build(asm, minv, np.array(modes, dtype=np.int8))) == empty


def test_the_kernels_signatures_are_those_of_a_run_and_its_analysis(monkeypatch):
    """Record the arguments Motion gives the state evaluation and the stretch kernel on a real run."""
    seen = {}

    def recording(name, kernel):
        def call(*args):
            seen[name] = tuple(numba.typeof(a) for a in args)
            return kernel(*args)
        return call

    monkeypatch.setattr(motion_module, "exact_states", recording("states", evaluate.states))
    monkeypatch.setattr(motion_module, "advance", recording("advance", run.advance))
    motion = simulate_system(load_system(CHAIN), 20.0)
    assert pre.cached()  # the run loop ran: compiled into numba's cache or loaded from it
    motion.states([1.0, 2.5])
    motion.at(3.3)
    expected = {evaluate.states: seen["states"], run.advance: seen["advance"]}
    kernels = pre.kernels()
    assert [k for k, _ in kernels] == [run.to_event, evaluate.states, run.advance]  # the later ones first
    for kernel, signature in kernels[1:]:
        assert signature == expected[kernel]
    to_event = kernels[0][1]
    assert to_event[1] == numba.typeof(build(motion.assembly, np.linalg.inv(motion.assembly.mass),
                                             np.zeros(2, dtype=np.int8)))
    # What the second process runs, here: nothing new compiles.  to_event is called inside the compiled run loop,
    # so its signature there is only seen as the one in memory (the run compiled here) or in the cache (the run
    # loaded: its entry was written when the run compiled it; no test starts a second process).
    before = {kernel: set(kernel.overloads) for kernel, _ in kernels}
    pre.compile_kernels()
    for kernel, signature in kernels:
        if before[kernel]:
            assert set(kernel.overloads) == before[kernel]
        else:
            assert kernel.stats.cache_hits[signature] == 1 and not kernel.stats.cache_misses[signature]


def test_nothing_starts_when_the_run_loop_is_cached_or_on_one_core(monkeypatch, spawned):
    spawned.forbid()
    monkeypatch.setattr(pre, "cached", lambda: True)
    pre.in_background()()
    monkeypatch.setattr(pre, "cached", lambda: False)
    monkeypatch.setattr(_compile_ahead, "usable_cores", lambda: 1)
    pre.in_background()()


def test_stop_ends_a_child_still_compiling(monkeypatch, spawned):
    monkeypatch.setattr(pre, "cached", lambda: False)
    spawned.command = [sys.executable, "-c", "import time; time.sleep(60)"]
    stop = pre.in_background()
    assert spawned.argv == [[sys.executable, "-P", "-m", pre.__name__]]
    assert spawned.children[0].poll() is None
    start = time.monotonic()
    stop()
    assert spawned.children[0].returncode not in (None, 0) and time.monotonic() - start < 30.0  # ended, not waited


@pytest.mark.parametrize("is_cached, tty, says", [(False, True, True), (True, True, False), (False, False, False)])
def test_a_first_run_on_a_terminal_says_it_compiles(monkeypatch, is_cached, tty, says):
    err = io.StringIO()
    err.isatty = lambda: tty
    monkeypatch.setattr(sys, "stderr", err)
    monkeypatch.setattr(pre, "cached", lambda: is_cached)
    monkeypatch.setattr(pre, "in_background", lambda ready: lambda: None)
    with pre.first_use():
        pass
    assert ("compiling the structure engine" in err.getvalue()) is says
    assert err.getvalue().count("\n") == int(says)  # one line or nothing
