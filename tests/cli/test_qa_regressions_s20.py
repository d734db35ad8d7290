"""Regressions a QA pass found in the day's new checks (each failed before its fix)."""

from __future__ import annotations

import json

import pytest

from frictionflow import BeltOscillator, Coulomb
from frictionflow.cli import main
from frictionflow.orbits.forced import continue_forced
from frictionflow.paper.pipeline import _warm_up
from frictionflow.paper.settings import Settings
from frictionflow.parameters import Param


def test_an_integer_parameter_keeps_every_digit():
    """Through a float, 2^63 - 1 became 2^63 (refused by the open bound) and 2^53 + 1 became 2^53."""
    seed = Param("seed", "", "seed", "run", 0, kind="int", lower=0, upper=2**63, upper_open=True)
    assert seed.check(2**63 - 1) == 2**63 - 1 and seed.check(2**53 + 1) == 2**53 + 1
    with pytest.raises(ValueError, match=r"seed must be an integer"):
        seed.check(2**63)


@pytest.mark.parametrize("seed", [2**63 - 1, 2**53 + 1])
def test_basins_seed_is_taken_and_recorded_exactly(capsys, tmp_path, seed):
    code = main(["basins", "--x0-range", "-1:1", "--v0-range", "-1:1", "--sample", "2", "--seed", str(seed),
                 "--t-end", "50", "--json", "--out", str(tmp_path / "b.nc")])
    out = capsys.readouterr().out
    assert code == 0 and f'"seed": {seed}' in out


def test_forced_continuation_takes_the_clis_max_points_range():
    """The API took max_points up to 10^6 where forced-continue --max-points stops at 10^5."""
    model = BeltOscillator(zeta=0.05, vb=0.1, fex=0.3, omega=1.2)
    with pytest.raises(ValueError, match=r"max_points must be an integer and in \[2, 100000\], got 200000"):
        continue_forced(model, Coulomb(0.2, 0.3), "omega", 1.2, 1.25, max_points=200_000)


def test_reproduce_warm_up_takes_any_dt_in_range():
    """reproduce --dt 1.5 failed in the warm-up run ("dt must be <= t_end = 1"), after --out was made."""
    _warm_up(Settings(dt=1.5))
