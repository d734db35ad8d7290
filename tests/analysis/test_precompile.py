"""The analysis kernels compiled in a second process during a first run (analysis.precompile)."""

from __future__ import annotations

import subprocess

from frictionflow.analysis import precompile


def test_compile_analysis_runs_the_analysis_on_a_made_up_trajectory():
    precompile.compile_analysis()  # raises if the made-up trajectory no longer fits analyze()


def test_nothing_starts_when_the_kernels_are_cached(monkeypatch):
    precompile.compile_analysis()
    assert precompile._cached()
    monkeypatch.setattr(precompile.subprocess, "Popen", lambda *a, **k: (_ for _ in ()).throw(AssertionError("started")))
    precompile.in_background()()


def test_the_second_process_compiles_and_exits_cleanly(monkeypatch):
    monkeypatch.setattr(precompile, "_cached", lambda: False)
    monkeypatch.setattr(precompile.os, "cpu_count", lambda: 2)
    children = []
    real_popen = subprocess.Popen

    def popen(*args, **kwargs):
        children.append(real_popen(*args, **kwargs))
        return children[-1]

    monkeypatch.setattr(precompile.subprocess, "Popen", popen)
    wait = precompile.in_background()
    wait()
    assert len(children) == 1 and children[0].returncode == 0


def test_one_core_starts_nothing(monkeypatch):
    monkeypatch.setattr(precompile, "_cached", lambda: False)
    monkeypatch.setattr(precompile.os, "cpu_count", lambda: 1)
    monkeypatch.setattr(precompile.subprocess, "Popen", lambda *a, **k: (_ for _ in ()).throw(AssertionError("started")))
    precompile.in_background()()
