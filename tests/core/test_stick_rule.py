"""Coulomb's stick rule, stated once (core.friction.holds_within): its three callers decide alike around the limit.

The statement, written here independently: a contact keeps sticking while
its held force is within the limit, |h| < F_s; beyond it, |h| > F_s, it
slips; exactly on it, it sticks only while sticking moves the held force
back inwards (sgn(h) h' < 0), and a held force that does not move counts as
moving outwards.  The callers: the single mass's ``rest_mode`` (adaptive,
tangent, flow map), the exact kernel's consistency test of STICK, and the
structure engine's active set (one unit mass on a unit spring as a
one-dof structure).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import frictionflow as ff
from frictionflow.core import exact as ke
from frictionflow.core import friction as kf
from frictionflow.core.structure import stick

from ..structure.builders import single_mass

FD, FS = 0.2, 0.4
#: held forces around the limit, relative: within, on it exactly, beyond (far outside every caller's tolerance)
OFFSETS = (-1e-6, -1e-10, 0.0, 1e-10, 1e-6)


def _expected(h, rate):
    if abs(h) < FS:
        return True
    if abs(h) > FS:
        return False
    return math.copysign(1.0, h) * rate < 0.0


def _cases():
    """(zeta, V_b, phase of the force or None, held force, its rate) on the grid."""
    for zeta in (0.0, 0.05):
        for side in (1.0, -1.0):
            for off in OFFSETS:
                h = side * FS * (1.0 + off)
                for vb in (0.1, -0.1, 0.0):  # unforced: the held force moves at V_b
                    yield zeta, vb, None, h, vb
                for phi in (0.7, -0.7):  # forced at V_b = 0: it moves at -f'(0) = Omega sin(phi)
                    yield zeta, 0.0, phi, h, math.sin(phi)


CASES = list(_cases())


def _x_for(zeta, vb, phi, h):
    """X that makes the held force F_e - f (resultant F_e = X + 2 zeta V_b) equal ``h`` at t = 0."""
    f = 0.0 if phi is None else math.cos(phi)
    return h - 2.0 * zeta * vb + f, f


@pytest.mark.parametrize("zeta, vb, phi, h, rate", CASES)
def test_the_three_callers_follow_the_statement(zeta, vb, phi, h, rate):
    want = _expected(h, rate)
    x, f = _x_for(zeta, vb, phi, h)
    df, ddf = (0.0, 0.0) if phi is None else (-math.sin(phi), -math.cos(phi))
    # the single mass's rule: 0 = stick, else the slip direction
    assert (kf.rest_mode(x, zeta, vb, FS, True, FD, f, df) == 0) == want
    # the exact kernel's consistency of STICK at X' = V_b
    lw = ke.law_record(kf.COULOMB, FD, FS, 0.0, True)
    assert ke.consistent(ke.STICK, lw, zeta, vb, x, vb, f, df, ddf, 0.0) == want
    # the structure's active set: a unit mass on a unit spring (and a damper 2 zeta), stuck on the belt
    asm = single_mass(zeta, vb, ff.Coulomb(fd=FD, fs=FS), x, vb, force=None if phi is None else (1.0, 1.0, phi))
    modes, released = np.zeros(1, dtype=np.int8), np.zeros(1, dtype=np.bool_)
    stick.release_over_limit(asm, np.linalg.inv(asm.mass), asm.q0.copy(), asm.v0.copy(), 0.0, modes, released)
    assert (modes[0] == 0) == want
    assert released[0] == (not want)


def test_the_grid_has_every_verdict_on_the_limit():
    on = [(h, rate) for _, _, _, h, rate in CASES if abs(h) == FS]
    assert {_expected(h, rate) for h, rate in on} == {True, False}
    assert any(rate == 0.0 for _, rate in on)


@pytest.mark.parametrize("held, rate, curv, want", [
    (1.0, -1.0, 5.0, True), (1.0, 1.0, -5.0, False), (-1.0, 1.0, 0.0, True), (-1.0, -1.0, 0.0, False),
    (1.0, 0.0, -1.0, True), (-1.0, 0.0, 1.0, True), (1.0, 0.0, 1.0, False), (1.0, 0.0, 0.0, False),
    (1.0, 1e-9, -1.0, True), (1.0, 1e-7, -1.0, False),  # |rate| within rate_tol counts as 0: the curvature decides
])
def test_on_the_limit_the_rate_then_the_curvature_decides(held, rate, curv, want):
    assert kf.holds_within(held, rate, curv, 1.0 - 1e-12, 1.0 + 1e-12, 1e-8) == want


def test_within_and_beyond_the_limit_the_value_decides():
    assert kf.holds_within(0.5, 10.0, 10.0, 0.9, 1.1, 0.0)
    assert not kf.holds_within(-1.2, -10.0, -10.0, 0.9, 1.1, 0.0)
    assert kf.limit_ratio(-3.0, 2.0) == 1.5 and kf.limit_ratio(1.0, 0.0) == math.inf
