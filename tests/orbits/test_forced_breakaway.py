"""A forced branch that ends where a break-away turns tangent.

On this Coulomb belt the harmonic branch from Omega = 1.2 passes a grazing
and a fold (1.3935) and comes back unstable, with two stick phases a period.
The second one's break-away happens ever closer to the held force's turn:
at Omega* ~ 1.38331 the force only touches F_s there, and below Omega* the
stick holds on past it, so the map jumps and the branch ends.  The
multiplier grows as 1 / (Omega - Omega*): the tracer used to creep towards
Omega* at its smallest step until ``max_points`` (400 points, the last at
1.38367) without reporting the end.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from frictionflow import BeltOscillator, Coulomb
from frictionflow.orbits.forced import continue_forced, find_forced_orbit, flow_run

MODEL = BeltOscillator(zeta=0.05, vb=0.1, fex=0.3, omega=1.2)
LAW = Coulomb(0.2, 0.3)


@pytest.fixture(scope="module")
def branch():
    return continue_forced(MODEL, LAW, "omega", 1.2, 1.5)


def _multiplier(omega: float, guess: np.ndarray) -> tuple[np.ndarray, float, int]:
    """The orbit near ``guess`` (damped Newton shooting), the largest |multiplier| of the map's Jacobian by central
    differences (not the run's monodromy) and its stick onsets a period."""
    model = replace(MODEL, omega=omega)
    orbit = find_forced_orbit(model, LAW, x0=guess[0], v0=guess[1], transient_periods=0)
    P = np.asarray(orbit.state, dtype=float)
    J = np.empty((2, 2))
    for j in range(2):
        d = np.zeros(2)
        d[j] = 1e-9
        J[:, j] = (flow_run(model, LAW, P + d).end - flow_run(model, LAW, P - d).end) / 2e-9
    return P, float(np.max(np.abs(np.linalg.eigvals(J)))), orbit.switches["stick_onsets"]


def test_branch_ends_at_the_tangent_break_away_where_the_multiplier_blows_up(branch):
    assert branch.end == "grazing"
    assert len(branch.points) < 100  # 400 (max_points) before, creeping at the smallest step
    end = branch.events[-1]
    assert end.type == "grazing" and end.detail["at"] == "breakaway_tangent" and end.detail["ends_branch"]
    assert [e.type for e in branch.events[:-1]] == ["grazing", "fold"]
    assert branch.points[-1].lam > end.lam  # reached coming down from the fold
    # independently: 1 / |mu| of the map's differenced Jacobian at the orbits falls linearly to 0 at Omega*,
    # walked down to it from the branch's last point (each guess extrapolated from the two before)
    offsets = np.geomspace(3e-3, 1e-4, 16)
    states = [np.asarray(q.state, dtype=float) for q in branch.points[-2:]]
    lams = [q.lam for q in branch.points[-2:]]
    inv = []
    for off in offsets:
        lam = end.lam + off
        guess = states[-1] + (states[-1] - states[-2]) * (lam - lams[-1]) / (lams[-1] - lams[-2])
        P, mu, sticks = _multiplier(lam, guess)
        assert sticks == 2
        states.append(P)
        lams.append(lam)
        inv.append(1.0 / mu)
    assert np.all(np.diff(inv) < 0.0) and 1.0 / inv[-1] > 100.0  # the same unstable orbit, its multiplier growing
    slope, at_zero = np.polyfit(offsets[-3:], inv[-3:], 1)
    assert abs(at_zero / slope) < 2e-6  # 1/mu = 0 within 2e-6 of end.lam


def test_both_ways_along_the_branch_end_at_the_same_point(branch):
    """From a stable orbit below Omega* (above the grazing at 1.3606) up through the fold: the same end.  (From
    one above Omega*, the interval [start, 1.5] would leave it out: that branch ends at its start's end.)"""
    near = min((q for q in branch.points if 1.365 < q.lam < 1.38 and q.stability == "stable"), key=lambda q: q.lam)
    orbit = find_forced_orbit(replace(MODEL, omega=near.lam), LAW, x0=near.state[0], v0=near.state[1],
                              transient_periods=0)
    again = continue_forced(orbit.model, LAW, "omega", near.lam, 1.5, orbit=orbit)
    assert again.end == "grazing" and again.events[-1].detail["at"] == "breakaway_tangent"
    assert again.events[-1].lam == pytest.approx(branch.events[-1].lam, abs=1e-8)


def test_branch_leaving_the_tangent_break_away_goes_on(branch):
    """From the unstable orbit nearest Omega* going up, the margin grows: the branch is not stopped there, it
    turns at the fold onto the stable orbits and leaves the interval."""
    last = branch.points[-1]
    assert last.stability == "unstable"
    orbit = find_forced_orbit(replace(MODEL, omega=last.lam), LAW, x0=last.state[0], v0=last.state[1],
                              transient_periods=0)
    up = continue_forced(orbit.model, LAW, "omega", last.lam, 1.5, orbit=orbit)
    assert [e.type for e in up.events] == ["fold"] and up.end == "interval end"
