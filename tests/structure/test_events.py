"""Events solved by hand: a normal load reaching 0 (contact loss) and V_r touching 0 tangentially (grazing)."""

from __future__ import annotations

import math

import numpy as np
import pytest

import frictionflow as ff
from frictionflow.solvers.structure import run_assembly

from .builders import single_mass


def test_contact_loss_is_reported_at_the_closed_form_time():
    """x'' + x = F_d (P + n x) while slipping: x = xe + (x0 - xe) cos(w t), w^2 = 1 - F_d n, xe = F_d P / w^2;
    N = P + n x reaches 0 at x = -P / n."""
    fd, p, nx, x0 = 0.3, 1.0, -2.0, -0.5
    law = ff.Coulomb(fd=fd, fs=0.4)
    motion = run_assembly(single_mass(0.0, 2.0, law, x0, 0.0, normal=[p, nx]), 50.0)
    w = math.sqrt(1.0 - fd * nx)
    xe = fd * p / w**2
    t_lost = math.acos((-p / nx - xe) / (x0 - xe)) / w
    assert motion.status == "contact_lost"
    name, t = motion.lost
    assert name == "contact.0" and t == pytest.approx(t_lost, rel=1e-13)
    assert motion.t[-1] == t and motion.state[0, -1] == pytest.approx(-p / nx, rel=1e-13)
    assert len(motion.switches) == 0


def test_a_negative_normal_load_at_the_start_is_a_loss_at_zero():
    motion = run_assembly(single_mass(0.0, 2.0, ff.Coulomb(fd=0.3), 1.0, 0.0, normal=[1.0, -2.0]), 5.0)
    assert motion.status == "contact_lost" and motion.lost == ("contact.0", 0.0)


def grazing(factor, t_end=10.0):
    """Undamped, slipping from x = F_d + A at rest: x' = -A sin t, V_r = V_b + A sin t; A = factor V_b.

    min V_r = V_b - A at t = 3 pi / 2, where x = F_d: held force F_d < F_s, so the mass sticks there if V_r
    reaches 0, and stays stuck for (F_s - F_d) / V_b (x grows at V_b up to F_s)."""
    fd, fs, vb = 0.02, 0.04, 0.01
    motion = run_assembly(single_mass(0.0, vb, ff.Coulomb(fd=fd, fs=fs), fd + factor * vb, 0.0), t_end)
    return motion, fd, fs, vb


def test_a_tangential_touch_of_vr_zero_is_not_skipped():
    motion, fd, fs, vb = grazing(1.0)
    assert len(motion.switches) >= 2
    assert motion.switches[0] == pytest.approx(1.5 * math.pi, abs=1e-6)
    assert motion.switch_mode[0] == 0
    # located within rounding of the touch: V_r there is within rounding of 0, x on the slip's closed form
    t1 = motion.switches[0]
    x1 = motion.state[0, np.searchsorted(motion.t, t1)]
    assert x1 == pytest.approx(fd + vb * math.cos(t1), abs=1e-15) and x1 == pytest.approx(fd, abs=1e-8)
    assert abs(vb + vb * math.sin(t1)) < 1e-15
    assert motion.switches[1] == pytest.approx(t1 + (fs - x1) / vb, rel=1e-13)


def test_two_roots_closer_than_any_step_are_found():
    """A = V_b (1 + 1e-10): V_r < 0 only on |t - 3 pi / 2| < sqrt(2e-10); the first root is the switch."""
    motion, *_ = grazing(1.0 + 1e-10)
    first = 1.5 * math.pi - math.acos(-1.0 / (1.0 + 1e-10)) + math.pi  # -A sin t = V_b, t < 3 pi / 2
    first = 1.5 * math.pi - abs(1.5 * math.pi - first)
    assert motion.switches[0] == pytest.approx(first, abs=1e-9)
    assert motion.switch_mode[0] == 0


def test_a_near_miss_does_not_switch():
    """A = V_b (1 - 1e-6): V_r stays >= 1e-8 V_b: it keeps slipping, every period."""
    motion, *_ = grazing(1.0 - 1e-6, t_end=40.0)
    assert len(motion.switches) == 0
    np.testing.assert_array_equal(motion.modes, 1)
