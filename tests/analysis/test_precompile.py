"""The analysis kernels compiled in a second process during a first run (analysis.precompile)."""

from __future__ import annotations

from frictionflow.analysis import precompile
from frictionflow import _compile_ahead


def test_compile_analysis_runs_the_analysis_on_a_made_up_trajectory():
    precompile.compile_analysis()  # raises if the made-up trajectory no longer fits analyze()


def test_nothing_starts_when_the_kernels_are_cached(spawned):
    precompile.compile_analysis()
    assert precompile._cached()
    spawned.forbid()
    precompile.in_background()()


def test_the_second_process_compiles_and_exits_cleanly(monkeypatch, spawned):
    monkeypatch.setattr(precompile, "_cached", lambda: False)
    wait = precompile.in_background()
    wait()
    assert spawned.argv[0][-2:] == ["-m", precompile.__name__]
    assert len(spawned.children) == 1 and spawned.children[0].returncode == 0


def test_one_core_starts_nothing(monkeypatch, spawned):
    monkeypatch.setattr(precompile, "_cached", lambda: False)
    monkeypatch.setattr(_compile_ahead, "usable_cores", lambda: 1)
    spawned.forbid()
    precompile.in_background()()
