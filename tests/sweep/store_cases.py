"""The small sweep the store tests (integrity, repair) damage and resume: 4 chunks of 1 x 2 x 2 points."""

from __future__ import annotations

import pytest
import xarray as xr

from frictionflow.sweep import run_sweep, runner

#: 4 chunks of 1 x 2 x 2 points (chunk_size=4) along zeta, about 0.1 s of work
CFG = {
    "friction": "coulomb",
    "fs": 0.04,
    "t_end": 100.0,
    "grid": {"zeta": [0.0, 0.04, 0.08, 0.12], "vb": [0.005, 0.02], "fd": [0.01, 0.02]},
}
CFG_TOML = """friction = "coulomb"
fs = 0.04
t_end = 100.0
[grid]
zeta = [0.0, 0.04, 0.08, 0.12]
vb = [0.005, 0.02]
fd = [0.01, 0.02]
"""


def run_small(out, cfg=CFG) -> xr.Dataset:
    """The sweep into ``out``, loaded and closed."""
    with run_sweep(cfg, out, chunk_size=4) as ds:
        return ds.load()


def interrupted(out, monkeypatch, after: int) -> None:
    """A run of :data:`CFG` into ``out`` interrupted (Ctrl-C) after ``after`` chunks (of 4)."""
    real, calls = runner.compute_chunk, []

    def compute(*args):
        if len(calls) == after:
            raise KeyboardInterrupt
        calls.append(args)
        return real(*args)

    with monkeypatch.context() as m:
        m.setattr(runner, "compute_chunk", compute)
        with pytest.raises(KeyboardInterrupt):
            run_small(out)
