"""Fig. 4 (Case II instantaneous power): the data set and the paper's statements about it."""

import math

import pytest

from frictionflow.paper import fig4
from frictionflow.paper.cases import select

BASE = (0.01, 0.01, 0.02)


def ratio(ds, var, other, solver="rk4"):
    return float(select(ds, *other)[var].sel(solver=solver)) / float(select(ds, *BASE)[var].sel(solver=solver))


def test_dataset_has_what_the_figure_shows(data):
    ds = data["fig4"]
    assert ds.P_dv_inst.dims == ds.P_f.dims == ("solver", "case", "tau")
    assert {"peak_P_dv", "peak_P_f", "last_P_dv", "last_P_fin", "last_net_friction"} <= set(ds.data_vars)
    for column in fig4.COLUMNS:
        for zeta, vb, fd, *_ in column:
            assert select(ds, zeta, vb, fd).P_f.notnull().all()


def test_case2_doubling_friction_leaves_damper_power_and_doubles_friction_power(data):
    # y = X - F_d obeys the same equation for any F_d (the band test |X| < F_d shifts with it): the motion,
    # hence P_dv = 2 zeta X'^2, is the same; P_f = F_d X' doubles
    ds = data["fig4"]
    a, b = select(ds, *BASE), select(ds, 0.01, 0.01, 0.04)
    for solver in ("rk4", "exact"):
        assert float(abs(b.P_dv_inst - a.P_dv_inst).sel(solver=solver).max()) < 1e-6 * float(a.peak_P_dv.sel(solver=solver))
        assert float(b.peak_P_f.sel(solver=solver) / a.peak_P_f.sel(solver=solver)) == pytest.approx(2.0, rel=1e-6)


def test_case2_belt_speed_scales_both_powers_it_is_not_only_a_phase_change(data):
    ds = data["fig4"]
    amp = ratio(ds, "last_amplitude", (0.01, 0.1, 0.02))
    assert amp > 8
    # P_f = F_d X' ~ A and P_dv = 2 zeta X'^2 ~ A^2: the peaks scale with the orbit
    assert ratio(ds, "peak_P_f", (0.01, 0.1, 0.02)) == pytest.approx(amp, rel=0.02)
    assert ratio(ds, "peak_P_dv", (0.01, 0.1, 0.02)) == pytest.approx(amp**2, rel=0.05)


def last_cycle_peak(c, var: str) -> float:
    """Largest |var| over the last cycle, from the shown history of the paper's method."""
    s = c.sel(solver="rk4")
    inside = (s.tau >= s.window_start) & (s.tau <= s.window_end)
    return float(abs(s[var]).where(inside).max())


def test_case2_more_damping_reduces_power_through_the_faster_decay(data):
    ds = data["fig4"]
    hi, lo = select(ds, 0.03, 0.01, 0.02), select(ds, *BASE)
    amp = float(hi.last_amplitude.sel(solver="rk4") / lo.last_amplitude.sel(solver="rk4"))
    assert amp < 1e-4
    # within one cycle the orbit shrinks by exp(-2 pi zeta): a peak and the cycle's half range agree to that
    rel = 1 - math.exp(-2 * math.pi * 0.03)
    assert last_cycle_peak(hi, "P_f") / last_cycle_peak(lo, "P_f") == pytest.approx(amp, rel=rel)
    # P_dv = 2 zeta X'^2 carries zeta itself as well: 3 times the square of the amplitude ratio
    assert last_cycle_peak(hi, "P_dv_inst") / last_cycle_peak(lo, "P_dv_inst") == pytest.approx(3 * amp**2, rel=2 * rel)


def test_case2_net_friction_power_sign_is_set_by_the_window_not_by_the_damper(data):
    c = select(data["fig4"], *BASE).sel(solver="rk4")
    from_max, from_min = float(c.last_net_friction), float(c.last_net_friction_from_min)
    p_dv, a = float(c.last_P_dv), float(c.last_amplitude)
    # from a minimum of X to the next X rises: F_d dX > 0; from a maximum it falls
    assert from_min > 0 > from_max
    assert float(c.last_R_f_from_min) < 1 < float(c.last_R_f)
    # net friction ~ F_d A zeta, damper ~ zeta A^2: the ratio is ~F_d / A (~800 here), not ~1
    assert abs(from_min) / p_dv == pytest.approx(0.02 / a, rel=0.5)
    assert abs(from_min) / p_dv > 100
