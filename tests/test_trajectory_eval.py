"""Trajectories as continuous objects: ``traj(t)`` against closed forms, resampling, dense datasets.

The references are derived here from the equation of motion, phase by phase
(which phase a time falls in is read from the solver's public switch record):

* slip, or Karnopp's saturated band: X'' + 2 zeta X' + X = F with F constant
  (``slip_solution`` of conftest);
* stick (X' = V_b held), Karnopp's band holding F_e = X + 2 zeta X', sliding
  on a band edge: X'' = 0, a straight line;
* Karnopp's band holding F_e = X: X'' + 2 zeta X' + X = X, so
  X' = X'_0 e^{-2 zeta s}, X = X_0 + X'_0 (1 - e^{-2 zeta s}) / (2 zeta);
* smooth slip laws (no closed form): scipy's DOP853 at rtol 1e-12 from the
  phase's first sample.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from frictionflow import RK4, Adaptive, BeltOscillator, Coulomb, Cubic, Exact, Karnopp, SlipLaw, Stribeck, SwitchMode, simulate

from .conftest import slip_solution

S = SwitchMode
RNG_SEED = 14


def phase_closed_form(mode: SwitchMode, law, zeta: float, x0: float, v0: float, s: np.ndarray):
    """(X, X') a time ``s`` into a phase of ``mode`` started at (x0, v0), from the equation of motion."""
    constant = {S.SLIP_POSITIVE: law.fd, S.SLIP_NEGATIVE: -law.fd,
                S.BAND_SATURATED_POSITIVE: law.fs, S.BAND_SATURATED_NEGATIVE: -law.fs}
    if mode in constant:
        return slip_solution(s, x0, v0, constant[mode], zeta)
    if mode == S.BAND_HOLD and law.stick_force == "spring" and zeta > 0:
        e = np.exp(-2 * zeta * s)
        return x0 + v0 * (1 - e) / (2 * zeta), v0 * e
    return x0 + v0 * s, np.full_like(s, v0)


def phases(traj, first: SwitchMode):
    """(start time, start sample index, mode) of every phase, from the switch record."""
    out = [(traj.t[0], 0, first)]
    for t_ev, m in zip(traj.events["t"], traj.events["mode"], strict=True):
        # the phase's first sample: the last one at the switch time (zero-length phases share it)
        out.append((t_ev, int(np.searchsorted(traj.t, t_ev, side="right")) - 1, SwitchMode(m)))
    return out


def reference(traj, first: SwitchMode, t: np.ndarray, smooth=None):
    """The motion at times ``t`` from each phase's first sample: closed forms, or ``smooth`` (a DOP853 solve)."""
    ph = phases(traj, first)
    starts = np.array([p[0] for p in ph])
    x, v = np.empty_like(t), np.empty_like(t)
    for k, tq in enumerate(t):
        t0, i0, mode = ph[int(np.searchsorted(starts, tq, side="right")) - 1]
        if smooth is not None and mode in (S.SLIP_POSITIVE, S.SLIP_NEGATIVE):
            x[k], v[k] = smooth(traj, int(mode), traj.x[i0], traj.v[i0], tq - t0)
        else:
            xs, vs = phase_closed_form(mode, traj.friction, traj.zeta, traj.x[i0], traj.v[i0], np.array([tq - t0]))
            x[k], v[k] = xs[0], vs[0]
    return x, v


def dop853(traj, d: int, x0: float, v0: float, s: float):
    """Slip in direction ``d`` with the law's slip force, to rtol 1e-12."""
    if s == 0:
        return x0, v0
    law, zeta, vb = traj.friction, traj.zeta, traj.vb

    def rhs(_, y):
        return [y[1], d * float(law.slip_magnitude(abs(vb - y[1]))) - y[0] - 2 * zeta * y[1]]

    sol = solve_ivp(rhs, (0.0, s), [x0, v0], method="DOP853", rtol=1e-12, atol=1e-15)
    return sol.y[0, -1], sol.y[1, -1]


def check(traj, first, rtol, n=300, smooth=None):
    """traj(t) at random times against the reference, to ``rtol`` of the motion's scale."""
    rng = np.random.default_rng(RNG_SEED)
    t = np.sort(rng.uniform(traj.t[0], traj.t[-1], n))
    x, v = traj(t)
    xr, vr = reference(traj, first, t, smooth)
    scale = max(np.abs(traj.x).max(), np.abs(traj.v).max())
    assert np.abs(x - xr).max() <= rtol * scale
    assert np.abs(v - vr).max() <= rtol * scale


# -- the exact solver: closed form to rounding ---------------------------------------------------------

EXACT_CASES = {
    "coulomb": (0.05, 0.01, Coulomb(0.02, 0.04), 0.0),
    "coulomb-spring": (0.05, 0.01, Coulomb(0.02, 0.04, stick_force="spring"), 0.0),
    "karnopp": (0.02, 0.01, Karnopp(0.02, 0.025, vd=2e-3), 0.1),
    "karnopp-undamped": (0.0, 0.01, Karnopp(0.02, stick_force="spring"), 0.0),
    # F_e = X with damping: band hold (EXP), saturated band and sliding on the band's edge all occur
    "karnopp-spring": (0.02, 0.01, Karnopp(0.02, 0.025, vd=2e-3, stick_force="spring"), 0.1),
}


@pytest.mark.parametrize("case", EXACT_CASES)
def test_exact_trajectory_is_the_closed_form_at_any_time(case):
    zeta, vb, law, x0 = EXACT_CASES[case]
    traj = simulate(BeltOscillator(zeta, vb), law, Exact(), t_end=120.0, x0=x0, v0=0.0)  # v0 = 0 < V_b: slip+
    assert len(traj.events["t"]) >= 2
    check(traj, S.SLIP_POSITIVE, rtol=1e-12)


def test_the_spring_band_case_visits_every_band_mode():
    zeta, vb, law, x0 = EXACT_CASES["karnopp-spring"]
    traj = simulate(BeltOscillator(zeta, vb), law, Exact(), t_end=120.0, x0=x0, v0=0.0)
    seen = {SwitchMode(m) for m in traj.events["mode"]}
    assert {S.BAND_HOLD, S.BAND_SATURATED_POSITIVE, S.BAND_EDGE_LOWER} <= seen


def test_exact_evaluation_matches_the_solvers_own_dense_samples():
    """The solver's closed-form grid (dense_dt) is what traj(t) gives on a run without it."""
    model, law = BeltOscillator(0.05, 0.01), Karnopp(0.02, 0.04)
    sparse = simulate(model, law, Exact(), t_end=80.0)
    grid = simulate(model, law, Exact(dense_dt=0.0137), t_end=80.0)
    x, v = sparse(grid.t)
    assert np.allclose(x, grid.x, rtol=0, atol=1e-14) and np.allclose(v, grid.v, rtol=0, atol=1e-14)


def test_a_start_on_a_mode_boundary_takes_the_mode_the_solver_took():
    # F_e = X + 2 zeta X' = F_s exactly: band hold and saturation share the first sample's F_c
    law = Karnopp(0.02, 0.025, vd=2e-3)
    traj = simulate(BeltOscillator(0.1, 0.01), law, Exact(), t_end=40.0, x0=0.025 - 0.002, v0=0.01)
    grid = simulate(BeltOscillator(0.1, 0.01), law, Exact(dense_dt=0.01), t_end=40.0, x0=0.025 - 0.002, v0=0.01)
    x, _ = traj(grid.t)
    assert np.abs(x - grid.x).max() <= 1e-14


# -- the adaptive solver: to its tolerance ---------------------------------------------------------------

def test_adaptive_trajectory_is_the_closed_form_to_its_tolerance():
    traj = simulate(BeltOscillator(0.05, 0.01), Coulomb(0.02, 0.04), Adaptive(rtol=1e-10), t_end=100.0, v0=0.0)
    check(traj, S.SLIP_POSITIVE, rtol=1e-8)


def _user_slip(speed):
    return 0.02 + 0.02 * math.exp(-speed / 0.05)


@pytest.mark.parametrize("law", [Stribeck(0.02, 0.04, vs=0.05), Cubic(), SlipLaw(_user_slip)], ids=["stribeck", "cubic", "user"])
def test_adaptive_smooth_laws_match_an_independent_integration(law):
    traj = simulate(BeltOscillator(0.05, 0.01), law, Adaptive(rtol=1e-10), t_end=60.0, v0=0.0)
    check(traj, S.SLIP_POSITIVE, rtol=1e-7, n=80, smooth=dop853)


def test_a_looser_tolerance_gives_a_looser_curve_but_within_it():
    traj = simulate(BeltOscillator(0.05, 0.01), Coulomb(0.02, 0.04), Adaptive(rtol=1e-6), t_end=60.0, v0=0.0)
    check(traj, S.SLIP_POSITIVE, rtol=1e-4)


# -- RK4: interpolation between its samples ---------------------------------------------------------------

def slip_stretches(traj):
    """Sample index ranges (i0, i1) of slip, excluding the steps that straddle a band edge."""
    slip = traj.mode != 0
    edges = np.flatnonzero(np.diff(slip.astype(int))) + 1
    bounds = np.concatenate([[0], edges, [len(traj)]])
    return [(a + 1, b - 2) for a, b in zip(bounds[:-1], bounds[1:], strict=True) if slip[a] and b - a > 20]


@pytest.mark.parametrize("law, every, rtol", [
    (Karnopp(0.02, 0.04), None, 1e-9),
    (Coulomb(0.02, 0.04), None, 1e-9),
    (Karnopp(0.02, 0.04), 25, 1e-7),  # thinned: cubic Hermite over 25 steps, error ~ h^4
], ids=["karnopp", "coulomb", "karnopp-thinned"])
def test_rk4_is_interpolated_between_its_samples(law, every, rtol):
    traj = simulate(BeltOscillator(0.05, 0.01), law, RK4(dt=1e-3, record_every=every), t_end=40.0, v0=0.0)
    rng = np.random.default_rng(RNG_SEED)
    scale = np.abs(traj.x).max()
    for i0, i1 in slip_stretches(traj):
        t = rng.uniform(traj.t[i0], traj.t[i1], 50)
        x, v = traj(t)
        xr, vr = slip_solution(t - traj.t[i0], traj.x[i0], traj.v[i0], traj.fc[i0], traj.zeta)
        assert np.abs(x - xr).max() <= rtol * scale and np.abs(v - vr).max() <= rtol * scale


def test_rk4_smooth_law_matches_an_independent_integration():
    traj = simulate(BeltOscillator(0.05, 0.01), Stribeck(0.02, 0.04, vs=0.05), RK4(dt=1e-3), t_end=30.0, v0=0.0)
    rng = np.random.default_rng(RNG_SEED)
    scale = np.abs(traj.x).max()
    i0, i1 = slip_stretches(traj)[0]
    for tq in rng.uniform(traj.t[i0], traj.t[i1], 10):
        x, v = traj(tq)
        xr, vr = dop853(traj, int(traj.mode[i0]), traj.x[i0], traj.v[i0], tq - traj.t[i0])
        assert abs(x - xr) <= 1e-8 * scale and abs(v - vr) <= 1e-8 * scale


# -- the interface ------------------------------------------------------------------------------------------

def test_scalars_give_floats_arrays_keep_their_shape_and_the_span_is_enforced():
    traj = simulate(BeltOscillator(0.05, 0.01), Coulomb(0.02, 0.04), t_end=20.0)
    x, v = traj.at(3.0)
    assert isinstance(x, float) and isinstance(v, float)
    xs, vs = traj(np.full((2, 3), 3.0))
    assert xs.shape == (2, 3) and np.all(xs == x) and np.all(vs == v)
    assert traj(traj.t[0]) == (traj.x[0], traj.v[0])
    with pytest.raises(ValueError, match="span"):
        traj(20.5)


def test_sample_resamples_on_a_regular_grid():
    traj = simulate(BeltOscillator(0.05, 0.01), Coulomb(0.02, 0.04), t_end=20.0)
    r = traj.sample(0.5)
    assert np.allclose(r.t, np.arange(41) * 0.5) and len(r) == 41
    x, v = traj(r.t)
    assert np.array_equal(r.x, x) and np.array_equal(r.v, v)
    # the work totals run on: at the end they are the solver's
    assert np.allclose(r.work[-1], traj.work[-1], rtol=1e-12, atol=1e-18)


def test_dense_dataset_draws_the_curve_and_marks_the_samples():
    traj = simulate(BeltOscillator(0.05, 0.01), Coulomb(0.02, 0.04), t_end=100.0)
    assert len(traj) < 200  # the exact solver keeps only switches, zeros and extremes
    ds = traj.to_xarray()
    assert np.diff(ds.tau.values).max() <= 2 * math.pi / 64 * (1 + 1e-12)  # a small fraction of a period
    samples = ds.where(ds.is_sample, drop=True)
    assert np.array_equal(samples.tau.values, traj.t) and np.array_equal(samples.X.values, traj.x)
    assert int(ds.switch.sum()) == len(traj.events["t"])
    assert set(ds.tau.values[ds.switch.values]) == set(traj.events["t"])
    # off the samples the dataset is the closed form, F_c included
    grid = simulate(BeltOscillator(0.05, 0.01), Coulomb(0.02, 0.04), Exact(dense_dt=0.05), t_end=100.0)
    added = ds.where(~ds.is_sample, drop=True)
    x, _ = grid(added.tau.values)
    assert np.abs(added.X.values - x).max() < 1e-14
    assert ds.sizes["tau"] == traj.to_xarray(dense=False).sizes["tau"] + int((~ds.is_sample).sum())


def test_dense_work_integrals_are_the_solvers():
    """At added points the running work is a quadrature of the curve: it matches the solver's own grid."""
    model, law = BeltOscillator(0.05, 0.01), Karnopp(0.02, 0.04)
    traj = simulate(model, law, t_end=60.0)
    grid = simulate(model, law, Exact(dense_dt=0.05), t_end=60.0)
    r = traj.sample(0.05)
    j = np.clip(np.searchsorted(grid.t, r.t), 0, len(grid) - 1)
    same = np.abs(grid.t[j] - r.t) <= 1e-12  # the grid's dense points (j dense_dt) where they meet r's
    assert same.sum() > 0.9 * len(r)
    scale = np.abs(grid.work).max(axis=0)
    assert np.all(np.abs(r.work[same] - grid.work[j[same]]) <= 1e-11 * scale)


def test_a_run_sampled_densely_enough_is_left_as_it_is():
    traj = simulate(BeltOscillator(0.05, 0.01), Karnopp(0.02, 0.04), RK4(dt=1e-2), t_end=10.0)
    assert traj.dense() is traj
    ds = traj.to_xarray()
    assert bool(ds.is_sample.all()) and ds.sizes["tau"] == len(traj)


@pytest.mark.parametrize("zeta, law", [(0.05, Coulomb(0.02, 0.04)), (0.02, Karnopp(0.02, 0.025, vd=2e-3))], ids=["coulomb", "karnopp"])
def test_the_dense_trajectory_analyses_as_its_samples(zeta, law):
    """Added points carry quadrature increments that sum, per sample interval, to the solver's own."""
    from frictionflow import analyze

    traj = simulate(BeltOscillator(zeta, 0.01), law, t_end=150.0, x0=0.1, v0=0.0)
    dense = traj.dense()
    assert len(dense) > 5 * len(traj)
    a, b = analyze(traj), analyze(dense)
    assert a.steady_state.kind == b.steady_state.kind == "periodic"
    for k, value in a.power.averages().items():
        assert b.power.averages()[k] == pytest.approx(value, rel=1e-12, abs=1e-20), k
    assert b.TR_B == pytest.approx(a.TR_B, rel=1e-12)
