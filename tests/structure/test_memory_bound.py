"""A structure run's records are held to ``max_memory`` as the single mass's are: refused in one line, up front.

Before, a structure run had no memory bound: ``simulate --model F --dense-dt 1e-6`` ran for a minute and died in a
70-line ``ArrayMemoryError`` traceback (25 GiB of samples), exit 1, and ``--dense-dt 1e-5`` ran at 10 GB.  The dense
grid's samples (t_end / dense_dt, a bound from below on every run's) are now checked before any work, and each
attempt's records before they are made (a run whose switches outgrow the bound).
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest

from frictionflow.solvers.structure import simulate_system
from frictionflow.solvers.structure_motion import row_bytes
from frictionflow.system import assemble, load_system

from ..cli.processes import in_process, one_line

MODELS = Path(__file__).resolve().parents[2] / "examples" / "models"
CHAIN = MODELS / "stick_slip_chain.toml"
STRIBECK = MODELS / "stribeck_chain.toml"


def test_a_run_sampled_too_densely_is_refused_before_any_work_with_nothing_written(tmp_path):
    out = tmp_path / "run.nc"
    code, stdout, err, seconds = in_process("simulate", "--model", str(CHAIN), "--dense-dt", "1e-6", "--json",
                                            "--out", str(out))
    assert code == 2 and stdout == "" and not out.exists()
    one_line(err, "dense_dt=1e-06", "3e+08 samples", "max_memory=4 GiB", "sample it less densely")
    assert seconds < 30.0  # refused from the count, not after a run (the old tree's took over a minute)


@pytest.mark.parametrize("solver, path", [("exact", CHAIN), ("adaptive", STRIBECK)])
def test_the_bound_is_the_records_bytes(solver, path):
    """The line's GiB are the dense samples times the bytes of one row of the solver's records, counted here
    from the records themselves; just above that bound the run is made, and sampled as asked."""
    system = load_system(path)
    t_end, dense_dt = 20.0, 1e-3
    samples = t_end / dense_dt + 1.0
    need = samples * row_bytes(assemble(system), derivatives=solver == "adaptive") / 2**30
    said = f"needs about {samples:.3g} samples ({need:.3g} GiB) but max_memory={need / 2:g} GiB"
    with pytest.raises(ValueError, match=re.escape(said)):
        simulate_system(system, t_end, dense_dt=dense_dt, solver=solver, max_memory=need / 2)
    motion = simulate_system(system, t_end, dense_dt=dense_dt, solver=solver, max_memory=4 * need)
    on_grid = np.abs(motion.t / dense_dt - np.round(motion.t / dense_dt)) < 1e-6
    assert np.unique(np.round(motion.t[on_grid] / dense_dt)).size == samples  # the whole grid, 0 and t_end too


def test_a_run_whose_steps_outgrow_the_bound_is_refused_when_its_records_would():
    """No dense grid: the adaptive Stribeck chain's 12,654 samples over t = 300 outgrow its first records (4,096
    rows); with room for about 6,000 rows, the first attempt is made and the larger one refused."""
    system = load_system(STRIBECK)
    row = row_bytes(assemble(system), derivatives=True)
    bound = 6_000 * row / 2**30
    with pytest.raises(ValueError, match="a run to t_end=300 needs about .* samples .* but max_memory="):
        simulate_system(system, 300.0, solver="adaptive", max_memory=bound)
    assert len(simulate_system(system, 300.0, solver="adaptive", max_memory=3 * bound).t) > 6_000


@pytest.mark.parametrize("bad", [0.0, -1.0, float("nan"), "4"])
def test_a_bad_max_memory_is_refused_naming_it(bad):
    with pytest.raises((ValueError, TypeError), match="max_memory"):
        simulate_system(load_system(CHAIN), 10.0, max_memory=bad)


def test_max_memory_applies_beside_a_model_file():
    code, stdout, err, _ = in_process("simulate", "--model", str(CHAIN), "--dense-dt", "0.01", "--max-memory",
                                      "1e-5", "--json")
    assert code == 2 and stdout == ""
    one_line(err, "dense_dt=0.01", "max_memory=1e-05 GiB")
    code, stdout, err, _ = in_process("simulate", "--model", str(CHAIN), "--t-end", "20", "--max-memory", "1",
                                      "--json")
    assert code == 0, err
