"""Case II is a transient: decay rates, and how the paper's averages depend on the window position."""

import math

import numpy as np
import pytest

from frictionflow.paper import transient

from .test_fig3 import envelope, terminal_state


def test_dataset_has_what_the_figures_show(data):
    ds = data["transient"]
    assert ds.R_c.dims == ("case", "solver", "cycle_start", "tau_i")
    assert {"P_dv", "P_fin", "P_df", "R_c", "R_f", "TR_B", "peak_P_dv", "peak_P_f", "window_start",
            "net_friction", "amplitude", "decay_rate", "implied_tau", "paper_value"} <= set(ds.data_vars)
    assert list(ds.cycle_start.values) == ["max", "min"]
    assert len(ds.case) == len(transient.CASES)


def test_every_case_decays_at_rate_zeta_in_both_solvers(data):
    ds = data["transient"]
    for solver in ("rk4", "exact"):
        np.testing.assert_allclose(ds.decay_rate.sel(solver=solver), ds.zeta, rtol=1e-3)


@pytest.mark.parametrize(("var", "power"), [("P_fin", 1), ("R_c", 1), ("peak_P_f", 1), ("P_dv", 2), ("peak_P_dv", 2)])
def test_averages_fall_with_the_window_position_at_rate_zeta_or_twice_it(data, var, power):
    ds = data["transient"].sel(solver="rk4", cycle_start="max")
    for i, zeta in enumerate(ds.zeta.values):
        c = ds.isel(case=i)
        ok = np.isfinite(c[var].values) & (c.window_start.values > 20.0)
        slope = np.polyfit(c.window_start.values[ok], np.log(c[var].values[ok]), 1)[0]
        assert -slope == pytest.approx(power * zeta, rel=1e-3), (var, i)


def test_the_paper_numbers_fix_its_window_near_tau_500_to_600(data, settings):
    # leading order: A(tau) = envelope of the free spiral from the exact solver's last band exit;
    # peak P_dv = 2 zeta A^2, peak |P_f| = F_d A, R_c = pi zeta A / F_d.  A relative O(zeta pi) error in A
    # moves the crossing by O(pi) time units.
    zeta, fd = 0.01, 0.02
    start = terminal_state(transient.CASES[0][0], settings)
    a0 = envelope(start[0], start, fd, zeta)

    def crossing(amplitude: float) -> float:
        return start[0] + math.log(a0 / amplitude) / zeta

    predicted = {
        "damper power below 1e-11": crossing(math.sqrt(1e-11 / (2 * zeta))),
        "friction power of order 1e-6": crossing(1e-6 / fd),
        "99.99 % dissipated by friction": crossing(1e-4 * fd / (math.pi * zeta)),
    }
    ds = data["transient"]
    for name, tau in predicted.items():
        measured = float(ds.implied_tau.sel(paper_number=name))
        assert measured == pytest.approx(tau, abs=2 * math.pi), name
        assert 450 < measured < 650, name


def test_moving_the_window_changes_rc_by_orders_of_magnitude(data):
    c = data["transient"].sel(solver="rk4", cycle_start="max").isel(case=0)
    rc = c.R_c.dropna("tau_i")
    start = c.window_start.dropna("tau_i")
    span = float(start[-1] - start[0])
    assert float(rc[0] / rc[-1]) == pytest.approx(math.exp(0.01 * span), rel=0.1)
    assert float(rc[0] / rc[-1]) > 100


def test_both_solvers_agree_on_every_window(data):
    ds = data["transient"].sel(cycle_start="max")
    for var in ("P_dv", "P_fin", "R_c", "TR_B"):
        a, b = ds[var].sel(solver="rk4"), ds[var].sel(solver="exact")
        ok = np.isfinite(a.values) & np.isfinite(b.values) & (ds.window_start.sel(solver="rk4").values > 20.0)
        np.testing.assert_allclose(a.values[ok], b.values[ok], rtol=1e-3, err_msg=var)


def test_the_damper_is_fed_by_the_initial_kinetic_energy_not_by_the_friction(data):
    # E = (X'^2 + X^2)/2 starts at (V_b^2 + F_d^2)/2 and ends within F_d A + A^2/2 of F_d^2/2 (A: the amplitude
    # left at the end), so W_dv - W_f,net = V_b^2/2 up to that.  In slip the friction's work is F_d times the
    # change of X, and X starts at X* = F_d: over the run it is at most F_d A, plus what the band visits took.
    ds = data["transient"]
    for i in range(len(ds.case)):
        a_end = float(ds.amplitude.sel(solver="exact", cycle_start="max").isel(case=i).dropna("tau_i")[-1])
        bound = float(ds.fd[i]) * a_end + a_end**2
        for solver in ("rk4", "exact"):
            c = ds.isel(case=i).sel(solver=solver)
            assert abs(float(c.run_W_dv - c.run_W_f_net - c.initial_K)) < bound, (i, solver)
            assert float(c.run_W_f_net) < bound  # friction's net work: zero (as A -> 0) or negative
            assert float(c.run_W_dv) > 0.9 * float(c.initial_K)
