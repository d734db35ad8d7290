"""Pseudo-arclength continuation: a fold of cycles, grazing, branch ends and power along branches."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from scipy.optimize import brentq, minimize_scalar

from frictionflow import BeltOscillator, Coulomb, Cubic, Stribeck, analyze, simulate
from frictionflow.cli import main
from frictionflow.orbits import ShootingError, continuation, find_orbit, shoot
from frictionflow.orbits.settings import ContinuationSettings

from ..conftest import slip_solution

FD, FS, VB = 0.02, 0.04, 0.01
STRIBECK = Stribeck(FD, FS, 0.01)
VB_FOLD = 0.016  # on the tail of the Gaussian Stribeck curve: a subcritical Hopf in zeta


@pytest.fixture(scope="module")
def fold_run():
    """Orbits born at the Hopf point of the equilibrium, continued in zeta (about 3 s)."""
    return continuation(BeltOscillator(zeta=0.3, vb=VB_FOLD), STRIBECK, "zeta", 0.2, 0.4, seeds=("hopf",), n_equilibria=21)


def _one(result, kind):
    found = [b for b in result.bifurcations if b.type == kind]
    assert len(found) == 1, [b.type for b in result.bifurcations]
    return found[0]


def test_hopf_branch_starts_subcritical_with_period_two_pi(fold_run):
    hopf = _one(fold_run, "hopf")
    assert hopf.value == pytest.approx(STRIBECK.hopf_damping(VB_FOLD), rel=1e-12)
    assert hopf.detail["criticality"] == "subcritical"
    branch = fold_run.branches[1]
    first = branch.points[0]
    # at the Hopf point the eigenvalues are +-i: the cycles are born with period 2 pi
    assert first.period == pytest.approx(2 * math.pi, abs=2e-3)
    assert first.value == pytest.approx(hopf.value, abs=1e-3) and first.value > hopf.value
    assert first.amplitude < 1e-3 and first.stability == "unstable"


def test_continuation_passes_the_fold_of_cycles(fold_run):
    fold = _one(fold_run, "fold")
    assert fold.detail["smooth"] and fold.detail["refined"]
    assert abs(fold.detail["multiplier"] - 1.0) < 1e-6  # a fold of cycles: the multiplier passes 1
    pts = fold_run.branches[1].points
    values = np.array([p.value for p in pts])
    k = int(np.argmax(values))
    assert 0 < k < len(pts) - 1  # zeta grows up to the fold and falls after it: the branch turned
    assert fold.value >= values.max() - 1e-12 and fold.value - values.max() < 2e-3
    assert all(p.stability == "unstable" for p in pts[:k]) and all(p.stable for p in pts[k + 1 :])
    assert all(not p.stick_fraction for p in pts[: k + 1])

    # independently: just below the fold two slip-only cycles coexist, on either side of mu = 1 ...
    below = BeltOscillator(zeta=fold.value - 0.002, vb=VB_FOLD)
    x_star = STRIBECK.sliding_equilibrium(VB_FOLD)
    inner, outer = shoot(below, STRIBECK, x_star + 0.017), shoot(below, STRIBECK, x_star + 0.022)
    assert inner.multiplier.real > 1.0 > outer.multiplier.real > 0.0
    assert not inner.has_stick and not outer.has_stick and outer.state[0] - inner.state[0] > 1e-4
    # ... and just above it there is none: a large start decays onto the equilibrium
    above = BeltOscillator(zeta=fold.value + 0.003, vb=VB_FOLD)
    with pytest.raises(ShootingError):
        shoot(above, STRIBECK, outer.state[0])
    tr = simulate(above, STRIBECK, t_end=600.0, x0=outer.state[0], v0=0.0)
    assert abs(tr.x[-1] - x_star) < 1e-5 and abs(tr.v[-1]) < 1e-5


def test_grazing_where_the_stable_cycle_gains_a_stick_phase(fold_run):
    graze = _one(fold_run, "grazing")
    assert graze.detail["stick_phase"] == "appears"
    fold = _one(fold_run, "fold")
    assert graze.value < fold.value
    model = lambda z: BeltOscillator(zeta=z, vb=VB_FOLD)
    x_big = STRIBECK.sliding_equilibrium(VB_FOLD) + 0.022
    assert shoot(model(graze.value - 2e-3), STRIBECK, x_big).has_stick
    assert not shoot(model(graze.value + 2e-3), STRIBECK, x_big).has_stick


def test_power_along_the_branches(fold_run):
    for b in fold_run.branches:
        for p in b.points:
            pw = p.measures.power
            if p.kind == "equilibrium":
                assert pw.P_fin == 0 and p.amplitude == 0
                assert p.measures.TR_B == pytest.approx(STRIBECK.sliding_equilibrium(VB_FOLD) / FD, rel=1e-12)
            else:  # one period of periodic motion: input = damper + friction output
                assert pw.P_fin == pytest.approx(pw.P_dv + pw.P_df, rel=1e-7)
    d = fold_run.to_dict()
    assert all(isinstance(b, list) for b in d["branches"])
    need = {"value", "kind", "stability", "period", "amplitude", "P_fin", "P_df", "P_dv", "R_c", "R_f", "TR_B"}
    assert all(need <= pt.keys() for b in d["branches"] for pt in b)
    assert all({"type", "value"} <= b.keys() for b in d["bifurcations"])


def _first_velocity_maximum(zeta):
    """Largest X' of the first oscillation after slip starts at the stick limit (F_s - 2 zeta V_b, V_b)."""
    x0 = FS - 2 * zeta * VB
    t = np.linspace(0, 2.5 * math.pi / math.sqrt(1 - zeta**2), 4001)
    _, v = slip_solution(t, x0, VB, FD, zeta)
    i = int(np.argmin(v[:2500]))
    j = i + int(np.argmax(v[i:]))
    r = minimize_scalar(lambda s: -slip_solution(s, x0, VB, FD, zeta)[1], bounds=(t[j - 1], t[j + 1]), method="bounded", options={"xatol": 1e-13})
    return -r.fun


def test_coulomb_stick_slip_branch_ends_where_slip_grazes_the_belt_speed():
    # With damping the slip spiral from the stick limit may no longer climb back to V_b: the
    # stick-slip cycle ends (no fold, no partner) where its maximum of X' just touches V_b.
    res = continuation(BeltOscillator(zeta=0.0, vb=VB), Coulomb(FD, FS), "zeta", 0.0, 0.5, seeds=("start",), n_equilibria=3)
    zeta_graze = brentq(lambda z: _first_velocity_maximum(z) - VB, 0.05, 0.3, xtol=1e-13)
    graze = _one(res, "grazing")
    assert graze.detail["ends_branch"]
    assert graze.value == pytest.approx(zeta_graze, abs=2e-5)
    assert res.branches[1].end == "grazing"
    assert all(p.stable and p.stick_fraction > 0 for p in res.branches[1].points)


def test_period_blows_up_as_the_belt_slows_down():
    # zeta = 0: T(V_b) = pi + 2 atan(V_b/(F_s-F_d)) + 2 (F_s-F_d)/V_b at every point of the branch
    res = continuation(BeltOscillator(zeta=0.0, vb=VB), Coulomb(FD, FS), "vb", VB, 1e-4, seeds=("start",), n_equilibria=3, max_period=100.0)
    pts = res.branches[1].points
    for p in pts:
        assert p.period == pytest.approx(math.pi + 2 * math.atan(p.value / (FS - FD)) + 2 * (FS - FD) / p.value, rel=1e-11)
        assert abs(p.multiplier) < 1e-12 and p.stable
    blowup = _one(res, "period_blowup")
    assert pts[-1].period > 100.0 > pts[-2].period
    assert blowup.value == pts[-1].value and res.branches[1].end == "period blowup"


def test_bad_requests_are_refused_before_any_work():
    m = BeltOscillator(zeta=0.05, vb=VB)
    with pytest.raises(ValueError, match="param must be one of"):
        continuation(m, Coulomb(FD, FS), "vs", 0.01, 0.02)
    with pytest.raises(ValueError, match="must differ"):
        continuation(m, Coulomb(FD, FS), "vb", 0.01, 0.01)
    with pytest.raises(ValueError, match="fs"):
        continuation(m, Coulomb(FD, FS), "fd", 0.01, 0.05)  # F_d would exceed F_s


def test_stick_slip_branch_folds_back_at_a_grazing_corner():
    # delta = 1 with viscous friction, continued in V_b: the stable stick-slip cycle loses its stick
    # phase and at the same point turns back as the unstable slip-only cycle of the subcritical Hopf
    # point -- a non-smooth fold (the multiplier jumps from 0 to ~4.4 instead of passing 1).
    law = Stribeck(FD, FS, 0.01, delta=1.0, viscous=0.05)
    res = continuation(BeltOscillator(zeta=0.1, vb=VB), law, "vb", 0.027, 0.033, seeds=("start",), n_equilibria=3)
    fold = _one(res, "fold")
    graze = _one(res, "grazing")
    assert not fold.detail["smooth"] and graze.detail["stick_phase"] == "vanishes" and fold.value == graze.value
    pts = res.branches[1].points
    k = int(np.argmax([p.value for p in pts]))
    assert all(p.stable and p.stick_fraction > 0 for p in pts[:k])
    assert all(p.stability == "unstable" and p.stick_fraction == 0 for p in pts[k + 1 :])
    assert pts[-1].value == 0.027  # back to where it started, on the other (unstable) cycle
    # independently: just before the corner both cycles exist, just beyond neither
    before = BeltOscillator(zeta=0.1, vb=fold.value - 2e-4)
    stick_cycle = find_orbit(before, law)  # where a simulation from the default start goes
    slip_cycle = shoot(before, law, law.sliding_equilibrium(before.vb) + 0.02)
    assert stick_cycle.has_stick and stick_cycle.stable
    assert not slip_cycle.has_stick and slip_cycle.multiplier.real > 1
    assert stick_cycle.state[0] - slip_cycle.state[0] > 1e-4  # two distinct cycles
    beyond = BeltOscillator(zeta=0.1, vb=fold.value + 2e-4)
    tr = simulate(beyond, law, t_end=400.0, x0=stick_cycle.state[0], v0=0.0)
    assert abs(tr.x[-1] - law.sliding_equilibrium(beyond.vb)) < 1e-6 and abs(tr.v[-1]) < 1e-6


# -- accuracy near a Hopf point: the tolerance bounds the error in X, not the residual ---------------------------

HOPF_LAW = Cubic(fs=0.4, k1=0.45, k3=0.6)


@pytest.fixture(scope="module")
def hopf_branch():
    res = continuation(BeltOscillator(zeta=0.05, vb=0.3), HOPF_LAW, "vb", 0.2, 0.8, seeds=("hopf",))
    return [b for b in res.branches if b.points[0].kind == "periodic"][0]


def test_branch_points_next_to_a_hopf_point_are_as_accurate_as_a_single_orbit(hopf_branch):
    """The first points barely contract (mu = 0.99978): a residual of 1e-9 would leave X off by 5e-6.
    Each must agree with an orbit shot to 1e-13 at the same V_b from the same section point."""
    first = hopf_branch.points[:4]
    assert abs(first[0].multiplier) > 0.999
    for p in first:
        o = find_orbit(BeltOscillator(zeta=0.05, vb=p.value), HOPF_LAW, x0=p.x, v0=0.0, transient=0, tol=1e-13)
        assert p.measures.amplitude == pytest.approx(o.amplitude, rel=1e-9), p.value
        assert p.period == pytest.approx(o.period, rel=1e-11), p.value


def test_continue_takes_a_tolerance(capsys):
    code = main(["continue", "--friction", "cubic", "--fs", "0.4", "--k1", "0.45", "--k3", "0.6", "--zeta", "0.05",
                 "--param", "vb", "--from", "0.42", "--to", "0.45", "--seeds", "hopf", "--tol", "1e-11", "--json"])
    out, _ = capsys.readouterr()
    assert code == 0 and json.loads(out)["branches"]
    assert main(["continue", "--param", "vb", "--from", "0.42", "--to", "0.45", "--tol", "0.5"]) == 2
    assert "tol" in capsys.readouterr().err


def test_continuation_refuses_a_bad_tolerance():
    with pytest.raises(ValueError, match="tol"):
        continuation(BeltOscillator(zeta=0.05, vb=0.3), HOPF_LAW, "vb", 0.2, 0.8, tol=0.0)


def test_continuation_takes_its_settings_as_a_record_or_as_keywords():
    """A ContinuationSettings, its fields as keywords, or both (keywords win): the same branches; other keywords refused."""
    model, law = BeltOscillator(zeta=0.05, vb=0.3), HOPF_LAW
    by_keywords = continuation(model, law, "vb", 0.2, 0.8, seeds=(), n_equilibria=11)
    by_record = continuation(model, law, "vb", 0.2, 0.8, settings=ContinuationSettings(seeds=(), n_equilibria=11))
    overridden = continuation(model, law, "vb", 0.2, 0.8, settings=ContinuationSettings(seeds=(), n_equilibria=5),
                              n_equilibria=11)
    assert by_record.to_dict() == by_keywords.to_dict() == overridden.to_dict()
    assert len(by_keywords.branches[0].points) >= 11
    with pytest.raises(TypeError, match="continuation.*'n_equilibrium'"):
        continuation(model, law, "vb", 0.2, 0.8, n_equilibrium=11)
    with pytest.raises(TypeError, match="settings must be a ContinuationSettings"):
        continuation(model, law, "vb", 0.2, 0.8, settings={"seeds": ()})


def test_a_grazing_and_a_smooth_fold_close_together_are_told_apart():
    """Stribeck at V_b = 0.017 in zeta: the stick-slip cycle grazes at 0.30427 and goes on slip-only, stable, to a
    smooth fold at 0.31020.  The branch seeded by the simulation at zeta = 0 stepped over both at once and reported a
    non-smooth fold at the grazing (which the map then drew); the Hopf branch found the smooth fold.  Both branches now
    give the grazing and the smooth fold, and a simulation between them settles on the branch's slip-only cycle."""
    model, law = BeltOscillator(zeta=0.0, vb=0.017), Stribeck(0.02, 0.04, vs=0.01)
    res = continuation(model, law, "zeta", 0.0, 1.0)
    folds = [b for b in res.bifurcations if b.type == "fold"]
    assert folds and all(b.detail["smooth"] for b in folds)
    assert all(b.value == pytest.approx(0.3101954526, abs=1e-8) for b in folds)
    seeded = [b for b in res.bifurcations if b.type == "grazing"]
    assert {b.branch for b in seeded} == {b.branch for b in folds}  # each periodic branch: the grazing, then the fold
    # independently: between them a stable slip-only cycle, larger than the fold's (no fold at the grazing)
    run = analyze(simulate(BeltOscillator(zeta=0.3075, vb=0.017), law, t_end=800.0, x0=0.044, v0=0.0))
    assert run.steady_state.kind == "periodic" and run.steady_state.stick_fraction == 0.0
    fold_cycle = max((p for br in res.branches for p in br.points if p.kind == "periodic" and p.stable
                      and p.stick_fraction == 0.0), key=lambda p: p.value)
    assert 0.3101 < fold_cycle.value < 0.31020 and run.amplitude["X_max"] > fold_cycle.x
