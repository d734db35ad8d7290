"""Fig. 3 (Case II "limit cycles"): the data set, and why they are turns of a decaying spiral."""

import math

import numpy as np
import pytest

from frictionflow.paper import fig3
from frictionflow.paper.cases import select
from frictionflow.paper.runs import Point, run

from .closed_form import slip


def terminal_state(point: Point, settings) -> tuple[float, float, float]:
    """(tau, X, X') where the exact solver proves the band is never reached again."""
    ex = run(point, "exact", settings, t_end=20.0)
    k = int(np.searchsorted(ex.t, ex.extra["t_terminal"]))
    return float(ex.t[k]), float(ex.x[k]), float(ex.v[k])


def envelope(t: float, start: tuple[float, float, float], fd: float, zeta: float) -> float:
    """Amplitude exp(-zeta s) sqrt(y0^2 + b^2) of the free spiral (tests/paper/closed_form.py)."""
    t0, x0, v0 = start
    w = math.sqrt(1 - zeta**2)
    y0 = x0 - fd
    return math.exp(-zeta * (t - t0)) * math.hypot(y0, (v0 + zeta * y0) / w)


def test_dataset_has_what_the_figure_shows(data):
    ds = data["fig3"]
    assert {"solver", "case", "tau", "zeta", "vb", "fd"} <= set(ds.coords)
    assert ds.X.dims == ds.V.dims == ("solver", "case", "tau")
    for panel in fig3.PANELS.values():
        for zeta, vb, *_ in panel:
            c = select(ds, zeta, vb, 0.02)
            assert c.X.notnull().all() and c.V.notnull().all()


@pytest.mark.parametrize("zeta", [0.01, 0.03])
def test_case2_has_no_limit_cycle_it_decays_at_rate_zeta(data, zeta):
    c = select(data["fig3"], zeta, 0.01, 0.02)
    # the cycle amplitudes decay exponentially at exactly the damper's rate, in both solvers
    assert float(c.decay_rate.sel(solver="rk4")) == pytest.approx(zeta, rel=1e-3)
    assert float(c.decay_rate.sel(solver="exact")) == pytest.approx(zeta, rel=1e-3)
    # the exact solver proves the band is never reached again after the first turn: steady sliding
    assert float(c.t_terminal.sel(solver="exact")) < 4 * math.pi
    assert str(c.kind.sel(solver="exact").values) == "equilibrium"
    assert str(c.kind.sel(solver="rk4").values) != "periodic"


def test_case2_end_of_run_is_the_free_spiral_from_the_last_band_exit(data, settings):
    point = Point(0.01, 0.01, 0.02)
    start = terminal_state(point, settings)
    c = select(data["fig3"], point.zeta, point.vb, point.fd)
    x, v = slip(c.tau.values, *start, point.fd, point.zeta)
    a = envelope(float(c.tau[-1]), start, point.fd, point.zeta)
    for solver in ("exact", "rk4"):
        s = c.sel(solver=solver)
        assert float(abs(s.X - x).max()) < 1e-3 * a, solver
        assert float(abs(s.V - v).max()) < 1e-3 * a, solver


def test_case2_larger_damping_orbit_is_smaller_only_because_it_decayed_faster(data, settings):
    ds = data["fig3"]
    small, large = Point(0.01, 0.01, 0.02), Point(0.03, 0.01, 0.02)
    a1 = float(select(ds, 0.01, 0.01, 0.02).last_amplitude.sel(solver="rk4"))
    a3 = float(select(ds, 0.03, 0.01, 0.02).last_amplitude.sel(solver="rk4"))
    t_mid = float(select(ds, 0.01, 0.01, 0.02).window_end.sel(solver="rk4")) - math.pi
    predicted = envelope(t_mid, terminal_state(large, settings), 0.02, 0.03) / envelope(
        t_mid, terminal_state(small, settings), 0.02, 0.01)
    assert a3 / a1 < 1e-4  # "smaller", by five orders at tau ~ 600 ...
    # ... by the ratio of two decays exp(-zeta tau) from about the same start; the half range of a decaying
    # cycle differs from the envelope at its middle by a relative ~zeta pi / 2 for each
    assert a3 / a1 == pytest.approx(predicted, rel=math.pi * 0.04)


def test_case2_belt_speed_scales_the_orbit_tenfold_it_is_not_of_little_influence(data, settings):
    ds = data["fig3"]
    a1 = float(select(ds, 0.01, 0.01, 0.02).last_amplitude.sel(solver="rk4"))
    a10 = float(select(ds, 0.01, 0.1, 0.02).last_amplitude.sel(solver="rk4"))
    t_mid = float(select(ds, 0.01, 0.01, 0.02).window_end.sel(solver="rk4")) - math.pi
    predicted = envelope(t_mid, terminal_state(Point(0.01, 0.1, 0.02), settings), 0.02, 0.01) / envelope(
        t_mid, terminal_state(Point(0.01, 0.01, 0.02), settings), 0.02, 0.01)
    assert a10 / a1 > 8  # the spiral starts at about V_b - V_d: 0.099 against 0.009
    assert a10 / a1 == pytest.approx(predicted, rel=0.01)
