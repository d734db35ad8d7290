"""The exact kernel's mode rules against the shared stick rules and the modes' definitions."""

from __future__ import annotations

import numpy as np
import pytest

from frictionflow import SwitchMode
from frictionflow.core import closed_form as cf
from frictionflow.core import event_modes as em
from frictionflow.core import exact as ke
from frictionflow.core import friction as kf

S = SwitchMode


def _region(law, zeta, vb, fs, vd, res, x, v, f):
    """The mode by region, from SwitchMode's definitions: V_r = V_b - X' against the band, then F_e - f against F_s."""
    vr = vb - v
    width = 0.0 if law == kf.COULOMB else vd
    if vr > width:
        return S.SLIP_POSITIVE
    if vr < -width:
        return S.SLIP_NEGATIVE
    if law == kf.COULOMB:
        return S.STICK
    fe = (x + 2.0 * zeta * v if res else x) - f
    return S.BAND_SATURATED_POSITIVE if fe >= fs else S.BAND_SATURATED_NEGATIVE if fe <= -fs else S.BAND_HOLD


@pytest.mark.parametrize("law", [kf.COULOMB, kf.KARNOPP])
def test_region_mode_is_the_region_the_state_lies_in(law):
    rng = np.random.default_rng(7)
    vb, vd, fs, zeta = 0.01, 0.002, 0.04, 0.05
    for _ in range(3000):
        res = bool(rng.integers(2))
        v = vb + rng.choice([0.0, vd, -vd, 1.0]) * rng.normal() * 0.004
        x, f = rng.normal() * 0.05, rng.choice([0.0, rng.normal() * 0.02])
        got = ke.region_mode(law, zeta, vb, 0.02, fs, vd, res, x, v, f)
        assert em.EXACT_EVENT_MODES[got] == _region(law, zeta, vb, fs, vd, res, x, v, f)


def test_coulomb_modes_agree_with_the_shared_stick_rule_off_the_bound():
    # exact's consistency and friction.rest_mode ask one rule (friction.holds_within) with two tolerances;
    # within rounding of |F_e - f| = F_s those differ (module docstring of core/exact.py), away from it
    # the slip directions (rest_mode's own, exact's slip modes' consistency) must choose alike too
    rng = np.random.default_rng(3)
    sign = {ke.STICK: 0, ke.SLIP_POS: 1, ke.SLIP_NEG: -1}
    checked = 0
    for _ in range(20000):
        zeta, vb = rng.choice([0.0, 0.05]), rng.choice([0.01, -0.02, 0.0])
        fd, fs, res = 0.02, rng.choice([0.02, 0.04]), bool(rng.integers(2))
        f, df, ddf = (rng.choice([0.0, rng.normal() * 0.03]) for _ in range(3))
        x = rng.normal() * 0.05
        fe = (x + 2.0 * zeta * vb if res else x) - f
        if abs(abs(fe) - fs) < 1e-9 * fs:
            continue
        m = ke.select_mode(ke.law_record(kf.COULOMB, fd, fs, 0.0, res), zeta, vb, x, vb, f, df, ddf, 0.0)
        if m < 0:  # no mode consistent: the kernel's fallback
            m = ke.region_mode(kf.COULOMB, zeta, vb, fd, fs, 0.0, res, x, vb, f)
        assert sign[m] == kf.rest_mode(x, zeta, vb, fs, res, fd, f, df)
        checked += 1
    assert checked > 19000


def test_held_modes_by_stick_rule():
    assert em.held_modes("switch") == (S.STICK,)
    assert em.held_modes("band") == tuple(m for m in S if m.name.startswith("BAND_"))


@pytest.mark.parametrize("resultant", [True, False])
@pytest.mark.parametrize("zeta", [0.0, 0.05])
def test_exact_motion_follows_each_modes_friction_force(zeta, resultant):
    # X'' = F_c - X - 2 zeta X': a constant F_c oscillates about it; F_c = X + 2 zeta X' leaves X'' = 0;
    # F_c = X leaves X'' = -2 zeta X' (exponential, linear when zeta = 0)
    fd, fs = 0.02, 0.04
    constant = {S.SLIP_POSITIVE: fd, S.SLIP_NEGATIVE: -fd, S.BAND_SATURATED_POSITIVE: fs,
                S.BAND_SATURATED_NEGATIVE: -fs}
    for mode in em.EXACT_CODES:
        dyn, centre = em.exact_motion(mode, zeta, fd, fs, resultant)
        if mode in constant:
            assert (dyn, centre) == (cf.OSC, constant[mode])
        elif mode == S.BAND_HOLD and not resultant:
            assert (dyn, centre) == (cf.EXP if zeta > 0.0 else cf.LIN, 0.0)
        else:  # stick (X' = V_b), the resultant held by the band, sliding on a band edge
            assert (dyn, centre) == (cf.LIN, 0.0)
