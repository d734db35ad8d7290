"""Fig. 5 (dissipation ratios): the data set, a leading-order closed form, and the paper's trends.

Over a cycle of the free spiral from a maximum of X, with amplitude A at its
start and w ~ 1: the friction puts in F_d (X_max,next - X_min) = F_d A
(e^(-2 pi zeta) + e^(-pi zeta)) and the damper takes 2 zeta int X'^2 =
zeta A^2 int e^(-2 zeta s) ds / (2 pi) per period, so with the cycle's half range
A_h = A (1 + e^(-pi zeta)) / 2,

    R_c = pi zeta A_h / F_d (1 + O(zeta^2))      (the first-order terms cancel).

The friction's output over the same cycle is F_d (X_max - X_min) = F_d A (1 + e^(-pi zeta)), so

    R_f = e^(pi zeta)  from a maximum,   e^(-pi zeta)  from a minimum     (1 + O(zeta^2)).
"""

import math

import numpy as np
import pytest


def test_dataset_has_what_the_figure_shows(data):
    ds = data["fig5"]
    assert {"solver", "vb", "fd", "zeta"} <= set(ds.coords)
    assert ds.last_R_c.dims == ds.last_R_f.dims == ("solver", "vb", "fd", "zeta")
    assert {0.01, 0.1} <= set(ds.vb.values.tolist()) and {0.02, 0.04} <= set(ds.fd.values.tolist())
    assert {0.01, 0.03} <= set(ds.zeta.values.tolist())
    assert ds.last_R_c.sel(solver="rk4", vb=0.1, fd=0.02, zeta=0.01).notnull()  # the red symbol


def test_rc_follows_pi_zeta_a_over_fd(data):
    sw = data["sweep"].sel(solver="rk4")
    z = sw.zeta.where(sw.zeta > 0, drop=True)
    c = sw.sel(zeta=z)
    predicted = math.pi * c.zeta * c.last_amplitude / c.fd
    err = abs(c.last_R_c / predicted - 1)
    assert bool((err < 10 * c.zeta**2).all())


def test_rc_halves_when_friction_doubles(data):
    sw = data["sweep"].sel(vb=0.01)
    z = sw.zeta.where(sw.zeta > 0, drop=True)
    r = sw.last_R_c.sel(fd=0.04, zeta=z) / sw.last_R_c.sel(fd=0.02, zeta=z)
    assert np.allclose(r.values, 0.5, rtol=1e-6)


def test_rc_falls_with_damping_at_the_papers_window_so_it_does_not_increase_slightly(data):
    sw = data["sweep"].sel(solver="rk4", vb=0.01, fd=0.02)
    ratio = float(sw.last_R_c.sel(zeta=0.03) / sw.last_R_c.sel(zeta=0.01))
    amplitude = float(sw.last_amplitude.sel(zeta=0.03) / sw.last_amplitude.sel(zeta=0.01))
    assert ratio < 1e-3
    assert ratio == pytest.approx(3 * amplitude, rel=10 * 0.03**2)


def test_rc_grows_tenfold_with_belt_speed_so_the_change_is_not_little(data):
    sw = data["sweep"].sel(solver="rk4", fd=0.02, zeta=0.01)
    ratio = float(sw.last_R_c.sel(vb=0.1) / sw.last_R_c.sel(vb=0.01))
    assert ratio > 8
    assert ratio == pytest.approx(float(sw.last_amplitude.sel(vb=0.1) / sw.last_amplitude.sel(vb=0.01)), rel=1e-3)


def test_friction_share_of_9999_percent_is_not_a_balance_transient_rc_plus_rf_is_not_one(data):
    sw = data["sweep"]
    w = sw.sel(solver="rk4", vb=0.01, fd=0.02, zeta=0.01)
    # over a cycle from a maximum the friction takes out more than it puts in: R_f = e^(pi zeta), not 1 - R_c
    assert float(w.last_R_f) == pytest.approx(math.exp(math.pi * 0.01), rel=10 * 0.01**2)
    assert abs(float(w.last_R_c + w.last_R_f) - 1) > 100 * float(w.last_R_c)
    # in the steady state nothing flows: the ratios do not exist
    steady = sw.sel(solver="exact").where(sw.zeta > 0, drop=True)
    assert float(abs(steady.steady_P_fin).max()) == 0.0
    assert bool(steady.steady_R_c.isnull().all())


def test_case1_has_no_damper_share_and_friction_dissipates_all_it_puts_in(data):
    c = data["sweep"].sel(zeta=0.0, solver="exact")
    assert float(abs(c.steady_R_c).max()) == 0.0
    assert np.allclose(c.steady_R_f.values, 1.0, rtol=1e-12)


def test_both_solvers_give_the_same_ratios_over_the_same_kind_of_window(data):
    sw = data["sweep"]
    z = sw.zeta.where(sw.zeta > 0, drop=True)
    r = sw.last_R_c.sel(solver="rk4", zeta=z) / sw.last_R_c.sel(solver="exact", zeta=z)
    assert np.allclose(r.values, 1.0, rtol=1e-4)
