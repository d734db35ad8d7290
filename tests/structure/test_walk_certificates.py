"""The walk's certificates on event functions built by hand, against dense scans written here.

An event function g(tau) = c + sum_m a_m cos(w_m tau + p_m) is a phase of undamped modes
(z_m(tau) = a_m e^{i p_m} e^{i w_m tau}, W = 1, no forcing), so the walk (chord bound, the sharper
|g''| bound from g'' at an interval's ends and |g'''|, the one-root test with both slopes, the
earliest of several roots) runs on a function whose every root a dense grid and bisection find
independently.  The constant c puts the least value a hair above or below 0: a near miss (no root)
or two roots closer than any interval the walk takes; a too optimistic certificate skips the pair.
"""

from __future__ import annotations

import numpy as np
import pytest

import frictionflow as ff
from frictionflow.core.structure.combo import build
from frictionflow.core.structure.events import EPS, chord_low, new_room, walk
from frictionflow.core.structure.phase import Mags, Phase, bound

from .builders import single_mass

T_END = 6.0


def engine_combo():
    """A combination built by the engine (its record type, so the walk runs as compiled for the engine); the parts
    the walk reads are replaced in :func:`phase_of`."""
    asm = single_mass(0.0, 1.0, ff.Coulomb(0.2, 0.4), 0.0, 0.0)
    return build(asm, np.linalg.inv(asm.mass), np.zeros(1, dtype=np.int8))


def trig_sum(amp, w, p, tau):
    """sum_m a_m cos(w_m tau + p_m) at the points ``tau`` (numpy, from the definition)."""
    return np.cos(np.outer(tau, w) + p) @ amp


def phase_of(rows, slope=0.0):
    """(modes record, phase) for the event functions ``rows`` = [(c, amp, w, p)], each on modes of its own and
    each with the term ``slope`` tau."""
    lam, z0 = [], []
    for _, amp, w, p in rows:
        lam.extend(1j * np.asarray(w))
        z0.extend(np.asarray(amp) * np.exp(1j * np.asarray(p)))
    m, k = len(lam), len(rows)
    wm, start = np.zeros((k, m), dtype=np.complex128), 0
    for e, (_, amp, _, _) in enumerate(rows):
        wm[e, start:start + len(amp)] = 1.0
        start += len(amp)
    cb = engine_combo()._replace(lam=np.array(lam), active=np.ones(k, dtype=np.bool_), Dh=np.zeros((k, 0)), W=wm,
                       WA=np.abs(wm))
    zeros = np.zeros(m, dtype=np.complex128)
    ph = Phase(0.0, np.array(z0), zeros, zeros.copy(), np.zeros((m, 0), dtype=np.complex128), np.zeros(0),
               np.array([c for c, *_ in rows], dtype=float), np.full(k, slope), np.zeros(0), np.zeros(0))
    return cb, ph


def first_event(rows, h0=1.0, slope=0.0):
    """The walk's (tau, slot, graze) on the functions ``rows`` over (0, T_END] (:func:`phase_of`)."""
    cb, ph = phase_of(rows, slope)
    room = new_room(len(cb.lam), len(rows), 0, np.zeros(len(rows), dtype=np.bool_))
    return walk(cb, ph, np.zeros(0), T_END, h0, 1e-13 * T_END, room)


def scanned_root(c, amp, w, p, slope=0.0):
    """The first root of the row's function (plus ``slope`` tau) in (0, T_END] from a grid of 6e5 points and
    bisection; None: none."""
    tau = np.linspace(0.0, T_END, 600_001)
    g = c + slope * tau + trig_sum(amp, w, p, tau)
    below = np.nonzero(g <= 0.0)[0]
    if len(below) == 0:
        return None, g.min()
    lo, hi = tau[below[0] - 1], tau[below[0]]
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if c + slope * mid + trig_sum(amp, w, p, np.array([mid]))[0] > 0.0 else (lo, mid)
    return hi, g.min()


def random_row(rng, dip):
    """A sum of three to five modes (w in [0.5, 3]) whose least value on the grid is ``dip``."""
    n = rng.integers(3, 6)
    amp, w, p = rng.uniform(0.2, 1.0, n), rng.uniform(0.5, 3.0, n), rng.uniform(0.0, 2.0 * np.pi, n)
    tau = np.linspace(0.0, T_END, 600_001)
    g = trig_sum(amp, w, p, tau)
    c = dip - g.min()
    if g[0] + c < 0.05:  # starting near 0 is a departing function: not this test's subject
        return None
    return c, amp, w, p


def test_a_touch_is_reported_as_a_graze_of_the_undecided_function():
    """1 + cos(tau) touches 0 at pi without crossing: no interval decides it, so the walk reports a graze there,
    of that function and not of 3 + cos(tau), which is proven clear on the same intervals."""
    one = (np.array([1.0]), np.array([1.0]), np.array([0.0]))
    for rows, slot_expected in (([(1.0, *one), (3.0, *one)], 0), ([(3.0, *one), (1.0, *one)], 1)):
        tau, slot, graze = first_event(rows)
        assert graze and slot == slot_expected
        assert 1.0 + np.cos(tau) <= 1e-13 and tau == pytest.approx(np.pi, abs=1e-6)


@pytest.mark.parametrize("dip", [-1e-7, 1e-7, -1e-9, 3e-9])
def test_near_double_roots_are_found_or_rightly_missed(dip):
    """Random multi-mode functions dipping 1e-7 or 1e-9 below 0 (two roots ~1e-3 or ~1e-4 apart) or just above."""
    rng = np.random.default_rng(11 if dip < 0 else 12)
    checked = 0
    while checked < 12:
        row = random_row(rng, dip)
        if row is None:
            continue
        root, gmin = scanned_root(*row)
        tau, slot, graze = first_event([row])
        if root is None:
            assert slot == -1 and tau == T_END, (row, tau)
        else:
            assert slot == 0 and not graze
            assert tau == pytest.approx(root, abs=1e-10)  # (the roots are >= 4e-5 apart)
        checked += 1


def test_the_earliest_of_several_functions_is_the_event():
    """Three functions with near-double roots at different times: the walk's event is the earliest root."""
    rng = np.random.default_rng(5)
    rows, roots = [], []
    while len(rows) < 3:
        row = random_row(rng, -1e-6)
        if row is not None:
            root, _ = scanned_root(*row)
            if root is not None:
                rows.append(row)
                roots.append(root)
    tau, slot, graze = first_event(rows)
    assert not graze and slot == int(np.argmin(roots)) and tau == pytest.approx(min(roots), abs=1e-10)


def test_two_close_roots_inside_the_longest_interval():
    """c + cos(tau), c = 1 - 1e-12: roots pi -+ 1.4e-6, both inside the first interval (h0 = 6)."""
    c = 1.0 - 1e-12
    tau, slot, graze = first_event([(c, np.array([1.0]), np.array([1.0]), np.array([0.0]))], h0=T_END)
    assert slot == 0 and not graze
    assert tau == pytest.approx(np.arccos(-c), abs=1e-9)  # the root before pi, not the one after


@pytest.mark.parametrize("t0", [1.3, 2.5, 3.7])
def test_three_roots_in_one_sign_change(t0):
    """g = sin(tau - t0) - e (tau - t0), e = 1 - 1e-6: roots at t0 and t0 -+ 2.4e-3, g > 0 before them and < 0
    after.  The first interval's ends bracket all three, both ends' slopes < 0: the one-root test must not pass
    (a secant on the near-symmetric bracket lands on the middle root)."""
    e = 1.0 - 1e-6
    row = (e * t0, np.array([1.0]), np.array([1.0]), np.array([-t0 - 0.5 * np.pi]))
    root, _ = scanned_root(*row, slope=-e)
    assert root == pytest.approx(t0 - np.sqrt(6e-6), abs=1e-5)  # the scan found the first of the three
    tau, slot, graze = first_event([row], h0=T_END, slope=-e)
    assert slot == 0 and not graze and tau == pytest.approx(root, abs=1e-10)


@pytest.mark.parametrize("seed", range(20))
def test_the_chord_bound_is_below_every_function_it_covers(seed):
    """chord_low(g(a), g(b), h, M2) <= min g on [a, a + h] for g with |g''| <= M2 (dense scan), and equals the
    least value of the extremal g = chord - M2 t (h - t) / 2 (no room to be more optimistic)."""
    rng = np.random.default_rng(seed)
    h, m2 = rng.uniform(0.01, 2.0), rng.uniform(0.1, 5.0)
    t = np.linspace(0.0, h, 200_001)
    ga, gb = rng.uniform(-0.2, 1.0, 2) * m2 * h * h
    quad = np.polynomial.Polynomial([ga, (gb - ga) / h - m2 * h / 2.0, m2 / 2.0])  # chord - m2 t (h - t) / 2
    vertex = np.clip(quad.deriv().roots()[0], 0.0, h)
    assert chord_low(ga, gb, h, m2) == pytest.approx(quad(vertex), abs=1e-12 * m2 * h * h)
    w = np.sqrt(m2) * rng.uniform(0.1, 1.0)  # cos(w t + p) A with A w^2 <= m2 plus a line: |g''| <= m2
    amp, p = m2 / w**2 * rng.uniform(0.0, 1.0), rng.uniform(0.0, 2.0 * np.pi)
    g = amp * np.cos(w * t + p) + rng.uniform(-1.0, 1.0) * t + rng.uniform(-1.0, 1.0)
    assert chord_low(g[0], g[-1], h, m2) <= g.min() + 4.0 * EPS * (abs(g).max() + 1.0)


@pytest.mark.parametrize("seed", range(5))
def test_the_third_derivative_bound_holds(seed):
    """The |g'''| bound the sharper |g''| bound rests on (phase.bound, order 3) against the closed form's
    g''' = sum a w^3 sin(w tau + p) on a dense grid of the interval."""
    rng = np.random.default_rng(seed)
    amp, w, p = rng.uniform(0.2, 1.0, 4), rng.uniform(0.5, 3.0, 4), rng.uniform(0.0, 2.0 * np.pi, 4)
    cb, ph = phase_of([(1.0, amp, w, p)])
    a, h = rng.uniform(0.0, 3.0), rng.uniform(0.01, 1.0)
    za = ph.z0 * np.exp(cb.lam * a)
    mg = Mags(np.abs(za), np.abs(ph.b0), np.abs(ph.b1), np.abs(ph.bh), np.abs(cb.lam),
              np.zeros(len(cb.lam)), np.zeros(len(cb.lam)))  # no mode dies here: |z'(0)|, |z''(0)| unread
    tau = np.linspace(a, a + h, 10_001)
    g3 = np.abs(np.sin(np.outer(tau, w) + p) @ (amp * w**3)).max()
    assert g3 <= bound(cb, np.zeros(0), 0, a, h, mg, 3)
