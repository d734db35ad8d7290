"""The records a structure run writes into: a run that fills them is run again, larger, with the same bits.

The first attempt is sized from an estimate of the samples; a run that
outgrows it is run again from the start with records sized from the pace it
kept, so that a long run pays one more attempt, not a doubling per 1,024
switches.  The reruns are checked against a run that never filled its records.
"""

from __future__ import annotations

import numpy as np
import pytest

from frictionflow import Coulomb
from frictionflow.core import codes
from frictionflow.core.assembly import natural_frequencies
from frictionflow.core.structure.run import Result
from frictionflow.solvers import structure, structure_adaptive, structure_motion

from .chains import chain


def bench_chain(n: int):
    """The benchmark's chain (benchmarks/bench_structure.py): sustained stick-slip."""
    laws = [Coulomb(0.2, 0.4) if i % 2 == 0 else Coulomb(0.1, 0.35) for i in range(n)]
    return chain(n, [0.1] * n, laws, q0=0.5 * np.sin(np.arange(1, n + 1)))


def counted(monkeypatch, module, name):
    """Wrap ``module.name`` to count its calls and remember the capacities it was given."""
    calls = []
    inner = getattr(module, name)

    def wrapper(*args):
        calls.append(len(args[-2].t) if name == "run" else len(args[-3].t))
        return inner(*args)
    monkeypatch.setattr(module, name, wrapper)
    return calls


def assert_same_motion(a, b):
    for field in ("t", "state", "force", "modes", "work", "switches", "switch_contact", "switch_mode"):
        np.testing.assert_array_equal(getattr(a, field), getattr(b, field), err_msg=field)
    assert a.status == b.status and a.lost == b.lost


def test_a_run_that_fills_its_records_is_run_once_more_with_the_same_bits(monkeypatch):
    """Records of 32 rows for a run of ~280 switches: one more attempt, sized from the pace, and the same Motion
    as a run whose first records were large enough."""
    asm = bench_chain(10)
    whole = structure.run_assembly(asm, 100.0)
    assert len(whole.switches) > 250
    calls = counted(monkeypatch, structure, "run")
    monkeypatch.setattr(structure, "first_capacity", lambda *args: 32)
    again = structure.run_assembly(asm, 100.0)
    assert len(calls) == 2 and calls[0] == 32 and calls[1] >= len(whole.t)
    assert_same_motion(again, whole)


def test_the_first_records_hold_a_long_run(monkeypatch):
    """The estimate sizes the first attempt: 3,000 switches of the 10-mass chain run once (the doubling from
    1,024 rows ran them three times)."""
    calls = counted(monkeypatch, structure, "run")
    motion = structure.run_assembly(bench_chain(10), 1000.0)
    assert len(motion.switches) > 2048 and len(calls) == 1


def test_the_adaptive_solver_regrows_alike(monkeypatch):
    """The adaptive solver's records of 16 rows: it runs again until they hold the run, with the same bits."""
    asm = bench_chain(2)
    whole = structure.run_assembly(asm, 20.0, solver="adaptive")
    calls = counted(monkeypatch, structure_adaptive, "run_kernel")
    monkeypatch.setattr(structure_adaptive, "FIRST_CAP", 16)
    again = structure.run_assembly(asm, 20.0, solver="adaptive")
    assert calls[0] == 16 and 2 <= len(calls) <= 3 and len(whole.t) > 16
    assert_same_motion(again, whole)


def test_regrow_carries_the_pace_to_the_end():
    """A run that filled 100 rows by a quarter of its time gets 1.25 x 400 rows; one that filled them by 0.9 of
    it still at least doubles; the switches counted are always covered."""
    samples, events = structure_motion.buffers(bench_chain(2), 100)
    samples.t[:100] = np.linspace(0.0, 25.0, 100)
    full = Result(codes.FULL, 100, 150, -1, np.nan)
    assert structure_motion.regrow(full, (samples, events), 100.0, 100) == 500
    samples.t[:100] = np.linspace(0.0, 90.0, 100)
    assert structure_motion.regrow(full, (samples, events), 100.0, 100) == 200
    assert structure_motion.regrow(Result(codes.OK, 60, 450, -1, np.nan), (samples, events), 100.0, 100) == 451


@pytest.mark.parametrize("n", [2, 100])
def test_first_capacity_is_bounded(n):
    """The first attempt holds the estimate, at least the floor and at most FIRST_BYTES of records."""
    asm = bench_chain(n)
    row = structure_motion.row_bytes(asm)
    assert structure_motion.first_capacity(asm, 10.0, 1024) == 1024
    most = max(1024, structure_motion.FIRST_BYTES // row)
    assert structure_motion.first_capacity(asm, 5000.0, 1024) == min(5000, most)
    assert structure_motion.first_capacity(asm, 1e12, 1024) * row <= max(structure_motion.FIRST_BYTES, 1024 * row)


def test_fastest_bound_bounds_the_natural_frequencies():
    """sqrt(||M^-1 K||_inf) is at least the largest undamped natural frequency (numpy's eigenvalues)."""
    for n in (1, 2, 10, 30):
        asm = bench_chain(n)
        bound = structure.fastest_bound(asm, np.linalg.inv(asm.mass))
        assert natural_frequencies(asm).max() <= bound * (1 + 1e-12)


def test_a_run_that_stopped_says_when_and_which_contact_flipped():
    """The line for a stopped run names the last sample's time, the status and, for zero-length phases in a row,
    the contact whose mode changed last (a line without them left the user to guess where to look)."""
    samples, events = structure_motion.buffers(bench_chain(2), 10)
    samples.t[:3] = [0.0, 1.5, 15.673552831]
    events.contact[:2] = [0, 1]
    names = {"contact": ("contact.0", "contact.1")}
    stuck = structure_motion.stopped(Result(codes.STUCK, 3, 2, -1, np.nan), (samples, events), names, "exact")
    assert stuck == ("solver=exact: the run stopped at t=15.673552831 with status 'stuck' "
                     "(contact.1 switched without time passing)")
    capped = structure_motion.stopped(Result(codes.STEP_CAP, 2, 2, -1, np.nan), (samples, events), names, "adaptive")
    assert capped == "solver=adaptive: the run stopped at t=1.5 with status 'step cap'"
