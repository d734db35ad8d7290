"""Fig. 6 (force transmissibility): the data set, Case I's closed form and Case II's steady state.

Over a cycle of the free spiral from a maximum of X the largest |X + 2 zeta X'|
is at the cycle's start, X_max = F_d + A with A = A_h (1 + pi zeta / 2) in terms
of the half range A_h, so TR_B = 1 + A_h (1 + pi zeta / 2) / F_d (1 + O(zeta^2)).
"""

import math

import numpy as np
import pytest

from .closed_form import case1_circle

VD, DT = 1e-3, 1e-3


def test_dataset_has_what_the_figure_shows(data):
    ds = data["fig6"]
    assert ds.last_TR_B.dims == ds.steady_TR_B.dims == ("solver", "vb", "fd", "zeta")
    assert set(ds.vb.values.tolist()) == {0.01, 0.1} and set(ds.fd.values.tolist()) == {0.02, 0.04}
    assert 0.0 in ds.zeta.values


@pytest.mark.parametrize("vb", [0.01, 0.1])
@pytest.mark.parametrize("fd", [0.02, 0.04])
def test_trb_case1_is_fd_plus_vb_minus_vd_over_fd(data, vb, fd):
    c = data["fig6"].sel(vb=vb, fd=fd, zeta=0.0)
    ref = case1_circle(vb, VD, fd)["TR_B"]
    assert float(c.steady_TR_B.sel(solver="exact")) == pytest.approx(ref, rel=1e-12)
    assert float(c.last_TR_B.sel(solver="rk4")) == pytest.approx(ref, rel=DT**2)


def test_trb_case1_falls_with_friction_and_grows_with_belt_speed(data):
    t = data["fig6"].steady_TR_B.sel(solver="exact", zeta=0.0)
    assert float(t.sel(vb=0.01, fd=0.04)) < float(t.sel(vb=0.01, fd=0.02)) < float(t.sel(vb=0.1, fd=0.02))


def test_trb_belt_speed_changes_it_more_than_friction_so_friction_does_not_dominate(data):
    t = data["fig6"].steady_TR_B.sel(solver="exact", zeta=0.0)
    by_vb = float(t.sel(vb=0.1, fd=0.02) - t.sel(vb=0.01, fd=0.02))
    by_fd = float(t.sel(vb=0.01, fd=0.04) - t.sel(vb=0.01, fd=0.02))
    assert abs(by_vb) > 10 * abs(by_fd)


def test_trb_case2_steady_state_is_exactly_one_the_vibration_has_died_out(data):
    ds = data["fig6"]
    steady = ds.steady_TR_B.sel(solver="exact").where(ds.zeta > 0, drop=True)
    assert np.allclose(steady.values, 1.0, rtol=0, atol=1e-12)


def test_trb_trend_with_damping_is_a_snapshot_of_the_decay_not_of_smaller_limit_cycles(data):
    ds = data["sweep"].sel(solver="rk4")
    for vb in (0.01, 0.1):
        for fd in (0.02, 0.04):
            line = ds.last_TR_B.sel(vb=vb, fd=fd).values
            assert np.all(np.diff(line) < 0), (vb, fd)  # falls with zeta at a fixed window ...
    z = ds.zeta.where(ds.zeta > 0, drop=True)
    c = ds.sel(zeta=z)
    # ... by exactly how far each transient has decayed: the window's amplitude sets it
    predicted = c.last_amplitude * (1 + math.pi * c.zeta / 2) / c.fd
    assert bool((abs((c.last_TR_B - 1) / predicted - 1) < 10 * c.zeta**2).all())
