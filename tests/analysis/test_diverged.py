"""A state that leaves the floating-point range is reported as ``diverged``, never as a normal result."""

from __future__ import annotations

import math

import numpy as np

from frictionflow import BeltOscillator, SlipLaw, analyze, simulate
from frictionflow.core import batch, sections
from frictionflow.quantities import KINDS


def _pumping_law():
    # slip force growing with the relative speed in the direction of motion: negative damping, no limit
    return SlipLaw(lambda s: 0.02 - 5.0 * s, fs=0.02, fd=0.02)


def test_a_run_that_overflows_is_diverged_with_no_numbers():
    tr = simulate(BeltOscillator(0.0, 0.01), _pumping_law(), t_end=500.0, x0=0.1, v0=0.0)
    bad = ~np.isfinite(tr.x)
    assert bad.any()
    res = analyze(tr)
    assert res.steady_state.kind == "diverged"
    assert res.steady_state.window[0] == tr.t[np.argmax(bad)]
    d = res.to_dict()
    assert all(v is None for v in d["averages"].values()) and d["TR_B"] is None
    assert all(v is None for v in d["amplitude"].values())


def test_batch_rows_of_a_point_whose_energy_overflowed_are_diverged():
    rec = np.full((0, sections.NF), np.nan)
    tail = np.zeros(sections.NA)
    fin = np.zeros(sections.NA)
    fin[sections.A_E] = math.inf
    out = np.zeros(batch.NR)
    p = np.zeros(8)
    p[1] = 0.02
    batch._row(rec, tail, fin, p, 0.0, 0.01, 1e-8, 3, 0.0, False, 0.0, out)
    assert KINDS[int(out[batch.R_KIND])] == "diverged"
    assert np.isnan(np.delete(out, batch.R_KIND)).all()
