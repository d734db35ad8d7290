"""Continuations draw a progress bar on stderr when asked (``progress``), per branch traced."""

from __future__ import annotations

import pytest

from frictionflow import BeltOscillator, Coulomb, Stribeck
from frictionflow.orbits import continuation
from frictionflow.orbits.forced import continue_forced


def test_forced_branch_progress_bar_counts_its_points(capsys):
    model = BeltOscillator(zeta=0.05, vb=0.1, fex=0.3, omega=1.2)
    branch = continue_forced(model, Coulomb(0.2, 0.3), "omega", 1.2, 1.25, progress=True, max_points=30)
    err = capsys.readouterr().err
    assert "branch" in err and f"{len(branch.points) - 1}/30" in err  # the first point is the start, not traced
    quiet = continue_forced(model, Coulomb(0.2, 0.3), "omega", 1.2, 1.25, max_points=30)
    assert capsys.readouterr().err == "" and len(quiet.points) == len(branch.points)


def test_continuation_progress_bar(capsys):
    law = Stribeck(fd=0.02, fs=0.04, vs=0.01)
    continuation(BeltOscillator(zeta=0.1, vb=0.01), law, "zeta", 0.1, 0.3, progress=True, max_points=40)
    assert "branch" in capsys.readouterr().err


@pytest.mark.parametrize("value", ["yes", 1, None])
def test_progress_must_be_a_boolean(value):
    with pytest.raises(TypeError, match="progress"):
        continue_forced(BeltOscillator(zeta=0.05, vb=0.1, fex=0.3, omega=1.2), Coulomb(0.2, 0.3), "omega", 1.2, 1.25,
                        progress=value)
