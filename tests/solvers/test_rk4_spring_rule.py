"""RK4's stick band with the spring stick rule, for laws with Coulomb's rule.

For Coulomb, Stribeck and Cubic the band stands in for the constraint
V_r = 0: while the rule (|X - f| < F_s with ``stick_force="spring"``)
holds, the interface holds the whole resultant X + 2 zeta X' - f, and the
mass moves with the belt.  It used to hold X - f alone, Karnopp's band (the
paper's): the damper's force -2 zeta V_b pushed the mass out of the band,
so RK4 with Coulomb never stuck (an equilibrium where the exact and adaptive
solvers find stick-slip) and with Stribeck converged to the resultant rule's
cycle instead of the spring rule's.  Now RK4 converges to the event-driven
solvers as its band and step shrink.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from frictionflow import BeltOscillator, Coulomb, Karnopp, Stribeck, analyze, simulate
from frictionflow.core.friction import band_force, band_law
from frictionflow.solvers import RK4, Adaptive, Exact
from frictionflow.solvers.base import kernel_params
from frictionflow.sweep.compute import VARIABLES, compute_chunk

MODEL = BeltOscillator(zeta=0.05, vb=0.01)
T_END = 300.0
CASES = {  # the law with a given RK4 band, its event-driven solver
    "coulomb": (lambda band: Coulomb(0.02, 0.04, stick_force="spring", rk4_band=band), Exact()),
    "stribeck": (lambda band: Stribeck(fd=0.02, fs=0.04, vs=0.01, stick_force="spring", rk4_band=band), Adaptive()),
}


def _cycle(law, solver) -> tuple[str, float, float]:
    ss = analyze(simulate(MODEL, law, solver, t_end=T_END)).steady_state
    return ss.kind, ss.period, ss.stick_fraction


@pytest.mark.parametrize("name", sorted(CASES))
def test_rk4_converges_to_the_event_driven_cycle(name):
    law, reference = CASES[name]
    kind, period, stick = _cycle(law(1e-4), reference)
    assert kind == "periodic"
    errors = []
    for band, dt in ((1e-4, 1e-3), (1e-5, 1e-4)):
        k, p, s = _cycle(law(band), RK4(dt=dt))
        assert k == "periodic", (band, dt)
        errors.append((abs(p - period) / period, abs(s - stick)))
    coarse, fine = errors
    assert fine[0] < 0.25 * coarse[0] and fine[0] < 1e-3  # first order in the band: ~10x less with 10x narrower
    assert fine[1] < 2e-3


def test_the_band_holds_the_resultant_for_coulomb_and_the_held_force_for_karnopp():
    x, v, zeta, fext = 0.03, 0.01, 0.05, 0.0
    for law, held in ((Coulomb(0.02, 0.04, stick_force="spring"), x + 2 * zeta * v),
                      (Karnopp(0.02, 0.04, stick_force="spring"), x),
                      (Coulomb(0.02, 0.04), x + 2 * zeta * v)):
        p = kernel_params(MODEL, law)
        assert band_force(band_law(int(p[0]), p), x, v, zeta, v, fext) == pytest.approx(held, abs=1e-15)
    p = kernel_params(MODEL, Coulomb(0.02, 0.04, stick_force="spring"))  # beyond F_s by the spring alone: saturated
    assert band_force(band_law(int(p[0]), p), 0.041, v, zeta, v, fext) == 0.04


def test_rk4_sweep_point_is_rk4_simulate():
    """The batched kernels (sweeps, basins) select the same band force as the single run."""
    tr = simulate(MODEL, CASES["coulomb"][0](1e-4), RK4(), t_end=T_END)
    ss = analyze(tr).steady_state
    settings = {"friction": "coulomb", "fd": 0.02, "fs": 0.04, "stick_force": "spring", "vb": MODEL.vb,
                "solver": "rk4", "t_end": T_END}
    out = compute_chunk({"settings": settings, "grid": {"zeta": [MODEL.zeta]}}, (0,), (1,))
    names = [v[0] for v in VARIABLES]
    got = {k: float(out[names.index(k)].ravel()[0]) for k in ("period", "stick_fraction")}
    assert got["period"] == pytest.approx(ss.period, rel=1e-9)
    assert got["stick_fraction"] == pytest.approx(ss.stick_fraction, abs=1e-9)
    assert math.isfinite(got["period"]) and not np.isnan(got["stick_fraction"])
