"""The exact solver's replication of a repeating stretch of switches: identical to integrating it.

``Exact(replicate=False)`` integrates every switch; the default copies a
stretch that starts from a state bitwise equal to an earlier switch's
(:func:`frictionflow.core.exact.run`).  The reference here is the full
integration itself: the two trajectories must agree bit for bit (times
included), and the copy must happen where it can and not where it cannot.
"""

import math

import numpy as np
import pytest

from frictionflow import BeltOscillator, Coulomb, Exact, Karnopp, analyze, simulate
from frictionflow.core import exact as kernel
from frictionflow.core import sections
from frictionflow.core.records import run_record
from frictionflow.solvers.base import kernel_params, output_buffers


def assert_identical(a, b):
    for name in ("t", "x", "v", "fc", "mode", "dwork"):
        x, y = getattr(a, name), getattr(b, name)
        assert x.dtype == y.dtype and x.shape == y.shape, name
        assert x.tobytes() == y.tobytes(), name  # bit for bit (signed zeros included)
    assert a.events["t"].tobytes() == b.events["t"].tobytes()
    assert np.array_equal(a.events["mode"], b.events["mode"])
    assert a.extra == b.extra


def kernel_counts(model, friction, t_end, x0=None, v0=None, dense_dt=0.0, stop_periodic=False, replicate=True,
                  periodic_stop=False):
    """(switches, switches copied) of the kernel run that ``Exact`` makes (sweeps: replicate False, periodic_stop True)."""
    p = kernel_params(model, friction)
    bufs = output_buffers(Exact(dense_dt=dense_dt or None).sample_estimate(t_end))
    t_mode = np.zeros(2, dtype=np.int64)
    x0 = friction.fd if x0 is None else x0
    v0 = model.vb if v0 is None else v0
    run = run_record((x0, v0), t_end, model.zeta, model.vb, sections.tail_start(0.0, t_end), dense_dt,
                     (0.0, 0.0, 0), (stop_periodic, False, 1e-9, 3), (0.0, 0.0))
    args = (run, p, *bufs, t_mode, replicate, periodic_stop)
    _, ne, status, _, _ = kernel.run(*args)
    assert status == kernel.DONE
    return ne, int(t_mode[1])


CASES = [  # (model, law, x0, v0, does the run stick-slip: is most of it copied?)
    (BeltOscillator(0.05, 0.01), Coulomb(0.02, 0.04), None, None, True),
    (BeltOscillator(0.0, 0.01), Coulomb(0.02, 0.04), None, None, True),  # undamped
    (BeltOscillator(0.2, 0.005), Coulomb(0.02, 0.06), None, None, True),
    (BeltOscillator(0.05, 0.01), Coulomb(0.02, 0.04, stick_force="spring"), None, None, True),
    (BeltOscillator(0.05, -0.01), Coulomb(0.02, 0.04), -0.02, -0.01, True),  # belt the other way
    (BeltOscillator(0.01, 0.05), Coulomb(0.02, 0.04), 0.0, 1.0, True),  # a long transient first
    (BeltOscillator(0.05, 0.01), Karnopp(0.02, 0.04, 1e-3), None, None, True),
    (BeltOscillator(0.05, 0.01), Karnopp(0.02, 0.04, 1e-3), 0.5, 0.0, True),
    (BeltOscillator(0.05, 0.01), Karnopp(0.02, 0.04, 1e-3, stick_force="spring"), None, None, False),  # ends held
    (BeltOscillator(0.3, 0.02), Coulomb(0.02, 0.05), None, None, False),  # ends sliding
]


@pytest.mark.parametrize("model, friction, x0, v0, cycles", CASES)
def test_replicated_run_is_the_integrated_one_bit_for_bit(model, friction, x0, v0, cycles):
    t_end = 1500.0
    full = simulate(model, friction, Exact(replicate=False), t_end=t_end, x0=x0, v0=v0)
    fast = simulate(model, friction, Exact(), t_end=t_end, x0=x0, v0=v0)
    assert_identical(fast, full)
    ne, copied = kernel_counts(model, friction, t_end, x0, v0)
    assert ne == len(full.events["t"])
    if cycles:
        assert copied > 0.8 * ne  # the stick-slip cycle repeats: most of it is copied
    else:
        assert copied == 0


@pytest.mark.parametrize("t_end", np.linspace(40.0, 140.0, 37))
def test_copies_stop_short_of_the_tail_and_the_end(t_end):
    # run ends and tail starts at every phase of the cycle (period ~ 7.63): the last copies and the
    # tail's sample fall anywhere relative to the switches
    model, friction = BeltOscillator(0.05, 0.01), Coulomb(0.02, 0.04)
    full = simulate(model, friction, Exact(replicate=False), t_end=t_end)
    fast = simulate(model, friction, Exact(), t_end=t_end)
    assert_identical(fast, full)
    assert sections.tail_start(0.0, t_end) in fast.t


def test_analysis_is_unchanged():
    model, friction = BeltOscillator(0.05, 0.01), Coulomb(0.02, 0.04)
    a = analyze(simulate(model, friction, Exact(replicate=False), t_end=2000.0))
    b = analyze(simulate(model, friction, Exact(), t_end=2000.0))
    assert b.steady_state.period == a.steady_state.period
    assert b.power.P_fin == a.power.P_fin and b.power.R_c == a.power.R_c


def test_no_copy_where_the_stretch_cannot_repeat():
    model, friction = BeltOscillator(0.05, 0.01), Coulomb(0.02, 0.04)
    ne, copied = kernel_counts(model, friction, 1000.0)
    assert copied > 0
    # a dense grid reads the absolute time; the periodic stop ends the run itself
    assert kernel_counts(model, friction, 1000.0, dense_dt=0.37)[1] == 0
    assert kernel_counts(model, friction, 1000.0, stop_periodic=True, periodic_stop=True)[1] == 0
    assert kernel_counts(model, friction, 1000.0, replicate=False)[1] == 0
    assert kernel_counts(model, friction, 1000.0, replicate=False, periodic_stop=True)[1] == 0  # the sweeps' call
    # the periodic stop looked for but not asked for by the run record: replication goes on
    assert kernel_counts(model, friction, 1000.0, periodic_stop=True)[1] > 0
    # no sticking: the slip decays onto its equilibrium, no state repeats
    ne, copied = kernel_counts(BeltOscillator(0.05, 0.5), Coulomb(0.02, 0.04), 1000.0)
    assert copied == 0
    # a decaying Karnopp transient that ends in the band: nothing repeats either
    ne, copied = kernel_counts(BeltOscillator(0.05, 0.1), Karnopp(0.02, 0.04, 1e-4), 1000.0)
    assert copied == 0


def test_dense_and_forced_runs_are_unchanged():
    model, friction = BeltOscillator(0.05, 0.01), Coulomb(0.02, 0.04)
    assert_identical(simulate(model, friction, Exact(dense_dt=0.5), t_end=300.0),
                     simulate(model, friction, Exact(dense_dt=0.5, replicate=False), t_end=300.0))
    forced = BeltOscillator(0.05, 0.01, fex=0.01, omega=0.8)
    assert_identical(simulate(forced, friction, Exact(), t_end=200.0),
                     simulate(forced, friction, Exact(replicate=False), t_end=200.0))


def test_repr_shows_only_a_disabled_replication():
    assert repr(Exact()) == "Exact(dense_dt=None)"
    assert repr(Exact(replicate=False)) == "Exact(dense_dt=None, replicate=False)"
    assert Exact(replicate=False).describe() == Exact().describe()


def test_periodic_stop_false_never_stops_early():
    # the façade's call (periodic_stop False) never stops early; the sweeps' (True) stops
    model, friction, t_end = BeltOscillator(0.05, 0.01), Coulomb(0.02, 0.04), 1000.0
    p = kernel_params(model, friction)

    def stop(*last):
        bufs = output_buffers(Exact().sample_estimate(t_end))
        t_mode = np.zeros(1, dtype=np.int64)
        run = run_record((friction.fd, model.vb), t_end, model.zeta, model.vb, sections.tail_start(0.0, t_end), 0.0,
                         (0.0, 0.0, 0), (True, False, 1e-9, 3), (0.0, 0.0))
        return kernel.run(run, p, *bufs, t_mode, *last)[4]

    assert stop(False, True) < 0.2 * t_end  # stopped once the sections repeated
    assert stop(False, False) == t_end
