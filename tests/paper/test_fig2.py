"""Fig. 2 (Case I, no damper): the data set, and the paper's claims checked against closed forms."""

import math

import numpy as np
import pytest

from frictionflow.paper import fig2
from frictionflow.paper.cases import select

from .closed_form import case1_circle

VD = 1e-3
DT = 1e-3  # the paper's method's step (Settings)
# RK4 leaves the band inside a step at X ~ F_d, where F_c jumps by |F_d - X| <= |X'| dt; the velocity is then
# off by <= |X'| dt^2: the radius by a relative dt^2.
RK4_RADIUS_RTOL = DT**2
# A window cut at the first sample after each section is up to one step longer or shorter than the period;
# the integrand vanishes there (X' = 0), so only the division by its length errs: by < dt / (2 pi).
WINDOW_RTOL = DT / (2 * math.pi)
CYCLING = [(0.01, 0.02), (0.1, 0.02), (0.01, 0.04)]


def test_dataset_has_what_the_figure_shows(data):
    ds = data["fig2"]
    assert {"solver", "case", "tau", "vb", "fd", "zeta"} <= set(ds.coords)
    assert ds.P_f.dims == ("solver", "case", "tau")
    assert list(ds.solver.values) == ["rk4", "exact"]
    # panel (a): V_b = 0.001, 0.01, 0.1 at F_d = 0.02; panel (b): F_d = 0.02, 0.04 at V_b = 0.01
    for vb, fd, *_ in fig2.PANELS["a"] + fig2.PANELS["b"]:
        assert select(ds, 0.0, vb, fd).P_f.notnull().all()
    assert float(ds.tau[-1]) == pytest.approx(600.0) and float(ds.tau[-1] - ds.tau[0]) == pytest.approx(20.0)


@pytest.mark.parametrize(("vb", "fd"), CYCLING)
def test_case1_cycle_is_the_slip_circle_of_radius_vb_minus_vd(data, vb, fd):
    ref = case1_circle(vb, VD, fd)
    c = select(data["fig2"], 0.0, vb, fd)
    r = np.hypot(c.X - fd, c.V)  # distance from (F_d, 0) at every shown sample
    assert float(abs(r.sel(solver="exact") - ref["radius"]).max()) < 1e-12
    assert float(abs(r.sel(solver="rk4") - ref["radius"]).max()) < RK4_RADIUS_RTOL * ref["radius"]
    assert set(c.kind.values) == {"periodic"}
    assert float(c.period.sel(solver="exact")) == pytest.approx(2 * math.pi, rel=1e-12)


@pytest.mark.parametrize(("vb", "fd"), CYCLING)
def test_case1_friction_input_equals_friction_dissipation(data, vb, fd):
    ref = case1_circle(vb, VD, fd)
    c = select(data["fig2"], 0.0, vb, fd)
    ex = c.sel(solver="exact")
    assert float(ex.steady_P_fin) == pytest.approx(ref["P_fin"], rel=1e-10)
    assert float(ex.steady_P_df) == pytest.approx(float(ex.steady_P_fin), rel=1e-12)
    rk = c.sel(solver="rk4")  # the paper's method over its last cycle, by quadrature of the samples
    assert float(rk.last_P_fin) == pytest.approx(ref["P_fin"], rel=WINDOW_RTOL)
    assert float(rk.last_P_df) == pytest.approx(float(rk.last_P_fin), rel=WINDOW_RTOL)
    assert float(rk.last_TR_B) == pytest.approx(ref["TR_B"], rel=RK4_RADIUS_RTOL)


@pytest.mark.parametrize(("vb", "fd"), CYCLING)
def test_case1_friction_power_changes_sign_with_amplitude_fd_times_radius(data, vb, fd):
    p = select(data["fig2"], 0.0, vb, fd).P_f.sel(solver="rk4")
    amp = fd * (vb - VD)
    assert float(p.min()) == pytest.approx(-amp, rel=1e-3)
    assert float(p.max()) == pytest.approx(amp, rel=1e-3)


def test_case1_at_vb_equal_vd_is_rest_not_stick_the_mass_does_not_move_with_the_belt(data):
    c = select(data["fig2"], 0.0, VD, 0.02)
    ex, rk = c.sel(solver="exact"), c.sel(solver="rk4")
    # exact: at rest inside the band at X = F_d - V_b, while the belt moves at V_b
    assert float(abs(ex.V).max()) < 1e-15
    assert float(abs(ex.X - (0.02 - VD)).max()) < 1e-15
    assert float(ex.steady_P_fin) == 0.0
    # RK4: a residual velocity six orders below the belt's, constant: creep, not stick (stick would be X' = V_b)
    assert 1e-8 < float(rk.V.min()) and float(rk.V.max()) < 1e-6
    assert float(rk.V.max() - rk.V.min()) < 1e-15
