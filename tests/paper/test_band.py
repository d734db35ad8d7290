"""Karnopp's band at V_b <= V_d: rest, creep and backward "stick" instead of stick."""

import numpy as np
import pytest

VD, FD = 1e-3, 0.02


def test_datasets_have_what_the_figure_shows(data):
    sweep, hist = data["band_sweep"], data["band_history"]
    assert list(sweep.model.values) == ["karnopp_rk4", "karnopp_exact", "coulomb_exact"]
    assert {"steady_V_max", "steady_V_min", "stick_fraction", "kind"} <= set(sweep.data_vars)
    assert VD in sweep.vb.values
    assert hist.V.dims == ("model", "tau_short") and hist.X_long.dims == ("model", "tau_long")
    assert hist.V_half.dims == ("model", "tau_half") and hist.creep_speed.dims == ("dt",)


def test_above_vd_karnopps_cycle_is_vd_smaller_than_ideal_coulombs(data):
    sw = data["band_sweep"].where(data["band_sweep"].vb > VD, drop=True)
    vb = sw.vb.values
    np.testing.assert_allclose(sw.steady_V_max.sel(model="coulomb_exact"), vb, rtol=1e-12)
    np.testing.assert_allclose(sw.steady_V_max.sel(model="karnopp_exact"), vb - VD, rtol=1e-12)
    # RK4 leaves the band within a step: radius off by a relative dt^2 (see test_fig2)
    np.testing.assert_allclose(sw.steady_V_max.sel(model="karnopp_rk4"), vb - VD, rtol=1e-6)


def test_at_vb_equal_vd_the_mass_rests_while_the_belt_moves_so_it_is_not_stick(data):
    c = data["band_sweep"].sel(vb=VD, model="karnopp_exact")
    assert str(c.kind.values) == "equilibrium" and float(c.stick_fraction) == 1.0
    assert abs(float(c.steady_V_max)) < 1e-15 and float(c.steady_P_fin) == 0.0
    assert float(c.steady_X_max) == pytest.approx(FD - VD, abs=1e-15)  # at rest at F_d - V_b, belt at V_b
    # ideal Coulomb friction at the same belt speed: the slip circle of radius V_b
    assert float(data["band_sweep"].sel(vb=VD, model="coulomb_exact").steady_V_max) == pytest.approx(VD, rel=1e-12)


def test_rk4_creep_at_vb_equal_vd_is_a_numerical_artefact_that_changes_with_the_step(data):
    hist = data["band_history"]
    creep = hist.creep_speed.values
    assert np.all((creep > 0) & (creep < 1e-3 * VD))
    assert creep.max() / creep.min() > 4  # a physical velocity would not depend on the step
    # and RK4 keeps drifting at that speed while the exact solver stays put
    x_rk, x_ex = hist.X_long.sel(model="karnopp_rk4"), hist.X_long.sel(model="karnopp_exact")
    t = hist.tau_long
    creeping = (t > 100.0) & (x_rk < FD - 1e-5)  # until it reaches X = F_d, thousands of time units later
    slope = np.polyfit(t[creeping], x_rk[creeping], 1)[0]
    assert slope == pytest.approx(float(hist.creep_speed.sel(dt=1e-3)), rel=1e-3)
    assert float(x_ex[t > 100.0].max() - x_ex[t > 100.0].min()) < 1e-15


def test_below_vd_the_band_holds_the_mass_while_it_moves_against_the_belt(data):
    hist = data["band_history"]
    vb = float(hist.attrs["vb_half"])
    for model in ("karnopp_rk4", "karnopp_exact"):
        c = hist.sel(model=model)
        assert float(c.band_share_half) > 0.95, model  # Karnopp calls nearly all of it stick ...
        # ... while the mass moves against the belt half the time: inside the band X'' = F_c(X) - X is odd in X, so
        # over whole shuttles X' < 0 exactly half of each (over the 2.4 of the plotted window, 58 %)
        assert float(c.backward_share_half) == pytest.approx(0.5, abs=2e-3), model
        assert float(c.V_half.min()) == pytest.approx(-vb, rel=1e-6), model  # at the belt's speed, backwards
