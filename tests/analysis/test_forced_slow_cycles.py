"""A slowly attracting forced cycle is not a torus.

The forced classifier called a section quasi-periodic when it revisits itself and the largest exponent is within
its uncertainty of 0 (at least 1e-4).  A stable cycle whose multipliers are within ~1e-4 T of the unit circle passes
both while its section spirals in, so a run far from converged was reported ``quasi_periodic``:

* the damped linear case (Coulomb in pure slip, zeta = 1e-4): the section spirals onto the harmonic response
  with multipliers exp(-zeta T) = 0.9991 -- one attractor, which cannot be quasi-periodic;
* a phase lock of 281 forcing periods (Stribeck, stick phases): its section fills a closed curve and converges
  onto 281 points of it.

Now the section must also not close in on a point or a cycle (``core.strobe.closing_in``), the structures' test
too; such runs are ``not_settled``.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from frictionflow import BeltOscillator, analyze, simulate
from frictionflow.analysis.forced import closing_in, section_indices
from frictionflow.core import strobe
from frictionflow.friction import Coulomb, Stribeck
from frictionflow.quantities import KINDS
from frictionflow.solvers import Exact

from ..sweep.test_forced_sweep import _grid_agrees

GOLDEN = (math.sqrt(5.0) - 1.0) / 2.0


def _curve(angles: np.ndarray) -> np.ndarray:
    """A closed curve that is no circle, travelled at an uneven speed: (2, len) points."""
    return np.vstack([np.cos(angles) + 0.3 * np.cos(2 * angles), 0.5 * np.sin(angles) + 0.2 * np.sin(3 * angles)])


def _spiked(angles: np.ndarray, width: float = 1e-3) -> np.ndarray:
    """A closed curve with a narrow spike (as a stick-slip torus's kink): few points land on it."""
    phase = np.mod(angles, 2 * np.pi) - np.pi
    return np.vstack([np.cos(angles) + 2.0 * np.exp(-phase**2 / width), np.sin(angles)])


@pytest.mark.parametrize("n", [64, 200, 1000, 4000])
def test_a_torus_section_does_not_close_in(n: int) -> None:
    k = np.arange(n)
    assert not strobe.closing_in(_curve(2 * np.pi * GOLDEN * k))
    for rho in (GOLDEN, math.sqrt(2) - 1, math.pi - 3):
        assert not strobe.closing_in(_spiked(2 * np.pi * rho * k))


def test_a_torus_near_a_rational_rotation_does_not_close_in() -> None:
    """Rotation 1/4 + 2e-5 with a narrow spike: the 4-step differences drop once (the spike left behind) and
    then hold; the largest-difference rule alone took it for a converging 4-cycle (as for 22 of 300 random
    spiked tori), the mean and the steady fall both are needed."""
    k = np.arange(200)
    points = _spiked(2 * np.pi * 0.2500183399320113 * k, 3.9551599729759614e-06)
    assert not strobe.closing_in(points)
    # rotation numbers near a rational one (near-returns after 7 steps, but they do not shrink)
    assert not strobe.closing_in(_curve(2 * np.pi * (3 / 7 + 1e-4 * GOLDEN) * k))


@pytest.mark.parametrize("m", [1, 3, 40, 281])
def test_a_cycle_attracting_slowly_closes_in(m: int) -> None:
    """m points of the curve, each approached along the curve and across it, at 0.3 % a period."""
    n = max(2000, 8 * m)
    k = np.arange(n)
    cycle = _curve(2 * np.pi * (k % m) / m + 0.5)
    off = 0.05 * np.exp(-3e-3 * k) * np.vstack([np.cos(2.1 * k), np.sin(2.1 * k)])
    assert strobe.closing_in(cycle + off)
    assert not strobe.closing_in(cycle + 0.05 * np.vstack([np.cos(2.1 * k), np.sin(2.1 * k)]))  # not converging


def test_linear_slow_spiral_is_not_quasi_periodic_on_every_path() -> None:
    """Coulomb in pure slip (belt 1 outruns every motion): a damped linear oscillator with F_d added, whose
    stroboscopic map contracts by exp(-zeta T) = 0.9991 a period.  At t_end 20000 the section has not converged
    (X_max is 0.2973, the closed form's 0.29608): not settled, by simulate and by the batched sweep alike."""
    zeta, omega, fex, fd = 1e-4, 0.7, 0.1, 0.1
    model = BeltOscillator(zeta=zeta, vb=1.0, fex=fex, omega=omega)
    tr = simulate(model, Coulomb(fd, fd), Exact(), t_end=20000.0, x0=0.0, v0=0.0)
    result = analyze(tr)
    ss = result.steady_state
    assert ss.kind == "not_settled" and abs(ss.lyapunov) <= 1e-4  # the exponent alone cannot tell it from 0
    idx = section_indices(tr)
    xs, vs = tr.x[idx[len(idx) // 2:]], tr.v[idx[len(idx) // 2:]]
    assert closing_in(xs, vs)
    steady = fd + fex / math.hypot(1 - omega**2, 2 * zeta * omega)  # the linear steady response's peak
    assert result.amplitude["X_max"] - steady > 1e-3  # still on the way in
    refs = _grid_agrees({"friction": "coulomb", "fd": fd, "fs": fd, "vb": 1.0, "zeta": zeta, "t_end": 20000.0},
                        {"omega": [omega], "fex": [fex]})
    assert KINDS[int(refs[0]["kind"])] == "not_settled"


def test_a_281_period_phase_lock_is_not_quasi_periodic() -> None:
    """The QA case (Stribeck, stick phases, Omega = 0.914005): its section P_k converges onto a cycle of 281
    forcing periods (|P_{k+281} - P_k| falls by orders of magnitude over the tail), its exponent is -0.0015 over
    two whole cycles.  It was quasi_periodic at t_end 30000."""
    model = BeltOscillator(zeta=0.03, vb=0.12, fex=0.02, omega=0.914005)
    tr = simulate(model, Stribeck(0.02, 0.04), t_end=30000.0, x0=0.02, v0=0.12)
    ss = analyze(tr).steady_state
    idx = section_indices(tr)
    tail = idx[len(idx) // 2:]
    returns = np.hypot(tr.x[tail][281:] - tr.x[tail][:-281], tr.v[tail][281:] - tr.v[tail][:-281])
    assert returns[-281:].max() < 0.1 * returns[:281].max()  # independent of the classifier's quarters
    assert ss.kind == "not_settled"
