"""API defects of frictionflow.orbits: numpy scalars as numbers, one clear error naming the argument,
the energy residual reported wherever an orbit or run is, and identity equality of results holding arrays."""

from __future__ import annotations

import math

import numpy as np
import pytest

import frictionflow as ff
import frictionflow.orbits as o

M = ff.BeltOscillator(zeta=0.05, vb=0.01)
F = ff.Stribeck(fd=0.02, fs=0.04)
MF = ff.BeltOscillator(zeta=0.05, vb=0.01, fex=0.01)
C = ff.Coulomb()


@pytest.fixture(scope="module")
def result():
    """A short continuation whose start is a numpy scalar (item 1) and that has a periodic branch (item 2)."""
    return o.continuation(M, F, "vb", np.float64(0.01), np.float64(0.03), seeds=("hopf",), max_points=4)


# -- 1: continuation's start and stop ------------------------------------------------------------------------------
def test_continuation_accepts_numpy_scalars(result):
    assert isinstance(result.start, float) and result.start == 0.01 and result.stop == 0.03


@pytest.mark.parametrize("start, stop, name", [("a", 0.03, "start"), (None, 0.03, "start"), (0.01, None, "stop"),
                                               (0.01, True, "stop"), (0.01, math.inf, "stop")])
def test_continuation_names_a_bad_end(start, stop, name):
    with pytest.raises(ValueError, match=f"^{name} must be a finite real number"):
        o.continuation(M, F, "vb", start, stop)


# -- 2: the energy residual -----------------------------------------------------------------------------------------
def test_continuation_points_carry_their_energy_residual(result):
    d = result.to_dict()
    periodic = [j for j, b in enumerate(result.branches) if b.kind == "periodic"]
    assert periodic
    for j, b in enumerate(result.branches):
        for p, row in zip(b.points, d["branches"][j], strict=True):
            assert row["energy_residual"] == pytest.approx(p.measures.power.energy_residual, nan_ok=True)
    assert all(row["energy_residual"] < 1e-6 for row in d["branches"][periodic[0]])


def test_sweep_rows_carry_their_energy_residual():
    (row,) = o.sweep(M, F, "vb", [0.01], t_end=60.0)
    run = ff.analyze(ff.simulate(*o.with_param(M, F, "vb", 0.01), t_end=60.0))
    assert row["energy_residual"] == run.power.energy_residual
    assert 0.0 <= row["energy_residual"] < 1e-6


def test_stroboscopic_sweep_carries_its_energy_residual():
    s = o.stroboscopic_sweep(MF, C, "fex", [0.01, 0.02], transient_periods=10, keep=4)
    assert s.energy_residual.shape == (2,)
    assert np.all(np.isfinite(s.energy_residual)) and np.all(s.energy_residual < 1e-6)


# -- 3: the sweep's t_end -------------------------------------------------------------------------------------------
@pytest.mark.parametrize("t_end", [None, "a", 0.0, math.inf, True])
def test_sweep_names_a_bad_t_end_before_any_run(t_end):
    with pytest.raises(ValueError, match="^t_end must be"):
        o.sweep(M, F, "vb", [], t_end=t_end)  # no value: refused before (and without) any run


def test_sweep_accepts_a_numpy_t_end():
    (row,) = o.sweep(M, F, "vb", [np.float64(0.01)], t_end=np.float64(20.0))
    assert row["value"] == 0.01


# -- 4: identity equality of results with arrays --------------------------------------------------------------------
def test_periodic_orbits_compare_by_identity():
    a, b = o.find_orbit(M, F), o.find_orbit(M, F)
    assert (a == b) is False and (a == a) is True and a != b
    assert len({a, b, a}) == 2


def test_forced_orbits_compare_by_identity():
    a, b = o.find_forced_orbit(MF, C), o.find_forced_orbit(MF, C)
    assert (a == b) is False and (a == a) is True
    assert len({a, b}) == 2
    s = o.stroboscopic_sweep(MF, C, "fex", [0.01], transient_periods=2, keep=2)
    assert (s == s) is True and hash(s) == hash(s)


# -- 5: parameter_names and multipliers -----------------------------------------------------------------------------
def test_parameter_names_names_law():
    with pytest.raises(TypeError, match="^law must be a FrictionLaw, got str"):
        o.parameter_names("x")


@pytest.mark.parametrize("bad", [np.array([1.0, 2.0]), np.full((2, 2), np.nan), np.ones((2, 3)), "ab",
                                 np.zeros((0, 0)), [[1.0, math.inf], [0.0, 1.0]]])
def test_multipliers_names_monodromy(bad):
    with pytest.raises(ValueError, match="^monodromy must be a square matrix"):
        o.multipliers(bad)


def test_multipliers_of_a_good_matrix():
    assert np.allclose(o.multipliers([[2.0, 0.0], [0.0, 0.5]]), [2.0, 0.5])


# -- 6: find_forced_orbit's max_iter and tol ------------------------------------------------------------------------
@pytest.mark.parametrize("max_iter", [0, -1, 1.5, True, None])
def test_find_forced_orbit_names_max_iter(max_iter):
    with pytest.raises(ValueError, match=r"^max_iter must be an integer in \[1, "):
        o.find_forced_orbit(MF, C, max_iter=max_iter)


@pytest.mark.parametrize("tol", [None, "a", 0.0, -1e-9, math.nan, True])
def test_find_forced_orbit_names_tol(tol):
    with pytest.raises(ValueError, match="^tol must be a finite number > 0"):
        o.find_forced_orbit(MF, C, tol=tol)


def test_find_forced_orbit_accepts_numpy_scalars():
    orbit = o.find_forced_orbit(MF, C, tol=np.float64(1e-10), max_iter=np.int64(30), x0=np.float64(0.0))
    assert orbit.residual < 1e-8


# -- 7: start states and parameter values ---------------------------------------------------------------------------
@pytest.mark.parametrize("kw, name", [({"x0": "a"}, "x0"), ({"v0": "a"}, "v0"), ({"x0": True}, "x0"),
                                      ({"transient": "a"}, "transient"), ({"tol": "a"}, "tol")])
def test_find_orbit_names_a_bad_argument(kw, name):
    with pytest.raises(ValueError, match=f"^{name} must be"):
        o.find_orbit(M, F, **kw)


def test_find_orbit_accepts_numpy_scalars():
    orbit = o.find_orbit(M, F, x0=np.array(0.02), v0=np.float64(0.01), tol=np.float32(1e-9), transient=np.int64(300))
    assert orbit.period > 0


@pytest.mark.parametrize("param, value", [("fs", "x"), ("vb", None), ("fd", True), ("zeta", np.bool_(True)),
                                          ("fd", [0.1])])
def test_with_param_names_value(param, value):
    with pytest.raises(ValueError, match=rf"^value must be a real number \({param}\), got"):
        o.with_param(M, F, param, value)


def test_with_param_accepts_numpy_scalars():
    m, law = o.with_param(M, F, "fd", np.float64(0.03))
    assert law.fd == 0.03 and type(law.fd) is float
    m, _ = o.with_param(M, F, "vb", np.array(0.02))
    assert m.vb == 0.02


@pytest.mark.parametrize("value", ["x", None, True])
def test_state_equilibrium_names_value(value):
    with pytest.raises(ValueError, match=r"^value must be a real number \(NaN: none\)"):
        o.state_equilibrium(M, ff.LuGre(), value)


def test_state_equilibrium_accepts_numpy_scalars():
    assert o.state_equilibrium(M, ff.LuGre(), np.float64(0.3)).value == 0.3


@pytest.mark.parametrize("param", ["omega", "phi", "vb_omega", "vb_phi"])
def test_continuation_refuses_a_parameter_the_autonomous_system_lacks(param):
    """continue --vary omega=0.2:0.4 with fex = 0 ran: a flat branch over a parameter that does not enter."""
    with pytest.raises(ValueError, match=f"param {param} does not enter the autonomous system"):
        o.continuation(ff.BeltOscillator(zeta=0.05, vb=0.1), ff.Coulomb(0.2, 0.3), param, 0.2, 0.4)
